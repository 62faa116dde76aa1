/* SPDX-License-Identifier: MIT */
/*
 * The temporal depth filter of temporal_depth.c over SIMD lanes (pixels in
 * a row band, in order); included by temporal_depth_<isa>.c.  The same
 * operations in the same order as the reference (no FMA, true divisions:
 * three per vector, they are most of its cost),
 * so the result is identical; the pixels after the last whole vector go to
 * the reference (the filter works in place: an overlapping vector would run
 * a pixel twice).
 */
#include <stddef.h>

#include "pipeline/temporal_depth.h"

void DAO_ISA_FN(dao_temporal_depth)(const struct dao_temporal_depth_setup *s, float *z,
				    float *hist, uint8_t *count, uint8_t *age, int y0, int y1)
{
	const size_t i0 = (size_t)y0 * (size_t)s->width, i1 = (size_t)y1 * (size_t)s->width;
	const vf zero = v_zero(), one = v_set1(1.0f), top = v_set1((float)DAO_TEMPORAL_DEPTH_MAX_COUNT);
	const vf r2 = v_set1(s->reject * s->reject), wmin = v_set1(1.0f - s->alpha);
	const vf ema = v_set1((1.0f - s->alpha) / (1.0f + s->alpha));
	const vf k2 = v_set1(s->noise_k * s->noise_k);
	const vf q2 = v_set1(s->quantum * s->quantum / 12.0f);
	const vf persist = v_set1((float)s->persist), full = v_set1(255.0f);
	size_t i = i0;
	for (; i + VN <= i1; i += VN) {
		const vf zi = v_load(z + i), h = v_load(hist + i);
		const vf n = s->fresh ? zero : v_load_u8(count + i);
		const vf a = s->fresh ? full : v_load_u8(age + i);
		const vm has = v_gt(zi, zero);
		const vf inv = v_sel(has, v_div(one, v_sel(has, zi, one)), zero);
		vf var;
		if (s->sigma) {
			const vf sg = v_load(s->sigma + i);
			var = v_mul(sg, sg);
		} else {
			const vf inv2 = v_mul(inv, inv);
			var = v_add(k2, v_mul(v_mul(q2, inv2), inv2));
		}
		const vf d = v_sub(inv, h);
		const vf m = v_max(n, one), m1 = v_add(m, one);
		const vf q = v_div(one, v_mul(m, m1));
		const vf vh = v_max(v_mul(m1, q), ema);
		const vm keep = m_and(v_gt(n, zero),
				      v_le(v_mul(d, d), v_mul(r2, v_mul(var, v_add(one, vh)))));
		const vf n1 = v_sel(keep, v_min(v_add(n, one), top), one);
		const vf w = v_max(v_mul(m, q), wmin);
		const vf h1 = v_sel(keep, v_add(h, v_mul(w, d)), inv);
		const vf zk = v_sel(m_or(v_eq(n1, one), v_eq(h1, inv)), zi,
				    v_div(one, v_sel(has, h1, one)));
		/* (no pixel is held without persistence: no division then) */
		const vm hold = m_and(v_gt(n, zero), v_lt(a, persist));
		const vf zh = s->persist > 0 ? v_sel(hold, v_div(one, v_sel(hold, h, one)), zero) : zero;
		v_store(z + i, v_sel(has, zk, zh));
		v_store(hist + i, v_sel(has, h1, h));
		vi_store_u8(count + i, vi_from_whole(v_sel(has, n1, n)));
		vi_store_u8(age + i, vi_from_whole(v_sel(has, zero, v_min(v_add(a, one), full))));
	}
	dao_temporal_depth_span_ref(s, z, hist, count, age, i, i1);
}
