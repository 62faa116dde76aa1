/* SPDX-License-Identifier: MIT */
/* Rigid transforms: composition, inverse, interpolation (rigid.h; the
 * interpolation is <depthao/pose.h>'s). */
#include "tf/rigid.h"

#include <errno.h>
#include <math.h>

#include <depthao/pose.h>

void dao_rigid_identity(struct dao_rigid *a)
{
	*a = (struct dao_rigid){ { 0, 0, 0, 1 }, { 0, 0, 0 } };
}

/* Hamilton product a b of quaternions x, y, z, w. */
static void quat_mul(const double a[4], const double b[4], double out[4])
{
	const double x = a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1];
	const double y = a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0];
	const double z = a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3];
	const double w = a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2];
	out[0] = x;
	out[1] = y;
	out[2] = z;
	out[3] = w;
}

/* v rotated by the unit quaternion q: v + 2 u x (u x v + w v), u = (x, y, z). */
static void quat_rotate(const double q[4], const double v[3], double out[3])
{
	const double c1[3] = { q[1] * v[2] - q[2] * v[1] + q[3] * v[0],
			       q[2] * v[0] - q[0] * v[2] + q[3] * v[1],
			       q[0] * v[1] - q[1] * v[0] + q[3] * v[2] };
	const double c2[3] = { q[1] * c1[2] - q[2] * c1[1], q[2] * c1[0] - q[0] * c1[2],
			       q[0] * c1[1] - q[1] * c1[0] };
	for (int i = 0; i < 3; i++)
		out[i] = v[i] + 2.0 * c2[i];
}

void dao_rigid_compose(const struct dao_rigid *a, const struct dao_rigid *b, struct dao_rigid *out)
{
	double q[4], t[3];
	quat_mul(a->q, b->q, q);
	quat_rotate(a->q, b->t, t);
	for (int i = 0; i < 3; i++)
		out->t[i] = t[i] + a->t[i];
	for (int i = 0; i < 4; i++)
		out->q[i] = q[i];
}

void dao_rigid_inverse(const struct dao_rigid *a, struct dao_rigid *out)
{
	const double q[4] = { -a->q[0], -a->q[1], -a->q[2], a->q[3] };
	double t[3];
	quat_rotate(q, a->t, t);
	for (int i = 0; i < 3; i++)
		out->t[i] = -t[i];
	for (int i = 0; i < 4; i++)
		out->q[i] = q[i];
}

void dao_rigid_interpolate(const struct dao_rigid *a, const struct dao_rigid *b, double s,
			   struct dao_rigid *out)
{
	dao_pose_interpolate(a->q, a->t, b->q, b->t, s, out->q, out->t);
}

int dao_rigid_check(struct dao_rigid *a, double tolerance, const char **why)
{
	double n = 0.0;
	for (int i = 0; i < 4; i++) {
		if (!isfinite(a->q[i])) {
			*why = "a rotation that is not a finite number";
			return -EINVAL;
		}
		n += a->q[i] * a->q[i];
	}
	for (int i = 0; i < 3; i++)
		if (!isfinite(a->t[i]) || fabs(a->t[i]) > 1e6) {
			*why = "a translation that is not a finite number within 1e6 m";
			return -EINVAL;
		}
	n = sqrt(n);
	if (!(fabs(n - 1.0) <= tolerance)) {
		*why = "a rotation quaternion whose norm is not 1";
		return -EINVAL;
	}
	for (int i = 0; i < 4; i++)
		a->q[i] /= n;
	return 0;
}
