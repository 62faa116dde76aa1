/* SPDX-License-Identifier: MIT */
/*
 * Thickness from the image: the extent of each surface's run along rows and
 * columns (thickness.h).  Two passes, O(1) per pixel, no allocation.
 */
#include "kernels/thickness.h"

#include "core/half.h"
#include "core/math_util.h"
#include "core/multiversion.h"
#include "kernels/gtao_planes.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#ifdef __SSE2__
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#include <immintrin.h>
#endif

void dao_thickness_setup_init(struct dao_thickness_setup *t, const struct dao_camera *cam,
			      float max)
{
	t->width = (int)cam->width;
	t->height = (int)cam->height;
	t->ax = cam->ax;
	t->ay = cam->ay;
	t->bx = cam->bx;
	t->by = cam->by;
	t->max = max;
	t->crease_cos = cosf(DAO_SLAB_CREASE_DEG * (DAO_PI_F / 180.0f));
	t->spacing = 0.0f;
	t->noise_k = 0.0f;
	t->fill_px = DAO_THICKNESS_FILL_PX;
}

void dao_thickness_setup_rounding(struct dao_thickness_setup *t, float scale)
{
	float a = (scale - DAO_SLAB_ROUND_FROM) / (DAO_SLAB_ROUND_TO - DAO_SLAB_ROUND_FROM);
	a = a > 0.0f ? (a < 1.0f ? a : 1.0f) : 0.0f;
	const float deg = DAO_SLAB_CREASE_DEG + a * (DAO_SLAB_CREASE_ROUNDED_DEG - DAO_SLAB_CREASE_DEG);
	t->crease_cos = cosf(deg * (DAO_PI_F / 180.0f));
}

void dao_thickness_setup_noise(struct dao_thickness_setup *t, float scale, float sigma)
{
	t->noise_k = scale > DAO_SLAB_ROUND_FROM ? DAO_THICKNESS_NOISE_TOL * sigma : 0.0f;
	t->fill_px = scale <= (float)DAO_THICKNESS_FILL_PX ? DAO_THICKNESS_FILL_PX : 0;
}

/* (comparisons, not fminf: libm's is a call per pixel, a sixth of the time) */
static inline int same_surface(float a, float b)
{
	return a > 0.0f && b > 0.0f && fabsf(a - b) <= DAO_THICKNESS_JUMP * (a < b ? a : b);
}

/*
 * A run ends on the outline of its object when the next pixel is farther, or
 * when it has no data and the first pixel with data beyond the hole is
 * farther by more than a step (or there is none up to the border); at the
 * border or in front of an occluder the surface goes on unseen.  A hole with
 * the same surface beyond it (a sensor's dropouts inside a wall, a floor or a
 * box) or something nearer says nothing about where the surface ends.  The
 * run's end pixel is z[k * step], the next one out is k + dir (in 0..n-1).
 * Each hole is walked by at most the two runs beside it.
 */
static inline int outline(const float *z, size_t step, int n, int k, int dir)
{
	const float inside = z[(size_t)k * step];
	int j = k + dir;
	const float next = z[(size_t)j * step];
	if (next > 0.0f)
		return next > inside;
	while (j >= 0 && j < n && !(z[(size_t)j * step] > 0.0f))
		j += dir;
	return j < 0 || j >= n || z[(size_t)j * step] > inside + DAO_THICKNESS_JUMP * inside;
}

void dao_thickness_fill_rows(const struct dao_thickness_setup *t, const float *z, float *zf,
			     int y0, int y1)
{
	const int w = t->width;
	for (int y = y0; y < y1; y++) {
		const float *zr = z + (size_t)y * w;
		float *fr = zf + (size_t)y * w;
		memcpy(fr, zr, (size_t)w * sizeof(float));
		int x = 0;
		while (x < w) {
#ifdef __SSE2__
			/* (four pixels with depth at a time: the same test) */
			while (x + 4 <= w &&
			       _mm_movemask_ps(_mm_cmpgt_ps(_mm_loadu_ps(zr + x), _mm_setzero_ps())) == 0xf)
				x += 4;
			if (x >= w)
				break;
#endif
			if (zr[x] > 0.0f) {
				x++;
				continue;
			}
			const int a = x;
			while (x < w && !(zr[x] > 0.0f))
				x++;
			/* the hole a .. x - 1 */
			const int len = x - a;
			if (a > 0 && x < w && len <= t->fill_px && same_surface(zr[a - 1], zr[x])) {
				const float za = zr[a - 1], dz = (zr[x] - za) / (float)(len + 1);
				for (int k = 0; k < len; k++)
					fr[a + k] = za + dz * (float)(k + 1);
			}
		}
	}
}

struct vec { float x, y, z; };

static inline struct vec vsub(struct vec a, struct vec b)
{
	return (struct vec){ a.x - b.x, a.y - b.y, a.z - b.z };
}

static inline float vdot(struct vec a, struct vec b)
{
	return a.x * b.x + a.y * b.y + a.z * b.z;
}

static inline struct vec vcross(struct vec a, struct vec b)
{
	return (struct vec){ a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x };
}

static inline float vcross_len(struct vec a, struct vec b)
{
	const struct vec c = vcross(a, b);
	return sqrtf(vdot(c, c));
}

static inline struct vec vunit(struct vec a)
{
	const float l = sqrtf(vdot(a, a));
	return l > 0.0f ? (struct vec){ a.x / l, a.y / l, a.z / l } : a;
}

static inline struct vec vneg(struct vec a)
{
	return (struct vec){ -a.x, -a.y, -a.z };
}

/* cos(a, b) >= c (c > 0), without roots or divisions; bb = vdot(b, b) (made once where b
 * stays the same) */
static inline int cos_above_bb(struct vec a, struct vec b, float bb, float c)
{
	const float d = vdot(a, b);
	return d > 0.0f && d * d >= c * c * vdot(a, a) * bb;
}

static inline int cos_above(struct vec a, struct vec b, float c)
{
	return cos_above_bb(a, b, vdot(b, b), c);
}

/* |cos(a, b)| <= c */
static inline int abs_cos_below(struct vec a, struct vec b, float c)
{
	const float d = vdot(a, b);
	return d * d <= c * c * vdot(a, a) * vdot(b, b);
}

struct fb_memo;

/* One line: its pixels' depths z[k * step] at (u0 + k du, v0 + k dv); memo: the face
 * bounds made so far in this pass (face_bound; NULL: none). */
struct line_geom {
	const struct dao_thickness_setup *t;
	const float *z;
	size_t step;
	float u0, v0, du, dv;
	struct fb_memo *memo;
};

/* The view position of the point k pixels along the line (k may be fractional), at depth zk. */
static inline struct vec line_pos(const struct line_geom *g, float k, float zk)
{
	const float u = g->u0 + k * g->du, v = g->v0 + k * g->dv;
	return (struct vec){ (u * g->t->ax + g->t->bx) * zk, (v * g->t->ay + g->t->by) * zk, zk };
}

/* The segment from pixel k to pixel k + 1. */
static inline struct vec seg(const struct line_geom *g, int k)
{
	const struct vec a = line_pos(g, (float)k, g->z[(size_t)k * g->step]);
	const struct vec b = line_pos(g, (float)(k + 1), g->z[(size_t)(k + 1) * g->step]);
	return vsub(b, a);
}

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
#define DAO_SLAB_STRAIGHT_COS 0.94f /* 20 degrees */

static int slab_edge(const struct line_geom *g, int s, int e, int dir, struct vec *face, float *t)
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
#define DAO_BOUND_EDGE_PX 8   /* an edge face's pixels, at most */
#define DAO_BOUND_FACE_SEGS 4 /* the broad face's straight segments, at least */
#define DAO_BOUND_CROSS 2     /* the lines across the normal and the outline come from */
#define DAO_BOUND_ALLOW 0.5f  /* px: the face's extent beyond its pixels' centres */
#define DAO_BOUND_DEPTH_PX 1.0f /* px: added to the end's depth behind the face */
#define DAO_BOUND_FACE_LONG 12 /* noisy depth: the broad face's direction over this, px */
#define DAO_BOUND_HOLE_PX 8   /* a hole's pixels beyond the end, at most (README.md:
			       * 4 and 8 tried) */

struct face_bound {
	struct vec normal; /* the broad face's, towards the camera */
	float t;           /* the thickness across it its value is made for, m (the middle of
			    * what the bound and the end's pixels allow) */
	int k0, k1;        /* the pixels it holds for, k0 <= k1 */
	struct vec at;     /* a point of the broad face */
	int f;             /* the broad face's first pixel from the end, */
	struct vec d;      /* and its direction (k0, k1: straight_face_end from there) */
};

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

/* The line c across from this one (rows: a row, columns: a column) is in the image. */
static inline int cross_ok(const struct line_geom *g, int c)
{
	const int li = g->du != 0.0f ? (int)g->v0 : (int)g->u0;
	const int nl = g->du != 0.0f ? g->t->height : g->t->width;
	return li + c >= 0 && li + c < nl;
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

/* Noisy depth whose dropouts are not filled (structured light, active stereo, ToF): where
 * the bound lent by the lines beside and the hidden face apply. */
static inline int noisy_unfilled(const struct dao_thickness_setup *t)
{
	return t->noise_k > 0.0f && t->fill_px == 0;
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
static int straight_face_end(const struct line_geom *g, int end, int dir, int len, int j,
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
static int face_bound_at(const struct line_geom *g, int n, int s, int e, int dir, int f, int h,
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
static void face_bound_pixels(const struct line_geom *g, int s, int e, int dir,
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

/*
 * The face bounds a pass has made, by line, end pixel and direction: a line's
 * end that carried_bound tries (the line across, its run cut to what
 * face_bound looks at) is often the end of that line's own run, whose bound
 * the pass makes too (a checkerboard's every square, README.md).  The same
 * arithmetic on the same pixels: the run's length matters only to how many of
 * its points face_bound looks at, to the pixels the bound holds for (made by
 * each caller) and, on noisy depth, to the broad face's direction over
 * DAO_BOUND_FACE_LONG pixels; so an entry is found only for the same length as
 * fb_memo_len counts it.  Direct-mapped; an entry overwritten is made again.
 */
#define FB_MEMO_BITS 8
#define FB_LOOKED (DAO_BOUND_EDGE_PX + DAO_BOUND_FACE_SEGS + 1) /* points face_bound looks at */
struct fb_memo_entry {
	int line, k, dir; /* dir 0: empty */
	int len;          /* fb_memo_len of the run */
	int full;         /* len from the whole run from k (else a cut of it: carried_bound) */
	int ok;
	struct face_bound b;
};
struct fb_memo {
	struct fb_memo_entry e[1 << FB_MEMO_BITS];
};

static void fb_memo_clear(struct fb_memo *m)
{
	for (int i = 0; i < 1 << FB_MEMO_BITS; i++)
		m->e[i].dir = 0;
}

static inline int line_index(const struct line_geom *g)
{
	return g->du != 0.0f ? (int)g->v0 : (int)g->u0;
}

static inline struct fb_memo_entry *fb_memo_slot(struct fb_memo *m, int line, int k, int dir)
{
	const uint32_t key = ((uint32_t)k * 2u + (dir > 0)) * 0x9E3779B1u + (uint32_t)line * 0x85EBCA77u;
	return &m->e[key >> (32 - FB_MEMO_BITS)];
}

/* A run's length as far as its face bound depends on it: the points looked at, on noisy
 * depth up to the broad face's direction (DAO_BOUND_FACE_LONG past the last edge face
 * pixel tried: a run longer than that gives the same bound). */
#define FB_LOOKED_NOISY (DAO_BOUND_EDGE_PX + DAO_BOUND_FACE_LONG + 1)
static inline int fb_memo_len(const struct line_geom *g, int len)
{
	const int most = g->t->noise_k > 0.0f ? FB_LOOKED_NOISY : FB_LOOKED;
	return len < most ? len : most;
}

/* Whether the end of the run s..e (dir as face_bound's) can have a bound: a direct step
 * to farther, or a hole of at most DAO_BOUND_HOLE_PX px with something farther by a step
 * beyond it (*h its pixels; else 0).  carried_bound and neighbour_bound need it too. */
static inline __attribute__((always_inline)) int end_beyond(const struct line_geom *g, int n,
							    int end, int dir, int *h)
{
	const int out = end - dir;
	*h = 0;
	if (out < 0 || out >= n)
		return 0;
	const float zend = g->z[(size_t)end * g->step];
	if (!(g->z[(size_t)out * g->step] > zend)) {
		if (g->z[(size_t)out * g->step] > 0.0f)
			return 0; /* something nearer */
		/* a hole of at most DAO_BOUND_HOLE_PX px with something farther by a step
		 * beyond it: it can hide an edge face of as many pixels */
		int j = out;
		while (j >= 0 && j < n && !(g->z[(size_t)j * g->step] > 0.0f) &&
		       *h < DAO_BOUND_HOLE_PX) {
			j -= dir;
			(*h)++;
		}
		if (j < 0 || j >= n || !(g->z[(size_t)j * g->step] > zend + DAO_THICKNESS_JUMP * zend))
			return 0;
	}
	return 1;
}

static inline __attribute__((always_inline)) int bound_end(const struct line_geom *g, int n,
							   int s, int e, int dir, int *h)
{
	return e - s + 1 > DAO_BOUND_FACE_SEGS && end_beyond(g, n, dir < 0 ? e : s, dir, h);
}

/* face_bound without b's pixels (k0, k1), through the memo, at an end that passed
 * bound_end (h: its hole); full: s..e is the whole run from the end inwards, or at
 * least FB_LOOKED_NOISY of it (fb_memo_entry). */
static inline __attribute__((always_inline)) int face_bound_memo_at(const struct line_geom *g,
								    int n, int s, int e,
								    int dir, int h, int full,
								    struct face_bound *b)
{
	const int end = dir < 0 ? e : s;
	const int len = e - s + 1;
	/* made already in this pass? */
	const int line = line_index(g);
	const int mlen = fb_memo_len(g, len);
	struct fb_memo_entry *me = NULL;
	if (g->memo) {
		me = fb_memo_slot(g->memo, line, end, dir);
		if (me->dir == dir && me->line == line && me->k == end && me->len == mlen) {
			if (me->ok)
				*b = me->b;
			return me->ok;
		}
	}
	/* the end's first points and segments, each made once */
	struct vec pt[FB_LOOKED];
	struct vec sg[FB_LOOKED - 1];
	int np = FB_LOOKED;
	if (np > len)
		np = len;
	for (int j = 0; j < np; j++) {
		const int k = end + dir * j;
		pt[j] = line_pos(g, (float)k, g->z[(size_t)k * g->step]);
		if (j > 0)
			sg[j - 1] = vsub(pt[j], pt[j - 1]);
	}
	int tried = 0, ok = 0;
	for (int f = 0; f <= DAO_BOUND_EDGE_PX && f + DAO_BOUND_FACE_SEGS < np; f++) {
		/* (a straight stretch is tried once, from its first pixel that passes) */
		if (f > 0 && !cos_above(sg[f], sg[f - 1], DAO_SLAB_STRAIGHT_COS))
			tried = 0;
		if (tried)
			continue;
		int j = f + 1;
		const float ff = vdot(sg[f], sg[f]);
		while (j < f + DAO_BOUND_FACE_SEGS &&
		       cos_above_bb(sg[j], sg[f], ff, DAO_SLAB_STRAIGHT_COS))
			j++;
		if (j < f + DAO_BOUND_FACE_SEGS)
			continue;
		if (face_bound_at(g, n, s, e, dir, f, h, pt[0], pt[f], pt[f + DAO_BOUND_FACE_SEGS],
				  b)) {
			ok = 1;
			break;
		}
		tried = 1;
	}
	if (me) {
		me->line = line;
		me->k = end;
		me->dir = dir;
		me->len = mlen;
		me->full = full;
		me->ok = ok;
		if (ok)
			me->b = *b;
	}
	return ok;
}

/* face_bound without b's pixels (k0, k1), through the memo. */
static inline __attribute__((always_inline)) int face_bound_memo(const struct line_geom *g, int n,
								 int s, int e, int dir,
								 struct face_bound *b)
{
	int h;
	return bound_end(g, n, s, e, dir, &h) && face_bound_memo_at(g, n, s, e, dir, h, 0, b);
}

/* The bound at the end of the run s..e of a line of n pixels (dir as slab_edge's);
 * own: the line's whole run (else one cut to what is looked at, whose pixels k0, k1
 * are not made). */
static inline __attribute__((always_inline)) int face_bound(const struct line_geom *g, int n, int s, int e, int dir,
		      struct face_bound *b, int own)
{
	const int ok = face_bound_memo(g, n, s, e, dir, b);
	if (ok && own)
		face_bound_pixels(g, s, e, dir, b);
	return ok;
}

/*
 * A bound carried across (README.md, "No visible edge face"): where the end of
 * the run s..e (dir as face_bound's) is a direct step to something farther
 * but gives no bound of its own (the side face of a turned board, which looks
 * away, ends the columns of its far end on a slanted outline), the outline is
 * followed over the lines across, at most DAO_BOUND_CARRY of them to each
 * side, each line's end walked out from the last one's while it stays on the
 * surface.  Where the outline runs along the lines (their ends 2 px or more
 * apart), their ends are like this one and are not tried; where it turns to
 * cross them (the board's top), the line there and the next are, and the
 * first whose end gives a bound on the same broad face (this end's point
 * within DAO_BOUND_CARRY_TOL of its plane, for the distance between them)
 * lends it to the straight broad face at this end.  An outline that crosses
 * the lines at this end is followed no further (each line's own end is the
 * same), unless it runs along them on the other side (a corner).
 */
#define DAO_BOUND_CARRY 16
#define DAO_BOUND_CARRY_WALK 64 /* pixels walked out along a line across, at most */
#define DAO_BOUND_CARRY_TOL 0.1f

__attribute__((noinline)) static int carried_bound(const struct line_geom *g, int n, int s,
						   int e, int dir, struct face_bound *b)
{
	const int end = dir < 0 ? e : s;
	const int len = e - s + 1;
	const int out = end - dir;
	const float *z = g->z;
	const size_t st = g->step;
	if (out < 0 || out >= n || len <= DAO_BOUND_FACE_SEGS)
		return 0;
	const float ze = z[(size_t)end * st];
	if (!(z[(size_t)out * st] > ze))
		return 0;
	/* this end's straight broad face: its first segments before the first line across
	 * is tried, the rest once a bound is found */
#define PT(j) line_pos(g, (float)(end + dir * (j)), z[(size_t)(end + dir * (j)) * st])
	struct vec pe = { 0.0f, 0.0f, 0.0f }, d = pe, q = pe;
	int j = -1;
	const ptrdiff_t cs = g->du != 0.0f ? (ptrdiff_t)g->t->width : 1;
	/* (cross_z with the stride made once) */
#define CZ(k, c) z[(ptrdiff_t)(k) * (ptrdiff_t)st + (ptrdiff_t)(c) * cs]
	/* the lines beside (side -1, +1): in the image, and on this end's surface at the end
	 * (each side's first line, and the other side's corner test) */
	int in[2], on[2];
	for (int o = 0; o < 2; o++) {
		in[o] = cross_ok(g, 2 * o - 1);
		on[o] = in[o] && same_surface(ze, CZ(end, 2 * o - 1));
	}
	for (int side = -1; side <= 1; side += 2) {
		int k = end, turned = 0;
		float zk = ze;
		for (int i = 1; i <= DAO_BOUND_CARRY; i++) {
			const int c = side * i;
			if (i == 1 ? !on[side > 0] : !cross_ok(g, c))
				break;
			float zc = CZ(k, c);
			if (i > 1 && !same_surface(zk, zc))
				break;
			const int k_last = k;
			for (int w = 0; w < DAO_BOUND_CARRY_WALK; w++) {
				const int kn = k - dir;
				if (kn < 0 || kn >= n)
					break;
				const float zn = CZ(kn, c);
				if (!same_surface(zc, zn))
					break;
				k = kn;
				zc = zn;
			}
			zk = zc;
			/* the outline's step from the last line: along the lines (2 px or more),
			 * their ends are like this one; where it turns to cross them (a step
			 * under 2 px), that line and the next are tried, and no further */
			const int dki = k - k_last;
			const int across = dki < 2 && dki > -2;
			if (i == 1 && across) {
				/* the outline crosses the lines: theirs end as this one does, unless
				 * it runs along them on the other side (this end is a corner) */
				const int o = -side, k2 = end + dir;
				if (!in[o > 0] || on[o > 0] ||
				    (k2 >= 0 && k2 < n &&
				     same_surface(z[(size_t)k2 * st], CZ(k2, o))))
					break;
				turned = 1;
			} else if (turned)
				turned = 2;
			else if (across)
				turned = 1;
			if (!turned)
				continue;
			if (j < 0) {
				pe = PT(0);
				d = vsub(PT(DAO_BOUND_FACE_SEGS), pe);
				q = pe;
				const float dd = vdot(d, d);
				for (j = 0; j < DAO_BOUND_FACE_SEGS; j++) {
					const struct vec r = PT(j + 1);
					if (!cos_above_bb(vsub(r, q), d, dd, DAO_SLAB_STRAIGHT_COS))
						return 0;
					q = r;
				}
			}
			const struct line_geom gc = { g->t, z + (ptrdiff_t)c * cs, st,
						      g->u0 + (float)c * g->dv,
						      g->v0 + (float)c * g->du, g->du, g->dv, g->memo };
			/* line c from its end inwards, as far as face_bound looks */
			int m = 0;
			float zm = CZ(k, c);
			while (m < FB_LOOKED - 1) {
				const int k1 = k + dir * (m + 1);
				if (k1 < 0 || k1 >= n)
					break;
				const float z1 = CZ(k1, c);
				if (!same_surface(zm, z1))
					break;
				zm = z1;
				m++;
			}
			struct face_bound fb;
			const int ok = face_bound(&gc, n, dir < 0 ? k - m : k, dir < 0 ? k : k + m, dir,
						  &fb, 0);
			if (!ok) {
				if (turned == 2)
					break;
				continue;
			}
			const struct vec dp = vsub(pe, fb.at);
			const float off = vdot(dp, fb.normal);
			if (off * off > DAO_BOUND_CARRY_TOL * DAO_BOUND_CARRY_TOL * vdot(dp, dp))
				break; /* another face */
			j = straight_face_end(g, end, dir, len, j, q, d);
			const int kb = end + dir * j;
			*b = fb;
			b->k0 = end < kb ? end : kb;
			b->k1 = end < kb ? kb : end;
			return 1;
		}
	}
#undef CZ
#undef PT
	return 0;
}

/*
 * A bound lent by the lines beside (README.md, "Noisy input"): on noisy depth
 * the face bound of a board's end often fails on one line and holds on the
 * next (the broad face's normal, the outline's slope, the lines' ends and a
 * lip of one pixel at the silhouette all come from a few noisy pixels), so a
 * board's columns came out bimodal, a quarter to a third of the panels'
 * board pixels at the bound under structured light (clean: 0 - 8 %).  Where
 * this end (a step to farther or a hole with farther beyond it, as
 * face_bound's) has no bound of its own or carried, and its broad face goes
 * straight from one of its first DAO_BOUND_NEIGH_SKIP + 1 pixels, the lines
 * up to DAO_BOUND_NEIGH to each side whose runs end within
 * DAO_BOUND_NEIGH_SHIFT px of it are tried, nearest first: the nearest bound
 * on each side on the same broad face (as carried_bound's), the thinner of
 * the two, is lent to the straight broad face at this end.  Only on noisy
 * depth (noise_k > 0) whose dropouts are not filled (fill_px 0: structured
 * light, active stereo): on sharp depth the lines agree, and on Gaussian depth
 * it gained nothing and cost shelves-below.  Chosen on the tune set
 * (README.md: 3 and 8 lines, one side or both required, Gaussian too).
 */
#define DAO_BOUND_NEIGH 3
#define DAO_BOUND_NEIGH_SHIFT 2
#define DAO_BOUND_NEIGH_SKIP 2

__attribute__((noinline)) static int neighbour_bound(const struct line_geom *g, int n, int s,
						     int e, int dir, struct face_bound *b)
{
	/* (run_face_bounds: on noisy depth not filled, at an end that passed bound_end) */
	const int end = dir < 0 ? e : s;
	const int len = e - s + 1;
	const float *z = g->z;
	const size_t st = g->step;
	const float ze = z[(size_t)end * st];
	/* this end's straight broad face, from one of its first DAO_BOUND_NEIGH_SKIP + 1
	 * pixels (past a lip at the silhouette, which may be what failed its own bound) */
#define PT(j) line_pos(g, (float)(end + dir * (j)), z[(size_t)(end + dir * (j)) * st])
	struct vec pe = { 0.0f, 0.0f, 0.0f }, d = pe, q = pe;
	int j = 0;
	for (int f = 0; f <= DAO_BOUND_NEIGH_SKIP; f++) {
		if (f + DAO_BOUND_FACE_SEGS >= len)
			return 0;
		pe = PT(f);
		d = vsub(PT(f + DAO_BOUND_FACE_SEGS), pe);
		q = pe;
		const float dd = vdot(d, d);
		for (j = f; j < f + DAO_BOUND_FACE_SEGS; j++) {
			const struct vec r = PT(j + 1);
			if (!cos_above_bb(vsub(r, q), d, dd, DAO_SLAB_STRAIGHT_COS))
				break;
			q = r;
		}
		if (j == f + DAO_BOUND_FACE_SEGS)
			break;
		if (f == DAO_BOUND_NEIGH_SKIP)
			return 0;
	}
#undef PT
	const ptrdiff_t cs = g->du != 0.0f ? (ptrdiff_t)g->t->width : 1;
#define CZ(k, c) z[(ptrdiff_t)(k) * (ptrdiff_t)st + (ptrdiff_t)(c) * cs]
	/* the nearest bound on each side; of two, the thinner */
	struct face_bound got[2];
	int found = 0;
	for (int side = -1; side <= 1; side += 2) {
		for (int i = 1; i <= DAO_BOUND_NEIGH; i++) {
			const int c = side * i;
			if (!cross_ok(g, c))
				break;
			/* line c's run end beside this one: within DAO_BOUND_NEIGH_SHIFT px of
			 * this end, nearest first, on its surface, with none of it further out */
			int k = -1;
			for (int o = 0; o <= 2 * DAO_BOUND_NEIGH_SHIFT && k < 0; o++) {
				const int kk = end - dir * ((o + 1) / 2 * (o % 2 ? 1 : -1));
				const int ko = kk - dir;
				if (kk >= 0 && kk < n && same_surface(ze, CZ(kk, c)) &&
				    (ko < 0 || ko >= n || !same_surface(CZ(kk, c), CZ(ko, c))))
					k = kk;
			}
			if (k < 0)
				continue;
			const struct line_geom gc = { g->t, z + (ptrdiff_t)c * cs, st,
						      g->u0 + (float)c * g->dv,
						      g->v0 + (float)c * g->du, g->du, g->dv, g->memo };
			/* its face bound (face_bound's, for the run cut to what it looks at on
			 * noisy depth): line c's end first, then the memo's entry made from a
			 * whole run from k (its length is the run's: no need to walk it), else
			 * inwards as far as face_bound looks and through the memo */
			int h;
			if (!end_beyond(&gc, n, k, dir, &h))
				continue;
			struct face_bound fb;
			const struct fb_memo_entry *me =
				gc.memo ? fb_memo_slot(gc.memo, line_index(&gc), k, dir) : NULL;
			if (me && me->dir == dir && me->full && me->line == line_index(&gc) &&
			    me->k == k) {
				if (!me->ok)
					continue;
				fb = me->b;
			} else {
				int m = 0;
				float zm = CZ(k, c);
				while (m < FB_LOOKED_NOISY) {
					const int k1 = k + dir * (m + 1);
					if (k1 < 0 || k1 >= n || !same_surface(zm, CZ(k1, c)))
						break;
					zm = CZ(k1, c);
					m++;
				}
				if (m < DAO_BOUND_FACE_SEGS ||
				    !face_bound_memo_at(&gc, n, dir < 0 ? k - m : k,
							dir < 0 ? k : k + m, dir, h, 1, &fb))
					continue;
			}
			const struct vec dp = vsub(pe, fb.at);
			const float off = vdot(dp, fb.normal);
			if (off * off > DAO_BOUND_CARRY_TOL * DAO_BOUND_CARRY_TOL * vdot(dp, dp))
				continue; /* another face */
			got[found++] = fb;
			break;
		}
	}
	if (!found)
		return 0;
	if (found == 1)
		got[1] = got[0];
	j = straight_face_end(g, end, dir, len, j, q, d);
	const int kb = end + dir * j;
	*b = got[got[1].t < got[0].t];
	b->k0 = end < kb ? end : kb;
	b->k1 = end < kb ? kb : end;
#undef CZ
	return 1;
}

/* Both ends of the run s..e: *count bounds in b (own, carried or lent). */
static void run_face_bounds(const struct line_geom *g, int n, int s, int e, int *count,
			    struct face_bound b[2])
{
	/* (an end that fails bound_end has none of the three) */
	const int lend = noisy_unfilled(g->t);
	*count = 0;
	for (int dir = -1; dir <= 1; dir += 2) {
		int h;
		if (!bound_end(g, n, s, e, dir, &h))
			continue;
		struct face_bound *bb = &b[*count];
		if (face_bound_memo_at(g, n, s, e, dir, h, 1, bb))
			face_bound_pixels(g, s, e, dir, bb);
		else if (!carried_bound(g, n, s, e, dir, bb) &&
			 !(lend && neighbour_bound(g, n, s, e, dir, bb)))
			continue;
		(*count)++;
	}
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
__attribute__((noinline)) static float face_bound_value(const struct line_geom *g, int count,
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

/*
 * The run of pixels s..e (all with data, neighbours on the same surface) of a
 * line of n pixels, the k-th at z[k * step] and at pixel coordinates
 * (u0 + k du, v0 + k dv).  Its chord spans from the outer edge of its first
 * pixel to the outer edge of its last (a run of one pixel is a pixel wide),
 * each end at its own depth.  Where an end of the run is a slab's edge face
 * (slab_edge) or the run is the edge face of a slab receding beyond an end
 * (receding_face), each pixel's ray crosses the slab, of thickness t along
 * the face direction f, over t / sin(ray, f).
 */
struct run_est {
	float value; /* every pixel's, without slabs */
	int slabs;   /* slab edges found (0 - 2) */
	struct vec face[2];
	float slab_t[2];
	int bounds; /* ends without a visible edge face (0 - 2, face_bound) */
	struct face_bound bound[2];
};

/*
 * A board seen almost along its plane (README.md, "Thickness from the
 * image"): beyond the end of a run in front (dir = -1 before its first pixel,
 * +1 after its last) its broad face recedes at a grazing angle, each pixel a
 * step farther than the last, so the run is only the board's edge face and
 * the face's pixels are runs of their own.  On a plane 1/z is linear along
 * the line: the two pixels out, j1 and j2, must recede (1/z falling by sg a
 * pixel) faster than the run's face does by more than half of that (a
 * crease), the two lines must meet within 1.25 px of the end pixel, and a
 * third point must not put j1 and j2 on a background: the end pixel lies on
 * their line (within 5 % of sg), or the pixel after j2 is at least a step sg
 * farther (the face going on, or the background behind it; where it is
 * nearer or level, j2 was the background).  On success, as slab_edge: the
 * face's direction and the run's extent across it, t.
 */
#define DAO_RECEDE_CREASE 0.5f
#define DAO_RECEDE_MEET 1.25f
#define DAO_RECEDE_TOL 0.05f

static int receding_face(const struct line_geom *g, int n, int s, int e, int dir,
			 struct vec *face, float *t)
{
	const int end = dir < 0 ? s : e, j1 = end + dir, j2 = end + 2 * dir, j3 = end + 3 * dir;
	if (e - s < 2 || j2 < 0 || j2 >= n)
		return 0;
	const float *z = g->z;
	const size_t st = g->step;
	const float z1 = z[(size_t)j1 * st], z2 = z[(size_t)j2 * st];
	if (!(z1 > 0.0f) || !(z2 > z1))
		return 0;
	const float wi1 = 1.0f / z[(size_t)(end - dir) * st];
	const float wi2 = 1.0f / z[(size_t)(end - 2 * dir) * st];
	const float wj1 = 1.0f / z1, wj2 = 1.0f / z2;
	const float sr = wi1 - wi2, sg = wj2 - wj1, den = sr - sg;
	if (!(den > DAO_RECEDE_CREASE * -sg))
		return 0;
	/* the lines meet m = num / den pixels out from the end */
	const float num = wj1 - wi1 - sg - sr;
	if (num < -DAO_RECEDE_MEET * den || num > DAO_RECEDE_MEET * den)
		return 0;
	const float tol = DAO_RECEDE_TOL * -sg;
	int third = fabsf(wj1 - 1.0f / z[(size_t)end * st] - sg) <= tol;
	if (!third && j3 >= 0 && j3 < n && z[(size_t)j3 * st] > 0.0f)
		third = 1.0f / z[(size_t)j3 * st] - wj2 <= sg + tol;
	if (!third)
		return 0;
	const int far = dir < 0 ? e : s;
	const struct vec p1 = line_pos(g, (float)j1, z1), p2 = line_pos(g, (float)j2, z2);
	const struct vec pout = line_pos(g, (float)far - 0.5f * (float)dir, z[(size_t)far * st]);
	*face = vunit(vsub(p2, p1));
	*t = vcross_len(vsub(pout, p1), *face);
	return 1;
}

/*
 * Whether the surface beyond an end of the run s..e (the pixels next to it, in
 * 0..n-1, farther: the run ends on its outline) lies within `gap` behind that
 * end (thickness.h, DAO_CHORD_GAP); a hole beside an end says nothing.
 */
static inline int near_behind(const float *z, size_t step, int s, int e, float gap)
{
	const float b0 = z[(size_t)(s - 1) * step], b1 = z[(size_t)(e + 1) * step];
	return (b0 > 0.0f && b0 - z[(size_t)s * step] <= gap) ||
	       (b1 > 0.0f && b1 - z[(size_t)e * step] <= gap);
}

/*
 * A face hidden in a hole across the baseline (README.md, "Noisy input"): on
 * noisy depth whose dropouts are not filled (structured light, active
 * stereo), a board seen edge-on shows as a short run, its edge face, and its
 * broad face, receding at a grazing angle beyond one end, falls where the
 * block matching finds no depth: a hole with the background beyond it.  Along
 * the rows, the baseline, such holes lie beside every object (the projector's
 * shadow, the second camera's occlusion; a pole's as a board's); along the
 * columns there is no shadow.  So in the column pass a run of at least
 * DAO_HIDDEN_RUN_PX pixels whose chord is under DAO_HIDDEN_CHORD spacings,
 * with a hole of DAO_HIDDEN_HOLE_PX or more beside an end, gets the bound
 * instead of its chord: its extent is unknown.  Chosen on the tune set
 * (README.md: holes of 2 - 5 px, rows too, the chord lifted by 3 or 8 cm).
 */
#define DAO_HIDDEN_HOLE_PX 2
#define DAO_HIDDEN_RUN_PX 5
#define DAO_HIDDEN_CHORD 0.5f

static inline int hidden_face(const float *z, size_t step, int n, int s, int e)
{
	int h0 = 0, h1 = 0;
	for (int j = 1; j <= DAO_HIDDEN_HOLE_PX; j++) {
		h0 += s - j >= 0 && !(z[(size_t)(s - j) * step] > 0.0f);
		h1 += e + j < n && !(z[(size_t)(e + j) * step] > 0.0f);
	}
	return h0 == DAO_HIDDEN_HOLE_PX || h1 == DAO_HIDDEN_HOLE_PX;
}

/* (noinline: one build of the arithmetic, whichever clone of a sweep calls it) */
__attribute__((noinline)) static void run_estimate(const struct line_geom *lg, int n, int s,
						   int e, struct run_est *r)
{
	const struct dao_thickness_setup *t = lg->t;
	const struct line_geom g = *lg;
	const float *z = g.z;
	const size_t step = g.step;
	const float u0 = g.u0, v0 = g.v0, du = g.du, dv = g.dv;
	const float zs = z[(size_t)s * step];
	const float ze = z[(size_t)e * step];
	r->value = t->max;
	r->slabs = 0;
	if (s > 0 && e + 1 < n && outline(z, step, n, s, -1) && outline(z, step, n, e, 1)) {
		const float us = u0 + ((float)s - 0.5f) * du, vs = v0 + ((float)s - 0.5f) * dv;
		const float ue = u0 + ((float)e + 0.5f) * du, ve = v0 + ((float)e + 0.5f) * dv;
		const float dx = (ue * t->ax + t->bx) * ze - (us * t->ax + t->bx) * zs;
		const float dy = (ve * t->ay + t->by) * ze - (vs * t->ay + t->by) * zs;
		const float dz = ze - zs;
		float chord = sqrtf(dx * dx + dy * dy + dz * dz);
		/* a pole before a wall: its chord plus half a spacing, on sharp depth or
		 * with the dropouts filled (thickness.h) */
		if ((t->noise_k == 0.0f || t->fill_px > 0) && chord < t->spacing &&
		    near_behind(z, step, s, e, DAO_CHORD_GAP * t->spacing)) {
			const float raised = chord + DAO_CHORD_EXTRA * t->spacing;
			chord = raised < t->spacing ? raised : t->spacing;
		}
		/* a face hidden in a hole across the baseline, on noisy depth not filled */
		if (noisy_unfilled(t) && du == 0.0f &&
		    e - s + 1 >= DAO_HIDDEN_RUN_PX && chord < DAO_HIDDEN_CHORD * t->spacing &&
		    hidden_face(z, step, n, s, e))
			chord = t->max;
		if (chord < r->value)
			r->value = chord;
		if (e - s >= 4) {
			r->slabs += slab_edge(&g, s, e, -1, &r->face[r->slabs], &r->slab_t[r->slabs]);
			r->slabs += slab_edge(&g, s, e, 1, &r->face[r->slabs], &r->slab_t[r->slabs]);
		}
		for (int dir = -1; dir <= 1 && r->slabs < 2; dir += 2)
			r->slabs += receding_face(&g, n, s, e, dir, &r->face[r->slabs],
						  &r->slab_t[r->slabs]);
	}
	run_face_bounds(&g, n, s, e, &r->bounds, r->bound);
}

/* Pixel k's value in a run with slabs (r->slabs > 0). */
__attribute__((noinline)) static float run_slab_value(const struct line_geom *g,
						      const struct run_est *r, int k)
{
	const struct vec p = line_pos(g, (float)k, g->z[(size_t)k * g->step]);
	const float lp = sqrtf(vdot(p, p));
	float vk = r->value, sns[2];
	/* the chord caps no slab the ray meets at a grazing angle (thickness.h) */
	for (int q = 0; q < r->slabs; q++) {
		sns[q] = vcross_len(p, r->face[q]);
		if (sns[q] < DAO_SLAB_GRAZING_SIN * lp)
			vk = g->t->max;
	}
	for (int q = 0; q < r->slabs; q++)
		/* the ray crosses the slab over t / sin(ray, face) = t |p| / |p x f| */
		vk = slab_cap(vk, r->slab_t[q], lp, sns[q], g->t->spacing);
	return vk;
}

/* The run's pixels get its values (take_min: where smaller than what they hold). */
static void run(const struct line_geom *g, float *thick, int n, int s, int e, int take_min)
{
	struct run_est r;
	run_estimate(g, n, s, e, &r);
	const size_t step = g->step;
	if (r.slabs || r.bounds) {
		for (int k = s; k <= e; k++) {
			const float vk = face_bound_value(g, r.bounds, r.bound, k,
							  r.slabs ? run_slab_value(g, &r, k) : r.value);
			float *o = &thick[(size_t)k * step];
			if (!take_min || vk < *o)
				*o = vk;
		}
	} else if (take_min) {
		for (int k = s; k <= e; k++) {
			float *o = &thick[(size_t)k * step];
			if (r.value < *o)
				*o = r.value;
		}
	} else {
		for (int k = s; k <= e; k++)
			thick[(size_t)k * step] = r.value;
	}
}

/* One line of n pixels (run), holes: the bound (take_min: left alone). */
static void line(const struct dao_thickness_setup *t, const float *z, float *thick, int n,
		 size_t step, float u0, float v0, float du, float dv, int take_min,
		 struct fb_memo *memo)
{
	const struct line_geom g = { t, z, step, u0, v0, du, dv, memo };
	int i = 0;
	while (i < n) {
		const float zs = z[(size_t)i * step];
		if (!(zs > 0.0f)) {
			if (!take_min)
				thick[(size_t)i * step] = t->max;
			i++;
			continue;
		}
		const int s = i;
		while (i + 1 < n && same_surface(z[(size_t)i * step], z[(size_t)(i + 1) * step]))
			i++;
		run(&g, thick, n, s, i, take_min);
		i++;
	}
}

/*
 * The same-surface test between a[c] and b[c] for n <= 64 pixels side by side:
 * bit c of the result.  With SSE2 four at a time (the same comparisons and
 * the one product: min(a, b) as a < b ? a : b, the same bits).
 */
static inline uint64_t same_mask(const float *a, const float *b, int n)
{
	uint64_t m = 0;
	int c = 0;
#ifdef __SSE2__
	const __m128 zero = _mm_setzero_ps(), jump = _mm_set1_ps(DAO_THICKNESS_JUMP);
	const __m128 sign = _mm_set1_ps(-0.0f);
	for (; c + 4 <= n; c += 4) {
		const __m128 va = _mm_loadu_ps(a + c), vb = _mm_loadu_ps(b + c);
		const __m128 d = _mm_andnot_ps(sign, _mm_sub_ps(va, vb));
		const __m128 ok = _mm_and_ps(_mm_and_ps(_mm_cmpgt_ps(va, zero), _mm_cmpgt_ps(vb, zero)),
					     _mm_cmple_ps(d, _mm_mul_ps(jump, _mm_min_ps(va, vb))));
		m |= (uint64_t)_mm_movemask_ps(ok) << c;
	}
#endif
	for (; c < n; c++)
		m |= (uint64_t)same_surface(a[c], b[c]) << c;
	return m;
}

/* the bits below n (1 <= n <= 64) */
static inline uint64_t low_bits(int n)
{
	return n >= 64 ? ~(uint64_t)0 : ((uint64_t)1 << n) - 1;
}

/* line() for rows, its runs' ends found a chunk of pixels at a time (same_mask). */
void dao_thickness_rows(const struct dao_thickness_setup *t, const float *z, float *thick,
			int y0, int y1)
{
	const int w = t->width;
	struct fb_memo memo;
	fb_memo_clear(&memo);
	for (int y = y0; y < y1; y++) {
		const size_t o = (size_t)y * w;
		const struct line_geom g = { t, z + o, 1, 0.0f, (float)y, 1.0f, 0.0f, &memo };
		int start = 0;
		for (int xc = 0; xc < w; xc += 64) {
			const int n = w - xc < 64 ? w - xc : 64;
			/* (the row's last pixel has no next: it ends its run) */
			const int last = xc + n == w;
			const float *zc = z + o + xc;
			uint64_t ends = ~same_mask(zc, zc + 1, last ? n - 1 : n) & low_bits(n);
			while (ends) {
				const int x = xc + __builtin_ctzll(ends);
				ends &= ends - 1;
				if (z[o + x] > 0.0f)
					run(&g, thick + o, w, start, x, 0);
				else
					thick[o + x] = t->max;
				start = x + 1;
			}
		}
	}
}

void dao_thickness_rows_ref(const struct dao_thickness_setup *t, const float *z, float *thick,
			    int y0, int y1)
{
	/* (no memo: each face bound made from the pixels) */
	for (int y = y0; y < y1; y++) {
		const size_t o = (size_t)y * t->width;
		line(t, z + o, thick + o, t->width, 1, 0.0f, (float)y, 1.0f, 0.0f, 0, NULL);
	}
}

void dao_thickness_cols_ref(const struct dao_thickness_setup *t, const float *z, float *thick,
			    int x0, int x1)
{
	for (int x = x0; x < x1; x++)
		line(t, z + x, thick + x, t->height, (size_t)t->width, (float)x, 0.0f, 0.0f, 1.0f, 1,
		     NULL);
}

/*
 * The column pass over a block of columns side by side, in two sweeps that
 * read and write whole rows of the block (a column walk, a row stride per
 * pixel, missed the cache at nearly every pixel of the plane).  Down the
 * rows, the same-surface test between two rows is made for the block's
 * columns at once, and where a column's run ends its value is made
 * (run_estimate) and left in the scratch at the run's last row: the other
 * rows of the run hold RUN_INSIDE, a hole +inf (it leaves the pixel alone);
 * a run with slabs leaves each of its pixels' own values.  Up the rows, each
 * column carries the value of the run it is in (a run's last row is met
 * first), and the plane takes the smaller one.  The same runs and arithmetic
 * as line(): the result is dao_thickness_cols_ref's.
 */
#define RUN_INSIDE (-1.0f)

_Static_assert(DAO_THICKNESS_COL_BLOCK <= 64, "a block's ends are the bits of a uint64_t");

/* The row's columns c < n: v[c] = the run's value from sc[c] unless RUN_INSIDE,
 * thick[c] = the smaller of it and v[c] */
DAO_MULTIVERSION
static void cols_put(const float *restrict sc, float *restrict thick, float *restrict v, int n)
{
	for (int c = 0; c < n; c++) {
		const float r = sc[c];
		const float vc = r == RUN_INSIDE ? v[c] : r;
		const float o = thick[c];
		v[c] = vc;
		thick[c] = vc < o ? vc : o;
	}
}

/* cols_put for n = 4 m columns from a multiple of 4 on, each also to its entry
 * of its phase's row of the thickness plane, as a half: column 4 j + q to o[q][j]
 * (with SSE2 16 columns at a time, a 4 x 4 transpose: the same selections and
 * minima, the same halves; HALF4: 4 floats to 4 halves in the low 64 bits) */
#define COLS_PUT_SPLIT_SSE2(HALF4)                                                          \
	const __m128 inside = _mm_set1_ps(RUN_INSIDE);                                     \
	for (; j + 4 <= m; j += 4) {                                                       \
		__m128 r[4];                                                               \
		for (int i = 0; i < 4; i++) {                                              \
			const int c = 4 * (j + i);                                         \
			const __m128 sv = _mm_loadu_ps(sc + c);                            \
			const __m128 in = _mm_cmpeq_ps(sv, inside);                        \
			const __m128 vc = _mm_or_ps(_mm_and_ps(in, _mm_loadu_ps(v + c)),    \
						    _mm_andnot_ps(in, sv));                \
			_mm_storeu_ps(v + c, vc);                                          \
			r[i] = _mm_min_ps(vc, _mm_loadu_ps(thick + c)); /* vc < o ? vc : o */ \
			_mm_storeu_ps(thick + c, r[i]);                                    \
		}                                                                          \
		_MM_TRANSPOSE4_PS(r[0], r[1], r[2], r[3]);                                 \
		_mm_storel_epi64((__m128i *)(o0 + j), HALF4(r[0]));                       \
		_mm_storel_epi64((__m128i *)(o1 + j), HALF4(r[1]));                       \
		_mm_storel_epi64((__m128i *)(o2 + j), HALF4(r[2]));                       \
		_mm_storel_epi64((__m128i *)(o3 + j), HALF4(r[3]));                       \
	}

static inline void cols_put_split_tail(const float *restrict sc, float *restrict thick,
				       float *restrict v, uint16_t *restrict o0,
				       uint16_t *restrict o1, uint16_t *restrict o2,
				       uint16_t *restrict o3, int j, int m)
{
	for (; j < m; j++) {
		float r[4];
		for (int q = 0; q < 4; q++) {
			const int c = 4 * j + q;
			const float vc = sc[c] == RUN_INSIDE ? v[c] : sc[c];
			const float o = thick[c];
			v[c] = vc;
			r[q] = vc < o ? vc : o;
			thick[c] = r[q];
		}
		o0[j] = dao_half_from_float(r[0]);
		o1[j] = dao_half_from_float(r[1]);
		o2[j] = dao_half_from_float(r[2]);
		o3[j] = dao_half_from_float(r[3]);
	}
}

DAO_MULTIVERSION
static void cols_put_split(const float *restrict sc, float *restrict thick, float *restrict v,
			   uint16_t *restrict o0, uint16_t *restrict o1, uint16_t *restrict o2,
			   uint16_t *restrict o3, int m)
{
	int j = 0;
#ifdef __SSE2__
	COLS_PUT_SPLIT_SSE2(dao_half_from_ps_sse2)
#endif
	cols_put_split_tail(sc, thick, v, o0, o1, o2, o3, j, m);
}

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define HAVE_SPLIT_F16C 1
/* the same with the conversion of F16C (which rounds the same), for CPUs that
 * have it (__builtin_cpu_supports) */
__attribute__((target("f16c"))) static inline __m128i half4_f16c(__m128 r)
{
	return _mm_cvtps_ph(r, 0); /* to nearest even */
}

__attribute__((target("f16c"))) static void
cols_put_split_f16c(const float *restrict sc, float *restrict thick, float *restrict v,
		    uint16_t *restrict o0, uint16_t *restrict o1, uint16_t *restrict o2,
		    uint16_t *restrict o3, int m)
{
	int j = 0;
	COLS_PUT_SPLIT_SSE2(half4_f16c)
	cols_put_split_tail(sc, thick, v, o0, o1, o2, o3, j, m);
}
#else
#define HAVE_SPLIT_F16C 0
#endif

void dao_thickness_cols(const struct dao_thickness_setup *t, const float *z, float *thick,
			float *scratch, struct dao_gtao_planes *pl, int x0, int x1)
{
	const size_t w = (size_t)t->width;
	const int h = t->height;
	const size_t bs = DAO_THICKNESS_COL_BLOCK;
#if HAVE_SPLIT_F16C
	const int f16c = __builtin_cpu_supports("f16c");
#endif
	struct fb_memo memo;
	fb_memo_clear(&memo);
	for (int xb = x0; xb < x1; xb += DAO_THICKNESS_COL_BLOCK) {
		const int nb = x1 - xb < DAO_THICKNESS_COL_BLOCK ? x1 - xb : DAO_THICKNESS_COL_BLOCK;
		int start[DAO_THICKNESS_COL_BLOCK];
		for (int c = 0; c < nb; c++)
			start[c] = 0;
		for (int y = 0; y < h; y++) {
			const float *za = z + (size_t)y * w + xb;
			float *sr = scratch + (size_t)y * bs;
			uint64_t ends = low_bits(nb);
			if (y + 1 < h)
				ends &= ~same_mask(za, za + w, nb);
			for (int c = 0; c < nb; c++)
				sr[c] = RUN_INSIDE;
			/* the rows the way up writes: asked for now, while this sweep reads the
			 * depth (the row pass left them in the other threads' caches) */
			for (int c = 0; c < nb; c += 16)
				__builtin_prefetch(thick + (size_t)y * w + xb + c, 1, 3);
			if (pl)
				for (int q = 0; q < 4; q++)
					__builtin_prefetch(dao_gtao_thick_row(pl, y, q) + xb / 4, 1, 3);
			while (ends) {
				const int c = __builtin_ctzll(ends);
				ends &= ends - 1;
				/* the run start[c] .. y of column xb + c ends here */
				if (za[c] > 0.0f) {
					const struct line_geom g = { t, z + xb + c, w, (float)(xb + c), 0.0f,
								     0.0f, 1.0f, &memo };
					struct run_est r;
					run_estimate(&g, h, start[c], y, &r);
					if (r.slabs || r.bounds) {
						for (int k = start[c]; k <= y; k++)
							scratch[(size_t)k * bs + c] = face_bound_value(
								&g, r.bounds, r.bound, k,
								r.slabs ? run_slab_value(&g, &r, k) : r.value);
					} else {
						sr[c] = r.value;
					}
				} else {
					sr[c] = INFINITY;
				}
				start[c] = y + 1;
			}
		}
		float v[DAO_THICKNESS_COL_BLOCK];
		for (int c = 0; c < nb; c++)
			v[c] = INFINITY;
		const int split = pl && !(xb & 3) && !(nb & 3);
		for (int y = h - 1; y >= 0; y--) {
			const float *sr = scratch + (size_t)y * bs;
			float *tr = thick + (size_t)y * w + xb;
			if (split) {
				uint16_t *o[4];
				for (int q = 0; q < 4; q++)
					o[q] = (uint16_t *)dao_gtao_thick_row(pl, y, q) + xb / 4;
#if HAVE_SPLIT_F16C
				if (f16c)
					cols_put_split_f16c(sr, tr, v, o[0], o[1], o[2], o[3],
							    nb / 4);
				else
#endif
					cols_put_split(sr, tr, v, o[0], o[1], o[2], o[3], nb / 4);
			} else {
				cols_put(sr, tr, v, nb);
				if (pl)
					dao_gtao_planes_fill_thickness_cols(pl, thick, y, y + 1, xb,
									    xb + nb);
			}
		}
	}
}
