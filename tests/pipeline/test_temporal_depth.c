/* SPDX-License-Identifier: MIT */
/*
 * The temporal depth filter (depth-temporal, pipeline/temporal_depth.h):
 *   - its rules, pixel by pixel: a first sample passes unchanged, the first
 *     frames average, a jump beyond the threshold starts over, holes stay
 *     holes unless persistence is asked for, a per-pixel sigma replaces the
 *     model;
 *   - the context's rules: frames continue a history only when frame_index
 *     steps forward by 1 .. DAO_TEMPORAL_MAX_GAP; dao_context_reset, a step
 *     back or the same index start it over; the first frame equals the
 *     filter off;
 *   - still scenes with sensor noise redrawn every frame converge: depth
 *     RMS error against the clean depth, AO MAE against the ray-traced truth
 *     and flicker, by frame count, with the filter before the spatial
 *     prefilter (as the pipeline runs it) and after it (for comparison);
 *   - moving objects leave no trails: where the clean depth changed within
 *     the last frames, the error is not worse than without the filter
 *     beyond a stated bound.
 * With the argument "real": the real Kinect recording in ../shared/data, whose
 * wall residual must drop over its 12 frames (exit 77 without it).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/cmocka_all.h"
#include "common/test_common.h"
#include "pipeline/temporal_depth.h"
#include "synth/suite.h"
#include "synth/synth.h"

#define W 320
#define H 240
#define FRAMES 16
#define ALPHA 0.8f /* dao_params_stream_defaults() */

/* ---- the kernel's rules -------------------------------------------------- */

struct px {
	float z[4], hist[4];
	uint8_t count[4], age[4];
};

static void run_px(struct px *p, const float *in, int fresh, int persist, const float *sigma)
{
	struct dao_temporal_depth_setup s = { .width = 4, .alpha = 0.5f, .reject = 3.0f,
					      .noise_k = 0.001f, .quantum = 0.0f,
					      .persist = persist, .fresh = fresh, .sigma = sigma };
	memcpy(p->z, in, sizeof p->z);
	dao_temporal_depth_ref(&s, p->z, p->hist, p->count, p->age, 0, 1);
}

static void test_kernel_rules(void **state)
{
	(void)state;
	struct px p;
	memset(&p, 0xff, sizeof p); /* garbage state: fresh must ignore it */
	/* first frame: output is the input, bit for bit */
	const float f0[4] = { 2.0f, 0.0f, 1.2345678f, 3.0f };
	run_px(&p, f0, 1, 0, NULL);
	assert_memory_equal(p.z, f0, sizeof f0);
	/* sigma of 1/z is 0.001: 1/2.0 + 0.002 is within 3 sigma, so it averages
	 * with weight 1/2 (a mean of the first two: 1/count = 1/2 = 1 - alpha) */
	const float inv1 = 0.5f + 0.002f;
	float f1[4] = { 1.0f / inv1, 0.0f, 1.2345678f, 3.0f };
	run_px(&p, f1, 0, 0, NULL);
	assert_float_equal(1.0f / p.z[0], 0.5f + 0.001f, 1e-6);
	assert_true(p.z[1] == 0.0f);       /* a hole stays a hole */
	assert_true(p.z[2] == 1.2345678f); /* the same value twice: the same output */
	/* a jump of 5 sigma starts over: the output is the new sample */
	float f2[4] = { 1.0f / (0.501f + 0.005f), 0.0f, 1.2345678f, 0.0f };
	run_px(&p, f2, 0, 0, NULL);
	assert_true(p.z[0] == f2[0]);
	assert_true(p.count[0] == 1);
	/* pixel 3 lost its depth: no persistence, so no data; history kept */
	assert_true(p.z[3] == 0.0f);
	assert_true(p.count[3] == 2 && p.age[3] == 1);
	/* it comes back at its old depth: the history goes on (count 3) */
	float f3[4] = { f2[0], 0.0f, 1.2345678f, 3.0f };
	run_px(&p, f3, 0, 0, NULL);
	assert_true(p.count[3] == 3 && p.age[3] == 0 && p.z[3] == 3.0f);
	/* persistence 2: two frames hold the filtered depth, the third is a hole */
	const float hole[4] = { 0.0f, 0.0f, 0.0f, 0.0f };
	for (int k = 0; k < 3; k++) {
		run_px(&p, hole, 0, 2, NULL);
		if (k < 2)
			assert_float_equal(p.z[3], 3.0f, 1e-6);
		else
			assert_true(p.z[3] == 0.0f);
		assert_true(p.z[1] == 0.0f); /* never had data: nothing to hold */
	}
	/* a per-pixel sigma replaces the model: 0.01 lets a 5-sigma-of-the-model
	 * step through */
	const float sig[4] = { 0.01f, 0.01f, 0.01f, 0.01f };
	float f4[4] = { 1.0f / (1.0f / f2[0] + 0.005f), 0.0f, 0.0f, 0.0f };
	run_px(&p, f4, 0, 0, sig);
	assert_true(p.count[0] == 3); /* two samples, three hole frames, this one */
	/* many frames at the same depth: the count stops at its cap */
	for (int k = 0; k < 300; k++)
		run_px(&p, f4, 0, 0, NULL);
	assert_true(p.count[0] == DAO_TEMPORAL_DEPTH_MAX_COUNT);
}

/* ---- the context's rules ------------------------------------------------- */

static void noisy_plane(uint16_t *mm, int w, int h, unsigned seed)
{
	for (int i = 0; i < w * h; i++) {
		seed = seed * 1103515245u + 12345u;
		mm[i] = (uint16_t)(2000 + (int)((seed >> 16) % 21) - 10 + (i % w));
	}
}

static void process(struct dao_context *ctx, uint16_t *mm, int w, int h, uint64_t index,
		    float *ao, float *z)
{
	struct dao_error err;
	struct dao_frame in = { .format = DAO_PIXFMT_DEPTH16, .width = (uint32_t)w,
			.height = (uint32_t)h, .stride = w * 2, .data = mm, .depth_unit = 0.001f};
	struct dao_frame out = { .format = DAO_PIXFMT_GRAY_F32, .width = (uint32_t)w,
			.height = (uint32_t)h, .stride = w * 4, .data = ao};
	struct dao_frame zf = { .format = DAO_PIXFMT_DEPTH_F32, .width = (uint32_t)w,
			.height = (uint32_t)h, .stride = w * 4, .data = z};
	if (dao_context_process(ctx, &in, NULL, index, &out, &err) ||
	    dao_context_get_depth(ctx, &zf, &err))
		fail_msg("%s", err.message);
}

/* Builds a history (two frames at last - 1, last), then processes frame
 * `seed` at `index` (after dao_context_reset if `reset`); returns 1 if its
 * depth equals the filter off. */
static int starts_over(struct dao_context *ctx, struct dao_context *off, uint64_t last,
		       uint64_t index, int reset, unsigned seed)
{
	enum { w = 64, h = 48 };
	static uint16_t mm[w * h];
	static float a[w * h], b[w * h], za[w * h], zb[w * h];
	noisy_plane(mm, w, h, seed);
	process(ctx, mm, w, h, last - 1, a, za);
	noisy_plane(mm, w, h, seed + 1);
	process(ctx, mm, w, h, last, a, za);
	if (reset)
		dao_context_reset(ctx);
	noisy_plane(mm, w, h, seed + 2);
	process(ctx, mm, w, h, index, a, za);
	process(off, mm, w, h, index, b, zb);
	return memcmp(za, zb, sizeof za) == 0;
}

static void test_context_rules(void **state)
{
	(void)state;
	enum { w = 64, h = 48 };
	struct dao_camera cam;
	struct dao_params p, off;
	struct dao_context *ctx, *plain;
	dao_camera_from_intrinsics(&cam, w, h, 50, 50, 31.5, 23.5, NULL);
	dao_params_init(&off, DAO_QUALITY_DEFAULT);
	p = off;
	assert_true(p.depth_temporal == 0.0f); /* the library default: off */
	dao_params_stream_defaults(&p);
	assert_true(p.depth_temporal > 0.0f);
	assert_int_equal(dao_context_create(&ctx, &cam, &p, NULL), 0);
	assert_int_equal(dao_context_create(&plain, &cam, &off, NULL), 0);
	/* the first frame of a history equals the filter off, AO included */
	static uint16_t mm[w * h];
	static float a[w * h], b[w * h], za[w * h], zb[w * h];
	noisy_plane(mm, w, h, 1);
	process(ctx, mm, w, h, 10, a, za);
	process(plain, mm, w, h, 10, b, zb);
	assert_memory_equal(a, b, sizeof a);
	assert_memory_equal(za, zb, sizeof za);
	/* frames 1 .. DAO_TEMPORAL_MAX_GAP on continue it */
	assert_false(starts_over(ctx, plain, 20, 21, 0, 2));
	assert_false(starts_over(ctx, plain, 30, 30 + DAO_TEMPORAL_MAX_GAP, 0, 5));
	/* the same index, a step back, a larger jump, a reset start it over */
	assert_true(starts_over(ctx, plain, 40, 40, 0, 8));
	assert_true(starts_over(ctx, plain, 50, 49, 0, 11));
	assert_true(starts_over(ctx, plain, 60, 61 + DAO_TEMPORAL_MAX_GAP, 0, 14));
	assert_true(starts_over(ctx, plain, 70, 71, 1, 17));
	/* a new radius keeps the depth history; a new depth range drops it */
	noisy_plane(mm, w, h, 50);
	process(ctx, mm, w, h, 100, a, za);
	p.radius = 0.3f;
	assert_int_equal(dao_context_set_params(ctx, &p, NULL), 0);
	off.radius = 0.3f;
	assert_int_equal(dao_context_set_params(plain, &off, NULL), 0);
	noisy_plane(mm, w, h, 51);
	process(ctx, mm, w, h, 101, a, za);
	process(plain, mm, w, h, 101, b, zb);
	assert_true(memcmp(za, zb, sizeof za) != 0);
	p.depth_max = 10.0f;
	off.depth_max = 10.0f;
	assert_int_equal(dao_context_set_params(ctx, &p, NULL), 0);
	assert_int_equal(dao_context_set_params(plain, &off, NULL), 0);
	noisy_plane(mm, w, h, 52);
	process(ctx, mm, w, h, 102, a, za);
	process(plain, mm, w, h, 102, b, zb);
	assert_memory_equal(za, zb, sizeof za);
	dao_context_destroy(ctx);
	dao_context_destroy(plain);
}

/* ---- still scenes ------------------------------------------------------- */

enum order { OFF, BEFORE, AFTER };
static const char *const order_name[] = { "off", "before prefilter", "after prefilter" };

struct series {
	double depth_rms[FRAMES];  /* mm, the filter's output alone (BEFORE) or prefiltered */
	double pre_rms[FRAMES];    /* mm, the depth the AO sees (after the prefilter) */
	double mae[FRAMES];        /* AO against the ground truth */
	double flicker[FRAMES];    /* mean |AO(t) - AO(t-1)|, from the second frame */
};

static void camera(struct dao_camera *cam)
{
	dao_camera_from_intrinsics(cam, W, H, 262.5, 262.5, 159.5, 119.5, NULL);
}

static double rms_mm(const float *z, const float *clean, int n)
{
	double e = 0;
	int c = 0;
	for (int i = 0; i < n; i++)
		if (z[i] > 0 && clean[i] > 0) {
			e += (z[i] - clean[i]) * (z[i] - clean[i]);
			c++;
		}
	return 1000.0 * sqrt(e / (c ? c : 1));
}

/*
 * A still scene with sensor noise drawn anew each frame (seeds 100 + f),
 * processed with the filter off, before the prefilter (the pipeline), or
 * after it (prefilter in one context, the filter on its output, the AO from
 * that in a second context without prefilter).  reject_scale scales the
 * rejection threshold of the AFTER order.
 */
/*
 * The prefilter's noise: the fixed model the filter's gains were measured
 * with (bilateral, depth-noise), or the measured noise driving the domain
 * filter (noise-model=auto), measured before the temporal filter.
 */
static void noise_model(struct dao_params *p, int auto_noise)
{
	p->prefilter = auto_noise ? DAO_PREFILTER_DOMAIN : DAO_PREFILTER_BILATERAL;
	p->noise_model = auto_noise ? DAO_NOISE_MODEL_AUTO : DAO_NOISE_MODEL_FIXED;
}

static void run_still(const char *scene, enum order order, float alpha, float reject_scale,
		      int auto_noise, struct series *res)
{
	struct dao_camera cam;
	struct dao_error err;
	camera(&cam);
	struct synth_scene sc;
	struct synth_image img;
	assert_int_equal(synth_scene_build(scene, 0.0, &sc, &err), 0);
	assert_int_equal(synth_render(&sc, &cam, 0.5, 8, 2, &img, &err), 0);
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	noise_model(&p, auto_noise);
	p.threads = 2;
	if (order == BEFORE)
		p.depth_temporal = alpha;
	struct dao_context *ctx, *ao_ctx = NULL;
	assert_int_equal(dao_context_create(&ctx, &cam, &p, &err), 0);
	if (order == AFTER) {
		struct dao_params q = p;
		q.prefilter = DAO_PREFILTER_NONE;
		assert_int_equal(dao_context_create(&ao_ctx, &cam, &q, &err), 0);
	}
	const int n = W * H;
	float *ao = malloc(n * 4), *prev = malloc(n * 4), *z = malloc(n * 4), *zt = malloc(n * 4);
	float *hist = calloc(n, 4);
	uint8_t *count = calloc(n, 1), *age = calloc(n, 1), *prev_hole = calloc(n, 1);
	struct dao_temporal_depth_setup ts = {
		.width = W, .alpha = alpha, .reject = p.depth_temporal_reject * reject_scale,
		.noise_k = p.depth_noise, .quantum = 0.001f,
	};
	for (int f = 0; f < FRAMES; f++) {
		struct synth_case c;
		memset(&c, 0, sizeof c);
		assert_int_equal(synth_case_make(&c, scene, 1, img.depth, img.gt, W, H, 100 + (uint64_t)f,
						 &err), 0);
		struct dao_frame in = { .format = DAO_PIXFMT_DEPTH16, .width = W, .height = H,
				.stride = W * 2, .data = c.depth_mm, .depth_unit = 0.001f};
		struct dao_frame out = { .format = DAO_PIXFMT_GRAY_F32, .width = W, .height = H,
				.stride = W * 4, .data = ao};
		struct dao_frame zf = { .format = DAO_PIXFMT_DEPTH_F32, .width = W, .height = H,
				.stride = W * 4, .data = z};
		assert_int_equal(dao_context_process(ctx, &in, NULL, (uint64_t)f, &out, &err), 0);
		assert_int_equal(dao_context_get_depth(ctx, &zf, &err), 0);
		/* the filter's own output, on the decoded depth */
		memcpy(zt, c.depth_m, n * 4);
		ts.fresh = f == 0;
		dao_temporal_depth_ref(&ts, zt, hist, count, age, 0, H);
		if (order == AFTER) {
			/* the same filter on the prefiltered depth, AO from that */
			memcpy(zt, z, n * 4);
			dao_temporal_depth_ref(&ts, zt, hist, count, age, 0, H);
			struct dao_frame zin = { .format = DAO_PIXFMT_DEPTH_F32, .width = W,
					.height = H, .stride = W * 4, .data = zt};
			assert_int_equal(dao_context_process(ao_ctx, &zin, NULL, (uint64_t)f, &out, &err), 0);
			memcpy(z, zt, n * 4);
		}
		res->depth_rms[f] = rms_mm(order == OFF ? c.depth_m : zt, img.depth, n);
		res->pre_rms[f] = rms_mm(z, img.depth, n);
		double e = 0, d = 0;
		int ne = 0, nd = 0;
		for (int i = 0; i < n; i++) {
			if (!(img.depth[i] > 0) || !c.depth_mm[i])
				continue;
			e += fabs(ao[i] - img.gt[i]);
			ne++;
			if (f > 0 && !prev_hole[i]) {
				d += fabs(ao[i] - prev[i]);
				nd++;
			}
		}
		res->mae[f] = e / ne;
		res->flicker[f] = f > 0 ? d / nd : 0.0;
		memcpy(prev, ao, n * 4);
		for (int i = 0; i < n; i++)
			prev_hole[i] = c.depth_mm[i] == 0;
		synth_case_free(&c);
	}
	dao_context_destroy(ctx);
	dao_context_destroy(ao_ctx);
	synth_image_free(&img);
	free(ao);
	free(prev);
	free(z);
	free(zt);
	free(hist);
	free(count);
	free(age);
	free(prev_hole);
}

/*
 * noise-model=auto: the history's test takes the noise measured in the frame,
 * not depth-noise.  A still plane whose independent noise in 1/z is 4x the
 * model's (0.005 against 0.0012 1/m), redrawn every frame: with the model's
 * noise most samples fail the test and the filter averages nothing; with the
 * measured one the history averages (8 frames: 0.41 of one frame's RMS for
 * Gaussian noise at alpha 0.8, up to rejections).
 */
static double plane_frame(float *z, const float *clean, int n, unsigned *seed, double sigma_w)
{
	double se = 0.0;
	for (int i = 0; i < n; i++) {
		*seed = *seed * 1103515245u + 12345u;
		const double u1 = ((*seed >> 8) + 0.5) / 16777216.0;
		*seed = *seed * 1103515245u + 12345u;
		const double u2 = ((*seed >> 8) + 0.5) / 16777216.0;
		const double g = sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
		z[i] = (float)(1.0 / (1.0 / clean[i] + sigma_w * g));
		se += (z[i] - clean[i]) * (z[i] - clean[i]);
	}
	return sqrt(se / n);
}

static double still_plane_rms(int auto_noise, double *first)
{
	enum { w = 160, h = 120, frames = 8 };
	struct dao_camera cam;
	struct dao_params p;
	struct dao_context *ctx;
	struct dao_error err;
	static float clean[w * h], z[w * h], ao[w * h], out[w * h];
	dao_camera_from_intrinsics(&cam, w, h, 130, 130, 79.5, 59.5, NULL);
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	dao_params_stream_defaults(&p);
	p.prefilter = DAO_PREFILTER_NONE; /* the depth the AO sees is the temporal filter's */
	p.noise_model = auto_noise ? DAO_NOISE_MODEL_AUTO : DAO_NOISE_MODEL_FIXED;
	assert_true(p.depth_noise < 0.002f);
	assert_int_equal(dao_context_create(&ctx, &cam, &p, NULL), 0);
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++)
			clean[y * w + x] = (float)(1.0 / (0.6 + 0.0008 * x + 0.0005 * y));
	unsigned seed = 7;
	double rms = 0.0;
	for (int f = 0; f < frames; f++) {
		const double raw = plane_frame(z, clean, w * h, &seed, 0.005);
		if (f == 0)
			*first = raw;
		struct dao_frame in = { .format = DAO_PIXFMT_DEPTH_F32, .width = w, .height = h,
				.stride = w * 4, .data = z};
		struct dao_frame o = { .format = DAO_PIXFMT_GRAY_F32, .width = w, .height = h,
				.stride = w * 4, .data = ao};
		struct dao_frame zf = { .format = DAO_PIXFMT_DEPTH_F32, .width = w, .height = h,
				.stride = w * 4, .data = out};
		if (dao_context_process(ctx, &in, NULL, (uint64_t)f + 1, &o, &err) ||
		    dao_context_get_depth(ctx, &zf, &err))
			fail_msg("%s", err.message);
		rms = rms_mm(out, clean, w * h) * 1e-3;
	}
	dao_context_destroy(ctx);
	return rms;
}

static void test_measured_noise(void **state)
{
	(void)state;
	double first_fixed, first_auto;
	const double fixed = still_plane_rms(0, &first_fixed);
	const double measured = still_plane_rms(1, &first_auto);
	print_message("still plane, noise 4x the model's, 8 frames: depth RMS %.2f mm -> fixed model "
		      "%.2f mm (%.2f), measured noise %.2f mm (%.2f)\n",
		      first_fixed * 1e3, fixed * 1e3, fixed / first_fixed, measured * 1e3,
		      measured / first_auto);
	assert_true(fixed / first_fixed > 0.7);   /* the fixed model rejects most samples */
	assert_true(measured / first_auto < 0.5); /* the measured noise lets the history average */
}

static double mean_from(const double *v, int f0)
{
	double s = 0;
	for (int f = f0; f < FRAMES; f++)
		s += v[f];
	return s / (FRAMES - f0);
}

static void print_series(const char *scene, const char *what, const struct series *s)
{
	print_message("%-12s %-24s", scene, what);
	const int at[] = { 0, 1, 3, 7, 15 };
	for (int k = 0; k < 5; k++)
		print_message(" | t=%-2d depth %5.2f mm pre %5.2f mm MAE %.4f", at[k] + 1,
			      s->depth_rms[at[k]], s->pre_rms[at[k]], s->mae[at[k]]);
	print_message(" | flicker %.5f\n", mean_from(s->flicker, FRAMES / 2));
}

static void test_still_converges(void **state)
{
	(void)state;
	/* boxes and spheres chose the defaults; room-corner and stairs are held out */
	const char *scenes[] = { "boxes", "spheres", "room-corner", "stairs" };
	for (int k = 0; k < 4; k++) {
		struct series off, on;
		run_still(scenes[k], OFF, ALPHA, 1.0f, 0, &off);
		run_still(scenes[k], BEFORE, ALPHA, 1.0f, 0, &on);
		struct series after, after_scaled;
		run_still(scenes[k], AFTER, ALPHA, 1.0f, 0, &after);
		/* the prefilter cut the noise to pre_rms / depth_rms: a threshold
		 * scaled alike */
		run_still(scenes[k], AFTER, ALPHA, (float)(off.pre_rms[0] / off.depth_rms[0]), 0,
			  &after_scaled);
		print_series(scenes[k], order_name[OFF], &off);
		print_series(scenes[k], order_name[BEFORE], &on);
		print_series(scenes[k], order_name[AFTER], &after);
		print_series(scenes[k], "after, scaled threshold", &after_scaled);
		const double mae_off = mean_from(off.mae, FRAMES / 2), mae_on = mean_from(on.mae, FRAMES / 2);
		const double fl_off = mean_from(off.flicker, FRAMES / 2);
		const double fl_on = mean_from(on.flicker, FRAMES / 2);
		const double mae_after = mean_from(after.mae, FRAMES / 2);
		const double fl_after = mean_from(after.flicker, FRAMES / 2);
		print_message("%-12s settled (frames 9-16): AO MAE off %.4f, before %.4f, after %.4f; "
			      "flicker off %.5f, before %.5f, after %.5f; depth seen by the AO at 16: "
			      "before %.2f mm, after %.2f mm\n", scenes[k], mae_off, mae_on, mae_after,
			      fl_off, fl_on, fl_after, on.pre_rms[FRAMES - 1], after.pre_rms[FRAMES - 1]);
		/* converges: measured 0.39-0.40 of the first frame's RMS at frame 16 */
		assert_true(on.depth_rms[1] < on.depth_rms[0] && on.depth_rms[3] < on.depth_rms[1] &&
			    on.depth_rms[7] < on.depth_rms[3]);
		assert_true(on.depth_rms[FRAMES - 1] <= 0.5 * on.depth_rms[0]);
		/* the AO gains: MAE -0.0012..-0.0028, flicker 0.46-0.71 times */
		assert_true(mae_on <= mae_off - 0.0008);
		assert_true(fl_on <= 0.85 * fl_off);
		/* before the prefilter: the AO sees depth nearer the truth and flickers
		 * less than with the filter after it */
		assert_true(on.pre_rms[FRAMES - 1] < after.pre_rms[FRAMES - 1]);
		assert_true(fl_on < fl_after);
		/* with noise-model=auto (measured before the temporal
		 * filter): MAE -0.0004..-0.0058, flicker 0.34-0.69 times (measured
		 * after it, the prefilter backed off: spheres MAE +0.0001) */
		struct series aoff, aon;
		run_still(scenes[k], OFF, ALPHA, 1.0f, 1, &aoff);
		run_still(scenes[k], BEFORE, ALPHA, 1.0f, 1, &aon);
		const double amae_off = mean_from(aoff.mae, FRAMES / 2);
		const double amae_on = mean_from(aon.mae, FRAMES / 2);
		const double afl_off = mean_from(aoff.flicker, FRAMES / 2);
		const double afl_on = mean_from(aon.flicker, FRAMES / 2);
		print_message("%-12s noise-model=auto, settled: AO MAE off %.4f, on %.4f; flicker off "
			      "%.5f, on %.5f\n", scenes[k], amae_off, amae_on, afl_off, afl_on);
		assert_true(amae_on <= amae_off && afl_on <= 0.85 * afl_off);
	}
}

/* ---- moving objects ------------------------------------------------------ */

#define MOVE_FRAMES 12
#define MOVE_LOOKBACK 4 /* frames whose clean depth defines "recently changed" */

struct moving {
	int w, h;
	float *clean[MOVE_FRAMES], *gt[MOVE_FRAMES];
};

static void moving_render(const char *scene, struct moving *m)
{
	struct dao_camera cam;
	struct dao_error err;
	camera(&cam);
	m->w = W;
	m->h = H;
	for (int f = 0; f < MOVE_FRAMES; f++) {
		struct synth_scene sc;
		struct synth_image img;
		assert_int_equal(synth_scene_build(scene, (double)f / (MOVE_FRAMES - 1), &sc, &err), 0);
		assert_int_equal(synth_render(&sc, &cam, 0.5, 6, 2, &img, &err), 0);
		m->clean[f] = img.depth;
		m->gt[f] = img.gt;
		free(img.normal);
	}
}

static void moving_free(struct moving *m)
{
	for (int f = 0; f < MOVE_FRAMES; f++) {
		free(m->clean[f]);
		free(m->gt[f]);
	}
}

struct moved {
	double trail;     /* share of recently changed pixels > 5 sigma off the clean depth */
	double depth_mae; /* mm there */
	double ao_mae;    /* there */
	double ao_all;    /* AO MAE of the whole frame */
	long pixels;
};

/* A pixel whose clean depth differs from that of one of the last frames by 3 %. */
static int recently_changed(const struct moving *m, int f, int i)
{
	const float z = m->clean[f][i];
	for (int k = 1; k <= MOVE_LOOKBACK && f - k >= 0; k++) {
		const float o = m->clean[f - k][i];
		if ((o > 0) != (z > 0) || fabsf(o - z) > 0.03f * z)
			return 1;
	}
	return 0;
}

/* Frames MOVE_LOOKBACK .. end of the sequence, filter at `alpha` (0 = off). */
static struct moved run_moving(const char *scene, const struct moving *m, float alpha,
			       float reject, int auto_noise)
{
	struct dao_camera cam;
	struct dao_error err;
	camera(&cam);
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	noise_model(&p, auto_noise);
	p.threads = 2;
	p.depth_temporal = alpha;
	p.depth_temporal_reject = reject;
	struct dao_context *ctx;
	assert_int_equal(dao_context_create(&ctx, &cam, &p, &err), 0);
	const int n = W * H;
	float *ao = malloc(n * 4), *z = malloc(n * 4);
	struct moved r = { 0 };
	long all = 0;
	for (int f = 0; f < MOVE_FRAMES; f++) {
		struct synth_case c;
		memset(&c, 0, sizeof c);
		assert_int_equal(synth_case_make(&c, scene, 1, m->clean[f], m->gt[f], W, H,
						 200 + (uint64_t)f, &err), 0);
		struct dao_frame in = { .format = DAO_PIXFMT_DEPTH16, .width = W, .height = H,
				.stride = W * 2, .data = c.depth_mm, .depth_unit = 0.001f};
		struct dao_frame out = { .format = DAO_PIXFMT_GRAY_F32, .width = W, .height = H,
				.stride = W * 4, .data = ao};
		struct dao_frame zf = { .format = DAO_PIXFMT_DEPTH_F32, .width = W, .height = H,
				.stride = W * 4, .data = z};
		assert_int_equal(dao_context_process(ctx, &in, NULL, (uint64_t)f, &out, &err), 0);
		assert_int_equal(dao_context_get_depth(ctx, &zf, &err), 0);
		for (int i = 0; f >= MOVE_LOOKBACK && i < n; i++) {
			const float zc = m->clean[f][i];
			if (!(zc > 0) || !c.depth_mm[i])
				continue;
			r.ao_all += fabs(ao[i] - m->gt[f][i]);
			all++;
			if (!recently_changed(m, f, i))
				continue;
			const double e = fabs(z[i] - zc), sigma = p.depth_noise * zc * zc;
			r.trail += e > 5.0 * sigma;
			r.depth_mae += e;
			r.ao_mae += fabs(ao[i] - m->gt[f][i]);
			r.pixels++;
		}
		synth_case_free(&c);
	}
	dao_context_destroy(ctx);
	free(ao);
	free(z);
	r.trail /= r.pixels;
	r.depth_mae *= 1000.0 / r.pixels;
	r.ao_mae /= r.pixels;
	r.ao_all /= all;
	return r;
}

static void test_moving_no_trails(void **state)
{
	(void)state;
	/* spheres and chair chose the defaults; thin-poles and floating-plate are held out */
	const char *scenes[] = { "spheres", "chair", "thin-poles", "floating-plate" };
	for (int k = 0; k < 4; k++) {
		struct moving m;
		moving_render(scenes[k], &m);
		struct moved off = run_moving(scenes[k], &m, 0.0f, 3.0f, 0);
		struct moved on = run_moving(scenes[k], &m, ALPHA, 3.0f, 0);
		print_message("%-15s moved pixels %6ld: > 5 sigma off %.4f -> %.4f, depth error %.2f -> "
			      "%.2f mm, AO MAE there %.4f -> %.4f, whole frame %.4f -> %.4f\n",
			      scenes[k], off.pixels, off.trail, on.trail, off.depth_mae, on.depth_mae,
			      off.ao_mae, on.ao_mae, off.ao_all, on.ao_all);
		/* no trails: measured 0 pixels > 5 sigma with and without the filter;
		 * the depth error where things moved 0.78-1.19 times that without it
		 * (a surface moving along the view by less than the threshold per
		 * frame lags: the floating plate, held out, +0.7 mm), its AO
		 * -0.0002..+0.0026 */
		assert_true(on.trail <= off.trail + 0.002);
		assert_true(on.depth_mae <= 1.3 * off.depth_mae);
		assert_true(on.ao_mae <= off.ao_mae + 0.004);
		assert_true(on.ao_all <= off.ao_all); /* and the frames as a whole gain */
		if (k == 0) {
			/* the measure sees trails: without the disocclusion test (the
			 * largest threshold) the history smears the moving sphere */
			struct moved blind = run_moving(scenes[k], &m, ALPHA, 100.0f, 0);
			print_message("%-15s without the disocclusion test: > 5 sigma off %.4f, depth "
				      "error %.2f mm\n", scenes[k], blind.trail, blind.depth_mae);
			assert_true(blind.trail >= off.trail + 0.02);
		}
		/* noise-model=auto: no trails either, AO where things
		 * moved -0.0016..+0.0019, the frames gain (noise measured after the
		 * temporal filter: thin poles +0.0084 where they moved) */
		struct moved aoff = run_moving(scenes[k], &m, 0.0f, 3.0f, 1);
		struct moved aon = run_moving(scenes[k], &m, ALPHA, 3.0f, 1);
		print_message("%-15s noise-model=auto: > 5 sigma off %.4f -> %.4f, AO MAE there %.4f "
			      "-> %.4f, whole frame %.4f -> %.4f\n", scenes[k], aoff.trail, aon.trail,
			      aoff.ao_mae, aon.ao_mae, aoff.ao_all, aon.ao_all);
		assert_true(aon.trail <= aoff.trail + 0.002);
		assert_true(aon.ao_mae <= aoff.ao_mae + 0.004);
		assert_true(aon.ao_all <= aoff.ao_all);
		moving_free(&m);
	}
}

/* ---- the real Kinect recording ----------------------------------------- */

#define BLOCK 16
#define REAL_FRAMES 12

/* RMS distance (m, along z) of a block's depth from the least-squares plane of
 * its 1/z (affine in the pixel on any plane); -1 if a pixel has no depth. */
static double block_residual(const float *z, int w, int x0, int y0)
{
	double m[3][3] = { { 0 } }, t[3] = { 0 };
	for (int y = y0; y < y0 + BLOCK; y++)
		for (int x = x0; x < x0 + BLOCK; x++) {
			if (!(z[y * w + x] > 0))
				return -1;
			const double v = 1.0 / z[y * w + x], r[3] = { 1, x - x0, y - y0 };
			for (int i = 0; i < 3; i++) {
				t[i] += r[i] * v;
				for (int j = 0; j < 3; j++)
					m[i][j] += r[i] * r[j];
			}
		}
	/* Cramer's rule */
	double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
		     m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
		     m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
	double c[3];
	for (int k = 0; k < 3; k++) {
		double a[3][3];
		memcpy(a, m, sizeof a);
		for (int i = 0; i < 3; i++)
			a[i][k] = t[i];
		c[k] = (a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
			a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
			a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])) / det;
	}
	double e = 0;
	for (int y = y0; y < y0 + BLOCK; y++)
		for (int x = x0; x < x0 + BLOCK; x++) {
			const double zp = 1.0 / (c[0] + c[1] * (x - x0) + c[2] * (y - y0));
			e += (z[y * w + x] - zp) * (z[y * w + x] - zp);
		}
	return sqrt(e / (BLOCK * BLOCK));
}

/*
 * The Kinect recording (12 consecutive frames, a still scene): the
 * residual of its walls from their planes (16 x 16 blocks beyond 2 m that
 * are planar to 1 % of z in the first frame) by frame, raw and through the
 * filter, and after the prefilter with the filter off and on.  Most of a
 * Kinect's wall residual is its fixed pattern (the same in every frame: a
 * plain mean of all 12 frames leaves 77 % of it), so the filter can only
 * take the part that changes from frame to frame.
 */
static int test_real_kinect(void)
{
	struct dao_oni_reader *rd;
	const struct dao_oni_stream_info *si;
	struct dao_camera cam;
	struct dao_error err;
	int s;
	const int opened = dao_test_open_kinect(&rd, &s, &si, &cam);
	if (opened)
		return opened;
	const int w = (int)si->width, h = (int)si->height, n = w * h;
	/* the filter's gain with the fixed noise model it was measured with;
	 * the stream defaults with noise-model=auto beside them */
	struct dao_params p, d;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.threads = 2;
	d = p;
	noise_model(&d, 1);
	dao_params_stream_defaults(&d);
	noise_model(&p, 0);
	struct dao_context *off, *on, *dflt;
	dao_context_create(&off, &cam, &p, NULL);
	dao_params_stream_defaults(&p);
	dao_context_create(&on, &cam, &p, NULL);
	dao_context_create(&dflt, &cam, &d, NULL);
	uint16_t *mm = malloc((size_t)n * 2);
	float *raw0 = malloc((size_t)n * 4), *raw = malloc((size_t)n * 4), *zt = malloc((size_t)n * 4);
	float *zoff = malloc((size_t)n * 4), *zon = malloc((size_t)n * 4), *hist = calloc(n, 4);
	float *zd = malloc((size_t)n * 4);
	uint8_t *count = calloc(n, 1), *age = calloc(n, 1);
	struct dao_temporal_depth_setup ts = { .width = w, .alpha = p.depth_temporal,
					       .reject = p.depth_temporal_reject,
					       .noise_k = p.depth_noise, .quantum = si->depth_unit };
	double sum_raw = 0, sum_t = 0, sum_off = 0, sum_on = 0, sum_d = 0, first_t = 0;
	for (int f = 0; f < REAL_FRAMES; f++) {
		struct dao_frame in = { .format = DAO_PIXFMT_DEPTH16, .width = si->width,
				.height = si->height, .stride = w * 2, .data = mm};
		struct dao_frame z1 = { .format = DAO_PIXFMT_DEPTH_F32, .width = si->width,
				.height = si->height, .stride = w * 4, .data = zoff};
		struct dao_frame z2 = { .format = DAO_PIXFMT_DEPTH_F32, .width = si->width,
				.height = si->height, .stride = w * 4, .data = zon};
		struct dao_frame z3 = { .format = DAO_PIXFMT_DEPTH_F32, .width = si->width,
				.height = si->height, .stride = w * 4, .data = zd};
		if (dao_oni_reader_read_depth(rd, (uint32_t)s, (uint32_t)f, &in, &err) ||
		    dao_context_process(off, &in, NULL, (uint64_t)f, NULL, &err) ||
		    dao_context_process(on, &in, NULL, (uint64_t)f, NULL, &err) ||
		    dao_context_process(dflt, &in, NULL, (uint64_t)f, NULL, &err) ||
		    dao_context_get_depth(off, &z1, &err) || dao_context_get_depth(on, &z2, &err) ||
		    dao_context_get_depth(dflt, &z3, &err)) {
			printf("FAIL: frame %d: %s\n", f, err.message);
			return 1;
		}
		for (int i = 0; i < n; i++)
			raw[i] = (float)mm[i] * in.depth_unit;
		if (f == 0)
			memcpy(raw0, raw, (size_t)n * 4);
		memcpy(zt, raw, (size_t)n * 4);
		ts.fresh = f == 0;
		dao_temporal_depth_ref(&ts, zt, hist, count, age, 0, h);
		double res[5] = { 0 };
		int blocks = 0;
		for (int y0 = 0; y0 + BLOCK <= h; y0 += BLOCK)
			for (int x0 = 0; x0 + BLOCK <= w; x0 += BLOCK) {
				const double r0 = block_residual(raw0, w, x0, y0);
				const float zc = raw0[(y0 + BLOCK / 2) * w + x0 + BLOCK / 2];
				if (r0 < 0 || zc < 2.0f || r0 > 0.01 * zc)
					continue;
				const double r[5] = { block_residual(raw, w, x0, y0),
						      block_residual(zt, w, x0, y0),
						      block_residual(zoff, w, x0, y0),
						      block_residual(zon, w, x0, y0),
						      block_residual(zd, w, x0, y0) };
				if (r[0] < 0 || r[1] < 0 || r[2] < 0 || r[3] < 0 || r[4] < 0)
					continue;
				for (int k = 0; k < 5; k++)
					res[k] += r[k];
				blocks++;
			}
		for (int k = 0; k < 5; k++)
			res[k] *= 1000.0 / blocks;
		printf("frame %2d: %d wall blocks, residual from their planes: raw %.2f mm, filtered "
		       "%.2f mm; after the prefilter: filter off %.2f mm, on %.2f mm; stream defaults "
		       "%.2f mm\n", f, blocks, res[0], res[1], res[2], res[3], res[4]);
		if (f == 0)
			first_t = res[1];
		if (f >= REAL_FRAMES - 4) { /* settled */
			sum_raw += res[0];
			sum_t += res[1];
			sum_off += res[2];
			sum_on += res[3];
			sum_d += res[4];
		}
	}
	dao_oni_reader_close(rd);
	dao_context_destroy(off);
	dao_context_destroy(on);
	dao_context_destroy(dflt);
	free(zd);
	free(mm);
	free(raw0);
	free(raw);
	free(zt);
	free(zoff);
	free(zon);
	free(hist);
	free(count);
	free(age);
	printf("last 4 frames: filtered / raw %.3f, pipeline on / off %.3f; stream defaults / "
	       "fixed model with the filter %.3f; first frame %.2f mm\n", sum_t / sum_raw,
	       sum_on / sum_off, sum_d / sum_on, first_t);
	/* the measured noise's domain filter takes the walls much further
	 * (measured 0.24 before its side windows; 0.51 with them, which keep
	 * what bends the two-sided fit on the walls' correlated error, while
	 * the AO's false occlusion on these frames' open planes went down,
	 * depthao realcheck) */
	if (sum_d > 0.6 * sum_on) {
		printf("FAIL: with the stream defaults the wall residual is %.3f of the fixed "
		       "model's\n", sum_d / sum_on);
		return 1;
	}
	/* measured 0.82 and 0.885 (a plain mean of all frames reaches 0.77) */
	if (sum_t > 0.87 * sum_raw || sum_on > 0.93 * sum_off) {
		printf("FAIL: the wall residual did not drop enough over the frames\n");
		return 1;
	}
	return 0;
}

int main(int argc, char **argv)
{
	if (argc > 1 && !strcmp(argv[1], "real"))
		return test_real_kinect();
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_kernel_rules),
		cmocka_unit_test(test_context_rules),
		cmocka_unit_test(test_measured_noise),
		cmocka_unit_test(test_moving_no_trails),
		cmocka_unit_test(test_still_converges),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
