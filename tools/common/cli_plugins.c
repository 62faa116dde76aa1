/* SPDX-License-Identifier: MIT */
#define _XOPEN_SOURCE 700
#include "cli_plugins.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/*
 * A tool run from the build tree loads the plugins built beside it: meson
 * writes their directories into this file next to the tool's binary
 * (tools/meson.build).  Installed tools have no such file, so no build path
 * is compiled into them (a reproducible build); they use the plugin
 * directory and $DEPTHAO_PLUGIN_PATH.
 */
#define BUILD_PLUGIN_PATH_FILE "dao-build-plugin-path"

/* The plugin path of the build tree the running binary is in; 0 if it is in none. */
static int build_tree_plugin_path(char *path, size_t len)
{
	char exe[PATH_MAX];
	ssize_t n = readlink("/proc/self/exe", exe, sizeof(exe) - 1);
	if (n <= 0)
		return 0;
	exe[n] = '\0';
	char *slash = strrchr(exe, '/');
	if (!slash || (size_t)(slash - exe) + sizeof("/" BUILD_PLUGIN_PATH_FILE) > sizeof exe)
		return 0;
	strcpy(slash + 1, BUILD_PLUGIN_PATH_FILE);
	FILE *f = fopen(exe, "re");
	if (!f)
		return 0;
	int ok = 0;
	while (!ok && fgets(path, (int)len, f)) /* the first line that is not a comment */
		ok = path[0] != '#';
	fclose(f);
	if (!ok)
		return 0;
	path[strcspn(path, "\n")] = '\0';
	return path[0] != '\0';
}

int cli_plugins_load(struct dao_plugins **out, struct dao_error *err)
{
	const char *env = getenv(DAO_PLUGIN_PATH_ENV);
	char path[8192];
	if ((!env || !*env) && build_tree_plugin_path(path, sizeof path))
		return dao_plugins_load(out, path, err);
	return dao_plugins_load(out, NULL, err);
}
