/* SPDX-License-Identifier: MIT */
/*
 * depthao eval --depth --real: on the real frames of ../shared/data there is
 * no true depth, so the filters are measured on planes.  RANSAC in 1/z
 * (synth_planes_find_frame, as sensorstats and realcheck find them) finds
 * the planes of the RAW frame; each plane's region, eroded by 2 px, is the
 * mask, and a pixel counts only where the raw, the filtered and the
 * reference depth all have depth, so the three are fitted on the same
 * pixels.  Each plane is fitted again by least squares in 1/z to each depth
 * image, and the RMS of z - z_plane is the residual; a frame's residual is
 * the pixel-weighted RMS over its planes.  Also the picture of eval --depth.
 */
#include "eval_depth.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/io.h>

#include "synth/depth_accuracy.h"
#include "synth/open_planes.h"
#include "synth/planes.h"
#include "synth/real_frames.h"
#include "synth/rs_reference.h"

#define REAL_ERODE_PX 2
#define REAL_MIN_PLANE_PX 2000
#define BAR_REAL_RATIO 3.0
#define REAL_TILE_PX 16      /* the local residual: planes fitted to 16 x 16 tiles */

struct real_result {
	int shift_x, shift_y;  /* stream: the raw frame's best shift from the previous one, px */
	int drift_x, drift_y;  /* ... and from the stream's first frame (the motion summed) */
	double moved;          /* ... share of pixels whose depth changed by > 3 % unshifted */
	struct dao_noise_info noise; /* depthao's noise state for the frame */
	int planes;
	long px;
	double sq[3];          /* raw, filtered, reference: sum of rms^2 * n */
	double tile_sq[3];     /* the same over whole tiles of the regions */
	long tile_px;
	double ms_filt, ms_ref;
};

/* depthao's filter and the reference chain with their histories: one frame alone, or the
 * frames of a recording in order (a stream). */
struct real_stream {
	const struct eval_depth_filter *filter;
	struct dao_context *ctx;
	struct rs_ref rs;
	int open;
	float *prev;          /* a stream's previous raw frame (its motion), prev_px pixels */
	float *first;         /* ... and its first (the motion summed over the stream) */
	size_t prev_px;
};

static void stream_close(struct real_stream *st)
{
	dao_context_destroy(st->ctx);
	rs_ref_free(&st->rs);
	free(st->prev);
	free(st->first);
	*st = (struct real_stream){ .filter = st->filter };
}

/* Frame z (frame_index `index`) through both filters of `st`, opened on first use. */
static int filter_frame(const float *z, const struct dao_camera *cam, double unit, int index,
			struct real_stream *st, float *filt, float *ref, struct real_result *res,
			struct dao_error *err)
{
	const uint32_t w = cam->width, h = cam->height;
	const size_t np = (size_t)w * h;
	uint16_t *counts = malloc(np * sizeof(uint16_t));
	if (!counts)
		return dao_error_set(err, -ENOMEM, "out of memory");
	for (size_t i = 0; i < np; i++) {   /* back to the source's counts */
		double c = z[i] > 0.0f ? floor(z[i] / unit + 0.5) : 0.0;
		counts[i] = c > 0.0 && c <= 65535.0 ? (uint16_t)c : 0;
	}
	struct dao_frame in = { .format = DAO_PIXFMT_DEPTH16, .width = w, .height = h,
				.stride = (int32_t)(w * 2), .data = counts, .depth_unit = (float)unit };
	struct dao_frame out = { .format = DAO_PIXFMT_DEPTH_F32, .width = w, .height = h,
				 .stride = (int32_t)(w * 4), .data = filt };
	int r = 0;
	if (!st->open) {
		struct dao_params p;
		struct rs_ref_options ro;
		rs_ref_options_default(&ro);
		r = eval_depth_params(&p, st->filter, err);
		if (!r)
			r = dao_context_create(&st->ctx, cam, &p, err);
		if (!r)
			r = rs_ref_init(&st->rs, &ro, (int)w, (int)h, cam->fx, err);
		if (!r)   /* once untimed: the context's lazy set-up */
			r = dao_context_process(st->ctx, &in, NULL, (uint64_t)index, NULL, err);
		dao_context_reset(st->ctx);
		st->open = !r;
	}
	double t0 = eval_thread_ms();
	if (!r)
		r = dao_context_process(st->ctx, &in, NULL, (uint64_t)index, NULL, err);
	if (!r)
		r = dao_context_get_depth(st->ctx, &out, err);
	double t1 = eval_thread_ms();
	if (!r)
		dao_context_noise(st->ctx, &res->noise);
	if (!r)
		rs_ref_process(&st->rs, z, ref);
	res->ms_ref = eval_thread_ms() - t1;
	res->ms_filt = t1 - t0;
	free(counts);
	return r;
}

#define MOTION_MAX_PX 16   /* the frame-to-frame shift searched, +-px */
#define MOTION_STEP_PX 4   /* every 4th pixel of every 4th row compared */
#define MOTION_CAP 0.1     /* a relative difference counts at most this much */

/* Robust mismatch of raw frame b shifted by (dx, dy) against a: the mean of
 * min(|za - zb| / za, MOTION_CAP) over the compared pixels with depth in both
 * (MOTION_CAP where fewer than a tenth of them have). */
static double shift_cost(const float *a, const float *b, int w, int h, int dx, int dy)
{
	double s = 0.0;
	long n = 0, all = 0;
	for (int y = MOTION_MAX_PX; y < h - MOTION_MAX_PX; y += MOTION_STEP_PX)
		for (int x = MOTION_MAX_PX; x < w - MOTION_MAX_PX; x += MOTION_STEP_PX) {
			const float za = a[(size_t)y * w + x], zb = b[(size_t)(y + dy) * w + x + dx];
			all++;
			if (!(za > 0.0f) || !(zb > 0.0f))
				continue;
			s += fmin(fabs((double)za - zb) / za, MOTION_CAP);
			n++;
		}
	return n * 10 >= all && n ? s / (double)n : MOTION_CAP;
}

/* The best global image shift of z against a (a handheld camera's small
 * rotation moves the image nearly uniformly). */
static void best_shift(const float *a, const float *z, int w, int h, int *sx, int *sy)
{
	double best = INFINITY;
	for (int dy = -MOTION_MAX_PX; dy <= MOTION_MAX_PX; dy++)
		for (int dx = -MOTION_MAX_PX; dx <= MOTION_MAX_PX; dx++) {
			const double c = shift_cost(a, z, w, h, dx, dy);
			if (c < best) {
				best = c;
				*sx = dx;
				*sy = dy;
			}
		}
}

/* The camera's motion between two raw frames and from the first: the best
 * shifts, and the share of pixels whose depth changed by more than 3 % from
 * the previous frame where they stand. */
static void frame_motion(const float *first, const float *prev, const float *z, int w, int h,
			 struct real_result *res)
{
	best_shift(prev, z, w, h, &res->shift_x, &res->shift_y);
	best_shift(first, z, w, h, &res->drift_x, &res->drift_y);
	long n = 0, moved = 0;
	for (size_t i = 0; i < (size_t)w * h; i++)
		if (prev[i] > 0.0f && z[i] > 0.0f) {
			n++;
			moved += fabsf(prev[i] - z[i]) > 0.03f * prev[i];
		}
	res->moved = n ? (double)moved / (double)n : 0.0;
}

/* The local residual: a plane fitted to each tile wholly inside the mask (the sensor's
 * noise without the slow deviations of a real surface or a sensor's distortion). */
static void tile_residuals(const float *const img[3], const uint8_t *mask,
			   const struct dao_camera *cam, struct real_result *res)
{
	const int w = (int)cam->width, h = (int)cam->height, t = REAL_TILE_PX;
	for (int y0 = 0; y0 + t <= h; y0 += t)
		for (int x0 = 0; x0 + t <= w; x0 += t) {
			int full = 1;
			for (int y = y0; y < y0 + t && full; y++)
				for (int x = x0; x < x0 + t; x++)
					full &= mask[(size_t)y * w + x];
			double rms[3];
			long n;
			for (int k = 0; full && k < 3; k++)
				full = !depth_plane_residual_rect(img[k], mask, cam, x0, y0, t, t,
								  &rms[k], &n);
			if (!full)
				continue;
			res->tile_px += n;
			for (int k = 0; k < 3; k++)
				res->tile_sq[k] += rms[k] * rms[k] * (double)n;
		}
}

/* The residuals of the three images on every large plane of the raw frame. */
static int plane_residuals(const float *const img[3], const struct dao_camera *cam, double unit,
			   struct real_result *res, struct dao_error *err)
{
	const int w = (int)cam->width, h = (int)cam->height;
	const size_t np = (size_t)w * h;
	struct synth_plane planes[SYNTH_PLANES_MAX];
	int count = 0;
	int32_t *labels = malloc(np * sizeof(int32_t));
	uint8_t *mask = malloc(np);
	int r = !labels || !mask ? dao_error_set(err, -ENOMEM, "out of memory") : 0;
	if (!r)
		r = synth_planes_find_frame(img[0], cam, unit, planes, &count, labels, err);
	if (!r)
		r = synth_labels_erode(labels, w, h, REAL_ERODE_PX);
	for (int p = 0; !r && p < count; p++) {
		long n = 0;
		for (size_t i = 0; i < np; i++) {
			mask[i] = labels[i] == p && img[0][i] > 0.0f && img[1][i] > 0.0f &&
				  img[2][i] > 0.0f;
			n += mask[i];
		}
		if (n < REAL_MIN_PLANE_PX)
			continue;
		double rms[3];
		long used;
		int ok = 1;
		for (int k = 0; k < 3; k++)
			ok &= depth_plane_residual(img[k], mask, cam, &rms[k], &used) == 0;
		if (!ok)
			continue;
		tile_residuals(img, mask, cam, res);
		res->planes++;
		res->px += n;
		for (int k = 0; k < 3; k++)
			res->sq[k] += rms[k] * rms[k] * (double)n;
	}
	free(labels);
	free(mask);
	return r;
}

static int real_frame(const struct synth_real_frame *f, const char *dir, struct real_stream *st,
		      struct real_result *res)
{
	float *z = NULL, *filt = NULL, *ref = NULL;
	struct dao_camera cam;
	struct dao_error err = { 0 };
	double unit;
	*res = (struct real_result){ 0 };
	if (synth_real_frame_load(f, dir, &z, &cam, &unit, &err)) {
		fprintf(stderr, "depthao: %s: %s (skipped)\n", f->name, err.message);
		return 1;
	}
	const size_t np = (size_t)cam.width * cam.height;
	filt = malloc(np * sizeof(float));
	ref = malloc(np * sizeof(float));
	int r = !filt || !ref ? dao_error_set(&err, -ENOMEM, "out of memory") : 0;
	if (!r)
		r = filter_frame(z, &cam, unit, f->frame < 0 ? 0 : f->frame, st, filt, ref, res,
				 &err);
	const float *const img[3] = { z, filt, ref };
	if (!r)
		r = plane_residuals(img, &cam, unit, res, &err);
	if (r)
		fprintf(stderr, "depthao: %s: %s\n", f->name, err.message);
	if (!r && st->prev && st->first && st->prev_px == np)
		frame_motion(st->first, st->prev, z, (int)cam.width, (int)cam.height, res);
	if (!st->first) {   /* the stream keeps its first raw frame ... */
		st->first = z;
		z = NULL;
		if (!(z = malloc(np * sizeof(float))))
			fprintf(stderr, "depthao: %s: out of memory (no motion)\n", f->name);
		else
			memcpy(z, st->first, np * sizeof(float));
	}
	free(st->prev);   /* ... and the last, for the next one's motion */
	st->prev = z;
	st->prev_px = z ? np : 0;
	free(filt);
	free(ref);
	return r ? -1 : 0;
}

/* One row of a table; adds to the counts of frames below the bar. */
static void print_real_row(const struct synth_real_frame *f, const struct real_result *res,
			   int stream, int *measured, int *below, int *tiles_below)
{
	double rms[3], tile[3];
	for (int k = 0; k < 3; k++) {
		rms[k] = sqrt(res->sq[k] / (double)res->px);
		tile[k] = res->tile_px ? sqrt(res->tile_sq[k] / (double)res->tile_px) : 0.0;
	}
	const double ratio = rms[1] > 0.0 ? rms[0] / rms[1] : INFINITY;
	const double tratio = tile[1] > 0.0 ? tile[0] / tile[1] : INFINITY;
	(*measured)++;
	*below += ratio < BAR_REAL_RATIO;
	*tiles_below += tratio < BAR_REAL_RATIO;
	printf("| %s | %s | %d | %ld | %.2f / %.2f / %.2f | %.2f | %.2f "
	       "| %.2f / %.2f / %.2f | %.2f | %.1f / %.1f |",
	       f->name, f->sensor, res->planes, res->px, 1e3 * rms[0], 1e3 * rms[1],
	       1e3 * rms[2], ratio, rms[2] > 0.0 ? rms[0] / rms[2] : INFINITY, 1e3 * tile[0],
	       1e3 * tile[1], 1e3 * tile[2], tratio, res->ms_filt, res->ms_ref);
	if (stream)
		printf(" %+d, %+d | %+d, %+d | %.1f %% | %d / %d / %.1f |", res->shift_x,
		       res->shift_y, res->drift_x, res->drift_y, 100.0 * res->moved, res->noise.age, res->noise.cells_measured,
		       (double)res->noise.prefilter_scale);
	putchar('\n');
}

static const char real_header[] =
	"| frame | sensor | planes | px | residual mm raw / depthao / ref "
	"| raw / depthao | raw / ref | tile residual mm raw / depthao / ref "
	"| raw / depthao | CPU ms depthao / ref |\n"
	"|---|---|---:|---:|---|---:|---:|---|---:|---|\n";

/* The frames of the recording (frame >= 0) in order through one pair of filters. */
static int real_stream_table(const struct synth_real_frame *frames, int n, const char *dir,
			     const struct eval_depth_filter *f)
{
	struct real_stream st = { .filter = f };
	int measured = 0, below = 0, tiles_below = 0, status = 0;
	printf("\nThe recording's frames in order, as a stream (depthao's temporal depth filter, "
	       "the reference's temporal filter); the camera's motion from the previous frame: "
	       "the raw frame's best global shift (+-%d px; also from the first frame) and the "
	       "share of pixels whose depth "
	       "changed by > 3 %% in place; depthao's noise state (dao_noise_info: frames since "
	       "the full measurement, cells measured again, the prefilter's scale)\n\n",
	       MOTION_MAX_PX);
	for (const char *c = real_header; *c != '\n'; c++)
		putchar(*c);
	printf(" shift px | from frame 0 px | depth moved | noise age / cells measured / "
	       "prefilter scale px |\n|---|---|---:|---:|---|---:|---:|---|---:|---|---|---|---:|---|\n");
	for (int i = 0; i < n && !status; i++) {
		struct real_result res;
		if (frames[i].frame < 0)
			continue;
		int r = real_frame(&frames[i], dir, &st, &res);
		status = r < 0;
		if (!r && res.px)
			print_real_row(&frames[i], &res, 1, &measured, &below, &tiles_below);
	}
	stream_close(&st);
	return status;
}

int eval_depth_real(const char *data_dir, int check, const struct eval_depth_filter *f)
{
	const char *dir = data_dir ? data_dir : synth_real_data_dir();
	int n, measured = 0, below = 0, tiles_below = 0;
	const struct synth_real_frame *frames = synth_real_frames(&n);
	printf("\nReal frames (%s): plane-fit residual on the raw frame's RANSAC planes "
	       "(>= %d px after a %d px erosion), the same pixels for all three; whole "
	       "planes, and %d x %d px tiles of them each fitted alone; each frame alone\n\n%s",
	       dir, REAL_MIN_PLANE_PX, REAL_ERODE_PX, REAL_TILE_PX, REAL_TILE_PX, real_header);
	for (int i = 0; i < n; i++) {
		struct real_stream st = { .filter = f };
		struct real_result res;
		int r = real_frame(&frames[i], dir, &st, &res);
		stream_close(&st);
		if (r < 0)
			return 1;
		if (!r && res.px)
			print_real_row(&frames[i], &res, 0, &measured, &below, &tiles_below);
	}
	printf("\nBar (issue #36, residual >= %.0fx lower than raw, frames alone): whole planes "
	       "%s (%d of %d frames), tiles %s (%d of %d)\n", BAR_REAL_RATIO,
	       measured && !below ? "holds" : "does NOT hold", measured - below, measured,
	       measured && !tiles_below ? "hold" : "do NOT hold", measured - tiles_below, measured);
	if (measured && real_stream_table(frames, n, dir, f))
		return 1;
	return check && (below || !measured);
}

/* Panel k (0..4) of the picture at output pixel (x, y) of w/2 x h/2 panels. */
static void panel_pixel(uint8_t *rgb, const float *const img[3], const float *truth, int k,
			size_t i, float zmin, float zmax)
{
	static const uint8_t none[3] = { 20, 30, 90 };
	float v;
	if (k < 3) {
		const float z = k == 2 ? truth[i] : img[k][i];
		if (!(z > 0.0f)) {
			memcpy(rgb, none, 3);
			return;
		}
		v = 1.0f - 0.85f * fminf(fmaxf((z - zmin) / (zmax - zmin), 0.0f), 1.0f);
	} else {
		const float z = img[k - 3][i];
		if (!(z > 0.0f) || !(truth[i] > 0.0f)) {
			memcpy(rgb, none, 3);
			return;
		}
		v = 1.0f - fminf(fabsf(z - truth[i]) / 0.05f, 1.0f);   /* white 0, black >= 5 cm */
	}
	rgb[0] = rgb[1] = rgb[2] = (uint8_t)lrintf(255.0f * v);
}

int eval_depth_picture(const char *path, const float *raw, const float *filt, const float *truth,
		       int w, int h)
{
	const int pw = w / 2, ph = h / 2;
	struct dao_frame pic = { 0 };
	struct dao_error err;
	float zmin = INFINITY, zmax = 0.0f;
	for (size_t i = 0; i < (size_t)w * h; i++)
		if (truth[i] > 0.0f) {
			zmin = fminf(zmin, truth[i]);
			zmax = fmaxf(zmax, truth[i]);
		}
	if (!(zmax > zmin))
		zmax = zmin + 1.0f;
	if (dao_frame_alloc(&pic, DAO_PIXFMT_RGB24, (uint32_t)(5 * pw), (uint32_t)ph, &err)) {
		fprintf(stderr, "depthao: %s\n", err.message);
		return 1;
	}
	const float *const img[3] = { raw, filt, truth };
	for (int y = 0; y < ph; y++)
		for (int k = 0; k < 5; k++)
			for (int x = 0; x < pw; x++)
				panel_pixel((uint8_t *)pic.data + (size_t)y * pic.stride +
						    3 * (size_t)(k * pw + x),
					    img, truth, k, (size_t)(2 * y) * w + 2 * x, zmin, zmax);
	int r = dao_png_write_compressed(path, &pic, 9, &err);   /* a picture for the docs: small */
	if (r)
		fprintf(stderr, "depthao: %s\n", err.message);
	dao_frame_free(&pic);
	return r ? 1 : 0;
}
