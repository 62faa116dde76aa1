/* SPDX-License-Identifier: MIT */
/* An IMU's rotation over time (imu_track.h). */
#include "tf/imu_track.h"

#include <math.h>
#include <stdlib.h>

#include "tf/rigid.h"

static int by_stamp(const void *a, const void *b)
{
	const struct dao_imu_sample *x = a, *y = b;
	if (x->stamp_ns != y->stamp_ns)
		return x->stamp_ns > y->stamp_ns ? 1 : -1;
	return (x->order > y->order) - (x->order < y->order);
}

static void quat_normalise(double q[4])
{
	const double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
	for (int i = 0; i < 4; i++)
		q[i] /= n;
}

/* exp(v / 2) for a rotation vector v (axis times angle): the unit quaternion */
static void quat_exp_half(const double v[3], double out[4])
{
	const double angle = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
	/* sin(a / 2) / a, by its series where a is tiny (no division by ~0) */
	const double k = angle < 1e-6 ? 0.5 - angle * angle / 48.0 : sin(0.5 * angle) / angle;
	out[0] = v[0] * k;
	out[1] = v[1] * k;
	out[2] = v[2] * k;
	out[3] = cos(0.5 * angle);
}

size_t dao_imu_track(struct dao_imu_sample *s, size_t n, int orientation, uint64_t gap_ns)
{
	if (n == 0)
		return 0;
	for (size_t i = 0; i < n; i++)
		s[i].order = i;
	qsort(s, n, sizeof(*s), by_stamp);
	size_t m = 1;
	for (size_t i = 1; i < n; i++)
		if (s[i].stamp_ns != s[m - 1].stamp_ns)
			s[m++] = s[i];
	if (orientation) {
		for (size_t i = 0; i < m; i++) {
			quat_normalise(s[i].q);
			s[i].segment = 0; /* absolute: a gap loses nothing */
		}
		return m;
	}
	struct dao_rigid q; /* translations stay 0: compose multiplies the rotations */
	dao_rigid_identity(&q);
	double prev_w[3] = { s[0].w[0], s[0].w[1], s[0].w[2] };
	uint64_t prev_t = s[0].stamp_ns;
	size_t segment = 0;
	for (size_t i = 0; i < m; i++) {
		const uint64_t dt_ns = s[i].stamp_ns - prev_t;
		if (i > 0 && dt_ns <= gap_ns) {
			const double dt = (double)dt_ns * 1e-9;
			const double v[3] = { 0.5 * (prev_w[0] + s[i].w[0]) * dt,
					      0.5 * (prev_w[1] + s[i].w[1]) * dt,
					      0.5 * (prev_w[2] + s[i].w[2]) * dt };
			struct dao_rigid step = { .t = { 0.0, 0.0, 0.0 } };
			quat_exp_half(v, step.q);
			dao_rigid_compose(&q, &step, &q);
			quat_normalise(q.q);
		} else if (i > 0) {
			segment++;
		}
		prev_t = s[i].stamp_ns;
		for (int k = 0; k < 3; k++)
			prev_w[k] = s[i].w[k];
		for (int k = 0; k < 4; k++)
			s[i].q[k] = q.q[k];
		s[i].segment = segment;
	}
	return m;
}
