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

void DAO_ISA_FN(dao_normals_from_depth)(const struct dao_camera *cam, const float *z, int r,
					float *n, int y0, int y1)
{
	const int w = (int)cam->width, h = (int)cam->height;
	const vf zero = v_zero(), ax = v_set1(cam->ax), bx = v_set1(cam->bx), ay = v_set1(cam->ay),
		 by = v_set1(cam->by), fr = v_set1((float)r);
	for (int y = y0; y < y1; y++) {
		float *out = n + 3 * (size_t)y * w;
		int x = 0;
		if (y >= r && y + r < h) {
			for (x = 0; x < r && x < w; x++)
				dao_normal_pixel(cam, z, r, x, y, out + 3 * x);
			const float *row = z + (size_t)y * w;
			for (; x + VN + r <= w; x += VN) {
				vf zc = v_load(row + x), zl = v_load(row + x - r), zr = v_load(row + x + r);
				vf zu = v_load(row + x - (size_t)r * w), zd = v_load(row + x + (size_t)r * w);
				vm ok = m_and(m_and(v_gt(zc, zero), m_and(v_gt(zl, zero), v_gt(zr, zero))),
					      m_and(v_gt(zu, zero), v_gt(zd, zero)));
				if (!m_all(ok)) {
					for (int k = 0; k < VN; k++)
						dao_normal_pixel(cam, z, r, x + k, y, out + 3 * (x + k));
					continue;
				}
				vf u = v_add(v_iota(), v_set1((float)x)), v = v_set1((float)y);
				vf px = v_mul(v_add(v_mul(u, ax), bx), zc), py = v_mul(v_add(v_mul(v, ay), by), zc);
				/* x axis: the side with the smaller |dz| (the right one on a tie, as normals.c) */
				vm right = v_lt(v_abs(v_sub(zr, zc)), v_abs(v_sub(zc, zl)));
				vf uq = v_sel(right, v_add(u, fr), v_sub(u, fr)), zq = v_sel(right, zr, zl);
				vf qx = v_mul(v_add(v_mul(uq, ax), bx), zq), qy = v_mul(v_add(v_mul(v, ay), by), zq);
				vf sgn = v_sel(right, v_set1(1.0f), v_set1(-1.0f));
				vf dx0 = v_mul(sgn, v_sub(qx, px)), dx1 = v_mul(sgn, v_sub(qy, py)),
				   dx2 = v_mul(sgn, v_sub(zq, zc));
				/* y axis */
				vm down = v_lt(v_abs(v_sub(zd, zc)), v_abs(v_sub(zc, zu)));
				vf vq = v_sel(down, v_add(v, fr), v_sub(v, fr));
				zq = v_sel(down, zd, zu);
				qx = v_mul(v_add(v_mul(u, ax), bx), zq);
				qy = v_mul(v_add(v_mul(vq, ay), by), zq);
				sgn = v_sel(down, v_set1(1.0f), v_set1(-1.0f));
				vf dy0 = v_mul(sgn, v_sub(qx, px)), dy1 = v_mul(sgn, v_sub(qy, py)),
				   dy2 = v_mul(sgn, v_sub(zq, zc));
				vf c0 = v_sub(v_mul(dx1, dy2), v_mul(dx2, dy1));
				vf c1 = v_sub(v_mul(dx2, dy0), v_mul(dx0, dy2));
				vf c2 = v_sub(v_mul(dx0, dy1), v_mul(dx1, dy0));
				vf len = v_sqrt(v_add(v_add(v_mul(c0, c0), v_mul(c1, c1)), v_mul(c2, c2)));
				vm degenerate = m_andnot(v_ge(len, zero), v_gt(len, zero)); /* len == 0 */
				if (m_any(degenerate)) {
					for (int k = 0; k < VN; k++)
						dao_normal_pixel(cam, z, r, x + k, y, out + 3 * (x + k));
					continue;
				}
				/* face the viewer: flip when N . P > 0 */
				vf dot = v_add(v_add(v_mul(c0, px), v_mul(c1, py)), v_mul(c2, zc));
				len = v_sel(v_gt(dot, zero), v_neg(len), len);
				float a[VN], b[VN], c[VN];
				v_store(a, v_div(c0, len));
				v_store(b, v_div(c1, len));
				v_store(c, v_div(c2, len));
				float *o = out + 3 * x;
				for (int k = 0; k < VN; k++)
					o[3 * k] = a[k], o[3 * k + 1] = b[k], o[3 * k + 2] = c[k];
			}
		}
		for (; x < w; x++)
			dao_normal_pixel(cam, z, r, x, y, out + 3 * x);
	}
}
