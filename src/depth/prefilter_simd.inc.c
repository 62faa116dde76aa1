/* SPDX-License-Identifier: MIT */
/*
 * The prefilter passes of prefilter.c over SIMD lanes (pixels along a row);
 * included by prefilter_<isa>.c after the SIMD vocabulary.  Same maths, with
 * the weights' exp from simd/fastmath.h (v_exp2_neg_fast, 7.5e-5 relative: a
 * weight's error moves the filtered depth by that times the spread of the
 * window, ~1e-7).
 */
#include <stddef.h>

#include "depth/prefilter.h"
#include "simd/fastmath.h"

/* The weights are 2^x with log2 e folded into the range and spatial terms. */
#define PF_LOG2E 1.44269504088896f

/* log2 e / (2 sigma_range^2) per lane (dao_prefilter_inv_2rr times log2 e) */
static inline vf inv_2rr(const struct dao_prefilter_setup *s, vf wc)
{
	vf sw = v_mul(v_max(v_set1(s->noise_k), v_mul(v_mul(v_set1(s->unit), wc), wc)),
		      v_set1(DAO_PREFILTER_RANGE_SIGMAS));
	sw = v_max(sw, v_mul(v_set1(1e-6f), wc));
	return v_div(v_set1(PF_LOG2E), v_mul(v_mul(v_set1(2.0f), sw), sw));
}

/* Columns per chunk of the horizontal pass: 1/z of the chunk and its borders
 * is made once into a buffer (zeros off the image, which weigh 0 as holes). */
#define PF_CHUNK 512
#define PF_MAX_RADIUS 8

void DAO_ISA_FN(dao_prefilter_h)(const struct dao_prefilter_setup *s, const float *z, float *tmp,
				 int y0, int y1)
{
	const int w = s->width, r = s->radius > PF_MAX_RADIUS ? PF_MAX_RADIUS : s->radius;
	const vf one = v_set1(1.0f), zero = v_zero();
	float wb[PF_CHUNK + 2 * PF_MAX_RADIUS + VN];
	float spatial[2 * PF_MAX_RADIUS + 1];
	for (int i = -r; i <= r; i++)
		spatial[i + r] = -(float)(i * i) * s->inv_2ss * PF_LOG2E;
	for (int y = y0; y < y1; y++) {
		const float *row = z + (size_t)y * w;
		float *o = tmp + (size_t)y * w;
		for (int x0 = 0; x0 < w; x0 += PF_CHUNK) {
			const int n = w - x0 < PF_CHUNK ? w - x0 : PF_CHUNK;
			/* wb[i + r] is column x0 + i, for i in [-r, n + r + VN) */
			for (int i = -r; i < n + r + VN; i++) {
				const int x = x0 + i;
				const float zz = x >= 0 && x < w ? row[x] : 0.0f;
				wb[i + r] = zz > 0.0f ? 1.0f / zz : 0.0f;
			}
			for (int i = 0; i < n; i += VN) {
				const float *c = wb + r + i;
				const vf wc = v_load(c);
				const vm has = v_gt(wc, zero);
				const vf k = inv_2rr(s, v_sel(has, wc, one));
				vf sum = wc, wsum = v_sel(has, one, zero); /* the centre weighs 1 */
				for (int t = -r; t <= r; t++) {
					if (t == 0)
						continue;
					const vf ws = v_load(c + t);
					const vm ok = v_gt(ws, zero);
					const vf d = v_sub(ws, wc);
					const vf e = v_fnma(v_mul(d, d), k, v_set1(spatial[t + r]));
					const vf wt = v_sel(ok, v_exp2_neg_fast(e), zero);
					sum = v_fma(wt, ws, sum);
					wsum = v_add(wsum, wt);
				}
				const vf res = v_sel(has, v_div(sum, v_sel(has, wsum, one)), zero);
				if (i + VN <= n) {
					v_store(o + x0 + i, res);
				} else {
					float l[VN];
					v_store(l, res);
					for (int k2 = 0; i + k2 < n; k2++)
						o[x0 + i + k2] = l[k2];
				}
			}
		}
	}
}

void DAO_ISA_FN(dao_prefilter_v)(const struct dao_prefilter_setup *s, const float *tmp, float *out,
				 int y0, int y1)
{
	const int w = s->width, r = s->radius;
	const vf one = v_set1(1.0f), zero = v_zero();
	for (int y = y0; y < y1; y++) {
		const int a = y - r < 0 ? 0 : y - r, b = y + r >= s->height ? s->height - 1 : y + r;
		float *o = out + (size_t)y * w;
		int x = 0;
		for (; x + VN <= w; x += VN) {
			vf wc = v_load(tmp + (size_t)y * w + x);
			vm has = v_gt(wc, zero);
			vf k = inv_2rr(s, v_sel(has, wc, one));
			vf sum = zero, wsum = zero;
			for (int j = a; j <= b; j++) {
				vf ws = v_load(tmp + (size_t)j * w + x);
				vm ok = v_gt(ws, zero);
				vf d = v_sub(ws, wc);
				vf e = v_fnma(v_mul(d, d), k,
					      v_set1(-(float)((j - y) * (j - y)) * s->inv_2ss * PF_LOG2E));
				vf wt = v_sel(ok, v_exp2_neg_fast(e), zero);
				sum = v_fma(wt, ws, sum);
				wsum = v_add(wsum, wt);
			}
			vf m = v_div(sum, v_sel(has, wsum, one));
			v_store(o + x, v_sel(has, v_div(one, v_sel(has, m, one)), zero));
		}
		for (; x < w; x++)
			o[x] = dao_prefilter_v_pixel(s, tmp, x, y);
	}
}
