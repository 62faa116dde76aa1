/* SPDX-License-Identifier: MIT */
/*
 * HBAO, SSAO and eye-dome lighting through the public API: open surfaces
 * stay open, occlusion grows towards a wall (floor-and-wall scene with its
 * closed form, MAE printed), VBAO stays within 5 % of GTAO on the room
 * corner, EDL darkens only the far side of a depth step,
 * strength 0 switches them off, and results do not depend on the thread count.
 */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "common/floor_wall.h"
#include "common/test_common.h"

#define W 128
#define H 96

static void run(const struct dao_params *p, const float *z, float *ao)
{
	struct dao_camera cam;
	struct dao_context *ctx;
	struct dao_error err;
	assert_int_equal(dao_camera_from_intrinsics(&cam, W, H, 100, 100, 63.5, 47.5, &err), 0);
	assert_int_equal(dao_context_create(&ctx, &cam, p, &err), 0);
	struct dao_frame in = {.format = DAO_PIXFMT_DEPTH_F32, .width = W, .height = H,
			.stride = W * 4, .data = (void *)z};
	struct dao_frame out = {.format = DAO_PIXFMT_GRAY_F32, .width = W, .height = H,
			.stride = W * 4, .data = ao};
	assert_int_equal(dao_context_process(ctx, &in, NULL, 0, &out, &err), 0);
	dao_context_destroy(ctx);
}

static struct dao_params params_for(int algorithm)
{
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.algorithm = algorithm;
	p.prefilter = DAO_PREFILTER_NONE;
	p.denoise = DAO_DENOISE_NONE;
	p.slices = 8;
	p.steps = 12;
	return p;
}

static void test_open_plane(void **state)
{
	(void)state;
	float *z = malloc(W * H * sizeof(float)), *ao = malloc(W * H * sizeof(float));
	for (int i = 0; i < W * H; i++)
		z[i] = 2.0f;
	const int algos[] = {DAO_ALGORITHM_HBAO, DAO_ALGORITHM_SSAO, DAO_ALGORITHM_EDL,
			     DAO_ALGORITHM_VBAO};
	for (int k = 0; k < 4; k++) {
		struct dao_params p = params_for(algos[k]);
		run(&p, z, ao);
		double sum = 0;
		for (int i = 0; i < W * H; i++)
			sum += ao[i];
		print_message("open plane, algorithm %d: mean visibility %.5f\n", algos[k], sum / (W * H));
		assert_true(sum / (W * H) > 0.995);
	}
	free(z);
	free(ao);
}

static void test_floor_and_wall(void **state)
{
	(void)state;
	struct synth_scene s;
	floor_wall_scene(&s);
	struct dao_camera cam;
	dao_camera_from_intrinsics(&cam, W, H, 100, 100, 63.5, 47.5, NULL);
	struct synth_image img;
	assert_int_equal(synth_render(&s, &cam, 0.5, 0, 1, &img, NULL), 0);
	float *ao = malloc(W * H * sizeof(float));
	const int algos[] = {DAO_ALGORITHM_GTAO, DAO_ALGORITHM_HBAO, DAO_ALGORITHM_SSAO,
			     DAO_ALGORITHM_VBAO};
	const char *names[] = {"gtao", "hbao", "ssao", "vbao"};
	for (int k = 0; k < 4; k++) {
		struct dao_params p = params_for(algos[k]);
		run(&p, img.depth, ao);
		double err = 0, near = 0, far = 0;
		int n = 0, nn = 0, nf = 0;
		for (int y = 40; y < 56; y++)
			for (int x = 0; x < W; x++) {
				double X = (x - 63.5) / 100.0 * 2.0;
				if (X > 0.28)
					break;
				err += fabs(ao[y * W + x] - floor_wall_visibility(X, 0.5));
				n++;
				if (X > 0.15)
					near += ao[y * W + x], nn++;
				if (X < -0.3)
					far += ao[y * W + x], nf++;
			}
		near /= nn;
		far /= nf;
		print_message("floor-wall %s: MAE %.4f vs the closed form; visibility %.3f near the "
			      "wall, %.3f beyond R\n", names[k], err / n, near, far);
		assert_true(near < far - 0.1); /* occluded at the wall ... */
		assert_true(far > 0.97);        /* ... open beyond the radius */
		assert_true(err / n < 0.12);
	}
	free(ao);
	synth_image_free(&img);
}

/* A thin bar floating above a floor: GTAO takes it for a wall reaching to infinity
 * behind it; the visibility bitmask knows it is only vbao-thickness deep. */
static void test_vbao_thin_bar(void **state)
{
	(void)state;
	float *z = malloc(W * H * sizeof(float)), *g = malloc(W * H * sizeof(float));
	float *v = malloc(W * H * sizeof(float));
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++)
			z[y * W + x] = x >= 60 && x < 64 ? 1.85f : 2.0f; /* a 4 px (8 cm) bar, 15 cm up */
	struct dao_params p = params_for(DAO_ALGORITHM_GTAO);
	run(&p, z, g);
	p = params_for(DAO_ALGORITHM_VBAO);
	p.vbao_thickness = 0.05f;
	run(&p, z, v);
	double sg = 0, sv = 0;
	int n = 0;
	for (int y = 20; y < 76; y++)
		for (int x = 66; x < 80; x++) { /* floor beside the bar */
			sg += g[y * W + x];
			sv += v[y * W + x];
			n++;
		}
	print_message("thin bar: floor beside it, GTAO %.3f, VBAO %.3f\n", sg / n, sv / n);
	assert_true(sv / n > sg / n + 0.03); /* light passes under the bar */
	assert_true(sv / n < 0.995);          /* but the bar still occludes */
	free(z);
	free(g);
	free(v);
}

/* MAE against the truth over the pixels with depth, at the default preset (medium). */
static double room_mae(const struct dao_camera *cam, const struct synth_image *img, int algorithm,
		       int mode, float thickness)
{
	const int w = (int)cam->width, h = (int)cam->height;
	float *ao = dao_test_ao_of_depth(cam, img->depth, algorithm, mode, thickness);
	assert_non_null(ao);
	double sum = 0;
	int n = 0;
	for (int i = 0; i < w * h; i++)
		if (img->depth[i] > 0) {
			sum += fabs(ao[i] - img->gt[i]);
			n++;
		}
	free(ao);
	return sum / n;
}

/*
 * Issue #17: on thick scenes VBAO no more than 5 % above GTAO.  With
 * infinitely thick occluders (10 m) VBAO is a horizon method, so on the
 * room corner (two walls and a floor, eval's scene, 64 rays) the gap is
 * how it weighs samples: with a hard cut at the radius it was 20 % worse
 * than GTAO (0.0199 against 0.0166, with the estimated thickness too);
 * with the falloff 1.6 % (0.0169).
 */
static void test_vbao_room_corner(void **state)
{
	(void)state;
	struct synth_scene s;
	struct dao_camera cam;
	struct synth_image img;
	assert_int_equal(synth_scene_build("room-corner", 0.0, &s, NULL), 0);
	synth_default_camera(&cam);
	assert_int_equal(synth_render(&s, &cam, 0.5, 8, 2, &img, NULL), 0);
	const double g = room_mae(&cam, &img, DAO_ALGORITHM_GTAO, 0, 0.2f);
	const double v = room_mae(&cam, &img, DAO_ALGORITHM_VBAO, DAO_VBAO_THICKNESS_CONSTANT, 10.0f);
	const double e = room_mae(&cam, &img, DAO_ALGORITHM_VBAO, DAO_VBAO_THICKNESS_IMAGE, 0.2f);
	print_message("room corner, MAE: gtao %.4f, vbao 10 m %.4f (%+.1f %%), image %.4f "
		      "(%+.1f %%)\n", g, v, 100 * (v / g - 1), e, 100 * (e / g - 1));
	assert_true(v <= 1.05 * g);
	assert_true(e <= 1.05 * g);
	synth_image_free(&img);
}

/* Bent normals: the normal on open ground, tilted away from a wall beside it. */
static void test_bent_normals(void **state)
{
	(void)state;
	struct synth_scene s;
	floor_wall_scene(&s);
	struct dao_camera cam;
	struct dao_error err;
	dao_camera_from_intrinsics(&cam, W, H, 100, 100, 63.5, 47.5, NULL);
	struct synth_image img;
	assert_int_equal(synth_render(&s, &cam, 0.5, 0, 1, &img, NULL), 0);
	struct dao_params p = params_for(DAO_ALGORITHM_GTAO);
	struct dao_context *ctx;
	assert_int_equal(dao_context_create(&ctx, &cam, &p, &err), 0);
	float *bent = malloc(3 * W * H * sizeof(float)), *nrm = malloc(3 * W * H * sizeof(float));
	struct dao_frame bf = {.format = DAO_PIXFMT_NORMAL_F32, .width = W, .height = H,
			.stride = W * 12, .data = bent};
	struct dao_frame nf = {.format = DAO_PIXFMT_NORMAL_F32, .width = W, .height = H,
			.stride = W * 12, .data = nrm};
	assert_int_equal(dao_context_get_bent_normals(ctx, &bf, &err), -EAGAIN);
	struct dao_frame in = {.format = DAO_PIXFMT_DEPTH_F32, .width = W, .height = H,
			.stride = W * 4, .data = img.depth};
	assert_int_equal(dao_context_process(ctx, &in, NULL, 0, NULL, &err), 0);
	assert_int_equal(dao_context_get_bent_normals(ctx, &bf, &err), 0);
	assert_int_equal(dao_context_get_normals(ctx, &nf, &err), 0);
	double far_dev = 0, near_dx = 0;
	int nfar = 0, nnear = 0;
	for (int y = 40; y < 56; y++)
		for (int x = 0; x < W; x++) {
			double X = (x - 63.5) / 100.0 * 2.0;
			const float *b = bent + 3 * (y * W + x), *nn = nrm + 3 * (y * W + x);
			double len = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
			assert_true(fabs(len - 1.0) < 1e-4);
			if (X < -0.3) { /* beyond R from the wall: open, bent = normal */
				far_dev += acos(fmin(1.0, b[0] * nn[0] + b[1] * nn[1] + b[2] * nn[2]));
				nfar++;
			} else if (X > 0.15 && X < 0.28) { /* beside the wall at +x: bent towards -x */
				near_dx += b[0] - nn[0];
				nnear++;
			}
		}
	far_dev /= nfar;
	near_dx /= nnear;
	print_message("bent normals: %.2f deg from the normal on open floor, x shift %.3f beside the wall\n",
		      far_dev * 180 / 3.14159265, near_dx);
	assert_true(far_dev < 2.0 * 3.14159265 / 180); /* within 2 degrees */
	assert_true(near_dx < -0.1);
	dao_context_destroy(ctx);
	free(bent);
	free(nrm);
	synth_image_free(&img);
}

static void test_edl_step(void **state)
{
	(void)state;
	float *z = malloc(W * H * sizeof(float)), *ao = malloc(W * H * sizeof(float));
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++)
			z[y * W + x] = x < W / 2 ? 1.0f : 2.0f; /* near left half, far right half */
	struct dao_params p = params_for(DAO_ALGORITHM_EDL);
	run(&p, z, ao);
	const int y = H / 2;
	assert_float_equal(ao[y * W + W / 2 - 3], 1.0f, 1e-6); /* near side: nothing in front */
	assert_true(ao[y * W + W / 2] < 0.5f);                 /* far side at the step: dark */
	assert_float_equal(ao[y * W + W - 10], 1.0f, 1e-6);    /* far side away from it: open */
	free(z);
	free(ao);
}

static void test_strength_zero_and_threads(void **state)
{
	(void)state;
	struct synth_scene s;
	floor_wall_scene(&s);
	struct dao_camera cam;
	dao_camera_from_intrinsics(&cam, W, H, 100, 100, 63.5, 47.5, NULL);
	struct synth_image img;
	assert_int_equal(synth_render(&s, &cam, 0.5, 0, 1, &img, NULL), 0);
	float *a = malloc(W * H * sizeof(float)), *b = malloc(W * H * sizeof(float));
	const int algos[] = {DAO_ALGORITHM_HBAO, DAO_ALGORITHM_SSAO, DAO_ALGORITHM_EDL};
	for (int k = 0; k < 3; k++) {
		struct dao_params p = params_for(algos[k]);
		p.threads = 1;
		run(&p, img.depth, a);
		p.threads = 2;
		run(&p, img.depth, b);
		assert_memory_equal(a, b, W * H * sizeof(float));
		p.strength = 0.0f;
		run(&p, img.depth, a);
		for (int i = 0; i < W * H; i++)
			assert_float_equal(a[i], 1.0f, 1e-6);
	}
	struct dao_params p = params_for(DAO_ALGORITHM_SSAO);
	struct dao_error err;
	p.ssao_min = 0.6f; /* not below ssao-max 0.5 */
	assert_int_equal(dao_params_validate(&p, &err), -22);
	assert_non_null(strstr(err.message, "ssao-min"));
	assert_int_equal(dao_params_set(&p, "algorithm", "vbao-typo", &err), -22);
	assert_int_equal(dao_params_set(&p, "algorithm", "hbao", &err), 0);
	assert_int_equal(p.algorithm, DAO_ALGORITHM_HBAO);
	free(a);
	free(b);
	synth_image_free(&img);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_open_plane),
		cmocka_unit_test(test_floor_and_wall),
		cmocka_unit_test(test_vbao_thin_bar),
		cmocka_unit_test(test_vbao_room_corner),
		cmocka_unit_test(test_bent_normals),
		cmocka_unit_test(test_edl_step),
		cmocka_unit_test(test_strength_zero_and_threads),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
