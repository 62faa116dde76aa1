/* SPDX-License-Identifier: MIT */
#include <math.h>
#include <stddef.h>

#include "core/math_util.h"
#include "depth/prefilter.h"

/* range tolerance in units of sigma_w: wide enough to average noise, narrow enough for edges */
#define RANGE_SIGMAS 2.5f

void dao_prefilter_bilateral(const float *z, float *out, int w, int h, int radius,
			     float noise_k, float unit, int y0, int y1)
{
	const float sigma_s = 0.5f * (float)radius + 0.5f;
	const float inv_2ss = 1.0f / (2.0f * sigma_s * sigma_s);
	for (int y = y0; y < y1; y++) {
		for (int x = 0; x < w; x++) {
			const float zc = z[(size_t)y * w + x];
			if (zc <= 0.0f) {
				out[(size_t)y * w + x] = 0.0f;
				continue;
			}
			const float wc = 1.0f / zc;
			float sw = fmaxf(noise_k, unit * wc * wc) * RANGE_SIGMAS;
			/* a floor so exact (noise-free float) input still averages ulp noise */
			sw = fmaxf(sw, 1e-6f * wc);
			const float inv_2rr = 1.0f / (2.0f * sw * sw);
			float sum = 0.0f, wsum = 0.0f;
			const int ya = dao_clampi(y - radius, 0, h - 1), yb = dao_clampi(y + radius, 0, h - 1);
			const int xa = dao_clampi(x - radius, 0, w - 1), xb = dao_clampi(x + radius, 0, w - 1);
			for (int j = ya; j <= yb; j++) {
				const float *row = z + (size_t)j * w;
				const float dy2 = (float)((j - y) * (j - y));
				for (int i = xa; i <= xb; i++) {
					const float zs = row[i];
					if (zs <= 0.0f)
						continue;
					const float d = 1.0f / zs - wc;
					const float r2 = (float)((i - x) * (i - x)) + dy2;
					const float wt = expf(-r2 * inv_2ss - d * d * inv_2rr);
					sum += wt * (1.0f / zs);
					wsum += wt;
				}
			}
			out[(size_t)y * w + x] = 1.0f / (sum / wsum);
		}
	}
}
