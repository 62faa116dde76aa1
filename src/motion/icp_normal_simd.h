/* SPDX-License-Identifier: MIT */
/*
 * What the source grid (icp_source_simd.inc.c) and the pairs
 * (icp_pairs_simd.inc.c) both do at a pixel, over SIMD lanes: the depth edge
 * test of its four neighbours r px away and the normal's direction, the
 * cross product of the central differences of the view positions (the
 * reference's float operations in its order: the output to the bit).
 * Included by those kernels after the SIMD vocabulary.
 */
#ifndef DAO_MOTION_ICP_NORMAL_SIMD_H
#define DAO_MOTION_ICP_NORMAL_SIMD_H

/* ok without the lanes where a neighbour's depth (zl, zr left and right, zu,
 * zd up and down) differs from z by more than tolk z, or z has none */
static inline vm icp_smooth(vm ok, vf z, vf zl, vf zr, vf zu, vf zd, vf tolk)
{
	const vf tol = v_mul(tolk, z);
	ok = m_and(ok, m_and(v_gt(z, v_zero()), m_and(v_le(v_abs(v_sub(zl, z)), tol),
							v_le(v_abs(v_sub(zr, z)), tol))));
	return m_and(ok, m_and(v_le(v_abs(v_sub(zu, z)), tol), v_le(v_abs(v_sub(zd, z)), tol)));
}

/* the unnormalised normal c: (x at ur) - (x at ul) across (x at vd) - (x at
 * vu), ux and vy the pixel's ray, ul/ur and vu/vd its neighbours' */
static inline void icp_cross(vf ux, vf vy, vf ul, vf ur, vf vu, vf vd, vf zl, vf zr, vf zu,
			     vf zd, vf c[3])
{
	const vf dx0 = v_sub(v_mul(ur, zr), v_mul(ul, zl)), dx1 = v_mul(vy, v_sub(zr, zl));
	const vf dx2 = v_sub(zr, zl);
	const vf dy0 = v_mul(ux, v_sub(zd, zu)), dy1 = v_sub(v_mul(vd, zd), v_mul(vu, zu));
	const vf dy2 = v_sub(zd, zu);
	c[0] = v_sub(v_mul(dx1, dy2), v_mul(dx2, dy1));
	c[1] = v_sub(v_mul(dx2, dy0), v_mul(dx0, dy2));
	c[2] = v_sub(v_mul(dx0, dy1), v_mul(dx1, dy0));
}

#endif
