/* SPDX-License-Identifier: MIT */
/*
 * The reprojection's landing pass (motion/reproject.h) over SIMD lanes, VN
 * pixels of a row at a time; included by reproject_land_<isa>.c.  The
 * reference's float operations in its order (no FMA: the project builds as
 * ISO C, so nothing is contracted; the division is IEEE), so the same
 * landing pixels and 1/z to the bit; a row's last w mod VN pixels run the
 * reference's scalar code (motion/reproject_px.h).
 */
#include "motion/reproject.h"
#include "motion/reproject_px.h"

void DAO_ISA_FN(dao_reproject_land)(const struct dao_reproject_land *s, int y0, int y1)
{
	const int w = s->w, h = s->h;
	const float dgs[3] = {s->R[0] * s->ax, s->R[3] * s->ax, s->R[6] * s->ax};
	const vf dg0 = v_set1(dgs[0]), dg1 = v_set1(dgs[1]), dg2 = v_set1(dgs[2]);
	const vf T0 = v_set1(s->T[0]), T1 = v_set1(s->T[1]), T2 = v_set1(s->T[2]);
	const vf iax = v_set1(s->inv_ax), iay = v_set1(s->inv_ay);
	const vf ub = v_set1(s->ub), vb = v_set1(s->vb);
	const vf umax = v_set1((float)w - 0.5f), vmax = v_set1((float)h - 0.5f);
	const vf wf = v_set1((float)w), hf = v_set1((float)h);
	const vf zero = v_zero(), one = v_set1(1.0f), half = v_set1(0.5f), mhalf = v_set1(-0.5f);
	const vf none_lo = v_set1((float)h), none_hi = v_set1(-1.0f);
	const vi vw = vi_set1(w), minus1 = vi_set1(-1);
	for (int y = y0; y < y1; y++) {
		float g0s[3];
		dao_reproject_row_g0(s, y, g0s);
		const vf g00 = v_set1(g0s[0]), g01 = v_set1(g0s[1]), g02 = v_set1(g0s[2]);
		const size_t row = (size_t)y * (size_t)w;
		vf lo = none_lo, hi = none_hi;
		int x = 0;
		for (; x + VN <= w; x += VN) {
			const size_t i = row + (size_t)x;
			const vf hv = v_load(s->hist + i);
			const vf fx = v_add(v_set1((float)x), v_iota());
			const vf den = v_add(v_add(g02, v_mul(fx, dg2)), v_mul(T2, hv));
			const vm front = v_gt(den, zero);
			const vf d = v_div(one, v_sel(front, den, one));
			const vf qx = v_add(v_add(g00, v_mul(fx, dg0)), v_mul(T0, hv));
			const vf qy = v_add(v_add(g01, v_mul(fx, dg1)), v_mul(T1, hv));
			const vf u = v_sub(v_mul(v_mul(qx, d), iax), ub);
			const vf v = v_sub(v_mul(v_mul(qy, d), iay), vb);
			vm ok = m_and(m_and(v_gt(v_load_u8(s->count + i), zero), v_gt(hv, zero)), front);
			ok = m_and(ok, m_and(m_and(v_gt(u, mhalf), v_gt(v, mhalf)),
					     m_and(v_lt(u, umax), v_lt(v, vmax))));
			/* u > -0.5: floor(u + 0.5) is the reference's truncation */
			const vf xu = v_floor(v_add(v_sel(ok, u, zero), half));
			const vf yv = v_floor(v_add(v_sel(ok, v, zero), half));
			ok = m_and(ok, m_and(v_lt(xu, wf), v_lt(yv, hf)));
			const vi o = vi_add(vi_mul(vi_from_whole(yv), vw), vi_from_whole(xu));
			vi_store(s->dest + i, vi_sel(ok, o, minus1));
			v_store(s->zinv + i, v_mul(hv, d));
			lo = v_min(lo, v_sel(ok, yv, none_lo));
			hi = v_max(hi, v_sel(ok, yv, none_hi));
		}
		int32_t rlo = (int32_t)-v_hmax(v_neg(lo)), rhi = (int32_t)v_hmax(hi);
		dao_reproject_px_span(s, g0s, dgs, x, w, row, &rlo, &rhi);
		s->rows[2 * y] = rlo;
		s->rows[2 * y + 1] = rhi;
	}
}
