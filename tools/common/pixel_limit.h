/* SPDX-License-Identifier: MIT */
/* The limit on decoded image size, as the CLI and the daemon config take it. */
#ifndef DAO_TOOLS_PIXEL_LIMIT_H
#define DAO_TOOLS_PIXEL_LIMIT_H

#include <stdint.h>

/*
 * "N" (pixels) or "WxH" (their product), 1 .. DAO_MAX_DIMENSION^2.
 * 0 and *out set, or -1.
 */
int pixel_limit_parse(const char *text, uint64_t *out);

#endif
