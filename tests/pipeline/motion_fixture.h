/* SPDX-License-Identifier: MIT */
/*
 * What the camera-motion tests share (test_reproject.c, test_ao_history.c,
 * test_depth_motion.c, test_pose_prior.c), on top of the scene of
 * test_icp_scene.h: poses applied to points, two views of the scene and the
 * motion between them, random and hostile motions, and contexts run on a
 * float depth frame.  Failures end the cmocka test that called.
 */
#ifndef DAO_TEST_MOTION_FIXTURE_H
#define DAO_TEST_MOTION_FIXTURE_H

#include <stddef.h>
#include <stdint.h>

#include <depthao/context.h>
#include <depthao/params.h>

#include "test_icp_scene.h"

/* w = R a + t: camera pose c to world (or a motion cur -> prev applied) */
void pose_apply(const struct dao_pose *c, const double a[3], double w[3]);
/* a = R^T (w - t): the inverse */
void pose_apply_inverse(const struct dao_pose *c, const double w[3], double a[3]);

/* Two camera poses and the motion between them (from cur to prev). */
struct two_views {
	struct dao_pose prev, cur, motion; /* motion = prev^-1 cur */
};
/* The poses from {yaw, pitch (degrees), tx, ty, tz (m)} as pose_from takes them. */
void two_views_make(struct two_views *v, const double prev[5], const double cur[5]);
/* The room as prev sees it into f->z0, as cur sees it into f->z1 (render: noise
 * 0 clean, else noisy with seed0 and seed1). */
void two_views_render(const struct scene_fixture *f, const struct two_views *v, double noise,
		      uint64_t seed0, uint64_t seed1);

/*
 * Motion k of `count` random ones drawn from *st (gaussian): the first half
 * small (yaw and pitch sigma 20 degrees, translation 0.2 m), the rest 250x
 * that; the last three hostile: t[2] NaN, r[0] +infinity, t[0] -infinity.
 */
void fuzzed_motion(uint64_t *st, int k, int count, struct dao_pose *m);

/* The settings for the depth alone: `quality`'s with the stream defaults,
 * algorithm none, prefilter none. */
void depth_only_params(struct dao_params *p, enum dao_quality quality);
/* A context on cam with p but depth_temporal_motion = motion. */
struct dao_context *motion_context(const struct dao_camera *cam, const struct dao_params *p,
				   int motion);
/* One W x H float depth frame through ctx: the AO into ao (GRAY_F32) when ao is
 * not NULL, the filtered depth into zout when zout is not NULL. */
void run_frame(struct dao_context *ctx, float *z, uint64_t index, float *ao, float *zout);

/* mean |z - truth| / truth over the pixels where both have depth */
double rel_mae(const float *z, const float *truth, size_t n);

/* The pose c (camera to world) for ctx's next frame (dao_context_set_pose). */
void give_pose(struct dao_context *ctx, const struct dao_pose *c);

/* The motion ctx applied to the last frame (state APPLIED, asserted) and the true
 * motion prev^-1 cur. */
void applied_motion(struct dao_context *ctx, const struct dao_pose *prev,
		    const struct dao_pose *cur, struct dao_motion_info *mi,
		    struct dao_pose *truth);

#endif
