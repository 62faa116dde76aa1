/* SPDX-License-Identifier: MIT */
/*
 * GTAO with tile noise, the fast path (included by gtao_simd.inc.c).
 *
 * With DAO_NOISE_TILE the pixels of one tile phase along a row, grouped in
 * blocks (dao_gtao_block_radius), share the slice directions, the step
 * jitter and the radius in pixels, so all of a block's samples sit at the
 * same offset from their pixels.  The taps of every step are worked out once
 * per block radius in scalar code (the arithmetic of dao_gtao_sample, so the
 * very same taps) into a table of offsets relative to the block's row, which
 * every block of that radius reuses in all rows of the same tile row (y mod
 * 4: same noise); the lanes read their two taps with one load each from the
 * phase plane (entries of one phase are 4 columns apart, as the block's
 * pixels are).  What stays per lane: the depth-edge rule, the horizon
 * cosine, the falloff and the thickness update.
 */

/* floor(a / 4) for any sign */
static inline int floor_div4(int a)
{
	return a >= 0 ? a / 4 : -((3 - a) / 4);
}

enum {
	TAP_USE1 = 1,  /* at a depth edge the second tap is the one closer to the line */
	TAP_ONLY0 = 2, /* the sample is on the first tap: it alone will do */
	TAP_ONLY1 = 4, /* ... on the second tap */
};

/* The constants of one tile phase and tile row: slice directions and step positions. */
struct tile_phase {
	int a;
	float dx[DAO_MAX_SLICES], dy[DAO_MAX_SLICES]; /* per slice */
	float t[DAO_MAX_STEPS]; /* per step, before scaling by the radius */
};

static void tile_phase_init(const struct dao_gtao_setup *s, int a, int y, struct tile_phase *ph)
{
	float n0, n1;
	dao_tile_noise(a, y, s->frame, &n0, &n1);
	ph->a = a;
	/* the reference's directions and steps, bit for bit */
	for (int sl = 0; sl < s->slices; sl++)
		dao_gtao_slice_dir(s, sl, n0, &ph->dx[sl], &ph->dy[sl]);
	for (int i = 0; i < s->steps; i++)
		ph->t[i] = dao_gtao_step_t(s, i, n1);
}

/* Entries from the first entry of phase 0 of a row to (row + dr, phase q, entry j). */
static inline int32_t tile_offset(const struct dao_gtao_planes *pl, int dr, int q, int j)
{
	return (int32_t)(((ptrdiff_t)dr * 4 + q) * pl->stride4 + j);
}

/* dao_gtao_sample for a block at step distance dist, relative to the block's
 * pixels; a step whose columns lie beyond the padding samples nothing (its
 * columns are then out of reach). */
static void tile_step_make(const struct dao_gtao_setup *s, const struct dao_gtao_planes *pl,
			   int a, float dmaj, float slope, int major_x, float dist,
			   struct tile_step *o)
{
	int mo = (int)lrintf(dmaj * dist);
	if (mo == 0)
		mo = dmaj > 0.0f ? 1 : -1;
	const float off = (float)mo * slope;
	const float fo = floorf(off);
	const int c0 = (int)fo;
	o->f = off - fo;
	o->flags = (o->f >= 0.5f ? TAP_USE1 : 0) | (o->f < 1e-3f ? TAP_ONLY0 : 0) |
		   (o->f > 1.0f - 1e-3f ? TAP_ONLY1 : 0);
	const int use1 = o->flags & TAP_USE1;
	int out; /* columns beyond the padding: off the image for every pixel */
	if (major_x) {
		/* columns x + mo (off the image: zero padding), rows y + c0 and y + c0 + 1 */
		out = mo < -pl->max_offset || mo > pl->max_offset;
		const int q = (a + mo) & 3, j = floor_div4(a + mo);
		o->o0 = tile_offset(pl, c0, q, j);
		o->o1 = tile_offset(pl, c0 + 1, q, j);
		o->dr_lo = c0;
		o->dr_hi = c0 + 1;
		o->dc_lo = o->dc_hi = mo;
		o->ux_s = o->ux_e = (float)mo * s->ax;
		o->vy_s = off * s->ay;
		o->vy_e = (float)(c0 + use1) * s->ay;
	} else {
		/* row y + mo, columns x + c0 and x + c0 + 1 */
		out = c0 < -pl->max_offset || c0 + 1 > pl->max_offset;
		o->o0 = tile_offset(pl, mo, (a + c0) & 3, floor_div4(a + c0));
		o->o1 = tile_offset(pl, mo, (a + c0 + 1) & 3, floor_div4(a + c0 + 1));
		o->dr_lo = o->dr_hi = mo;
		o->dc_lo = c0;
		o->dc_hi = c0 + 1;
		o->ux_s = off * s->ax;
		o->ux_e = (float)(c0 + use1) * s->ax;
		o->vy_s = o->vy_e = (float)mo * s->ay;
	}
	o->oe = use1 ? o->o1 : o->o0;
	o->c_s = o->ux_s * o->ux_s + o->vy_s * o->vy_s;
	o->c_e = o->ux_e * o->ux_e + o->vy_e * o->vy_e;
	if (out) { /* beyond the padding, so beyond the image: never sampled */
		o->o0 = o->o1 = o->oe = 0;
		o->dc_lo = o->dc_hi = INT32_MAX / 2;
	}
}

/* The steps of slice sl's two sides for block radius rp: st[0..steps) for the
 * positive side, st[steps..2 steps) for the negative one. */
static void tile_slice_make(const struct dao_gtao_setup *s, const struct dao_gtao_planes *pl,
			    const struct tile_phase *ph, float rp, int sl, struct tile_step *st)
{
	const float dx = ph->dx[sl], dy = ph->dy[sl];
	const int major_x = fabsf(dx) >= fabsf(dy);
	for (int side = 0; side < 2; side++) {
		const float sg = side ? -1.0f : 1.0f;
		const float dmaj = sg * (major_x ? dx : dy), dmin = sg * (major_x ? dy : dx);
		const float slope = dmin / dmaj;
		struct tile_step *o = st + (size_t)side * (size_t)s->steps;
		for (int i = 0; i < s->steps; i++) {
			/* the reference's step distance, bit for bit */
			const float dist = 1.0f + ph->t[i] * (rp - 1.0f);
			tile_step_make(s, pl, ph->a, dmaj, slope, major_x, dist, &o[i]);
		}
	}
}

/* Whether one table holds every slice of this configuration (else each block
 * makes its slices' steps as it goes). */
static inline int tile_table_fits(const struct dao_gtao_setup *s)
{
	return s->slices * 2 * s->steps <= TILE_STEPS_MAX;
}

static void tile_cache_reset(const struct dao_gtao_setup *s, struct tile_cache *c)
{
	c->per = s->slices * 2 * s->steps;
	c->steps = s->steps;
	c->count = tile_table_fits(s) ? TILE_STEPS_MAX / c->per : 0;
	if (c->count > TILE_TABLES)
		c->count = TILE_TABLES;
	c->next = 0;
	for (int i = 0; i < TILE_TABLES; i++)
		c->rp[i] = -1.0f;
}

/* The table of block radius rp in c: the one made for it (*fresh = 0), or the
 * slot to make it in (*fresh = 1; then tile_cache_reach), or NULL when no
 * table fits; *slot: its index. */
static struct tile_step *tile_cache_slot(struct tile_cache *c, float rp, int *slot, int *fresh)
{
	if (!c->count)
		return NULL;
	for (int i = 0; i < c->count; i++)
		if (c->rp[i] == rp) {
			*slot = i;
			*fresh = 0;
			return c->st + (size_t)i * (size_t)c->per;
		}
	const int i = c->next;
	c->next = (c->next + 1) % c->count;
	c->rp[i] = rp;
	*slot = i;
	*fresh = 1;
	return c->st + (size_t)i * (size_t)c->per;
}

/* How far the taps of a freshly made table reach from the pixel in rows and
 * columns, and with side_lims each slice side's limits (side_lim). */
static void tile_cache_reach(struct tile_cache *c, int slot, int side_lims)
{
	const struct tile_step *st = c->st + (size_t)slot * (size_t)c->per;
	int rr = 0, rc = 0;
	for (int k = 0; k < c->per; k++) {
		const int r = abs(st[k].dr_lo) > abs(st[k].dr_hi) ? abs(st[k].dr_lo) : abs(st[k].dr_hi);
		const int q = abs(st[k].dc_lo) > abs(st[k].dc_hi) ? abs(st[k].dc_lo) : abs(st[k].dc_hi);
		rr = r > rr ? r : rr;
		rc = q > rc ? q : rc;
	}
	c->reach_r[slot] = rr;
	c->reach_c[slot] = rc;
	for (int side = 0; side_lims && side * c->steps < c->per; side++) {
		const struct tile_step *o = st + (size_t)side * (size_t)c->steps;
		int32_t *lim = c->side_lim[slot][side];
		lim[0] = lim[2] = INT32_MAX;
		lim[1] = lim[3] = INT32_MIN;
		for (int k = 0; k < c->steps; k++) {
			lim[0] = o[k].dr_hi < lim[0] ? o[k].dr_hi : lim[0];
			lim[1] = o[k].dr_lo > lim[1] ? o[k].dr_lo : lim[1];
			lim[2] = o[k].dc_hi < lim[2] ? o[k].dc_hi : lim[2];
			lim[3] = o[k].dc_lo > lim[3] ? o[k].dc_lo : lim[3];
		}
	}
}

/* The steps of every slice for block radius rp (NULL when they do not fit:
 * tile_lanes then makes them per slice), how far their taps reach from the
 * pixel in rows and columns (*reach_r, *reach_c), and each slice side's
 * limits (*lim, tile_cache's side_lim). */
static const struct tile_step *tile_cache_get(const struct dao_gtao_setup *s,
					      const struct dao_gtao_planes *pl,
					      const struct tile_phase *ph, float rp,
					      struct tile_cache *c, int *reach_r, int *reach_c,
					      const int32_t (**lim)[4])
{
	int i, fresh;
	struct tile_step *st = tile_cache_slot(c, rp, &i, &fresh);
	if (!st)
		return NULL;
	if (fresh) {
		for (int sl = 0; sl < s->slices; sl++)
			tile_slice_make(s, pl, ph, rp, sl, st + (size_t)sl * 2 * (size_t)s->steps);
		tile_cache_reach(c, i, 1);
	}
	*reach_r = c->reach_r[i];
	*reach_c = c->reach_c[i];
	*lim = (const int32_t (*)[4])c->side_lim[i];
	return st;
}

/* Per-lane constants of the VN pixels of a block being processed. */
struct tile_px {
	struct px p;
	vf X0, Y0;  /* x ax + bx of the pixel, y ay + by of the row */
	vf Q;       /* |U0|^2 = X0^2 + Y0^2 + 1 */
	vf nu, inu; /* -|U0| and its inverse: a cosine c is c nu in tile_sample's units */
	int y, h, w;         /* the row, the image size */
	int x_first, x_last; /* columns of the first and the last lane */
};

/* Whether a step's taps are off the image for every lane (no sample anywhere:
 * skipping it changes nothing).  Otherwise its rows lie in -1 .. height, which
 * the phase plane has (rows -1 and height are zeros). */
static inline int tile_skip(const struct tile_px *t, const struct tile_step *st)
{
	return t->y + st->dr_hi < 0 || t->y + st->dr_lo >= t->h || t->x_last + st->dc_hi < 0 ||
	       t->x_first + st->dc_lo >= t->w;
}

/* Whether tile_skip may skip any step of a slice side with limits lim
 * (tile_cache's side_lim): exactly when one of its steps would be. */
static inline int tile_side_checks(const struct tile_px *t, const int32_t lim[4])
{
	return t->y + lim[0] < 0 || t->y + lim[1] >= t->h || t->x_last + lim[2] < 0 ||
	       t->x_first + lim[3] >= t->w;
}

/*
 * One step of one side: the sample's horizon cosine, weighted towards `low` by
 * the falloff, and whether there is a sample; all in units of -1 / |U0| (see
 * below), where the largest cosine is the smallest value.
 *
 * D = S - P = z_s G with G = U - P iz, iz = 1 / z_s, U = (u ax + bx, v ay + by,
 * 1): G has the direction of D and |D| = |G| / iz.  With P = z U0, U0 = (X0,
 * Y0, 1), G = Gz U0 + (du, dv, 0) where Gz = 1 - z iz and (du, dv) is the
 * sample's offset in U.  With B = X0 du + Y0 dv and Q = |U0|^2:
 *   G.U0 = Gz Q + B,   |G|^2 = Gz (Gz Q + 2 B) + du^2 + dv^2,
 * and as V = -U0 / |U0| the cosine is c = (G.U0 / |G|) (-1 / |U0|): the factor
 * is left to the end of the search (tile_sides), which then takes the minimum.
 * Lanes without a sample have iz = 0, so |D| = inf and weight 0.
 */
/* A step's 1/z from its two taps in a plane (1/z, or the thickness read the
 * same way), as every tile kernel with the depth-edge rule reads it. */
struct tile_tap {
	vf iz;       /* 0 where there is no sample */
	vm ok;       /* a sample */
	vm edge;     /* the taps straddle a depth edge: the tap closer to the line */
	vm only;     /* on a tap without data on the other: it alone (TAP_ONLY*) */
};

static inline __attribute__((always_inline)) struct tile_tap
tile_tap_read(const float *base, const struct tile_step *st)
{
	const vf zero = v_zero();
	const vf iz0 = v_load(base + st->o0), iz1 = v_load(base + st->o1);
	const vf izmin = v_min(iz0, iz1);
	struct tile_tap r;
	r.ok = v_gt(izmin, zero); /* both taps have data */
	const vf d01 = v_sub(iz1, iz0);
	/* |z0 - z1| > 0.1 min(z0, z1), in 1/z: the tap closer to the line, at its place */
	r.edge = m_and(r.ok, v_gt(v_abs(d01), v_mul(v_set1(0.1f), izmin)));
	/* no sample (a tap without data): iz = 0 */
	r.iz = v_sel(r.edge, v_load(base + st->oe), v_sel(r.ok, v_fma(v_set1(st->f), d01, iz0), zero));
	r.only = v_gt(zero, zero);
	if (st->flags & (TAP_ONLY0 | TAP_ONLY1)) { /* on a tap: it alone will do */
		const vm has0 = v_gt(iz0, zero), has1 = v_gt(iz1, zero);
		r.only = (st->flags & TAP_ONLY0) ? m_andnot(has0, has1) : m_andnot(has1, has0);
		r.iz = v_sel(r.only, (st->flags & TAP_ONLY0) ? iz0 : iz1, r.iz);
		r.ok = m_or(r.ok, r.only);
	}
	return r;
}

/* The same interpolation of a plane of halves (the thickness) at a step whose
 * taps were read (tile_tap_read): the value at the edge's tap, the lone tap, or
 * between. */
static inline __attribute__((always_inline)) vf
tile_tap_follow(const uint16_t *base, const struct tile_step *st, const struct tile_tap *tp)
{
	const vf a0 = v_load_h(base + st->o0), a1 = v_load_h(base + st->o1);
	vf a = v_sel(tp->edge, v_load_h(base + st->oe), v_fma(v_set1(st->f), v_sub(a1, a0), a0));
	if (st->flags & (TAP_ONLY0 | TAP_ONLY1))
		a = v_sel(tp->only, (st->flags & TAP_ONLY0) ? a0 : a1, a);
	return a;
}

static inline __attribute__((always_inline)) vf
tile_sample(const struct dao_gtao_setup *s, const float *base, const struct tile_px *t,
	    const struct tile_step *st, vf lowk, vm *okp, const int major_x, const int use_max)
{
	const vf one = v_set1(1.0f), zero = v_zero();
	const struct px *p = &t->p;
	const struct tile_tap tp = tile_tap_read(base, st);
	/* the line the same lanes of the next block span (DAO_GTAO_BLOCK entries on,
	 * after the span's other tile phases) add to these taps: the taps lie up to
	 * max_r_px rows away, beyond the caches, and each load moves by a fixed step
	 * from span to span, which the hardware's prefetchers do not follow (one
	 * address per step and slice from the same instructions); as vbao_front */
	__builtin_prefetch(base + st->o0 + DAO_GTAO_BLOCK + VN - 1);
	__builtin_prefetch(base + st->o1 + DAO_GTAO_BLOCK + VN - 1);
	const vf iz = tp.iz;
	vm ok = tp.ok;
	const vm edge = tp.edge;
	const vf Gz = v_fnma(p->Pz, iz, one);
	/* an edge moves the sample on the minor axis only */
	const vf du = major_x ? v_set1(st->ux_s) : v_sel(edge, v_set1(st->ux_e), v_set1(st->ux_s));
	const vf dv = major_x ? v_sel(edge, v_set1(st->vy_e), v_set1(st->vy_s)) : v_set1(st->vy_s);
	const vf B = v_fma(t->X0, du, v_mul(t->Y0, dv));
	const vf GU = v_fma(Gz, t->Q, B);
	const vf g2 = v_fma(Gz, v_add(GU, B), v_sel(edge, v_set1(st->c_e), v_set1(st->c_s)));
	const vf rg = v_rsqrt_fast(g2); /* G is never 0: the sample is off the pixel's ray */
	/* |D| for the falloff weight: the estimate of 1/iz is plenty there */
	const vf len = v_mul(v_mul(g2, rg), v_rcp_fast(iz));
	const vf w = v_fma(len, v_set1(s->falloff_mul), v_set1(s->falloff_add));
	*okp = ok;
	if (use_max) {
		/* The sample's value lowk + (c - lowk) clamp(w, 0, 1) matters to the
		 * minimum only where it is below lowk (the search starts there), and
		 * then lowk minus it is min(e w, e) with e = lowk - c, w unclamped:
		 * e > 0 and w >= 1 give e, 0 < w < 1 give e w, w <= 0 gives at most 0
		 * (no change), and e <= 0 gives at most 0 for any w.  A lane without a
		 * sample has w = -inf (iz = 0): e w is -inf, or NaN where e = 0, and
		 * min then returns its second operand, 0.  tile_sides keeps the
		 * largest of these (lowk minus the horizon): two operations fewer a
		 * step than clamping w. */
		const vf e = v_fnma(GU, rg, lowk);
		return v_min(v_mul(e, w), e);
	}
	const vf wgt = v_min(v_max(w, zero), one);
	return v_fma(v_sub(v_mul(GU, rg), lowk), wgt, lowk);
}

/*
 * The largest horizon cosines of both sides of a slice (search_side of the
 * reference), the two sides' steps interleaved for instruction-level
 * parallelism; base: the phase plane at the lanes' first entry.  The search
 * runs in the units of tile_sample (a cosine c is c |U0|, negated), so the
 * highest horizon is the smallest value.  use_max: no thickness heuristic
 * (decay 1), so a step without a sample, weighing 0, cannot change the
 * horizon; with it, such lanes keep theirs explicitly.
 */
static inline __attribute__((always_inline)) void
tile_sides(const struct dao_gtao_setup *s, const float *base, const struct tile_px *t,
	   const struct tile_step *st, vf low_pos, vf low_neg, vf *hc_pos, vf *hc_neg,
	   const int use_max, const int major_x, const int check_p, const int check_n)
{
	const vf decay = v_set1(s->decay);
	const struct tile_step *sn = st + s->steps;
	const vf lp = v_mul(low_pos, t->nu), ln = v_mul(low_neg, t->nu);
	/* use_max: how far below lp, ln the horizons are (tile_sample) */
	vf bp = use_max ? v_zero() : lp, bn = use_max ? v_zero() : ln;
	for (int i = 0; i < s->steps; i++) {
		vm okp, okn;
		if (!check_p || !tile_skip(t, &st[i])) {
			const vf cp = tile_sample(s, base, t, &st[i], lp, &okp, major_x, use_max);
			if (use_max)
				bp = v_max(bp, cp);
			else /* thickness heuristic (UE4): a lower sample after a higher one
			      * pulls the horizon towards it */
				bp = v_sel(okp, v_sel(v_lt(cp, bp), cp, v_fma(v_sub(bp, cp), decay, cp)),
					   bp);
		}
		if (!check_n || !tile_skip(t, &sn[i])) {
			const vf cn = tile_sample(s, base, t, &sn[i], ln, &okn, major_x, use_max);
			if (use_max)
				bn = v_max(bn, cn);
			else
				bn = v_sel(okn, v_sel(v_lt(cn, bn), cn, v_fma(v_sub(bn, cn), decay, cn)),
					   bn);
		}
	}
	if (use_max) {
		bp = v_sub(lp, bp);
		bn = v_sub(ln, bn);
	}
	*hc_pos = v_mul(bp, t->inu);
	*hc_neg = v_mul(bn, t->inu);
}

/* tile_sides specialised on the heuristic, the major axis and which sides may
 * have steps to skip (chk_p, chk_n: tile_lanes' side checks). */
static void tile_sides_any(const struct dao_gtao_setup *s, const float *base,
			   const struct tile_px *t, const struct tile_step *st, vf low_pos,
			   vf low_neg, vf *hc_pos, vf *hc_neg, int major_x, int chk_p, int chk_n)
{
#define TILE_SIDES(k)                                                                    \
	case k:                                                                          \
		tile_sides(s, base, t, st, low_pos, low_neg, hc_pos, hc_neg, (k) >> 3,  \
			   ((k) >> 2) & 1, ((k) >> 1) & 1, (k) & 1);                     \
		break;
	const int use_max = s->decay == 1.0f;
	switch (use_max * 8 + major_x * 4 + chk_p * 2 + chk_n) {
	TILE_SIDES(0) TILE_SIDES(1) TILE_SIDES(2) TILE_SIDES(3)
	TILE_SIDES(4) TILE_SIDES(5) TILE_SIDES(6) TILE_SIDES(7)
	TILE_SIDES(8) TILE_SIDES(9) TILE_SIDES(10) TILE_SIDES(11)
	TILE_SIDES(12) TILE_SIDES(13) TILE_SIDES(14) default: TILE_SIDES(15)
	}
#undef TILE_SIDES
}

/* The normals of columns x0 .. x0 + DAO_GTAO_BLOCK_SPAN - 1 of row y split by
 * tile phase, as the blocks use them: nb[q][c][e] is component c of column
 * x0 + 4 e + q (0 past the row's end). */
static void tile_group_normals(const float *n, int w, int y, int x0,
			       float nb[4][3][DAO_GTAO_BLOCK])
{
	const float *row = n + 3 * (size_t)y * (size_t)w;
	for (int g = 0; g < DAO_GTAO_BLOCK_SPAN; g += 4 * VN) {
		const int xg = x0 + g;
		if (xg + 4 * VN <= w) {
			vf comp[3][4];
			for (int m = 0; m < 4; m++)
				v_load3(row + 3 * (size_t)(xg + m * VN), &comp[0][m], &comp[1][m],
					&comp[2][m]);
			for (int c = 0; c < 3; c++) {
				vf q[4];
				v_deinterleave4(comp[c], q);
				for (int k = 0; k < 4; k++)
					v_store(&nb[k][c][g / 4], q[k]);
			}
			continue;
		}
		for (int e = g / 4; e < (g + 4 * VN) / 4; e++)
			for (int k = 0; k < 4; k++) {
				const int x = x0 + 4 * e + k;
				for (int c = 0; c < 3; c++)
					nb[k][c][e] = x < w ? row[3 * (size_t)x + (size_t)c] : 0.0f;
			}
	}
}

#include "kernels/vbao_tile.inc.c"

/* VN lanes of a block of phase a: columns x0, x0 + 4, ... (entries jb, jb + 1,
 * ... of the phase plane; nq: their normals, from tile_group_normals); GTAO
 * (is_vbao 0, vb and pipe NULL), or VBAO with vb (pipe: its slices in flight,
 * room that tile_row keeps).  is_vbao is a constant: each kernel gets its
 * own copy, and GTAO's has none of VBAO's code (nor its registers). */
static inline __attribute__((always_inline)) void
tile_lanes(const struct dao_gtao_setup *s, const struct dao_gtao_planes *pl,
	   const float (*nq)[DAO_GTAO_BLOCK], float *ob, const struct tile_phase *ph,
	   const struct tile_step *tsteps, const int32_t (*lim)[4], int reach_r, int reach_c,
	   float rp, int y, int jb, int h, struct dao_tile_scratch *sc,
	   const struct tile_vbao *vb, struct vbao_pipe *pipe, const int is_vbao)
{
	const int x0 = 4 * (jb + h) + ph->a;
	struct tile_px t;
	struct px *p = &t.p; /* the tile kernel sets x, Pz, V and active */
	t.Y0 = v_set1((float)y * s->ay + s->by);
	t.y = y;
	t.h = s->height;
	t.w = s->width;
	t.x_first = x0;
	t.x_last = x0 + 4 * (VN - 1);
	/* every tap of the table on the image for every lane: no step is skipped */
	const int inner = tsteps && y - reach_r >= 0 && y + reach_r < t.h && x0 - reach_c >= 0 &&
			  t.x_last + reach_c < t.w;
	p->x = v_fma(v_iota(), v_set1(4.0f), v_set1((float)x0));
	/* lanes past x_end have no depth here (they are another strip's) */
	const vm in = v_lt(p->x, v_set1((float)s->x_end));
	const vf one = v_set1(1.0f);
	/* depth from the phase plane: 1 / (1 / z), within an ulp of z */
	const vf iz = v_sel(in, v_load(dao_gtao_phase_row(pl, y, ph->a) + jb + h), v_zero());
	const vm has_z = v_gt(iz, v_zero());
	p->Pz = v_sel(has_z, v_div(one, v_sel(has_z, iz, one)), v_zero());
	t.X0 = v_add(v_mul(p->x, v_set1(s->ax)), v_set1(s->bx));
	/* V = -P / |P| = -U0 / |U0| with U0 = P / z = (X0, Y0, 1) */
	t.Q = v_fma(t.X0, t.X0, v_fma(t.Y0, t.Y0, one));
	const vf iu = v_rsqrt(t.Q);
	t.nu = v_neg(v_mul(t.Q, iu));
	t.inu = v_neg(iu);
	p->Vx = v_mul(t.X0, t.inu), p->Vy = v_mul(t.Y0, t.inu), p->Vz = t.inu;
	/* the pixel's own radius decides whether it is searched at all */
	const vf r = v_mul(v_set1(s->search_radius * s->focal), iz);
	p->active = m_and(has_z, m_and(v_ge(r, v_set1(s->min_r_px)), v_ge(r, one)));
	vf vis = one;
	if (m_any(p->active)) {
		const vf N[3] = { v_load(nq[0] + h), v_load(nq[1] + h), v_load(nq[2] + h) };
		const vf NV = v_fma(N[0], p->Vx, v_fma(N[1], p->Vy, v_mul(N[2], p->Vz)));
		const float *base = dao_gtao_phase_row(pl, y, 0) + jb + h;
		const uint16_t *tbase =
			is_vbao && vb->plane ? dao_gtao_thick_row(pl, y, 0) + jb + h : NULL;
		vf sum = v_zero(), norm = v_zero();
		/* VBAO with the steps of every slice in the table and in one chunk: the
		 * slices' two passes interleaved (vbao_pipe) */
		struct vbao_pipe *vp = is_vbao && tsteps && s->steps <= VBAO_CHUNK ? pipe : NULL;
		if (vp)
			vp->n = 0;
		for (int sl = 0; sl < s->slices; sl++) {
			/* the axis dir x V is -(dir x U0) / |U0|, and dir x U0 = (diry,
			 * -dirx, dirx Y0 - diry X0) with dir = (dx ax, dy ay, 0) */
			const float dirx = ph->dx[sl] * s->ax, diry = ph->dy[sl] * s->ay;
			const vf az = v_fnma(v_set1(diry), t.X0, v_mul(v_set1(dirx), t.Y0));
			const vf a2 = v_fma(az, az, v_set1(dirx * dirx + diry * diry));
			/* VBAO places its sectors from n: the precise acos and sqrt there */
			struct slice_v g = slice_from_axis(p, v_set1(dirx), v_set1(diry), v_set1(diry),
							   v_set1(-dirx), az, a2, N, NV, !is_vbao);
			if (!m_any(g.ok))
				continue;
			const struct tile_step *st;
			if (tsteps) {
				st = tsteps + (size_t)sl * 2 * (size_t)s->steps;
			} else {
				tile_slice_make(s, pl, ph, rp, sl, sc->local);
				st = sc->local;
			}
			const int major_x = fabsf(ph->dx[sl]) >= fabsf(ph->dy[sl]);
			/* outside the inner blocks, which sides have steps to skip */
			const int chk_p = !inner && (!tsteps || tile_side_checks(&t, lim[2 * sl]));
			const int chk_n = !inner && (!tsteps || tile_side_checks(&t, lim[2 * sl + 1]));
			if (is_vbao) {
				if (vp) {
					vbao_pipe_slice(vb, s, base, tbase, &t, st, &g, major_x, chk_p,
							chk_n, vp, &sum, &norm);
					continue;
				}
				const vi mask = vbao_sides_any(vb, s, base, tbase, &t, st, &g, major_x,
							       chk_p, chk_n);
				vbao_accumulate(&g, mask, &sum, &norm);
				continue;
			}
			vf hc_pos, hc_neg;
			tile_sides_any(s, base, &t, st, v_neg(g.sin_n), g.sin_n, &hc_pos, &hc_neg,
				       major_x, chk_p, chk_n);
			slice_accumulate(&g, hc_pos, hc_neg, &sum, &norm, 1);
		}
		if (vp && vp->n)
			vbao_pipe_back(vb, s, tbase, &t, vp, (vp->n - 1) & 1, &sum, &norm);
		const vm has = v_gt(norm, v_zero());
		vis = v_sel(has, v_div(sum, v_sel(has, norm, one)), one);
	}
	v_store(ob + h, v_sel(has_z, finish_lanes(s, vis), v_set1(s->invalid_value)));
}

/* The largest 1/z of the block of phase a at entry jb of row y (0: no depth);
 * the radius in pixels the block searches, from it (dao_gtao_block_radius,
 * then at most max_r_px; -1 when no pixel of the block has depth). */
static inline float tile_block_izmax(const struct dao_gtao_planes *pl, int y, int a, int jb)
{
	const float *izrow = dao_gtao_phase_row(pl, y, a);
	vf m = v_load(izrow + jb);
	for (int k = VN; k < DAO_GTAO_BLOCK; k += VN)
		m = v_max(m, v_load(izrow + jb + k));
	return v_hmax(m);
}

static inline float tile_block_rp(const struct dao_gtao_setup *s,
				  const struct dao_gtao_planes *pl, int y, int a, int jb)
{
	const float izmax = tile_block_izmax(pl, y, a, jb);
	if (izmax <= 0.0f)
		return -1.0f;
	const float rq = dao_gtao_quantize_radius(s->search_radius * s->focal * izmax);
	return rq < s->max_r_px ? rq : s->max_r_px; /* fminf: a libm call */
}

/* A block without depth: every pixel of it (from column x0, every 4th) invalid. */
static inline void tile_block_invalid(const struct dao_gtao_setup *s, float *ao, int y, int x0)
{
	const int xe = (x0 & ~(DAO_GTAO_BLOCK_SPAN - 1)) + DAO_GTAO_BLOCK_SPAN;
	for (int x = x0; x < xe && x < s->x_end; x += 4)
		ao[(size_t)y * s->width + x] = s->invalid_value;
}

/* The same into tile_row's buffer (ob: the block's phase's entries). */
static inline void tile_block_invalid_buf(const struct dao_gtao_setup *s, float *ob)
{
	for (int e = 0; e < DAO_GTAO_BLOCK; e += VN)
		v_store(ob + e, v_set1(s->invalid_value));
}

/* The AO of a block span from tile_row's buffer (ob[a][e]: column xb + 4 e + a)
 * into row y, the columns before x_end: contiguous stores, where each block
 * wrote every 4th column one float at a time. */
static inline void tile_span_store(const struct dao_gtao_setup *s, float *ao, int y, int xb,
				   const float ob[4][DAO_GTAO_BLOCK])
{
	float *dst = ao + (size_t)y * s->width + xb;
	if (xb + DAO_GTAO_BLOCK_SPAN <= s->x_end) {
		for (int e = 0; e < DAO_GTAO_BLOCK; e += VN) {
			vf v[4], q[4];
			for (int a = 0; a < 4; a++)
				v[a] = v_load(ob[a] + e);
			v_interleave4(v, q);
			for (int a = 0; a < 4; a++)
				v_store(dst + 4 * e + a * VN, q[a]);
		}
		return;
	}
	for (int x = 0; xb + x < s->x_end; x++)
		dst[x] = ob[x & 3][x >> 2];
}

/* Asks for the normals of the block span at column x of row y (-1: none),
 * the one tile_row splits next: a row of normals is read once, 3 floats a
 * pixel, and the first lines of each of its spans missed the caches. */
static inline void tile_prefetch_normals(const struct dao_gtao_setup *s, const float *n, int y,
					 int x)
{
	if (y < 0)
		return;
	const float *row = n + 3 * ((size_t)y * (size_t)s->width + (size_t)x);
	const int count = 3 * (s->width - x < DAO_GTAO_BLOCK_SPAN ? s->width - x : DAO_GTAO_BLOCK_SPAN);
	/* every line of the span's floats (16 a line), and its last float's: an
	 * unaligned plane puts them on one line more */
	for (int k = 0; k < count; k += 16)
		__builtin_prefetch(row + k);
	__builtin_prefetch(row + count - 1);
}

/* Columns [x_begin, x_end) of row y, block by block: the four tile phases of
 * DAO_GTAO_BLOCK_SPAN columns share one split of their normals (is_vbao, vb:
 * tile_lanes). */
static inline __attribute__((always_inline)) void
tile_row(const struct dao_gtao_setup *s, const struct dao_gtao_planes *pl, const float *n,
	 float *ao, const struct tile_phase ph[4], struct dao_tile_scratch *sc,
	 const struct tile_vbao *vb, int y, int y_next, const int is_vbao)
{
	float nb[4][3][DAO_GTAO_BLOCK];
	float ob[4][DAO_GTAO_BLOCK] __attribute__((aligned(64)));
	struct vbao_pipe pipe;
	for (int xb = s->x_begin; xb < s->x_end; xb += DAO_GTAO_BLOCK_SPAN) {
		const int jb = xb / 4;
		int split = 0;
		for (int a = 0; a < 4 && xb + a < s->x_end; a++) {
			const float rp = tile_block_rp(s, pl, y, a, jb);
			if (rp < 0.0f) {
				tile_block_invalid_buf(s, ob[a]);
				continue;
			}
			int reach_r = 0, reach_c = 0;
			const int32_t (*lim)[4] = NULL;
			const struct tile_step *tsteps =
				tile_cache_get(s, pl, &ph[a], rp, &sc->cache[a], &reach_r, &reach_c, &lim);
			if (!split) {
				tile_group_normals(n, s->width, y, xb, nb);
				split = 1;
				tile_prefetch_normals(s, n, xb + DAO_GTAO_BLOCK_SPAN < s->x_end ? y : y_next,
						      xb + DAO_GTAO_BLOCK_SPAN < s->x_end
							      ? xb + DAO_GTAO_BLOCK_SPAN
							      : s->x_begin);
			}
			for (int h = 0; h < DAO_GTAO_BLOCK; h += VN)
				if (4 * (jb + h) + a < s->x_end)
					tile_lanes(s, pl, (const float (*)[DAO_GTAO_BLOCK])nb[a], ob[a], &ph[a],
						   tsteps, lim, reach_r, reach_c, rp, y, jb, h, sc, vb,
						   is_vbao ? &pipe : NULL, is_vbao);
		}
		tile_span_store(s, ao, y, xb, (const float (*)[DAO_GTAO_BLOCK])ob);
	}
}

/* Rows [y0, y1), columns [x_begin, x_end) (x_begin a multiple of the block
 * span): GTAO, or VBAO with vb (is_vbao); sc: this thread's scratch. */
static inline __attribute__((always_inline)) void
tile_rows(const struct dao_gtao_setup *s, const struct dao_gtao_planes *pl, const float *n,
	  float *ao, int y0, int y1, struct dao_tile_scratch *sc, const struct tile_vbao *vb,
	  const int is_vbao)
{
	/* Rows by tile row (y mod 4), so that the tables of a tile phase serve every
	 * row of the band with that noise.  The tables of every preset fit in the
	 * scratch; more slices x steps than that are made per block and slice
	 * (tile_lanes). */
	struct tile_phase ph[4];
	for (int cls = 0; cls < 4; cls++) {
		int yc = y0 + ((cls - y0) & 3); /* the first row of the band in this tile row */
		if (yc >= y1)
			continue;
		for (int a = 0; a < 4; a++) {
			tile_phase_init(s, a, yc, &ph[a]);
			tile_cache_reset(s, &sc->cache[a]);
		}
		for (int y = yc; y < y1; y += 4)
			tile_row(s, pl, n, ao, ph, sc, vb, y, y + 4 < y1 ? y + 4 : -1, is_vbao);
	}
}

/* The two kernels of tile_rows, each compiled for itself. */
static void gtao_tile(const struct dao_gtao_setup *s, const struct dao_gtao_planes *pl,
		      const float *n, float *ao, int y0, int y1, struct dao_tile_scratch *sc)
{
	tile_rows(s, pl, n, ao, y0, y1, sc, NULL, 0);
}

static void vbao_tile(const struct dao_gtao_setup *s, const struct dao_gtao_planes *pl,
		      const float *n, float *ao, int y0, int y1, struct dao_tile_scratch *sc,
		      const struct tile_vbao *vb)
{
	tile_rows(s, pl, n, ao, y0, y1, sc, vb, 1);
}

#include "kernels/hbao_tile.inc.c"
