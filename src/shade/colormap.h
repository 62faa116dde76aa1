/* SPDX-License-Identifier: MIT */
#ifndef DAO_SHADE_COLORMAP_H
#define DAO_SHADE_COLORMAP_H

#include <stdint.h>

/* A 256-entry RGB lookup table. */
struct dao_colormap {
	uint8_t rgb[256][3];
};

/* Fills `map` for DAO_SHADE_TURBO, _JET or _GRAY (others give gray). */
void dao_colormap_fill(struct dao_colormap *map, int shade_mode);

#endif
