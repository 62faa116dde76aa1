/* SPDX-License-Identifier: MIT */
#include <errno.h>
#include <math.h>
#include <string.h>

#include <depthao/pose.h>

#include "core/error_internal.h"
#include "motion/pose_prior.h"

void dao_pose_prior_clear(struct dao_pose_prior *pp)
{
	memset(pp, 0, sizeof *pp);
}

int dao_pose_prior_set(struct dao_pose_prior *pp, const double q[4], const double t[3],
		       struct dao_error *err)
{
	pp->have_next = 0;
	if (!q)
		return 0;
	if (!t)
		return dao_error_set(err, -EINVAL, "camera pose: the translation is NULL "
				     "(pass both, or a NULL rotation to give no pose)");
	for (int i = 0; i < 7; i++) {
		const double v = i < 4 ? q[i] : t[i - 4];
		if (!isfinite(v))
			return dao_error_set(err, -EINVAL, "camera pose: %s[%d] is not a finite "
					     "number", i < 4 ? "rotation" : "translation", i < 4 ? i : i - 4);
	}
	const double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
	if (!(fabs(n - 1.0) <= DAO_POSE_QUAT_TOLERANCE))
		return dao_error_set(err, -EINVAL, "camera pose: the rotation quaternion (x, y, z, w) "
				     "has norm %g; it must be a unit quaternion (within %g)", n,
				     DAO_POSE_QUAT_TOLERANCE);
	const double d = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
	if (!(d <= DAO_POSE_MAX_TRANSLATION))
		return dao_error_set(err, -EINVAL, "camera pose: the translation is %g m from the "
				     "world's origin, more than %g m: check its unit (metres)", d,
				     DAO_POSE_MAX_TRANSLATION);
	const double u[4] = {q[0] / n, q[1] / n, q[2] / n, q[3] / n};
	dao_pose_quat_to_matrix(u, pp->next.r);
	memcpy(pp->next.t, t, sizeof pp->next.t);
	pp->have_next = 1;
	return 0;
}

void dao_pose_prior_begin(struct dao_pose_prior *pp)
{
	pp->cur = pp->next;
	pp->have_cur = pp->have_next;
	pp->have_next = 0;
}

void dao_pose_prior_end(struct dao_pose_prior *pp)
{
	pp->prev = pp->cur;
	pp->have_prev = pp->have_cur;
}

int dao_pose_prior_relative(const struct dao_pose_prior *pp, struct dao_pose *out)
{
	if (!pp->have_cur || !pp->have_prev)
		return 0;
	const struct dao_pose *a = &pp->prev, *b = &pp->cur;
	/* R = Ra^T Rb, t = Ra^T (tb - ta) */
	for (int i = 0; i < 3; i++) {
		for (int j = 0; j < 3; j++)
			out->r[i * 3 + j] = a->r[i] * b->r[j] + a->r[3 + i] * b->r[3 + j] +
					    a->r[6 + i] * b->r[6 + j];
		out->t[i] = a->r[i] * (b->t[0] - a->t[0]) + a->r[3 + i] * (b->t[1] - a->t[1]) +
			    a->r[6 + i] * (b->t[2] - a->t[2]);
	}
	return 1;
}

void dao_pose_prior_result(const struct dao_icp_setup *s, const struct dao_camera *cam,
			   const float *z, const struct dao_pose *given, struct dao_icp_result *out)
{
	memset(out, 0, sizeof *out);
	out->pose = *given;
	float near = INFINITY;
	const int step = s->step > 0 ? s->step : 1;
	for (uint32_t y = 0; y < cam->height; y += (uint32_t)step)
		for (uint32_t x = 0; x < cam->width; x += (uint32_t)step) {
			const float v = z[(size_t)y * cam->width + x];
			if (v > 0.0f) {
				near = v < near ? v : near;
				out->points++;
			}
		}
	out->near_z = out->points ? near : 0.0f;
	if (!out->points)
		out->reason = DAO_ICP_FEW_POINTS;
	else if (!(dao_pose_angle(given) <= s->max_angle) ||
		 !(dao_pose_distance(given) <= s->max_dist))
		out->reason = DAO_ICP_MOTION;
	else
		out->reason = DAO_ICP_OK;
	out->valid = out->reason == DAO_ICP_OK;
}
