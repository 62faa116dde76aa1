/* SPDX-License-Identifier: MIT */
#include "plugin/output_path.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error_internal.h"

size_t dao_output_uri_path_len(const char *uri)
{
	const char *q = strrchr(uri, '?');
	return q && strchr(q, '=') ? (size_t)(q - uri) : strlen(uri);
}

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

int dao_output_parse_overwrite(const char *sink, const char *uri, const char *value,
			       int *overwrite, struct dao_error *err)
{
	if (value && (!strcmp(value, "true") || !strcmp(value, "1"))) {
		*overwrite = 1;
		return 0;
	}
	if (value && (!strcmp(value, "false") || !strcmp(value, "0"))) {
		*overwrite = 0;
		return 0;
	}
	return dao_error_set(err, -EINVAL, "%s: overwrite='%s' in '%s' must be true or false",
			     sink, value ? value : "", uri);
}
