/* SPDX-License-Identifier: MIT */
/*
 * Temporal accumulation on a still scene with sensor noise drawn anew each
 * frame: frame-to-frame flicker (mean |AO(t) - AO(t-1)|) with and without
 * it, and the error against the ray-traced ground truth, which must not get
 * worse.  Also: a moved object is not smeared (the history is dropped where
 * the depth changed), and new parameters restart the history.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "common/test_common.h"
#include "synth/suite.h"
#include "synth/synth.h"

#define W 320
#define H 240
#define FRAMES 16

struct measured {
	double flicker, mae;
};

static struct measured run_sequence(const char *scene, int algorithm, float temporal)
{
	struct dao_camera cam;
	struct dao_error err;
	dao_camera_from_intrinsics(&cam, W, H, 262.5, 262.5, 159.5, 119.5, &err);
	struct synth_scene sc;
	struct synth_image img;
	assert_int_equal(synth_scene_build(scene, 0.0, &sc, &err), 0);
	assert_int_equal(synth_render(&sc, &cam, 0.5, 8, 2, &img, &err), 0);
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.algorithm = algorithm;
	p.temporal = temporal;
	struct dao_context *ctx;
	assert_int_equal(dao_context_create(&ctx, &cam, &p, &err), 0);
	float *prev = malloc(W * H * sizeof(float)), *cur = malloc(W * H * sizeof(float));
	unsigned char *prev_hole = calloc(W * H, 1);
	double flicker = 0, mae = 0;
	int nf = 0, nm = 0;
	for (int f = 0; f < FRAMES; f++) {
		struct synth_case c;
		memset(&c, 0, sizeof c);
		assert_int_equal(synth_case_make(&c, scene, 1, img.depth, img.gt, W, H, 100 + (uint64_t)f, &err), 0);
		struct dao_frame in = {.format = DAO_PIXFMT_DEPTH16, .width = W, .height = H,
				.stride = W * 2, .data = c.depth_mm, .depth_unit = 0.001f};
		struct dao_frame out = {.format = DAO_PIXFMT_GRAY_F32, .width = W, .height = H,
				.stride = W * 4, .data = cur};
		assert_int_equal(dao_context_process(ctx, &in, NULL, (uint64_t)f, &out, &err), 0);
		if (f >= FRAMES / 2) { /* settled */
			double d = 0, e = 0;
			int n = 0;
			for (int i = 0; i < W * H; i++) {
				/* pixels with depth in both frames (a hole shows invalid_value) */
				if (!(img.depth[i] > 0) || !c.depth_mm[i] || prev_hole[i])
					continue;
				d += fabs(cur[i] - prev[i]);
				e += fabs(cur[i] - img.gt[i]);
				n++;
			}
			flicker += d / n;
			mae += e / n;
			nf++;
			nm++;
		}
		memcpy(prev, cur, W * H * sizeof(float));
		for (int i = 0; i < W * H; i++)
			prev_hole[i] = c.depth_mm[i] == 0;
		synth_case_free(&c);
	}
	dao_context_destroy(ctx);
	synth_image_free(&img);
	free(prev);
	free(cur);
	free(prev_hole);
	return (struct measured){flicker / nf, mae / nm};
}

static void test_flicker_cut(void **state)
{
	(void)state;
	const char *scenes[] = {"boxes", "thin-pole"};
	const int algos[] = {DAO_ALGORITHM_GTAO, DAO_ALGORITHM_VBAO};
	const char *names[] = {"gtao", "vbao"};
	for (int s = 0; s < 2; s++)
		for (int a = 0; a < 2; a++) {
			struct measured off = run_sequence(scenes[s], algos[a], 0.0f);
			struct measured on = run_sequence(scenes[s], algos[a], 0.8f);
			print_message("%s %s: flicker %.5f -> %.5f (%.1fx less), MAE %.4f -> %.4f\n",
				      scenes[s], names[a], off.flicker, on.flicker,
				      off.flicker / on.flicker, off.mae, on.mae);
			assert_true(off.flicker >= 4.0 * on.flicker); /* the bar of issue #7 */
			assert_true(on.mae <= off.mae + 1e-4);       /* and no worse */
		}
}

static void test_moved_object_not_smeared(void **state)
{
	(void)state;
	struct dao_camera cam;
	struct dao_error err;
	dao_camera_from_intrinsics(&cam, 64, 48, 50, 50, 31.5, 23.5, &err);
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.temporal = 0.9f;
	p.prefilter = DAO_PREFILTER_NONE;
	p.denoise = DAO_DENOISE_NONE;
	struct dao_context *ctx, *fresh;
	assert_int_equal(dao_context_create(&ctx, &cam, &p, &err), 0);
	assert_int_equal(dao_context_create(&fresh, &cam, &p, &err), 0);
	float z[64 * 48], a[64 * 48], b[64 * 48];
	struct dao_frame in = {.format = DAO_PIXFMT_DEPTH_F32, .width = 64, .height = 48,
			.stride = 64 * 4, .data = z};
	struct dao_frame oa = {.format = DAO_PIXFMT_GRAY_F32, .width = 64, .height = 48,
			.stride = 64 * 4, .data = a};
	struct dao_frame ob = {.format = DAO_PIXFMT_GRAY_F32, .width = 64, .height = 48,
			.stride = 64 * 4, .data = b};
	for (int f = 0; f < 10; f++) { /* a box on the left for a while ... */
		for (int i = 0; i < 64 * 48; i++)
			z[i] = (i % 64) < 20 && (i / 64) > 10 && (i / 64) < 30 ? 1.5f : 2.0f;
		assert_int_equal(dao_context_process(ctx, &in, NULL, (uint64_t)f, &oa, &err), 0);
	}
	for (int i = 0; i < 64 * 48; i++) /* ... then gone: the floor there is new */
		z[i] = 2.0f;
	assert_int_equal(dao_context_process(ctx, &in, NULL, 10, &oa, &err), 0);
	assert_int_equal(dao_context_process(fresh, &in, NULL, 10, &ob, &err), 0);
	assert_true(memcmp(a, b, sizeof a) != 0); /* the history did run (elsewhere) */
	for (int y = 12; y < 28; y++)
		for (int x = 2; x < 18; x++)
			assert_float_equal(a[y * 64 + x], b[y * 64 + x], 1e-6); /* no trace of the box */
	/* new parameters: the history starts over */
	p.radius = 0.3f;
	assert_int_equal(dao_context_set_params(ctx, &p, &err), 0);
	assert_int_equal(dao_context_set_params(fresh, &p, &err), 0);
	assert_int_equal(dao_context_process(ctx, &in, NULL, 11, &oa, &err), 0);
	assert_int_equal(dao_context_process(fresh, &in, NULL, 11, &ob, &err), 0);
	assert_memory_equal(a, b, sizeof a);
	dao_context_destroy(ctx);
	dao_context_destroy(fresh);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_flicker_cut),
		cmocka_unit_test(test_moved_object_not_smeared),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
