/* SPDX-License-Identifier: MIT */
/*
 * Normals from depth (normals.c) over SIMD lanes along a row; included by
 * normals_<isa>.c after the SIMD vocabulary.  The lanes take the common
 * case: the pixel and its four neighbours at distance r all have depth.
 * Groups with a hole, and pixels within r of the border, use the reference
 * per-pixel code.
 */
#include <stddef.h>

#include "normals/normals.h"

/*
 * One axis's one-sided difference at every lane (axis_delta of normals.c):
 * the largest k <= r with a neighbour at +-k, of those the side with the
 * smaller |dz|.  c: the centre's depths, at: the row/column step between taps
 * (1 or the width), zc the centre depth; taps beyond r_minus before and
 * r_plus after the centre are off the image.  Returns the found lanes; *zq
 * the neighbour's depth and *off its signed offset in pixels.
 */
static inline vm pick_side(const float *c, ptrdiff_t at, int r, int r_minus, int r_plus, vf zc,
			   vf *zq, vf *off)
{
	const vf zero = v_zero();
	vm found = v_gt(zero, zero); /* no lane yet */
	*zq = zero;
	*off = zero;
	for (int k = r; k >= 1; k--) {
		/* off the image (k beyond r_minus / r_plus): no data */
		const vf zm = k <= r_minus ? v_load(c - k * at) : zero;
		const vf zp = k <= r_plus ? v_load(c + k * at) : zero;
		const vm hm = v_gt(zm, zero), hp = v_gt(zp, zero);
		const vm take = m_andnot(m_or(hm, hp), found);
		/* +k when it has data and -k has none or a larger |dz| */
		const vm nearer = v_lt(v_abs(v_sub(zp, zc)), v_abs(v_sub(zc, zm)));
		const vm plus = m_andnot(hp, m_andnot(hm, nearer));
		*zq = v_sel(take, v_sel(plus, zp, zm), *zq);
		*off = v_sel(take, v_sel(plus, v_set1((float)k), v_set1(-(float)k)), *off);
		found = m_or(found, take);
	}
	return found;
}

void DAO_ISA_FN(dao_normals_from_depth)(const struct dao_camera *cam, const float *z, int r,
					float *n, int y0, int y1)
{
	const int w = (int)cam->width, h = (int)cam->height;
	const vf zero = v_zero(), ax = v_set1(cam->ax), bx = v_set1(cam->bx), ay = v_set1(cam->ay),
		 by = v_set1(cam->by), fr = v_set1((float)r);
	for (int y = y0; y < y1; y++) {
		float *out = n + 3 * (size_t)y * w;
		/* rows within r of the top or bottom: the taps off the image have no
		 * data, as in the reference */
		const int up = y < r ? y : r, down = y + r >= h ? h - 1 - y : r;
		const int inner = up == r && down == r;
		int x = 0;
		if (w >= 2 * r + VN) {
			for (x = 0; x < r; x++)
				dao_normal_pixel(cam, z, r, x, y, out + 3 * x);
			const float *row = z + (size_t)y * w;
			/* the last vector ends r before the border, overlapping the one
			 * before (outputs depend only on the inputs) */
			const int xlast = w - r - VN;
			for (; x <= xlast; x = (x < xlast && x + VN > xlast) ? xlast : x + VN) {
				vf zc = v_load(row + x), zl = v_load(row + x - r), zr = v_load(row + x + r);
				const vm has = v_gt(zc, zero);
				if (!m_any(has)) { /* no depth: (0, 0, -1) */
					v_store3(out + 3 * x, zero, zero, v_set1(-1.0f));
					continue;
				}
				vm ok = m_and(has, m_and(v_gt(zl, zero), v_gt(zr, zero)));
				vf zu = zero, zd = zero;
				if (inner) {
					zu = v_load(row + x - (size_t)r * w);
					zd = v_load(row + x + (size_t)r * w);
					ok = m_and(ok, m_and(v_gt(zu, zero), v_gt(zd, zero)));
				}
				vf zqx, offx, zqy, offy;
				vm found = has;
				if (inner && m_all(ok)) {
					/* the common case: every tap at distance r has data */
					vm right = v_lt(v_abs(v_sub(zr, zc)), v_abs(v_sub(zc, zl)));
					zqx = v_sel(right, zr, zl);
					offx = v_sel(right, fr, v_neg(fr));
					vm down_m = v_lt(v_abs(v_sub(zd, zc)), v_abs(v_sub(zc, zu)));
					zqy = v_sel(down_m, zd, zu);
					offy = v_sel(down_m, fr, v_neg(fr));
				} else {
					/* holes or the border: nearer taps, or none on an axis (then -V) */
					found = m_and(found, pick_side(row + x, 1, r, r, r, zc, &zqx, &offx));
					found = m_and(found, pick_side(row + x, (ptrdiff_t)w, r, up, down, zc,
								       &zqy, &offy));
				}
				vf u = v_add(v_iota(), v_set1((float)x)), v = v_set1((float)y);
				vf px = v_mul(v_add(v_mul(u, ax), bx), zc), py = v_mul(v_add(v_mul(v, ay), by), zc);
				/* d = Q - P towards +k, P - Q towards -k */
				vf uq = v_add(u, offx);
				vf qx = v_mul(v_add(v_mul(uq, ax), bx), zqx), qy = v_mul(v_add(v_mul(v, ay), by), zqx);
				vf sgn = v_sel(v_gt(offx, zero), v_set1(1.0f), v_set1(-1.0f));
				vf dx0 = v_mul(sgn, v_sub(qx, px)), dx1 = v_mul(sgn, v_sub(qy, py)),
				   dx2 = v_mul(sgn, v_sub(zqx, zc));
				vf vq = v_add(v, offy);
				qx = v_mul(v_add(v_mul(u, ax), bx), zqy);
				qy = v_mul(v_add(v_mul(vq, ay), by), zqy);
				sgn = v_sel(v_gt(offy, zero), v_set1(1.0f), v_set1(-1.0f));
				vf dy0 = v_mul(sgn, v_sub(qx, px)), dy1 = v_mul(sgn, v_sub(qy, py)),
				   dy2 = v_mul(sgn, v_sub(zqy, zc));
				vf c0 = v_sub(v_mul(dx1, dy2), v_mul(dx2, dy1));
				vf c1 = v_sub(v_mul(dx2, dy0), v_mul(dx0, dy2));
				vf c2 = v_sub(v_mul(dx0, dy1), v_mul(dx1, dy0));
				vf len = v_sqrt(v_add(v_add(v_mul(c0, c0), v_mul(c1, c1)), v_mul(c2, c2)));
				/* no neighbour on an axis, or a degenerate cross product: -P / |P| */
				const vm cross_ok = m_and(found, v_gt(len, zero));
				if (m_any(m_andnot(has, cross_ok))) { /* a lane with depth needs it */
					const vf lp = v_sqrt(v_add(v_add(v_mul(px, px), v_mul(py, py)),
								   v_mul(zc, zc)));
					c0 = v_sel(cross_ok, c0, v_neg(px));
					c1 = v_sel(cross_ok, c1, v_neg(py));
					c2 = v_sel(cross_ok, c2, v_neg(zc));
					len = v_sel(cross_ok, len, v_sel(has, lp, v_set1(1.0f)));
				}
				/* face the viewer: flip when N . P > 0 (-P faces it already) */
				vf dot = v_add(v_add(v_mul(c0, px), v_mul(c1, py)), v_mul(c2, zc));
				len = v_sel(m_and(cross_ok, v_gt(dot, zero)), v_neg(len), len);
				/* no depth: (0, 0, -1) */
				v_store3(out + 3 * x, v_sel(has, v_div(c0, len), zero),
					 v_sel(has, v_div(c1, len), zero),
					 v_sel(has, v_div(c2, len), v_set1(-1.0f)));
			}
		}
		for (; x < w; x++)
			dao_normal_pixel(cam, z, r, x, y, out + 3 * x);
	}
}
