/* SPDX-License-Identifier: MIT */
#ifndef DAO_KERNELS_GTAO_H
#define DAO_KERNELS_GTAO_H

#include <math.h>
#include <stdint.h>
#include <string.h>

#include <depthao/camera.h>
#include <depthao/params.h>

#include "core/math_util.h"

/* Everything the GTAO kernels need per frame, derived once from camera and params. */
struct dao_gtao_setup {
	int width, height;
	int x_begin, x_end;        /* columns the optimised kernels compute (a strip; 0..width) */
	float ax, ay, bx, by;      /* UvToViewParams */
	float focal;               /* pixels per metre at z = 1 (mean of fx, fy) */
	float search_radius;       /* where the falloff weight reaches 0, m */
	float falloff_mul, falloff_add; /* weight = saturate(dist * mul + add) */
	float decay;               /* share of the horizon kept when a later sample is lower */
	float max_r_px, min_r_px;
	float power;               /* sample distribution power */
	int slices, steps;
	int noise;                 /* enum dao_noise */
	uint32_t frame;
	const float *r2_tile;      /* R2 noise of this frame over a 64 x 64 tile: n0[4096], n1[4096] */
	float final_power, albedo, invalid_value;
};

/*
 * With K samples per side the largest sampled horizon is on average below the
 * true one (peaks fall between samples, about half a sample spacing R/K
 * short), so GTAO under-occludes; searching a little beyond R compensates:
 * R_eff = R (1 + DAO_GTAO_RADIUS_REACH / K).  Tuned against the ray-traced
 * ground truth (`depthao eval`), like XeGTAO's radius multiplier.
 */
#define DAO_GTAO_RADIUS_REACH 1.2f

/* The radius the kernels search for a world radius R and K steps per side. */
static inline float dao_gtao_effective_radius(float R, int steps)
{
	return R * (1.0f + DAO_GTAO_RADIUS_REACH / (float)steps);
}

/* Screen direction of slice sl for the rotation noise n0 (every GTAO-style
 * kernel computes it with this very expression, so all agree bit for bit). */
static inline void dao_gtao_slice_dir(const struct dao_gtao_setup *s, int sl, float n0,
				      float *dx, float *dy)
{
	const float phi = ((float)sl + n0) * DAO_PI_F / (float)s->slices;
	*dx = cosf(phi);
	*dy = sinf(phi);
}

/* Position of step i along a side, in [0, 1) of the radius, for the jitter n1. */
static inline float dao_gtao_step_t(const struct dao_gtao_setup *s, int i, float n1)
{
	return powf(((float)i + n1) / (float)s->steps, s->power);
}

void dao_gtao_setup_init(struct dao_gtao_setup *s, const struct dao_camera *cam,
			 const struct dao_params *p, uint64_t frame_index);

/*
 * Scalar reference GTAO (Jimenez et al. 2016) over rows [y0, y1): the
 * correctness oracle for every optimised kernel.
 * z: metres (0 = no data), n: 3 floats per pixel, ao: visibility out.
 */
void dao_gtao_ref(const struct dao_gtao_setup *s, const float *z, const float *n, float *ao,
		  int y0, int y1);

/*
 * Bent normals (unit, view space; 0 where there is no depth) from the same
 * horizons as dao_gtao_ref: per slice the direction halfway between its two
 * horizons, weighted like the slice integral.
 */
void dao_gtao_bent_ref(const struct dao_gtao_setup *s, const float *z, const float *n, float *bent,
		       int y0, int y1);

/*
 * With tile noise the pixels of one tile phase along a row form blocks of
 * DAO_GTAO_BLOCK (columns 64 b + a + 4 k, k = 0..15) that search with one
 * radius in pixels, the block's largest (its nearest depth): their samples
 * then lie at the same offsets, which the optimised kernel reads with
 * contiguous loads instead of gathers.  Farther pixels of a block place some
 * samples beyond their own radius, where the falloff weight is 0.
 */
#define DAO_GTAO_BLOCK 16
#define DAO_GTAO_BLOCK_SPAN (4 * DAO_GTAO_BLOCK) /* columns a block spans */

/* The search radius in pixels (before max_r_px) of the block of pixel (x, y);
 * z: metres (0 = no data). */
float dao_gtao_block_radius(const struct dao_gtao_setup *s, const float *z, int x, int y);

/* The largest 1/z of the block of pixel (x, y), 0 when none has depth (1/z as
 * the optimised kernels store it, so both round alike). */
float dao_gtao_block_izmax(const struct dao_gtao_setup *s, const float *z, int x, int y);

/*
 * A block radius rounded up to the grid 2^(k/8) (at most 9 % larger, 4.5 % on
 * average), so that neighbouring blocks of a row mostly share one radius
 * and with it the table of sample taps the optimised kernel makes per radius.
 */
static inline float dao_gtao_quantize_radius(float r)
{
	/* 2^(k/8), k = 0..8 */
	static const float grid[9] = {
		1.000000000e+00f, 1.090507733e+00f, 1.189207115e+00f, 1.296839555e+00f,
		1.414213562e+00f, 1.542210825e+00f, 1.681792831e+00f, 1.834008086e+00f,
		2.000000000e+00f,
	};
	if (!(r >= 1.1754944e-38f) || r > 1e30f)
		return r; /* 0, subnormal or huge: left alone (no such radius is searched) */
	/* r = m 2^e with m in [1, 2): the grid point at or above m, times 2^e */
	uint32_t bits, gb;
	memcpy(&bits, &r, sizeof bits);
	const uint32_t e = bits & 0x7f800000u;
	const uint32_t mb = (bits & 0x007fffffu) | 0x3f800000u;
	float m;
	memcpy(&m, &mb, sizeof m);
	int k = 0; /* counted, not searched: no branch on the data */
	for (int i = 0; i < 8; i++)
		k += grid[i] < m;
	memcpy(&gb, &grid[k], sizeof gb);
	gb += e - 0x3f800000u;
	float out;
	memcpy(&out, &gb, sizeof out);
	return out;
}

/* Fills tile[0..8191] with this frame's R2 noise pairs over a 64 x 64 tile. */
void dao_gtao_fill_r2_tile(float *tile, uint64_t frame_index);

/* The per-pixel noise pair (slice rotation, step jitter) in [0, 1). */
void dao_gtao_noise(const struct dao_gtao_setup *s, int x, int y, float *n0, float *n1);

/* Visibility post-processing shared by all kernels: final power, then multi-bounce. */
float dao_gtao_finish(const struct dao_gtao_setup *s, float vis);

#endif
