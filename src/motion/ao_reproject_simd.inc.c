/* SPDX-License-Identifier: MIT */
/*
 * The AO history's reprojection (motion/ao_reproject.h) over SIMD lanes, VN
 * pixels of a row at a time; included by ao_reproject_<isa>.c.  The
 * reference's steps in floats where it computes in doubles (the row's rays
 * are still made in doubles): the landing point, the taps' weights and
 * depth test and the history depth differ from it by float rounding, so a
 * tap at the depth test's edge or a landing point at the snap's or the
 * image's border may decide the other way (tests/pipeline/test_ao_history.c
 * states the bound).  The history depth is written as hz (zc + c) / qz - c,
 * the reference's s zc + (s - 1) c with s = hz / qz, so that the identity
 * motion (qz = zc, c = 0) still copies the history bit for bit.  The taps are
 * gathers; a row's last w mod VN pixels run in masked lanes.
 */
#include "motion/ao_reproject.h"

/* What every vector of the pass reads: the history and the constants. */
struct ar_ctx {
	const float *hist_ao, *hist_z;
	vf c, one, half, zero, xlast, ylast, snap, tiny, rej;
	vi vw, one_i;
};

/*
 * The history at the landing points (u, v) of the lanes in ok: the pixel
 * itself at a pixel centre, else bilinear over the taps whose depth agrees
 * with qz; the AO into *ao_o and the history's depth in the current view
 * into *z_o (0 where none agrees).
 */
static inline __attribute__((always_inline)) void
ar_sample(const struct ar_ctx *x, vm ok, vf u, vf v, vf zc, vf qz, vf qs, vf *ao_o, vf *z_o)
{
	const vf zero = x->zero, one = x->one;
	const vf us = v_sel(ok, u, zero), vs = v_sel(ok, v, zero);
	const vf x0 = v_floor(us), y0f = v_floor(vs);
	const vf a = v_sub(us, x0), b = v_sub(vs, y0f);
	/* the nearest pixel */
	const vf xn = v_add(x0, v_keep(v_ge(a, x->half), one));
	const vf yn = v_add(y0f, v_keep(v_ge(b, x->half), one));
	const vm near = m_and(v_lt(v_abs(v_sub(us, xn)), x->snap),
			      v_lt(v_abs(v_sub(vs, yn)), x->snap));
	const vf rq = v_mul(x->rej, qz);
	/* a landing point at a pixel centre: that pixel alone */
	const vm ms = m_and(ok, near);
	const vi js = vi_add(vi_mul(vi_from_whole(yn), x->vw), vi_from_whole(xn));
	vf hzs = zero, aos = zero;
	vm gs = ms;
	if (m_any(ms)) {
		/* both at once: the AO's gather does not wait for the test */
		hzs = v_gather(x->hist_z, js, ms);
		aos = v_gather(x->hist_ao, js, ms);
		gs = m_and(m_and(ms, v_gt(hzs, zero)), v_le(v_abs(v_sub(hzs, qz)), rq));
	}
	/* else bilinear over the taps whose depth agrees */
	const vm mb = m_andnot(ok, near);
	const vf wx[2] = {v_sub(one, a), a}, wy[2] = {v_sub(one, b), b};
	const vm cx_ok[2] = {m_and(v_ge(x0, zero), v_gt(wx[0], zero)),
			     m_and(v_lt(x0, x->xlast), v_gt(wx[1], zero))};
	const vm ry_ok[2] = {m_and(v_ge(y0f, zero), v_gt(wy[0], zero)),
			     m_and(v_lt(y0f, x->ylast), v_gt(wy[1], zero))};
	const vi j00 = vi_add(vi_mul(vi_from_whole(y0f), x->vw), vi_from_whole(x0));
	vf sw = zero, sao = zero, sz = zero;
	for (int dy = 0; dy < 2; dy++)
		for (int dx = 0; dx < 2; dx++) {
			const vm m = m_and(mb, m_and(ry_ok[dy], cx_ok[dx]));
			if (!m_any(m))
				continue;
			vi j = j00;
			if (dx)
				j = vi_add(j, x->one_i);
			if (dy)
				j = vi_add(j, x->vw);
			const vf hz = v_gather(x->hist_z, j, m);
			const vf tao = v_gather(x->hist_ao, j, m);
			const vm g = m_and(m_and(m, v_gt(hz, zero)), v_le(v_abs(v_sub(hz, qz)), rq));
			const vf wt = v_keep(g, v_mul(wy[dy], wx[dx]));
			sw = v_add(sw, wt);
			sao = v_add(sao, v_mul(wt, v_keep(g, tao)));
			sz = v_add(sz, v_mul(wt, v_keep(g, hz)));
		}
	const vm gb = m_and(mb, v_gt(sw, x->tiny));
	const vf sws = v_sel(gb, sw, one);
	const vf ao = v_sel(ms, aos, v_div(sao, sws));
	const vf hz = v_sel(ms, hzs, v_div(sz, sws));
	/* the history's point (on the previous ray through q, at hz) in the
	 * current view: hz (zc + c) / qz - c */
	const vf zh = v_sub(v_mul(hz, v_div(v_add(zc, x->c), qs)), x->c);
	const vm good = m_and(m_or(gs, gb), v_gt(zh, zero));
	*ao_o = v_keep(good, ao);
	*z_o = v_keep(good, zh);
}

void DAO_ISA_FN(dao_ao_history_reproject_rows)(const struct dao_camera *cam,
					       const struct dao_pose *cur_to_prev, float reject,
					       const float *z, const float *hist_ao,
					       const float *hist_z, float *ao_out, float *z_out,
					       int y0, int y1)
{
	const int w = (int)cam->width, h = (int)cam->height;
	const double *R = cur_to_prev->r, *t = cur_to_prev->t;
	/* the z of R^T t: where the previous camera's offset lies along the current view */
	const double cd = R[2] * t[0] + R[5] * t[1] + R[8] * t[2];
	const double axd = 1.0 / cam->fx, bxd = -cam->cx / cam->fx;
	const vf c = v_set1((float)cd), t0 = v_set1((float)t[0]), t1 = v_set1((float)t[1]);
	const vf t2 = v_set1((float)t[2]);
	const vf fx = v_set1((float)cam->fx), cx = v_set1((float)cam->cx);
	const vf fy = v_set1((float)cam->fy), cy = v_set1((float)cam->cy);
	const vf zero = v_zero(), one = v_set1(1.0f), half = v_set1(0.5f), mhalf = v_set1(-0.5f);
	const vf umax = v_set1((float)w - 0.5f), vmax = v_set1((float)h - 0.5f);
	const vf xlast = v_set1((float)(w - 1)), ylast = v_set1((float)(h - 1));
	const vf snap = v_set1(1e-3f), tiny = v_set1(1e-6f), rej = v_set1(reject);
	const vi vw = vi_set1(w), one_i = vi_set1(1), lanes = vi_from_whole(v_iota());
	const struct ar_ctx ctx = {
		.hist_ao = hist_ao, .hist_z = hist_z, .c = c, .one = one, .half = half,
		.zero = zero, .xlast = xlast, .ylast = ylast, .snap = snap, .tiny = tiny,
		.rej = rej, .vw = vw, .one_i = one_i,
	};
	for (int y = y0; y < y1; y++) {
		const double ry = ((double)y - cam->cy) / cam->fy;
		/* R times the ray of pixel (x, y), (x ax + bx, ry, 1): rb + x rd */
		vf rb[3], rd[3];
		for (int k = 0; k < 3; k++) {
			rb[k] = v_set1((float)(R[k * 3] * bxd + R[k * 3 + 1] * ry + R[k * 3 + 2]));
			rd[k] = v_set1((float)(R[k * 3] * axd));
		}
		for (int x = 0; x < w; x += VN) {
			const size_t i = (size_t)y * (size_t)w + (size_t)x;
			const int n = w - x < VN ? w - x : VN;
			const vm in = v_lt(v_iota(), v_set1((float)n));
			const vf zc = n == VN ? v_load(z + i) : v_gather(z + i, lanes, in);
			vm ok = m_and(in, v_gt(zc, zero));
			/* q = R p + t, p = zc ray */
			const vf xf = v_add(v_set1((float)x), v_iota());
			const vf qx = v_add(v_mul(zc, v_add(rb[0], v_mul(xf, rd[0]))), t0);
			const vf qy = v_add(v_mul(zc, v_add(rb[1], v_mul(xf, rd[1]))), t1);
			const vf qz = v_add(v_mul(zc, v_add(rb[2], v_mul(xf, rd[2]))), t2);
			ok = m_and(ok, v_gt(qz, zero)); /* else behind the previous camera */
			const vf qs = v_sel(ok, qz, one);
			const vf u = v_add(v_div(v_mul(fx, qx), qs), cx);
			const vf v = v_add(v_div(v_mul(fy, qy), qs), cy);
			/* else outside the previous image */
			ok = m_and(ok, m_and(m_and(v_gt(u, mhalf), v_gt(v, mhalf)),
					     m_and(v_lt(u, umax), v_lt(v, vmax))));
			vf ao_o = zero, z_o = zero;
			if (m_any(ok))
				ar_sample(&ctx, ok, u, v, zc, qz, qs, &ao_o, &z_o);
			if (n == VN) {
				v_store(ao_out + i, ao_o);
				v_store(z_out + i, z_o);
			} else {
				float la[VN], lz[VN];
				v_store(la, ao_o);
				v_store(lz, z_o);
				for (int k = 0; k < n; k++)
					ao_out[i + (size_t)k] = la[k], z_out[i + (size_t)k] = lz[k];
			}
		}
	}
}
