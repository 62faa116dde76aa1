/* SPDX-License-Identifier: MIT */
/*
 * The face bounds a pass has made (the memo) and the lookups through it,
 * always inlined where a run's bounds are made (thickness_run.c) and where
 * they are carried or lent across (thickness_bound_across.c); the passes
 * (thickness_passes.c) keep one memo each.
 */
#ifndef DAO_KERNELS_THICKNESS_MEMO_H
#define DAO_KERNELS_THICKNESS_MEMO_H

#include "kernels/thickness_internal.h"

#include <stdint.h>

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
	int ok;
	struct face_bound b;
};
struct fb_memo {
	struct fb_memo_entry e[1 << FB_MEMO_BITS];
};

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
 * beyond it (*h its pixels; else 0).  carried_bound needs it too. */
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
 * bound_end (h: its hole). */
static inline __attribute__((always_inline)) int face_bound_memo_at(const struct line_geom *g,
								    int n, int s, int e,
								    int dir, int h,
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
	return bound_end(g, n, s, e, dir, &h) && face_bound_memo_at(g, n, s, e, dir, h, b);
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

#endif
