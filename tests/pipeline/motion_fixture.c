/* SPDX-License-Identifier: MIT */
/* What the camera-motion tests share (motion_fixture.h). */
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>

#include <cmocka.h>

#include <depthao/pose.h>

#include "motion_fixture.h"

void pose_apply(const struct dao_pose *c, const double a[3], double w[3])
{
	for (int i = 0; i < 3; i++)
		w[i] = c->r[i * 3] * a[0] + c->r[i * 3 + 1] * a[1] + c->r[i * 3 + 2] * a[2] + c->t[i];
}

void pose_apply_inverse(const struct dao_pose *c, const double w[3], double a[3])
{
	for (int i = 0; i < 3; i++)
		a[i] = c->r[i] * (w[0] - c->t[0]) + c->r[3 + i] * (w[1] - c->t[1]) +
		       c->r[6 + i] * (w[2] - c->t[2]);
}

void two_views_make(struct two_views *v, const double prev[5], const double cur[5])
{
	pose_from(&v->prev, prev[0], prev[1], prev[2], prev[3], prev[4]);
	pose_from(&v->cur, cur[0], cur[1], cur[2], cur[3], cur[4]);
	relative(&v->prev, &v->cur, &v->motion);
}

void two_views_render(const struct scene_fixture *f, const struct two_views *v, double noise,
		      uint64_t seed0, uint64_t seed1)
{
	render(f, &v->prev, 1, noise, seed0, f->z0);
	render(f, &v->cur, 1, noise, seed1, f->z1);
}

void fuzzed_motion(uint64_t *st, int k, int count, struct dao_pose *m)
{
	const double scale = k < count / 2 ? 0.2 : 50.0;
	pose_from(m, scale * 100.0 * gauss(st), scale * 100.0 * gauss(st), scale * gauss(st),
		  scale * gauss(st), scale * gauss(st));
	if (k == count - 3)
		m->t[2] = NAN;
	if (k == count - 2)
		m->r[0] = INFINITY;
	if (k == count - 1)
		m->t[0] = -INFINITY;
}

void depth_only_params(struct dao_params *p, enum dao_quality quality)
{
	dao_params_init(p, quality);
	dao_params_stream_defaults(p);
	p->algorithm = DAO_ALGORITHM_NONE; /* the depth alone */
	p->prefilter = DAO_PREFILTER_NONE; /* the temporal filter's effect alone */
}

struct dao_context *motion_context(const struct dao_camera *cam, const struct dao_params *p,
				   int motion)
{
	struct dao_params q = *p;
	q.depth_temporal_motion = motion;
	struct dao_context *ctx;
	struct dao_error err;
	if (dao_context_create(&ctx, cam, &q, &err))
		fail_msg("%s", err.message);
	return ctx;
}

void run_frame(struct dao_context *ctx, float *z, uint64_t index, float *ao, float *zout)
{
	struct dao_error err;
	struct dao_frame in = {.format = DAO_PIXFMT_DEPTH_F32, .width = W, .height = H,
			       .stride = W * 4, .data = z};
	struct dao_frame out = {.format = DAO_PIXFMT_GRAY_F32, .width = W, .height = H,
				.stride = W * 4, .data = ao};
	struct dao_frame zf = {.format = DAO_PIXFMT_DEPTH_F32, .width = W, .height = H,
			       .stride = W * 4, .data = zout};
	if (dao_context_process(ctx, &in, NULL, index, ao ? &out : NULL, &err) ||
	    (zout && dao_context_get_depth(ctx, &zf, &err)))
		fail_msg("%s", err.message);
}

double rel_mae(const float *z, const float *truth, size_t n)
{
	double s = 0.0;
	size_t c = 0;
	for (size_t i = 0; i < n; i++)
		if (z[i] > 0.0f && truth[i] > 0.0f) {
			s += fabs(z[i] - truth[i]) / truth[i];
			c++;
		}
	return c ? s / (double)c : 0.0;
}

void applied_motion(struct dao_context *ctx, const struct dao_pose *prev,
		    const struct dao_pose *cur, struct dao_motion_info *mi,
		    struct dao_pose *truth)
{
	*mi = (struct dao_motion_info)DAO_MOTION_INFO_INIT;
	dao_context_motion(ctx, mi);
	assert_int_equal(mi->state, DAO_MOTION_APPLIED);
	relative(prev, cur, truth);
}

void give_pose(struct dao_context *ctx, const struct dao_pose *c)
{
	double q[4];
	struct dao_error err;
	dao_pose_matrix_to_quat(c->r, q);
	if (dao_context_set_pose(ctx, q, c->t, &err))
		fail_msg("%s", err.message);
}
