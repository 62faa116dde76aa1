/* SPDX-License-Identifier: MIT */
#include <math.h>
#include <string.h>

#include <depthao/pose.h>

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
	if (mi->state != DAO_MOTION_APPLIED && mi->state != DAO_MOTION_STILL)
		return;
	for (int i = 0; i < 12; i++)
		if (!isfinite(i < 9 ? mi->rotation[i] : mi->translation[i - 9]))
			return;
	p->accepted++;
	/* world <- previous <- this: R' = R M_r, t' = R M_t + t */
	double r[9], t[3], q[4];
	for (int i = 0; i < 3; i++) {
		for (int j = 0; j < 3; j++)
			r[i * 3 + j] = p->r[i * 3] * mi->rotation[j] + p->r[i * 3 + 1] * mi->rotation[3 + j] +
				       p->r[i * 3 + 2] * mi->rotation[6 + j];
		t[i] = p->r[i * 3] * mi->translation[0] + p->r[i * 3 + 1] * mi->translation[1] +
		       p->r[i * 3 + 2] * mi->translation[2] + p->t[i];
	}
	/* a rotation still after thousands of products: through the unit quaternion */
	dao_pose_matrix_to_quat(r, q);
	dao_pose_quat_to_matrix(q, p->r);
	memcpy(p->t, t, sizeof t);
}

int pose_track_follows(const struct dao_params *params)
{
	return params->depth_temporal > 0.0f &&
	       params->depth_temporal_motion != DAO_DEPTH_MOTION_OFF;
}

int pose_track_publishable(const struct pose_track *p, const struct dao_params *params)
{
	return pose_track_follows(params) && (p->frames == 1 || p->state != DAO_MOTION_NONE);
}
