/* SPDX-License-Identifier: MIT */
/* Rigid poses: quaternion <-> rotation matrix, interpolation (<depthao/pose.h>);
 * a pose moved by a frame's motion (dao_motion_accumulate, <depthao/context.h>). */
#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

#include <depthao/context.h>
#include <depthao/pose.h>

void dao_pose_quat_to_matrix(const double q[4], double r[9])
{
	const double x = q[0], y = q[1], z = q[2], w = q[3];
	r[0] = 1 - 2 * (y * y + z * z), r[1] = 2 * (x * y - z * w), r[2] = 2 * (x * z + y * w);
	r[3] = 2 * (x * y + z * w), r[4] = 1 - 2 * (x * x + z * z), r[5] = 2 * (y * z - x * w);
	r[6] = 2 * (x * z - y * w), r[7] = 2 * (y * z + x * w), r[8] = 1 - 2 * (x * x + y * y);
}

/*
 * Shepperd (1978): 4 w^2 = 1 + tr, 4 x^2 = 1 + r0 - r4 - r8 (and y, z alike);
 * the largest of the four is taken from its square root, the others from
 * the off-diagonal sums and differences divided by it.
 */
void dao_pose_matrix_to_quat(const double r[9], double q[4])
{
	const double tr = r[0] + r[4] + r[8];
	double v[4]; /* x, y, z, w */
	if (tr >= r[0] && tr >= r[4] && tr >= r[8]) {
		const double s = 2.0 * sqrt(fmax(1.0 + tr, 0.0));
		v[3] = 0.25 * s;
		v[0] = (r[7] - r[5]) / s, v[1] = (r[2] - r[6]) / s, v[2] = (r[3] - r[1]) / s;
	} else if (r[0] >= r[4] && r[0] >= r[8]) {
		const double s = 2.0 * sqrt(fmax(1.0 + r[0] - r[4] - r[8], 0.0));
		v[0] = 0.25 * s;
		v[3] = (r[7] - r[5]) / s, v[1] = (r[1] + r[3]) / s, v[2] = (r[2] + r[6]) / s;
	} else if (r[4] >= r[8]) {
		const double s = 2.0 * sqrt(fmax(1.0 - r[0] + r[4] - r[8], 0.0));
		v[1] = 0.25 * s;
		v[3] = (r[2] - r[6]) / s, v[0] = (r[1] + r[3]) / s, v[2] = (r[5] + r[7]) / s;
	} else {
		const double s = 2.0 * sqrt(fmax(1.0 - r[0] - r[4] + r[8], 0.0));
		v[2] = 0.25 * s;
		v[3] = (r[3] - r[1]) / s, v[0] = (r[2] + r[6]) / s, v[1] = (r[5] + r[7]) / s;
	}
	/* the largest component is at least 1/2 of a unit quaternion: n > 0 for
	 * anything near a rotation */
	const double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3]);
	const double k = (v[3] < 0.0 ? -1.0 : 1.0) / n;
	for (int i = 0; i < 4; i++)
		q[i] = v[i] * k;
}

void dao_pose_interpolate(const double qa[4], const double ta[3], const double qb[4],
			  const double tb[3], double s, double q[4], double t[3])
{
	double d = 0.0, wa, wb;
	for (int i = 0; i < 4; i++)
		d += qa[i] * qb[i];
	const double sign = d < 0.0 ? -1.0 : 1.0; /* the shorter arc: -qb is the same rotation */
	d = fabs(d);
	if (d > 0.9999995) { /* nearly the same rotation: linear, then normalised */
		wa = 1.0 - s;
		wb = s;
	} else { /* slerp: sin((1-s) th) / sin th, sin(s th) / sin th, cos th = d */
		const double th = acos(d), sn = sin(th);
		wa = sin((1.0 - s) * th) / sn;
		wb = sin(s * th) / sn;
	}
	wb *= sign;
	double v[4], n = 0.0;
	for (int i = 0; i < 4; i++) {
		v[i] = wa * qa[i] + wb * qb[i];
		n += v[i] * v[i];
	}
	n = sqrt(n);
	/* (1 - s) a + s b: a at s = 0 and b at s = 1 exactly */
	double u[3];
	for (int i = 0; i < 3; i++)
		u[i] = (1.0 - s) * ta[i] + s * tb[i];
	for (int i = 0; i < 4; i++)
		q[i] = v[i] / n;
	for (int i = 0; i < 3; i++)
		t[i] = u[i];
}

int dao_motion_accumulate(const struct dao_motion_info *mi, double rotation[9],
			  double translation[3])
{
	if (!mi || !rotation || !translation ||
	    mi->size < offsetof(struct dao_motion_info, translation) + sizeof mi->translation)
		return -EINVAL;
	if (mi->state != DAO_MOTION_APPLIED && mi->state != DAO_MOTION_STILL)
		return 0;
	for (int i = 0; i < 12; i++)
		if (!isfinite(i < 9 ? mi->rotation[i] : mi->translation[i - 9]))
			return 0;
	/* fixed <- previous <- this: R' = R M, t' = R m + t */
	const double *r = rotation, *m = mi->rotation;
	double rn[9], t[3], q[4];
	for (int i = 0; i < 3; i++) {
		for (int j = 0; j < 3; j++)
			rn[i * 3 + j] = r[i * 3] * m[j] + r[i * 3 + 1] * m[3 + j] + r[i * 3 + 2] * m[6 + j];
		t[i] = r[i * 3] * mi->translation[0] + r[i * 3 + 1] * mi->translation[1] +
		       r[i * 3 + 2] * mi->translation[2] + translation[i];
	}
	/* a rotation still after thousands of products */
	dao_pose_matrix_to_quat(rn, q);
	dao_pose_quat_to_matrix(q, rotation);
	memcpy(translation, t, sizeof t);
	return 1;
}
