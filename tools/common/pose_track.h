/* SPDX-License-Identifier: MIT */
/*
 * The camera's pose accumulated from the per-frame motion that
 * depth-temporal-motion=icp estimates (dao_context_motion): camera to world,
 * the world being the optical frame of the first frame (x right, y down,
 * z forward; metres), so that x_world = R x_camera + t, as the TUM RGB-D
 * trajectory format and `depthao synth`'s poses.txt have it.  A frame whose
 * estimate was accepted (state APPLIED or STILL) moves the pose by it; any
 * other (NONE: no history to compare with; REFUSED) keeps it, the motion
 * taken as none, as the filter takes it (the library's
 * dao_motion_accumulate).  What depthao process --pose-out and depthaod's
 * stats share.  The rotation as a quaternion: dao_pose_matrix_to_quat()
 * (<depthao/pose.h>).
 */
#ifndef DAO_TOOLS_POSE_TRACK_H
#define DAO_TOOLS_POSE_TRACK_H

#include <depthao/context.h>

struct pose_track {
	double r[9];  /* row-major rotation, camera to world */
	double t[3];  /* the optical centre in the world, m */
	unsigned long long frames, accepted, refused; /* frames added; estimates used, refused */
	int state, reason; /* the last frame's (enum dao_motion_state, dao_motion_info.reason) */
	int moved;         /* the last frame's motion was accepted: it moved the pose */
};

/* The identity, no frames. */
void pose_track_reset(struct pose_track *p);
/* One processed frame's motion. */
void pose_track_add(struct pose_track *p, const struct dao_motion_info *mi);

/* Whether a run with these parameters follows the camera: the temporal depth
 * filter on and depth-temporal-motion not off (else every state is NONE). */
int pose_track_follows(const struct dao_params *params);

/*
 * Whether the pose after the last pose_track_add() is one to hand on (a
 * sink's /tf): the run follows the camera, and the frame is the track's
 * first (the origin) or its motion was accepted (STILL or APPLIED).  Not
 * after a cut or a gap in the source's poses (NONE: the motion unknown), nor
 * where the estimate was refused (REFUSED: the camera may well have moved;
 * the pose held there would be stale).
 */
int pose_track_publishable(const struct pose_track *p, const struct dao_params *params);

#endif
