/* SPDX-License-Identifier: MIT */
/*
 * noise-interval (src/depth/noise_reuse.h) through the public API: interval
 * 1 measures every frame and each frame's result is its own; with a longer
 * interval the frames between measurements reuse the last one (reported by
 * dao_context_noise, and the same output as measuring again when the frame
 * is the same), the cells an object moves into are measured again, a cut
 * measures everything, a seek, a gap, dao_context_reset and new parameters
 * restart the schedule; and the AO of a moving synthetic sequence, and of
 * the Kinect recording (the argument `real`), stays within a bound of
 * measuring every frame.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/cmocka_all.h"
#include "common/noise_fields.h"
#include "common/test_common.h"

enum { W = 320, H = 240, FRAMES = 30, INTERVAL = 15 };

static struct dao_camera camera(void)
{
	struct dao_camera cam;
	dao_camera_from_intrinsics(&cam, W, H, 262.5, 262.5, 159.5, 119.5, NULL);
	return cam;
}

/* the structured-light or ToF sensor of the sequences */
enum sensor { SL, TOF };

/*
 * Frame f of a moving scene, metres: a floor-to-wall plane (1.4 - 3.5 m)
 * with a box 1.1 m away moving 4 px a frame across it (its sides stand
 * out by 0.25 m), a hole band that shifts too, and the sensor's noise, a
 * new sample each frame: structured light sigma 0.0012 in 1/z (blobs of
 * 1 px), ToF 0.003 m in z (sigma_w = 0.003 w^2).
 */
static void scene_seed(float *z, int f, enum sensor s, float *n, uint64_t seed)
{
	dao_test_correlated_noise(n, W, H, 1.0, s == SL ? 1.0 : 0.0, seed);
	const int bx = 40 + 4 * f, by = 70;
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			double w = 0.5 + 0.0012 * (x - 160) + 0.0008 * (y - 120);
			if (x >= bx && x < bx + 80 && y >= by && y < by + 90)
				w = 1.0 / 1.1;
			const double nw = s == SL ? 0.0012 * n[y * W + x] : 0.003 * w * w * n[y * W + x];
			const int hole = (x + 2 * f) % 97 < 3;
			z[y * W + x] = hole ? 0.0f : (float)(1.0 / (w + nw));
		}
}

static void scene(float *z, int f, enum sensor s, float *n)
{
	scene_seed(z, f, s, n, 100 + (uint64_t)f);
}

static void run(struct dao_context *ctx, const float *z, uint64_t index, float *ao)
{
	struct dao_frame in = { .format = DAO_PIXFMT_DEPTH_F32, .width = W, .height = H,
				.stride = 4 * W, .data = (void *)z };
	struct dao_frame out = { .format = DAO_PIXFMT_GRAY_F32, .width = W, .height = H,
				 .stride = 4 * W, .data = ao };
	struct dao_error err;
	if (dao_context_process(ctx, &in, NULL, index, &out, &err))
		fail_msg("frame %llu: %s", (unsigned long long)index, err.message);
}

static struct dao_context *context(int interval, int stream)
{
	struct dao_camera cam = camera();
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	if (stream)
		dao_params_stream_defaults(&p);
	p.noise_interval = interval;
	p.threads = 2;
	struct dao_context *ctx;
	struct dao_error err;
	if (dao_context_create(&ctx, &cam, &p, &err))
		fail_msg("%s", err.message);
	return ctx;
}

static struct dao_noise_info noise(const struct dao_context *ctx)
{
	struct dao_noise_info ni;
	dao_context_noise(ctx, &ni);
	return ni;
}

/* the measured figures are the same (age and cells measured aside) */
static int same_figures(const struct dao_noise_info *a, const struct dao_noise_info *b)
{
	return a->measured == b->measured && a->sigma_area == b->sigma_area &&
	       a->sigma_link == b->sigma_link && a->sigma_slope == b->sigma_slope &&
	       a->prefilter_scale == b->prefilter_scale && a->normal_radius == b->normal_radius &&
	       a->denoise_noise == b->denoise_noise;
}

/* The defaults: interval 1, every frame measured, each frame's result its
 * own (the same as a new context's on that frame alone); the stream
 * defaults a longer one. */
static void test_interval_one(void **state)
{
	(void)state;
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	assert_int_equal(p.noise_interval, 1);
	dao_params_stream_defaults(&p);
	assert_int_equal(p.noise_interval, INTERVAL);
	float *z = malloc(W * H * 4), *n = malloc(W * H * 4);
	float *ao = malloc(W * H * 4), *ao1 = malloc(W * H * 4);
	struct dao_context *ctx = context(1, 0);
	for (int f = 0; f < 6; f++) {
		scene(z, f, SL, n);
		run(ctx, z, (uint64_t)f, ao);
		const struct dao_noise_info ni = noise(ctx);
		assert_int_equal(ni.measured, 1);
		assert_int_equal(ni.age, 0);
		assert_int_equal(ni.cells_measured, 0);
		struct dao_context *one = context(1, 0);
		run(one, z, (uint64_t)f, ao1);
		assert_memory_equal(ao, ao1, W * H * 4);
		dao_context_destroy(one);
	}
	dao_context_destroy(ctx);
	free(z);
	free(n);
	free(ao);
	free(ao1);
}

/*
 * A still scene, a new noise sample each frame: frames 0, 1, 2, 4, 8 of
 * the schedule are measured, the others reuse the last measurement, with
 * its figures; a frame the same as the measured one before it comes out
 * as measuring it again would make it; a new noise sample does not.
 */
static void test_reuse(void **state)
{
	(void)state;
	float *z = malloc(W * H * 4), *n = malloc(W * H * 4);
	float *ao = malloc(W * H * 4), *ao1 = malloc(W * H * 4);
	struct dao_context *ctx = context(INTERVAL, 0), *every = context(1, 0);
	struct dao_noise_info last = { 0 };
	int last_f = 0;
	for (int f = 0; f < 20; f++) {
		scene_seed(z, 0, SL, n, 100 + (uint64_t)f); /* frame 0, frame f's noise */
		run(ctx, z, (uint64_t)f, ao);
		run(every, z, (uint64_t)f, ao1);
		const struct dao_noise_info ni = noise(ctx), n1 = noise(every);
		const int measured = f == 0 || f == 1 || f == 2 || f == 4 || f == 8 || f == 16;
		assert_int_equal(ni.cells_measured, 0);
		if (measured) {
			assert_int_equal(ni.age, 0);
			assert_true(same_figures(&ni, &n1));
			assert_memory_equal(ao, ao1, W * H * 4);
			last = ni, last_f = f;
		} else {
			assert_int_equal(ni.age, f - last_f);
			assert_true(same_figures(&ni, &last));
			assert_false(same_figures(&ni, &n1)); /* another noise sample: other figures */
		}
	}
	/* the frame measured last (16) again, as frame 20: the same output as
	 * measuring it */
	scene_seed(z, 0, SL, n, 116);
	run(ctx, z, 20, ao);
	run(every, z, 20, ao1);
	assert_int_equal(noise(ctx).age, 4);
	assert_memory_equal(ao, ao1, W * H * 4);
	dao_context_destroy(ctx);
	dao_context_destroy(every);
	free(z);
	free(n);
	free(ao);
	free(ao1);
}

/* The moving box: the cells it enters and leaves are measured again, the
 * rest reused; a cut (everything nearer) measures all. */
static void test_scene_moves(void **state)
{
	(void)state;
	float *z = malloc(W * H * 4), *n = malloc(W * H * 4), *ao = malloc(W * H * 4);
	struct dao_context *ctx = context(INTERVAL, 1);
	int again = 0, reused = 0;
	for (int f = 0; f < 12; f++) {
		scene(z, f, TOF, n);
		run(ctx, z, (uint64_t)f, ao);
		const struct dao_noise_info ni = noise(ctx);
		assert_int_equal(ni.measured, 1);
		if (getenv("DAO_TEST_VERBOSE"))
			print_message("frame %d: age %d, cells measured %d\n", f, ni.age,
				      ni.cells_measured);
		if (ni.age > 0) {
			/* the box's two vertical edges move through a column of cells
			 * each (about 3 cells tall) in 8 frames: a few cells, never
			 * most of the 10 x 8 */
			assert_true(ni.cells_measured <= 12);
			again += ni.cells_measured, reused++;
		}
	}
	assert_true(reused >= 6 && again > 0);
	/* a cut: everything 30 % nearer */
	scene(z, 12, TOF, n);
	for (int i = 0; i < W * H; i++)
		z[i] *= 0.7f;
	run(ctx, z, 12, ao);
	assert_int_equal(noise(ctx).age, 0);
	/* the schedule restarted there: 13 and 14 measured too, 15 not */
	run(ctx, z, 13, ao);
	assert_int_equal(noise(ctx).age, 0);
	run(ctx, z, 14, ao);
	assert_int_equal(noise(ctx).age, 0);
	run(ctx, z, 15, ao);
	assert_int_equal(noise(ctx).age, 1);
	dao_context_destroy(ctx);
	free(z);
	free(n);
	free(ao);
}

/* A seek, a gap, the same index, dao_context_reset and new parameters
 * restart the schedule: the next frame is measured. */
static void test_restarts(void **state)
{
	(void)state;
	float *z = malloc(W * H * 4), *n = malloc(W * H * 4), *ao = malloc(W * H * 4);
	struct dao_context *ctx = context(INTERVAL, 1);
	scene(z, 0, SL, n);
	uint64_t f = 100;
	for (int k = 0; k < 3; k++)
		run(ctx, z, f++, ao);
	run(ctx, z, f, ao);
	assert_int_equal(noise(ctx).age, 1); /* measured at 0, 1, 2, 4 of the schedule */
	/* a step back (a seek) */
	run(ctx, z, 50, ao);
	assert_int_equal(noise(ctx).age, 0);
	for (f = 51; f < 54; f++)
		run(ctx, z, f, ao);
	assert_int_equal(noise(ctx).age, 1);
	run(ctx, z, f + DAO_TEMPORAL_MAX_GAP + 1, ao); /* a gap */
	assert_int_equal(noise(ctx).age, 0);
	f += DAO_TEMPORAL_MAX_GAP + 1;
	run(ctx, z, f, ao); /* the same index */
	assert_int_equal(noise(ctx).age, 0);
	for (int k = 0; k < 3; k++)
		run(ctx, z, ++f, ao);
	assert_int_equal(noise(ctx).age, 1);
	dao_context_reset(ctx);
	run(ctx, z, ++f, ao);
	assert_int_equal(noise(ctx).age, 0);
	for (int k = 0; k < 3; k++)
		run(ctx, z, ++f, ao);
	assert_int_equal(noise(ctx).age, 1);
	struct dao_params p;
	dao_context_get_params(ctx, &p);
	p.radius = 0.4f;
	assert_int_equal(dao_context_set_params(ctx, &p, NULL), 0);
	run(ctx, z, ++f, ao);
	assert_int_equal(noise(ctx).age, 0);
	dao_context_destroy(ctx);
	free(z);
	free(n);
	free(ao);
}

/* MAE and largest difference of two AO planes over the pixels with depth */
static void ao_diff(const float *a, const float *b, const float *z, double *mae, double *max)
{
	double s = 0;
	int n = 0;
	*max = 0;
	for (int i = 0; i < W * H; i++) {
		if (!(z[i] > 0.0f))
			continue;
		const double d = fabs((double)a[i] - b[i]);
		s += d, n++;
		*max = d > *max ? d : *max;
	}
	*mae = s / n;
}

/*
 * The moving sequences with the stream defaults, measured every frame and
 * every INTERVAL frames: the AO differs by far less than a new noise sample
 * changes it (the MAE between the AO of two noise samples of the same
 * frame, measured every frame), the scale of what the sensor's noise alone
 * does to a frame's AO; DAO_TEST_VERBOSE=1 prints each frame.  (The frame's
 * medians are the last full measurement's: the ToF box hides more or less
 * of the far plane as it moves, and their every-frame value drifts by up to
 * 15 % over 13 frames; the cells the box enters are measured again.)
 */
static void test_moving_sequence(void **state)
{
	(void)state;
	float *z = malloc(W * H * 4), *z2 = malloc(W * H * 4), *n = malloc(W * H * 4);
	float *ao = malloc(W * H * 4), *ao1 = malloc(W * H * 4), *ao2 = malloc(W * H * 4);
	for (int s = SL; s <= TOF; s++) {
		struct dao_context *sched = context(INTERVAL, 1), *every = context(1, 1);
		struct dao_context *alone = context(1, 0);
		double sum = 0, max = 0, noise_mae = 0, noise_max = 0;
		for (int f = 0; f < FRAMES; f++) {
			scene(z, f, (enum sensor)s, n);
			run(sched, z, (uint64_t)f, ao);
			run(every, z, (uint64_t)f, ao1);
			double mae, mx;
			ao_diff(ao, ao1, z, &mae, &mx);
			sum += mae;
			max = mx > max ? mx : max;
			if (getenv("DAO_TEST_VERBOSE")) {
				const struct dao_noise_info a = noise(sched), b = noise(every);
				print_message("  frame %2d: age %d cells %2d  MAE %.5f max %.4f  area %.5f/%.5f "
					      "link %.5f/%.5f slope %.5f/%.5f\n", f, a.age,
					      a.cells_measured, mae, mx, a.sigma_area, b.sigma_area,
					      a.sigma_link, b.sigma_link, a.sigma_slope, b.sigma_slope);
			}
			/* what a new noise sample does: frame f with another noise
			 * sample, each alone */
			scene_seed(z2, f, (enum sensor)s, n, 5000 + (uint64_t)f);
			run(alone, z, 0, ao1);
			run(alone, z2, 0, ao2);
			ao_diff(ao1, ao2, z, &mae, &mx);
			noise_mae += mae;
			noise_max = mx > noise_max ? mx : noise_max;
		}
		print_message("%s: AO with noise-interval %d against 1: MAE %.5f, max %.4f over %d "
			      "frames; a new noise sample: MAE %.5f, max %.4f\n",
			      s == SL ? "structured light" : "ToF", INTERVAL, sum / FRAMES, max, FRAMES,
			      noise_mae / FRAMES, noise_max);
		/* measured: 0.13 (structured light) and 0.25 (ToF) of a new sample's MAE
		 * (the largest pixel is of the same order as a new sample's: single
		 * pixels at the box's edges, where the side windows decide) */
		assert_true(sum < 0.35 * noise_mae);
		dao_context_destroy(sched);
		dao_context_destroy(every);
		dao_context_destroy(alone);
	}
	free(z);
	free(z2);
	free(n);
	free(ao);
	free(ao1);
	free(ao2);
}

/*
 * The Kinect recording (12 frames, a still scene, 640 x 480) with the
 * stream defaults, noise-interval 15 against 1: the AO differs by less than
 * a third of what consecutive frames of the still scene differ by
 * (measured every frame: the sensor's noise from frame to frame).
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
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	dao_params_stream_defaults(&p);
	p.threads = 2;
	struct dao_context *sched, *every;
	dao_context_create(&sched, &cam, &p, NULL);
	p.noise_interval = 1;
	dao_context_create(&every, &cam, &p, NULL);
	uint16_t *mm = malloc((size_t)n * 2);
	float *a = malloc((size_t)n * 4), *b = malloc((size_t)n * 4), *prev = malloc((size_t)n * 4);
	double sum = 0, max = 0, step = 0;
	int frames = 0, fail = 0;
	for (uint32_t f = 0; f < si->frame_count; f++) {
		struct dao_frame in = { .format = DAO_PIXFMT_DEPTH16, .width = si->width,
				.height = si->height, .stride = w * 2, .data = mm};
		struct dao_frame oa = { .format = DAO_PIXFMT_GRAY_F32, .width = si->width,
				.height = si->height, .stride = w * 4, .data = a};
		struct dao_frame ob = { .format = DAO_PIXFMT_GRAY_F32, .width = si->width,
				.height = si->height, .stride = w * 4, .data = b};
		if (dao_oni_reader_read_depth(rd, (uint32_t)s, f, &in, &err) ||
		    dao_context_process(sched, &in, NULL, f, &oa, &err) ||
		    dao_context_process(every, &in, NULL, f, &ob, &err)) {
			printf("FAIL: frame %u: %s\n", f, err.message);
			return 1;
		}
		struct dao_noise_info ni;
		dao_context_noise(sched, &ni);
		double d = 0, mx = 0, ds = 0;
		int valid = 0;
		for (int i = 0; i < n; i++) {
			if (!mm[i])
				continue;
			const double e = fabs((double)a[i] - b[i]);
			d += e, valid++;
			mx = e > mx ? e : mx;
			ds += fabs((double)b[i] - prev[i]);
		}
		printf("frame %2u: age %d, cells measured %2d: AO against every frame MAE %.5f, max %.4f; "
		       "against the frame before %.5f\n", f, ni.age, ni.cells_measured, d / valid, mx,
		       f ? ds / valid : 0.0);
		sum += d / valid, max = mx > max ? mx : max;
		if (f)
			step += ds / valid;
		frames++;
		memcpy(prev, b, (size_t)n * 4);
	}
	printf("noise-interval 15 against 1: AO MAE %.5f, max %.4f over %d frames; consecutive frames "
	       "(measured every frame) differ by %.5f\n", sum / frames, max, frames, step / (frames - 1));
	if (!(sum / frames < step / (frames - 1) / 3)) {
		printf("FAIL: more than a third of the frame-to-frame change\n");
		fail = 1;
	}
	dao_oni_reader_close(rd);
	dao_context_destroy(sched);
	dao_context_destroy(every);
	free(mm);
	free(a);
	free(b);
	free(prev);
	return fail;
}

int main(int argc, char **argv)
{
	if (argc > 1 && strcmp(argv[1], "real") == 0)
		return test_real_kinect();
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_interval_one),
		cmocka_unit_test(test_reuse),
		cmocka_unit_test(test_scene_moves),
		cmocka_unit_test(test_restarts),
		cmocka_unit_test(test_moving_sequence),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
