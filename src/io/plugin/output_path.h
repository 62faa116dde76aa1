/* SPDX-License-Identifier: MIT */
#ifndef DAO_PLUGIN_OUTPUT_PATH_H
#define DAO_PLUGIN_OUTPUT_PATH_H

#include <stddef.h>

/*
 * Recording sinks never replace a file: when the name given exists, the
 * recording goes to the first free one of NAME-1.EXT, NAME-2.EXT, ...
 * (unless the URI asks to overwrite).
 */
#define DAO_OUTPUT_NUMBERED_MAX 9999

/* Length of the path part of a sink URI: up to the last '?' when options ("k=v") follow. */
size_t dao_output_uri_path_len(const char *uri);

/*
 * "dir/name.ext" -> "dir/name-k.ext" (k >= 1; no extension: "dir/name-k"),
 * malloc'ed; NULL when out of memory.
 */
char *dao_output_numbered(const char *path, unsigned k);

/*
 * Parses one "overwrite=true|false" option value; 0, or -EINVAL with a
 * message naming the sink and the URI.
 */
struct dao_error;
int dao_output_parse_overwrite(const char *sink, const char *uri, const char *value,
			       int *overwrite, struct dao_error *err);

#endif
