/* SPDX-License-Identifier: MIT */
/*
 * The 5x5 plane denoise of denoise_plane.c over SIMD lanes (pixels along a
 * row), with its tile-cancelling spatial weights; included by
 * denoise_plane_<isa>.c.  Same arithmetic; the two border
 * columns of each side run the reference's arithmetic on lanes (its bytes,
 * border_lanes), or its per-pixel code on images narrower than a vector and
 * four columns; rows near the top and bottom leave out the rows off the
 * image as it does.
 */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "denoise/denoise.h"

/* smaller_side_gradient of the reference, as selects in reverse priority */
static inline vf gradient(vf m1, vf m2, vf p1, vf p2, vf zc)
{
	const vf zero = v_zero(), inf = v_set1(INFINITY);
	vm has_m = m_and(v_gt(m1, zero), v_gt(m2, zero));
	vm has_p = m_and(v_gt(p1, zero), v_gt(p2, zero));
	vf cm = v_sel(has_m, v_abs(v_sub(v_add(m1, v_sub(m1, m2)), zc)), inf);
	vf cp = v_sel(has_p, v_abs(v_sub(v_add(p1, v_sub(p1, p2)), zc)), inf);
	vm m1_ok = v_gt(m1, zero);
	vf g = v_sel(m1_ok, v_sub(zc, m1), zero);
	vm p1_near = m_and(v_gt(p1, zero),
			   m_or(v_le(m1, zero), v_lt(v_abs(v_sub(p1, zc)), v_abs(v_sub(zc, m1)))));
	g = v_sel(p1_near, v_sub(p1, zc), g);
	g = v_sel(has_p, v_sub(p2, p1), g);
	return v_sel(v_lt(cm, cp), v_sub(m1, m2), g);
}

/* The taps' sums of weights and weighted AO, rows j0 .. j1 of -2 .. 2 (the
 * others are off the image); holes: whether a tap without depth must be
 * tested for (else it weighs 0 by itself).  Each tap's spatial weight
 * (denoise.h: 1 inside, 1/2 on the border rows and columns, 1/4 at the
 * corners) is folded into its tap weight (a constant where unrolled):
 * c (1 - saturate(|plane - t| / tol)) = max(c - |plane - t| (c / tol), 0),
 * the same operations as without it (c is a power of two: exact).
 * The columns are unrolled; the rows too except with AVX-512, where the
 * kernel's code twice as long ran 10-13 % slower (thread CPU time,
 * docs/perf/fuse.md); with 16 vector registers the unrolled rows are the
 * faster.  Either way the same operations in the same order: the same bits. */
static inline __attribute__((always_inline)) void
plane_taps(const float *zr, const float *ar, int w, int j0, int j1, const vf ak[5], vf gy,
	   vf inv_tol, const int holes, vf *sum_out, vf *wsum_out)
{
	const vf zero = v_zero();
	const vf c[3] = { v_set1(1.0f), v_set1(0.5f), v_set1(0.25f) };
	const vf inv_tol_c[3] = { inv_tol, v_mul(inv_tol, c[1]), v_mul(inv_tol, c[2]) };
	vf sum = zero, wsum = zero;
#if VN >= 16
#pragma GCC unroll 1
#else
#pragma GCC unroll 5
#endif
	for (int j = -2; j <= 2; j++) {
		if (j < j0 || j > j1)
			continue;
		const float *zt = zr + (ptrdiff_t)j * w;
		const float *at = ar + (ptrdiff_t)j * w;
		const vf jg = v_mul(v_set1((float)j), gy);
#pragma GCC unroll 5
		for (int k = -2; k <= 2; k++) {
			const vf t = v_load(zt + k);
			const vf plane = v_add(ak[k + 2], jg);
			const int cls = (j == -2 || j == 2) + (k == -2 || k == 2);
			vf wt = v_max(v_fnma(v_abs(v_sub(plane, t)), inv_tol_c[cls], c[cls]), zero);
			if (holes)
				wt = v_sel(v_gt(t, zero), wt, zero);
			sum = v_fma(wt, v_load(at + k), sum);
			wsum = v_add(wsum, wt);
		}
	}
	*sum_out = sum;
	*wsum_out = wsum;
}

/*
 * The border columns: five rows (j = -2 .. 2) of BORDER_W floats, each the
 * image's columns 0 .. 3 at 2 .. 5 and w - 4 .. w - 1 at 6 .. 9, 0 around
 * them and for rows off the image, so that positions 2, 3, 8, 9 are the
 * pixels x = 0, 1, w - 2, w - 1 with their taps where the reference finds
 * them (zat: 0 off the image).  Lanes from position p on, with
 * dao_denoise_plane_pixel's arithmetic: no fused multiply-add, the taps in
 * its order, a tap it skips (no depth) adding exact zeros; the same bytes.
 */
#define BORDER_W (VN + 12)

static vf border_lanes(const struct dao_denoise_setup *s, const float zb[5][BORDER_W],
		       const float ab[5][BORDER_W], int p)
{
	const vf zero = v_zero(), one = v_set1(1.0f);
	const float *zr = zb[2] + p;
	const vf zc = v_load(zr);
	const vm has = v_gt(zc, zero);
	const vf gx = gradient(v_load(zr - 1), v_load(zr - 2), v_load(zr + 1), v_load(zr + 2), zc);
	const vf gy = gradient(v_load(zb[1] + p), v_load(zb[0] + p), v_load(zb[3] + p),
			       v_load(zb[4] + p), zc);
	const vf sig = v_mul(v_mul(v_set1(s->noise_k), zc), zc);
	const vf tol = v_mul(v_set1(s->sharpness), v_max(sig, v_mul(v_set1(0.002f), zc)));
	const vf inv_tol = v_div(one, v_sel(has, tol, one));
	vf sum = zero, wsum = zero;
	for (int j = -2; j <= 2; j++) {
		const vf jg = v_mul(v_set1((float)j), gy);
		for (int k = -2; k <= 2; k++) {
			const vf t = v_load(zb[j + 2] + p + k);
			/* (zc + k gx) + j gy; c (1 - saturate(|plane - t| / tol)) */
			const vf plane = v_add(v_add(zc, v_mul(v_set1((float)k), gx)), jg);
			const vf sat = v_min(v_max(v_mul(v_abs(v_sub(plane, t)), inv_tol), zero), one);
			const vf c = v_set1(dao_denoise_plane_tap_weight(j) *
					    dao_denoise_plane_tap_weight(k));
			const vm use = v_gt(t, zero);
			const vf wt = v_sel(use, v_mul(c, v_sub(one, sat)), zero);
			sum = v_add(sum, v_sel(use, v_mul(wt, v_load(ab[j + 2] + p + k)), zero));
			wsum = v_add(wsum, wt);
		}
	}
	return v_sel(has, v_div(sum, v_sel(has, wsum, one)), v_set1(s->invalid_value));
}

/* Row y's two border columns each side into o (w >= 8) */
static void border_row(const struct dao_denoise_setup *s, const float *z, const float *ao_in,
		       float zb[5][BORDER_W], float ab[5][BORDER_W], int y, float *o)
{
	const int w = s->width, h = s->height;
	for (int j = -2; j <= 2; j++) {
		float *zd = zb[j + 2] + 2, *ad = ab[j + 2] + 2;
		const int yy = y + j;
		if (yy < 0 || yy >= h) {
			memset(zd, 0, 8 * sizeof *zd);
			memset(ad, 0, 8 * sizeof *ad);
			continue;
		}
		const float *zs = z + (size_t)yy * w, *as = ao_in + (size_t)yy * w;
		memcpy(zd, zs, 4 * sizeof *zd);
		memcpy(zd + 4, zs + w - 4, 4 * sizeof *zd);
		memcpy(ad, as, 4 * sizeof *ad);
		memcpy(ad + 4, as + w - 4, 4 * sizeof *ad);
	}
	float r[2 * VN];
	for (int p = 2; p < 10; p += VN) /* one vector from VN = 8 on, two at 4 */
		v_store(r + p - 2, border_lanes(s, zb, ab, p));
	o[0] = r[0], o[1] = r[1], o[w - 2] = r[6], o[w - 1] = r[7];
}

void DAO_ISA_FN(dao_denoise_plane)(const struct dao_denoise_setup *s, const float *z,
				   const float *ao_in, float *ao_out, int y0, int y1)
{
	const int w = s->width, h = s->height;
	const vf zero = v_zero(), one = v_set1(1.0f);
	/* the vectors of the interior reach the border columns from VN + 4 columns on */
	const int lanes_at_borders = w >= VN + 4;
	float zb[5][BORDER_W], ab[5][BORDER_W];
	memset(zb, 0, sizeof zb);
	memset(ab, 0, sizeof ab);
	for (int y = y0; y < y1; y++) {
		float *o = ao_out + (size_t)y * w;
		/* rows off the image have no depth (0), as in the reference */
		const int j0 = y < 2 ? -y : -2, j1 = y + 2 >= h ? h - 1 - y : 2;
		int x = 0;
		if (lanes_at_borders) {
			border_row(s, z, ao_in, zb, ab, y, o);
			x = 2;
		}
		for (; x < 2 && x < w; x++)
			o[x] = dao_denoise_plane_pixel(s, z, ao_in, x, y);
		/* the last vector ends at the border, overlapping the one before: each
		 * output depends only on the inputs, so recomputing pixels is harmless */
		const int xlast = w - 2 - VN;
		for (; x <= xlast; x = (x < xlast && x + VN > xlast) ? xlast : x + VN) {
			const float *zr = z + (size_t)y * w + x;
			vf zc = v_load(zr);
			vm has = v_gt(zc, zero);
			vf gx = gradient(v_load(zr - 1), v_load(zr - 2), v_load(zr + 1), v_load(zr + 2), zc);
			vf gy = gradient(j0 <= -1 ? v_load(zr - w) : zero, j0 <= -2 ? v_load(zr - 2 * w) : zero,
					 j1 >= 1 ? v_load(zr + w) : zero, j1 >= 2 ? v_load(zr + 2 * w) : zero,
					 zc);
			vf sig = v_mul(v_mul(v_set1(s->noise_k), zc), zc);
			vf tol = v_mul(v_set1(s->sharpness), v_max(sig, v_mul(v_set1(0.002f), zc)));
			vf inv_tol = v_div(one, v_sel(has, tol, one));
			/* zc + k gx for the five columns, then + j gy per row */
			const vf ak[5] = { v_fnma(v_set1(2.0f), gx, zc), v_sub(zc, gx), zc,
					   v_add(zc, gx), v_fma(v_set1(2.0f), gx, zc) };
			/* A hole (t = 0) weighs 1 - |plane| / tol, which is already 0 where
			 * |plane| >= tol; |zc + k gx + j gy| >= zc - 2 |gx| - 2 |gy|, so when
			 * that bound clears tol (with a margin for rounding) at every lane
			 * with depth, the taps need no hole test. */
			const vf low = v_fnma(v_set1(2.0f), v_add(v_abs(gx), v_abs(gy)), zc);
			const vm clear = v_ge(v_mul(low, inv_tol), v_set1(1.01f));
			vf sum, wsum;
			if (m_any(m_andnot(has, clear)))
				plane_taps(zr, ao_in + (size_t)y * w + x, w, j0, j1, ak, gy, inv_tol, 1,
					   &sum, &wsum);
			else
				plane_taps(zr, ao_in + (size_t)y * w + x, w, j0, j1, ak, gy, inv_tol, 0,
					   &sum, &wsum);
			vf r = v_sel(has, v_div(sum, v_sel(has, wsum, one)), v_set1(s->invalid_value));
			v_store(o + x, r);
		}
		for (; x < w - 2 * lanes_at_borders; x++)
			o[x] = dao_denoise_plane_pixel(s, z, ao_in, x, y);
	}
}
