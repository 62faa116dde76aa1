/* SPDX-License-Identifier: MIT */
/*
 * The true thickness of what each pixel sees: the length of its camera ray
 * inside the solid it hits (synth.h, synth_ray_inside), for measuring
 * thickness estimates against (the ceiling of tests/kernels/thickness_ceiling.c).
 * The solid is the union of the primitives the ray passes through without
 * leaving solid matter: a shelf board ending inside the side panel it
 * touches goes on through the panel.
 */
#include <math.h>

#include "synth/synth.h"

int synth_prim_inside(const struct synth_prim *p, vec3 x)
{
	const vec3 d = v3_sub(x, p->c);
	switch (p->kind) {
	case SYNTH_HALFSPACE:
		return v3_dot(p->n, d) <= 0.0;
	case SYNTH_SPHERE:
		return v3_dot(d, d) <= p->r * p->r;
	case SYNTH_BOX:
		return fabs(v3_dot(d, p->axis[0])) <= p->half.x &&
		       fabs(v3_dot(d, p->axis[1])) <= p->half.y &&
		       fabs(v3_dot(d, p->axis[2])) <= p->half.z;
	case SYNTH_CYLINDER: {
		const double a = v3_dot(d, p->n);
		const vec3 r = v3_sub(d, v3_scale(p->n, a));
		return fabs(a) <= p->h && v3_dot(r, r) <= p->r * p->r;
	}
	}
	return 0;
}

/* how far past a surface a point is taken to test what lies beyond it, m */
#define STEP_PAST 1e-7

double synth_ray_inside(const struct synth_scene *s, vec3 o, vec3 d, double t, int prim)
{
	/* in metres: t along a unit d */
	const double dl = sqrt(v3_dot(d, d));
	d = v3_scale(d, 1.0 / dl);
	t *= dl;
	const double t0 = t;
	int cur = prim;
	/* each primitive is convex: the ray leaves it once, and enters a primitive it
	 * left only through another one, so 2 count steps end any walk */
	for (int guard = 0; guard < 2 * s->count; guard++) {
		const struct synth_prim *p = &s->prims[cur];
		double texit;
		vec3 n;
		if (p->kind == SYNTH_HALFSPACE) {
			/* inside n.(x - c) <= 0: out only moving along n, through the plane
			 * (synth_prim_intersect takes only entries) */
			const double den = v3_dot(p->n, d);
			if (den <= 0.0)
				return INFINITY;
			texit = t - v3_dot(p->n, v3_sub(v3_add(o, v3_scale(d, t)), p->c)) / den;
		} else if (!synth_prim_intersect(p, o, d, t + STEP_PAST, INFINITY, &texit, &n)) {
			return t - t0; /* grazing an edge: the ray is out */
		}
		const vec3 past = v3_add(o, v3_scale(d, texit + STEP_PAST));
		int next = -1;
		for (int i = 0; i < s->count && next < 0; i++)
			if (i != cur && synth_prim_inside(&s->prims[i], past))
				next = i;
		t = texit;
		if (next < 0)
			return t - t0;
		cur = next;
	}
	return t - t0;
}

void synth_inside_plane(const struct synth_scene *s, const struct dao_camera *cam, float *out)
{
	const int w = (int)cam->width, h = (int)cam->height;
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			const vec3 d = v3_normalize(v3((x - cam->cx) / cam->fx, (y - cam->cy) / cam->fy,
						       1.0));
			double t;
			const int prim = synth_trace(s, v3(0, 0, 0), d, 0.0, 1e9, &t, NULL);
			out[(size_t)y * w + x] =
				prim < 0 ? 0.0f : (float)synth_ray_inside(s, v3(0, 0, 0), d, t, prim);
		}
}
