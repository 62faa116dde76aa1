/* SPDX-License-Identifier: MIT */
/*
 * The AO context: owns the working planes and runs the per-frame pipeline
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
 */
#include <errno.h>
#include <math.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <depthao/context.h>

#include "core/clock.h"
#include "core/error_internal.h"
#include "core/multiversion.h"
#include "core/planes_alloc.h"
#include "core/sized.h"
#include "core/math_util.h"
#include "denoise/denoise.h"
#include "depth/decode.h"
#include "depth/domain.h"
#include "depth/noise_estimate.h"
#include "depth/noise_reuse.h"
#include "depth/prefilter.h"
#include "kernels/ao_variants.h"
#include "kernels/depth_fill.h"
#include "kernels/thickness.h"
#include "kernels/gtao.h"
#include "kernels/gtao_planes.h"
#include "normals/normals.h"
#include "params/params_abi.h"
#include "pipeline/kernels.h"
#include "pipeline/temporal_depth.h"
#include "motion/icp.h"
#include "motion/pose_prior.h"
#include "motion/pose_track.h"
#include "motion/reproject.h"
#include "motion/ao_reproject.h"
#include "core/threadpool.h"
#include "shade/colormap.h"
#include "shade/shade.h"
#include "simd/cpu_internal.h"

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

/* The kernel set of ctx->params, resolved once per parameter change (not per frame). */
static void use_kernels(struct dao_context *ctx)
{
	ctx->simd = dao_simd_resolve(ctx->params.simd);
	dao_kernels_select(&ctx->kernels, ctx->simd);
}

static double now_ms(void)
{
	return (double)dao_mono_ns() * 1e-6;
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

static int check_depth(const struct dao_context *ctx, const struct dao_frame *depth,
		       struct dao_error *err)
{
	int r = dao_frame_check(depth, "depth input", ctx->cam.width, ctx->cam.height, err);
	if (r)
		return r;
	if (depth->format != DAO_PIXFMT_DEPTH16 && depth->format != DAO_PIXFMT_DEPTH_F32)
		return dao_error_set(err, -EINVAL,
				     "depth input: format %s is not depth16 or depth-f32",
				     dao_pixfmt_name(depth->format));
	if (depth->format == DAO_PIXFMT_DEPTH16 &&
	    (!isfinite(depth->depth_unit) || depth->depth_unit <= 0.0f || depth->depth_unit > 1.0f))
		return dao_error_set(err, -EINVAL,
				     "depth input: depth_unit %g must be in (0, 1] metres per count "
				     "(e.g. 0.001 for millimetres)", (double)depth->depth_unit);
	if ((depth->stride & (depth->format == DAO_PIXFMT_DEPTH16 ? 1 : 3)) != 0 &&
	    depth->height > 1)
		return dao_error_set(err, -EINVAL,
				     "depth input: stride %d is not a multiple of the sample size",
				     (int)depth->stride);
	return 0;
}

/* Copies caller normals, normalised and facing the camera; non-finite ones are rejected. */
static int load_normals(struct dao_context *ctx, const struct dao_frame *nf, struct dao_error *err)
{
	int r = dao_frame_check(nf, "normals input", ctx->cam.width, ctx->cam.height, err);
	if (r)
		return r;
	if (nf->format != DAO_PIXFMT_NORMAL_F32)
		return dao_error_set(err, -EINVAL, "normals input: format %s is not normal-f32",
				     dao_pixfmt_name(nf->format));
	const int w = (int)ctx->cam.width;
	for (int y = 0; y < (int)ctx->cam.height; y++) {
		const unsigned char *row = (const unsigned char *)nf->data + (size_t)y * nf->stride;
		for (int x = 0; x < w; x++) {
			size_t i = (size_t)y * w + x;
			float v[3];
			memcpy(v, row + 12 * (size_t)x, sizeof v);
			float *o = ctx->n + 3 * i;
			float zc = ctx->z[i];
			if (zc <= 0.0f) {
				o[0] = 0.0f, o[1] = 0.0f, o[2] = -1.0f;
				continue;
			}
			float len = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
			if (!isfinite(len) || len < 1e-6f)
				return dao_error_set(err, -EINVAL,
						     "normals input: pixel (%d, %d) has depth but its "
						     "normal is not a finite non-zero vector", x, y);
			double P[3];
			dao_camera_pixel_to_view(&ctx->cam, x, y, zc, P);
			if (v[0] * P[0] + v[1] * P[1] + v[2] * P[2] > 0.0f)
				len = -len;
			o[0] = v[0] / len, o[1] = v[1] / len, o[2] = v[2] / len;
		}
	}
	return 0;
}

static int check_ao_out(const struct dao_context *ctx, const struct dao_frame *ao,
			struct dao_error *err)
{
	int r = dao_frame_check(ao, "AO output", ctx->cam.width, ctx->cam.height, err);
	if (r)
		return r;
	if (ao->format != DAO_PIXFMT_GRAY_F32 && ao->format != DAO_PIXFMT_GRAY16 &&
	    ao->format != DAO_PIXFMT_GRAY8)
		return dao_error_set(err, -EINVAL,
				     "AO output: format %s is not gray-f32, gray16 or gray8",
				     dao_pixfmt_name(ao->format));
	return 0;
}


/* R2 noise: this frame's 64 x 64 tile (it repeats every 64 frames; kept until then). */
static void use_r2_tile(struct dao_context *ctx, struct dao_gtao_setup *g, uint64_t frame_index)
{
	if (ctx->params.noise != DAO_NOISE_R2)
		return;
	if (ctx->r2_frame != (frame_index & 63u)) {
		dao_gtao_fill_r2_tile(ctx->r2_tile, frame_index);
		ctx->r2_frame = frame_index & 63u;
	}
	g->r2_tile = ctx->r2_tile;
}

/* One frame's work, shared by the stage functions the pool runs on row bands. */
struct frame_job {
	struct dao_context *ctx;
	const struct dao_frame *depth;
	struct dao_frame *ao_out;
	int normal_radius;
	struct dao_gtao_setup gtao;
	struct dao_variant_setup variant; /* HBAO, SSAO, EDL, VBAO */
	int algorithm;
	struct dao_thickness_setup thickness; /* VBAO with its thickness from the image */
	const float *thick;                   /* ... its plane, NULL: vbao_thickness */
	const float *thick_z;                 /* ... the depth its passes read */
	struct dao_denoise_setup denoise;
	struct dao_prefilter_setup prefilter;
	int depth_temporal;  /* run the temporal depth filter */
	int temporal_in_decode; /* ... in stage_decode, on the rows just decoded */
	int depth_only;      /* algorithm=none: ao_out written by the stage that writes
			      * z_raw last, on its rows (depth_only_output) */
	struct dao_temporal_depth_setup depth_temporal_setup;
	struct dao_domain_pass dt_pass; /* the domain filter's pass being run */
	/* the output's time, summed over bands: stage_finish's, or algorithm=none's
	 * (depth_only_output, from stage_decode or stage_temporal_depth) */
	_Atomic uint64_t output_ns;
	const struct dao_frame *shade_out; /* dao_context_process_shaded's image, or NULL */
	struct dao_shade_setup shade;      /* ... its settings (shade_setup) */
	_Atomic uint64_t shade_ns;         /* stage_finish: the shading's time, summed over bands */
	struct dao_kernels k;  /* k.simd: the resolved kernel set */
};

/* v rounded to the nearest integer, ties to even (as lrintf), for 0 <= v < 2^22:
 * adding 1.5 * 2^23 leaves no fraction bits; vectorises, unlike lrintf */
static inline int32_t round_even(float v)
{
	return (int32_t)((v + 12582912.0f) - 12582912.0f);
}

/* dao_saturate as two plain selects, which the compiler turns into min/max
 * (the nested form stays a branch); NaN gives 0 as there */
static inline float sat01(float v)
{
	v = v > 0.0f ? v : 0.0f;
	return v < 1.0f ? v : 1.0f;
}

/* a pixel of the caller's AO image before its format: the AO plane's value
 * (src), or with no plane (algorithm=none) 1 where z has depth and `none`
 * elsewhere */
static inline float ao_value(const float *src, const float *z, float none, int x)
{
	return src ? sat01(src[x]) : z[x] > 0.0f ? 1.0f : none;
}

/*
 * Row y of the caller's AO image (ao_value); one loop per format, simple
 * enough for the compiler to vectorise (checked with -fopt-info-vec);
 * rounding to nearest-even like lrintf.  Inlined into each caller, where src
 * is known to be a plane or NULL.
 */
static inline __attribute__((always_inline)) void
ao_out_row(const struct dao_frame *out, int y, int w, const float *src, const float *z, float none)
{
	unsigned char *row = (unsigned char *)out->data + (size_t)y * out->stride;
	switch (out->format) {
	case DAO_PIXFMT_GRAY_F32:
		for (int x = 0; x < w; x++) {
			const float v = ao_value(src, z, none, x);
			memcpy(row + 4 * (size_t)x, &v, 4);
		}
		break;
	case DAO_PIXFMT_GRAY16:
		/* in chunks through an aligned buffer: the caller's rows need not be */
		for (int x0 = 0; x0 < w; x0 += 256) {
			uint16_t q[256];
			const int n = w - x0 < 256 ? w - x0 : 256;
			for (int x = 0; x < n; x++)
				q[x] = (uint16_t)round_even(ao_value(src, z, none, x0 + x) * 65535.0f);
			memcpy(row + 2 * (size_t)x0, q, 2 * (size_t)n);
		}
		break;
	default:
		for (int x = 0; x < w; x++)
			row[x] = (uint8_t)round_even(ao_value(src, z, none, x) * 255.0f);
		break;
	}
}

/*
 * algorithm=none: rows [y0, y1) of the caller's AO image as stage_output
 * writes a plane of visibility 1: 1 where z_raw has depth, invalid_value
 * (saturated) elsewhere.  No AO plane is written and read back.
 */
DAO_MULTIVERSION
static void depth_only_rows(const struct dao_context *c, const struct dao_frame *out, int y0,
			    int y1)
{
	const int w = (int)c->cam.width;
	const float none = sat01(c->params.invalid_value);
	for (int y = y0; y < y1; y++)
		ao_out_row(out, y, w, NULL, c->z_raw + (size_t)y * w, none);
}

/* algorithm=none with an AO image: its rows, while z_raw's are in the cache
 * (the decode's or the temporal depth filter's rows: whichever writes z_raw
 * last); timed as the output */
static void depth_only_output(struct frame_job *j, int y0, int y1)
{
	if (!j->depth_only || !j->ao_out)
		return;
	const uint64_t t = dao_mono_ns();
	depth_only_rows(j->ctx, j->ao_out, y0, y1);
	atomic_fetch_add_explicit(&j->output_ns, dao_mono_ns() - t, memory_order_relaxed);
}

/* 1/z rows of the filtered depth into the plane the optimised GTAO reads */
static void fill_inverse_depth(struct dao_context *c, const struct dao_kernels *k, int y0, int y1)
{
	k->planes_fill(&c->planes, c->z, c->params.noise == DAO_NOISE_TILE, y0, y1);
}

/* decoding, and on the same rows while they are in cache the temporal depth filter */
static void stage_decode(void *arg, int y0, int y1)
{
	struct frame_job *j = arg;
	struct dao_context *c = j->ctx;
	dao_decode_depth(j->depth, c->params.depth_min, c->params.depth_max, c->z_raw, y0, y1);
	if (j->temporal_in_decode)
		j->k.temporal_depth(&j->depth_temporal_setup, c->z_raw, c->depth_hist, c->depth_count,
				    c->depth_age, y0, y1);
	if (!j->depth_temporal || j->temporal_in_decode)
		depth_only_output(j, y0, y1);
}

/* the temporal depth filter on its own (after the noise measurement) */
static void stage_temporal_depth(void *arg, int y0, int y1)
{
	struct frame_job *j = arg;
	struct dao_context *c = j->ctx;
	j->k.temporal_depth(&j->depth_temporal_setup, c->z_raw, c->depth_hist, c->depth_count,
			    c->depth_age, y0, y1);
	depth_only_output(j, y0, y1);
}

static void stage_prefilter_h(void *arg, int y0, int y1)
{
	struct frame_job *j = arg;
	j->k.prefilter_h(&j->prefilter, j->ctx->z_raw, j->ctx->tmp, y0, y1);
}

static void stage_prefilter_v(void *arg, int y0, int y1)
{
	struct frame_job *j = arg;
	j->k.prefilter_v(&j->prefilter, j->ctx->tmp, j->ctx->z_buf, y0, y1);
}

/* Strips [a, b) of a domain pass in the thread's scratch, which stays in its
 * core's cache from one strip to the next. */
static void stage_domain(void *arg, int thread, int a, int b)
{
	struct frame_job *j = arg;
	const struct dao_domain_pass *p = &j->dt_pass;
	const int lane1 = b * DAO_DOMAIN_STRIP < p->lanes ? b * DAO_DOMAIN_STRIP : p->lanes;
	j->k.domain_pass(p, j->ctx->dt_scratch + (size_t)thread * j->ctx->dt_thread_floats,
			 a * DAO_DOMAIN_STRIP, lane1);
}

static void stage_noise_blocks(void *arg, int by0, int by1)
{
	struct frame_job *j = arg;
	dao_noise_blocks(&j->ctx->noise, j->ctx->z_raw, by0, by1);
}

/* the cells' medians, by rows of cells (1.4M instructions a 640x480 frame) */
static void stage_noise_cells(void *arg, int cy0, int cy1)
{
	struct frame_job *j = arg;
	dao_noise_cell_rows(&j->ctx->noise, cy0, cy1);
}

/* noise-interval: the cells the scene moved in, measured again */
static void stage_noise_moved(void *arg, int i0, int i1)
{
	struct frame_job *j = arg;
	for (int i = i0; i < i1; i++)
		dao_noise_reuse_measure_cell(&j->ctx->noise_reuse, &j->ctx->noise, j->ctx->z_raw, i);
}

static void stage_thickness_fill(void *arg, int y0, int y1)
{
	struct frame_job *j = arg;
	dao_thickness_fill_rows(&j->thickness, j->ctx->z, j->ctx->thick_z, y0, y1);
}

static void stage_thickness_rows(void *arg, int y0, int y1)
{
	struct frame_job *j = arg;
	dao_thickness_rows(&j->thickness, j->thick_z, j->ctx->thick, y0, y1);
}

/*
 * The thickness estimate's row pass needs the filtered depth of its rows
 * only, like the normals: it runs in their bands, and the estimate costs
 * one dispatch to the pool (the columns) instead of three.  Under load each
 * dispatch waits for both threads (docs/performance.md).
 */
static void stage_normals(void *arg, int y0, int y1)
{
	struct frame_job *j = arg;
	j->k.normals(&j->ctx->cam, j->ctx->z, j->normal_radius, j->ctx->n, y0, y1);
	if (j->k.simd != DAO_SIMD_REFERENCE)
		fill_inverse_depth(j->ctx, &j->k, y0, y1);
	if (j->thick)
		stage_thickness_rows(arg, y0, y1);
}

/*
 * Blocks of DAO_THICKNESS_COL_BLOCK columns, after every row: their columns
 * are then final, and vbao's optimised kernels get them split by phase, like
 * the depth, row by row as the pass finishes them (no third dispatch).  The
 * i-th block handed out is block i / 2 of the left half or of the right half
 * by turns, so that the threads work on blocks far apart: neighbouring blocks
 * share a cache line at their border in each row of the plane and of the
 * split (the rows are not aligned to them), and two threads that wrote them
 * side by side, sweeping the same rows at the same time, took the line from
 * each other in every row (1.6 ms of CPU a frame in the split, 2 threads).
 */
static void stage_thickness_cols(void *arg, int thread, int i0, int i1)
{
	struct frame_job *j = arg;
	struct dao_context *c = j->ctx;
	const int w = (int)c->cam.width;
	const int nblocks = (w + DAO_THICKNESS_COL_BLOCK - 1) / DAO_THICKNESS_COL_BLOCK;
	const int half = (nblocks + 1) / 2;
	float *scratch =
		c->thick_scratch + (size_t)thread * dao_thickness_cols_scratch((int)c->cam.height);
	for (int i = i0; i < i1; i++) {
		const int b = i & 1 ? half + i / 2 : i / 2;
		const int x0 = b * DAO_THICKNESS_COL_BLOCK;
		const int x1 = x0 + DAO_THICKNESS_COL_BLOCK < w ? x0 + DAO_THICKNESS_COL_BLOCK : w;
		dao_thickness_cols(&j->thickness, j->thick_z, c->thick, scratch,
				   j->k.simd != DAO_SIMD_REFERENCE ? &c->planes : NULL, x0, x1);
	}
}

static void stage_gtao(void *arg, int thread, int y0, int y1)
{
	struct frame_job *j = arg;
	struct dao_context *c = j->ctx;
	struct dao_tile_scratch *sc = &c->tile_scratch[thread];
	switch (j->algorithm) {
	case DAO_ALGORITHM_HBAO:
		j->k.hbao(&j->variant, c->z, &c->planes, c->n, c->ao_raw, y0, y1, sc);
		break;
	case DAO_ALGORITHM_SSAO: dao_ssao_ref(&j->variant, c->z, c->n, c->ao_raw, y0, y1); break;
	case DAO_ALGORITHM_EDL: dao_edl_ref(&j->variant, c->z, c->ao_raw, y0, y1); break;
	case DAO_ALGORITHM_VBAO:
		j->k.vbao(&j->variant, c->z, &c->planes, c->n, c->ao_raw, y0, y1, sc);
		break;
	default: j->k.gtao(&j->gtao, c->z, &c->planes, c->n, c->ao_raw, y0, y1, sc); break;
	}
}

/*
 * Wide images: the optimised GTAO in vertical strips, all rows of one strip
 * before the next, so the taps of neighbouring rows (up to max-screen-radius
 * away) stay in the core's cache; items are strip * height + row.  Strips are
 * at most GTAO_STRIP_MAX columns and of (nearly) equal width, whole blocks
 * each, so that the pool's bands cost about the same and no thread waits long
 * for the last one.
 */
#define GTAO_STRIP_MAX 512

static int gtao_strip_width(int w)
{
	const int strips = (w + GTAO_STRIP_MAX - 1) / GTAO_STRIP_MAX;
	const int groups = (w + DAO_GTAO_BLOCK_SPAN - 1) / DAO_GTAO_BLOCK_SPAN;
	return (groups + strips - 1) / strips * DAO_GTAO_BLOCK_SPAN;
}

static void stage_gtao_strips(void *arg, int thread, int i0, int i1)
{
	struct frame_job *j = arg;
	struct dao_context *c = j->ctx;
	const int h = (int)c->cam.height, w = (int)c->cam.width, sw = gtao_strip_width(w);
	while (i0 < i1) {
		int strip = i0 / h, y0 = i0 % h, y1 = y0 + (i1 - i0);
		if (y1 > h)
			y1 = h;
		struct dao_gtao_setup g = j->gtao;
		g.x_begin = strip * sw;
		g.x_end = g.x_begin + sw < w ? g.x_begin + sw : w;
		if (j->algorithm == DAO_ALGORITHM_VBAO) {
			struct dao_variant_setup v = j->variant;
			v.g = &g;
			j->k.vbao(&v, c->z, &c->planes, c->n, c->ao_raw, y0, y1,
				  &c->tile_scratch[thread]);
		} else if (j->algorithm == DAO_ALGORITHM_HBAO) {
			struct dao_variant_setup v = j->variant;
			v.g = &g;
			j->k.hbao(&v, c->z, &c->planes, c->n, c->ao_raw, y0, y1,
				  &c->tile_scratch[thread]);
		} else {
			j->k.gtao(&g, c->z, &c->planes, c->n, c->ao_raw, y0, y1,
				  &c->tile_scratch[thread]);
		}
		i0 += y1 - y0;
	}
}

static void stage_denoise_plane(void *arg, int y0, int y1)
{
	struct frame_job *j = arg;
	j->k.denoise_plane(&j->denoise, j->ctx->z, j->ctx->ao_raw, j->ctx->ao_buf, y0, y1);
}

static void stage_denoise_h(void *arg, int y0, int y1)
{
	struct frame_job *j = arg;
	dao_denoise_bilateral_h(&j->denoise, j->ctx->z, j->ctx->n, j->ctx->ao_raw, j->ctx->tmp,
				y0, y1);
}

static void stage_denoise_v(void *arg, int y0, int y1)
{
	struct frame_job *j = arg;
	dao_denoise_bilateral_v(&j->denoise, j->ctx->z, j->ctx->n, j->ctx->tmp, j->ctx->ao_buf,
				y0, y1);
}

/*
 * Temporal accumulation: an exponential history per pixel, out = (1 - a) cur
 * + a hist, dropped where the depth moved by more than temporal_reject of it
 * (something moved in or out: disocclusion).  The noise pattern changes with
 * the frame index, so a still scene converges instead of flickering.
 */
static void stage_temporal(void *arg, int y0, int y1)
{
	struct frame_job *j = arg;
	struct dao_context *c = j->ctx;
	const float a = c->params.temporal, reject = c->params.temporal_reject;
	const int w = (int)c->cam.width;
	for (size_t i = (size_t)y0 * w; i < (size_t)y1 * w; i++) {
		float z = c->z[i], hz = c->hist_z[i];
		if (!(z > 0.0f) && c->hist_valid)
			continue; /* a hole this frame: the pixel's history waits for its return */
		int keep = c->hist_valid && hz > 0.0f && fabsf(z - hz) <= reject * z;
		float out = keep ? (1.0f - a) * c->ao[i] + a * c->hist_ao[i] : c->ao[i];
		c->ao[i] = out;
		c->hist_ao[i] = out;
		/* the history's depth is averaged too: sensor noise alone then rarely trips it */
		c->hist_z[i] = keep ? (1.0f - a) * z + a * hz : z;
	}
}

/* Pixels without input depth are exactly invalid_value, whatever the filters did;
 * then the caller's output format. */
DAO_MULTIVERSION
static void stage_output(void *arg, int y0, int y1)
{
	struct frame_job *j = arg;
	struct dao_context *c = j->ctx;
	const int w = (int)c->cam.width;
	const float invalid = c->params.invalid_value;
	for (size_t i = (size_t)y0 * w; i < (size_t)y1 * w; i++)
		c->ao[i] = c->z_raw[i] > 0.0f ? c->ao[i] : invalid; /* a select: vectorises */
	struct dao_frame *out = j->ao_out;
	if (!out)
		return;
	for (int y = y0; y < y1; y++)
		ao_out_row(out, y, w, c->ao + (size_t)y * w, NULL, 0.0f);
}

/*
 * The AO's last steps on one band of rows, while the rows are in the core's
 * cache: the denoise's (last) pass, the temporal accumulation and the
 * output, each of which reads only the rows it writes once the denoise's
 * input is complete (the GTAO stage; the bilateral's horizontal pass).  One
 * dispatch to the pool instead of three, and the AO plane is not read back
 * from the shared cache twice (docs/performance.md).  With
 * dao_context_process_shaded the shading too: it reads the rows' final AO,
 * depth and normals only (shade.h), so the same bytes as
 * dao_context_shade after the frame.  The output's and the shading's
 * shares of the time are summed over the bands for dao_timings.
 */
#define FINISH_CHUNK_ROWS 16 /* 16 rows of 3 planes of 640 floats: 120 KB */

static void stage_finish(void *arg, int y0, int y1)
{
	struct frame_job *j = arg;
	const struct dao_context *c = j->ctx;
	uint64_t out_ns = 0, shade_ns = 0;
	/* in chunks, so that the rows are still in cache on one thread too
	 * (its band is the whole frame) */
	for (int a = y0; a < y1; a += FINISH_CHUNK_ROWS) {
		const int b = a + FINISH_CHUNK_ROWS < y1 ? a + FINISH_CHUNK_ROWS : y1;
		switch (j->ctx->params.denoise) {
		case DAO_DENOISE_PLANE: stage_denoise_plane(arg, a, b); break;
		case DAO_DENOISE_BILATERAL: stage_denoise_v(arg, a, b); break;
		default: break;
		}
		if (j->ctx->params.temporal > 0.0f)
			stage_temporal(arg, a, b);
		const uint64_t t = dao_mono_ns();
		stage_output(arg, a, b);
		const uint64_t t1 = dao_mono_ns();
		out_ns += t1 - t;
		if (j->shade_out) {
			j->k.shade(&j->shade, c->z_raw, c->n, c->ao, j->shade_out, a, b);
			shade_ns += dao_mono_ns() - t1;
		}
	}
	atomic_fetch_add_explicit(&j->output_ns, out_ns, memory_order_relaxed);
	atomic_fetch_add_explicit(&j->shade_ns, shade_ns, memory_order_relaxed);
}

/*
 * noise-model=auto: the frame's noise per region, and what it drives
 * (noise_estimate.h); with noise-interval > 1 a recent frame's where the
 * scene stayed (noise_reuse.h).  Without a measurable block, the model's
 * settings stay.
 */
static void estimate_noise(struct dao_context *ctx, struct frame_job *job,
			   struct dao_domain_setup *dt)
{
	const struct dao_params *p = &ctx->params;
	struct dao_noise_grid *g = &ctx->noise;
	struct dao_noise_reuse *nr = &ctx->noise_reuse;
	const float f = (float)(0.5 * (ctx->cam.fx + ctx->cam.fy));
	int moved = 0;
	if (p->noise_interval > 1 && !dao_noise_reuse_due(nr)) {
		moved = dao_noise_reuse_changes(nr, g, ctx->z_raw);
		if (moved < 0)
			dao_noise_reuse_restart(nr); /* a cut: all again */
	}
	g->row = job->k.noise_row;
	if (p->noise_interval <= 1 || dao_noise_reuse_due(nr)) {
		dao_pool_run(ctx->pool, g->bh, 2, stage_noise_blocks, job);
		dao_pool_run(ctx->pool, g->ch, 1, stage_noise_cells, job);
		dao_noise_cells_finish(g);
		dao_noise_reuse_store(nr, g, ctx->z_raw, p->noise_interval);
		moved = 0;
	} else if (moved > 0) {
		dao_pool_run(ctx->pool, moved, 4, stage_noise_moved, job);
	}
	dao_noise_reuse_advance(nr);
	if (!nr->valid)
		return;
	struct dao_noise_info *ni = &ctx->noise_info;
	ni->measured = 1;
	ni->age = nr->age - 1; /* advanced already */
	ni->cells_measured = moved;
	ni->sigma_area = nr->area;
	ni->sigma_link = nr->link;
	ni->sigma_slope = nr->slope;
	ni->prefilter_scale = dao_auto_scale(nr->slope, f, nr->w);
	job->prefilter.noise_k = nr->area;
	if (p->noise_model == DAO_NOISE_MODEL_AUTO) {
		job->denoise.noise_k = nr->area;
		/* the temporal depth filter tests a sample against the history
		 * with the noise of one sample: `area` (the independent part) or
		 * `link` (what neighbours differ by: bands, correlated blobs),
		 * whichever is larger */
		job->depth_temporal_setup.noise_k = fmaxf(nr->area, nr->link);
		if (p->normals == DAO_NORMALS_WIDE)
			job->normal_radius = dao_auto_normal_radius(nr->slope, f, nr->w);
		ni->normal_radius = job->normal_radius;
		ni->denoise_noise = job->denoise.noise_k;
	}
	if (p->prefilter != DAO_PREFILTER_DOMAIN)
		return;
	const int nc = g->cw * g->ch;
	const float *link = nr->cell, *wm = nr->cell + nc;
	for (int i = 0; i < nc; i++) {
		ctx->noise_cells[i] = link[i];
		ctx->noise_cells[nc + i] = 1.0f / dao_auto_scale(nr->slope, f, wm[i]);
	}
	/* interpolated between the cells where the passes need them (domain.h) */
	dt->noise_cells = ctx->noise_cells;
	dt->inv_scale_cells = ctx->noise_cells + nc;
	dt->cells_x = g->cw, dt->cells_y = g->ch;
	dt->cell_span = DAO_NOISE_BLOCK * DAO_NOISE_CELL;
}

/*
 * The side windows' test (domain.h) compares residuals with the sensor's
 * noise, measured before the temporal depth filter; the prefilter's input
 * holds what that filter left: less where the noise changes from frame to
 * frame, as much where it does not (a still clean scene, a Kinect's fixed
 * pattern).  Measured again after it (`area`, the frame's), the test's
 * threshold follows the ratio: a stream's creases would otherwise stay round
 * under a threshold its averaged noise no longer reaches
 * (tests/pipeline/test_temporal_depth.c, still Gaussian stairs).
 */
static void side_noise_after_temporal(struct dao_context *ctx, struct frame_job *job,
				      struct dao_domain_setup *dt)
{
	struct dao_noise_grid *g = &ctx->noise;
	struct dao_noise_reuse *nr = &ctx->noise_reuse;
	const float before = ctx->noise_info.sigma_area;
	if (ctx->params.prefilter != DAO_PREFILTER_DOMAIN || !ctx->noise_info.measured ||
	    job->depth_temporal_setup.fresh || !(before > 0.0f))
		return;
	if (ctx->noise_info.age == 0) { /* measured in this frame: the ratio too */
		dao_pool_run(ctx->pool, g->bh, 2, stage_noise_blocks, job);
		dao_pool_run(ctx->pool, g->ch, 1, stage_noise_cells, job);
		dao_noise_cells_finish(g);
		if (g->usable_cells)
			nr->side_ratio = g->frame_area / before;
	}
	const float r = nr->side_ratio;
	if (!isnan(r))
		dt->side_noise = DAO_DOMAIN_SIDE_NOISE * (r < 1.0f ? r : 1.0f);
}

/* prefilter=domain: z_raw -> z_buf, the passes alternating through tmp */
static void run_domain(struct dao_context *ctx, struct frame_job *job,
		       const struct dao_domain_setup *dt)
{
	for (int k = 0; k < 2 * dt->iterations; k++) {
		const float *in = k == 0 ? ctx->z_raw : (k & 1) ? ctx->tmp : ctx->z_buf;
		dao_domain_pass_init(&job->dt_pass, dt, k, in, (k & 1) ? ctx->z_buf : ctx->tmp);
		const int strips = (job->dt_pass.lanes + DAO_DOMAIN_STRIP - 1) / DAO_DOMAIN_STRIP;
		dao_pool_run_threads(ctx->pool, strips, 1, stage_domain, job);
	}
}

/* The frame's settings for every stage, from the parameters and the camera. */
static void frame_job_init(struct dao_context *ctx, struct frame_job *job,
			   const struct dao_frame *depth, struct dao_frame *ao, uint64_t frame_index)
{
	const struct dao_params *p = &ctx->params;
	*job = (struct frame_job){
		.ctx = ctx,
		.depth = depth,
		.ao_out = ao,
		.normal_radius = p->normals == DAO_NORMALS_WIDE ? p->normal_radius : 1,
		.denoise = {
			.width = (int)ctx->cam.width, .height = (int)ctx->cam.height,
			.ax = ctx->cam.ax, .ay = ctx->cam.ay, .bx = ctx->cam.bx, .by = ctx->cam.by,
			.noise_k = p->depth_noise,
			.sharpness = p->denoise_sharpness,
			.radius = p->denoise_radius,
			.invalid_value = p->invalid_value,
		},
	};
	dao_gtao_setup_init(&job->gtao, &ctx->cam, p, frame_index);
	job->algorithm = p->algorithm;
	if (p->algorithm != DAO_ALGORITHM_GTAO && p->algorithm != DAO_ALGORITHM_NONE)
		dao_variant_setup_init(&job->variant, &job->gtao, p);
	if (p->algorithm == DAO_ALGORITHM_VBAO && p->vbao_thickness_mode == DAO_VBAO_THICKNESS_IMAGE) {
		dao_thickness_setup_init(&job->thickness, &ctx->cam, p->vbao_thickness_max);
		job->thickness.spacing = job->gtao.search_radius / (float)job->gtao.steps;
		job->thick = ctx->thick;
		job->variant.thickness = ctx->thick;
	}
	job->k = ctx->kernels;
	use_r2_tile(ctx, &job->gtao, frame_index);
	ctx->depth_unit = depth->format == DAO_PIXFMT_DEPTH16 ? depth->depth_unit : 0.0f;
	dao_prefilter_setup_init(&job->prefilter, (int)ctx->cam.width, (int)ctx->cam.height,
				 p->prefilter_radius, p->depth_noise, ctx->depth_unit);
	job->depth_temporal = p->depth_temporal > 0.0f;
	job->depth_only = p->algorithm == DAO_ALGORITHM_NONE;
	atomic_init(&job->output_ns, 0);
	atomic_init(&job->shade_ns, 0);
	/*
	 * The noise is measured on the samples as the sensor delivers them,
	 * before the temporal filter: the spatial filters keep the strength
	 * the sensor's noise asks for and the temporal filter's averaging
	 * comes on top.  Measured after it, the prefilter and the normals
	 * backed off to what it leaves and the stream gained nothing
	 * (tests/pipeline/test_temporal_depth.c: still boxes AO MAE 0.0335
	 * against 0.0346 without the filter, thin poles moving +0.0084).
	 */
	job->temporal_in_decode = job->depth_temporal && p->noise_model == DAO_NOISE_MODEL_FIXED &&
				  p->depth_temporal_motion == DAO_DEPTH_MOTION_OFF;
}

/* The histories (AO, depth, noise) go on only from one frame to one of the
 * next few; otherwise they start again. */
static void continue_histories(struct dao_context *ctx, uint64_t frame_index)
{
	const int consecutive = ctx->have_index && frame_index - ctx->last_frame_index >= 1u &&
				frame_index - ctx->last_frame_index <= DAO_TEMPORAL_MAX_GAP;
	if (!consecutive) {
		ctx->hist_valid = 0;
		ctx->depth_hist_valid = 0;
		dao_noise_reuse_restart(&ctx->noise_reuse);
	}
}

/* The temporal depth filter's and the domain filter's settings, and the
 * noise figures of the fixed model (estimate_noise replaces them). */
static void noise_and_filter_init(struct dao_context *ctx, struct frame_job *job,
				  struct dao_domain_setup *dt)
{
	const struct dao_params *p = &ctx->params;
	job->depth_temporal_setup = (struct dao_temporal_depth_setup){
		.width = (int)ctx->cam.width,
		.alpha = p->depth_temporal,
		.reject = p->depth_temporal_reject,
		.noise_k = p->depth_noise,
		.quantum = ctx->depth_unit,
		.persist = p->depth_temporal_persist,
		.fresh = !ctx->depth_hist_valid,
	};
	*dt = (struct dao_domain_setup){
		.width = (int)ctx->cam.width, .height = (int)ctx->cam.height,
		.iterations = p->prefilter_iterations,
		.inv_scale = 1.0f / p->prefilter_scale,
		.range_coef = dao_domain_range_coef(p->prefilter_range),
		.noise = p->depth_noise, .unit = ctx->depth_unit,
		.sides = 1,
	};
	ctx->noise_info = (struct dao_noise_info){
		.sigma_area = p->depth_noise, .sigma_link = p->depth_noise,
		.sigma_slope = p->depth_noise,
		.prefilter_scale = p->prefilter_scale, .normal_radius = job->normal_radius,
		.denoise_noise = p->depth_noise,
	};
}

/*
 * depth-temporal-motion=icp: the motion from this frame to the last, from
 * the decoded depth against the history (motion/icp.h), seeded with the last
 * frame's; where accepted and it moves a pixel of the nearest surface by
 * 0.02 px or more, the history is carried into this view (motion/reproject.h)
 * before the filter runs.  Refused or too small, the history stays as it is:
 * the filter as without motion, bit for bit.  The estimate and the
 * reprojection run on the context's threads.
 */
static void follow_motion(struct dao_context *ctx, const struct frame_job *job)
{
	const struct dao_pose *prior = ctx->motion_ran && ctx->motion.valid ? &ctx->motion.pose : NULL;
	struct dao_pose seed;
	if (prior)
		seed = *prior;
	ctx->motion_applied = 0;
	ctx->motion_ran = 0;
	ctx->motion_origin = DAO_MOTION_FROM_DEPTH;
	const int mode = ctx->params.depth_temporal_motion;
	if (!job->depth_temporal || mode == DAO_DEPTH_MOTION_OFF ||
	    job->depth_temporal_setup.fresh || !ctx->motion_mem)
		return;
	/* the pairs weighed by the noise the filter uses (measured, or the
	 * model's), on this context's kernels and threads */
	ctx->icp.noise_k = job->depth_temporal_setup.noise_k;
	ctx->icp.quantum = job->depth_temporal_setup.quantum;
	ctx->icp.pairs = ctx->kernels.icp_pairs;
	ctx->icp.source = ctx->kernels.icp_source;
	ctx->icp.target = ctx->kernels.icp_target;
	ctx->icp.pool = ctx->pool;
	/* source, source+icp: the motion between the poses given (motion/pose_prior.h) */
	struct dao_pose given;
	const int have_given = mode != DAO_DEPTH_MOTION_ICP &&
			       dao_pose_prior_relative(&ctx->poses, &given);
	if (mode == DAO_DEPTH_MOTION_SOURCE && !have_given)
		return;
	if (mode == DAO_DEPTH_MOTION_SOURCE) {
		dao_pose_prior_result(&ctx->icp, &ctx->cam, ctx->z_raw, &given, &ctx->motion);
		ctx->motion_origin = DAO_MOTION_FROM_SOURCE;
	} else {
		if (have_given)
			seed = given, prior = &seed, ctx->motion_origin = DAO_MOTION_FROM_SOURCE_ICP;
		dao_icp_estimate(&ctx->icp, &ctx->cam, ctx->depth_hist, ctx->depth_count,
				 ctx->z_raw, prior ? &seed : NULL, ctx->icp_scratch, &ctx->motion);
	}
	ctx->motion_ran = 1;
	if (!ctx->motion.valid ||
	    dao_pose_pixel_extent(&ctx->motion.pose, &ctx->cam, ctx->motion.near_z) < 0.02)
		return;
	dao_history_reproject(&ctx->cam, &ctx->motion.pose, ctx->depth_hist, ctx->depth_count,
			      ctx->depth_age, ctx->motion_hist, ctx->motion_count, ctx->motion_age,
			      (int32_t *)(void *)ctx->icp_scratch, ctx->kernels.reproject_land,
			      ctx->pool);
	float *h = ctx->depth_hist;
	uint8_t *c = ctx->depth_count, *a = ctx->depth_age;
	ctx->depth_hist = ctx->motion_hist, ctx->motion_hist = h;
	ctx->depth_count = ctx->motion_count, ctx->motion_count = c;
	ctx->depth_age = ctx->motion_age, ctx->motion_age = a;
	ctx->motion_applied = 1;
}

/* the temporal depth filter when it could not run in the decode (the noise is
 * measured between them) */
static void run_temporal_depth(struct dao_context *ctx, struct frame_job *job,
			       struct dao_domain_setup *dt)
{
	if (!job->depth_temporal || job->temporal_in_decode)
		return;
	dao_pool_run(ctx->pool, (int)ctx->cam.height, 8, stage_temporal_depth, job);
	side_noise_after_temporal(ctx, job, dt);
}

/* depth-fill: the depth output's holes, ctx->z -> ctx->z_fill (the AO reads ctx->z) */
static void stage_depth_fill(void *arg, int y0, int y1)
{
	const struct dao_context *ctx = ((struct frame_job *)arg)->ctx;
	dao_depth_fill_rows(ctx->z, ctx->z_fill, (int)ctx->cam.width, y0, y1,
			    ctx->params.depth_fill);
}

/* z_raw -> ctx->z: the prefilter's output, or z_raw itself without one */
static void run_prefilter(struct dao_context *ctx, struct frame_job *job,
			  const struct dao_domain_setup *dt)
{
	const int h = (int)ctx->cam.height;
	if (ctx->params.prefilter == DAO_PREFILTER_BILATERAL) {
		dao_pool_run(ctx->pool, h, 4, stage_prefilter_h, job);
		dao_pool_run(ctx->pool, h, 4, stage_prefilter_v, job);
		ctx->z = ctx->z_buf;
	} else if (ctx->params.prefilter == DAO_PREFILTER_DOMAIN) {
		run_domain(ctx, job, dt);
		ctx->z = ctx->z_buf;
	} else {
		ctx->z = ctx->z_raw;
	}
	ctx->have_fill = ctx->params.depth_fill > 0;
	if (ctx->have_fill)
		dao_pool_run(ctx->pool, h, 8, stage_depth_fill, job);
}

/* The normals (computed, or the caller's), and VBAO's thickness inputs that
 * are made row by row beside them. */
static int run_normals(struct dao_context *ctx, struct frame_job *job,
		       const struct dao_frame *normals, struct dao_error *err)
{
	const int h = (int)ctx->cam.height;
	/* slabs' creases as rounded as the measured noise had the prefilter make them
	 * (before the normals stage: it runs the thickness's rows) */
	if (job->thick && ctx->params.prefilter == DAO_PREFILTER_DOMAIN &&
	    ctx->noise_info.measured) {
		dao_thickness_setup_rounding(&job->thickness, ctx->noise_info.prefilter_scale);
		dao_thickness_setup_noise(&job->thickness, ctx->noise_info.prefilter_scale,
					  ctx->noise_info.sigma_area);
	}
	/* the thickness's passes read the depth with its dropouts filled: every row of it
	 * before they start (the row pass looks at the rows beside its own) */
	job->thick_z = ctx->z;
	if (job->thick && job->thickness.fill_px > 0) {
		dao_pool_run(ctx->pool, h, 8, stage_thickness_fill, job);
		job->thick_z = ctx->thick_z;
	}
	if (!normals) {
		dao_pool_run(ctx->pool, h, 4, stage_normals, job); /* and the thickness's rows */
		return 0;
	}
	int r = load_normals(ctx, normals, err);
	if (r)
		return r;
	if (job->k.simd != DAO_SIMD_REFERENCE)
		fill_inverse_depth(ctx, &job->k, 0, h);
	if (job->thick)
		dao_pool_run(ctx->pool, h, 8, stage_thickness_rows, job);
	return 0;
}

/* The AO itself: VBAO's thickness columns, then the AO by strips or rows. */
static void run_ao(struct dao_context *ctx, struct frame_job *job)
{
	const struct dao_params *p = &ctx->params;
	const int h = (int)ctx->cam.height;
	if (job->thick)
		dao_pool_run_threads(ctx->pool,
				     ((int)ctx->cam.width + DAO_THICKNESS_COL_BLOCK - 1) /
					     DAO_THICKNESS_COL_BLOCK,
				     1, stage_thickness_cols, job);
	const int sw = gtao_strip_width((int)ctx->cam.width);
	const int strips = ((int)ctx->cam.width + sw - 1) / sw;
	/* the optimised kernels compute strips (vbao, hbao: with tile noise, the tile kernel) */
	const int in_strips = job->k.simd != DAO_SIMD_REFERENCE &&
			      (job->algorithm == DAO_ALGORITHM_GTAO ||
			       ((job->algorithm == DAO_ALGORITHM_VBAO ||
				 job->algorithm == DAO_ALGORITHM_HBAO) &&
				p->noise == DAO_NOISE_TILE));
	if (strips > 1 && in_strips)
		dao_pool_run_threads(ctx->pool, h * strips, 2, stage_gtao_strips, job);
	else
		dao_pool_run_threads(ctx->pool, h, 2, stage_gtao, job);
}

/* the AO history moved into this view by the motion the depth history followed */
static void stage_ao_reproject(void *arg, int y0, int y1)
{
	struct dao_context *c = ((struct frame_job *)arg)->ctx;
	c->kernels.ao_reproject(&c->cam, &c->motion.pose, c->params.temporal_reject, c->z,
				c->hist_ao, c->hist_z, c->ao_motion_ao, c->ao_motion_z, y0, y1);
}

/* Per row, the nearest and farthest depth of the last frame (0 and 0 when the
 * row has none); rows in parallel. */
DAO_MULTIVERSION
static void stage_row_range(void *arg, int y0, int y1)
{
	struct dao_context *ctx = arg;
	const int w = (int)ctx->cam.width;
	for (int y = y0; y < y1; y++) {
		const float *zr = ctx->z_raw + (size_t)y * w;
		float a = INFINITY, b = 0.0f;
		for (int x = 0; x < w; x++) {
			/* no data is 0: it never raises b, and is kept out of a */
			const float z = zr[x], za = z > 0.0f ? z : INFINITY;
			a = za < a ? za : a;
			b = z > b ? z : b;
		}
		ctx->row_range[2 * y] = b > 0.0f ? a : 0.0f;
		ctx->row_range[2 * y + 1] = b;
	}
}

static void depth_range(struct dao_context *ctx, float *lo, float *hi)
{
	dao_pool_run(ctx->pool, (int)ctx->cam.height, 16, stage_row_range, ctx);
	float a = INFINITY, b = 0.0f;
	for (uint32_t y = 0; y < ctx->cam.height; y++) {
		if (ctx->row_range[2 * y + 1] > 0.0f && ctx->row_range[2 * y] < a)
			a = ctx->row_range[2 * y];
		if (ctx->row_range[2 * y + 1] > b)
			b = ctx->row_range[2 * y + 1];
	}
	if (!(b > a)) {
		a = b > 0.0f ? b * 0.5f : 0.5f;
		b = a * 2.0f + 0.001f;
	}
	*lo = a;
	*hi = b;
}

/* The shaded image's settings for the last frame: the colormap, and the
 * depth range where the mode needs it and the parameters leave it open. */
static void shade_setup(struct dao_context *ctx, struct dao_shade_setup *ss)
{
	const struct dao_params *p = &ctx->params;
	if (ctx->cmap_mode != p->shade) {
		dao_colormap_fill(&ctx->cmap, p->shade);
		ctx->cmap_mode = p->shade;
	}
	float lo = p->near_m, hi = p->far_m;
	/* only the depth colormaps use the range: the automatic one is a pass
	 * over the depth, skipped for the others */
	const int colormap = p->shade == DAO_SHADE_TURBO || p->shade == DAO_SHADE_JET ||
			     p->shade == DAO_SHADE_GRAY;
	if (colormap && (lo <= 0.0f || hi <= 0.0f)) {
		float a, b;
		depth_range(ctx, &a, &b);
		if (lo <= 0.0f)
			lo = a;
		if (hi <= 0.0f)
			hi = b;
		if (hi <= lo)
			hi = lo + 0.001f;
	}
	*ss = (struct dao_shade_setup){
		.width = (int)ctx->cam.width, .height = (int)ctx->cam.height,
		.ax = ctx->cam.ax, .ay = ctx->cam.ay, .bx = ctx->cam.bx, .by = ctx->cam.by,
		.mode = p->shade,
		.near_m = lo, .far_m = hi,
		.power = p->shade_power,
		.occ = { (float)((p->occlusion_color >> 16) & 255), (float)((p->occlusion_color >> 8) & 255),
			 (float)(p->occlusion_color & 255) },
		.map = &ctx->cmap,
	};
}

/* The shaded image's frame: the camera's size, RGB24 or GRAY8. */
static int shade_check(const struct dao_context *ctx, const struct dao_frame *out,
		       struct dao_error *err)
{
	int r = dao_frame_check(out, "shaded output", ctx->cam.width, ctx->cam.height, err);
	if (r)
		return r;
	if (out->format != DAO_PIXFMT_RGB24 && out->format != DAO_PIXFMT_GRAY8)
		return dao_error_set(err, -EINVAL, "shaded output: format %s is not rgb24 or gray8",
				     dao_pixfmt_name(out->format));
	return 0;
}

/* The denoise, the temporal AO, the output and the shading (stage_finish
 * fuses them). */
static void run_finish(struct dao_context *ctx, struct frame_job *job)
{
	if (ctx->motion_applied && ctx->hist_valid && ctx->params.temporal > 0.0f &&
	    ctx->ao_motion_mem) {
		float *a = ctx->hist_ao, *z = ctx->hist_z;
		dao_pool_run(ctx->pool, (int)ctx->cam.height, 8, stage_ao_reproject, job);
		ctx->hist_ao = ctx->ao_motion_ao, ctx->ao_motion_ao = a;
		ctx->hist_z = ctx->ao_motion_z, ctx->ao_motion_z = z;
	}
	const struct dao_params *p = &ctx->params;
	const int h = (int)ctx->cam.height;
	ctx->ao = p->denoise == DAO_DENOISE_PLANE || p->denoise == DAO_DENOISE_BILATERAL
			  ? ctx->ao_buf
			  : ctx->ao_raw;
	if (p->denoise == DAO_DENOISE_BILATERAL)
		dao_pool_run(ctx->pool, h, 4, stage_denoise_h, job);
	if (job->shade_out)
		shade_setup(ctx, &job->shade);
	dao_pool_run(ctx->pool, h, 4, stage_finish, job);
	ctx->hist_valid = p->temporal > 0.0f;
}

/* t[]: the clock before decode, noise, temporal depth, prefilter, normals, AO,
 * finish, and after it */
enum { T_DECODE, T_NOISE, T_TEMPORAL, T_PREFILTER, T_NORMALS, T_AO, T_FINISH, T_END };

static void record_timings(struct dao_context *ctx, struct frame_job *job, const double *t)
{
	struct dao_timings *tm = &ctx->times;
	/* the output's and the shading's shares: their times summed over the
	 * bands, over the threads */
	const double threads = (double)dao_pool_threads(ctx->pool);
	const double out_ms = (double)atomic_load(&job->output_ns) * 1e-6 / threads;
	const double finish_ms = t[T_END] - t[T_FINISH];
	double shade_ms = (double)atomic_load(&job->shade_ns) * 1e-6 / threads;
	shade_ms = shade_ms < finish_ms ? shade_ms : finish_ms;
	tm->decode_ms = (t[T_NOISE] - t[T_DECODE]) + (t[T_PREFILTER] - t[T_TEMPORAL]);
	tm->noise_ms = t[T_TEMPORAL] - t[T_NOISE];
	tm->prefilter_ms = t[T_NORMALS] - t[T_PREFILTER];
	tm->normals_ms = t[T_AO] - t[T_NORMALS];
	tm->gtao_ms = t[T_FINISH] - t[T_AO];
	tm->output_ms = out_ms < finish_ms - shade_ms ? out_ms : finish_ms - shade_ms;
	tm->denoise_ms = finish_ms - shade_ms - tm->output_ms;
	if (job->depth_only) { /* the output beside the decode (depth_only_output) */
		tm->output_ms = out_ms < tm->decode_ms ? out_ms : tm->decode_ms;
		tm->decode_ms -= tm->output_ms;
		tm->denoise_ms = 0.0;
	}
	if (job->shade_out)
		tm->shade_ms = shade_ms;
	tm->process_ms = t[T_END] - t[T_DECODE];
}

/* algorithm=none, after the prefilter: no normals, AO, denoise or shading
 * (the caller's AO image was written beside the decode: depth_only_output) */
static void run_depth_only(struct dao_context *ctx)
{
	ctx->ao = ctx->ao_raw;
	ctx->hist_valid = 0; /* the AO history no longer matches the depth */
}

/* dao_context_process, and with `shaded` the shading in its last pass */
static int process_frame(struct dao_context *ctx, const struct dao_frame *depth,
			 const struct dao_frame *normals, uint64_t frame_index,
			 struct dao_frame *ao, const struct dao_frame *shaded, struct dao_error *err)
{
	if (!ctx)
		return dao_error_set(err, -EINVAL, "context is NULL");
	int r = check_depth(ctx, depth, err);
	if (!r && ao)
		r = check_ao_out(ctx, ao, err);
	if (!r && shaded)
		r = shade_check(ctx, shaded, err);
	if (r)
		return r;

	struct frame_job job;
	struct dao_domain_setup dt;
	frame_job_init(ctx, &job, depth, ao, frame_index);
	job.shade_out = shaded;
	continue_histories(ctx, frame_index);
	dao_pose_prior_begin(&ctx->poses);
	noise_and_filter_init(ctx, &job, &dt);
	ctx->have_frame = 0;
	ctx->have_index = 0; /* until this frame is through: an error leaves the histories half done */
	ctx->track.current = 0; /* nor is the pose this frame's until it is through */

	double t[T_END + 1];
	t[T_DECODE] = now_ms();
	dao_pool_run(ctx->pool, (int)ctx->cam.height, 8, stage_decode, &job);
	ctx->depth_hist_valid = job.depth_temporal;
	t[T_NOISE] = now_ms();
	if (ctx->params.noise_model != DAO_NOISE_MODEL_FIXED)
		estimate_noise(ctx, &job, &dt);
	t[T_TEMPORAL] = now_ms();
	follow_motion(ctx, &job);
	run_temporal_depth(ctx, &job, &dt);
	t[T_PREFILTER] = now_ms();
	run_prefilter(ctx, &job, &dt);
	t[T_NORMALS] = now_ms();
	ctx->depth_only = job.depth_only;
	if (ctx->depth_only) {
		t[T_AO] = t[T_FINISH] = t[T_NORMALS];
		run_depth_only(ctx);
	} else {
		r = run_normals(ctx, &job, normals, err);
		if (r)
			return r;
		t[T_AO] = now_ms();
		run_ao(ctx, &job);
		t[T_FINISH] = now_ms();
		run_finish(ctx, &job);
	}
	t[T_END] = now_ms();
	record_timings(ctx, &job, t);
	ctx->have_frame = 1;
	ctx->have_index = 1;
	ctx->last_frame_index = frame_index;
	dao_pose_prior_end(&ctx->poses);
	struct dao_motion_info mi = DAO_MOTION_INFO_INIT;
	dao_context_motion(ctx, &mi);
	dao_track_add(&ctx->track, dao_track_follows(&ctx->params), &mi);
	return 0;
}

/* no normals or AO after a frame with algorithm=none */
static int no_shading(struct dao_error *err)
{
	return dao_error_set(err, -ENODATA,
			     "no shaded image with algorithm=none (no normals or AO were "
			     "computed): choose an AO algorithm, or take the depth");
}

int dao_context_process(struct dao_context *ctx, const struct dao_frame *depth,
			const struct dao_frame *normals, uint64_t frame_index,
			struct dao_frame *ao, struct dao_error *err)
{
	return process_frame(ctx, depth, normals, frame_index, ao, NULL, err);
}

int dao_context_process_shaded(struct dao_context *ctx, const struct dao_frame *depth,
			       const struct dao_frame *normals, uint64_t frame_index,
			       struct dao_frame *ao, struct dao_frame *shaded, struct dao_error *err)
{
	int r = process_frame(ctx, depth, normals, frame_index, ao, shaded, err);
	if (!r && shaded && ctx->depth_only)
		return no_shading(err);
	return r;
}

struct shade_job {
	const struct dao_shade_setup *setup;
	const struct dao_context *ctx;
	const struct dao_frame *out;
	struct dao_kernels k;
};

static void stage_shade(void *arg, int y0, int y1)
{
	const struct shade_job *j = arg;
	j->k.shade(j->setup, j->ctx->z_raw, j->ctx->n, j->ctx->ao, j->out, y0, y1);
}

int dao_context_shade(struct dao_context *ctx, struct dao_frame *out, struct dao_error *err)
{
	if (!ctx)
		return dao_error_set(err, -EINVAL, "context is NULL");
	int r = shade_check(ctx, out, err);
	if (r)
		return r;
	if (!ctx->have_frame)
		return dao_error_set(err, -EAGAIN,
				     "no frame to shade: call dao_context_process() first");
	if (ctx->depth_only)
		return no_shading(err);
	struct dao_shade_setup ss;
	shade_setup(ctx, &ss);
	const double t0 = now_ms();
	struct shade_job sj = { .setup = &ss, .ctx = ctx, .out = out };
	sj.k = ctx->kernels;
	dao_pool_run(ctx->pool, (int)ctx->cam.height, 8, stage_shade, &sj);
	ctx->times.shade_ms = now_ms() - t0;
	return 0;
}

static int copy_plane(const struct dao_context *ctx, const float *src, size_t comps,
		      enum dao_pixfmt fmt, struct dao_frame *out, const char *what,
		      struct dao_error *err)
{
	if (!ctx)
		return dao_error_set(err, -EINVAL, "context is NULL");
	int r = dao_frame_check(out, what, ctx->cam.width, ctx->cam.height, err);
	if (r)
		return r;
	if (out->format != fmt)
		return dao_error_set(err, -EINVAL, "%s: format %s, expected %s", what,
				     dao_pixfmt_name(out->format), dao_pixfmt_name(fmt));
	if (!ctx->have_frame)
		return dao_error_set(err, -EAGAIN, "%s: no frame processed yet", what);
	if (ctx->depth_only && fmt == DAO_PIXFMT_NORMAL_F32)
		return dao_error_set(err, -ENODATA,
				     "%s: algorithm=none computed no normals: choose an AO algorithm",
				     what);
	const size_t row = (size_t)ctx->cam.width * comps;
	for (uint32_t y = 0; y < ctx->cam.height; y++)
		memcpy((char *)out->data + (size_t)y * out->stride, src + y * row, row * sizeof(float));
	return 0;
}

int dao_context_get_normals(const struct dao_context *ctx, struct dao_frame *out,
			    struct dao_error *err)
{
	return copy_plane(ctx, ctx ? ctx->n : NULL, 3, DAO_PIXFMT_NORMAL_F32, out, "normals output",
			  err);
}

struct bent_job {
	struct dao_context *ctx;
	struct dao_gtao_setup gtao;
};

static void stage_bent(void *arg, int y0, int y1)
{
	struct bent_job *j = arg;
	dao_gtao_bent_ref(&j->gtao, j->ctx->z, j->ctx->n, j->ctx->bent, y0, y1);
}

int dao_context_get_bent_normals(struct dao_context *ctx, struct dao_frame *out,
				 struct dao_error *err)
{
	if (!ctx)
		return dao_error_set(err, -EINVAL, "context is NULL");
	if (!ctx->have_frame)
		return dao_error_set(err, -EAGAIN, "bent normals: no frame processed yet");
	if (ctx->depth_only)
		return dao_error_set(err, -ENODATA,
				     "bent normals: algorithm=none computed no normals: choose an AO "
				     "algorithm");
	if (!ctx->bent && !(ctx->bent = malloc(3 * ctx->npix * sizeof(float))))
		return dao_error_set(err, -ENOMEM, "out of memory for bent normals");
	struct bent_job job = {.ctx = ctx};
	dao_gtao_setup_init(&job.gtao, &ctx->cam, &ctx->params, ctx->last_frame_index);
	use_r2_tile(ctx, &job.gtao, ctx->last_frame_index);
	dao_pool_run(ctx->pool, (int)ctx->cam.height, 2, stage_bent, &job);
	return copy_plane(ctx, ctx->bent, 3, DAO_PIXFMT_NORMAL_F32, out, "bent normals output",
			  err);
}

/* metres -> counts of `unit`: 0 stays 0 (no depth), a depth below half a count
 * is 1 (it has depth), one past the range 65535; nearest, ties to even
 * (exact arithmetic: the same counts on every instruction set) */
DAO_MULTIVERSION
static void depth_to_counts(const float *z, int w, float unit, uint16_t *q)
{
	const float inv = 1.0f / unit;
	for (int x = 0; x < w; x++) {
		const float c = z[x] * inv; /* inf for a tiny unit: saturates */
		const float s = c < 65535.0f ? c : 65535.0f;
		const uint16_t v = (uint16_t)round_even(s > 0.0f ? s : 0.0f);
		q[x] = z[x] > 0.0f ? (v ? v : 1) : 0;
	}
}

int dao_context_get_depth(const struct dao_context *ctx, struct dao_frame *out,
			  struct dao_error *err)
{
	const float *z = !ctx ? NULL : ctx->have_fill ? ctx->z_fill : ctx->z;
	if (!ctx || !out || out->format != DAO_PIXFMT_DEPTH16)
		return copy_plane(ctx, z, 1, DAO_PIXFMT_DEPTH_F32, out, "depth output", err);
	int r = dao_frame_check(out, "depth output", ctx->cam.width, ctx->cam.height, err);
	if (r)
		return r;
	if (!(out->depth_unit > 0.0f) || !isfinite(out->depth_unit))
		return dao_error_set(err, -EINVAL,
				     "depth output: depth16 needs depth_unit, the metres of one "
				     "count, positive and finite (e.g. 0.001 for millimetres)");
	if (!ctx->have_frame)
		return dao_error_set(err, -EAGAIN, "depth output: no frame processed yet");
	const int w = (int)ctx->cam.width;
	for (uint32_t y = 0; y < ctx->cam.height; y++) {
		unsigned char *row = (unsigned char *)out->data + (size_t)y * out->stride;
		const float *src = z + (size_t)y * w;
		/* in chunks through an aligned buffer: the caller's rows need not be */
		for (int x0 = 0; x0 < w; x0 += 256) {
			uint16_t q[256];
			const int n = w - x0 < 256 ? w - x0 : 256;
			depth_to_counts(src + x0, n, out->depth_unit, q);
			memcpy(row + 2 * (size_t)x0, q, 2 * (size_t)n);
		}
	}
	return 0;
}

/* The caller's struct may be shorter or longer than the library's: core/sized.h. */
int dao_context_noise_sized(const struct dao_context *ctx, struct dao_noise_info *out,
			    size_t size)
{
	return ctx ? dao_sized_copy_out(out, size, &ctx->noise_info, sizeof(ctx->noise_info))
		   : -EINVAL;
}

int dao_context_motion_sized(const struct dao_context *ctx, struct dao_motion_info *out,
			     size_t size)
{
	if (!ctx)
		return -EINVAL;
	struct dao_motion_info m = {.size = sizeof m};
	const struct dao_icp_result *r = &ctx->motion;
	struct dao_pose id;
	dao_pose_identity(&id);
	const struct dao_pose *pose = ctx->motion_ran ? &r->pose : &id;
	memcpy(m.rotation, pose->r, sizeof m.rotation);
	memcpy(m.translation, pose->t, sizeof m.translation);
	if (ctx->motion_ran) {
		m.state = !r->valid ? DAO_MOTION_REFUSED
				    : ctx->motion_applied ? DAO_MOTION_APPLIED : DAO_MOTION_STILL;
		m.reason = r->valid ? 0 : (int)r->reason;
		m.points = r->points;
		m.pairs = r->inliers;
		m.rms = r->rms;
		m.condition = r->cond;
		m.iterations = r->iterations;
		m.origin = ctx->motion_origin;
	}
	return dao_sized_copy_out(out, size, &m, sizeof m);
}

int dao_context_pose_track_sized(const struct dao_context *ctx, struct dao_pose_track *out,
				 size_t size)
{
	return ctx ? dao_sized_copy_out(out, size, &ctx->track, sizeof(ctx->track))
		   : -EINVAL;
}

int dao_context_timings_sized(const struct dao_context *ctx, struct dao_timings *out,
			      size_t size)
{
	return ctx ? dao_sized_copy_out(out, size, &ctx->times, sizeof(ctx->times)) : -EINVAL;
}

enum dao_simd dao_context_simd(const struct dao_context *ctx)
{
	return ctx->simd;
}
