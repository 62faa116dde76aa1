/* SPDX-License-Identifier: MIT */
/*
 * Thickness from the image: the face bound at a run's end (face_bound_at,
 * the pixels it holds for: face_bound_pixels), with the straight face's end
 * (straight_face_end, straight_chord) and the lines across it (cross_end).
 * Its constants and result are in thickness_internal.h, the memo it is made
 * through in thickness_memo.h.
 */
#include "kernels/thickness_internal.h"

/*
 * No visible edge face (README.md, "Thickness from the image"): where a run
 * ends at a direct step to something farther (not at a hole: a hole can hide
 * an edge face) and, from at most DAO_BOUND_EDGE_PX pixels of its end
 * inwards, DAO_BOUND_FACE_SEGS segments go straight (a broad face), a face at
 * right angles to the broad face behind its end, of depth T, would show on
 * screen.  Its back edge is the end P moved by -T N (N the broad face's
 * normal, from the neighbouring lines), and the lines across cut the face's
 * parallelogram over a rate (pixels per metre along this line, from the
 * screen motion of P - T N and the outline's direction where the runs of the
 * lines DAO_BOUND_CROSS across end).  Where that face would face the camera
 * (the rate points outwards) but the run shows it over only f pixels, T is at
 * most (f + 1/2) / rate; the rate is taken at the outline's least steep
 * slope within a pixel's rounding of the lines' ends, so a quantised outline
 * cannot make it larger.  Seen square-on, or where the face would look away
 * (every convex outline: a pole's, a sphere's, a box's hidden faces), there is
 * no bound.  It holds for the pixels of the end and of the straight broad face
 * (a board meets the floor in a crease without a step: the floor keeps its
 * value), as a slab's edge face does (run_slab_value: 3 times the ray's
 * length through a slab of thickness T, at least that length plus the
 * spacing of VBAO's samples), with T the middle of what the end allows: the
 * f pixels of an edge face also put T at least (f - 1/2) / rate, so f / rate;
 * with none, half the bound.  Unlike slab_edge it needs only its own end to
 * be an outline.
 *
 * Noisy input (README.md, "Noisy input"): a structured-light sensor's block
 * matching loses the last pixels of a silhouette (its window straddles the
 * edge), with the edge face in them.  So the end may also be a hole of h <=
 * DAO_BOUND_HOLE_PX pixels with something farther by a step beyond it (the
 * lines across may end the same way): the hole can hide an edge face of as
 * many pixels, T is at most (f + h + 1/2) / rate, and the value is made for
 * the middle of (f - 1/2) / rate (0 without f) and that.  And an edge face's
 * pixels may lie in front of the broad face by the depth noise the frame
 * measured (noise_k z^2: a disparity band, 13 mm at 2.1 m, against an 8 mm
 * edge face), not only behind it; and the broad face's direction, which sets
 * its normal and so whether the face behind the end would show, is taken
 * over DAO_BOUND_FACE_LONG pixels where the face goes on straight that far
 * (a chair's backrest under structured light: 0.6 mm of depth a pixel over
 * four pixels, 1.75 clean).
 */

/* d/dT of the pixel coordinates along (al) and across (ac) the line of p - T n, at T = 0 */
static inline void line_rates(const struct line_geom *g, struct vec p, struct vec n, float *al,
			      float *ac)
{
	const float iz2 = 1.0f / (p.z * p.z);
	const float ru = (p.x * n.z - n.x * p.z) * iz2 / g->t->ax;
	const float rv = (p.y * n.z - n.y * p.z) * iz2 / g->t->ay;
	*al = ru * g->du + rv * g->dv;
	*ac = ru * g->dv + rv * g->du;
}

static inline float cross_z(const struct line_geom *g, int k, int c)
{
	const ptrdiff_t cs = g->du != 0.0f ? (ptrdiff_t)g->t->width : 1;
	return g->z[(ptrdiff_t)k * (ptrdiff_t)g->step + (ptrdiff_t)c * cs];
}

static inline struct vec cross_pos(const struct line_geom *g, int k, int c, float zk)
{
	const float u = g->u0 + (float)k * g->du + (float)c * g->dv;
	const float v = g->v0 + (float)k * g->dv + (float)c * g->du;
	return (struct vec){ (u * g->t->ax + g->t->bx) * zk, (v * g->t->ay + g->t->by) * zk, zk };
}

/* From pixel k0 (depth zk) of the line c across outwards (-dir) to where its run ends at a
 * direct step to farther, at most 3 |c| pixels past `end`: *k its last pixel. */
static int cross_end(const struct line_geom *g, int n, int k0, int end, int dir, int c, float zk,
		     int *k)
{
	int j = k0;
	for (;;) {
		const int jn = j - dir;
		if (jn < 0 || jn >= n || (jn - end) * -dir > 3 * (c < 0 ? -c : c))
			return 0;
		const float zn = cross_z(g, jn, c);
		if (!(zn > 0.0f)) {
			/* a hole: the end if beyond it lies something farther by a step */
			int jh = jn;
			while (jh >= 0 && jh < n && !(cross_z(g, jh, c) > 0.0f) &&
			       (jh - jn) * -dir < DAO_BOUND_HOLE_PX)
				jh -= dir;
			if (jh < 0 || jh >= n || !(cross_z(g, jh, c) > 0.0f))
				return 0;
			*k = j;
			return cross_z(g, jh, c) > zk + DAO_THICKNESS_JUMP * zk;
		}
		if (!same_surface(zk, zn)) {
			*k = j;
			return zn > zk;
		}
		j = jn;
		zk = zn;
	}
}

/* Whether the chord to r (the pixel j + 1 from end) from the pixel DAO_BOUND_FACE_LONG
 * back, or from jf where that pixel lies nearer the end than jf, turns by less than the
 * straightness angle from d (dd = |d|^2).  (straight_face_end's jf lies
 * DAO_BOUND_FACE_SEGS or more before j, so the chord spans that many segments or more;
 * a chord of one segment or none would not count.) */
static int straight_chord(const struct line_geom *g, int end, int dir, int j, int jf,
			  struct vec r, struct vec d, float dd)
{
	const int jb = j + 1 - DAO_BOUND_FACE_LONG > jf ? j + 1 - DAO_BOUND_FACE_LONG : jf;
	if (jb >= j)
		return 0;
	const int kb = end + dir * jb;
	const struct vec pb = line_pos(g, (float)kb, g->z[(size_t)kb * g->step]);
	return cos_above_bb(vsub(r, pb), d, dd, DAO_SLAB_STRAIGHT_COS);
}

/* From the pixel end + dir j (at q) of a run len long, the last pixel k of the straight
 * face in direction d: each segment on from there turns by less than the straightness
 * angle from d.  On noisy depth a segment that turns more passes where the chord to it
 * from DAO_BOUND_FACE_LONG pixels back (from no nearer the end than DAO_BOUND_FACE_SEGS
 * before j) does not: the noise tilts single segments of a straight face, a crease
 * turns the chord too (README.md, "Boards seen face-on under Gaussian noise").
 * Returns k's offset from end. */
int straight_face_end(const struct line_geom *g, int end, int dir, int len, int j,
			     struct vec q, struct vec d)
{
	const float dd = vdot(d, d);
	const int noisy = g->t->noise_k > 0.0f;
	const int jf = j > DAO_BOUND_FACE_SEGS ? j - DAO_BOUND_FACE_SEGS : 0;
	while (j + 1 < len) {
		const int k = end + dir * (j + 1);
		const struct vec r = line_pos(g, (float)k, g->z[(size_t)k * g->step]);
		if (!cos_above_bb(vsub(r, q), d, dd, DAO_SLAB_STRAIGHT_COS) &&
		    !(noisy && straight_chord(g, end, dir, j, jf, r, d, dd)))
			break;
		q = r;
		j++;
	}
	return j;
}

/* The bound with the broad face from pixel f of the end on (its segments straight;
 * pt: the points of the end's first pixels, pf = pt[f], pm = pt[f + DAO_BOUND_FACE_SEGS]). */
int face_bound_at(const struct line_geom *g, int n, int s, int e, int dir, int f, int h,
			 struct vec p0, struct vec pf, struct vec pm, struct face_bound *b)
{
	const int end = dir < 0 ? e : s;
	const int len = e - s + 1;
	/* the normal: along the line and across it, DAO_BOUND_CROSS lines to each side
	 * (those first: they are on the broad face's surface or there is no bound) */
	const int c = DAO_BOUND_CROSS;
	const int k0 = end + dir * (f + 2);
	if (!cross_ok(g, c) || !cross_ok(g, -c))
		return 0;
	const float z0 = g->z[(size_t)k0 * g->step];
	const float zp = cross_z(g, k0, c), zm = cross_z(g, k0, -c);
	if (!same_surface(z0, zp) || !same_surface(z0, zm))
		return 0;
	struct vec d = vunit(vsub(pm, pf));
	/* on noisy depth the broad face's direction from DAO_BOUND_FACE_LONG pixels where
	 * the face goes on that far (quantised depth tilts a few pixels' chord) */
	if (g->t->noise_k > 0.0f && f + DAO_BOUND_FACE_LONG < len) {
		const int kl = end + dir * (f + DAO_BOUND_FACE_LONG);
		const struct vec pl = line_pos(g, (float)kl, g->z[(size_t)kl * g->step]);
		const struct vec dl = vunit(vsub(pl, pf));
		if (cos_above(dl, d, DAO_SLAB_STRAIGHT_COS))
			d = dl;
	}
	struct vec nrm = vunit(vcross(d, vsub(cross_pos(g, k0, c, zp), cross_pos(g, k0, -c, zm))));
	if (vdot(nrm, pf) > 0.0f)
		nrm = vneg(nrm);
	/* an edge face's pixels lie behind the broad face (a convex edge), within the
	 * frame's depth noise */
	if (f > 0 && vdot(vsub(p0, pf), nrm) >= g->t->noise_k * pf.z * pf.z)
		return 0;
	/* the screen motion of pf - T nrm, outwards, before the outline's slope */
	float al, ac;
	line_rates(g, pf, nrm, &al, &ac);
	const float slack = fabsf(ac) / (float)(2 * c);
	/* (the lines' ends lie from k0 to 3 c past the end: |ep - em| <= f + 2 + 3 c) */
	if (!(al * (float)-dir + slack * (float)(f + 2 + 3 * c) - slack > 0.0f))
		return 0; /* not outwards at any slope the lines' ends can give */
	/* the outline's direction on screen: where the lines across end */
	int ep, em;
	if (!cross_end(g, n, k0, end, dir, c, zp, &ep) ||
	    !cross_end(g, n, k0, end, dir, -c, zm, &em))
		return 0;
	const float rate = (al - ac * (float)(ep - em) / (float)(2 * c)) * (float)-dir - slack;
	if (!(rate > 0.0f))
		return 0;
	float bt = ((float)(f + h) + DAO_BOUND_ALLOW) / rate;
	/* with the dropouts filled (Gaussian-like noise), where the edge face shows the
	 * prefilter rounds the crease into it, so f counts some of the broad face too: the
	 * end pixel's distance behind the broad face (its far edge's, T) plus a pixel's
	 * extent, at least half a pixel's, when that is less (README.md, "Boards seen
	 * face-on under Gaussian noise") */
	float td = INFINITY;
	if (f > 0 && g->t->noise_k > 0.0f && g->t->fill_px > 0) {
		td = vdot(vsub(pf, p0), nrm) + DAO_BOUND_DEPTH_PX / rate;
		if (td < 0.5f / rate)
			td = 0.5f / rate;
		if (td < bt)
			bt = td;
	}
	if (!(bt < g->t->max))
		return 0;
	/* (the pixels of the straight broad face: face_bound_pixels) */
	b->f = f;
	b->d = d;
	b->normal = nrm;
	b->at = pf;
	/* the f pixels of the edge face put T within (f -+ 1/2) / rate; with none, within
	 * 0 .. 1/2 / rate; a hole of h px beyond the end adds h / rate to the top: the
	 * value is made for the middle (README.md) */
	b->t = (f > 0 ? (float)f + 0.5f * (float)h : 0.5f * ((float)h + DAO_BOUND_ALLOW)) / rate;
	if (td < b->t)
		b->t = td;
	return 1;
}

/* b's pixels, k0 .. k1: from the end of the run s..e over its straight broad face. */
void face_bound_pixels(const struct line_geom *g, int s, int e, int dir,
			      struct face_bound *b)
{
	const int end = dir < 0 ? e : s;
	const int km = end + dir * (b->f + DAO_BOUND_FACE_SEGS);
	const struct vec pm = line_pos(g, (float)km, g->z[(size_t)km * g->step]);
	const int j = straight_face_end(g, end, dir, e - s + 1, b->f + DAO_BOUND_FACE_SEGS, pm, b->d);
	const int kb = end + dir * j;
	b->k0 = end < kb ? end : kb;
	b->k1 = end < kb ? kb : end;
}
