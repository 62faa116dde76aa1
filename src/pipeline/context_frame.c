/* SPDX-License-Identifier: MIT */
/*
 * A frame through the AO context's pipeline (context.c has the overview):
 * the input checks, the stages on row bands run by the pool, and
 * dao_context_process / dao_context_process_shaded that run them in order.
 */
#include <errno.h>
#include <math.h>
#include <stdatomic.h>
#include <stdint.h>
#include <string.h>

#include "core/error_internal.h"
#include "core/math_util.h"
#include "core/multiversion.h"
#include "core/threadpool.h"
#include "denoise/denoise.h"
#include "depth/decode.h"
#include "depth/domain.h"
#include "depth/prefilter.h"
#include "kernels/ao_variants.h"
#include "kernels/depth_fill.h"
#include "kernels/thickness.h"
#include "motion/ao_reproject.h"
#include "motion/reproject.h"
#include "pipeline/context_internal.h"
#include "pipeline/temporal_depth.h"

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
void dao_ctx_use_r2_tile(struct dao_context *ctx, struct dao_gtao_setup *g, uint64_t frame_index)
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
	struct dao_shade_setup shade;      /* ... its settings (dao_ctx_shade_setup) */
	_Atomic uint64_t shade_ns;         /* stage_finish: the shading's time, summed over bands */
	struct dao_kernels k;  /* k.simd: the resolved kernel set */
};

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
				q[x] = (uint16_t)dao_round_even(ao_value(src, z, none, x0 + x) * 65535.0f);
			memcpy(row + 2 * (size_t)x0, q, 2 * (size_t)n);
		}
		break;
	default:
		for (int x = 0; x < w; x++)
			row[x] = (uint8_t)dao_round_even(ao_value(src, z, none, x) * 255.0f);
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
	dao_ctx_use_r2_tile(ctx, &job->gtao, frame_index);
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
		dao_ctx_shade_setup(ctx, &job->shade);
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
		r = dao_ctx_shade_check(ctx, shaded, err);
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
	t[T_DECODE] = dao_ctx_now_ms();
	dao_pool_run(ctx->pool, (int)ctx->cam.height, 8, stage_decode, &job);
	ctx->depth_hist_valid = job.depth_temporal;
	t[T_NOISE] = dao_ctx_now_ms();
	if (ctx->params.noise_model != DAO_NOISE_MODEL_FIXED)
		estimate_noise(ctx, &job, &dt);
	t[T_TEMPORAL] = dao_ctx_now_ms();
	follow_motion(ctx, &job);
	run_temporal_depth(ctx, &job, &dt);
	t[T_PREFILTER] = dao_ctx_now_ms();
	run_prefilter(ctx, &job, &dt);
	t[T_NORMALS] = dao_ctx_now_ms();
	ctx->depth_only = job.depth_only;
	if (ctx->depth_only) {
		t[T_AO] = t[T_FINISH] = t[T_NORMALS];
		run_depth_only(ctx);
	} else {
		r = run_normals(ctx, &job, normals, err);
		if (r)
			return r;
		t[T_AO] = dao_ctx_now_ms();
		run_ao(ctx, &job);
		t[T_FINISH] = dao_ctx_now_ms();
		run_finish(ctx, &job);
	}
	t[T_END] = dao_ctx_now_ms();
	record_timings(ctx, &job, t);
	ctx->have_frame = 1;
	ctx->have_index = 1;
	ctx->last_frame_index = frame_index;
	dao_pose_prior_end(&ctx->poses);
	struct dao_motion_info mi = DAO_MOTION_INFO_INIT;
	dao_context_motion(ctx, &mi);
	dao_track_add(&ctx->track, dao_track_follows(&ctx->params), &mi, frame_index,
		      depth->timestamp_ns);
	return 0;
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
		return dao_ctx_no_shading(err);
	return r;
}
