/* SPDX-License-Identifier: MIT */
#ifndef DAO_DENOISE_DENOISE_H
#define DAO_DENOISE_DENOISE_H

#include <depthao/camera.h>

/* What the AO denoise filters need besides the AO itself. */
struct dao_denoise_setup {
	int width, height;
	float ax, ay, bx, by;  /* UvToViewParams */
	float noise_k;         /* sigma(z) = noise_k z^2 */
	float sharpness;       /* depth tolerance in units of sigma(z) */
	int radius;            /* bilateral radius, px */
	float invalid_value;
};

/*
 * Depth tolerance of the denoise filters at depth z: sharpness x the larger
 * of sensor noise (k z^2) and a relative floor (0.2 % of z) for clean input.
 */
static inline float dao_denoise_tolerance(const struct dao_denoise_setup *s, float z)
{
	float sigma = s->noise_k * z * z;
	float floor_rel = 0.002f * z;
	return s->sharpness * (sigma > floor_rel ? sigma : floor_rel);
}

/*
 * Spatial weight of the plane denoise's taps along one axis, offset -2 .. 2:
 * 1/2, 1, 1, 1, 1/2.  Any pattern of period 4 (the GTAO noise tile) or 2
 * sums to its mean under it -- the two end taps are the same tile phase and
 * share one tap's weight -- so on a smooth surface the tile leaves no grid,
 * which a plain 5-tap box does not achieve (its response at 1/4 and 1/2
 * cycles per pixel is -1/5 and 1/5).  The weights are powers of two: the
 * optimised kernels scale by them exactly.
 */
static inline float dao_denoise_plane_tap_weight(int offset)
{
	return offset == -2 || offset == 2 ? 0.5f : 1.0f;
}

/*
 * Seed 002's 5x5 spatial filter (UE4 mobile GTAO): per axis the depth
 * gradient of the smoother side is extrapolated to a plane, and each tap is
 * weighted by 1 - saturate(|plane z - tap z| / tolerance), times the tile-
 * cancelling spatial weights above.  Rows [y0, y1).
 */
void dao_denoise_plane(const struct dao_denoise_setup *s, const float *z, const float *ao_in,
		       float *ao_out, int y0, int y1);

/* One output pixel of the reference plane filter (the optimised ones use it at borders). */
float dao_denoise_plane_pixel(const struct dao_denoise_setup *s, const float *z,
			      const float *ao_in, int x, int y);

#define DAO_DENOISE_SIMD_PROTO(isa)                                                           \
	void dao_denoise_plane_##isa(const struct dao_denoise_setup *s, const float *z,       \
				     const float *ao_in, float *ao_out, int y0, int y1)

DAO_DENOISE_SIMD_PROTO(generic);
DAO_DENOISE_SIMD_PROTO(sse41);
DAO_DENOISE_SIMD_PROTO(avx2);
DAO_DENOISE_SIMD_PROTO(avx512);

/*
 * Seed 004's separable cross-bilateral blur: Gaussian in pixels (its taps
 * equalised over the noise tile's period, denoise_bilateral.c) times a
 * depth test; the test compares each tap with the plane of the centre pixel
 * (from its normal), so slopes are not cut.  The horizontal pass writes
 * `tmp`; the vertical pass reads it.  Rows [y0, y1) of each pass.
 */
void dao_denoise_bilateral_h(const struct dao_denoise_setup *s, const float *z, const float *n,
			     const float *ao_in, float *tmp, int y0, int y1);
void dao_denoise_bilateral_v(const struct dao_denoise_setup *s, const float *z, const float *n,
			     const float *tmp, float *ao_out, int y0, int y1);

#endif
