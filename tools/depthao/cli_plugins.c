/* SPDX-License-Identifier: MIT */
#define _XOPEN_SOURCE 700 /* realpath */
#include "cli_plugins.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#ifndef DAO_BUILD_ROOT
#define DAO_BUILD_ROOT ""
#endif
#ifndef DAO_BUILD_PLUGIN_PATH
#define DAO_BUILD_PLUGIN_PATH ""
#endif

static int running_from_build_tree(void)
{
	char exe[PATH_MAX], root[PATH_MAX];
	ssize_t n = readlink("/proc/self/exe", exe, sizeof(exe) - 1);
	if (n <= 0 || !DAO_BUILD_ROOT[0] || !realpath(DAO_BUILD_ROOT, root))
		return 0;
	exe[n] = '\0';
	size_t len = strlen(root);
	return strncmp(exe, root, len) == 0 && exe[len] == '/';
}

int cli_plugins_load(struct dao_plugins **out, struct dao_error *err)
{
	const char *env = getenv(DAO_PLUGIN_PATH_ENV);
	if ((!env || !*env) && DAO_BUILD_PLUGIN_PATH[0] != '\0' && running_from_build_tree())
		return dao_plugins_load(out, DAO_BUILD_PLUGIN_PATH, err);
	return dao_plugins_load(out, NULL, err);
}
