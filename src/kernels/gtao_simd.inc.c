/* SPDX-License-Identifier: MIT */
/*
 * GTAO over SIMD lanes: the same algorithm as gtao_ref.c (read that first),
 * one pixel per lane along a row.  Included by gtao_<isa>.c after the SIMD
 * vocabulary header; DAO_ISA_FN(name) gives the ISA-suffixed name.
 *
 * With tile noise it runs the block kernel of gtao_tile.inc.c instead.
 *
 * Differences from the reference, all measured by tests/simd/test_simd_kernels.c:
 *  - depth is read from a plane of 1/z with a one-pixel border of zeros, so
 *    the two taps of a sample are one masked gather each and the 1/z
 *    interpolation needs no division;
 *  - sin/cos/acos are polynomials (simd/fastmath.h), sin n = +-sqrt(1 - cos^2 n),
 *    and cos(2h - n) comes from the same polynomial;
 *  - divisions by the slice direction are multiplications by its reciprocal.
 */
#include <stddef.h>
#include <stdlib.h>

#include "core/math_util.h"
#include "kernels/gtao.h"
#include "kernels/gtao_planes.h"
#include "kernels/ao_variants.h"
#include "kernels/gtao_simd.h"
#include "kernels/gtao_tile.h"
#include "kernels/noise.h"
#include "simd/fastmath.h"

/* Per-lane state of one slice side's horizon search. */
struct side {
	vf dmaj, dmin, slope;    /* direction on the major / minor axis, dmin / dmaj */
	vf low;                  /* cosine of "no occluder" on this side */
};

/* Per-lane constants of the pixels being processed. */
struct px {
	vf x, y, Px, Py, Pz, Vx, Vy, Vz, r_px, jitter;
	vm active;
};

/* fract(a * fx + b * fy) with the reference's order of roundings */
static inline vf ign(vf fx, vf fy)
{
	vf in = v_add(v_mul(v_set1(0.06711056f), fx), v_mul(v_set1(0.00583715f), fy));
	vf f = v_sub(in, v_floor(in));
	vf o = v_mul(v_set1(52.9829189f), f);
	return v_sub(o, v_floor(o));
}

static void noise(const struct dao_gtao_setup *s, vf x, vf y, int xi, int yi, vf *n0, vf *n1)
{
	switch (s->noise) {
	case DAO_NOISE_IGN: {
		const vf shift = v_set1(5.588238f * (float)(s->frame & 63u));
		*n0 = ign(v_add(x, shift), v_add(y, shift));
		*n1 = ign(v_add(v_add(y, v_set1(7.0f)), shift), v_add(v_add(x, v_set1(13.0f)), shift));
		return;
	}
	case DAO_NOISE_R2: {
		/* per-frame 64 x 64 tile, filled by the context; VN divides 64 and x is a
		 * multiple of VN, so the lanes never wrap within a tile row */
		const size_t o = (size_t)(yi & 63) * 64 + (size_t)(xi & 63);
		*n0 = v_load(s->r2_tile + o);
		*n1 = v_load(s->r2_tile + 4096 + o);
		return;
	}
	default:
		*n0 = v_set1(0.5f);
		*n1 = v_set1(0.5f);
		return;
	}
}

/* The reference's (i + jitter) / steps raised to the distribution power. */
static inline vf step_t(const struct dao_gtao_setup *s, int i, vf jitter)
{
	vf t = v_mul(v_add(v_set1((float)i), jitter), v_set1(1.0f / (float)s->steps));
	if (s->power == 1.0f)
		return t;
	if (s->power == 2.0f)
		return v_mul(t, t);
	float l[VN];
	v_store(l, t);
	for (int k = 0; k < VN; k++)
		l[k] = powf(l[k], s->power);
	return v_load(l);
}

/* Where step i of a side samples: the snapped major coordinate m, the minor
 * coordinate fm on the line, and whether the taps are on the image. */
struct pos {
	vf m, fm, fl, f;
	vm ok;
};

static inline struct pos sample_pos(const struct dao_gtao_setup *s, const struct px *p,
				    const struct side *sd, vf cmaj, vf cmin, vf nmaj, vf nmin,
				    vf step_sign, int i)
{
	const vf one = v_set1(1.0f), zero = v_zero();
	struct pos o;
	vf dist = v_add(one, v_mul(step_t(s, i, p->jitter), v_sub(p->r_px, one)));
	/* snap the major-axis offset to a pixel (never the centre pixel) */
	vf mo = v_round(v_mul(sd->dmaj, dist));
	mo = v_sel(v_eq(mo, zero), step_sign, mo);
	o.m = v_add(cmaj, mo);
	o.ok = m_and(p->active, m_and(v_ge(o.m, zero), v_lt(o.m, nmaj)));
	vf off = v_mul(mo, sd->slope);
	vf fo = v_floor(off);
	o.fl = v_add(cmin, fo);
	o.f = v_sub(off, fo);
	o.fm = v_add(cmin, off);
	o.ok = m_and(o.ok, m_and(v_ge(o.fl, v_set1(-1.0f)), v_lt(o.fl, nmin)));
	return o;
}

/*
 * Largest horizon cosine along one side (dao_gtao_sample + search_side of the
 * reference).  major_x: lanes whose slice is closer to horizontal.
 */
static vf search_side(const struct dao_gtao_setup *s, const float *izp, int pw,
		      const struct px *p, const struct side *sd, vm major_x)
{
	const vf one = v_set1(1.0f), zero = v_zero();
	const vf cmaj = v_sel(major_x, p->x, p->y), cmin = v_sel(major_x, p->y, p->x);
	const vf nmaj = v_sel(major_x, v_set1((float)s->width), v_set1((float)s->height));
	const vf nmin = v_sel(major_x, v_set1((float)s->height), v_set1((float)s->width));
	const vi second = vi_sel(major_x, vi_set1(pw), vi_set1(1)); /* offset of the minor+1 tap */
	const vf step_sign = v_sel(v_gt(sd->dmaj, zero), one, v_set1(-1.0f));
	const vf ax = v_set1(s->ax), bx = v_set1(s->bx), ay = v_set1(s->ay), by = v_set1(s->by);
	const vf fmul = v_set1(s->falloff_mul), fadd = v_set1(s->falloff_add);
	const int use_max = s->decay == 1.0f;
	vf best = sd->low;
	for (int i = 0; i < s->steps; i++) {
		struct pos o = sample_pos(s, p, sd, cmaj, cmin, nmaj, nmin, step_sign, i);
		vm ok = o.ok;
		if (!m_any(ok))
			continue;
		/* padded coordinates: the border row/column holds "no data" */
		vi mi = vi_from_whole(v_add(o.m, one)), li = vi_from_whole(v_add(o.fl, one));
		vi row = vi_sel(major_x, li, mi), col = vi_sel(major_x, mi, li);
		vi idx = vi_add(vi_mul(row, vi_set1(pw)), col);
		vf iz0 = v_gather(izp, idx, ok), iz1 = v_gather(izp, vi_add(idx, second), ok);
		vf f = o.f;
		vm has0 = v_gt(iz0, zero), has1 = v_gt(iz1, zero);
		vm both = m_and(has0, has1);
		vm edge = v_gt(v_abs(v_sub(iz0, iz1)), v_mul(v_set1(0.1f), v_min(iz0, iz1)));
		vm use1 = v_ge(f, v_set1(0.5f));
		/* smooth: interpolate 1/z; edge: the tap closer to the line, at its place */
		vf iz = v_fma(f, v_sub(iz1, iz0), iz0);
		vf fmin = o.fm;
		vm edge_both = m_and(both, edge);
		iz = v_sel(edge_both, v_sel(use1, iz1, iz0), iz);
		fmin = v_sel(edge_both, v_add(o.fl, v_sel(use1, one, zero)), fmin);
		vm only0 = m_andnot(m_and(has0, v_lt(f, v_set1(1e-3f))), has1);
		vm only1 = m_andnot(m_and(has1, v_gt(f, v_set1(1.0f - 1e-3f))), has0);
		iz = v_sel(only0, iz0, v_sel(only1, iz1, iz));
		ok = m_and(ok, m_or(both, m_or(only0, only1)));
		if (!m_any(ok))
			continue;

		vf zs = v_rcp(v_sel(ok, iz, one));
		vf u = v_sel(major_x, o.m, fmin), v = v_sel(major_x, fmin, o.m);
		vf Dx = v_sub(v_mul(v_fma(u, ax, bx), zs), p->Px);
		vf Dy = v_sub(v_mul(v_fma(v, ay, by), zs), p->Py);
		vf Dz = v_sub(zs, p->Pz);
		vf len2 = v_fma(Dx, Dx, v_fma(Dy, Dy, v_mul(Dz, Dz)));
		ok = m_and(ok, v_gt(len2, zero));
		vf rl = v_rsqrt(v_sel(ok, len2, one));
		vf len = v_mul(len2, rl);
		vf c = v_mul(v_fma(Dx, p->Vx, v_fma(Dy, p->Vy, v_mul(Dz, p->Vz))), rl);
		vf wgt = v_min(v_max(v_fma(len, fmul, fadd), zero), one);
		c = v_fma(v_sub(c, sd->low), wgt, sd->low);
		vf nb;
		if (use_max)
			nb = v_max(best, c);
		else
			nb = v_sel(v_gt(c, best), c, v_fma(v_sub(best, c), v_set1(s->decay), c));
		best = v_sel(ok, nb, best);
	}
	return best;
}

/* acos, and sin t from cos t (t in [0, pi]), of c in [-1, 1] (every caller
 * clamps it): the precise polynomials, or with `fast` the short acos and
 * square roots from the hardware 1/sqrt estimate, without clamps of their own
 * (1 - c^2 >= 0 when |c| <= 1, the product rounded or fused) */
static inline vf acos_lanes(vf c, const int fast)
{
	return fast ? v_acos_fast_unit(c) : v_acos(c);
}

static inline vf sin_of_cos(vf c, const int fast)
{
	if (fast)
		return v_sqrt_fast(v_fnma(c, c, v_set1(1.0f)));
	return v_sqrt(v_max(v_fnma(c, c, v_set1(1.0f)), v_zero()));
}

/* One slice's frame at every lane: the projected normal's angle n from V, its
 * cosine and sine, the length lpn, and where the slice is usable. */
struct slice_v {
	vf n, cos_n, sin_n, lpn;
	vm ok;
};

/*
 * N is a unit normal and NV = N.V.  The slice plane's axis a = ortho x V, with
 * ortho = dir - (dir.V) V and dir = (dx ax, dy ay, 0), is dir x V (V x V = 0)
 * and is perpendicular to V.  N projected into the plane, pn = N - (N.a) a,
 * then has |pn|^2 = 1 - (N.a)^2 and pn.V = N.V, and the side of n is the sign
 * of ortho.pn = dir.N - (dir.V) N.V (dir.a = 0): no projection is formed.
 */
static inline __attribute__((always_inline)) struct slice_v
slice_from_axis(const struct px *p, vf dirx, vf diry, vf ax, vf ay, vf az, vf a2, const vf N[3],
		vf NV, const int fast)
{
	const vf one = v_set1(1.0f), zero = v_zero();
	struct slice_v g;
	const vf na = v_fma(N[0], ax, v_fma(N[1], ay, v_mul(N[2], az)));
	/* |pn|^2 = 1 - (N.a)^2 / |a|^2 */
	const vf l2 = v_fnma(v_mul(na, na), v_rcp(a2), one);
	g.ok = m_and(p->active, v_gt(l2, v_set1(1e-12f)));
	const vf rl = v_rsqrt(v_sel(g.ok, l2, one));
	g.lpn = v_mul(l2, rl);
	g.cos_n = v_min(v_max(v_mul(NV, rl), v_set1(-1.0f)), one);
	const vf dv = v_fma(dirx, p->Vx, v_mul(diry, p->Vy));
	const vf dn = v_fma(dirx, N[0], v_mul(diry, N[1]));
	const vm neg = v_lt(v_fnma(dv, NV, dn), zero);
	const vf n = acos_lanes(g.cos_n, fast);
	const vf sin_n = sin_of_cos(g.cos_n, fast);
	g.n = v_sel(neg, v_neg(n), n);
	g.sin_n = v_sel(neg, v_neg(sin_n), sin_n);
	return g;
}

/* The slice frame with the axis a = dir x V; any multiple of it does. */
static inline __attribute__((always_inline)) struct slice_v
slice_geometry(const struct dao_gtao_setup *s, const struct px *p, vf dx, vf dy, const vf N[3],
	       vf NV, const int fast)
{
	const vf dirx = v_mul(dx, v_set1(s->ax)), diry = v_mul(dy, v_set1(s->ay));
	const vf axx = v_mul(diry, p->Vz), axy = v_neg(v_mul(dirx, p->Vz));
	const vf axz = v_fnma(diry, p->Vx, v_mul(dirx, p->Vy));
	const vf a2 = v_fma(axx, axx, v_fma(axy, axy, v_mul(axz, axz)));
	return slice_from_axis(p, dirx, diry, axx, axy, axz, a2, N, NV, fast);
}

/*
 * Adds one slice's cosine-weighted integral (Jimenez 2016 eq. 7),
 * sum over both sides of 0.25 (cos n - cos(2h - n) + 2 h sin n), between the
 * horizons whose cosines are hc_pos / hc_neg, and its unoccluded value.
 * h1 = acos(hc_pos) and h0 = -acos(hc_neg), each clamped to n +- pi/2; then
 * cos(2h - n) = cos 2h cos n + sin 2h sin n with cos 2h = 2 cos^2 h - 1 and
 * sin 2h = 2 cos h sin h (sin h = +-sqrt(1 - cos^2 h)), or -cos n where the
 * clamp applies (2h - n = n +- pi): no trigonometric call.
 */
static inline __attribute__((always_inline)) void
slice_accumulate(const struct slice_v *g, vf hc_pos, vf hc_neg, vf *vis, vf *norm, const int fast)
{
	const vf one = v_set1(1.0f), zero = v_zero(), half_pi = v_set1(DAO_HALF_PI_F);
	const vf two = v_set1(2.0f);
	const vf c1 = v_min(v_max(hc_pos, v_set1(-1.0f)), one);
	const vf c0 = v_min(v_max(hc_neg, v_set1(-1.0f)), one);
	vf h1 = acos_lanes(c1, fast), h0 = v_neg(acos_lanes(c0, fast));
	const vm cl1 = v_gt(v_sub(h1, g->n), half_pi), cl0 = v_lt(v_sub(h0, g->n), v_neg(half_pi));
	h1 = v_sel(cl1, v_add(g->n, half_pi), h1);
	h0 = v_sel(cl0, v_sub(g->n, half_pi), h0);
	const vf s1 = sin_of_cos(c1, fast), s0 = v_neg(sin_of_cos(c0, fast));
	const vf k1 = v_fma(v_fma(v_mul(two, c1), c1, v_neg(one)), g->cos_n,
			    v_mul(v_mul(v_mul(two, c1), s1), g->sin_n));
	const vf k0 = v_fma(v_fma(v_mul(two, c0), c0, v_neg(one)), g->cos_n,
			    v_mul(v_mul(v_mul(two, c0), s0), g->sin_n));
	const vf ncos = v_neg(g->cos_n);
	const vf cos1 = v_sel(cl1, ncos, k1), cos0 = v_sel(cl0, ncos, k0);
	/* both sides: 0.25 (2 cos n - cos0 - cos1 + 2 (h0 + h1) sin n) */
	const vf a = v_mul(v_set1(0.25f), v_fma(v_add(h0, h1), v_add(g->sin_n, g->sin_n),
					       v_sub(v_sub(v_add(g->cos_n, g->cos_n), cos0), cos1)));
	*vis = v_add(*vis, v_sel(g->ok, v_mul(g->lpn, a), zero));
	*norm = v_add(*norm, v_sel(g->ok, v_mul(g->lpn, v_fma(g->n, g->sin_n, g->cos_n)), zero));
}

/* dao_gtao_finish over lanes: saturate, final power, multi-bounce fit. */
static inline vf finish_lanes(const struct dao_gtao_setup *s, vf vis)
{
	const vf zero = v_zero(), one = v_set1(1.0f);
	vis = v_min(v_max(vis, zero), one);
	if (s->final_power != 1.0f) {
		float l[VN];
		v_store(l, vis);
		for (int k = 0; k < VN; k++)
			l[k] = powf(l[k], s->final_power);
		vis = v_load(l);
	}
	if (s->albedo > 0.0f) {
		const float rho = s->albedo;
		const vf a = v_set1(2.0404f * rho - 0.3324f), b = v_set1(-4.7951f * rho + 0.6417f);
		const vf c = v_set1(2.7552f * rho + 0.6903f);
		vis = v_max(vis, v_mul(v_fma(v_fma(a, vis, b), vis, c), vis));
	}
	return v_min(v_max(vis, zero), one);
}

static vf gtao_lanes(const struct dao_gtao_setup *s, const float *izp, int pw, const struct px *p,
		     vf n0, const vf N[3])
{
	const vf one = v_set1(1.0f), zero = v_zero();
	const vf NV = v_fma(N[0], p->Vx, v_fma(N[1], p->Vy, v_mul(N[2], p->Vz)));
	vf vis = zero, norm = zero;
	for (int sl = 0; sl < s->slices; sl++) {
		vf phi = v_div(v_mul(v_add(v_set1((float)sl), n0), v_set1(DAO_PI_F)),
			       v_set1((float)s->slices));
		vf dx, dy;
		v_sincos(phi, &dy, &dx);
		struct slice_v g = slice_geometry(s, p, dx, dy, N, NV, 0);
		if (!m_any(g.ok))
			continue;
		vm major_x = v_ge(v_abs(dx), v_abs(dy));
		vf dmaj = v_sel(major_x, dx, dy), dmin = v_sel(major_x, dy, dx);
		struct side pos = { dmaj, dmin, v_div(dmin, dmaj), v_neg(g.sin_n) };
		struct side negs = { v_neg(dmaj), v_neg(dmin), pos.slope, g.sin_n };
		struct px pa = *p;
		pa.active = g.ok;
		vf hc_pos = search_side(s, izp, pw, &pa, &pos, major_x);
		vf hc_neg = search_side(s, izp, pw, &pa, &negs, major_x);
		slice_accumulate(&g, hc_pos, hc_neg, &vis, &norm, 0);
	}
	vm has = v_gt(norm, zero);
	return v_sel(has, v_div(vis, v_sel(has, norm, one)), one);
}

#include "kernels/gtao_tile.inc.c"

void DAO_ISA_FN(dao_gtao_simd)(const struct dao_gtao_setup *s, const float *z,
			       const struct dao_gtao_planes *pl, const float *n, float *ao, int y0,
			       int y1, struct dao_tile_scratch *sc)
{
	if (s->noise == DAO_NOISE_TILE) {
		gtao_tile(s, pl, n, ao, y0, y1, sc);
		return;
	}
	const int w = s->width, pw = w + 2;
	const float *iz_origin = pl->izp; /* pixel (-1, -1) */
	for (int y = y0; y < y1; y++) {
		for (int x0 = s->x_begin; x0 < s->x_end; x0 += VN) {
			const int lanes = s->x_end - x0 < VN ? s->x_end - x0 : VN;
			const size_t i0 = (size_t)y * w + (size_t)x0;
			float zl[VN], nl[3][VN], out[VN];
			for (int k = 0; k < VN; k++) {
				const int kk = k < lanes ? k : 0;
				zl[k] = k < lanes ? z[i0 + k] : 0.0f;
				for (int c = 0; c < 3; c++)
					nl[c][k] = n[3 * (i0 + kk) + c];
			}
			struct px p;
			p.x = v_add(v_set1((float)x0), v_iota());
			p.y = v_set1((float)y);
			p.Pz = v_load(zl);
			p.Px = v_mul(v_add(v_mul(p.x, v_set1(s->ax)), v_set1(s->bx)), p.Pz);
			p.Py = v_mul(v_add(v_mul(p.y, v_set1(s->ay)), v_set1(s->by)), p.Pz);
			vm has_z = v_gt(p.Pz, v_zero());
			vf zsafe = v_sel(has_z, p.Pz, v_set1(1.0f));
			vf lp = v_sqrt(v_fma(p.Px, p.Px, v_fma(p.Py, p.Py, v_mul(p.Pz, p.Pz))));
			vf ilp = v_div(v_set1(-1.0f), v_sel(has_z, lp, v_set1(1.0f)));
			p.Vx = v_mul(p.Px, ilp), p.Vy = v_mul(p.Py, ilp), p.Vz = v_mul(p.Pz, ilp);
			vf r = v_div(v_set1(s->search_radius * s->focal), zsafe);
			vm big = m_and(v_ge(r, v_set1(s->min_r_px)), v_ge(r, v_set1(1.0f)));
			p.active = m_and(has_z, big);
			p.r_px = v_min(r, v_set1(s->max_r_px));
			vf vis = v_set1(1.0f);
			if (m_any(p.active)) {
				vf n0;
				noise(s, p.x, p.y, x0, y, &n0, &p.jitter);
				const vf N[3] = { v_load(nl[0]), v_load(nl[1]), v_load(nl[2]) };
				vis = gtao_lanes(s, iz_origin, pw, &p, n0, N);
			}
			v_store(out, finish_lanes(s, vis));
			for (int k = 0; k < lanes; k++)
				ao[i0 + k] = zl[k] > 0.0f ? out[k] : s->invalid_value;
		}
	}
}

/* VBAO: the tile kernel with tile noise, the reference with any other. */
void DAO_ISA_FN(dao_vbao_simd)(const struct dao_variant_setup *v, const float *z,
			       const struct dao_gtao_planes *pl, const float *n, float *ao, int y0,
			       int y1, struct dao_tile_scratch *sc)
{
	const struct dao_gtao_setup *s = v->g;
	if (s->noise != DAO_NOISE_TILE) {
		dao_vbao_ref(v, z, n, ao, y0, y1);
		return;
	}
	const struct tile_vbao vb = { .fall_mul = v->vbao_fall_mul, .fall_add = v->vbao_fall_add,
				      .fall_full = (1.0f - v->vbao_fall_add) / v->vbao_fall_mul,
				      .fall_out = 1.001f * v->vbao_radius,
				      .thickness = v->vbao_thickness, .plane = v->thickness != NULL };
	vbao_tile(s, pl, n, ao, y0, y1, sc, &vb);
}

void DAO_ISA_FN(dao_gtao_planes_fill)(struct dao_gtao_planes *pl, const float *z, int phase,
				      int y0, int y1)
{
	if (!phase) {
		dao_gtao_planes_fill(pl, z, 0, y0, y1);
		return;
	}
	const int w = pl->width;
	const vf zero = v_zero(), one = v_set1(1.0f);
	for (int y = y0; y < y1; y++) {
		const float *zr = z + (size_t)y * w;
		float *o[4];
		for (int q = 0; q < 4; q++)
			o[q] = (float *)dao_gtao_phase_row(pl, y, q);
		int x = 0;
		/* 4 VN columns: 1/z (exact division, as the scalar fill), then split by phase */
		for (; x + 4 * VN <= w; x += 4 * VN) {
			vf v[4], q[4];
			for (int m = 0; m < 4; m++) {
				const vf zz = v_load(zr + x + m * VN);
				const vm has = v_gt(zz, zero);
				v[m] = v_sel(has, v_div(one, v_sel(has, zz, one)), zero);
			}
			v_deinterleave4(v, q);
			for (int k = 0; k < 4; k++)
				v_store(o[k] + x / 4, q[k]);
		}
		for (; x < w; x++)
			o[x & 3][x >> 2] = zr[x] > 0.0f ? 1.0f / zr[x] : 0.0f;
	}
}
