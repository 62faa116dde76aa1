/* SPDX-License-Identifier: MIT */
#include "plugin/output_path.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

char *dao_output_numbered(const char *path, unsigned k)
{
	const char *slash = strrchr(path, '/');
	const char *base = slash ? slash + 1 : path;
	const char *dot = strrchr(base, '.');
	size_t stem = dot && dot != base ? (size_t)(dot - path) : strlen(path);
	size_t n = strlen(path) + 16;
	char *out = malloc(n);
	if (out)
		snprintf(out, n, "%.*s-%u%s", (int)stem, path, k, path + stem);
	return out;
}
