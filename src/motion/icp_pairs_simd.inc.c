/* SPDX-License-Identifier: MIT */
/*
 * The pair kernel (motion/icp_pairs.h) over SIMD lanes, VN source points at
 * a time; included by icp_pairs_<isa>.c.  The geometry is the reference's,
 * operation for operation in floats (no FMA there); the sums run per lane in
 * floats (with FMA) over at most DAO_ICP_CHUNK points and are then added
 * lane by lane in doubles, so they differ from the reference's double sums
 * by float rounding (tests/simd/test_icp_pairs.c states the bound).  Lanes
 * past the range are masked; the source arrays are padded with zeros to a
 * multiple of DAO_ICP_PAD, so the loads stay inside them.
 */
#include <string.h>

#include "motion/icp_normal_simd.h"
#include "motion/icp_pairs.h"

enum { NSUM = 21 + 6 + 4 };

/* the lanes' pairs into the per-lane sums (lanes not `ok` add 0) */
static inline void DAO_ISA_FN(icp_sum)(vf acc[NSUM], vm ok, vf wgt, vf res, vf bw, vf e, vf j[6])
{
	int n = 0;
	for (int a = 0; a < 6; a++) {
		j[a] = v_keep(ok, j[a]);
		const vf wj = v_mul(wgt, j[a]);
		for (int b = a; b < 6; b++, n++)
			acc[n] = v_fma(wj, j[b], acc[n]);
		acc[21 + a] = v_fnma(wj, res, acc[21 + a]);
	}
	acc[27] = v_fma(res, res, acc[27]);
	acc[28] = v_fma(v_mul(bw, e), e, acc[28]);
	acc[29] = v_add(acc[29], bw);
	acc[30] = v_add(acc[30], v_keep(ok, v_set1(1.0f)));
}

static void DAO_ISA_FN(icp_block)(const struct dao_icp_step *st, int i0, int i1, vf acc[NSUM])
{
	const size_t cap = st->cap;
	const float *s = st->src;
	const vf zero = v_zero(), one = v_set1(1.0f), half = v_set1(0.5f);
	const int w = st->w, r = st->r;
	const vf lo = v_set1((float)r - 0.5f), hix = v_set1((float)(w - r) - 0.5f);
	const vf hiy = v_set1((float)(st->h - r) - 0.5f), rf = v_set1((float)r);
	const vi vw = vi_set1(w), vr = vi_set1(r), vrw = vi_set1(r * w);
	const vf tolk = v_set1(st->edge * (float)r);
	const vf ra = v_set1((float)r * st->ax), rb = v_set1((float)r * st->ay);
	const vf ax = v_set1(st->ax), bx = v_set1(st->bx), ay = v_set1(st->ay), by = v_set1(st->by);
	const vf iax = v_set1(st->inv_ax), iay = v_set1(st->inv_ay);
	const vf k2 = v_set1(st->k2), q2 = v_set1(st->q2), gate2 = v_set1(st->gate2);
	const vf cosg = v_set1(st->cos_gate), itc = v_set1(1.0f / st->tukey_c);
	const vf isc = v_set1(st->inv_scale);
	vf R[9], t[3];
	for (int k = 0; k < 9; k++)
		R[k] = v_set1(st->R[k]);
	for (int k = 0; k < 3; k++)
		t[k] = v_set1(st->t[k]);
	for (int i = i0; i < i1; i += VN) {
		vm ok = v_lt(v_iota(), v_set1((float)(i1 - i)));
		const vf sx = v_load(s + i), sy = v_load(s + cap + i), sz = v_load(s + 2 * cap + i);
		const vf p0 = v_add(v_add(v_add(v_mul(R[0], sx), v_mul(R[1], sy)), v_mul(R[2], sz)), t[0]);
		const vf p1 = v_add(v_add(v_add(v_mul(R[3], sx), v_mul(R[4], sy)), v_mul(R[5], sz)), t[1]);
		const vf p2 = v_add(v_add(v_add(v_mul(R[6], sx), v_mul(R[7], sy)), v_mul(R[8], sz)), t[2]);
		ok = m_and(ok, v_gt(p2, zero));
		const vf iz = v_div(one, v_sel(ok, p2, one));
		const vf u = v_mul(v_sub(v_mul(p0, iz), bx), iax);
		const vf v = v_mul(v_sub(v_mul(p1, iz), by), iay);
		ok = m_and(ok, m_and(m_and(v_gt(u, lo), v_gt(v, lo)), m_and(v_lt(u, hix), v_lt(v, hiy))));
		if (!m_any(ok))
			continue;
		const vf xf = v_round(v_sel(ok, u, rf)), yf = v_round(v_sel(ok, v, rf));
		const vi k = vi_add(vi_mul(vi_from_whole(yf), vw), vi_from_whole(xf));
		const vf z = v_gather(st->tz, k, ok);
		const vf zl = v_gather(st->tz, vi_add(k, vi_set1(-r)), ok);
		const vf zr = v_gather(st->tz, vi_add(k, vr), ok);
		const vf zu = v_gather(st->tz, vi_add(k, vi_set1(-r * w)), ok);
		const vf zd = v_gather(st->tz, vi_add(k, vrw), ok);
		ok = icp_smooth(ok, z, zl, zr, zu, zd, tolk);
		const vf ux = v_add(v_mul(xf, ax), bx), vy = v_add(v_mul(yf, ay), by);
		const vf ul = v_sub(ux, ra), ur = v_add(ux, ra), vu = v_sub(vy, rb), vd = v_add(vy, rb);
		const vf q0 = v_mul(ux, z), q1 = v_mul(vy, z);
		vf cn[3];
		icp_cross(ux, vy, ul, ur, vu, vd, zl, zr, zu, zd, cn);
		const vf c0 = cn[0], c1 = cn[1], c2 = cn[2];
		const vf len2 = v_add(v_add(v_mul(c0, c0), v_mul(c1, c1)), v_mul(c2, c2));
		ok = m_and(ok, v_gt(len2, zero));
		const vf cq = v_add(v_add(v_mul(c0, q0), v_mul(c1, q1)), v_mul(c2, z));
		const vf sg = v_sel(v_gt(cq, zero), v_set1(-1.0f), one);
		const vf il = v_div(sg, v_sqrt(v_sel(ok, len2, one)));
		const vf m0 = v_mul(c0, il), m1 = v_mul(c1, il), m2 = v_mul(c2, il);
		const vf d0 = v_sub(p0, q0), d1 = v_sub(p1, q1), d2 = v_sub(p2, z);
		ok = m_and(ok, v_le(v_add(v_add(v_mul(d0, d0), v_mul(d1, d1)), v_mul(d2, d2)), gate2));
		const vf nx = v_load(s + 3 * cap + i), ny = v_load(s + 4 * cap + i);
		const vf nz = v_load(s + 5 * cap + i);
		const vf rn0 = v_add(v_add(v_mul(R[0], nx), v_mul(R[1], ny)), v_mul(R[2], nz));
		const vf rn1 = v_add(v_add(v_mul(R[3], nx), v_mul(R[4], ny)), v_mul(R[5], nz));
		const vf rn2 = v_add(v_add(v_mul(R[6], nx), v_mul(R[7], ny)), v_mul(R[8], nz));
		ok = m_and(ok, v_ge(v_add(v_add(v_mul(rn0, m0), v_mul(rn1, m1)), v_mul(rn2, m2)), cosg));
		const vf rr = v_add(v_add(v_mul(m0, d0), v_mul(m1, d1)), v_mul(m2, d2));
		const vf mp = v_mul(v_add(v_add(v_mul(m0, p0), v_mul(m1, p1)), v_mul(m2, p2)), iz);
		const vf zs = v_sel(ok, z, one);
		const vf mq = v_div(v_add(v_add(v_mul(m0, q0), v_mul(m1, q1)), v_mul(m2, z)), zs);
		const vf pp = v_mul(p2, p2), zz = v_mul(z, z);
		const vf vp = v_add(v_mul(k2, v_mul(pp, pp)), q2), vq = v_add(v_mul(k2, v_mul(zz, zz)), q2);
		const vf quarter = v_set1(0.25f);
		const vf var = v_sel(ok, v_add(v_mul(v_max(v_mul(mp, mp), quarter), vp),
						 v_mul(v_max(v_mul(mq, mq), quarter), vq)), one);
		const vf ee = v_div(rr, v_sqrt(var));
		const vf f = v_mul(ee, itc), f2 = v_mul(f, f);
		ok = m_and(ok, v_lt(f2, one));
		if (!m_any(ok))
			continue;
		const vf bw = v_keep(ok, v_mul(v_sub(one, f2), v_sub(one, f2)));
		const vf wgt = st->noise_weight ? v_div(bw, var) : bw;
		const vf cx = v_mul(half, v_add(p0, q0)), cy = v_mul(half, v_add(p1, q1));
		const vf cz = v_mul(half, v_add(p2, z));
		const vf res = v_keep(ok, rr), e = v_keep(ok, ee);
		vf j[6] = {v_mul(v_sub(v_mul(cy, m2), v_mul(cz, m1)), isc),
			   v_mul(v_sub(v_mul(cz, m0), v_mul(cx, m2)), isc),
			   v_mul(v_sub(v_mul(cx, m1), v_mul(cy, m0)), isc), m0, m1, m2};
		DAO_ISA_FN(icp_sum)(acc, ok, wgt, res, bw, e, j);
	}
}

void DAO_ISA_FN(dao_icp_pairs)(const struct dao_icp_step *st, int i0, int i1,
			       struct dao_icp_sums *out)
{
	memset(out, 0, sizeof *out);
	for (int c0 = i0; c0 < i1; c0 += DAO_ICP_CHUNK) {
		const int c1 = i1 - c0 > DAO_ICP_CHUNK ? c0 + DAO_ICP_CHUNK : i1;
		vf acc[NSUM];
		for (int k = 0; k < NSUM; k++)
			acc[k] = v_zero();
		DAO_ISA_FN(icp_block)(st, c0, c1, acc);
		float lane[VN];
		double sum[NSUM];
		for (int k = 0; k < NSUM; k++) {
			v_store(lane, acc[k]);
			sum[k] = 0.0;
			for (int l = 0; l < VN; l++)
				sum[k] += lane[l];
		}
		for (int k = 0; k < 21; k++)
			out->a[k] += sum[k];
		for (int k = 0; k < 6; k++)
			out->b[k] += sum[21 + k];
		out->r2 += sum[27];
		out->e2w += sum[28];
		out->wsum += sum[29];
		out->n += (int)sum[30];
	}
}
