/* SPDX-License-Identifier: MIT */
/*
 * The AO context's state (struct dao_context), shared by the three files
 * that make up <depthao/context.h>: context.c (its life: creation, the
 * parameters and their buffers, reset, the poses given), context_frame.c
 * (a frame through the pipeline's stages) and context_outputs.c (the shaded
 * image, and the planes and figures handed out after a frame).
 */
#ifndef DAO_PIPELINE_CONTEXT_INTERNAL_H
#define DAO_PIPELINE_CONTEXT_INTERNAL_H

#include <stddef.h>
#include <stdint.h>

#include <depthao/context.h>

#include "core/clock.h"
#include "depth/noise_estimate.h"
#include "depth/noise_reuse.h"
#include "kernels/gtao.h"
#include "kernels/gtao_planes.h"
#include "motion/icp.h"
#include "motion/pose_prior.h"
#include "motion/pose_track.h"
#include "pipeline/kernels.h"
#include "shade/colormap.h"
#include "shade/shade.h"

/* the working planes in one block: 1 + 1 + 3 + 1 + 1 + 1 + 2 + 1 planes of floats, then
 * two of bytes */
#define PLANE_BYTES_PER_PIXEL (11 * sizeof(float) + 2)

struct dao_context {
	struct dao_camera cam;
	struct dao_params params;
	size_t npix;
	float *z_raw;   /* decoded depth, m */
	float *z;       /* prefiltered depth, m (aliases z_raw when no prefilter) */
	float *z_buf;   /* storage for the prefiltered plane */
	float *n;       /* normals, 3 per pixel */
	float *ao_raw;  /* GTAO output */
	float *ao;      /* after denoise (aliases ao_raw when none) */
	float *ao_buf;  /* storage for the denoised plane */
	float *tmp;     /* scratch of the separable denoise */
	float *bent;    /* bent normals, made on request (dao_context_get_bent_normals) */
	float *thick;   /* VBAO: thickness estimated from the image, m (made when first needed) */
	float *thick_scratch; /* ... its column pass's, one per pool thread */
	float *thick_z; /* ... the depth its passes read: dropouts filled (dao_thickness_fill_rows) */
	float *z_fill;  /* depth-fill > 0: ctx->z with its one-surface holes filled, the depth
			 * output's (dao_context_get_depth); nothing else reads it */
	int have_fill;  /* z_fill holds the last frame's */
	int thick_slots;
	float *row_range; /* per row: nearest and farthest depth (shading's automatic range) */
	uint64_t last_frame_index;
	int have_index;     /* last_frame_index is that of a frame processed to the end */
	float *hist_ao; /* temporal accumulation: the last output ... */
	float *hist_z;  /* ... and the depth it was computed for */
	int hist_valid;
	float *depth_hist;      /* temporal depth filter: filtered 1/z ... */
	uint8_t *depth_count;   /* ... samples in it, frames since the pixel had data */
	uint8_t *depth_age;
	int depth_hist_valid;
	/* depth-temporal-motion=icp: the camera's motion (motion/icp.h) and the
	 * history's second planes (motion/reproject.h); one block, motion_mem,
	 * of the estimate's scratch and the planes, whose pointers swap with
	 * depth_hist, depth_count and depth_age */
	struct dao_icp_setup icp;
	float *motion_mem, *icp_scratch;
	float *motion_hist;
	uint8_t *motion_count, *motion_age;
	struct dao_icp_result motion; /* the last frame's estimate */
	int motion_ran;               /* ... made for the last frame */
	int motion_applied;           /* ... and the history carried by it */
	/* ... and with temporal > 0 the AO history's second planes
	 * (motion/ao_reproject.h), which swap with hist_ao and hist_z */
	float *ao_motion_mem, *ao_motion_ao, *ao_motion_z;
	int motion_origin;            /* ... enum dao_motion_origin */
	struct dao_pose_prior poses;  /* dao_context_set_pose (motion/pose_prior.h) */
	struct dao_pose_track track;  /* dao_context_pose_track (motion/pose_track.h) */
	struct dao_gtao_planes planes; /* 1/z of the filtered depth for the optimised GTAO */
	float r2_tile[2 * 4096];
	uint64_t r2_frame; /* frame index mod 64 (R2 repeats) r2_tile holds, or UINT64_MAX */
	int have_frame;
	int depth_only;    /* the last frame ran with algorithm=none: no normals, no AO */
	float depth_unit;  /* metres per count of the last frame, 0 for float input */
	struct dao_colormap cmap;
	int cmap_mode;
	struct dao_pool *pool;
	int pool_threads;  /* params.threads the pool was made for */
	struct dao_tile_scratch *tile_scratch; /* one per pool thread (the tile kernels') */
	enum dao_simd simd;        /* params.simd resolved (AUTO: this CPU's best) ... */
	struct dao_kernels kernels; /* ... and its kernels, chosen when the parameters change */
	struct dao_timings times;
	/* prefilter=domain: one scratch per pool thread; the pool hands the
	 * threads bands of a pass's strips */
	float *dt_scratch;
	int dt_threads;
	size_t dt_thread_floats;
	/* noise-model=auto */
	struct dao_noise_grid noise;
	int have_noise_grid;
	float *noise_cells; /* per cell: the range noise, 1 / sigma_s */
	struct dao_noise_info noise_info;
	struct dao_noise_reuse noise_reuse; /* noise-interval: the measurement kept */
};

/* The clock of the stage timings, ms. */
static inline double dao_ctx_now_ms(void)
{
	return (double)dao_mono_ns() * 1e-6;
}

/* v rounded to the nearest integer, ties to even (as lrintf), for 0 <= v < 2^22:
 * adding 1.5 * 2^23 leaves no fraction bits; vectorises, unlike lrintf */
static inline int32_t dao_round_even(float v)
{
	return (int32_t)((v + 12582912.0f) - 12582912.0f);
}

/* context_frame.c: the R2 noise tile of frame_index into the GTAO setup g
 * (the bent normals redo the last frame's) */
void dao_ctx_use_r2_tile(struct dao_context *ctx, struct dao_gtao_setup *g, uint64_t frame_index);

/* context_outputs.c: the shaded image's settings and frame check (the fused
 * shading of dao_context_process_shaded and dao_context_shade), and the
 * error where algorithm=none left nothing to shade */
void dao_ctx_shade_setup(struct dao_context *ctx, struct dao_shade_setup *ss);
int dao_ctx_shade_check(const struct dao_context *ctx, const struct dao_frame *out,
			struct dao_error *err);
int dao_ctx_no_shading(struct dao_error *err);

#endif
