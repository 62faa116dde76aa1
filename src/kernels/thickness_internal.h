/* SPDX-License-Identifier: MIT */
/*
 * What the parts of the thickness estimate share (kernels/thickness.h is its
 * interface; docs/design/thickness.md lists the rules and the file of each):
 * 3-vectors, the same-surface test, a line's geometry, the face bound's
 * constants and result, a run's estimate, and the functions one file calls in
 * another.  Internal: the library's hidden symbols, no dao_ prefix.
 */
#ifndef DAO_KERNELS_THICKNESS_INTERNAL_H
#define DAO_KERNELS_THICKNESS_INTERNAL_H

#include "kernels/thickness.h"

#include <math.h>
#include <stddef.h>

/* (comparisons, not fminf: libm's is a call per pixel, a sixth of the time) */
static inline int same_surface(float a, float b)
{
	return a > 0.0f && b > 0.0f && fabsf(a - b) <= DAO_THICKNESS_JUMP * (a < b ? a : b);
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

/* Straight: segments that turn by less than this from each other (slab_edge, the face
 * bound's broad faces; thickness_slab.c, thickness_bound.c) */
#define DAO_SLAB_STRAIGHT_COS 0.94f /* 20 degrees */

/* The face bound's (thickness_bound.c, "No visible edge face"; carried and lent in
 * thickness_bound_across.c) */
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

/* The line c across from this one (rows: a row, columns: a column) is in the image. */
static inline int cross_ok(const struct line_geom *g, int c)
{
	const int li = g->du != 0.0f ? (int)g->v0 : (int)g->u0;
	const int nl = g->du != 0.0f ? g->t->height : g->t->width;
	return li + c >= 0 && li + c < nl;
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
struct run_est {
	float value; /* every pixel's, without slabs */
	int slabs;   /* slab edges found (0 - 2) */
	struct vec face[2];
	float slab_t[2];
	int bounds; /* ends without a visible edge face (0 - 2, face_bound) */
	struct face_bound bound[2];
};

/* thickness_run.c: a run's estimate (its chord, slabs and bounds) */
__attribute__((noinline)) void run_estimate(const struct line_geom *lg, int n, int s, int e,
					    struct run_est *r);

/* thickness_slab.c: a slab's edge face and the values of a slab's pixels */
int slab_edge(const struct line_geom *g, int s, int e, int dir, struct vec *face, float *t);
__attribute__((noinline)) float run_slab_value(const struct line_geom *g, const struct run_est *r,
					       int k);
__attribute__((noinline)) float face_bound_value(const struct line_geom *g, int count,
						 const struct face_bound *b, int k, float vk);

/* thickness_bound.c: the face bound at a run's end */
int straight_face_end(const struct line_geom *g, int end, int dir, int len, int j, struct vec q,
		      struct vec d);
int face_bound_at(const struct line_geom *g, int n, int s, int e, int dir, int f, int h,
		  struct vec p0, struct vec pf, struct vec pm, struct face_bound *b);
void face_bound_pixels(const struct line_geom *g, int s, int e, int dir, struct face_bound *b);

/* thickness_bound_across.c: a bound from the lines across, carried along the outline */
__attribute__((noinline)) int carried_bound(const struct line_geom *g, int n, int s, int e,
					    int dir, struct face_bound *b);

#endif
