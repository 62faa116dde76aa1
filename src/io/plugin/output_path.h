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

/*
 * "dir/name.ext" -> "dir/name-k.ext" (k >= 1; no extension: "dir/name-k"),
 * malloc'ed; NULL when out of memory.
 */
char *dao_output_numbered(const char *path, unsigned k);

#endif
