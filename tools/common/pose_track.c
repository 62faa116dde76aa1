/* SPDX-License-Identifier: MIT */
#include <math.h>
#include <string.h>

#include "common/pose_track.h"

void pose_track_reset(struct pose_track *p)
{
	memset(p, 0, sizeof *p);
	p->r[0] = p->r[4] = p->r[8] = 1.0;
}

void pose_track_quat(const double r[9], double q[4])
{
	const double tr = r[0] + r[4] + r[8];
	double s;
	if (tr > 0.0) {
		s = 2.0 * sqrt(tr + 1.0);
		q[3] = 0.25 * s, q[0] = (r[7] - r[5]) / s, q[1] = (r[2] - r[6]) / s,
		q[2] = (r[3] - r[1]) / s;
	} else if (r[0] > r[4] && r[0] > r[8]) {
		s = 2.0 * sqrt(1.0 + r[0] - r[4] - r[8]);
		q[3] = (r[7] - r[5]) / s, q[0] = 0.25 * s, q[1] = (r[1] + r[3]) / s,
		q[2] = (r[2] + r[6]) / s;
	} else if (r[4] > r[8]) {
		s = 2.0 * sqrt(1.0 + r[4] - r[0] - r[8]);
		q[3] = (r[2] - r[6]) / s, q[0] = (r[1] + r[3]) / s, q[1] = 0.25 * s,
		q[2] = (r[5] + r[7]) / s;
	} else {
		s = 2.0 * sqrt(1.0 + r[8] - r[0] - r[4]);
		q[3] = (r[3] - r[1]) / s, q[0] = (r[2] + r[6]) / s, q[1] = (r[5] + r[7]) / s,
		q[2] = 0.25 * s;
	}
	const double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
	const double k = (q[3] < 0.0 ? -1.0 : 1.0) / (n > 0.0 ? n : 1.0);
	for (int i = 0; i < 4; i++)
		q[i] *= k;
}

void pose_track_matrix(const double q[4], double r[9])
{
	const double x = q[0], y = q[1], z = q[2], w = q[3];
	r[0] = 1.0 - 2.0 * (y * y + z * z), r[1] = 2.0 * (x * y - z * w), r[2] = 2.0 * (x * z + y * w);
	r[3] = 2.0 * (x * y + z * w), r[4] = 1.0 - 2.0 * (x * x + z * z), r[5] = 2.0 * (y * z - x * w);
	r[6] = 2.0 * (x * z - y * w), r[7] = 2.0 * (y * z + x * w), r[8] = 1.0 - 2.0 * (x * x + y * y);
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
	pose_track_quat(r, q);
	pose_track_matrix(q, p->r);
	memcpy(p->t, t, sizeof t);
}
