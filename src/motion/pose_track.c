/* SPDX-License-Identifier: MIT */
/* The camera's pose track a context keeps (motion/pose_track.h). */
#include <string.h>

#include "motion/pose_track.h"

void dao_track_end(struct dao_pose_track *t)
{
	memset(t, 0, sizeof *t);
	t->size = sizeof *t;
	t->rotation[0] = t->rotation[4] = t->rotation[8] = 1.0;
}

void dao_track_add(struct dao_pose_track *t, int follows, const struct dao_motion_info *mi,
		   uint64_t frame_index, uint64_t timestamp_ns)
{
	if (!follows) {
		dao_track_end(t);
		return;
	}
	const int later = ++t->frames > 1; /* else the origin of a new track: the identity */
	const int moved = later && dao_motion_accumulate(mi, t->rotation, t->translation) == 1;
	t->accepted += (uint64_t)moved;
	t->refused += (uint64_t)(later && mi->state == DAO_MOTION_REFUSED);
	t->current = !later || moved;
	if (t->current) {
		t->frame_index = frame_index;
		t->timestamp_ns = timestamp_ns;
	}
}

int dao_track_follows(const struct dao_params *p)
{
	return p->depth_temporal > 0.0f && p->depth_temporal_motion != DAO_DEPTH_MOTION_OFF;
}
