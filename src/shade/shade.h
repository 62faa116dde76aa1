/* SPDX-License-Identifier: MIT */
#ifndef DAO_SHADE_SHADE_H
#define DAO_SHADE_SHADE_H

#include <stdint.h>

#include <depthao/frame.h>

#include "shade/colormap.h"

struct dao_shade_setup {
	int width, height;
	float ax, ay, bx, by;       /* UvToViewParams */
	int mode;                   /* enum dao_shade */
	float near_m, far_m;        /* resolved colormap range (> 0, near < far) */
	float power;                /* AO exponent */
	float occ[3];               /* occlusion colour, 0..255 */
	const struct dao_colormap *map;
};

/*
 * Occlusion-shaded image, seed 004's composite:
 *   out = mix(occlusion colour, base colour, AO^power)
 * with base = a Lambert head light (N . V) in gray, a depth colormap over
 * [near, far], or white (AO alone).  Pixels without depth are black.
 * `out` is RGB24 or GRAY8 (Rec. 601 luma of the RGB result).  Rows [y0, y1).
 */
void dao_shade(const struct dao_shade_setup *s, const float *z, const float *n, const float *ao,
	       const struct dao_frame *out, int y0, int y1);

/* One pixel of the same, as floats 0..255 (the optimised kernels' fallback). */
void dao_shade_pixel(const struct dao_shade_setup *s, const float *z, const float *n,
		     const float *ao, int x, int y, float rgb[3]);

/*
 * The same over SIMD lanes (shade_simd.inc.c): the Lambert head light with
 * AO^1 into RGB24 runs on lanes; other modes and outputs use dao_shade.
 */
void dao_shade_generic(const struct dao_shade_setup *s, const float *z, const float *n,
		       const float *ao, const struct dao_frame *out, int y0, int y1);
void dao_shade_sse41(const struct dao_shade_setup *s, const float *z, const float *n,
		     const float *ao, const struct dao_frame *out, int y0, int y1);
void dao_shade_avx2(const struct dao_shade_setup *s, const float *z, const float *n,
		    const float *ao, const struct dao_frame *out, int y0, int y1);
void dao_shade_avx512(const struct dao_shade_setup *s, const float *z, const float *n,
		      const float *ao, const struct dao_frame *out, int y0, int y1);

#endif
