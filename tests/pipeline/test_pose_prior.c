/* SPDX-License-Identifier: MIT */
/*
 * dao_context_set_pose and depth-temporal-motion=source / source+icp
 * (public API; the quaternions of <depthao/pose.h>, tested in
 * tests/motion/test_pose_math.c):
 * the boundary refuses bad poses with a message; without poses, source is
 * the filter without motion and source+icp is icp, bit for bit; given the
 * true poses of a pan, the motion reported is the true one and the history
 * follows it; given the motion ICP found, source reproduces ICP's filtered
 * depth; a flat wall ICP cannot pin down follows the given poses.
 */
#include <errno.h>
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
#include <depthao/pose.h>

#include "motion_fixture.h"

/* the filtered depth of a copy of z (z is used again) */
static void run(struct dao_context *ctx, const float *z, uint64_t index, float *zout)
{
	float *copy = malloc((size_t)W * H * 4);
	assert_non_null(copy);
	memcpy(copy, z, (size_t)W * H * 4);
	run_frame(ctx, copy, index, NULL, zout);
	free(copy);
}

static struct dao_context *make(const struct dao_camera *cam, int motion)
{
	struct dao_params p;
	depth_only_params(&p, DAO_QUALITY_DEFAULT);
	return motion_context(cam, &p, motion);
}

static void test_boundary(void **state)
{
	(void)state;
	struct scene_fixture f;
	fixture_init(&f);
	struct dao_context *ctx = make(&f.cam, DAO_DEPTH_MOTION_SOURCE);
	struct dao_error err = {0};
	const double t[3] = {1, 2, 3}, id[4] = {0, 0, 0, 1};
	assert_int_equal(dao_context_set_pose(NULL, id, t, &err), -EINVAL);
	const double nan_q[4] = {0, NAN, 0, 1}, big_q[4] = {0, 0, 0, 1.1};
	assert_int_equal(dao_context_set_pose(ctx, nan_q, t, &err), -EINVAL);
	assert_non_null(strstr(err.message, "rotation[1] is not a finite"));
	assert_int_equal(dao_context_set_pose(ctx, big_q, t, &err), -EINVAL);
	assert_non_null(strstr(err.message, "unit quaternion"));
	const double inf_t[3] = {0, INFINITY, 0}, far_t[3] = {2e6, 0, 0};
	assert_int_equal(dao_context_set_pose(ctx, id, inf_t, &err), -EINVAL);
	assert_non_null(strstr(err.message, "translation[1]"));
	assert_int_equal(dao_context_set_pose(ctx, id, far_t, &err), -EINVAL);
	assert_non_null(strstr(err.message, "metres"));
	assert_int_equal(dao_context_set_pose(ctx, id, NULL, &err), -EINVAL);
	/* within the tolerance: taken (and normalised); NULL rotation: no pose */
	const double near_q[4] = {0, 0, 0, 1.0005};
	assert_int_equal(dao_context_set_pose(ctx, near_q, t, &err), 0);
	assert_int_equal(dao_context_set_pose(ctx, NULL, NULL, &err), 0);
	dao_context_destroy(ctx);
	fixture_free(&f);
}

/* without poses: source = off and source+icp = icp, bit for bit */
static void test_without_poses(void **state)
{
	(void)state;
	struct scene_fixture f;
	fixture_init(&f);
	struct dao_context *ctx[4] = {make(&f.cam, DAO_DEPTH_MOTION_OFF),
				      make(&f.cam, DAO_DEPTH_MOTION_SOURCE),
				      make(&f.cam, DAO_DEPTH_MOTION_ICP),
				      make(&f.cam, DAO_DEPTH_MOTION_SOURCE_ICP)};
	float *zo[4];
	for (int m = 0; m < 4; m++)
		assert_non_null(zo[m] = malloc(f.npix * 4));
	for (unsigned k = 0; k < 4; k++) {
		struct dao_pose c;
		pose_from(&c, 0.5 * k, 0.2 * k, 0.01 * k, 0.0, 0.0);
		render(&f, &c, 1, 1.0, 400u + k, f.z0);
		if (k == 2) /* one pose alone gives no motion */
			give_pose(ctx[1], &c), give_pose(ctx[3], &c);
		for (int m = 0; m < 4; m++)
			run(ctx[m], f.z0, k, zo[m]);
		assert_memory_equal(zo[0], zo[1], f.npix * 4);
		assert_memory_equal(zo[2], zo[3], f.npix * 4);
		struct dao_motion_info mi = DAO_MOTION_INFO_INIT;
		dao_context_motion(ctx[1], &mi);
		assert_int_equal(mi.state, DAO_MOTION_NONE);
		dao_context_motion(ctx[3], &mi);
		assert_int_equal(mi.origin, DAO_MOTION_FROM_DEPTH);
	}
	for (int m = 0; m < 4; m++)
		dao_context_destroy(ctx[m]), free(zo[m]);
	fixture_free(&f);
}

/* the motion the context reports against the truth prev^-1 cur */
static void check_reported(struct dao_context *ctx, const struct dao_pose *prev,
			   const struct dao_pose *cur, int origin, double tol_r, double tol_t)
{
	struct dao_motion_info mi;
	struct dao_pose truth;
	applied_motion(ctx, prev, cur, &mi, &truth);
	assert_int_equal(mi.origin, origin);
	for (int i = 0; i < 9; i++)
		assert_true(fabs(mi.rotation[i] - truth.r[i]) < tol_r);
	for (int i = 0; i < 3; i++)
		assert_true(fabs(mi.translation[i] - truth.t[i]) < tol_t);
}

/*
 * A pan at 1 degree a frame with 10 mm sideways: given the true poses (in a
 * world that is not frame 0's: every pose moved by one fixed transform),
 * source reports the true motion and filters better than off; source+icp
 * refines it to within ICP's accuracy.
 */
static void test_pan_true_poses(void **state)
{
	(void)state;
	struct scene_fixture f;
	fixture_init(&f);
	struct dao_context *ctx[3] = {make(&f.cam, DAO_DEPTH_MOTION_OFF),
				      make(&f.cam, DAO_DEPTH_MOTION_SOURCE),
				      make(&f.cam, DAO_DEPTH_MOTION_SOURCE_ICP)};
	float *truth = malloc(f.npix * 4), *zo = malloc(f.npix * 4);
	assert_true(truth && zo);
	struct dao_pose g, last;
	pose_from(&g, 70.0, -20.0, 5.0, -3.0, 12.0); /* world <- the scene's frame */
	double mae[3] = {0, 0, 0};
	for (unsigned k = 0; k < 8; k++) {
		struct dao_pose c, w;
		pose_from(&c, -4.0 + (double)k, 0.3 * k, 0.01 * k, 0.0, 0.0);
		render(&f, &c, 1, 0.0, 0u, truth);
		render(&f, &c, 1, 1.0, 500u + k, f.z0);
		relative(&g, &c, &w); /* g^-1 c: every pose in another world frame */
		for (int m = 0; m < 3; m++) {
			if (m)
				give_pose(ctx[m], &w);
			run(ctx[m], f.z0, k, zo);
			if (k >= 3)
				mae[m] += rel_mae(zo, truth, f.npix) / 5.0;
		}
		if (k) {
			check_reported(ctx[1], &last, &c, DAO_MOTION_FROM_SOURCE, 1e-9, 1e-9);
			check_reported(ctx[2], &last, &c, DAO_MOTION_FROM_SOURCE_ICP, 2e-3, 2e-3);
		}
		last = c;
	}
	printf("pan with the true poses, frames 3-7: relative depth MAE off %.5f, source %.5f, "
	       "source+icp %.5f\n", mae[0], mae[1], mae[2]);
	assert_true(mae[1] < mae[0]);
	assert_true(mae[2] < mae[0]);
	for (int m = 0; m < 3; m++)
		dao_context_destroy(ctx[m]);
	free(truth), free(zo);
	fixture_free(&f);
}

/*
 * The motion ICP found, given as poses (chained), carries the history as
 * ICP's own did: the filtered depths agree but for float rounding of the
 * motion through a quaternion (a pixel whose nearest pixel flips).
 */
static void test_source_matches_icp(void **state)
{
	(void)state;
	struct scene_fixture f;
	fixture_init(&f);
	struct dao_context *icp = make(&f.cam, DAO_DEPTH_MOTION_ICP);
	struct dao_context *src = make(&f.cam, DAO_DEPTH_MOTION_SOURCE);
	float *za = malloc(f.npix * 4), *zb = malloc(f.npix * 4);
	assert_true(za && zb);
	struct dao_pose chain;
	dao_pose_identity(&chain);
	for (unsigned k = 0; k < 6; k++) {
		struct dao_pose c;
		pose_from(&c, 2.0 - (double)k, 0.0, -0.008 * k, 0.0, 0.0);
		render(&f, &c, 1, 1.0, 600u + k, f.z0);
		run(icp, f.z0, k, za);
		struct dao_motion_info mi = DAO_MOTION_INFO_INIT;
		dao_context_motion(icp, &mi);
		if (k) {
			assert_int_equal(mi.state, DAO_MOTION_APPLIED);
			struct dao_pose m, n; /* chain <- chain * (cur -> prev) */
			memcpy(m.r, mi.rotation, sizeof m.r);
			memcpy(m.t, mi.translation, sizeof m.t);
			for (int i = 0; i < 3; i++) {
				for (int j = 0; j < 3; j++)
					n.r[i * 3 + j] = chain.r[i * 3] * m.r[j] +
							 chain.r[i * 3 + 1] * m.r[3 + j] +
							 chain.r[i * 3 + 2] * m.r[6 + j];
				n.t[i] = chain.t[i] + chain.r[i * 3] * m.t[0] +
					 chain.r[i * 3 + 1] * m.t[1] + chain.r[i * 3 + 2] * m.t[2];
			}
			chain = n;
		}
		give_pose(src, &chain);
		run(src, f.z0, k, zb);
		size_t differ = 0, n = 0;
		for (size_t i = 0; i < f.npix; i++) {
			n += za[i] > 0.0f;
			differ += fabsf(za[i] - zb[i]) > 1e-5f * za[i];
		}
		printf("frame %u: %zu of %zu pixels differ\n", k, differ, n);
		assert_true(differ * 1000 <= n);
	}
	dao_context_destroy(icp);
	dao_context_destroy(src);
	free(za), free(zb);
	fixture_free(&f);
}

/* a flat wall the camera slides along: ICP refuses it (ill-posed), the given
 * poses carry the history; a still pose does not move it */
static void test_wall_and_still(void **state)
{
	(void)state;
	struct scene_fixture f;
	fixture_init(&f);
	struct dao_context *src = make(&f.cam, DAO_DEPTH_MOTION_SOURCE);
	struct dao_context *both = make(&f.cam, DAO_DEPTH_MOTION_SOURCE_ICP);
	float *zb = malloc(f.npix * 4);
	assert_non_null(zb);
	struct dao_pose last;
	for (unsigned k = 0; k < 6; k++) {
		struct dao_pose c;
		pose_from(&c, 0.0, 0.0, k < 3 ? 0.02 * k : 0.04, 0.0, 0.0); /* still from frame 3 */
		render(&f, &c, 0, 1.0, 700u + k, f.z0);
		give_pose(src, &c);
		give_pose(both, &c);
		run(src, f.z0, k, zb);
		run(both, f.z0, k, zb);
		struct dao_motion_info mi = DAO_MOTION_INFO_INIT;
		dao_context_motion(src, &mi);
		if (k == 1 || k == 2)
			check_reported(src, &last, &c, DAO_MOTION_FROM_SOURCE, 1e-12, 1e-12);
		else
			assert_int_equal(mi.state, k ? DAO_MOTION_STILL : DAO_MOTION_NONE);
		dao_context_motion(both, &mi);
		if (k)
			assert_int_equal(mi.state, DAO_MOTION_REFUSED);
		last = c;
	}
	/* the still frames' motion is the identity exactly */
	struct dao_motion_info mi = DAO_MOTION_INFO_INIT;
	dao_context_motion(src, &mi);
	assert_true(mi.rotation[0] == 1.0 && mi.translation[0] == 0.0);
	dao_context_destroy(src);
	dao_context_destroy(both);
	free(zb);
	fixture_free(&f);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_boundary),
		cmocka_unit_test(test_without_poses),
		cmocka_unit_test(test_pan_true_poses),
		cmocka_unit_test(test_source_matches_icp),
		cmocka_unit_test(test_wall_and_still),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
