/* SPDX-License-Identifier: MIT */
/*
 * Projective point-to-plane ICP (motion/icp.h).  Scalar; the source points
 * are gathered once per frame into structure-of-arrays scratch (x, y, z and
 * the normal, compacted), so the per-step loop reads them in order and is
 * ready for SIMD lanes; the target side is a gather from the previous plane.
 */
#include <math.h>
#include <string.h>

#include "motion/icp.h"

enum { SOA = 6 }; /* x, y, z, nx, ny, nz */

void dao_pose_identity(struct dao_pose *p)
{
	memset(p, 0, sizeof *p);
	p->r[0] = p->r[4] = p->r[8] = 1.0;
}

double dao_pose_angle(const struct dao_pose *p)
{
	const double c = 0.5 * (p->r[0] + p->r[4] + p->r[8] - 1.0);
	const double s = 0.5 * sqrt((p->r[7] - p->r[5]) * (p->r[7] - p->r[5]) +
				    (p->r[2] - p->r[6]) * (p->r[2] - p->r[6]) +
				    (p->r[3] - p->r[1]) * (p->r[3] - p->r[1]));
	return atan2(s, c);
}

double dao_pose_distance(const struct dao_pose *p)
{
	return sqrt(p->t[0] * p->t[0] + p->t[1] * p->t[1] + p->t[2] * p->t[2]);
}

void dao_icp_setup_default(struct dao_icp_setup *s)
{
	*s = (struct dao_icp_setup){
		.step = 4,
		.iterations = 6,
		.normal_radius = 6,
		.dist_gate = 0.10f,
		.cos_gate = 0.8660254f, /* 30 degrees */
		.huber = 0.01f,
		.max_angle = 0.2618f, /* 15 degrees a frame */
		.max_dist = 0.25f,
		.min_inlier_share = 0.3f,
		.min_inliers = 200,
		.min_cond = 1e-2f,
		.max_rms = 0.03f,
	};
}

size_t dao_icp_scratch_floats(const struct dao_icp_setup *s, int w, int h)
{
	const size_t gx = (size_t)(w + s->step - 1) / (size_t)s->step;
	const size_t gy = (size_t)(h + s->step - 1) / (size_t)s->step;
	return SOA * gx * gy;
}

/* Depth of pixel i of a plane: metres, or 1/inverse; 0 = none. */
static float depth_at(const float *plane, const uint8_t *count, int inverse, size_t i)
{
	const float v = plane[i];
	if (!(v > 0.0f) || (count && !count[i]))
		return 0.0f;
	return inverse ? 1.0f / v : v;
}

/*
 * Position and normal of pixel (x, y): the normal from central differences
 * over `r` pixels, refused at a depth edge (a neighbour more than 3 r %
 * off the centre's depth) or where a neighbour has no data.  Returns 0 or -1.
 */
static int point_normal(const struct dao_camera *cam, const float *plane, const uint8_t *count,
			int inverse, int r, int x, int y, float p[3], float n[3])
{
	const int w = (int)cam->width, h = (int)cam->height;
	if (x < r || y < r || x >= w - r || y >= h - r)
		return -1;
	const size_t i = (size_t)y * (size_t)w + (size_t)x;
	const float z = depth_at(plane, count, inverse, i);
	const float zl = depth_at(plane, count, inverse, i - (size_t)r);
	const float zr = depth_at(plane, count, inverse, i + (size_t)r);
	const float zu = depth_at(plane, count, inverse, i - (size_t)r * (size_t)w);
	const float zd = depth_at(plane, count, inverse, i + (size_t)r * (size_t)w);
	const float tol = 0.03f * (float)r * z;
	if (!(z > 0.0f) || !(fabsf(zl - z) <= tol) || !(fabsf(zr - z) <= tol) ||
	    !(fabsf(zu - z) <= tol) || !(fabsf(zd - z) <= tol))
		return -1;
	const float ux = (float)x * cam->ax + cam->bx, vy = (float)y * cam->ay + cam->by;
	const float ul = ux - (float)r * cam->ax, ur = ux + (float)r * cam->ax;
	const float vu = vy - (float)r * cam->ay, vd = vy + (float)r * cam->ay;
	p[0] = ux * z;
	p[1] = vy * z;
	p[2] = z;
	/* dx = P(x+r) - P(x-r), dy = P(y+r) - P(y-r) */
	const float dx[3] = {ur * zr - ul * zl, vy * (zr - zl), zr - zl};
	const float dy[3] = {ux * (zd - zu), vd * zd - vu * zu, zd - zu};
	float c[3] = {dx[1] * dy[2] - dx[2] * dy[1], dx[2] * dy[0] - dx[0] * dy[2],
		      dx[0] * dy[1] - dx[1] * dy[0]};
	const float len = sqrtf(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
	if (!(len > 0.0f))
		return -1;
	/* towards the camera */
	const float sgn = (c[0] * p[0] + c[1] * p[1] + c[2] * p[2]) > 0.0f ? -1.0f : 1.0f;
	for (int k = 0; k < 3; k++)
		n[k] = sgn * c[k] / len;
	return 0;
}

/* The source grid into scratch (SoA, compacted); returns the count. */
static int gather_source(const struct dao_icp_setup *s, const struct dao_camera *cam,
			 const float *cur_z, float *scratch, size_t cap, float *near_z,
			 float *mean_z)
{
	float *sx = scratch, *sy = scratch + cap, *sz = scratch + 2 * cap;
	float *nx = scratch + 3 * cap, *ny = scratch + 4 * cap, *nz = scratch + 5 * cap;
	int k = 0;
	double sum = 0.0;
	float near = INFINITY;
	for (int y = 0; y < (int)cam->height; y += s->step)
		for (int x = 0; x < (int)cam->width; x += s->step) {
			float p[3], n[3];
			if (point_normal(cam, cur_z, NULL, 0, s->normal_radius, x, y, p, n))
				continue;
			sx[k] = p[0], sy[k] = p[1], sz[k] = p[2];
			nx[k] = n[0], ny[k] = n[1], nz[k] = n[2];
			sum += p[2];
			near = fminf(near, p[2]);
			k++;
		}
	*near_z = k ? near : 0.0f;
	*mean_z = k ? (float)(sum / k) : 1.0f;
	return k;
}

/* The normal equations of one step: A (6x6, rotation columns scaled by 1/scale) and b. */
struct normal_eq {
	double a[36], b[6], r2;
	int n;
};

static void pair_and_accumulate(const struct dao_icp_setup *s, const struct dao_camera *cam,
				const float *prev_inv, const uint8_t *prev_count,
				const float *scratch, size_t cap, int count,
				const struct dao_pose *T, double scale, float gate, struct normal_eq *eq)
{
	const float *sx = scratch, *sy = scratch + cap, *sz = scratch + 2 * cap;
	const float *nx = scratch + 3 * cap, *ny = scratch + 4 * cap, *nz = scratch + 5 * cap;
	float R[9], t[3];
	for (int k = 0; k < 9; k++)
		R[k] = (float)T->r[k];
	for (int k = 0; k < 3; k++)
		t[k] = (float)T->t[k];
	const float inv_ax = 1.0f / cam->ax, inv_ay = 1.0f / cam->ay;
	const float g2 = gate * gate;
	memset(eq, 0, sizeof *eq);
	for (int i = 0; i < count; i++) {
		const float p[3] = {R[0] * sx[i] + R[1] * sy[i] + R[2] * sz[i] + t[0],
				    R[3] * sx[i] + R[4] * sy[i] + R[5] * sz[i] + t[1],
				    R[6] * sx[i] + R[7] * sy[i] + R[8] * sz[i] + t[2]};
		if (!(p[2] > 0.0f))
			continue;
		const float u = (p[0] / p[2] - cam->bx) * inv_ax;
		const float v = (p[1] / p[2] - cam->by) * inv_ay;
		if (!(u > -0.5f && v > -0.5f && u < (float)cam->width && v < (float)cam->height))
			continue;
		float q[3], m[3];
		if (point_normal(cam, prev_inv, prev_count, 1, s->normal_radius, (int)lrintf(u),
				 (int)lrintf(v), q, m))
			continue;
		const float d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
		if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > g2)
			continue;
		const float rn[3] = {R[0] * nx[i] + R[1] * ny[i] + R[2] * nz[i],
				     R[3] * nx[i] + R[4] * ny[i] + R[5] * nz[i],
				     R[6] * nx[i] + R[7] * ny[i] + R[8] * nz[i]};
		if (rn[0] * m[0] + rn[1] * m[1] + rn[2] * m[2] < s->cos_gate)
			continue;
		const double r = (double)m[0] * d[0] + (double)m[1] * d[1] + (double)m[2] * d[2];
		const double w = fabs(r) <= s->huber ? 1.0 : s->huber / fabs(r);
		/* d r / d omega = p x m, d r / d v = m; the lever arm taken at
		 * the pair's midpoint c: at p, its noise along the ray would
		 * correlate with r's and bias the rotation (errors in variables) */
		const float c[3] = {0.5f * (p[0] + q[0]), 0.5f * (p[1] + q[1]), 0.5f * (p[2] + q[2])};
		const double j[6] = {(c[1] * m[2] - c[2] * m[1]) / scale,
				     (c[2] * m[0] - c[0] * m[2]) / scale,
				     (c[0] * m[1] - c[1] * m[0]) / scale, m[0], m[1], m[2]};
		for (int a = 0; a < 6; a++) {
			for (int b = a; b < 6; b++)
				eq->a[a * 6 + b] += w * j[a] * j[b];
			eq->b[a] -= w * j[a] * r;
		}
		eq->r2 += r * r;
		eq->n++;
	}
	for (int a = 0; a < 6; a++)
		for (int b = 0; b < a; b++)
			eq->a[a * 6 + b] = eq->a[b * 6 + a];
}

/* Solves A x = b by Cholesky (A symmetric positive definite); -1 if it is not. */
static int cholesky_solve(const double a_in[36], const double b[6], double x[6])
{
	double l[36] = {0};
	for (int i = 0; i < 6; i++)
		for (int j = 0; j <= i; j++) {
			double s = a_in[i * 6 + j];
			for (int k = 0; k < j; k++)
				s -= l[i * 6 + k] * l[j * 6 + k];
			if (i == j) {
				if (!(s > 0.0))
					return -1;
				l[i * 6 + i] = sqrt(s);
			} else {
				l[i * 6 + j] = s / l[j * 6 + j];
			}
		}
	double y[6];
	for (int i = 0; i < 6; i++) {
		double s = b[i];
		for (int k = 0; k < i; k++)
			s -= l[i * 6 + k] * y[k];
		y[i] = s / l[i * 6 + i];
	}
	for (int i = 5; i >= 0; i--) {
		double s = y[i];
		for (int k = i + 1; k < 6; k++)
			s -= l[k * 6 + i] * x[k];
		x[i] = s / l[i * 6 + i];
	}
	return 0;
}

/* Smallest / largest eigenvalue of a symmetric 6x6 matrix (cyclic Jacobi). */
static double condition(const double a_in[36])
{
	double a[36];
	memcpy(a, a_in, sizeof a);
	for (int sweep = 0; sweep < 30; sweep++) {
		double off = 0.0;
		for (int p = 0; p < 6; p++)
			for (int q = p + 1; q < 6; q++)
				off += a[p * 6 + q] * a[p * 6 + q];
		if (off < 1e-30)
			break;
		for (int p = 0; p < 6; p++)
			for (int q = p + 1; q < 6; q++) {
				const double apq = a[p * 6 + q];
				if (fabs(apq) < 1e-300)
					continue;
				const double th = (a[q * 6 + q] - a[p * 6 + p]) / (2.0 * apq);
				const double t = (th >= 0 ? 1.0 : -1.0) / (fabs(th) + sqrt(th * th + 1.0));
				const double c = 1.0 / sqrt(t * t + 1.0), s = t * c;
				for (int k = 0; k < 6; k++) { /* columns p, q */
					const double kp = a[k * 6 + p], kq = a[k * 6 + q];
					a[k * 6 + p] = c * kp - s * kq;
					a[k * 6 + q] = s * kp + c * kq;
				}
				for (int k = 0; k < 6; k++) { /* rows p, q */
					const double pk = a[p * 6 + k], qk = a[q * 6 + k];
					a[p * 6 + k] = c * pk - s * qk;
					a[q * 6 + k] = s * pk + c * qk;
				}
			}
	}
	double lo = INFINITY, hi = 0.0;
	for (int i = 0; i < 6; i++) {
		lo = fmin(lo, a[i * 7]);
		hi = fmax(hi, a[i * 7]);
	}
	return hi > 0.0 ? fmax(lo, 0.0) / hi : 0.0;
}

/* T <- exp(xi) T, xi = (omega, v); the rotation by Rodrigues' formula. */
static void pose_update(struct dao_pose *T, const double w[3], const double v[3])
{
	const double th = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
	double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
	if (th > 0.0) {
		const double k[3] = {w[0] / th, w[1] / th, w[2] / th};
		const double c = cos(th), s = sin(th), cc = 1.0 - c;
		const double K[9] = {0, -k[2], k[1], k[2], 0, -k[0], -k[1], k[0], 0};
		for (int i = 0; i < 3; i++)
			for (int j = 0; j < 3; j++)
				R[i * 3 + j] = (i == j ? c : 0.0) + s * K[i * 3 + j] + cc * k[i] * k[j];
	}
	struct dao_pose n;
	for (int i = 0; i < 3; i++) {
		for (int j = 0; j < 3; j++)
			n.r[i * 3 + j] = R[i * 3] * T->r[j] + R[i * 3 + 1] * T->r[3 + j] +
					 R[i * 3 + 2] * T->r[6 + j];
		n.t[i] = R[i * 3] * T->t[0] + R[i * 3 + 1] * T->t[1] + R[i * 3 + 2] * T->t[2] +
			 v[i];
	}
	*T = n;
}

static enum dao_icp_verdict verdict(const struct dao_icp_setup *s, const struct dao_icp_result *o)
{
	if (o->inliers < s->min_inliers || (float)o->inliers < s->min_inlier_share * (float)o->points)
		return DAO_ICP_FEW_POINTS;
	if (!(o->cond >= s->min_cond))
		return DAO_ICP_DEGENERATE;
	if (!(o->rms <= s->max_rms))
		return DAO_ICP_RESIDUAL;
	if (!(dao_pose_angle(&o->pose) <= s->max_angle) ||
	    !(dao_pose_distance(&o->pose) <= s->max_dist))
		return DAO_ICP_MOTION;
	return DAO_ICP_OK;
}

void dao_icp_estimate(const struct dao_icp_setup *s, const struct dao_camera *cam,
		      const float *prev_inv, const uint8_t *prev_count, const float *cur_z,
		      const struct dao_pose *prior, float *scratch, struct dao_icp_result *out)
{
	const size_t cap = dao_icp_scratch_floats(s, (int)cam->width, (int)cam->height) / SOA;
	float mean_z;
	memset(out, 0, sizeof *out);
	if (prior)
		out->pose = *prior;
	else
		dao_pose_identity(&out->pose);
	out->points = gather_source(s, cam, cur_z, scratch, cap, &out->near_z, &mean_z);
	out->reason = DAO_ICP_FEW_POINTS;
	if (out->points < s->min_inliers)
		return;
	/* rotation in units of the motion it gives at the mean depth, so that
	 * the system's eigenvalues compare */
	const double scale = mean_z;
	struct normal_eq eq = {0};
	for (int it = 0; it < s->iterations; it++) {
		/* the distance gate from 4 times its value down to it: a first
		 * step from a far start pairs the surfaces that constrain it */
		const float gate = s->dist_gate * (float)(it < 2 ? 4 >> it : 1);
		pair_and_accumulate(s, cam, prev_inv, prev_count, scratch, cap, out->points,
				    &out->pose, scale, gate, &eq);
		out->iterations = it + 1;
		out->inliers = eq.n;
		if (eq.n < s->min_inliers)
			break;
		/* a flat wall leaves in-plane motion free: stop rather than take a
		 * wild step (the first steps, from a poor start, may be worse
		 * conditioned than the last: the verdict takes the last's) */
		out->cond = (float)condition(eq.a);
		double x[6];
		if (!(out->cond >= 1e-3f * s->min_cond) || cholesky_solve(eq.a, eq.b, x)) {
			out->reason = DAO_ICP_DEGENERATE;
			return;
		}
		const double w[3] = {x[0] / scale, x[1] / scale, x[2] / scale};
		pose_update(&out->pose, w, x + 3);
		if (!isfinite(out->pose.t[0] + out->pose.t[1] + out->pose.t[2] + out->pose.r[0])) {
			out->reason = DAO_ICP_NOT_FINITE;
			return;
		}
		/* converged: the step moves no point by more than a micrometre */
		if (fabs(x[0]) + fabs(x[1]) + fabs(x[2]) + fabs(x[3]) + fabs(x[4]) + fabs(x[5]) <
		    1e-6)
			break;
	}
	out->rms = eq.n ? (float)sqrt(eq.r2 / eq.n) : INFINITY;
	out->cond = eq.n ? (float)condition(eq.a) : 0.0f;
	out->reason = verdict(s, out);
	out->valid = out->reason == DAO_ICP_OK;
}

double dao_pose_pixel_extent(const struct dao_pose *p, const struct dao_camera *cam, double z)
{
	const double us[5] = {0, cam->width - 1.0, 0, cam->width - 1.0, cam->cx};
	const double vs[5] = {0, 0, cam->height - 1.0, cam->height - 1.0, cam->cy};
	double worst = 0.0;
	for (int k = 0; k < 5; k++) {
		double c[3], q[3], u, v;
		dao_camera_pixel_to_view(cam, us[k], vs[k], z, c);
		for (int i = 0; i < 3; i++)
			q[i] = p->r[i * 3] * c[0] + p->r[i * 3 + 1] * c[1] + p->r[i * 3 + 2] * c[2] +
			       p->t[i];
		if (dao_camera_view_to_pixel(cam, q, &u, &v))
			return INFINITY;
		worst = fmax(worst, hypot(u - us[k], v - vs[k]));
	}
	return worst;
}
