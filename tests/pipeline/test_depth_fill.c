/* SPDX-License-Identifier: MIT */
/*
 * depth-fill (dao_params.depth_fill): the filtered depth output's one-surface
 * hole fill (kernels/depth_fill.h).  A hole between two samples of one plane
 * takes the plane's depth; one across a depth step, at the border or wider
 * than the limit stays a hole; the normals and the AO never see the fill.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/cmocka_all.h"
#include "common/test_common.h"

enum { W = 128, H = 96, STEP_X = 96 };

/* A tilted plane, z = 1 m + 2 mm per column; right of STEP_X a surface 0.3 m
 * farther (a depth step of 26 %, far beyond the 3 % of one surface). */
static float truth(int x)
{
	return 1.0f + 0.002f * (float)x + (x >= STEP_X ? 0.3f : 0.0f);
}

/* The holes: row 20 x 30..34 (5 px, inside the plane), row 40 x 50..59
 * (10 px), row 60 x 93..98 (across the step), row 70 x 0..2 (at the border). */
static void make_scene(float *z)
{
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++)
			z[y * W + x] = truth(x);
	for (int x = 30; x <= 34; x++)
		z[20 * W + x] = 0.0f;
	for (int x = 50; x <= 59; x++)
		z[40 * W + x] = 0.0f;
	for (int x = 93; x <= 98; x++)
		z[60 * W + x] = 0.0f;
	for (int x = 0; x <= 2; x++)
		z[70 * W + x] = 0.0f;
}

static struct dao_frame f32_frame(float *z)
{
	return (struct dao_frame){ .format = DAO_PIXFMT_DEPTH_F32, .width = W, .height = H,
				   .stride = 4 * W, .data = z };
}

/* The filtered depth of `in` (and the AO into `ao` unless NULL). */
static void run(int algorithm, int fill, float *in, float *out, uint16_t *ao)
{
	struct dao_camera cam;
	dao_camera_from_intrinsics(&cam, W, H, 110, 110, 63.5, 47.5, NULL);
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.threads = 1;
	p.algorithm = algorithm;
	p.depth_fill = fill;
	struct dao_context *ctx = NULL;
	struct dao_error err;
	if (dao_context_create(&ctx, &cam, &p, &err))
		fail_msg("create: %s", err.message);
	struct dao_frame d = f32_frame(in), o = f32_frame(out);
	struct dao_frame a = { .format = DAO_PIXFMT_GRAY16, .width = W, .height = H,
			       .stride = 2 * W, .data = ao };
	if (dao_context_process(ctx, &d, NULL, 0, ao ? &a : NULL, &err) ||
	    dao_context_get_depth(ctx, &o, &err))
		fail_msg("process: %s", err.message);
	dao_context_destroy(ctx);
}

static void test_fill_rule(void **state)
{
	(void)state;
	float *in = malloc(sizeof(float) * W * H), *off = malloc(sizeof(float) * W * H),
	      *out = malloc(sizeof(float) * W * H);
	assert_non_null(in);
	assert_non_null(off);
	assert_non_null(out);
	make_scene(in);
	run(DAO_ALGORITHM_NONE, 0, in, off, NULL);
	run(DAO_ALGORITHM_NONE, 8, in, out, NULL);
	/* off: every hole stays */
	assert_true(off[20 * W + 32] == 0.0f && off[40 * W + 55] == 0.0f);
	/* the 5 px hole inside the plane: the plane's depth (the samples beside it are
	 * the prefilter's, exact on a noise-free plane to well within a millimetre) */
	for (int x = 30; x <= 34; x++)
		if (!(fabsf(out[20 * W + x] - truth(x)) < 0.5e-3f))
			fail_msg("x = %d: filled %.5f m, the plane %.5f m", x, (double)out[20 * W + x],
				 (double)truth(x));
	/* 10 px > 8: not filled; across the step: not filled; at the border: not filled */
	for (int x = 50; x <= 59; x++)
		assert_true(out[40 * W + x] == 0.0f);
	for (int x = 93; x <= 98; x++)
		assert_true(out[60 * W + x] == 0.0f);
	for (int x = 0; x <= 2; x++)
		assert_true(out[70 * W + x] == 0.0f);
	/* everything else is the unfilled output, bit for bit */
	for (int i = 0; i < W * H; i++)
		if (!(i / W == 20 && i % W >= 30 && i % W <= 34))
			assert_memory_equal(&out[i], &off[i], sizeof(float));
	/* a limit of 10 fills the 10 px hole, with the plane's depth */
	run(DAO_ALGORITHM_NONE, 10, in, out, NULL);
	for (int x = 50; x <= 59; x++)
		assert_true(fabsf(out[40 * W + x] - truth(x)) < 0.5e-3f);
	assert_true(out[60 * W + 95] == 0.0f);
	free(in);
	free(off);
	free(out);
}

/* The counts output is filled too: it is the same plane converted. */
static void test_fill_counts(void **state)
{
	(void)state;
	float *in = malloc(sizeof(float) * W * H);
	uint16_t *q = malloc(2 * W * H);
	assert_non_null(in);
	assert_non_null(q);
	make_scene(in);
	struct dao_camera cam;
	dao_camera_from_intrinsics(&cam, W, H, 110, 110, 63.5, 47.5, NULL);
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.threads = 1;
	p.algorithm = DAO_ALGORITHM_NONE;
	p.depth_fill = 8;
	struct dao_context *ctx = NULL;
	struct dao_error err;
	struct dao_frame d = f32_frame(in);
	struct dao_frame o = { .format = DAO_PIXFMT_DEPTH16, .width = W, .height = H,
			       .stride = 2 * W, .data = q, .depth_unit = 0.001f };
	if (dao_context_create(&ctx, &cam, &p, &err) ||
	    dao_context_process(ctx, &d, NULL, 0, NULL, &err) ||
	    dao_context_get_depth(ctx, &o, &err))
		fail_msg("%s", err.message);
	for (int x = 30; x <= 34; x++)
		assert_true(abs((int)q[20 * W + x] - (int)lrintf(truth(x) * 1000.0f)) <= 1);
	assert_int_equal(q[60 * W + 95], 0);
	dao_context_destroy(ctx);
	free(in);
	free(q);
}

/* The AO (GTAO; VBAO with the thickness from the image, whose own dropout fill
 * is the same rule) is the same to the bit with and without depth-fill. */
static void test_ao_unchanged(void **state)
{
	(void)state;
	static const int algos[] = { DAO_ALGORITHM_GTAO, DAO_ALGORITHM_VBAO };
	float *in = malloc(sizeof(float) * W * H), *out = malloc(sizeof(float) * W * H);
	uint16_t *a0 = malloc(2 * W * H), *a1 = malloc(2 * W * H);
	assert_non_null(in);
	assert_non_null(out);
	assert_non_null(a0);
	assert_non_null(a1);
	make_scene(in);
	for (size_t k = 0; k < sizeof algos / sizeof algos[0]; k++) {
		run(algos[k], 0, in, out, a0);
		assert_true(out[20 * W + 32] == 0.0f);
		run(algos[k], 16, in, out, a1);
		assert_true(out[20 * W + 32] > 0.0f); /* the fill ran ... */
		assert_memory_equal(a0, a1, 2 * W * H); /* ... and the AO did not see it */
	}
	free(in);
	free(out);
	free(a0);
	free(a1);
}

/* depth-fill is a runtime parameter: turned on and off on a running context, the next
 * frame's output follows (its plane allocated when it is first turned on). */
static void test_fill_runtime(void **state)
{
	(void)state;
	float *in = malloc(sizeof(float) * W * H), *out = malloc(sizeof(float) * W * H);
	assert_non_null(in);
	assert_non_null(out);
	make_scene(in);
	struct dao_camera cam;
	dao_camera_from_intrinsics(&cam, W, H, 110, 110, 63.5, 47.5, NULL);
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.threads = 1;
	p.algorithm = DAO_ALGORITHM_NONE;
	struct dao_context *ctx = NULL;
	struct dao_error err;
	struct dao_frame d = f32_frame(in), o = f32_frame(out);
	static const int fills[] = { 0, 8, 0 };
	for (int k = 0; k < 3; k++) {
		p.depth_fill = fills[k];
		if ((k == 0 ? dao_context_create(&ctx, &cam, &p, &err)
			    : dao_context_set_params(ctx, &p, &err)) ||
		    dao_context_process(ctx, &d, NULL, (uint64_t)k, NULL, &err) ||
		    dao_context_get_depth(ctx, &o, &err))
			fail_msg("frame %d: %s", k, err.message);
		if (fills[k])
			assert_true(fabsf(out[20 * W + 32] - truth(32)) < 0.5e-3f);
		else
			assert_true(out[20 * W + 32] == 0.0f);
	}
	dao_context_destroy(ctx);
	free(in);
	free(out);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_fill_rule),
		cmocka_unit_test(test_fill_counts),
		cmocka_unit_test(test_ao_unchanged),
		cmocka_unit_test(test_fill_runtime),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
