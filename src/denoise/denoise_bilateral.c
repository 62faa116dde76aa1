/* SPDX-License-Identifier: MIT */
#include <math.h>
#include <stddef.h>

#include "denoise/denoise.h"

/*
 * Depth of the centre pixel's tangent plane seen through pixel (u, v):
 * points X = z' (u ax + bx, v ay + by, 1) with N.(X - P) = 0 give
 * z' = N.P / N.(u ax + bx, v ay + by, 1).
 */
static inline float plane_depth(const struct dao_denoise_setup *s, const float *N, float npd,
				 int u, int v)
{
	float den = N[0] * ((float)u * s->ax + s->bx) + N[1] * ((float)v * s->ay + s->by) + N[2];
	return fabsf(den) > 1e-6f ? npd / den : -1.0f;
}

#define MAX_RADIUS 16

/*
 * The spatial weights of offsets -r .. r: a Gaussian (sigma (r + 1) / 2),
 * each residue class of the offset mod 4 scaled to the same total, so that a
 * pattern of period 4 or 2 (the GTAO noise tile) sums to its mean and leaves
 * no grid on smooth surfaces (a truncated Gaussian passes 10-20 % of the
 * 1/2 cycle/px component).  From r = 2 on every class has a tap.
 */
static void spatial_weights(int r, float g[2 * MAX_RADIUS + 1])
{
	const float sigma = 0.5f * (float)(r + 1);
	const float falloff = 1.0f / (2.0f * sigma * sigma);
	double cls[4] = { 0 };
	for (int k = -r; k <= r; k++) {
		g[k + r] = expf(-(float)(k * k) * falloff);
		cls[k & 3] += g[k + r];
	}
	if (r < 2)
		return;
	const double mean = 0.25 * (cls[0] + cls[1] + cls[2] + cls[3]);
	for (int k = -r; k <= r; k++)
		g[k + r] = (float)(g[k + r] * mean / cls[k & 3]);
}

static void blur_pass(const struct dao_denoise_setup *s, const float *z, const float *n,
		      const float *in, float *out, int y0, int y1, int horizontal)
{
	const int w = s->width, h = s->height;
	const int r = s->radius < MAX_RADIUS ? s->radius : MAX_RADIUS;
	float g[2 * MAX_RADIUS + 1];
	spatial_weights(r, g);
	for (int y = y0; y < y1; y++) {
		for (int x = 0; x < w; x++) {
			const size_t i = (size_t)y * w + x;
			const float zc = z[i];
			if (zc <= 0.0f) {
				out[i] = s->invalid_value;
				continue;
			}
			const float *N = n + 3 * i;
			const float P[3] = { ((float)x * s->ax + s->bx) * zc,
					     ((float)y * s->ay + s->by) * zc, zc };
			const float npd = N[0] * P[0] + N[1] * P[1] + N[2] * P[2];
			const float tol = dao_denoise_tolerance(s, zc);
			float sum = 0.0f, wsum = 0.0f;
			for (int k = -r; k <= r; k++) {
				int xx = horizontal ? x + k : x, yy = horizontal ? y : y + k;
				if (xx < 0 || yy < 0 || xx >= w || yy >= h)
					continue;
				const size_t t = (size_t)yy * w + xx;
				if (z[t] <= 0.0f)
					continue;
				float pz = plane_depth(s, N, npd, xx, yy);
				if (!(fabsf(z[t] - pz) < tol) && k != 0)
					continue;
				const float wt = g[k + r];
				sum += wt * in[t];
				wsum += wt;
			}
			out[i] = sum / wsum;
		}
	}
}

void dao_denoise_bilateral_h(const struct dao_denoise_setup *s, const float *z, const float *n,
			     const float *ao_in, float *tmp, int y0, int y1)
{
	blur_pass(s, z, n, ao_in, tmp, y0, y1, 1);
}

void dao_denoise_bilateral_v(const struct dao_denoise_setup *s, const float *z, const float *n,
			     const float *tmp, float *ao_out, int y0, int y1)
{
	blur_pass(s, z, n, tmp, ao_out, y0, y1, 0);
}
