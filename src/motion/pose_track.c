/* SPDX-License-Identifier: MIT */
/* The camera's pose track a context keeps (motion/pose_track.h). */
#include <string.h>

#include "motion/pose_track.h"

void dao_track_end(struct dao_track *t)
{
	memset(t, 0, sizeof *t);
	t->pub.size = sizeof t->pub;
	t->pub.rotation[0] = t->pub.rotation[4] = t->pub.rotation[8] = 1.0;
}

void dao_track_add(struct dao_track *t, int follows, const struct dao_motion_info *mi)
{
	if (!follows || !t->followed)
		dao_track_end(t); /* no track, or the origin of a new one */
	if (!follows)
		return;
	struct dao_pose_track *p = &t->pub;
	t->followed = 1;
	const int later = ++p->frames > 1;
	const int moved = later && dao_motion_accumulate(mi, p->rotation, p->translation) == 1;
	p->accepted += (uint64_t)moved;
	p->refused += (uint64_t)(later && mi->state == DAO_MOTION_REFUSED);
	p->current = !later || moved;
}

int dao_track_follows(const struct dao_params *p)
{
	return p->depth_temporal > 0.0f && p->depth_temporal_motion != DAO_DEPTH_MOTION_OFF;
}
