/* SPDX-License-Identifier: MIT */
#include <string.h>

#include "common/pose_track.h"

void pose_track_reset(struct pose_track *p)
{
	memset(p, 0, sizeof *p);
	p->r[0] = p->r[4] = p->r[8] = 1.0;
}

void pose_track_add(struct pose_track *p, const struct dao_motion_info *mi)
{
	p->frames++;
	p->state = mi->state;
	p->reason = mi->reason;
	p->refused += mi->state == DAO_MOTION_REFUSED;
	/* the first frame is the origin: a motion it has (from a frame before the track
	 * started: the motion switched on mid-stream) moves nothing */
	p->moved = p->frames > 1 && dao_motion_accumulate(mi, p->r, p->t) == 1;
	p->accepted += p->moved;
}

int pose_track_follows(const struct dao_params *params)
{
	return params->depth_temporal > 0.0f &&
	       params->depth_temporal_motion != DAO_DEPTH_MOTION_OFF;
}

int pose_track_publishable(const struct pose_track *p, const struct dao_params *params)
{
	return pose_track_follows(params) && (p->frames == 1 || p->moved);
}
