/* SPDX-License-Identifier: MIT */
/*
 * depth-temporal-motion=icp in the pipeline (public API): a still camera
 * gives the same depth and AO as the filter without it, bit for bit; a
 * panning camera's filtered depth is closer to the truth with it than
 * without; a frame the estimate refuses (a flat wall) is filtered as
 * without it.
 */
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <depthao/context.h>
#include <depthao/params.h>

#include "motion_fixture.h"

static void test_still_identical(void **state)
{
	(void)state;
	struct scene_fixture f;
	fixture_init(&f);
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	dao_params_stream_defaults(&p);
	struct dao_context *off, *icp;
	off = motion_context(&f.cam, &p, DAO_DEPTH_MOTION_OFF);
	icp = motion_context(&f.cam, &p, DAO_DEPTH_MOTION_ICP);
	float *ao0 = malloc(f.npix * 4), *ao1 = malloc(f.npix * 4);
	float *za = malloc(f.npix * 4), *zb = malloc(f.npix * 4);
	assert_true(ao0 && ao1 && za && zb);
	struct dao_pose still;
	dao_pose_identity(&still);
	/* the same frame again (clean, then a noisy one): the motion found is
	 * the identity to float rounding, the history is not moved */
	for (unsigned k = 0; k < 6; k++) {
		if (k == 0 || k == 3)
			render(&f, &still, 1, k ? 1.0 : 0.0, 100u + k, f.z0);
		if (k == 3) { /* a new history for the noisy frame */
			dao_context_reset(off);
			dao_context_reset(icp);
		}
		memcpy(f.z1, f.z0, f.npix * 4);
		run_frame(off, f.z0, k, ao0, za);
		run_frame(icp, f.z1, k, ao1, zb);
		assert_memory_equal(za, zb, f.npix * 4);
		assert_memory_equal(ao0, ao1, f.npix * 4);
		struct dao_motion_info mi = DAO_MOTION_INFO_INIT;
		dao_context_motion(icp, &mi);
		assert_int_equal(mi.size, sizeof mi);
		/* no history in frames 0 and 3 */
		assert_int_equal(mi.state, k % 3 == 0 ? DAO_MOTION_NONE : DAO_MOTION_STILL);
	}
	dao_context_destroy(off);
	dao_context_destroy(icp);
	free(ao0), free(ao1), free(za), free(zb);
	fixture_free(&f);
}

/* after processing the frame of camera `cur`: the motion the context reports
 * against the truth (from `cur` to `prev`); it must have been applied */
static void check_motion(struct dao_context *ctx, const struct dao_pose *prev,
			 const struct dao_pose *cur, double *worst_deg, double *worst_mm)
{
	struct dao_motion_info mi;
	struct dao_pose truth, est, e;
	applied_motion(ctx, prev, cur, &mi, &truth);
	memcpy(est.r, mi.rotation, sizeof est.r);
	memcpy(est.t, mi.translation, sizeof est.t);
	/* e = truth^-1 est */
	for (int i = 0; i < 3; i++) {
		for (int j = 0; j < 3; j++)
			e.r[i * 3 + j] = truth.r[i] * est.r[j] + truth.r[3 + i] * est.r[3 + j] +
					 truth.r[6 + i] * est.r[6 + j];
		e.t[i] = 0.0;
		for (int k = 0; k < 3; k++)
			e.t[i] += truth.r[k * 3 + i] * (est.t[k] - truth.t[k]);
	}
	*worst_deg = fmax(*worst_deg, dao_pose_angle(&e) * 180.0 / M_PI);
	*worst_mm = fmax(*worst_mm, dao_pose_distance(&e) * 1e3);
}

/* a still camera, new noise in every frame: the estimate's own scatter
 * (hundredths of a degree) may move the history by a fraction of a pixel;
 * the result stays better than no filter and close to the filter alone */
static void test_still_noisy(void **state)
{
	(void)state;
	struct scene_fixture f;
	fixture_init(&f);
	struct dao_params p;
	depth_only_params(&p, DAO_QUALITY_DEFAULT);
	struct dao_params raw = p;
	raw.depth_temporal = 0.0f;
	struct dao_context *ctx[3];
	ctx[0] = motion_context(&f.cam, &raw, DAO_DEPTH_MOTION_OFF);
	ctx[1] = motion_context(&f.cam, &p, DAO_DEPTH_MOTION_OFF);
	ctx[2] = motion_context(&f.cam, &p, DAO_DEPTH_MOTION_ICP);
	float *truth = malloc(f.npix * 4), *zo = malloc(f.npix * 4);
	assert_true(truth && zo);
	struct dao_pose still;
	dao_pose_identity(&still);
	render(&f, &still, 1, 0.0, 0u, truth);
	double mae[3] = {0, 0, 0};
	for (unsigned k = 0; k < 10; k++) {
		render(&f, &still, 1, 1.0, 400u + k, f.z0);
		for (int m = 0; m < 3; m++) {
			memcpy(f.z1, f.z0, f.npix * 4);
			run_frame(ctx[m], f.z1, k, NULL, zo);
			if (k >= 3)
				mae[m] += rel_mae(zo, truth, f.npix) / 7.0;
		}
	}
	printf("still, new noise each frame, frames 3-9: relative depth MAE raw %.5f, "
	       "filter %.5f, filter + icp %.5f\n", mae[0], mae[1], mae[2]);
	assert_true(mae[2] < mae[0]);
	assert_true(mae[2] < 1.1 * mae[1]);
	for (int m = 0; m < 3; m++)
		dao_context_destroy(ctx[m]);
	free(truth), free(zo);
	fixture_free(&f);
}

static void test_pan(void **state)
{
	(void)state;
	struct scene_fixture f;
	fixture_init(&f);
	struct dao_params p;
	depth_only_params(&p, DAO_QUALITY_DEFAULT);
	struct dao_params raw = p;
	raw.depth_temporal = 0.0f;
	struct dao_context *ctx[3];
	ctx[0] = motion_context(&f.cam, &raw, DAO_DEPTH_MOTION_OFF);
	ctx[1] = motion_context(&f.cam, &p, DAO_DEPTH_MOTION_OFF);
	ctx[2] = motion_context(&f.cam, &p, DAO_DEPTH_MOTION_ICP);
	float *truth = malloc(f.npix * 4), *zo = malloc(f.npix * 4);
	assert_true(truth && zo);
	double mae[3] = {0, 0, 0}, worst_deg = 0.0, worst_mm = 0.0;
	struct dao_pose last;
	dao_pose_identity(&last);
	/* 1 degree a frame (30 degrees/s at 30 fps) and 10 mm sideways */
	for (unsigned k = 0; k < 10; k++) {
		struct dao_pose c;
		pose_from(&c, -4.0 + (double)k, 0.3 * k, 0.01 * k, 0.0, 0.0);
		render(&f, &c, 1, 0.0, 0u, truth);
		render(&f, &c, 1, 1.0, 200u + k, f.z0);
		for (int m = 0; m < 3; m++) {
			memcpy(f.z1, f.z0, f.npix * 4);
			run_frame(ctx[m], f.z1, k, NULL, zo);
			if (k >= 3)
				mae[m] += rel_mae(zo, truth, f.npix) / 7.0;
		}
		if (k)
			check_motion(ctx[2], &last, &c, &worst_deg, &worst_mm);
		last = c;
	}
	printf("pan 1 deg/frame, frames 3-9: relative depth MAE raw %.5f, filter %.5f, "
	       "filter + icp %.5f; motion error at most %.4f deg, %.3f mm\n", mae[0], mae[1],
	       mae[2], worst_deg, worst_mm);
	struct dao_motion_info mi = DAO_MOTION_INFO_INIT;
	dao_context_motion(ctx[1], &mi);
	assert_int_equal(mi.state, DAO_MOTION_NONE);
	assert_true(mi.rotation[0] == 1.0 && mi.translation[0] == 0.0);
	assert_true(mae[2] < mae[1]);
	assert_true(mae[2] < mae[0]);
	for (int m = 0; m < 3; m++)
		dao_context_destroy(ctx[m]);
	free(truth), free(zo);
	fixture_free(&f);
}

/* a flat wall: the estimate is refused, the filter runs as without motion */
static void test_refused_falls_back(void **state)
{
	(void)state;
	struct scene_fixture f;
	fixture_init(&f);
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	dao_params_stream_defaults(&p);
	p.algorithm = DAO_ALGORITHM_NONE;
	struct dao_context *off, *icp;
	off = motion_context(&f.cam, &p, DAO_DEPTH_MOTION_OFF);
	icp = motion_context(&f.cam, &p, DAO_DEPTH_MOTION_ICP);
	float *za = malloc(f.npix * 4), *zb = malloc(f.npix * 4);
	assert_true(za && zb);
	for (unsigned k = 0; k < 4; k++) {
		struct dao_pose c;
		pose_from(&c, 0.0, 0.0, 0.02 * k, 0.0, 0.0);
		render(&f, &c, 0, 1.0, 300u + k, f.z0);
		memcpy(f.z1, f.z0, f.npix * 4);
		run_frame(off, f.z0, k, NULL, za);
		run_frame(icp, f.z1, k, NULL, zb);
		assert_memory_equal(za, zb, f.npix * 4);
		struct dao_motion_info mi = DAO_MOTION_INFO_INIT;
		dao_context_motion(icp, &mi);
		assert_int_equal(mi.state, k == 0 ? DAO_MOTION_NONE : DAO_MOTION_REFUSED);
		assert_int_equal(mi.reason, k == 0 ? 0 : 2); /* ill-posed */
	}
	dao_context_destroy(off);
	dao_context_destroy(icp);
	free(za), free(zb);
	fixture_free(&f);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_still_identical),
		cmocka_unit_test(test_still_noisy),
		cmocka_unit_test(test_pan),
		cmocka_unit_test(test_refused_falls_back),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
