/* SPDX-License-Identifier: MIT */
#ifndef DAO_DEPTH_PREFILTER_H
#define DAO_DEPTH_PREFILTER_H

#include <math.h>

/*
 * Edge-preserving depth prefilter: a separable bilateral filter in inverse
 * depth w = 1/z.
 *
 * Structured-light noise is roughly constant in disparity, i.e. in 1/z:
 * sigma(z) = k z^2 m  <=>  sigma(1/z) = k.  Filtering w therefore has one
 * noise level for the whole frame, and since w is an affine function of the
 * pixel on any plane, the differences to the centre are odd in the offset,
 * the weights even, and the weighted mean of a plane is the plane: planes stay
 * exactly in place, in each pass.  Range weights use the difference in w
 * against sigma_w = max(k, unit w^2) (the larger of sensor noise and depth
 * quantisation), so depth edges are kept.
 *
 * Pass 1 (horizontal) reads z (metres, 0 = no data) and writes w to tmp;
 * pass 2 (vertical) reads tmp and writes z to out.  Holes stay holes.
 * Each processes rows [y0, y1); outputs must not alias inputs.
 */
struct dao_prefilter_setup {
	int width, height, radius;
	float noise_k, unit;
	float inv_2ss;  /* 1 / (2 sigma_s^2), sigma_s = radius / 2 + 1/2 px */
};

void dao_prefilter_setup_init(struct dao_prefilter_setup *s, int width, int height, int radius,
			      float noise_k, float unit);

/* range tolerance in units of sigma_w: wide enough to average noise, narrow enough for edges */
#define DAO_PREFILTER_RANGE_SIGMAS 2.5f

/* 1 / (2 sigma_range^2) at inverse depth wc */
static inline float dao_prefilter_inv_2rr(const struct dao_prefilter_setup *s, float wc)
{
	float sw = fmaxf(s->noise_k, s->unit * wc * wc) * DAO_PREFILTER_RANGE_SIGMAS;
	/* a floor so exact (noise-free float) input still averages ulp noise */
	sw = fmaxf(sw, 1e-6f * wc);
	return 1.0f / (2.0f * sw * sw);
}

/* Reference passes (scalar, libm exp). */
void dao_prefilter_h_ref(const struct dao_prefilter_setup *s, const float *z, float *tmp, int y0,
			 int y1);
void dao_prefilter_v_ref(const struct dao_prefilter_setup *s, const float *tmp, float *out,
			 int y0, int y1);

/* One output pixel of each reference pass (the optimised passes use them at the borders). */
float dao_prefilter_h_pixel(const struct dao_prefilter_setup *s, const float *z, int x, int y);
float dao_prefilter_v_pixel(const struct dao_prefilter_setup *s, const float *tmp, int x, int y);

#define DAO_PREFILTER_SIMD_PROTO(isa)                                                          \
	void dao_prefilter_h_##isa(const struct dao_prefilter_setup *s, const float *z, float *tmp, \
				   int y0, int y1);                                             \
	void dao_prefilter_v_##isa(const struct dao_prefilter_setup *s, const float *tmp,           \
				   float *out, int y0, int y1)

DAO_PREFILTER_SIMD_PROTO(generic);
DAO_PREFILTER_SIMD_PROTO(sse41);
DAO_PREFILTER_SIMD_PROTO(avx2);
DAO_PREFILTER_SIMD_PROTO(avx512);

#endif
