/* SPDX-License-Identifier: MIT */
/*
 * The AO algorithms besides GTAO, for comparison (README.md, "Algorithms").
 * Scalar, plain C: they are their own reference.  Same frame setup, per-pixel
 * noise and row bands as GTAO; z in metres (0 = no data), n the
 * view-space normals, ao the visibility out (1 = open).
 */
#ifndef DAO_KERNELS_AO_VARIANTS_H
#define DAO_KERNELS_AO_VARIANTS_H

#include <depthao/params.h>

#include "kernels/gtao.h"

#define DAO_SSAO_MAX_SAMPLES 128

/* Per-frame constants of the variants (derived from the params once). */
struct dao_variant_setup {
	const struct dao_gtao_setup *g;
	float strength;
	float tan_bias;               /* HBAO: tan of the tangent bias angle */
	float ssao_min, ssao_max;
	int ssao_samples;             /* 2 x slices x steps (GTAO's sample budget) */
	float ssao_kernel[DAO_SSAO_MAX_SAMPLES][3]; /* unit hemisphere (z up), denser at the centre */
	float edl_radius;
	float vbao_thickness;
	/* vbao: each occluder's thickness in metres (>= 0), one per pixel (w x h),
	 * read at the sample's taps as its depth is; NULL: vbao_thickness
	 * everywhere.  The SIMD kernel reads it from pl->thick (gtao_planes.h). */
	const float *thickness;
};

void dao_variant_setup_init(struct dao_variant_setup *v, const struct dao_gtao_setup *g,
			    const struct dao_params *p);

/* HBAO; with tile noise a pixel searches its block's radius: the SIMD
 * kernel's taps (kernels/hbao_tile.inc.c), its farthest pixel's radius on
 * the grid of dao_gtao_quantize_radius. */
void dao_hbao_ref(const struct dao_variant_setup *v, const float *z, const float *n, float *ao,
		  int y0, int y1);
void dao_ssao_ref(const struct dao_variant_setup *v, const float *z, const float *n, float *ao,
		  int y0, int y1);
/*
 * Visibility bitmask AO (Therrien, Levesque, Gilet 2023): per slice a mask
 * of DAO_VBAO_SECTORS sectors over the normal's hemisphere; each sample
 * occludes the sectors between the angle of its front and of its back,
 * assumed vbao_thickness (or the thickness plane's value there) behind it,
 * so light passes behind thin objects.  With tile noise a pixel searches
 * its block's radius, as dao_gtao_ref does (the SIMD kernel's taps).
 * The free sectors are weighted by the cosine-weighted slice measure (the
 * paper counts them uniformly).
 */
#define DAO_VBAO_SECTORS 32

/* Part of GTAO's radius widening: sectors cover between samples, horizons do not. */
#ifndef DAO_VBAO_RADIUS_REACH
#define DAO_VBAO_RADIUS_REACH 0.6f
#endif

/* How far a sample may lie from the pixel and occlude, m: samples reach GTAO's
 * widened radius, but occlude only within the true one (widened less). */
static inline float dao_vbao_radius(const struct dao_gtao_setup *s)
{
	return s->search_radius / (1.0f + DAO_GTAO_RADIUS_REACH / (float)s->steps) *
	       (1.0f + DAO_VBAO_RADIUS_REACH / (float)s->steps);
}
void dao_vbao_ref(const struct dao_variant_setup *v, const float *z, const float *n, float *ao,
		  int y0, int y1);
void dao_edl_ref(const struct dao_variant_setup *v, const float *z, float *ao, int y0, int y1);

#endif
