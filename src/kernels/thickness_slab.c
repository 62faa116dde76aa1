/* SPDX-License-Identifier: MIT */
/*
 * Thickness from the image: slabs.  A slab's edge face at a run's end
 * (slab_edge; a slab receding beyond the end: receding_face, thickness_run.c),
 * and the value of a pixel whose ray crosses a slab (run_slab_value) or a
 * face bound's slab (face_bound_value), both through slab_cap.
 */
#include "kernels/thickness_internal.h"

/*
 * A slab's edge face at the end of a run (README.md, "Thickness from the
 * image"): seen from above or below, a board's broad face is wide on screen
 * and its thickness shows only in the narrow face of its edge, which ends
 * the run at its silhouette.  From the end pixel `e` inwards (dir = -1 from
 * the run's last pixel, +1 from its first) the points must go straight for
 * at least two segments (the edge face, at most DAO_SLAB_EDGE_MAX px), then
 * turn by more than acos(crease_cos) (a crease, with at most one segment
 * cutting the corner) onto two more straight segments (the broad face).  A
 * pole's surface turns at every pixel and never passes.  On success: the
 * broad face's direction in the line's plane and the edge face's extent
 * across it, t (the slab's thickness as the line cuts it).
 */
#define DAO_SLAB_EDGE_MAX 24

int slab_edge(const struct line_geom *g, int s, int e, int dir, struct vec *face, float *t)
{
	const int end = dir < 0 ? e : s;
	const int len = e - s + 1;
	/* segment j from the end: from pixel end + dir j to end + dir (j + 1) */
#define SEG(j) (dir < 0 ? vneg(seg(g, end - (j) - 1)) : seg(g, end + (j)))
#define PT(j) line_pos(g, (float)(end + dir * (j)), g->z[(size_t)(end + dir * (j)) * g->step])
	/* (walking the points: each is made once) */
	struct vec p = PT(1);
	const struct vec e0 = vsub(p, PT(0));
	const float ee = vdot(e0, e0);
	int m = 1;
	struct vec d = e0;
	while (m < DAO_SLAB_EDGE_MAX && m + 3 < len) {
		const struct vec q = PT(m + 1);
		d = vsub(q, p);
		if (!cos_above_bb(d, e0, ee, DAO_SLAB_STRAIGHT_COS))
			break;
		p = q;
		m++;
	}
#undef PT
	if (m < 2 || m + 3 >= len || cos_above_bb(d, e0, ee, DAO_SLAB_STRAIGHT_COS))
		return 0;
	/* d = segment m turned away from the edge face: the corner or the broad face */
	int f = m;
	struct vec d1 = SEG(m + 1);
	if (!cos_above(d, d1, DAO_SLAB_STRAIGHT_COS)) {
		/* segment m cuts the corner; the broad face starts one further */
		if (m + 4 >= len)
			return 0;
		f = m + 1;
		d = d1;
		d1 = SEG(m + 2);
		if (!cos_above(d, d1, DAO_SLAB_STRAIGHT_COS))
			return 0;
	}
	if (!abs_cos_below(d, e0, g->t->crease_cos))
		return 0;
#undef SEG
	/* convex: the corner lies on the camera's side of the line from the edge's end to
	 * the broad face (a concave crease, a floor meeting a wall, turns the other way) */
	const float ke = (float)end, kc = (float)(end + dir * f), kf = (float)(end + dir * (f + 2));
	const struct vec pe = line_pos(g, ke, g->z[(size_t)end * g->step]);
	const struct vec pc = line_pos(g, kc, g->z[(size_t)(end + dir * f) * g->step]);
	const struct vec pf = line_pos(g, kf, g->z[(size_t)(end + dir * (f + 2)) * g->step]);
	const struct vec fe = vsub(pe, pf), fc = vsub(pc, pf);
	if (vdot(vcross(fe, fc), vcross(fe, vneg(pf))) <= 0.0f)
		return 0;
	/* the edge face's far end: the outer edge of the end pixel */
	const struct vec pout = line_pos(g, ke + 0.5f * (float)-dir, g->z[(size_t)end * g->step]);
	*face = vunit(vsub(pc, pf));
	*t = vcross_len(vsub(pout, pc), *face);
	return 1;
}

/*
 * vk capped by a slab t thick that a ray |p| = lp long crosses over t lp / sl
 * (sl = lp times the sine of the ray to the slab's face): scale times that,
 * at least that plus the spacing of VBAO's samples, at most that plus the
 * larger of the spacing and DAO_SLAB_EXTRA_SEC spacings over the cosine of
 * the ray to the slab's normal, sl / lp (thickness.h), with no division by 0.
 */
static inline float slab_cap(float vk, float t, float lp, float sl, float spacing)
{
	float across = DAO_THICKNESS_SLAB_SCALE * t * lp;
	const float spaced = t * lp + spacing * sl;
	if (spaced > across)
		across = spaced;
	if (spacing > 0.0f) {
		const float wide = t * lp + DAO_SLAB_EXTRA_SEC * spacing * lp;
		const float most = wide > spaced ? wide : spaced;
		if (across > most)
			across = most;
	}
	return across < vk * sl ? across / sl : vk;
}

/* Pixel k's value vk under the bounds: at most a slab's of thickness t, the middle of the
 * bound's interval (run_slab_value, with the broad face's normal instead of its
 * direction), no division by 0. */
__attribute__((noinline)) float face_bound_value(const struct line_geom *g, int count,
							const struct face_bound *b, int k, float vk)
{
	const struct vec p = line_pos(g, (float)k, g->z[(size_t)k * g->step]);
	const float lp = sqrtf(vdot(p, p));
	for (int q = 0; q < count; q++) {
		if (k < b[q].k0 || k > b[q].k1)
			continue;
		/* the ray crosses the board over t / cos(ray, normal) = t |p| / |p.n| */
		vk = slab_cap(vk, b[q].t, lp, fabsf(vdot(p, b[q].normal)), g->t->spacing);
	}
	return vk;
}

/* Pixel k's value in a run with slabs (r->slabs > 0). */
__attribute__((noinline)) float run_slab_value(const struct line_geom *g,
						      const struct run_est *r, int k)
{
	const struct vec p = line_pos(g, (float)k, g->z[(size_t)k * g->step]);
	const float lp = sqrtf(vdot(p, p));
	float vk = r->value;
	for (int q = 0; q < r->slabs; q++)
		/* the ray crosses the slab over t / sin(ray, face) = t |p| / |p x f| */
		vk = slab_cap(vk, r->slab_t[q], lp, vcross_len(p, r->face[q]), g->t->spacing);
	return vk;
}
