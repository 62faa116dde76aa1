/* SPDX-License-Identifier: MIT */
#include <math.h>

#include "synth/geometry.h"

vec3 v3_normalize(vec3 a)
{
	double l = sqrt(v3_dot(a, a));
	return l > 0 ? v3_scale(a, 1.0 / l) : a;
}

static vec3 rot(const vec3 R[3], vec3 v)
{
	return v3(v3_dot(R[0], v), v3_dot(R[1], v), v3_dot(R[2], v));
}

void synth_prim_transform(struct synth_prim *p, const vec3 R[3], vec3 eye)
{
	p->c = rot(R, v3_sub(p->c, eye));
	p->n = rot(R, p->n);
	for (int i = 0; i < 3; i++)
		p->axis[i] = rot(R, p->axis[i]);
	synth_prim_bound(p);
}

void synth_prim_bound(struct synth_prim *p)
{
	p->bc = p->c;
	switch (p->kind) {
	case SYNTH_HALFSPACE:
		p->br = -1.0;
		break;
	case SYNTH_SPHERE:
		p->br = p->r;
		break;
	case SYNTH_BOX:
		p->br = sqrt(v3_dot(p->half, p->half));
		break;
	case SYNTH_CYLINDER:
		p->br = sqrt(p->r * p->r + p->h * p->h);
		break;
	}
}

static int hit_halfspace(const struct synth_prim *p, vec3 o, vec3 d, double tmin, double tmax,
			 double *t, vec3 *n)
{
	double den = v3_dot(p->n, d);
	if (den >= 0.0) /* moving away from (or along) the solid's surface */
		return 0;
	double tt = v3_dot(p->n, v3_sub(p->c, o)) / den;
	if (tt <= tmin || tt >= tmax)
		return 0;
	*t = tt;
	*n = p->n;
	return 1;
}

static int hit_sphere(const struct synth_prim *p, vec3 o, vec3 d, double tmin, double tmax,
		      double *t, vec3 *n)
{
	vec3 oc = v3_sub(o, p->c);
	double a = v3_dot(d, d), b = v3_dot(oc, d), c = v3_dot(oc, oc) - p->r * p->r;
	double disc = b * b - a * c;
	if (disc < 0.0)
		return 0;
	double s = sqrt(disc);
	double tt = (-b - s) / a;
	if (tt <= tmin)
		tt = (-b + s) / a;
	if (tt <= tmin || tt >= tmax)
		return 0;
	*t = tt;
	*n = v3_scale(v3_add(oc, v3_scale(d, tt)), 1.0 / p->r);
	return 1;
}

/* Slab test in the box's own frame. */
static int hit_box(const struct synth_prim *p, vec3 o, vec3 d, double tmin, double tmax,
		   double *t, vec3 *n)
{
	vec3 oc = v3_sub(o, p->c);
	double lo = -INFINITY, hi = INFINITY;
	int lo_axis = -1, hi_axis = -1;
	double lo_sign = 0, hi_sign = 0;
	const double he[3] = { p->half.x, p->half.y, p->half.z };
	for (int i = 0; i < 3; i++) {
		double oi = v3_dot(p->axis[i], oc), di = v3_dot(p->axis[i], d);
		if (fabs(di) < 1e-300) {
			if (oi < -he[i] || oi > he[i])
				return 0;
			continue;
		}
		double t0 = (-he[i] - oi) / di, t1 = (he[i] - oi) / di;
		double s0 = -1.0, s1 = 1.0;
		if (t0 > t1) {
			double tmp = t0; t0 = t1; t1 = tmp;
			s0 = 1.0, s1 = -1.0;
		}
		if (t0 > lo) { lo = t0; lo_axis = i; lo_sign = s0; }
		if (t1 < hi) { hi = t1; hi_axis = i; hi_sign = s1; }
		if (lo > hi)
			return 0;
	}
	double tt;
	vec3 nn;
	if (lo > tmin && lo_axis >= 0) {
		tt = lo;
		nn = v3_scale(p->axis[lo_axis], lo_sign);
	} else if (hi > tmin && hi_axis >= 0) {
		tt = hi;
		nn = v3_scale(p->axis[hi_axis], hi_sign);
	} else {
		return 0;
	}
	if (tt >= tmax)
		return 0;
	*t = tt;
	*n = nn;
	return 1;
}

static int hit_cylinder(const struct synth_prim *p, vec3 o, vec3 d, double tmin, double tmax,
			double *t, vec3 *n)
{
	vec3 oc = v3_sub(o, p->c);
	double oa = v3_dot(oc, p->n), da = v3_dot(d, p->n);
	vec3 op = v3_sub(oc, v3_scale(p->n, oa)), dp = v3_sub(d, v3_scale(p->n, da));
	double best = tmax;
	vec3 bn = { 0, 0, 0 };
	int found = 0;
	/* side: |op + t dp|^2 = r^2 */
	double a = v3_dot(dp, dp), b = v3_dot(op, dp), c = v3_dot(op, op) - p->r * p->r;
	if (a > 1e-300) {
		double disc = b * b - a * c;
		if (disc >= 0.0) {
			double s = sqrt(disc);
			for (int k = 0; k < 2; k++) {
				double tt = (-b + (k ? s : -s)) / a;
				if (tt <= tmin || tt >= best)
					continue;
				double ax = oa + tt * da;
				if (fabs(ax) > p->h)
					continue;
				best = tt;
				bn = v3_scale(v3_add(op, v3_scale(dp, tt)), 1.0 / p->r);
				found = 1;
				break;
			}
		}
	}
	/* caps at axial +-h */
	if (fabs(da) > 1e-300) {
		for (int k = 0; k < 2; k++) {
			double hc = k ? p->h : -p->h;
			double tt = (hc - oa) / da;
			if (tt <= tmin || tt >= best)
				continue;
			vec3 q = v3_add(op, v3_scale(dp, tt));
			if (v3_dot(q, q) > p->r * p->r)
				continue;
			best = tt;
			bn = v3_scale(p->n, k ? 1.0 : -1.0);
			found = 1;
		}
	}
	if (found) {
		*t = best;
		*n = bn;
	}
	return found;
}

int synth_prim_intersect(const struct synth_prim *p, vec3 o, vec3 d, double tmin, double tmax,
			 double *t, vec3 *n)
{
	switch (p->kind) {
	case SYNTH_HALFSPACE: return hit_halfspace(p, o, d, tmin, tmax, t, n);
	case SYNTH_SPHERE: return hit_sphere(p, o, d, tmin, tmax, t, n);
	case SYNTH_BOX: return hit_box(p, o, d, tmin, tmax, t, n);
	case SYNTH_CYLINDER: return hit_cylinder(p, o, d, tmin, tmax, t, n);
	}
	return 0;
}
