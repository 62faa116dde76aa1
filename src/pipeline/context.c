/* SPDX-License-Identifier: MIT */
/*
 * The AO context (<depthao/context.h>; its state: context_internal.h): owns
 * the working planes and runs the per-frame pipeline
 *   decode (+ temporal depth filter) -> prefilter -> normals -> GTAO ->
 *   denoise (+ temporal AO accumulation) -> output / shade.
 * Every stage works on row bands [y0, y1) of float planes.
 *
 * Two histories serve streams, both per pixel and exponential: the depth's
 * (depth-temporal, pipeline/temporal_depth.h: 1/z before the prefilter, so
 * the still parts of a scene converge to a smooth surface) and the AO's
 * (temporal: the output, so the noise pattern, which turns with the frame
 * index, averages out).  Both continue only while frames follow each other:
 * frame_index one to DAO_TEMPORAL_MAX_GAP past the last one; the same index,
 * a step back (a seek, a loop), a larger jump, new parameters they depend on
 * or dao_context_reset() start them over.
 *
 * This file: the context's life (creation, the parameters and the buffers
 * they need, reset, the poses given).  A frame's way through the stages:
 * context_frame.c; what is handed out after it: context_outputs.c.
 */
#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/error_internal.h"
#include "core/planes_alloc.h"
#include "core/threadpool.h"
#include "kernels/thickness.h"
#include "params/params_abi.h"
#include "pipeline/context_internal.h"
#include "simd/cpu_internal.h"

/* The kernel set of ctx->params, resolved once per parameter change (not per frame). */
static void use_kernels(struct dao_context *ctx)
{
	ctx->simd = dao_simd_resolve(ctx->params.simd);
	dao_kernels_select(&ctx->kernels, ctx->simd);
}

/* Worker threads for a `threads` parameter (0 = every available CPU). */
static int resolve_threads(int threads)
{
	return threads > 0 ? threads : dao_cpu_count();
}

/* Rejects a kernel set this CPU or build cannot run. */
static int check_simd(int simd, struct dao_error *err)
{
	if (dao_simd_supported((enum dao_simd)simd))
		return 0;
	char list[128] = "";
	for (int i = 0; i < DAO_SIMD_COUNT; i++)
		if (dao_simd_supported((enum dao_simd)i)) {
			strcat(list, list[0] ? ", " : "");
			strcat(list, dao_simd_name((enum dao_simd)i));
		}
	return dao_error_set(err, -ENOTSUP, "simd=%s: this CPU or build cannot run it (available: %s)",
			     dao_simd_name((enum dao_simd)simd), list);
}

static int make_pool(struct dao_context *ctx, int threads, struct dao_error *err)
{
	struct dao_pool *pool;
	int r = dao_pool_create(&pool, resolve_threads(threads));
	if (r)
		return dao_error_set(err, r, "cannot start %d worker threads: %s",
				     resolve_threads(threads), dao_strerror(r));
	/* the tile kernels' tables, one set per thread, here and not on the threads' stacks */
	struct dao_tile_scratch *sc = malloc((size_t)dao_pool_threads(pool) * sizeof *sc);
	if (!sc) {
		dao_pool_destroy(pool);
		return dao_error_set(err, -ENOMEM, "out of memory for %d threads' scratch",
				     resolve_threads(threads));
	}
	dao_pool_destroy(ctx->pool);
	free(ctx->tile_scratch);
	ctx->tile_scratch = sc;
	ctx->pool = pool;
	ctx->pool_threads = threads;
	return 0;
}

/* The buffers `p` needs beyond the planes every context has (allocated here,
 * never per frame; what is there already is kept). */
static int ensure_buffers(struct dao_context *ctx, const struct dao_params *p,
			  struct dao_error *err)
{
	const int w = (int)ctx->cam.width, h = (int)ctx->cam.height;
	if (p->prefilter == DAO_PREFILTER_DOMAIN && ctx->dt_threads < dao_pool_threads(ctx->pool)) {
		const size_t per = dao_domain_scratch_floats(w, h);
		float *s = malloc((size_t)dao_pool_threads(ctx->pool) * per * sizeof(float));
		if (!s)
			return dao_error_set(err, -ENOMEM, "out of memory for the domain prefilter");
		free(ctx->dt_scratch);
		ctx->dt_scratch = s;
		ctx->dt_threads = dao_pool_threads(ctx->pool);
		ctx->dt_thread_floats = per;
	}
	if (p->algorithm == DAO_ALGORITHM_VBAO && p->vbao_thickness_mode == DAO_VBAO_THICKNESS_IMAGE &&
	    ((!ctx->thick && !(ctx->thick = malloc(ctx->npix * sizeof(float)))) ||
	     (!ctx->thick_z && !(ctx->thick_z = malloc(ctx->npix * sizeof(float)))) ||
	     dao_gtao_planes_init_thickness(&ctx->planes) < 0))
		return dao_error_set(err, -ENOMEM, "out of memory for the thickness plane");
	if (p->algorithm == DAO_ALGORITHM_VBAO && p->vbao_thickness_mode == DAO_VBAO_THICKNESS_IMAGE &&
	    ctx->thick_slots < dao_pool_threads(ctx->pool)) {
		const size_t per = dao_thickness_cols_scratch(h);
		float *s = malloc((size_t)dao_pool_threads(ctx->pool) * per * sizeof(float));
		if (!s)
			return dao_error_set(err, -ENOMEM, "out of memory for the thickness plane");
		free(ctx->thick_scratch);
		ctx->thick_scratch = s;
		ctx->thick_slots = dao_pool_threads(ctx->pool);
	}
	if (p->depth_temporal_motion != DAO_DEPTH_MOTION_OFF && !ctx->motion_mem) {
		dao_icp_setup_default(&ctx->icp);
		const size_t sf = dao_icp_scratch_floats(&ctx->icp, w, h);
		/* scratch, 1/z, then the count and age bytes (rounded to floats) */
		const size_t floats = sf + ctx->npix + (2 * ctx->npix + 3) / 4;
		if (ctx->npix > SIZE_MAX / 16 || !(ctx->motion_mem = malloc(floats * sizeof(float))))
			return dao_error_set(err, -ENOMEM, "out of memory for depth-temporal-motion");
		ctx->icp_scratch = ctx->motion_mem;
		ctx->motion_hist = ctx->motion_mem + sf;
		ctx->motion_count = (uint8_t *)(ctx->motion_hist + ctx->npix);
		ctx->motion_age = ctx->motion_count + ctx->npix;
	}
	if (p->depth_temporal_motion != DAO_DEPTH_MOTION_OFF && p->temporal > 0.0f &&
	    !ctx->ao_motion_mem) {
		if (!(ctx->ao_motion_mem = malloc(2 * ctx->npix * sizeof(float))))
			return dao_error_set(err, -ENOMEM, "out of memory for depth-temporal-motion");
		ctx->ao_motion_ao = ctx->ao_motion_mem;
		ctx->ao_motion_z = ctx->ao_motion_mem + ctx->npix;
	}
	if (p->depth_fill > 0 && !ctx->z_fill && !(ctx->z_fill = malloc(ctx->npix * sizeof(float))))
		return dao_error_set(err, -ENOMEM, "out of memory for the filled depth (depth-fill)");
	if (p->noise_model != DAO_NOISE_MODEL_FIXED && !ctx->have_noise_grid) {
		if (dao_noise_grid_init(&ctx->noise, w, h))
			return dao_error_set(err, -ENOMEM, "out of memory for the noise estimate");
		ctx->noise_cells = malloc(2 * (size_t)ctx->noise.cw * ctx->noise.ch * sizeof(float));
		if (!ctx->noise_cells || dao_noise_reuse_init(&ctx->noise_reuse, &ctx->noise)) {
			dao_noise_grid_free(&ctx->noise);
			free(ctx->noise_cells);
			ctx->noise_cells = NULL;
			return dao_error_set(err, -ENOMEM, "out of memory for the noise estimate");
		}
		ctx->have_noise_grid = 1;
	}
	return 0;
}

int dao_context_create(struct dao_context **out, const struct dao_camera *cam,
		       const struct dao_params *params, struct dao_error *err)
{
	if (!out)
		return dao_error_set(err, -EINVAL, "context output pointer is NULL");
	*out = NULL;
	if (!cam)
		return dao_error_set(err, -EINVAL, "camera is NULL");
	/* re-validate the camera: it is a plain struct the caller may have filled */
	struct dao_camera checked;
	int r = dao_camera_from_intrinsics(&checked, cam->width, cam->height, cam->fx, cam->fy,
					   cam->cx, cam->cy, err);
	if (r)
		return r;
	struct dao_params p;
	if (params) {
		r = dao_params_validate(params, err);
		if (r)
			return r;
		dao_params_import(&p, params, NULL); /* the caller's struct may be older */
	} else {
		dao_params_init(&p, DAO_QUALITY_DEFAULT);
	}

	r = check_simd(p.simd, err);
	if (r)
		return r;
	struct dao_context *ctx = calloc(1, sizeof *ctx);
	if (!ctx)
		return dao_error_set(err, -ENOMEM, "out of memory for the context");
	ctx->cam = checked;
	ctx->params = p;
	use_kernels(ctx);
	dao_track_end(&ctx->track);
	ctx->npix = (size_t)checked.width * checked.height;
	const size_t per_pixel = PLANE_BYTES_PER_PIXEL;
	if (ctx->npix > SIZE_MAX / per_pixel) { /* a 32-bit size_t */
		free(ctx);
		return dao_error_set(err, -EOVERFLOW,
				     "%ux%u is too large for this build's address space "
				     "(%zu bytes per pixel); use a smaller frame",
				     checked.width, checked.height, per_pixel);
	}
	float *mem = dao_planes_alloc(ctx->npix * per_pixel);
	if (!mem) {
		free(ctx);
		return dao_error_set(err, -ENOMEM, "out of memory for %ux%u working planes",
				     checked.width, checked.height);
	}
	ctx->z_raw = mem;
	ctx->z_buf = mem + ctx->npix;
	ctx->n = mem + 2 * ctx->npix;
	ctx->ao_raw = mem + 5 * ctx->npix;
	ctx->ao_buf = mem + 6 * ctx->npix;
	ctx->tmp = mem + 7 * ctx->npix;
	ctx->hist_ao = mem + 8 * ctx->npix;
	ctx->hist_z = mem + 9 * ctx->npix;
	ctx->depth_hist = mem + 10 * ctx->npix;
	ctx->depth_count = (uint8_t *)(mem + 11 * ctx->npix);
	ctx->depth_age = ctx->depth_count + ctx->npix;
	ctx->row_range = malloc(2 * (size_t)checked.height * sizeof(float));
	if (!ctx->row_range ||
	    dao_gtao_planes_init(&ctx->planes, (int)checked.width, (int)checked.height,
				 p.max_screen_radius)) {
		dao_context_destroy(ctx);
		return dao_error_set(err, -ENOMEM, "out of memory for %ux%u working planes",
				     checked.width, checked.height);
	}
	ctx->r2_frame = UINT64_MAX;
	ctx->cmap_mode = -1;
	r = make_pool(ctx, p.threads, err);
	if (!r)
		r = ensure_buffers(ctx, &p, err);
	if (r) {
		dao_context_destroy(ctx);
		return r;
	}
	*out = ctx;
	return 0;
}

void dao_context_destroy(struct dao_context *ctx)
{
	if (!ctx)
		return;
	dao_pool_destroy(ctx->pool);
	free(ctx->tile_scratch);
	dao_planes_free(ctx->z_raw, ctx->npix * PLANE_BYTES_PER_PIXEL);
	dao_gtao_planes_free(&ctx->planes);
	free(ctx->bent);
	free(ctx->thick);
	free(ctx->thick_scratch);
	free(ctx->thick_z);
	free(ctx->z_fill);
	free(ctx->row_range);
	free(ctx->dt_scratch);
	free(ctx->motion_mem);
	free(ctx->ao_motion_mem);
	if (ctx->have_noise_grid)
		dao_noise_grid_free(&ctx->noise);
	free(ctx->noise_cells);
	dao_noise_reuse_free(&ctx->noise_reuse);
	free(ctx);
}

int dao_context_set_params(struct dao_context *ctx, const struct dao_params *caller,
			   struct dao_error *err)
{
	if (!ctx || !caller)
		return dao_error_set(err, -EINVAL, "context or parameters are NULL");
	int r = dao_params_validate(caller, err);
	if (r)
		return r;
	struct dao_params full; /* the caller's struct may be older */
	dao_params_import(&full, caller, NULL);
	const struct dao_params *params = &full;
	r = check_simd(params->simd, err);
	if (r)
		return r;
	if (!dao_gtao_planes_fit(&ctx->planes, params->max_screen_radius)) {
		/* a larger max-screen-radius needs wider padding of the phase plane */
		struct dao_gtao_planes pl;
		if (dao_gtao_planes_init(&pl, (int)ctx->cam.width, (int)ctx->cam.height,
					 params->max_screen_radius))
			return dao_error_set(err, -ENOMEM, "out of memory for max-screen-radius %g",
					     (double)params->max_screen_radius);
		dao_gtao_planes_free(&ctx->planes);
		ctx->planes = pl;
	}
	if (params->threads != ctx->pool_threads) {
		r = make_pool(ctx, params->threads, err);
		if (r)
			return r;
	}
	/* new settings: the AO history no longer matches; the depth history
	 * only depends on the depth range and its own switch */
	if (params->depth_min != ctx->params.depth_min || params->depth_max != ctx->params.depth_max ||
	    (params->depth_temporal > 0.0f) != (ctx->params.depth_temporal > 0.0f))
		ctx->depth_hist_valid = 0;
	r = ensure_buffers(ctx, params, err);
	if (r)
		return r;
	ctx->params = *params;
	use_kernels(ctx);
	ctx->hist_valid = 0;
	dao_noise_reuse_restart(&ctx->noise_reuse);
	/* the motion no longer followed: the track ends now, so that switching it on
	 * again, even before the next frame, starts a new one */
	if (!dao_track_follows(params))
		dao_track_end(&ctx->track);
	return 0;
}

void dao_context_reset(struct dao_context *ctx)
{
	if (!ctx)
		return;
	ctx->hist_valid = 0;
	ctx->depth_hist_valid = 0;
	dao_noise_reuse_restart(&ctx->noise_reuse);
	dao_pose_prior_clear(&ctx->poses);
	dao_track_end(&ctx->track);
}

int dao_context_set_pose(struct dao_context *ctx, const double rotation[4],
			 const double translation[3], struct dao_error *err)
{
	if (!ctx)
		return dao_error_set(err, -EINVAL, "context is NULL");
	return dao_pose_prior_set(&ctx->poses, rotation, translation, err);
}

int dao_context_get_params_sized(const struct dao_context *ctx, struct dao_params *out,
				 size_t size)
{
	if (!ctx || !out || size < DAO_PARAMS_SIZE_FIRST)
		return -EINVAL;
	if (size > sizeof(*out))
		size = sizeof(*out);
	memcpy(out, &ctx->params, size);
	out->size = (uint32_t)size;
	return 0;
}

const struct dao_camera *dao_context_camera(const struct dao_context *ctx)
{
	return &ctx->cam;
}
