/* SPDX-License-Identifier: MIT */
/*
 * Thickness from the image: a bound for a run's end that has none of its own,
 * from the lines across, carried along the outline (carried_bound).
 */
#include "kernels/thickness_memo.h"

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

__attribute__((noinline)) int carried_bound(const struct line_geom *g, int n, int s,
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

