/* SPDX-License-Identifier: MIT */
#include <math.h>
#include <stddef.h>

#include "core/math_util.h"
#include "denoise/denoise.h"

static inline float zat(const struct dao_denoise_setup *s, const float *z, int x, int y)
{
	if (x < 0 || y < 0 || x >= s->width || y >= s->height)
		return 0.0f;
	return z[(size_t)y * s->width + x];
}

/*
 * Depth step per pixel along one axis, from the side whose linear
 * extrapolation lands closer to the centre (seed 002: C1 < C2).
 */
static float smaller_side_gradient(const struct dao_denoise_setup *s, const float *z, int x,
				   int y, int sx, int sy, float zc)
{
	float m1 = zat(s, z, x - sx, y - sy), m2 = zat(s, z, x - 2 * sx, y - 2 * sy);
	float p1 = zat(s, z, x + sx, y + sy), p2 = zat(s, z, x + 2 * sx, y + 2 * sy);
	int have_m = m1 > 0.0f && m2 > 0.0f, have_p = p1 > 0.0f && p2 > 0.0f;
	float cm = have_m ? fabsf(m1 + (m1 - m2) - zc) : INFINITY;
	float cp = have_p ? fabsf(p1 + (p1 - p2) - zc) : INFINITY;
	if (cm < cp)
		return m1 - m2;
	if (have_p)
		return p2 - p1;
	/* only one neighbour on a side: a one-pixel difference, else flat */
	if (p1 > 0.0f && (m1 <= 0.0f || fabsf(p1 - zc) < fabsf(zc - m1)))
		return p1 - zc;
	if (m1 > 0.0f)
		return zc - m1;
	return 0.0f;
}

float dao_denoise_plane_pixel(const struct dao_denoise_setup *s, const float *z,
			      const float *ao_in, int x, int y)
{
	const int w = s->width;
	const float zc = z[(size_t)y * w + x];
	if (zc <= 0.0f)
		return s->invalid_value;
	const float gx = smaller_side_gradient(s, z, x, y, 1, 0, zc);
	const float gy = smaller_side_gradient(s, z, x, y, 0, 1, zc);
	const float inv_tol = 1.0f / dao_denoise_tolerance(s, zc);
	float sum = 0.0f, wsum = 0.0f;
	for (int j = -2; j <= 2; j++) {
		const int yy = y + j;
		if (yy < 0 || yy >= s->height)
			continue;
		for (int k = -2; k <= 2; k++) {
			const int xx = x + k;
			if (xx < 0 || xx >= w)
				continue;
			const size_t t = (size_t)yy * w + xx;
			if (z[t] <= 0.0f)
				continue;
			const float plane_z = zc + (float)k * gx + (float)j * gy;
			const float wt = dao_denoise_plane_tap_weight(j) * dao_denoise_plane_tap_weight(k) *
					 (1.0f - dao_saturate(fabsf(plane_z - z[t]) * inv_tol));
			sum += wt * ao_in[t];
			wsum += wt;
		}
	}
	/* the centre always has weight 1, so wsum >= 1 */
	return sum / wsum;
}

void dao_denoise_plane(const struct dao_denoise_setup *s, const float *z, const float *ao_in,
		       float *ao_out, int y0, int y1)
{
	for (int y = y0; y < y1; y++)
		for (int x = 0; x < s->width; x++)
			ao_out[(size_t)y * s->width + x] = dao_denoise_plane_pixel(s, z, ao_in, x, y);
}
