/* SPDX-License-Identifier: MIT */
/*
 * Camera poses the caller gives (dao_context_set_pose): the pose of the
 * frame about to be processed, camera-to-world, turned into the motion from
 * that frame to the last one (motion/icp.h's convention, p_prev = R p + t)
 * for depth-temporal-motion=source and source+icp.
 */
#ifndef DAO_MOTION_POSE_PRIOR_H
#define DAO_MOTION_POSE_PRIOR_H

#include <depthao/camera.h>
#include <depthao/error.h>

#include "motion/icp.h"

/* Translations beyond this (m, from the world's origin) are refused as absurd. */
#define DAO_POSE_MAX_TRANSLATION 1.0e6
/* A quaternion's norm must be within this of 1 (it is normalised then). */
#define DAO_POSE_QUAT_TOLERANCE 1.0e-3

struct dao_pose_prior {
	struct dao_pose next, cur, prev; /* camera-to-world */
	int have_next; /* given for the frame about to be processed */
	int have_cur;  /* ... for the frame being processed */
	int have_prev; /* ... for the last frame processed to the end */
};

/* Everything forgotten. */
void dao_pose_prior_clear(struct dao_pose_prior *pp);

/*
 * The pose of the next frame: q = x, y, z, w (unit, rotation camera to
 * world), t = the optical centre in the world (m); q NULL forgets it.
 * -EINVAL with a message for a non-finite value, a quaternion whose norm is
 * not 1 (within DAO_POSE_QUAT_TOLERANCE) or a translation beyond
 * DAO_POSE_MAX_TRANSLATION; the next frame has no pose then.
 */
int dao_pose_prior_set(struct dao_pose_prior *pp, const double q[4], const double t[3],
		       struct dao_error *err);

/* A frame starts: the given pose becomes the current one (and is used up). */
void dao_pose_prior_begin(struct dao_pose_prior *pp);
/* The frame was processed to the end: its pose is the one to compare the next with. */
void dao_pose_prior_end(struct dao_pose_prior *pp);

/* 1 and the motion from the current frame to the last (prev^-1 cur) when both
 * were given; else 0. */
int dao_pose_prior_relative(const struct dao_pose_prior *pp, struct dao_pose *cur_to_prev);

/*
 * depth-temporal-motion=source: the given motion judged as an ICP estimate
 * would be (motion/icp.h bounds: max_angle, max_dist), with the nearest
 * depth of `z` (metres, 0 = no data) on the setup's grid for the stillness
 * test; no depth on the grid: refused (FEW_POINTS).
 */
void dao_pose_prior_result(const struct dao_icp_setup *s, const struct dao_camera *cam,
			   const float *z, const struct dao_pose *given, struct dao_icp_result *out);

#endif
