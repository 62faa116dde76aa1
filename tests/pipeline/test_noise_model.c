/* SPDX-License-Identifier: MIT */
/*
 * noise-model and prefilter=domain through the public API: the context
 * reports the noise it measured and the settings it gave, the domain filter
 * flattens a noisy plane in the pipeline, the settings can change while a
 * stream runs, and frames with nothing to measure fall back to the model.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/cmocka_all.h"
#include "common/noise_fields.h"
#include "common/test_common.h"

enum { W = 320, H = 240 };

static struct dao_camera camera(void)
{
	struct dao_camera cam;
	dao_camera_from_intrinsics(&cam, W, H, 262.5, 262.5, 159.5, 119.5, NULL);
	return cam;
}

/* 1/z of a tilted plane, 1.4 m to 3.5 m */
static double plane_w(int x, int y)
{
	return 0.5 + 0.0012 * (x - 160) + 0.0008 * (y - 120);
}

/* metres: the plane with noise of sigma in 1/z (blur px correlation) */
static void noisy_plane(float *z, double sigma, double blur, uint64_t seed)
{
	float *n = malloc(W * H * sizeof(float));
	assert_non_null(n);
	dao_test_correlated_noise(n, W, H, sigma, blur, seed);
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++)
			z[y * W + x] = (float)(1.0 / (plane_w(x, y) + n[y * W + x]));
	free(n);
}

/* RMS in 1/z of z against the plane, away from the border */
static double plane_rms(const float *z)
{
	double s = 0;
	int n = 0;
	for (int y = 8; y < H - 8; y++)
		for (int x = 8; x < W - 8; x++) {
			const double e = 1.0 / z[y * W + x] - plane_w(x, y);
			s += e * e, n++;
		}
	return sqrt(s / n);
}

static void process(struct dao_context *ctx, float *z, float *filtered, float *ao)
{
	struct dao_frame in = { .format = DAO_PIXFMT_DEPTH_F32, .width = W, .height = H,
				.stride = 4 * W, .data = z };
	struct dao_frame out = { .format = DAO_PIXFMT_GRAY_F32, .width = W, .height = H,
				 .stride = 4 * W, .data = ao };
	struct dao_frame f = { .format = DAO_PIXFMT_DEPTH_F32, .width = W, .height = H,
			       .stride = 4 * W, .data = filtered };
	struct dao_error err;
	if (dao_context_process(ctx, &in, NULL, 0, &out, &err) ||
	    dao_context_get_depth(ctx, &f, &err))
		fail_msg("%s", err.message);
}

/* The measured noise, what it drives, and the plane coming out flat. */
static void test_auto(void **state)
{
	(void)state;
	struct dao_camera cam = camera();
	float *z = malloc(W * H * 4), *zf = malloc(W * H * 4), *ao = malloc(W * H * 4);
	const double sigma = 0.0012;
	noisy_plane(z, sigma, 0.0, 5);
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.threads = 2;
	p.prefilter = DAO_PREFILTER_DOMAIN;
	p.noise_model = DAO_NOISE_MODEL_AUTO;
	p.depth_noise = 0.05f; /* far off: must not be used */
	struct dao_context *ctx;
	assert_int_equal(dao_context_create(&ctx, &cam, &p, NULL), 0);
	process(ctx, z, zf, ao);
	struct dao_noise_info ni;
	dao_context_noise(ctx, &ni);
	const double before = plane_rms(z), after = plane_rms(zf);
	print_message("auto: area %.3f sigma, link %.3f sigma, slope %.3f sigma, scale %.2f px, "
		      "normal radius %d, plane RMS %.2e -> %.2e in 1/z\n", ni.sigma_area / sigma,
		      ni.sigma_link / sigma, ni.sigma_slope / sigma, (double)ni.prefilter_scale,
		      ni.normal_radius, before, after);
	assert_int_equal(ni.measured, 1);
	assert_true(fabs(ni.sigma_area / sigma - 1) < 0.05 && fabs(ni.sigma_link / sigma - 1) < 0.05);
	assert_true(fabs(ni.sigma_slope / sigma - 1) < 0.05);
	assert_true(ni.denoise_noise == ni.sigma_area);
	assert_true(ni.prefilter_scale >= 1.0f && ni.prefilter_scale <= 16.0f);
	assert_true(ni.normal_radius >= 1 && ni.normal_radius <= 8);
	/* independent noise at this depth and focal length: sigma_s 1.31 px (the
	 * mapping keeps small scales for it, noise_estimate.h), RMS 2.76x down */
	assert_true(after < before / 2.4);
	/* open ground: the AO of a plane is 1 */
	double occ = 0;
	for (int i = 0; i < W * H; i++)
		occ += 1.0 - ao[i];
	print_message("auto: mean occlusion of the plane %.4f\n", occ / (W * H));
	assert_true(occ / (W * H) < 0.01);

	/* auto-prefilter: the normals and the denoise keep the parameters */
	p.noise_model = DAO_NOISE_MODEL_AUTO_PREFILTER;
	assert_int_equal(dao_context_set_params(ctx, &p, NULL), 0);
	process(ctx, z, zf, ao);
	dao_context_noise(ctx, &ni);
	assert_int_equal(ni.measured, 1);
	assert_int_equal(ni.normal_radius, p.normal_radius);
	assert_true(ni.denoise_noise == p.depth_noise);

	/* fixed: the parameters, nothing measured */
	p.noise_model = DAO_NOISE_MODEL_FIXED;
	assert_int_equal(dao_context_set_params(ctx, &p, NULL), 0);
	process(ctx, z, zf, ao);
	dao_context_noise(ctx, &ni);
	assert_int_equal(ni.measured, 0);
	assert_true(ni.sigma_area == p.depth_noise && ni.prefilter_scale == p.prefilter_scale);
	dao_context_destroy(ctx);
	free(z);
	free(zf);
	free(ao);
}

/* A context made for the bilateral filter switches to the domain filter
 * and the measured noise while running (buffers made at the change). */
static void test_switch_while_running(void **state)
{
	(void)state;
	struct dao_camera cam = camera();
	float *z = malloc(W * H * 4), *zf = malloc(W * H * 4), *zf2 = malloc(W * H * 4);
	float *ao = malloc(W * H * 4);
	noisy_plane(z, 0.002, 1.0, 9);
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	struct dao_context *ctx;
	assert_int_equal(dao_context_create(&ctx, &cam, &p, NULL), 0);
	process(ctx, z, zf, ao);
	struct dao_error err;
	assert_int_equal(dao_params_set(&p, "prefilter", "domain", &err), 0);
	assert_int_equal(dao_params_set(&p, "noise-model", "auto", &err), 0);
	assert_int_equal(dao_params_set(&p, "threads", "3", &err), 0);
	if (dao_context_set_params(ctx, &p, &err))
		fail_msg("%s", err.message);
	process(ctx, z, zf2, ao);
	/* a fresh context with the same settings gives the same depth */
	struct dao_context *fresh;
	assert_int_equal(dao_context_create(&fresh, &cam, &p, NULL), 0);
	process(fresh, z, zf, ao);
	assert_memory_equal(zf, zf2, W * H * 4);
	dao_context_destroy(fresh);
	dao_context_destroy(ctx);
	free(z);
	free(zf);
	free(zf2);
	free(ao);
}

/* Nothing to measure (no 8x8 block without holes): the model's settings,
 * and the frame still comes out. */
static void test_nothing_to_measure(void **state)
{
	(void)state;
	struct dao_camera cam = camera();
	float *z = malloc(W * H * 4), *zf = malloc(W * H * 4), *ao = malloc(W * H * 4);
	noisy_plane(z, 0.0012, 0.0, 3);
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++)
			if ((x % 6) == 0 || (y % 6) == 0)
				z[y * W + x] = 0.0f;
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.prefilter = DAO_PREFILTER_DOMAIN;
	p.noise_model = DAO_NOISE_MODEL_AUTO;
	struct dao_context *ctx;
	assert_int_equal(dao_context_create(&ctx, &cam, &p, NULL), 0);
	process(ctx, z, zf, ao);
	struct dao_noise_info ni;
	dao_context_noise(ctx, &ni);
	assert_int_equal(ni.measured, 0);
	assert_true(ni.sigma_area == p.depth_noise);
	for (int i = 0; i < W * H; i++) {
		assert_true(ao[i] >= 0.0f && ao[i] <= 1.0f);
		assert_true((zf[i] == 0.0f) == (z[i] == 0.0f)); /* holes stay holes, none added */
	}
	dao_context_destroy(ctx);
	free(z);
	free(zf);
	free(ao);
}

/* Any frame size, down to one pixel, through every kernel set: the SIMD
 * passes hand lines narrower than a vector to the reference. */
static void test_small_frames(void **state)
{
	(void)state;
	static const int sizes[][2] = { { 1, 1 }, { 3, 2 }, { 7, 5 }, { 17, 9 }, { 33, 20 }, { 40, 70 } };
	for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
		const int w = sizes[k][0], h = sizes[k][1];
		float *z = malloc(sizeof(float) * w * h), *ao = malloc(sizeof(float) * w * h);
		float *ref = malloc(sizeof(float) * w * h), *zf = malloc(sizeof(float) * w * h);
		uint64_t seed = 1;
		for (int i = 0; i < w * h; i++)
			z[i] = i % 11 == 3 ? 0.0f : (float)(2.0 + 0.003 * dao_test_gauss(&seed));
		struct dao_camera cam;
		assert_int_equal(dao_camera_from_intrinsics(&cam, w, h, 50, 50, 0.5 * (w - 1), 0.5 * (h - 1), NULL), 0);
		struct dao_frame in = { .format = DAO_PIXFMT_DEPTH_F32, .width = w, .height = h,
					.stride = 4 * w, .data = z };
		struct dao_frame out = { .format = DAO_PIXFMT_GRAY_F32, .width = w, .height = h,
					 .stride = 4 * w, .data = ao };
		for (int simd = DAO_SIMD_REFERENCE; simd < DAO_SIMD_COUNT; simd++) {
			if (!dao_simd_supported((enum dao_simd)simd))
				continue;
			struct dao_params p;
			dao_params_init(&p, DAO_QUALITY_DEFAULT);
			p.prefilter = DAO_PREFILTER_DOMAIN;
			p.noise_model = DAO_NOISE_MODEL_AUTO;
			p.simd = simd;
			struct dao_context *ctx;
			struct dao_error err;
			assert_int_equal(dao_context_create(&ctx, &cam, &p, NULL), 0);
			if (dao_context_process(ctx, &in, NULL, 0, &out, &err))
				fail_msg("%dx%d: %s", w, h, err.message);
			struct dao_frame f = { .format = DAO_PIXFMT_DEPTH_F32, .width = w, .height = h,
					       .stride = 4 * w, .data = simd == DAO_SIMD_REFERENCE ? ref : zf };
			assert_int_equal(dao_context_get_depth(ctx, &f, NULL), 0);
			for (int i = 0; i < w * h; i++) {
				assert_true(ao[i] >= 0.0f && ao[i] <= 1.0f);
				assert_true((((float *)f.data)[i] == 0.0f) == (z[i] == 0.0f));
				if (simd != DAO_SIMD_REFERENCE && fabsf(zf[i] - ref[i]) > 1e-5f * ref[i])
					fail_msg("%dx%d %s: depth %g, reference %g at %d", w, h,
						 dao_simd_name((enum dao_simd)simd), (double)zf[i],
						 (double)ref[i], i);
			}
			dao_context_destroy(ctx);
		}
		free(z);
		free(ao);
		free(ref);
		free(zf);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_auto),
		cmocka_unit_test(test_switch_while_running),
		cmocka_unit_test(test_nothing_to_measure),
		cmocka_unit_test(test_small_frames),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
