/* SPDX-License-Identifier: MIT */
#ifndef DAO_KERNELS_NOISE_H
#define DAO_KERNELS_NOISE_H

#include <math.h>
#include <stdint.h>

static inline float dao_fract(float x)
{
	return x - floorf(x);
}

/*
 * Interleaved gradient noise (Jimenez, "Next Generation Post Processing in
 * Call of Duty: Advanced Warfare", 2014): fract(52.98 fract(0.0671 x + 0.00584 y)),
 * with the pixel shifted by 5.588 per frame so the pattern moves over time.
 */
static inline float dao_ign(int x, int y, uint32_t frame)
{
	float fx = (float)x + 5.588238f * (float)(frame & 63u);
	float fy = (float)y + 5.588238f * (float)(frame & 63u);
	return dao_fract(52.9829189f * dao_fract(0.06711056f * fx + 0.00583715f * fy));
}

/* Index of (x, y) along a Hilbert curve over a 64 x 64 tile. */
static inline uint32_t dao_hilbert64(uint32_t x, uint32_t y)
{
	uint32_t d = 0;
	for (uint32_t s = 32; s > 0; s >>= 1) {
		uint32_t rx = (x & s) > 0, ry = (y & s) > 0;
		d += s * s * ((3 * rx) ^ ry);
		if (ry == 0) {
			if (rx == 1) {
				x = s - 1 - x;
				y = s - 1 - y;
			}
			uint32_t t = x;
			x = y;
			y = t;
		}
	}
	return d;
}

/*
 * R2 sequence (Roberts 2018, generalised golden ratio 1.3247...) along a
 * Hilbert curve (as XeGTAO): two well-spread noise values per pixel.
 */
static inline void dao_r2(int x, int y, uint32_t frame, float *n0, float *n1)
{
	uint32_t i = dao_hilbert64((uint32_t)x & 63u, (uint32_t)y & 63u) + 288u * (frame & 63u);
	double a = 0.5 + 0.7548776662466927 * (double)i, b = 0.5 + 0.5698402909980532 * (double)i;
	*n0 = (float)(a - floor(a));
	*n1 = (float)(b - floor(b));
}

/* Bayer's 4 x 4 ordered-dither index: neighbours are as far apart in value as possible. */
static inline uint32_t dao_bayer4(uint32_t x, uint32_t y)
{
	static const uint8_t m[16] = { 0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5 };
	return m[(y & 3u) * 4u + (x & 3u)];
}

/*
 * The 4 x 4 tile noise: the slice rotation n0 is stratified, (i + 1/2) / 16
 * with i the Bayer index (so every 4 x 4 block sees 16 evenly spaced
 * rotations, neighbours far apart), and the step jitter n1 is the golden
 * ratio sequence over i (well spread and unrelated to n0's order).  Each
 * frame shifts both by the R2 offsets, so temporal accumulation sees new
 * values.  Only (x mod 4, y mod 4) matters: the optimised GTAO gives every
 * pixel of one tile phase along a row the same directions and steps.
 */
static inline void dao_tile_noise(int x, int y, uint32_t frame, float *n0, float *n1)
{
	uint32_t i = dao_bayer4((uint32_t)x, (uint32_t)y), f = frame & 63u;
	double a = ((double)i + 0.5) / 16.0 + 0.7548776662466927 * (double)f;
	double b = 0.5 + 0.6180339887498949 * (double)i + 0.5698402909980532 * (double)f;
	*n0 = (float)(a - floor(a));
	*n1 = (float)(b - floor(b));
}

#endif
