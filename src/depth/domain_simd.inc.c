/* SPDX-License-Identifier: MIT */
/*
 * The domain-transform pass of domain.c over SIMD lanes: VN neighbouring
 * lines (columns of the pass's input) go down together, each lane a line, so
 * the loads are contiguous and the recursion runs in every lane at once.  The
 * causal sweep keeps its moments in the scratch, the anticausal sweep fits
 * and collects VN samples of VN lines in registers, transposes them
 * (v_transpose) and stores them as rows of the transposed output.  Same
 * maths as the reference, the link weight included (dao_domain_link_weight:
 * the same operations, fused multiply-adds where the set has them).
 * Included by domain_<isa>.c after the SIMD vocabulary.
 */
#include <stddef.h>
#include <string.h>

#include "depth/domain.h"

/* samples per block of the causal sweep (its links, then its moments) */
#define DT_BLOCK 32
/* samples ahead the causal sweep asks for its input */
#define DT_PREFETCH 16

static inline vf dt_med3(vf a, vf b, vf c)
{
	return v_max(v_min(a, b), v_min(v_max(a, b), c));
}

/* dao_domain_link_weight (domain.h) for x < DAO_DOMAIN_MAX_EXPONENT (the
 * caller zeroes the link beyond) */
static inline vf dt_link_weight(vf x)
{
	vf q = v_fma(v_set1(DAO_DOMAIN_LINK_C3), x, v_set1(DAO_DOMAIN_LINK_C2));
	q = v_fma(q, x, v_set1(DAO_DOMAIN_LINK_C1));
	q = v_fma(q, x, v_set1(1.0f));
	q = v_mul(q, q), q = v_mul(q, q), q = v_mul(q, q), q = v_mul(q, q);
	return v_mul(q, q);
}

/* What a strip's sweeps read, in registers and locals (the stores to the
 * scratch could otherwise alias the pass's fields). */
struct dt_ctx {
	const float *in;
	/* per cell along the line: the knot and the difference to the next
	 * (0 after the last), VN each, or NULL */
	const float *noise_knots, *scale_knots;
	const float *pos;         /* per sample: the knots' offset (k 2 VN) and u */
	size_t stride;
	int in_depth;
	vf noise, unit, spatial, spatial_term, range, side_k2;
};

/* the knots of lanes lane0 .. lane0 + VN - 1 and their differences */
static void dt_cell_knots(const struct dao_domain_pass *p, const float *cells, int lane0,
			  float *knots)
{
	/* the lanes' cells a (and b = a + 1, clamped) and weights u, as in
	 * dao_domain_cell_knots; with cells of at least VN px the lanes span
	 * two values of a and of b, so a knot is a select of two cells'
	 * values per lane and the same arithmetic, VN lanes at once */
	int a[VN], b[VN];
	float af[VN], bf[VN], uf[VN];
	for (int j = 0; j < VN; j++) {
		dao_domain_cell_pos(lane0 + j, p->lane_cells, p->cell_span, &a[j], &uf[j]);
		b[j] = a[j] + 1 < p->lane_cells ? a[j] + 1 : a[j];
		af[j] = (float)a[j], bf[j] = (float)b[j];
	}
	if (a[VN - 1] - a[0] <= 1 && b[VN - 1] - b[0] <= 1) {
		const vm ma = v_gt(v_load(af), v_set1((float)a[0]));
		const vm mb = v_gt(v_load(bf), v_set1((float)b[0]));
		const vf u = v_load(uf);
		const float *ca0 = cells + (size_t)a[0] * p->lane_step;
		const float *ca1 = cells + (size_t)a[VN - 1] * p->lane_step;
		const float *cb0 = cells + (size_t)b[0] * p->lane_step;
		const float *cb1 = cells + (size_t)b[VN - 1] * p->lane_step;
		for (int k = 0; k < p->line_cells; k++) {
			const size_t at = (size_t)k * p->line_step;
			const vf va = v_sel(ma, v_set1(ca1[at]), v_set1(ca0[at]));
			const vf vb = v_sel(mb, v_set1(cb1[at]), v_set1(cb0[at]));
			v_store(knots + (size_t)k * 2 * VN, v_add(va, v_mul(v_sub(vb, va), u)));
		}
	} else {
		for (int j = 0; j < VN; j++)
			dao_domain_cell_knots(p, cells, lane0 + j, knots + j, 2 * VN);
	}
	for (int k = 0; k < p->line_cells; k++) {
		float *kn = knots + (size_t)k * 2 * VN;
		const vf d = k + 1 < p->line_cells ? v_sub(v_load(kn + 2 * VN), v_load(kn)) : v_zero();
		v_store(kn + VN, d);
	}
}

static inline vf dt_load_w(const struct dt_ctx *c, size_t at)
{
	const vf v = v_load(c->in + at);
	if (!c->in_depth)
		return v;
	/* a division, once per pixel and frame: the refined estimate's 3e-7
	 * would reach the output as is, and where the depth is ragged amplified */
	const vm has = v_gt(v, v_zero());
	return v_sel(has, v_div(v_set1(1.0f), v_sel(has, v, v_set1(1.0f))), v_zero());
}

/* the link between samples n-1 and n (link_exponent in domain.c); noise and
 * inv_scale: the per-cell values at n, or the pass's constants */
static inline vf dt_link(const struct dt_ctx *c, vf wm2, vf wm1, vf w0, vf wp1, vf noise,
			 vf spatial_term, vf *inv_sigma_out)
{
	const vf zero = v_zero();
	const vm ok = m_and(v_gt(wm1, zero), v_gt(w0, zero));
	const vf d = v_sub(w0, wm1);
	const vf dm = v_sel(v_gt(wm2, zero), v_sub(wm1, wm2), zero);
	const vf dp = v_sel(v_gt(wp1, zero), v_sub(wp1, w0), zero);
	const vf e = v_sub(d, dt_med3(dm, d, dp));
	const vf sigma = v_max(v_max(noise, v_mul(v_mul(c->unit, w0), w0)),
			       v_set1(DAO_DOMAIN_MIN_NOISE));
	/* (e / sigma)^2 with the refined reciprocal (3e-7 relative; a division
	 * costs more than the rest of the link on AVX-512) */
	const vf inv_sigma = v_rcp(sigma);
	*inv_sigma_out = inv_sigma;
	const vf r = v_mul(e, inv_sigma);
	const vf r2 = v_mul(r, r);
	const vf x = v_fma(c->range, r2, spatial_term);
	const vm on = m_and(ok, v_lt(x, v_set1(DAO_DOMAIN_MAX_EXPONENT)));
	return v_sel(on, dt_link_weight(x), zero);
}

/*
 * The causal sweep of a strip: per sample the link to the one before, then
 * the moments of the samples 0..n about n at distances n - k, the data
 * centred on w_n; stores the moments, the link, 1/z and the side test's
 * scale.  Built once per combination of the flags (constants at the call)
 * so that the loop tests none of them.  By blocks of at most DT_BLOCK
 * samples between the same two knots (hoisted): a loop of links stores the
 * link, 1/z and the scale, then a loop of moments reads them back from L1
 * (3 % faster than one loop doing both, measured with AVX-512).
 */
static inline __attribute__((always_inline)) void
dt_causal(const struct dt_ctx *cp, float *sc, int len, const int in_depth, const int noise_map,
	  const int scale_map, const int sides)
{
	struct dt_ctx c = *cp;
	c.in_depth = in_depth;
	if (!noise_map)
		c.noise_knots = NULL;
	if (!scale_map)
		c.scale_knots = NULL;
	const vf zero = v_zero(), one = v_set1(1.0f), two = v_set1(2.0f);
	const vf side_k2 = c.side_k2;
	vf wm2 = zero, wm1 = zero, w0 = zero, wp1 = dt_load_w(&c, 0), wprev = zero;
	vf s0 = zero, s1 = zero, s2 = zero, t0 = zero, t1 = zero, t2 = zero;
	const int maps = noise_map || scale_map;
	for (int b = 0; b < len;) {
		/* a block of samples between the same knots: the links, then the
		 * moments (the links' long chains overlap without the moments'
		 * recursion in the way; the block stays in L1 between the loops) */
		const size_t k = maps ? (size_t)c.pos[2 * b] : 0;
		/* the block's end: the pass's setup stored it at its first sample
		 * (dt_pos) */
		const int e = maps ? (int)c.pos[2 * b + 1] : (len - b < DT_BLOCK ? len : b + DT_BLOCK);
		const vf na = noise_map ? v_load(c.noise_knots + k) : c.noise;
		const vf nd = noise_map ? v_load(c.noise_knots + k + VN) : zero;
		/* the spatial factor folded into the scale's knot and difference */
		const vf sa = scale_map ? v_mul(c.spatial, v_load(c.scale_knots + k)) : zero;
		const vf sd = scale_map ? v_mul(c.spatial, v_load(c.scale_knots + k + VN)) : zero;
		for (int n = b; n < e; n++) {
			const size_t at = (size_t)n * c.stride;
			wm2 = wm1, wm1 = w0, w0 = wp1;
			wp1 = n + 1 < len ? dt_load_w(&c, at + c.stride) : zero;
			/* the line's samples are a row of the input apart (lanes
			 * floats, often a page or more): too far apart for the
			 * hardware's prefetchers */
			if (n + DT_PREFETCH < len)
				__builtin_prefetch(c.in + at + DT_PREFETCH * c.stride);
			const vf u = maps ? v_set1(c.pos[2 * len + n]) : zero;
			/* cell_value in domain.c, a + (b - a) u, as one multiply-add
			 * (the reference rounds the product: within an ulp) */
			const vf noise = noise_map ? v_fma(nd, u, na) : na;
			const vf sp = scale_map ? v_fma(sd, u, sa) : c.spatial_term;
			vf inv_sigma;
			const vf l = dt_link(&c, wm2, wm1, w0, wp1, noise, sp, &inv_sigma);
			float *o = sc + (size_t)n * DAO_DOMAIN_SCRATCH * VN;
			v_store(o + 6 * VN, n > 0 ? l : zero);
			v_store(o + 7 * VN, w0);
			/* 1 / (side_noise sigma)^2 from the link's refined reciprocal
			 * of sigma, not a division of its own (domain.c divides) */
			if (sides)
				v_store(o + 8 * VN, v_mul(v_mul(side_k2, inv_sigma), inv_sigma));
		}
		for (int n = b; n < e; n++) {
			float *o = sc + (size_t)n * DAO_DOMAIN_SCRATCH * VN;
			const vf l = v_load(o + 6 * VN), wn = v_load(o + 7 * VN);
			const vf dw = v_sub(wprev, wn), valid = v_sel(v_gt(wn, zero), one, zero);
			wprev = wn;
			const vf ls0 = v_mul(l, s0), ls1 = v_mul(l, s1);
			if (sides)
				t2 = v_fma(l, t2, v_mul(dw, v_fma(two, v_mul(l, t0), v_mul(dw, ls0))));
			t1 = v_fma(l, t1, v_fma(dw, v_add(ls1, ls0), v_mul(l, t0)));
			t0 = v_fma(l, t0, v_mul(dw, ls0));
			s2 = v_fma(l, s2, v_fma(two, ls1, ls0));
			s1 = v_fma(l, s1, ls0);
			s0 = v_fma(l, s0, valid);
			v_store(o, s0);
			v_store(o + VN, s1);
			v_store(o + 2 * VN, s2);
			v_store(o + 3 * VN, t0);
			v_store(o + 4 * VN, t1);
			v_store(o + 5 * VN, t2);
		}
		b = e;
	}
}

/* the value of a weighted least-squares line at d = 0, its residual sum of
 * squares and the weight it is divided by for the variance (dao_domain_line) */
static inline vf dt_line(vf s0, vf s1, vf s2, vf t0, vf t1, vf t2, vf *rss, vf *dof)
{
	const vf inv = v_rcp(v_fnma(s1, s1, v_mul(s2, s0)));
	const vf a = v_mul(v_fnma(s1, t1, v_mul(s2, t0)), inv);
	const vf b = v_mul(v_fnma(s1, t0, v_mul(s0, t1)), inv);
	*rss = v_max(v_fnma(b, t1, v_fnma(a, t0, t2)), v_zero());
	*dof = v_max(v_sub(s0, v_set1(DAO_DOMAIN_SIDE_DOF)), v_set1(DAO_DOMAIN_SIDE_MIN_WEIGHT));
	return a;
}

/* side_value in domain.c */
static inline vf dt_side(vf f0, vf f1, vf f2, vf f3, vf f4, vf f5, vf l0, vf l1, vf l2, vf l3,
			 vf l4, vf l5, vf r0, vf r1, vf r2, vf r3, vf r4, vf r5, vf k2)
{
	vf rf, df, rl, dl, rr, dr;
	const vf af = dt_line(f0, f1, f2, f3, f4, f5, &rf, &df);
	/* the one-sided fits only where a lane's two-sided fit may fail the
	 * test (creases, edges, hole borders; rss k2 > dof): elsewhere the
	 * blend is af */
	if (!m_any(v_gt(v_mul(rf, k2), df)))
		return af;
	const vf al = dt_line(l0, l1, l2, l3, l4, l5, &rl, &dl);
	const vf ar = dt_line(r0, r1, r2, r3, r4, r5, &rr, &dr);
	const vf vf_ = v_mul(rf, v_rcp(df)), vl = v_mul(rl, v_rcp(dl)), vr = v_mul(rr, v_rcp(dr));
	const vf tiny = v_set1(1e-30f), one = v_set1(1.0f);
	const vf vl2 = v_mul(vl, vl), vr2 = v_mul(vr, vr);
	const vf wl = v_mul(vr2, v_rcp(v_add(v_add(vl2, vr2), tiny)));
	const vf side = v_fma(v_sub(al, ar), wl, ar);
	const vf best = v_fma(v_set1(DAO_DOMAIN_SIDE_RATIO), v_min(vl, vr), tiny);
	const vf q = v_min(v_mul(vf_, k2), v_mul(vf_, v_rcp(best)));
	const vf t = v_min(v_max(v_sub(q, one), v_zero()), one);
	return v_fma(v_sub(side, af), t, af);
}

/* out: samples n .. n + count - 1 of rows lane0 + skip .. lane0 + VN - 1,
 * from tile[k] = sample n + k of the VN lines (transposed in place) */
static inline void dt_out_tile(const struct dao_domain_pass *p, vf tile[VN], int lane0, int skip,
			       int n, int count)
{
	const int len = p->len;
	for (int k = count; k < VN; k++)
		tile[k] = v_zero();
	v_transpose(tile);
	for (int j = skip; j < VN; j++) {
		float *out = p->out + (size_t)(lane0 + j) * len + n;
		if (count == VN) {
			v_store(out, tile[j]);
		} else {
			float row[VN];
			v_store(row, tile[j]);
			memcpy(out, row, (size_t)count * sizeof(float));
		}
	}
}

/*
 * VN lines from lane0.  The causal sweep stores its moments, link and 1/z
 * per sample; the anticausal sweep fits and collects VN samples of the VN
 * lines at a time in registers, which go out transposed.  Rows of the
 * output below lane0 + skip are left alone (the last strip overlaps the one
 * before it).
 */
static inline __attribute__((always_inline)) void
dt_strip_sides(const struct dao_domain_pass *p, float *sc, const float *pos, int lane0, int skip,
	       const int sides)
{
	const int len = p->len;
	/* the cells' knots of the strip's lanes, after its scratch */
	float *noise_knots = sc + (size_t)DAO_DOMAIN_SCRATCH * VN * len;
	float *scale_knots = noise_knots + (size_t)2 * VN * p->line_cells;
	if (p->noise_cells)
		dt_cell_knots(p, p->noise_cells, lane0, noise_knots);
	if (p->inv_scale_cells)
		dt_cell_knots(p, p->inv_scale_cells, lane0, scale_knots);
	const struct dt_ctx c = {
		.in = p->in + lane0,
		.noise_knots = p->noise_cells ? noise_knots : NULL,
		.scale_knots = p->inv_scale_cells ? scale_knots : NULL,
		.stride = (size_t)p->lanes,
		.in_depth = p->in_depth,
		.pos = pos,
		.noise = v_set1(p->noise), .unit = v_set1(p->unit), .spatial = v_set1(p->spatial),
		.spatial_term = v_set1(p->spatial * p->inv_scale), .range = v_set1(p->range_coef),
		.side_k2 = v_set1(p->side_k2),
	};
	if (c.noise_knots && c.scale_knots) {
		if (c.in_depth)
			dt_causal(&c, sc, len, 1, 1, 1, sides);
		else
			dt_causal(&c, sc, len, 0, 1, 1, sides);
	} else if (!c.noise_knots && !c.scale_knots) {
		if (c.in_depth)
			dt_causal(&c, sc, len, 1, 0, 0, sides);
		else
			dt_causal(&c, sc, len, 0, 0, 0, sides);
	} else {
		dt_causal(&c, sc, len, c.in_depth, c.noise_knots != NULL, c.scale_knots != NULL,
			  sides);
	}
	const vf zero = v_zero(), one = v_set1(1.0f), two = v_set1(2.0f);
	/* anticausal: distances k - n, added to the causal moments (whose first
	 * moments change sign), then the fit */
	vf r0 = zero, r1 = zero, r2 = zero, u0 = zero, u1 = zero, u2 = zero, lnext = zero;
	vf wnext = zero;
	const vf ridge = v_set1(DAO_DOMAIN_RIDGE);
	const int out_depth = p->out_depth;
	vf tile[VN];
	for (int n = len - 1; n >= 0; n--) {
		float *o = sc + (size_t)n * DAO_DOMAIN_SCRATCH * VN;
		const vf wn = v_load(o + 7 * VN), dw = v_sub(wnext, wn);
		const vm has = v_gt(wn, zero);
		const vf x0 = v_mul(lnext, r0), lr1 = v_mul(lnext, r1), lu0 = v_mul(lnext, u0);
		const vf x1 = v_fma(lnext, r1, x0);
		const vf x2 = v_fma(lnext, r2, v_fma(two, lr1, x0));
		const vf y0 = v_fma(lnext, u0, v_mul(dw, x0));
		const vf y1 = v_fma(lnext, u1, v_fma(dw, v_add(lr1, x0), lu0));
		const vf c0 = v_load(o), c1 = v_load(o + VN), c2 = v_load(o + 2 * VN);
		const vf c3 = v_load(o + 3 * VN), c4 = v_load(o + 4 * VN);
		const vf S0 = v_add(c0, x0), S1 = v_sub(x1, c1);
		const vf S2 = v_add(v_add(c2, x2), ridge);
		const vf T0 = v_add(c3, y0), T1 = v_sub(y1, c4);
		r0 = v_fma(lnext, r0, v_sel(has, one, zero)), r1 = x1, r2 = x2;
		u0 = y0, u1 = y1;
		vf d;
		/* holes: den = 0, a NaN here, zeroed below */
		if (sides) {
			const vf y2 = v_fma(lnext, u2, v_mul(dw, v_fma(two, lu0, v_mul(dw, x0))));
			const vf c5 = v_load(o + 5 * VN);
			d = dt_side(S0, S1, S2, T0, T1, v_add(c5, y2),
				    c0, v_neg(c1), v_add(c2, ridge), c3, v_neg(c4), c5,
				    v_add(x0, one), x1, v_add(x2, ridge), y0, y1, y2,
				    v_load(o + 8 * VN));
			u2 = y2;
		} else {
			const vf num = v_fnma(S1, T1, v_mul(S2, T0));
			const vf den = v_fnma(S1, S1, v_mul(S2, S0));
			d = v_mul(num, v_rcp(den));
		}
		lnext = v_load(o + 6 * VN);
		wnext = wn;
		vf v = v_add(d, wn);
		v = v_sel(v_gt(v, zero), v, wn);
		if (out_depth) /* a division: once per pixel and frame */
			v = v_div(one, v);
		tile[n % VN] = v_sel(has, v, zero);
		if (n % VN == 0)
			dt_out_tile(p, tile, lane0, skip, n, len - n < VN ? len - n : VN);
	}
}

static void dt_strip(const struct dao_domain_pass *p, float *sc, const float *pos, int lane0,
		     int skip)
{
	if (p->sides)
		dt_strip_sides(p, sc, pos, lane0, skip, 1);
	else
		dt_strip_sides(p, sc, pos, lane0, skip, 0);
}

/*
 * Where each sample of a line is between the cells' knots, the same for every
 * line: pos[2 len + n] = u of sample n; at the first sample b of each block of
 * the causal sweep (at most DT_BLOCK samples between the same two knots)
 * pos[2 b] = the knots' offset (k 2 VN) and pos[2 b + 1] = the block's end.
 */
static void dt_pos(const struct dao_domain_pass *p, float *pos)
{
	const int len = p->len;
	/* a loop the compiler vectorises, then the blocks' scan */
	for (int n = 0; n < len; n++) {
		int k;
		float u;
		dao_domain_cell_pos(n, p->line_cells, p->cell_span, &k, &u);
		pos[2 * n] = (float)(k * 2 * VN), pos[2 * len + n] = u;
	}
	for (int b = 0, e; b < len; b = e) {
		e = b + 1;
		while (e < len && e - b < DT_BLOCK && pos[2 * e] == pos[2 * b])
			e++;
		pos[2 * b + 1] = (float)e;
	}
}

void DAO_ISA_FN(dao_domain_pass)(const struct dao_domain_pass *p, float *scratch, int lane0,
				 int lane1)
{
	/* where each sample of a line is between the cells' knots, the same
	 * for every line: after the largest scratch a strip uses */
	float *pos = scratch + (size_t)(DAO_DOMAIN_SCRATCH + DAO_DOMAIN_KNOT_SCRATCH) * VN * p->len;
	if (p->noise_cells || p->inv_scale_cells)
		dt_pos(p, pos);
	int l0 = lane0;
	for (; l0 + VN <= lane1; l0 += VN)
		dt_strip(p, scratch, pos, l0, 0);
	if (l0 >= lane1)
		return;
	if (lane1 == p->lanes && p->lanes >= VN) /* overlap the strip before */
		dt_strip(p, scratch, pos, p->lanes - VN, l0 - (p->lanes - VN));
	else
		dao_domain_pass_ref(p, scratch, l0, lane1);
}
