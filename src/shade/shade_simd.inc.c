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
			vf nx, ny, nz;
			v_load3(n + 3 * ((size_t)y * w + x), &nx, &ny, &nz);
			vf u = v_add(v_iota(), v_set1((float)x));
			vf p0 = v_mul(v_add(v_mul(u, ax), bx), zc), p1 = v_mul(py0, zc), p2 = zc;
			vf lp = v_sqrt(v_add(v_add(v_mul(p0, p0), v_mul(p1, p1)), v_mul(p2, p2)));
			vf dot = v_add(v_add(v_mul(nx, p0), v_mul(ny, p1)), v_mul(nz, p2));
			vf ndl = v_div(v_neg(dot), lp);
			ndl = v_min(v_max(ndl, zero), one);
			vf g = v_mul(v_set1(255.0f), v_add(v_set1(0.12f), v_mul(v_set1(0.88f), ndl)));
			vf kv = v_min(v_max(v_load(ar + x), zero), one);
			/* clamp and round (ties to even, as lrintf) in the lanes */
			vf ch[3];
			for (int c = 0; c < 3; c++) {
				vf occ = v_set1(s->occ[c]);
				vf v = v_add(occ, v_mul(v_sub(g, occ), kv));
				ch[c] = v_round(v_sel(has, v_min(v_max(v, zero), v_set1(255.0f)), zero));
			}
			/* RGB triples of the lanes, then bytes */
			float rgb[3 * VN];
			v_store3(rgb, ch[0], ch[1], ch[2]);
			for (int k = 0; k < 3; k++)
				vi_store_u8(row + 3 * (size_t)x + (size_t)k * VN,
					    vi_from_whole(v_load(rgb + k * VN)));
		}
		for (; x < w; x++) {
			float c[3];
			dao_shade_pixel(s, z, n, ao, x, y, c);
			for (int k = 0; k < 3; k++)
				row[3 * x + k] = (uint8_t)lrintf(c[k] < 0 ? 0 : c[k] > 255 ? 255 : c[k]);
		}
	}
}
