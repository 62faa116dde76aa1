/* SPDX-License-Identifier: MIT */
#ifndef DAO_DEPTH_DOMAIN_H
#define DAO_DEPTH_DOMAIN_H

#include <math.h>
#include <stddef.h>

/*
 * prefilter=domain: a wide edge-preserving filter of inverse depth w = 1/z
 * whose cost does not depend on its scale, after the recursive filter of the
 * domain transform (Gastal & Oliveira 2011, "Domain Transform for
 * Edge-Aware Image and Video Processing"; librealsense's spatial filter is a
 * variant of it).
 *
 * Iterations i = 1..N of a vertical then a horizontal 1D pass, the spatial
 * scale of iteration i being sigma_s * sqrt(3) 2^(N-i) / sqrt(4^N - 1) (the
 * paper's schedule: the variances add up to sigma_s^2).  A 1D pass gives the
 * neighbours n-1, n of a line a link weight
 *
 *   l_n = a^1 * exp(-e_n^2 / (2 sigma_r^2)),   a = exp(-sqrt(2) / sigma_H),
 *
 * (e^-x as dao_domain_link_weight computes it, a Taylor polynomial of
 * e^(-x/32) to the 32nd power: within 3e-6 of e^-x where links are open)
 * and sample k weighs prod(l) over the links between it and the output
 * sample: a^|k| on open ground, (nearly) nothing across a depth edge, nothing
 * across a hole.  A causal and an anticausal sweep sum these weights, so a
 * pass costs the same at any scale.  Three choices differ from the paper's
 * filter, each measured (README.md):
 *
 * - The range term.  The transform's distance 1 + (sigma_s/sigma_r)|w_n -
 *   w_n-1| adds up the noise of every link crossed, which on noisy depth caps
 *   the reach at ~sigma_r/sigma_noise pixels whatever sigma_s (in a
 *   prototype of both: independent noise reduced 3.4x at sigma_s = 8 px,
 *   against 20x with the term below).  A Gaussian of the link's difference
 *   in units of the local noise does not accumulate.
 * - The difference tested is slope-corrected: e_n = d_n - med3(d_n-1, d_n,
 *   d_n+1) with d_n = w_n - w_n-1 (0 where a sample has no data).  A plane's
 *   constant slope drops out (it is no reason to stop), a step between n-1
 *   and n does not (the median of the three differences is a neighbouring
 *   one).
 * - Local linear regression instead of the weighted mean.  The recursive
 *   filter is a weighted mean; where the weights are one-sided (near holes,
 *   edges and the border) the mean of a tilted plane lags by the slope times
 *   the scale (0.017 in 1/z at 8 px: centimetres at 2 m).  Each pass sums the
 *   weights' moments S0, S1, S2 about the output sample n and the data's T0,
 *   T1 with the data centred on w_n (precision: the sums are of differences;
 *   the sweeps shift distances and centre by one sample per step) and
 *   returns the line fitted by weighted least squares at the sample:
 *
 *     w' = w_n + (S2 T0 - S1 T1 + lambda T0) / (S0 S2 - S1^2 + lambda S0),
 *
 *   exact for any w affine along the line, whatever the weights: a plane
 *   (1/z is affine in the pixel on any plane) stays where it is up to float
 *   rounding, next to edges and holes too.  On open ground S1 = 0 and it is
 *   the weighted mean.  lambda (px^2) only keeps a lone sample's 0/0 finite.
 * - Side windows (sides = 1, the pipeline's setting).  The slope-corrected
 *   link lets a crease (two planes meeting at an angle) through, and the
 *   two-sided line rounds it over the scale: normals tilted 10 px either
 *   side of every stair crease.  With the squares T2 carried as well, the
 *   causal sums alone are the line fitted to the samples up to n and the
 *   anticausal ones (plus n) to those from n on; where the two-sided fit's
 *   residual variance exceeds both (side_noise sigma)^2 and
 *   DAO_DOMAIN_SIDE_RATIO times the better side's, the output moves to the
 *   one-sided fits (weighted by the square of the other's residual), fully
 *   at twice the threshold: the plane each side of a crease is extrapolated
 *   to it (Yin et al., "Side Window Filtering", CVPR 2019, with local lines
 *   and the residual as the criterion as in the Kuwahara filter).  Planes
 *   keep the two-sided fit; a plane stays exact either way.
 *
 * Range scale: sigma_r = range x sigma with sigma = max(noise, unit w^2,
 * DAO_DOMAIN_MIN_NOISE) at the sample (sensor noise in 1/z, from the model
 * or the noise map; the depth quantum; a floor for exact float input).
 * Holes neither contribute nor are filled.
 */

/* A pass reads `len` rows of `lanes` floats and writes `lanes` rows of `len`
 * floats (transposed), so that the next pass again runs down the columns. */
struct dao_domain_pass {
	int len, lanes;
	const float *in;          /* 1/z, or z when in_depth; 0 = no data */
	float *out;               /* transposed; 1/z, or z when out_depth */
	int in_depth, out_depth;
	int sides;                /* 1: side windows at creases (see DAO_DOMAIN_SIDE_NOISE) */
	float side_k2;            /* 1 / side_noise^2 (sides) */
	/* a link is exp(-(spatial x inv_scale + range_coef x (e / sigma)^2)) */
	float spatial;            /* sqrt(2) / (schedule factor of the iteration) */
	float inv_scale;          /* 1 / sigma_s (1/px) */
	float range_coef;         /* 1 / (2 range^2) */
	float noise;              /* sigma of 1/z, 1/m */
	float unit;               /* depth quantum, m (0 for float input) */
	/* per-cell noise and 1 / sigma_s instead of the two scalars (NULL: the
	 * scalars): cell (a, b), a along the lanes and b along the line, at
	 * cells[a * lane_step + b * line_step], bilinear between cell centres
	 * (dao_domain_cell_knots, dao_domain_cell_at) */
	const float *noise_cells, *inv_scale_cells;
	int lane_cells, line_cells; /* cells along the lanes and along the line */
	int lane_step, line_step;
	int cell_span;            /* px per cell side */
};

#define DAO_DOMAIN_MAX_ITERATIONS 5
/* floats of scratch per sample and lane: the causal moments S0-S2, T0-T2,
 * the link, 1/z and the side test's 1 / (side_noise sigma)^2 */
#define DAO_DOMAIN_SCRATCH 9
/* and per sample of the longer side and lane for the cells' knots (at most
 * a cell per px: of noise and of scale, a knot and the difference to the next) */
#define DAO_DOMAIN_KNOT_SCRATCH 4
/* a link whose exponent exceeds this is 0 (e^-17 = 4e-8: below float's step at 1) */
#define DAO_DOMAIN_MAX_EXPONENT 17.0f
/*
 * The link weight e^-x for 0 <= x < DAO_DOMAIN_MAX_EXPONENT (0 beyond, the
 * caller's test): e^-x = (e^(-x/32))^32 with e^-t by its Taylor polynomial
 * 1 - t + t^2/2 - t^3/6 (t = x/32 <= 0.53), three multiply-adds and five
 * squarings instead of a range-reduced polynomial and an ldexp.  Relative to
 * e^-x, in float: within 2.7e-6 for x <= 1 (open links; the base's rounding
 * doubled by each squaring), 2.3e-5 to 2, 3.6e-4 to 4, 6.4e-3 to 8 (weights
 * below 3.4e-4 there), 15 % low at 17 (4e-8); every kernel set and the
 * reference compute it alike (fused multiply-adds where the set has them).
 */
#define DAO_DOMAIN_LINK_C1 (-1.0f / 32.0f)
#define DAO_DOMAIN_LINK_C2 (1.0f / 2048.0f)
#define DAO_DOMAIN_LINK_C3 (-1.0f / 196608.0f)

static inline float dao_domain_link_weight(float x)
{
	float q = fmaf(DAO_DOMAIN_LINK_C3, x, DAO_DOMAIN_LINK_C2);
	q = fmaf(q, x, DAO_DOMAIN_LINK_C1);
	q = fmaf(q, x, 1.0f);
	q *= q, q *= q, q *= q, q *= q;
	return q * q;
}

/* the least noise sigma in 1/z, 1/m (4 um at 2 m) */
#define DAO_DOMAIN_MIN_NOISE 1e-6f
/* lambda of the local linear fit, px^2 */
#define DAO_DOMAIN_RIDGE 1e-6f
/* side windows (README.md, Noise measured in the frame): a one-sided fit
 * replaces the two-sided one where the two-sided fit's residual variance
 * exceeds DAO_DOMAIN_SIDE_NOISE^2 sigma^2 and DAO_DOMAIN_SIDE_RATIO times the
 * better side's, fully at twice the threshold; a fit's residual variance is
 * its weighted RSS / (S0 - DAO_DOMAIN_SIDE_DOF), at least / 0.25 (fitted
 * on eval --set tune) */
#define DAO_DOMAIN_SIDE_NOISE 1.4f
#define DAO_DOMAIN_SIDE_RATIO 2.0f
#define DAO_DOMAIN_SIDE_DOF 1.5f
#define DAO_DOMAIN_SIDE_MIN_WEIGHT 0.25f

/* the residual variance of a weighted least-squares line from its moments
 * (rss = T2 - a T0 - b T1 for the line a + b d) and its value at d = 0;
 * S2 includes the ridge */
static inline float dao_domain_line(float s0, float s1, float s2, float t0, float t1, float t2,
				    float *var)
{
	const float den = s2 * s0 - s1 * s1;
	const float a = (s2 * t0 - s1 * t1) / den, b = (s0 * t1 - s1 * t0) / den;
	const float rss = t2 - a * t0 - b * t1;
	*var = fmaxf(rss, 0.0f) / fmaxf(s0 - DAO_DOMAIN_SIDE_DOF, DAO_DOMAIN_SIDE_MIN_WEIGHT);
	return a;
}

/* sqrt(3) 2^(N-i) / sqrt(4^N - 1): iteration i's share of sigma_s (i = 1..n) */
float dao_domain_schedule(int iteration, int iterations);

/* pass->spatial for iteration i of n */
float dao_domain_spatial(int iteration, int iterations);

/* pass->range_coef for a range scale in units of the noise: 1 / (2 range^2) */
float dao_domain_range_coef(float range);

/*
 * Per-cell values (noise-model=auto): bilinear between cell centres,
 * constant beyond the outer ones, computed where a pass needs them instead
 * of per-pixel maps (four planes of the frame written per frame and read
 * strided by every pass cost more time than the filter's arithmetic).  The
 * interpolation goes along the lanes first: knots[k] is the value at `lane`
 * on the k-th row of cells along the line (line_cells of them); then along
 * the line, the same arithmetic in every kernel set:
 *
 *   v = knots[k] + (knots[k + 1] - knots[k]) * u    (dao_domain_cell_pos)
 */
void dao_domain_cell_knots(const struct dao_domain_pass *p, const float *cells, int lane,
			   float *knots, size_t knot_stride);

/* the knot k and weight u of sample n along a line of `cells` cells of `span` px */
static inline void dao_domain_cell_pos(int n, int cells, int span, int *k, float *u)
{
	const float f = ((float)n - (0.5f * (float)span - 0.5f)) / (float)span;
	int i = (int)floorf(f);
	float t = f - (float)i;
	if (i < 0)
		i = 0, t = 0.0f;
	if (i >= cells - 1)
		i = cells - 1, t = 0.0f;
	*k = i, *u = t;
}

/*
 * Reference pass (scalar) over lanes [lane0, lane1).  scratch:
 * (DAO_DOMAIN_SCRATCH + DAO_DOMAIN_KNOT_SCRATCH) * len floats.
 */
void dao_domain_pass_ref(const struct dao_domain_pass *p, float *scratch, int lane0, int lane1);

/* Lanes the optimised passes process together: a scratch of
 * ((DAO_DOMAIN_SCRATCH + DAO_DOMAIN_KNOT_SCRATCH) * DAO_DOMAIN_STRIP + 3) *
 * len floats serves every set (dao_domain_scratch_floats). */
#define DAO_DOMAIN_STRIP 16

/* The whole filter of a w x h frame. */
struct dao_domain_setup {
	int width, height, iterations;
	float inv_scale;          /* 1 / sigma_s, 1/px */
	float range_coef;         /* dao_domain_range_coef(range) */
	float noise, unit;        /* as in struct dao_domain_pass */
	int sides;                /* as in struct dao_domain_pass */
	/* the side test's threshold in units of sigma (0: DAO_DOMAIN_SIDE_NOISE);
	 * smaller where the input is averaged beyond what sigma says (the
	 * temporal depth filter) */
	float side_noise;
	/* per-cell values (NULL: the scalars): cells_x x cells_y, row-major,
	 * cells of cell_span px, bilinear between their centres */
	const float *noise_cells, *inv_scale_cells;
	int cells_x, cells_y, cell_span;
};

/*
 * Pass k = 0 .. 2 iterations - 1: even passes run down the columns of the
 * frame (in: w x h, the depth z for k = 0, else 1/z) and write 1/z
 * transposed; odd passes run down the columns of that (the rows of the frame)
 * and write the frame's layout again, z after the last pass.
 */
void dao_domain_pass_init(struct dao_domain_pass *p, const struct dao_domain_setup *s, int k,
			  const float *in, float *out);

typedef void (*dao_domain_pass_fn)(const struct dao_domain_pass *p, float *scratch, int lane0,
				   int lane1);

/* Scratch floats of the filter for a frame (one strip of the longer side). */
size_t dao_domain_scratch_floats(int width, int height);

/* The filter on one thread: z (w x h, m) -> out (m); tmp: w x h floats. */
void dao_domain_filter(const struct dao_domain_setup *s, dao_domain_pass_fn pass, const float *z,
		       float *tmp, float *out, float *scratch);

#define DAO_DOMAIN_SIMD_PROTO(isa)                                                          \
	void dao_domain_pass_##isa(const struct dao_domain_pass *p, float *scratch, int lane0, \
				   int lane1)

DAO_DOMAIN_SIMD_PROTO(generic);
DAO_DOMAIN_SIMD_PROTO(sse41);
DAO_DOMAIN_SIMD_PROTO(avx2);
DAO_DOMAIN_SIMD_PROTO(avx512);

#endif
