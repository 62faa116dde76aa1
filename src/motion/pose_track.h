/* SPDX-License-Identifier: MIT */
/*
 * The camera's pose track a context keeps (dao_context_pose_track,
 * <depthao/context.h>): each processed frame's motion composed from the
 * track's first frame, while the motion is followed.  frames 0: no track.
 */
#ifndef DAO_MOTION_POSE_TRACK_H
#define DAO_MOTION_POSE_TRACK_H

#include <depthao/context.h>

/* No track (frames 0, the identity): the motion switched off, a reset.  The
 * next frame that follows the motion starts a new one. */
void dao_track_end(struct dao_pose_track *t);

/*
 * One processed frame, `frame_index` with the depth's `timestamp_ns`:
 * `follows` whether its parameters follow the motion (dao_track_follows),
 * `mi` the motion dao_context_motion reports for it.  The track's first frame
 * is its origin: its own motion (from a frame before the track began) moves
 * nothing.
 */
void dao_track_add(struct dao_pose_track *t, int follows, const struct dao_motion_info *mi,
		   uint64_t frame_index, uint64_t timestamp_ns);

/* Whether parameters follow the camera's motion: the temporal depth filter on
 * and depth-temporal-motion not off (else every motion is NONE). */
int dao_track_follows(const struct dao_params *p);

#endif
