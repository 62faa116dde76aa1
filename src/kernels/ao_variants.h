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
	/* vbao: a sample's weight saturate(|D| mul + add) falls from 1 to 0 over
	 * DAO_VBAO_FALLOFF_SHARE of GTAO's falloff band, centred where GTAO's is;
	 * vbao_radius: where it reaches 0, m */
	float vbao_fall_mul, vbao_fall_add, vbao_radius;
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
 * its block's radius, as dao_gtao_ref does (the SIMD kernel's taps).  A
 * sample weighs as GTAO's do (a falloff): the cosines of its front and back
 * move towards the hemisphere's edge's by the weight, as GTAO moves a
 * horizon, so with infinitely thick occluders and the same falloff the
 * mask's open part is GTAO's horizon, up to the sectors.
 * The free sectors are weighted by the cosine-weighted slice measure (the
 * paper counts them uniformly).
 */
#define DAO_VBAO_SECTORS 32

/*
 * VBAO's falloff band, a share of GTAO's (p->falloff R_eff wide, centred on
 * the widened radius R_eff).  A hard cut at the radius over-occluded where a
 * concave corner's occlusion fades out (room corner, clean, 64 rays: MAE
 * 0.0201 against GTAO's 0.0172); GTAO's whole band (share 1) closes that
 * (0.0174) but under-occludes the floor-and-wall creases behind the poles
 * (pole-widths 0.0193 -> 0.0218), where the sparse samples of a floor seen
 * at a grazing angle already miss its highest point, as GTAO's do.  3/4 of
 * it: room corner 0.0175, pole-widths 0.0211.  README.md, "Thickness from
 * the image", has every share measured; chosen on the tune set.
 */
#ifndef DAO_VBAO_FALLOFF_SHARE
#define DAO_VBAO_FALLOFF_SHARE 0.75f
#endif

void dao_vbao_ref(const struct dao_variant_setup *v, const float *z, const float *n, float *ao,
		  int y0, int y1);
void dao_edl_ref(const struct dao_variant_setup *v, const float *z, float *ao, int y0, int y1);

#endif
