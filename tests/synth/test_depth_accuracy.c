/* SPDX-License-Identifier: MIT */
/*
 * The measures of `depthao eval --depth` on hand-made frames whose answers
 * are known (synth/depth_accuracy.h), the librealsense-style reference
 * chain's stages and the crude 9 x 9 anchor on hand-made inputs
 * (synth/rs_reference.h, depth_box_mean), and depthao's
 * own filter against the truth on a noisy plane.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <depthao/depthao.h>

#include "synth/depth_accuracy.h"
#include "synth/rs_reference.h"

#define W 32
#define H 24

/* Left half at 1 m, right half at 2 m: a discontinuity between columns 15 and 16. */
static void step(float *z)
{
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++)
			z[y * W + x] = x < W / 2 ? 1.0f : 2.0f;
}

static void test_edge_distance(void **state)
{
	(void)state;
	float t[W * H];
	uint8_t d[W * H];
	step(t);
	depth_acc_edge_distance(t, W, H, d);
	assert_int_equal(d[5 * W + 15], 0);
	assert_int_equal(d[5 * W + 16], 0);
	assert_int_equal(d[5 * W + 12], 3);
	assert_int_equal(d[5 * W + 19], 3);
	assert_int_equal(d[5 * W + 0], 15);
	/* a slope of 2 % per pixel is no discontinuity */
	for (int i = 0; i < W * H; i++)
		t[i] = 1.0f + 0.02f * (float)(i % W);
	depth_acc_edge_distance(t, W, H, d);
	for (int i = 0; i < W * H; i++)
		assert_int_equal(d[i], 255);
}

static void test_errors_and_fill(void **state)
{
	(void)state;
	float t[W * H], r[W * H], f[W * H];
	uint8_t d[W * H];
	step(t);
	depth_acc_edge_distance(t, W, H, d);
	for (int i = 0; i < W * H; i++) {
		r[i] = t[i] + 0.004f;    /* raw 4 mm off */
		f[i] = t[i] + 0.001f;    /* filtered 1 mm off */
	}
	/* holes in the raw depth: one filled right (5 mm), one wrong (2 cm), one left empty */
	r[3 * W + 2] = r[3 * W + 3] = r[3 * W + 4] = 0.0f;
	f[3 * W + 2] = 1.005f;
	f[3 * W + 3] = 1.02f;
	f[3 * W + 4] = 0.0f;
	/* a pixel the filter emptied, and one pixel with no truth (ignored) */
	f[7 * W + 2] = 0.0f;
	t[9 * W + 2] = 0.0f;
	depth_acc_edge_distance(t, W, H, d);
	struct depth_acc acc = { 0 };
	depth_acc_add(t, r, f, d, W, H, &acc);
	assert_int_equal(acc.filled, 2);
	assert_int_equal(acc.filled_ok, 1);
	assert_int_equal(acc.dropped, 1);
	/* every pixel with truth and raw depth but the emptied one */
	const long n = acc.raw_in.n + acc.raw_edge.n;
	assert_int_equal(n, W * H - 3 - 1 - 1);
	assert_true(fabs(depth_err_mae(&acc.raw_in) - 0.004) < 1e-6);
	assert_true(fabs(depth_err_mae(&acc.filt_in) - 0.001) < 1e-6);
	assert_true(fabs(depth_err_rmse(&acc.raw_edge) - 0.004) < 1e-6);
	assert_true(fabs(depth_acc_reduction(&acc.raw_in, &acc.filt_in) - 0.75) < 1e-3);
	assert_int_equal(acc.fly_raw, 0);
	assert_int_equal(acc.fly_filt, 0);
}

static void test_flying_created(void **state)
{
	(void)state;
	float t[W * H], r[W * H], f[W * H];
	uint8_t d[W * H];
	step(t);
	depth_acc_edge_distance(t, W, H, d);
	memcpy(r, t, sizeof r);
	memcpy(f, t, sizeof f);
	f[4 * W + 15] = 1.5f;   /* between the two surfaces: created */
	f[4 * W + 16] = 1.5f;
	r[6 * W + 16] = 1.5f;   /* flying in raw already, kept */
	f[6 * W + 16] = 1.5f;
	f[6 * W + 5] = 1.5f;    /* off the surface but far from the edge: not in the band */
	struct depth_acc acc = { 0 };
	depth_acc_add(t, r, f, d, W, H, &acc);
	assert_int_equal(acc.fly_created, 2);
	assert_int_equal(acc.fly_filt, 3);
	assert_int_equal(acc.fly_raw, 1);
	assert_int_equal(acc.fly_px, 6 * H);
}

static void test_plane_residual(void **state)
{
	(void)state;
	struct dao_camera cam;
	assert_int_equal(dao_camera_from_intrinsics(&cam, W, H, 30.0, 30.0, 15.5, 11.5, NULL), 0);
	float z[W * H];
	uint8_t m[W * H];
	/* the plane 1/z = 0.5 + 0.1 x' - 0.05 y', exactly, then +-2 mm in a checkerboard */
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			const double w = 0.5 + 0.1 * (x - 15.5) / 30.0 - 0.05 * (y - 11.5) / 30.0;
			z[y * W + x] = (float)(1.0 / w);
			m[y * W + x] = 1;
		}
	double rms;
	long n;
	assert_int_equal(depth_plane_residual(z, m, &cam, &rms, &n), 0);
	assert_int_equal(n, W * H);
	assert_true(rms < 1e-5);
	for (int i = 0; i < W * H; i++)
		z[i] += ((i % W + i / W) % 2) ? 0.002f : -0.002f;
	assert_int_equal(depth_plane_residual(z, m, &cam, &rms, &n), 0);
	assert_true(fabs(rms - 0.002) < 2e-4);
	memset(m, 0, sizeof m);
	m[0] = m[1] = 1;
	assert_int_equal(depth_plane_residual(z, m, &cam, &rms, &n), -1);
}

/* The crude 9 x 9 anchor: a step stays a step, a hole a hole, and a
 * checkerboard of +-5 mm on a plane at 1 m averages out away from the border. */
static void test_box_mean(void **state)
{
	(void)state;
	float z[W * H], out[W * H];
	step(z);
	z[5 * W + 5] = 0.0f;
	depth_box_mean(z, out, W, H);
	for (int i = 0; i < W * H; i++)
		assert_true(out[i] == z[i]); /* each side one value, the other side > 3 % off */
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++)
			z[y * W + x] = 1.0f + ((x + y) & 1 ? 0.005f : -0.005f);
	depth_box_mean(z, out, W, H);
	/* 81 pixels, 41 of one sign: |mean - 1| = 0.01 / 81 */
	for (int y = 4; y < H - 4; y++)
		for (int x = 4; x < W - 4; x++)
			assert_true(fabsf(out[y * W + x] - 1.0f) < 0.01f / 81.0f + 1e-6f);
}

static void test_reference_spatial(void **state)
{
	(void)state;
	/* one row: the moving average crosses 100 -> 110 (< delta 20), not 110 -> 200 */
	float d[3] = { 100.0f, 110.0f, 200.0f };
	rs_ref_spatial(d, 3, 1, 0.5f, 20.0f, 1);
	assert_true(fabsf(d[0] - 102.5f) < 1e-4f);
	assert_true(fabsf(d[1] - 105.0f) < 1e-4f);
	assert_true(fabsf(d[2] - 200.0f) < 1e-4f);
	/* a hole stops the average */
	float e[3] = { 100.0f, 0.0f, 110.0f };
	rs_ref_spatial(e, 3, 1, 0.5f, 20.0f, 2);
	assert_true(e[0] == 100.0f && e[1] == 0.0f && e[2] == 110.0f);
}

static void test_reference_hole_fill(void **state)
{
	(void)state;
	/* the centre takes its farthest 4-neighbour (3), not the farther diagonal (9) */
	float z[9] = { 9, 1, 9, 3, 0, 1.5f, 9, 2, 9 };
	rs_ref_hole_fill_farthest(z, 3, 3);
	assert_true(z[4] == 3.0f);
}

static void test_reference_temporal(void **state)
{
	(void)state;
	struct rs_ref r;
	struct rs_ref_options o;
	struct dao_error err;
	rs_ref_options_default(&o);
	o.spatial_iterations = 0;
	o.hole_fill = 0;
	assert_int_equal(rs_ref_init(&r, &o, 2, 1, 525.0, &err), 0);
	const float k = (float)(525.0 * RS_REF_BASELINE * RS_REF_SUBPIXEL);
	float out[2];
	/* pixel 0 has depth in frames 1 and 2, pixel 1 only in frame 2 */
	const float f1[2] = { 2.0f, 0.0f }, f2[2] = { 2.0f, 3.0f }, f3[2] = { 0.0f, 0.0f };
	rs_ref_process(&r, f1, out);
	rs_ref_process(&r, f2, out);
	assert_true(fabsf(out[0] - 2.0f) < 1e-4f);
	assert_true(fabsf(out[1] - 3.0f) < 1e-4f);
	/* frame 2 of pixel 0: the disparity moved by 0.5 levels (< delta): 0.4 new, 0.6 old */
	const float f2b[2] = { k / (k / 2.0f + 0.5f), 3.0f };
	rs_ref_process(&r, f2b, out);
	assert_true(fabsf(k / out[0] - (k / 2.0f + 0.2f)) < 1e-2f);
	/* then nothing: pixel 0 (valid 3 of the last 4) persists, pixel 1 (2 of 4) too */
	rs_ref_process(&r, f3, out);
	assert_true(out[0] > 0.0f && out[1] > 0.0f);
	rs_ref_reset(&r);
	rs_ref_process(&r, f1, out);
	rs_ref_process(&r, f3, out);
	assert_true(out[0] == 0.0f);   /* valid in 1 of the last 4: empty */
	rs_ref_free(&r);
}

/* depthao's filter (as eval --depth runs it) on a noisy fronto-parallel plane at 2 m. */
static void test_filter_beats_raw(void **state)
{
	(void)state;
	enum { FW = 160, FH = 120 };
	struct dao_camera cam;
	struct dao_params p;
	struct dao_context *ctx;
	struct dao_error err;
	assert_int_equal(dao_camera_from_intrinsics(&cam, FW, FH, 131.0, 131.0, 79.5, 59.5, NULL), 0);
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	dao_params_stream_defaults(&p);
	p.algorithm = DAO_ALGORITHM_NONE;
	p.threads = 1;
	static uint16_t mm[FW * FH];
	static float t[FW * FH], r[FW * FH], f[FW * FH];
	static uint8_t d[FW * FH];
	uint64_t s = 12345;
	for (int i = 0; i < FW * FH; i++) {
		/* Gaussian by the sum of 4 uniforms, sigma 6 mm (0.0015 z^2 at 2 m) */
		double g = 0.0;
		for (int k = 0; k < 4; k++) {
			s = s * 6364136223846793005ull + 1442695040888963407ull;
			g += (double)(s >> 11) / 9007199254740992.0 - 0.5;
		}
		t[i] = 2.0f;
		mm[i] = (uint16_t)lrint(2000.0 + 6.0 * g * sqrt(3.0));
		r[i] = (float)mm[i] * 0.001f;
	}
	assert_int_equal(dao_context_create(&ctx, &cam, &p, &err), 0);
	struct dao_frame in = { .format = DAO_PIXFMT_DEPTH16, .width = FW, .height = FH,
				.stride = FW * 2, .data = mm, .depth_unit = 0.001f };
	struct dao_frame out = { .format = DAO_PIXFMT_DEPTH_F32, .width = FW, .height = FH,
				 .stride = FW * 4, .data = f };
	assert_int_equal(dao_context_process(ctx, &in, NULL, 0, NULL, &err), 0);
	assert_int_equal(dao_context_get_depth(ctx, &out, &err), 0);
	dao_context_destroy(ctx);
	depth_acc_edge_distance(t, FW, FH, d);
	struct depth_acc acc = { 0 };
	depth_acc_add(t, r, f, d, FW, FH, &acc);
	assert_int_equal(acc.raw_in.n, FW * FH);
	assert_true(depth_err_mae(&acc.raw_in) > 0.003);
	/* well below raw on a plane; the filter keeps every pixel and fills none */
	assert_true(depth_acc_reduction(&acc.raw_in, &acc.filt_in) > 0.5);
	assert_int_equal(acc.filled, 0);
	assert_int_equal(acc.dropped, 0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_edge_distance),
		cmocka_unit_test(test_errors_and_fill),
		cmocka_unit_test(test_flying_created),
		cmocka_unit_test(test_plane_residual),
		cmocka_unit_test(test_box_mean),
		cmocka_unit_test(test_reference_spatial),
		cmocka_unit_test(test_reference_hole_fill),
		cmocka_unit_test(test_reference_temporal),
		cmocka_unit_test(test_filter_beats_raw),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
