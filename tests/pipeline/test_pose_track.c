/* SPDX-License-Identifier: MIT */
/*
 * The camera's pose track a context keeps (dao_context_pose_track, public
 * API), driven by given poses (depth-temporal-motion=source, whose motions
 * are the poses' own to 1e-9: tests/pipeline/test_pose_prior.c) so that the
 * pose is known exactly: it composes the motions from the track's first
 * frame, whatever world the poses were given in; a frame without a motion or
 * with a refused one holds the pose (dead reckoning: the pose after a gap
 * lacks the motion lost in it) and is not current; the origin's own motion
 * moves nothing; the track ends when the motion is switched off (even off
 * and on between two frames), when the temporal depth filter is, and at a
 * reset, and goes on through other new settings; the AO path and the fused
 * shaded call keep it as the depth-only path does; the boundary.  (The
 * composition itself, 2000 random motions: tests/motion/test_pose_math.c.)
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

/* a b: the pose b given in a's frame, into the frame a is given in */
static void compose(const struct dao_pose *a, const struct dao_pose *b, struct dao_pose *out)
{
	struct dao_pose r;
	for (int i = 0; i < 3; i++) {
		for (int j = 0; j < 3; j++)
			r.r[i * 3 + j] = a->r[i * 3] * b->r[j] + a->r[i * 3 + 1] * b->r[3 + j] +
					 a->r[i * 3 + 2] * b->r[6 + j];
		r.t[i] = a->r[i * 3] * b->t[0] + a->r[i * 3 + 1] * b->t[1] +
			 a->r[i * 3 + 2] * b->t[2] + a->t[i];
	}
	*out = r;
}

static void set_params(struct dao_context *ctx, const struct dao_params *p)
{
	struct dao_error err;
	if (dao_context_set_params(ctx, p, &err))
		fail_msg("%s", err.message);
}

/* frame k of a pan with a step sideways, rendered (noisy) into f->z0, its pose in *c */
static void frame(const struct scene_fixture *f, unsigned k, struct dao_pose *c)
{
	pose_from(c, -4.0 + (double)k, 0.3 * k, 0.01 * k, 0.0, 0.0);
	render(f, c, 1, 1.0, 700u + k, f->z0);
}

static struct dao_pose_track track(const struct dao_context *ctx)
{
	struct dao_pose_track pt = DAO_POSE_TRACK_INIT;
	assert_int_equal(dao_context_pose_track_sized(ctx, &pt, sizeof pt), 0);
	assert_int_equal(pt.size, sizeof pt);
	return pt;
}

static void assert_pose(const struct dao_pose_track *pt, const struct dao_pose *want)
{
	for (int i = 0; i < 9; i++)
		if (fabs(pt->rotation[i] - want->r[i]) > 1e-9)
			fail_msg("rotation[%d] %.12f, want %.12f", i, pt->rotation[i], want->r[i]);
	for (int i = 0; i < 3; i++)
		if (fabs(pt->translation[i] - want->t[i]) > 1e-9)
			fail_msg("translation[%d] %.12f, want %.12f", i, pt->translation[i],
				 want->t[i]);
}

static void assert_track(const struct dao_context *ctx, uint64_t frames, int current,
			 uint64_t accepted, uint64_t refused, const struct dao_pose *want)
{
	struct dao_pose_track pt = track(ctx);
	assert_int_equal(pt.frames, frames);
	assert_int_equal(pt.current, current);
	assert_int_equal(pt.accepted, accepted);
	assert_int_equal(pt.refused, refused);
	assert_pose(&pt, want);
}

/* the frame the track's pose is of */
static uint64_t pose_frame(const struct dao_context *ctx)
{
	return track(ctx).frame_index;
}

static int state(const struct dao_context *ctx)
{
	struct dao_motion_info mi = DAO_MOTION_INFO_INIT;
	dao_context_motion(ctx, &mi);
	return mi.state;
}

/*
 * The poses given in a world that is not frame 0's; a frame without a pose,
 * the frame after it (no motion either: it needs two poses), then a jump of
 * 30 degrees (refused).
 */
static void test_composes_and_holds(void **state_)
{
	(void)state_;
	struct scene_fixture f;
	fixture_init(&f);
	struct dao_params p;
	depth_only_params(&p, DAO_QUALITY_DEFAULT);
	struct dao_context *ctx = motion_context(&f.cam, &p, DAO_DEPTH_MOTION_SOURCE);
	struct dao_pose g, id, c[8], w, held, want, turn;
	pose_from(&g, 70.0, -20.0, 5.0, -3.0, 12.0); /* world <- the scene's frame */
	dao_pose_identity(&id);
	assert_track(ctx, 0, 0, 0, 0, &id); /* no frame yet: no track */
	for (unsigned k = 0; k < 7; k++) {
		frame(&f, k, &c[k]);
		relative(&g, &c[k], &w);
		if (k == 6) { /* 30 degrees from frame 5 in one frame: refused */
			pose_from(&turn, 30.0, 0.0, 0.0, 0.0, 0.0);
			compose(&w, &turn, &w);
		}
		if (k != 3)
			give_pose(ctx, &w);
		run_frame(ctx, f.z0, k, NULL, NULL);
		relative(&c[0], &c[k], &want); /* c0^-1 ck: the camera in frame 0's view */
		switch (k) {
		case 0: /* the origin */
			assert_track(ctx, 1, 1, 0, 0, &id);
			break;
		case 1:
		case 2:
			assert_int_equal(state(ctx), DAO_MOTION_APPLIED);
			assert_track(ctx, k + 1, 1, k, 0, &want);
			held = want;
			break;
		case 3: /* no pose: no motion, the pose held (frame 2's) */
		case 4: /* a pose, but none for the frame before */
			assert_int_equal(state(ctx), DAO_MOTION_NONE);
			assert_track(ctx, k + 1, 0, 2, 0, &held);
			assert_int_equal(pose_frame(ctx), 2);
			break;
		case 5: /* the motion 4 -> 5 on the pose held since frame 2: 2 -> 4 is lost */
			assert_int_equal(state(ctx), DAO_MOTION_APPLIED);
			relative(&c[4], &c[5], &w);
			compose(&held, &w, &held);
			assert_track(ctx, 6, 1, 3, 0, &held);
			assert_int_equal(pose_frame(ctx), 5);
			break;
		case 6:
			assert_int_equal(state(ctx), DAO_MOTION_REFUSED);
			assert_track(ctx, 7, 0, 3, 1, &held);
			assert_int_equal(pose_frame(ctx), 5);
			break;
		}
	}
	/* the same pose again: no motion (STILL), accepted, the pose as it was */
	relative(&g, &c[6], &w);
	compose(&w, &turn, &w);
	give_pose(ctx, &w);
	run_frame(ctx, f.z0, 7, NULL, NULL);
	assert_int_equal(state(ctx), DAO_MOTION_STILL);
	assert_track(ctx, 8, 1, 4, 1, &held);
	assert_int_equal(pose_frame(ctx), 7);
	dao_context_destroy(ctx);
	fixture_free(&f);
}

/* Where a track ends and a new one starts; new settings that keep following go on. */
static void test_restarts(void **state_)
{
	(void)state_;
	struct scene_fixture f;
	fixture_init(&f);
	struct dao_params on, off, weaker, unfiltered;
	depth_only_params(&on, DAO_QUALITY_DEFAULT);
	on.depth_temporal_motion = DAO_DEPTH_MOTION_SOURCE;
	assert_true(on.depth_temporal > 0.0f); /* the stream defaults: the filter on */
	off = weaker = unfiltered = on;
	off.depth_temporal_motion = DAO_DEPTH_MOTION_OFF;
	weaker.depth_temporal = 0.5f * on.depth_temporal;
	unfiltered.depth_temporal = 0.0f;
	struct dao_context *ctx = motion_context(&f.cam, &on, DAO_DEPTH_MOTION_SOURCE);
	struct dao_pose c[12], id, want;
	dao_pose_identity(&id);
	unsigned k = 0;
	/* frames 0, 1; new settings that still follow the motion; frame 2 goes on */
	for (; k < 3; k++) {
		if (k == 2)
			set_params(ctx, &weaker);
		frame(&f, k, &c[k]);
		give_pose(ctx, &c[k]);
		run_frame(ctx, f.z0, k, NULL, NULL);
	}
	relative(&c[0], &c[2], &want);
	assert_track(ctx, 3, 1, 2, 0, &want);
	/* switched off: no track at once, nor while off (frame 3) */
	set_params(ctx, &off);
	assert_track(ctx, 0, 0, 0, 0, &id);
	frame(&f, k, &c[k]);
	give_pose(ctx, &c[k]);
	run_frame(ctx, f.z0, k++, NULL, NULL);
	assert_track(ctx, 0, 0, 0, 0, &id);
	/* on again: frame 4 is a new origin, though its motion from frame 3 is known */
	set_params(ctx, &on);
	frame(&f, k, &c[k]);
	give_pose(ctx, &c[k]);
	run_frame(ctx, f.z0, k++, NULL, NULL);
	assert_int_equal(state(ctx), DAO_MOTION_APPLIED);
	assert_track(ctx, 1, 1, 0, 0, &id);
	frame(&f, k, &c[k]);
	give_pose(ctx, &c[k]);
	run_frame(ctx, f.z0, k++, NULL, NULL);
	relative(&c[4], &c[5], &want);
	assert_track(ctx, 2, 1, 1, 0, &want);
	/* off and on again between two frames: frame 6 is a new origin, whose own
	 * motion (a jump of 30 degrees from frame 5, refused) is not counted */
	set_params(ctx, &off);
	set_params(ctx, &on);
	frame(&f, k, &c[k]);
	struct dao_pose turn, jumped;
	pose_from(&turn, 30.0, 0.0, 0.0, 0.0, 0.0);
	compose(&c[k], &turn, &jumped);
	give_pose(ctx, &jumped);
	run_frame(ctx, f.z0, k++, NULL, NULL);
	assert_int_equal(state(ctx), DAO_MOTION_REFUSED);
	assert_track(ctx, 1, 1, 0, 0, &id);
	/* the temporal depth filter off: no motion is followed */
	set_params(ctx, &unfiltered);
	assert_track(ctx, 0, 0, 0, 0, &id);
	set_params(ctx, &on);
	for (unsigned first = k; k < first + 2; k++) {
		frame(&f, k, &c[k]);
		give_pose(ctx, &c[k]);
		run_frame(ctx, f.z0, k, NULL, NULL);
	}
	relative(&c[7], &c[8], &want);
	assert_track(ctx, 2, 1, 1, 0, &want);
	/* a reset: no track until the next frame, its origin */
	dao_context_reset(ctx);
	assert_track(ctx, 0, 0, 0, 0, &id);
	frame(&f, k, &c[k]);
	give_pose(ctx, &c[k]);
	run_frame(ctx, f.z0, k++, NULL, NULL);
	assert_track(ctx, 1, 1, 0, 0, &id);
	dao_context_destroy(ctx);
	fixture_free(&f);
}

/* The AO pipeline, through dao_context_process_shaded (depthaod's call), keeps the
 * same track as the depth alone. */
static void test_ao_path(void **state_)
{
	(void)state_;
	struct scene_fixture f;
	fixture_init(&f);
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	dao_params_stream_defaults(&p);
	struct dao_context *ctx = motion_context(&f.cam, &p, DAO_DEPTH_MOTION_SOURCE);
	struct dao_error err;
	struct dao_frame ao = {0}, rgb = {0}, depth = {0};
	if (dao_frame_alloc(&ao, DAO_PIXFMT_GRAY16, W, H, &err) ||
	    dao_frame_alloc(&rgb, DAO_PIXFMT_RGB24, W, H, &err) ||
	    dao_frame_alloc(&depth, DAO_PIXFMT_DEPTH_F32, W, H, &err))
		fail_msg("%s", err.message);
	struct dao_pose c[3], want;
	for (unsigned k = 0; k < 3; k++) {
		frame(&f, k, &c[k]);
		for (int y = 0; y < H; y++)
			memcpy((uint8_t *)depth.data + (size_t)y * depth.stride, f.z0 + (size_t)y * W,
			       W * sizeof(float));
		give_pose(ctx, &c[k]);
		depth.timestamp_ns = 1000000000u + 33333333u * k;
		if (dao_context_process_shaded(ctx, &depth, NULL, k, &ao, &rgb, &err))
			fail_msg("%s", err.message);
	}
	relative(&c[0], &c[2], &want);
	assert_track(ctx, 3, 1, 2, 0, &want);
	assert_int_equal(track(ctx).timestamp_ns, 1000000000u + 33333333u * 2);
	/* a frame that fails half way (normals of the wrong format): not this frame's
	 * pose, nor moved; the next frame starts the histories over (no motion) */
	struct dao_frame bad = ao;
	give_pose(ctx, &c[2]);
	assert_int_equal(dao_context_process(ctx, &depth, &bad, 3, &ao, &err), -EINVAL);
	assert_track(ctx, 3, 0, 2, 0, &want);
	give_pose(ctx, &c[2]);
	depth.timestamp_ns = 2000000000u;
	if (dao_context_process(ctx, &depth, NULL, 4, &ao, &err))
		fail_msg("%s", err.message);
	assert_int_equal(state(ctx), DAO_MOTION_NONE);
	assert_track(ctx, 4, 0, 2, 0, &want);
	/* the pose held is frame 2's, and says so */
	assert_int_equal(pose_frame(ctx), 2);
	assert_int_equal(track(ctx).timestamp_ns, 1000000000u + 33333333u * 2);
	dao_context_destroy(ctx);

	/* the depth alone with a shaded image asked for: -ENODATA, but the frame was
	 * processed and the track goes on (depthaod and Python rely on it) */
	struct dao_params none;
	depth_only_params(&none, DAO_QUALITY_DEFAULT);
	ctx = motion_context(&f.cam, &none, DAO_DEPTH_MOTION_SOURCE);
	for (unsigned k = 0; k < 2; k++) {
		give_pose(ctx, &c[k]);
		assert_int_equal(dao_context_process_shaded(ctx, &depth, NULL, k, &ao, &rgb, &err),
				 -ENODATA);
	}
	relative(&c[0], &c[1], &want);
	assert_track(ctx, 2, 1, 1, 0, &want);
	dao_frame_free(&ao), dao_frame_free(&rgb), dao_frame_free(&depth);
	dao_context_destroy(ctx);
	fixture_free(&f);
}

static void test_boundary(void **state_)
{
	(void)state_;
	struct scene_fixture f;
	fixture_init(&f);
	struct dao_params p;
	depth_only_params(&p, DAO_QUALITY_DEFAULT);
	struct dao_context *ctx = motion_context(&f.cam, &p, DAO_DEPTH_MOTION_ICP);
	struct dao_pose_track pt;
	assert_int_equal(dao_context_pose_track_sized(NULL, &pt, sizeof pt), -EINVAL);
	assert_int_equal(dao_context_pose_track_sized(ctx, NULL, sizeof pt), -EINVAL);
	assert_int_equal(dao_context_pose_track_sized(ctx, &pt, 2), -EINVAL);
	/* an older program's shorter struct: its bytes only, and the size says so */
	memset(&pt, 0xab, sizeof pt);
	const size_t older = offsetof(struct dao_pose_track, frames);
	assert_int_equal(dao_context_pose_track_sized(ctx, &pt, older), 0);
	assert_int_equal(pt.size, older);
	assert_int_equal(pt.current, 0);
	struct dao_pose_track none = DAO_POSE_TRACK_INIT;
	dao_context_pose_track(ctx, &none); /* no track: frame 0, no time */
	assert_int_equal(none.frames, 0);
	assert_int_equal(none.frame_index, 0);
	assert_int_equal(none.timestamp_ns, 0);
	const uint8_t *tail = (const uint8_t *)&pt + older;
	for (size_t i = 0; i < sizeof pt - older; i++)
		assert_int_equal(tail[i], 0xab);
	dao_context_destroy(ctx);
	fixture_free(&f);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_composes_and_holds),
		cmocka_unit_test(test_restarts),
		cmocka_unit_test(test_ao_path),
		cmocka_unit_test(test_boundary),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
