/* SPDX-License-Identifier: MIT */
/*
 * The occlusion-shaded image (shade.c) over SIMD lanes: the Lambert head
 * light with AO^1 into RGB24, the CLI's and daemon's default.  Other modes,
 * AO powers and GRAY8 output go to the reference code.  Pixels without depth
 * are black.  Included by shade_<isa>.c.
 */
#include <string.h>

#include <depthao/params.h>

#include "shade/shade.h"

void DAO_ISA_FN(dao_shade)(const struct dao_shade_setup *s, const float *z, const float *n,
			   const float *ao, const struct dao_frame *out, int y0, int y1)
{
	if (s->mode != DAO_SHADE_LAMBERT || s->power != 1.0f || out->format != DAO_PIXFMT_RGB24) {
		dao_shade(s, z, n, ao, out, y0, y1);
		return;
	}
	const int w = s->width;
	const vf zero = v_zero(), one = v_set1(1.0f), ax = v_set1(s->ax), bx = v_set1(s->bx),
		 ay = v_set1(s->ay), by = v_set1(s->by);
	for (int y = y0; y < y1; y++) {
		uint8_t *row = (uint8_t *)out->data + (size_t)y * out->stride;
		const float *zr = z + (size_t)y * w, *ar = ao + (size_t)y * w;
		const vf py0 = v_add(v_mul(v_set1((float)y), ay), by);
		int x = 0;
		for (; x + VN <= w; x += VN) {
			const vf zraw = v_load(zr + x);
			const vm has = v_gt(zraw, zero);
			if (!m_any(has)) {
				memset(row + 3 * (size_t)x, 0, 3 * VN); /* no depth: black */
				continue;
			}
			const vf zc = v_sel(has, zraw, one); /* lanes without depth: any finite value */
			float nx[VN], ny[VN], nz[VN];
			const float *N = n + 3 * ((size_t)y * w + x);
			for (int k = 0; k < VN; k++)
				nx[k] = N[3 * k], ny[k] = N[3 * k + 1], nz[k] = N[3 * k + 2];
			vf u = v_add(v_iota(), v_set1((float)x));
			vf p0 = v_mul(v_add(v_mul(u, ax), bx), zc), p1 = v_mul(py0, zc), p2 = zc;
			vf lp = v_sqrt(v_add(v_add(v_mul(p0, p0), v_mul(p1, p1)), v_mul(p2, p2)));
			vf dot = v_add(v_add(v_mul(v_load(nx), p0), v_mul(v_load(ny), p1)),
				       v_mul(v_load(nz), p2));
			vf ndl = v_div(v_neg(dot), lp);
			ndl = v_min(v_max(ndl, zero), one);
			vf g = v_mul(v_set1(255.0f), v_add(v_set1(0.12f), v_mul(v_set1(0.88f), ndl)));
			vf kv = v_min(v_max(v_load(ar + x), zero), one);
			/* clamp and round (ties to even, as lrintf) in the lanes */
			int32_t q[3][VN];
			for (int c = 0; c < 3; c++) {
				vf occ = v_set1(s->occ[c]);
				vf v = v_add(occ, v_mul(v_sub(g, occ), kv));
				v = v_sel(has, v_min(v_max(v, zero), v_set1(255.0f)), zero);
				vi_store(q[c], vi_from_whole(v_round(v)));
			}
			for (int k = 0; k < VN; k++)
				for (int c = 0; c < 3; c++)
					row[3 * (x + k) + c] = (uint8_t)q[c][k];
		}
		for (; x < w; x++) {
			float c[3];
			dao_shade_pixel(s, z, n, ao, x, y, c);
			for (int k = 0; k < 3; k++)
				row[3 * x + k] = (uint8_t)lrintf(c[k] < 0 ? 0 : c[k] > 255 ? 255 : c[k]);
		}
	}
}
