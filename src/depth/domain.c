/* SPDX-License-Identifier: MIT */
/* The domain-transform depth filter: schedule and the reference pass (see domain.h). */
#include <math.h>
#include <stddef.h>

#include "depth/domain.h"

float dao_domain_schedule(int iteration, int iterations)
{
	return (float)(sqrt(3.0) * ldexp(1.0, iterations - iteration) /
		       sqrt(ldexp(1.0, 2 * iterations) - 1.0));
}

float dao_domain_spatial(int iteration, int iterations)
{
	return 1.41421356237f / dao_domain_schedule(iteration, iterations);
}

float dao_domain_range_coef(float range)
{
	return 1.0f / (2.0f * range * range);
}

static float med3(float a, float b, float c)
{
	return fmaxf(fminf(a, b), fminf(fmaxf(a, b), c));
}

/* 1/z of a sample as the pass reads it */
static float load_w(const struct dao_domain_pass *p, int n, int lane)
{
	const float v = p->in[(size_t)n * p->lanes + lane];
	if (!p->in_depth)
		return v;
	return v > 0.0f ? 1.0f / v : 0.0f;
}

/*
 * The exponent of the link between samples n-1 and n of a lane (w: 1/z
 * at n-2 .. n+1, 0 outside the line or without data; the noise sigma and
 * 1 / sigma_s there), or a value above
 * DAO_DOMAIN_MAX_EXPONENT when there is no link.
 */
static float link_exponent(const struct dao_domain_pass *p, const float w[4], float sigma,
			   float inv_scale)
{
	const float wm2 = w[0], wm1 = w[1], w0 = w[2], wp1 = w[3];
	if (!(wm1 > 0.0f && w0 > 0.0f))
		return INFINITY;
	const float d = w0 - wm1;
	/* a neighbouring difference without data counts as 0 */
	const float dm = wm2 > 0.0f ? wm1 - wm2 : 0.0f;
	const float dp = wp1 > 0.0f ? wp1 - w0 : 0.0f;
	const float e = d - med3(dm, d, dp);
	const float r = e / sigma;
	return p->spatial * inv_scale + p->range_coef * r * r;
}

/* the noise sigma a sample's links and side test use */
static float sample_sigma(const struct dao_domain_pass *p, float sigma, float w0)
{
	return fmaxf(fmaxf(sigma, p->unit * w0 * w0), DAO_DOMAIN_MIN_NOISE);
}

/*
 * Side windows: the two-sided fit (moments S*, T*), or where it does not
 * explain its samples (a crease, where the recursive filter's line bends the
 * corner round) the one-sided fits of the samples before and after n,
 * weighted by the square of the other's residual variance (Yin et al.,
 * "Side Window Filtering", CVPR 2019, with local lines and the residual as
 * the criterion, as the Kuwahara filter).  k2 = 1 / (side_noise sigma)^2.
 */
static float side_value(const float full[6], const float left[6], const float right[6], float k2)
{
	float vf, vl, vr;
	const float af = dao_domain_line(full[0], full[1], full[2], full[3], full[4], full[5], &vf);
	if (!(vf * k2 > 1.0f)) /* the test cannot fail: the blend is af */
		return af;
	const float al = dao_domain_line(left[0], left[1], left[2], left[3], left[4], left[5], &vl);
	const float ar = dao_domain_line(right[0], right[1], right[2], right[3], right[4], right[5],
					 &vr);
	const float vl2 = vl * vl, vr2 = vr * vr;
	const float wl = vr2 / (vl2 + vr2 + 1e-30f);
	const float side = ar + (al - ar) * wl;
	const float q = fminf(vf * k2, vf / (DAO_DOMAIN_SIDE_RATIO * fminf(vl, vr) + 1e-30f));
	const float t = fminf(fmaxf(q - 1.0f, 0.0f), 1.0f);
	return af + (side - af) * t;
}

void dao_domain_cell_knots(const struct dao_domain_pass *p, const float *cells, int lane,
			   float *knots, size_t knot_stride)
{
	int a;
	float u;
	dao_domain_cell_pos(lane, p->lane_cells, p->cell_span, &a, &u);
	const int b = a + 1 < p->lane_cells ? a + 1 : a;
	for (int k = 0; k < p->line_cells; k++) {
		const float va = cells[(size_t)a * p->lane_step + (size_t)k * p->line_step];
		const float vb = cells[(size_t)b * p->lane_step + (size_t)k * p->line_step];
		knots[k * knot_stride] = va + (vb - va) * u;
	}
}

/* a per-cell value at sample n of a line from its knots */
static float cell_value(const struct dao_domain_pass *p, const float *knots, int n)
{
	int k;
	float u;
	dao_domain_cell_pos(n, p->line_cells, p->cell_span, &k, &u);
	const float a = knots[k], b = knots[k + 1 < p->line_cells ? k + 1 : k];
	return a + (b - a) * u;
}

void dao_domain_pass_ref(const struct dao_domain_pass *p, float *scratch, int lane0, int lane1)
{
	const int len = p->len;
	float *noise_knots = scratch + (size_t)DAO_DOMAIN_SCRATCH * len;
	float *scale_knots = noise_knots + len;
	for (int lane = lane0; lane < lane1; lane++) {
		if (p->noise_cells)
			dao_domain_cell_knots(p, p->noise_cells, lane, noise_knots, 1);
		if (p->inv_scale_cells)
			dao_domain_cell_knots(p, p->inv_scale_cells, lane, scale_knots, 1);
		/* causal sweep: moments of the samples 0..n about sample n, at
		 * distances n - k, the data centred on w_n; each step moves the
		 * samples so far one further away and the centre by w_n-1 - w_n */
		float s0 = 0.0f, s1 = 0.0f, s2 = 0.0f, t0 = 0.0f, t1 = 0.0f, t2 = 0.0f;
		float w[4] = { 0.0f, 0.0f, 0.0f, len > 0 ? load_w(p, 0, lane) : 0.0f };
		for (int n = 0; n < len; n++) {
			w[0] = w[1], w[1] = w[2], w[2] = w[3];
			w[3] = n + 1 < len ? load_w(p, n + 1, lane) : 0.0f;
			const float sigma = sample_sigma(p, p->noise_cells ? cell_value(p, noise_knots, n)
									 : p->noise, w[2]);
			float x = INFINITY;
			if (n > 0) {
				const float inv_scale = p->inv_scale_cells ? cell_value(p, scale_knots, n)
									   : p->inv_scale;
				x = link_exponent(p, w, sigma, inv_scale);
			}
			const float l = x < DAO_DOMAIN_MAX_EXPONENT ? dao_domain_link_weight(x) : 0.0f;
			const float valid = w[2] > 0.0f ? 1.0f : 0.0f;
			const float dw = w[1] - w[2];
			const float ls0 = l * s0, ls1 = l * s1;
			/* the squares about the new centre: (v + dw)^2 */
			t2 = l * t2 + dw * (2.0f * l * t0 + dw * ls0);
			t1 = l * t1 + (dw * (ls1 + ls0) + l * t0);
			t0 = l * t0 + dw * ls0;
			s2 = l * s2 + (2.0f * ls1 + ls0);
			s1 = l * s1 + ls0;
			s0 = l * s0 + valid;
			float *sc = scratch + (size_t)n * DAO_DOMAIN_SCRATCH;
			sc[0] = s0, sc[1] = s1, sc[2] = s2, sc[3] = t0, sc[4] = t1, sc[5] = t2;
			sc[6] = l, sc[7] = w[2], sc[8] = p->side_k2 / (sigma * sigma);
		}
		/* anticausal sweep: the samples after n at distances k - n, added to
		 * the causal ones (whose first moments change sign), then the fit */
		float r0 = 0.0f, r1 = 0.0f, r2 = 0.0f, u0 = 0.0f, u1 = 0.0f, u2 = 0.0f, lnext = 0.0f;
		float wnext = 0.0f;
		for (int n = len - 1; n >= 0; n--) {
			const float *sc = scratch + (size_t)n * DAO_DOMAIN_SCRATCH;
			const float wn = sc[7], dw = wnext - wn, valid = wn > 0.0f ? 1.0f : 0.0f;
			/* samples n+1.. seen from n: weighted by the link */
			const float x0 = lnext * r0, x1 = lnext * r1 + x0;
			const float x2 = lnext * r2 + (2.0f * lnext * r1 + x0);
			const float y0 = lnext * u0 + dw * x0;
			const float y1 = lnext * u1 + (dw * (lnext * r1 + x0) + lnext * u0);
			const float y2 = lnext * u2 + dw * (2.0f * lnext * u0 + dw * x0);
			const float S0 = sc[0] + x0, S1 = x1 - sc[1], S2 = sc[2] + x2;
			const float T0 = sc[3] + y0, T1 = y1 - sc[4];
			r0 = x0 + valid, r1 = x1, r2 = x2;
			u0 = y0, u1 = y1, u2 = y2; /* the sample itself is 0 about itself */
			lnext = sc[6];
			wnext = wn;
			float v = 0.0f;
			if (wn > 0.0f) {
				float d;
				if (p->sides) {
					const float full[6] = { S0, S1, S2 + DAO_DOMAIN_RIDGE, T0, T1,
								sc[5] + y2 };
					const float left[6] = { sc[0], -sc[1], sc[2] + DAO_DOMAIN_RIDGE,
								sc[3], -sc[4], sc[5] };
					const float right[6] = { x0 + 1.0f, x1, x2 + DAO_DOMAIN_RIDGE,
								 y0, y1, y2 };
					d = side_value(full, left, right, sc[8]);
				} else {
					const float num = (S2 + DAO_DOMAIN_RIDGE) * T0 - S1 * T1;
					const float den = (S2 + DAO_DOMAIN_RIDGE) * S0 - S1 * S1;
					d = num / den;
				}
				v = wn + d;
				if (!(v > 0.0f)) /* cannot happen with data this side of infinity */
					v = wn;
				if (p->out_depth)
					v = 1.0f / v;
			}
			p->out[(size_t)lane * len + n] = v;
		}
	}
}

void dao_domain_pass_init(struct dao_domain_pass *p, const struct dao_domain_setup *s, int k,
			  const float *in, float *out)
{
	const int vertical = !(k & 1), it = k / 2 + 1;
	*p = (struct dao_domain_pass){
		.len = vertical ? s->height : s->width,
		.lanes = vertical ? s->width : s->height,
		.in = in, .out = out,
		.in_depth = k == 0,
		.out_depth = k == 2 * s->iterations - 1,
		.spatial = dao_domain_spatial(it, s->iterations),
		.inv_scale = s->inv_scale,
		.range_coef = s->range_coef,
		.noise = s->noise,
		.unit = s->unit,
		.sides = s->sides,
		.side_k2 = 1.0f / ((s->side_noise > 0.0f ? s->side_noise : DAO_DOMAIN_SIDE_NOISE) *
				   (s->side_noise > 0.0f ? s->side_noise : DAO_DOMAIN_SIDE_NOISE)),
		.noise_cells = s->noise_cells,
		.inv_scale_cells = s->inv_scale_cells,
		/* vertical passes: the lanes are the frame's columns (x) */
		.lane_cells = vertical ? s->cells_x : s->cells_y,
		.line_cells = vertical ? s->cells_y : s->cells_x,
		.lane_step = vertical ? 1 : s->cells_x,
		.line_step = vertical ? s->cells_x : 1,
		.cell_span = s->cell_span,
	};
}

size_t dao_domain_scratch_floats(int width, int height)
{
	/* and three per sample of a line: where it is between the knots, and
	 * the causal sweep's blocks */
	const size_t len = (size_t)(width > height ? width : height);
	return ((DAO_DOMAIN_SCRATCH + DAO_DOMAIN_KNOT_SCRATCH) * DAO_DOMAIN_STRIP + 3) * len;
}

void dao_domain_filter(const struct dao_domain_setup *s, dao_domain_pass_fn pass, const float *z,
		       float *tmp, float *out, float *scratch)
{
	for (int k = 0; k < 2 * s->iterations; k++) {
		struct dao_domain_pass p;
		dao_domain_pass_init(&p, s, k, k == 0 ? z : (k & 1) ? tmp : out, (k & 1) ? out : tmp);
		pass(&p, scratch, 0, p.lanes);
	}
}
