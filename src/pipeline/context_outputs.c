/* SPDX-License-Identifier: MIT */
/*
 * What the AO context hands out after a frame (context.c has the overview):
 * the shaded image (its settings also serve the fused shading of
 * context_frame.c), the normals, bent normals and filtered depth, and the
 * figures of the last frame (noise, motion, the pose track, timings).
 */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/error_internal.h"
#include "core/multiversion.h"
#include "core/sized.h"
#include "core/threadpool.h"
#include "pipeline/context_internal.h"

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
void dao_ctx_shade_setup(struct dao_context *ctx, struct dao_shade_setup *ss)
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
int dao_ctx_shade_check(const struct dao_context *ctx, const struct dao_frame *out,
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

/* no normals or AO after a frame with algorithm=none */
int dao_ctx_no_shading(struct dao_error *err)
{
	return dao_error_set(err, -ENODATA,
			     "no shaded image with algorithm=none (no normals or AO were "
			     "computed): choose an AO algorithm, or take the depth");
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
	int r = dao_ctx_shade_check(ctx, out, err);
	if (r)
		return r;
	if (!ctx->have_frame)
		return dao_error_set(err, -EAGAIN,
				     "no frame to shade: call dao_context_process() first");
	if (ctx->depth_only)
		return dao_ctx_no_shading(err);
	struct dao_shade_setup ss;
	dao_ctx_shade_setup(ctx, &ss);
	const double t0 = dao_ctx_now_ms();
	struct shade_job sj = { .setup = &ss, .ctx = ctx, .out = out };
	sj.k = ctx->kernels;
	dao_pool_run(ctx->pool, (int)ctx->cam.height, 8, stage_shade, &sj);
	ctx->times.shade_ms = dao_ctx_now_ms() - t0;
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
	dao_ctx_use_r2_tile(ctx, &job.gtao, ctx->last_frame_index);
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
		const uint16_t v = (uint16_t)dao_round_even(s > 0.0f ? s : 0.0f);
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
