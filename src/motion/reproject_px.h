/* SPDX-License-Identifier: MIT */
/*
 * The landing pass's scalar steps (motion/reproject.h), shared by the
 * reference and the kernels' row tails so that both compute the same bits.
 */
#ifndef DAO_MOTION_REPROJECT_PX_H
#define DAO_MOTION_REPROJECT_PX_H

#include "motion/reproject.h"

/* pixel (x, y) at 1/z = h is z (ray(x, y)) with ray = (x ax + bx, y ay + by, 1);
 * moved, q = z (R ray + T h) = z (g + T h) where g = R ray is linear in x
 * along a row: g = g0 + x dg.  So u = (g_0 + T_0 h) / (g_2 + T_2 h) and
 * 1/q_z = h / (g_2 + T_2 h): one division a pixel.  g0 of row y: */
static inline void dao_reproject_row_g0(const struct dao_reproject_land *s, int y, float g0[3])
{
	const float *R = s->R;
	const float vy = (float)y * s->ay + s->by;
	g0[0] = R[0] * s->bx + R[1] * vy + R[2];
	g0[1] = R[3] * s->bx + R[4] * vy + R[5];
	g0[2] = R[6] * s->bx + R[7] * vy + R[8];
}

/* pixel i = (x, y) of a row with g0 and dg = R column 0 times ax: its
 * landing pixel into dest[i] and 1/z into zinv[i]; returns its landing row
 * or -1 */
static inline int32_t dao_reproject_px(const struct dao_reproject_land *s, const float g0[3],
				       const float dg[3], int x, size_t i)
{
	const int w = s->w, h = s->h;
	const float *T = s->T;
	const float hv = s->hist[i];
	const float fx = (float)x;
	const float den = g0[2] + fx * dg[2] + T[2] * hv;
	const float d = 1.0f / (den > 0.0f ? den : 1.0f);
	const float u = (g0[0] + fx * dg[0] + T[0] * hv) * d * s->inv_ax - s->ub;
	const float v = (g0[1] + fx * dg[1] + T[1] * hv) * d * s->inv_ay - s->vb;
	const int ok = (s->count[i] != 0) & (hv > 0.0f) & (den > 0.0f) & (u > -0.5f) &
		       (v > -0.5f) & (u < (float)w - 0.5f) & (v < (float)h - 0.5f);
	/* nearest pixel: u > -0.5, so floor(u + 0.5) is the truncation */
	const int32_t xu = (int32_t)(ok ? u + 0.5f : 0.0f);
	const int32_t yv = (int32_t)(ok ? v + 0.5f : 0.0f);
	const int in = ok && xu < w && yv < h;
	s->dest[i] = in ? yv * w + xu : -1;
	s->zinv[i] = hv * d;
	return in ? yv : -1;
}

/* pixels [x0, x1) of row `row` (its first pixel's index) by dao_reproject_px,
 * widening [*lo, *hi] to their landing rows */
static inline void dao_reproject_px_span(const struct dao_reproject_land *s, const float g0[3],
					 const float dg[3], int x0, int x1, size_t row,
					 int32_t *lo, int32_t *hi)
{
	for (int x = x0; x < x1; x++) {
		const int32_t r = dao_reproject_px(s, g0, dg, x, row + (size_t)x);
		if (r >= 0) {
			*lo = r < *lo ? r : *lo;
			*hi = r > *hi ? r : *hi;
		}
	}
}

#endif
