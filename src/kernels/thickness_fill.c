/* SPDX-License-Identifier: MIT */
/*
 * Thickness from the image: dropouts inside a surface filled before the
 * passes (dao_thickness_fill_rows, thickness.h; docs/design/thickness.md,
 * rule 15); the same fill for the filtered depth output (dao_depth_fill_rows,
 * depth_fill.h; parameter depth-fill).
 */
#include "kernels/depth_fill.h"
#include "kernels/thickness_internal.h"

#include <string.h>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

void dao_depth_fill_rows(const float *z, float *zf, int w, int y0, int y1, int max_px)
{
	for (int y = y0; y < y1; y++) {
		const float *zr = z + (size_t)y * w;
		float *fr = zf + (size_t)y * w;
		memcpy(fr, zr, (size_t)w * sizeof(float));
		int x = 0;
		while (x < w) {
#ifdef __SSE2__
			/* (four pixels with depth at a time: the same test) */
			while (x + 4 <= w &&
			       _mm_movemask_ps(_mm_cmpgt_ps(_mm_loadu_ps(zr + x), _mm_setzero_ps())) == 0xf)
				x += 4;
			if (x >= w)
				break;
#endif
			if (zr[x] > 0.0f) {
				x++;
				continue;
			}
			const int a = x;
			while (x < w && !(zr[x] > 0.0f))
				x++;
			/* the hole a .. x - 1 */
			const int len = x - a;
			if (a > 0 && x < w && len <= max_px && same_surface(zr[a - 1], zr[x])) {
				const float za = zr[a - 1], dz = (zr[x] - za) / (float)(len + 1);
				for (int k = 0; k < len; k++)
					fr[a + k] = za + dz * (float)(k + 1);
			}
		}
	}
}

void dao_thickness_fill_rows(const struct dao_thickness_setup *t, const float *z, float *zf,
			     int y0, int y1)
{
	dao_depth_fill_rows(z, zf, t->width, y0, y1, t->fill_px);
}
