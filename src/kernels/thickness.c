/* SPDX-License-Identifier: MIT */
/*
 * Thickness from the image: the extent of each surface's run along rows and
 * columns (thickness.h).  Two passes, O(1) per pixel, no allocation.
 */
#include "kernels/thickness.h"

#include "core/math_util.h"

#include <math.h>
#include <stddef.h>

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
}

void dao_thickness_setup_rounding(struct dao_thickness_setup *t, float scale)
{
	float a = (scale - DAO_SLAB_ROUND_FROM) / (DAO_SLAB_ROUND_TO - DAO_SLAB_ROUND_FROM);
	a = a > 0.0f ? (a < 1.0f ? a : 1.0f) : 0.0f;
	const float deg = DAO_SLAB_CREASE_DEG + a * (DAO_SLAB_CREASE_ROUNDED_DEG - DAO_SLAB_CREASE_DEG);
	t->crease_cos = cosf(deg * (DAO_PI_F / 180.0f));
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

/* cos(a, b) >= c (c > 0), without roots or divisions */
static inline int cos_above(struct vec a, struct vec b, float c)
{
	const float d = vdot(a, b);
	return d > 0.0f && d * d >= c * c * vdot(a, a) * vdot(b, b);
}

/* |cos(a, b)| <= c */
static inline int abs_cos_below(struct vec a, struct vec b, float c)
{
	const float d = vdot(a, b);
	return d * d <= c * c * vdot(a, a) * vdot(b, b);
}

/* One line: its pixels' depths z[k * step] at (u0 + k du, v0 + k dv). */
struct line_geom {
	const struct dao_thickness_setup *t;
	const float *z;
	size_t step;
	float u0, v0, du, dv;
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
	int m = 1;
	struct vec d = e0;
	while (m < DAO_SLAB_EDGE_MAX && m + 3 < len) {
		const struct vec q = PT(m + 1);
		d = vsub(q, p);
		if (!cos_above(d, e0, DAO_SLAB_STRAIGHT_COS))
			break;
		p = q;
		m++;
	}
#undef PT
	if (m < 2 || m + 3 >= len || cos_above(d, e0, DAO_SLAB_STRAIGHT_COS))
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
 * The run of pixels s..e (all with data, neighbours on the same surface) of a
 * line of n pixels, the k-th at z[k * step] and at pixel coordinates
 * (u0 + k du, v0 + k dv).  Its chord spans from the outer edge of its first
 * pixel to the outer edge of its last (a run of one pixel is a pixel wide),
 * each end at its own depth.  Where an end of the run is a slab's edge face
 * (slab_edge), each pixel's ray crosses the slab, of thickness t along the
 * face direction f, over t / sin(ray, f).
 */
static void run(const struct line_geom *lg, float *thick, int n, int s, int e, int take_min)
{
	const struct dao_thickness_setup *t = lg->t;
	const struct line_geom g = *lg;
	const float *z = g.z;
	const size_t step = g.step;
	const float u0 = g.u0, v0 = g.v0, du = g.du, dv = g.dv;
	const float zs = z[(size_t)s * step];
	const float ze = z[(size_t)e * step];
	float value = t->max;
	int slabs = 0;
	struct vec face[2];
	float slab_t[2];
	if (s > 0 && e + 1 < n && outline(z, step, n, s, -1) && outline(z, step, n, e, 1)) {
		const float us = u0 + ((float)s - 0.5f) * du, vs = v0 + ((float)s - 0.5f) * dv;
		const float ue = u0 + ((float)e + 0.5f) * du, ve = v0 + ((float)e + 0.5f) * dv;
		const float dx = (ue * t->ax + t->bx) * ze - (us * t->ax + t->bx) * zs;
		const float dy = (ve * t->ay + t->by) * ze - (vs * t->ay + t->by) * zs;
		const float dz = ze - zs;
		const float chord = sqrtf(dx * dx + dy * dy + dz * dz);
		if (chord < value)
			value = chord;
		if (e - s >= 4) {
			slabs += slab_edge(&g, s, e, -1, &face[slabs], &slab_t[slabs]);
			slabs += slab_edge(&g, s, e, 1, &face[slabs], &slab_t[slabs]);
		}
	}
	if (slabs) {
		for (int k = s; k <= e; k++) {
			const struct vec p = line_pos(&g, (float)k, z[(size_t)k * step]);
			const float lp = sqrtf(vdot(p, p));
			float vk = value;
			for (int q = 0; q < slabs; q++) {
				/* scale t / sin(ray, face) = scale t |p| / |p x f|, and at least
				 * t / sin + spacing (thickness.h), no division by 0 */
				const float sn = vcross_len(p, face[q]);
				float across = DAO_THICKNESS_SLAB_SCALE * slab_t[q] * lp;
				const float spaced = slab_t[q] * lp + t->spacing * sn;
				if (spaced > across)
					across = spaced;
				if (across < vk * sn)
					vk = across / sn;
			}
			float *o = &thick[(size_t)k * step];
			if (!take_min || vk < *o)
				*o = vk;
		}
	} else if (take_min) {
		for (int k = s; k <= e; k++) {
			float *o = &thick[(size_t)k * step];
			if (value < *o)
				*o = value;
		}
	} else {
		for (int k = s; k <= e; k++)
			thick[(size_t)k * step] = value;
	}
}

/* One line of n pixels (run), holes: the bound (take_min: left alone). */
static void line(const struct dao_thickness_setup *t, const float *z, float *thick, int n,
		 size_t step, float u0, float v0, float du, float dv, int take_min)
{
	const struct line_geom g = { t, z, step, u0, v0, du, dv };
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
 * The same-surface test between each pixel and the next, for n pixels of a
 * row side by side (vectorised by the compiler): same[c] for z[c], z[c + 1].
 */
static void same_next(const float *z, unsigned char *same, int n)
{
	for (int c = 0; c < n; c++) {
		const float a = z[c], b = z[c + 1];
		const float m = a < b ? a : b;
		same[c] = (a > 0.0f) & (b > 0.0f) & (fabsf(a - b) <= DAO_THICKNESS_JUMP * m);
	}
}

/* line() for rows, its runs found a chunk of pixels at a time (same_next). */
void dao_thickness_rows(const struct dao_thickness_setup *t, const float *z, float *thick,
			int y0, int y1)
{
	const int w = t->width;
	unsigned char same[DAO_THICKNESS_COL_BLOCK];
	for (int y = y0; y < y1; y++) {
		const size_t o = (size_t)y * w;
		const struct line_geom g = { t, z + o, 1, 0.0f, (float)y, 1.0f, 0.0f };
		int start = 0;
		for (int xc = 0; xc < w; xc += DAO_THICKNESS_COL_BLOCK) {
			const int last = w - xc <= DAO_THICKNESS_COL_BLOCK;
			const int n = last ? w - xc : DAO_THICKNESS_COL_BLOCK;
			/* (the row's last pixel has no next: its test reads one float less) */
			same_next(z + o + xc, same, last ? n - 1 : n);
			if (last)
				same[n - 1] = 0;
			for (int c = 0; c < n; c++) {
				if (same[c])
					continue;
				const int x = xc + c;
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
	for (int y = y0; y < y1; y++) {
		const size_t o = (size_t)y * t->width;
		line(t, z + o, thick + o, t->width, 1, 0.0f, (float)y, 1.0f, 0.0f, 0);
	}
}

void dao_thickness_cols_ref(const struct dao_thickness_setup *t, const float *z, float *thick,
			    int x0, int x1)
{
	for (int x = x0; x < x1; x++)
		line(t, z + x, thick + x, t->height, (size_t)t->width, (float)x, 0.0f, 0.0f, 1.0f, 1);
}

/*
 * The column pass swept down the rows over a block of columns at once: the
 * same-surface test between two rows is made for the block's columns side by
 * side (contiguous, so the compiler vectorises it), and each column's run is
 * handed to run() when it ends.  The same runs as line() with the same
 * arithmetic: the result is dao_thickness_cols_ref's.
 */
void dao_thickness_cols(const struct dao_thickness_setup *t, const float *z, float *thick,
			int x0, int x1)
{
	const size_t w = (size_t)t->width;
	const int h = t->height;
	for (int xb = x0; xb < x1; xb += DAO_THICKNESS_COL_BLOCK) {
		const int nb = x1 - xb < DAO_THICKNESS_COL_BLOCK ? x1 - xb : DAO_THICKNESS_COL_BLOCK;
		int start[DAO_THICKNESS_COL_BLOCK];
		unsigned char same[DAO_THICKNESS_COL_BLOCK];
		for (int c = 0; c < nb; c++)
			start[c] = 0;
		for (int y = 0; y < h; y++) {
			const float *za = z + (size_t)y * w + xb;
			if (y + 1 < h) {
				const float *zb = za + w;
				for (int c = 0; c < nb; c++) {
					const float a = za[c], b = zb[c];
					const float m = a < b ? a : b;
					same[c] = (a > 0.0f) & (b > 0.0f) &
						  (fabsf(a - b) <= DAO_THICKNESS_JUMP * m);
				}
			} else {
				for (int c = 0; c < nb; c++)
					same[c] = 0;
			}
			for (int c = 0; c < nb; c++) {
				if (same[c])
					continue;
				/* the run start[c] .. y of column xb + c ends here */
				if (za[c] > 0.0f) {
					const struct line_geom g = { t, z + xb + c, w, (float)(xb + c), 0.0f,
								     0.0f, 1.0f };
					run(&g, thick + xb + c, h, start[c], y, 1);
				}
				start[c] = y + 1;
			}
		}
	}
}
