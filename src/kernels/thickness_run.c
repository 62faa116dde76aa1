/* SPDX-License-Identifier: MIT */
/*
 * Thickness from the image: one run's estimate (run_estimate).  Whether its
 * ends are its object's outline (outline), its chord, a pole's chord plus
 * half a spacing (near_behind), a face hidden in a hole (hidden_face), the
 * slabs at its ends (slab_edge, thickness_slab.c) and beyond them
 * (receding_face), and the bounds at its ends (run_face_bounds:
 * thickness_bound.c, thickness_bound_across.c).
 */
#include "kernels/thickness_memo.h"

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

/* Noisy depth whose dropouts are not filled (structured light, active stereo, ToF): where
 * the hidden face applies. */
static inline int noisy_unfilled(const struct dao_thickness_setup *t)
{
	return t->noise_k > 0.0f && t->fill_px == 0;
}

/* Both ends of the run s..e: *count bounds in b (own or carried). */
static void run_face_bounds(const struct line_geom *g, int n, int s, int e, int *count,
			    struct face_bound b[2])
{
	/* (an end that fails bound_end has neither) */
	*count = 0;
	for (int dir = -1; dir <= 1; dir += 2) {
		int h;
		if (!bound_end(g, n, s, e, dir, &h))
			continue;
		struct face_bound *bb = &b[*count];
		if (face_bound_memo_at(g, n, s, e, dir, h, bb))
			face_bound_pixels(g, s, e, dir, bb);
		else if (!carried_bound(g, n, s, e, dir, bb))
			continue;
		(*count)++;
	}
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
__attribute__((noinline)) void run_estimate(const struct line_geom *lg, int n, int s,
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
	}
	run_face_bounds(&g, n, s, e, &r->bounds, r->bound);
}
