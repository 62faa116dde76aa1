/* SPDX-License-Identifier: MIT */
/*
 * The source grid and the target's depth (motion/icp_source.h) over SIMD
 * lanes, VN grid points or pixels at a time; included by
 * icp_source_<isa>.c.  The reference's float operations in its order (no
 * FMA: the project builds as ISO C, so the compiler contracts nothing;
 * division and square root are IEEE), hence its output to the bit.  A grid
 * row's taps are gathers (the points are `step` pixels apart), or at step 4
 * away from the row's ends four loads de-interleaved.
 */
#include <string.h>

#include "motion/icp_normal_simd.h"
#include "motion/icp_pairs.h"
#include "motion/icp_source.h"

/* p[0], p[4], p[8], ... (VN values) */
static inline vf DAO_ISA_FN(every4th)(const float *p)
{
	const vf v[4] = {v_load(p), v_load(p + VN), v_load(p + 2 * VN), v_load(p + 3 * VN)};
	vf q[4];
	v_deinterleave4(v, q);
	return q[0];
}

void DAO_ISA_FN(dao_icp_source)(const struct dao_icp_grid *g, int y, float *out)
{
	const size_t st = g->stride;
	const int w = g->w, r = g->r;
	const int end = (g->gw + DAO_ICP_PAD - 1) / DAO_ICP_PAD * DAO_ICP_PAD;
	if (y < r || y >= g->h - r) {
		for (int k = 0; k < 6; k++)
			memset(out + (size_t)k * st, 0, (size_t)end * sizeof(float));
		return;
	}
	const float *row = g->z + (size_t)y * (size_t)w;
	const float *up = row - (size_t)r * (size_t)w, *down = row + (size_t)r * (size_t)w;
	const float vys = (float)y * g->ay + g->by;
	const vf vy = v_set1(vys), vu = v_set1(vys - g->ray), vd = v_set1(vys + g->ray);
	const vf stepf = v_set1((float)g->step), rf = v_set1((float)r), wr = v_set1((float)(w - r));
	const vf edge = v_set1(g->edge_r), ax = v_set1(g->ax), bx = v_set1(g->bx);
	const vf rax = v_set1(g->rax), zero = v_zero(), one = v_set1(1.0f);
	const vi ml = vi_set1(-r), mr = vi_set1(r);
	for (int gx = 0; gx < end; gx += VN) {
		const vf xf = v_mul(v_add(v_set1((float)gx), v_iota()), stepf);
		/* x < w - r also ends the row: a column past gw has x >= w */
		vm ok = m_and(v_ge(xf, rf), v_lt(xf, wr));
		float *o = out + gx;
		if (!m_any(ok)) {
			for (int k = 0; k < 6; k++)
				v_store(o + (size_t)k * st, zero);
			continue;
		}
		vf z, zl, zr, zu, zd;
		const int x0 = gx * g->step;
		if (g->step == 4 && x0 >= r && x0 + r + 4 * VN <= w) {
			/* every 4th pixel: four vectors' loads de-interleaved, no gathers
			 * (the lanes' values are the gathers', all inside the row) */
			z = DAO_ISA_FN(every4th)(row + x0);
			zl = DAO_ISA_FN(every4th)(row + x0 - r);
			zr = DAO_ISA_FN(every4th)(row + x0 + r);
			zu = DAO_ISA_FN(every4th)(up + x0);
			zd = DAO_ISA_FN(every4th)(down + x0);
		} else {
			const vi k = vi_from_whole(v_sel(ok, xf, rf));
			z = v_gather(row, k, ok);
			zl = v_gather(row, vi_add(k, ml), ok);
			zr = v_gather(row, vi_add(k, mr), ok);
			zu = v_gather(up, k, ok);
			zd = v_gather(down, k, ok);
		}
		ok = icp_smooth(ok, z, zl, zr, zu, zd, edge);
		const vf ux = v_add(v_mul(xf, ax), bx);
		const vf ul = v_sub(ux, rax), ur = v_add(ux, rax);
		const vf p0 = v_mul(ux, z), p1 = v_mul(vy, z);
		vf cn[3];
		icp_cross(ux, vy, ul, ur, vu, vd, zl, zr, zu, zd, cn);
		const vf c0 = cn[0], c1 = cn[1], c2 = cn[2];
		const vf len = v_sqrt(v_add(v_add(v_mul(c0, c0), v_mul(c1, c1)), v_mul(c2, c2)));
		ok = m_and(ok, v_gt(len, zero));
		const vf cp = v_add(v_add(v_mul(c0, p0), v_mul(c1, p1)), v_mul(c2, z));
		const vf sg = v_sel(v_gt(cp, zero), v_set1(-1.0f), one);
		const vf l = v_sel(ok, len, one);
		v_store(o, v_keep(ok, p0));
		v_store(o + st, v_keep(ok, p1));
		v_store(o + 2 * st, v_keep(ok, z));
		v_store(o + 3 * st, v_keep(ok, v_div(v_mul(sg, c0), l)));
		v_store(o + 4 * st, v_keep(ok, v_div(v_mul(sg, c1), l)));
		v_store(o + 5 * st, v_keep(ok, v_div(v_mul(sg, c2), l)));
	}
}

void DAO_ISA_FN(dao_icp_target)(const float *inv, const uint8_t *count, float *tz, size_t i0,
				size_t i1)
{
	const vf zero = v_zero(), one = v_set1(1.0f);
	size_t i = i0;
	for (; i + VN <= i1; i += VN) {
		const vf v = v_load(inv + i);
		vm has = v_gt(v, zero);
		if (count)
			has = m_and(has, v_gt(v_load_u8(count + i), zero));
		v_store(tz + i, v_keep(has, v_div(one, v_sel(has, v, one))));
	}
	for (; i < i1; i++) {
		const float v = inv[i];
		const int has = v > 0.0f && (!count || count[i]);
		tz[i] = has ? 1.0f / v : 0.0f;
	}
}
