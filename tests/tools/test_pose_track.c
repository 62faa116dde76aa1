/* SPDX-License-Identifier: MIT */
/*
 * tools/common/pose_track.c (depthao process --pose-out, depthaod's stats):
 * the pose accumulated from per-frame motions against poses composed here
 * independently (a turn of 1 degree a frame about the vertical with a step
 * along the view: after 90 frames a quarter turn, the camera on a known
 * arc); refused, still-less and non-finite motions hold the pose; which
 * poses are handed on (pose_track_publishable).  (The
 * quaternion round trip on every kind of rotation, trace above and below 0:
 * tests/motion/test_pose_math.c.)
 */
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include <depthao/pose.h>

#include "common/pose_track.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* the motion of a camera that turns by `deg` about its y axis and then steps `step` m
 * along its new z: p_prev = R p + t with t = R (0, 0, step) */
static void step_motion(struct dao_motion_info *mi, double deg, double step, int state)
{
	const double a = deg * M_PI / 180.0;
	memset(mi, 0, sizeof *mi);
	mi->size = sizeof *mi;
	mi->state = state;
	const double r[9] = {cos(a), 0, sin(a), 0, 1, 0, -sin(a), 0, cos(a)};
	memcpy(mi->rotation, r, sizeof r);
	mi->translation[0] = sin(a) * step;
	mi->translation[2] = cos(a) * step;
}

static void test_accumulates(void **state)
{
	(void)state;
	struct pose_track p;
	pose_track_reset(&p);
	struct dao_motion_info mi;
	step_motion(&mi, 0.0, 0.0, DAO_MOTION_NONE);
	pose_track_add(&p, &mi); /* the first frame */
	for (int k = 1; k <= 90; k++) {
		step_motion(&mi, 1.0, 0.01, k % 2 ? DAO_MOTION_APPLIED : DAO_MOTION_STILL);
		pose_track_add(&p, &mi);
		/* refused, none and broken estimates in between change nothing */
		step_motion(&mi, 30.0, 1.0, DAO_MOTION_REFUSED);
		pose_track_add(&p, &mi);
		step_motion(&mi, 30.0, 1.0, DAO_MOTION_NONE);
		pose_track_add(&p, &mi);
		step_motion(&mi, 1.0, 0.01, DAO_MOTION_APPLIED);
		mi.translation[1] = NAN;
		pose_track_add(&p, &mi);
	}
	assert_int_equal(p.frames, 1 + 4 * 90);
	assert_int_equal(p.accepted, 90);
	assert_int_equal(p.refused, 90);
	/* after k frames the heading is k degrees; the camera's position is the sum of
	 * steps of 1 cm along the heading after each turn */
	double x = 0.0, z = 0.0;
	for (int k = 1; k <= 90; k++) {
		x += 0.01 * sin(k * M_PI / 180.0);
		z += 0.01 * cos(k * M_PI / 180.0);
	}
	assert_true(fabs(p.t[0] - x) < 1e-9 && fabs(p.t[1]) < 1e-12 && fabs(p.t[2] - z) < 1e-9);
	/* a quarter turn about y: R = [[0,0,1],[0,1,0],[-1,0,0]] */
	const double want[9] = {0, 0, 1, 0, 1, 0, -1, 0, 0};
	for (int i = 0; i < 9; i++)
		assert_true(fabs(p.r[i] - want[i]) < 1e-9);
	double q[4];
	dao_pose_matrix_to_quat(p.r, q);
	assert_true(fabs(q[1] - sin(M_PI / 4)) < 1e-9 && fabs(q[3] - cos(M_PI / 4)) < 1e-9);
	assert_true(fabs(q[0]) < 1e-12 && fabs(q[2]) < 1e-12);
}

/* Which poses are handed on (a sink's /tf): the first frame's, then those of frames
 * whose motion was accepted; none where the motion is not followed. */
static void test_publishable(void **state)
{
	(void)state;
	struct dao_params on, off;
	dao_params_init(&on, DAO_QUALITY_DEFAULT);
	on.depth_temporal = 0.8f;
	on.depth_temporal_motion = DAO_DEPTH_MOTION_ICP;
	off = on;
	off.depth_temporal_motion = DAO_DEPTH_MOTION_OFF;
	struct pose_track p;
	pose_track_reset(&p);
	struct dao_motion_info mi;
	step_motion(&mi, 0.0, 0.0, DAO_MOTION_NONE);
	pose_track_add(&p, &mi);
	assert_true(pose_track_publishable(&p, &on)); /* the origin */
	assert_false(pose_track_publishable(&p, &off));
	static const struct {
		int state, publish;
	} seq[] = {
		{ DAO_MOTION_APPLIED, 1 }, { DAO_MOTION_STILL, 1 }, { DAO_MOTION_REFUSED, 0 },
		{ DAO_MOTION_APPLIED, 1 }, { DAO_MOTION_NONE, 0 }, { DAO_MOTION_STILL, 1 },
	};
	for (size_t k = 0; k < sizeof seq / sizeof seq[0]; k++) {
		step_motion(&mi, 1.0, 0.01, seq[k].state);
		pose_track_add(&p, &mi);
		assert_int_equal(pose_track_publishable(&p, &on), seq[k].publish);
		assert_false(pose_track_publishable(&p, &off));
	}
	step_motion(&mi, 1.0, 0.01, DAO_MOTION_APPLIED);
	mi.rotation[4] = NAN; /* accepted, but not a motion: not moved, not handed on */
	pose_track_add(&p, &mi);
	assert_false(pose_track_publishable(&p, &on));
	/* a track started at a frame with a motion (followed again mid-stream): that frame
	 * is the origin, its motion (from the frame before) moves nothing */
	pose_track_reset(&p);
	step_motion(&mi, 5.0, 0.1, DAO_MOTION_APPLIED);
	pose_track_add(&p, &mi);
	assert_true(pose_track_publishable(&p, &on));
	assert_true(p.r[0] == 1.0 && p.r[2] == 0.0 && p.t[0] == 0.0 && p.t[2] == 0.0);
	assert_int_equal(p.accepted, 0);
	pose_track_add(&p, &mi); /* the next one moves it */
	assert_true(fabs(p.t[2] - cos(5.0 * M_PI / 180.0) * 0.1) < 1e-12);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_accumulates),
		cmocka_unit_test(test_publishable),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
