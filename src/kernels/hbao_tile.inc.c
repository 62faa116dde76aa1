/* SPDX-License-Identifier: MIT */
/*
 * HBAO with tile noise (included by gtao_tile.inc.c): hbao_pixel of
 * ao_variants.c (read that first) on the blocks, step tables and phase plane
 * of the GTAO tile kernel.
 *
 * HBAO's directions and steps depend on the pixel only through its noise
 * and its radius, so with tile noise the pixels of a block (one tile phase
 * along a row, one radius: its farthest pixel's, where GTAO's blocks take their
 * nearest's, see hbao_block_izmin) sample at the same offsets, as GTAO's do.  Its
 * sample is the pixel nearest the point on the direction (no interpolation
 * between two taps, no depth-edge rule): one tap, one load per step and 16
 * pixels from the phase plane.  The tables hold per direction (2 x slices
 * over the full circle, hbao_pixel's order) and step the tap's offset, made
 * in scalar code with the reference's arithmetic, so the very same taps.
 *
 * In tile_sample's terms (D = z_s G, G = Gz U0 + (du, dv, 0), Gz = 1 - z iz):
 * the sample's elevation sin s = -D.z / |D| = -Gz / |G|, and
 * r^2 = |D|^2 / R^2 = |G|^2 z_s^2 / R^2.  Per lane stay the MinDiff tangent
 * (four neighbours, read from the phase plane as well), its biased elevation
 * per direction, and per step the horizon update and W(r) = 1 - r^2.
 */

/* The constants of one tile phase and tile row: HBAO's directions and steps. */
struct hbao_phase {
	int a;
	float dx[2 * DAO_MAX_SLICES], dy[2 * DAO_MAX_SLICES]; /* per direction */
	float t[DAO_MAX_STEPS]; /* per step, (i + n1) / steps */
};

static void hbao_phase_init(const struct dao_gtao_setup *s, int a, int y, struct hbao_phase *ph)
{
	float n0, n1;
	dao_tile_noise(a, y, s->frame, &n0, &n1);
	ph->a = a;
	/* hbao_pixel's expressions, bit for bit */
	const int dirs = 2 * s->slices;
	for (int d = 0; d < dirs; d++) {
		const float phi = 2.0f * DAO_PI_F * ((float)d + n0) / (float)dirs;
		ph->dx[d] = cosf(phi);
		ph->dy[d] = sinf(phi);
	}
	for (int i = 0; i < s->steps; i++)
		ph->t[i] = ((float)i + n1) / (float)s->steps;
}

/* The steps of direction d for block radius rp: the pixel nearest the point
 * dist along the direction, relative to the block's pixels (hbao_pixel's
 * lrintf of the offset); a column beyond the padding is off the image for
 * every pixel. */
static void hbao_dir_make(const struct dao_gtao_setup *s, const struct dao_gtao_planes *pl,
			  const struct hbao_phase *ph, float rp, int d, struct tile_step *o)
{
	for (int i = 0; i < s->steps; i++, o++) {
		const float dist = 1.0f + ph->t[i] * (rp - 1.0f);
		const int dc = (int)lrintf(ph->dx[d] * dist), dr = (int)lrintf(ph->dy[d] * dist);
		*o = (struct tile_step){ 0 };
		o->o0 = o->o1 = o->oe = tile_offset(pl, dr, (ph->a + dc) & 3, floor_div4(ph->a + dc));
		o->dr_lo = o->dr_hi = dr;
		o->dc_lo = o->dc_hi = dc;
		o->ux_s = o->ux_e = (float)dc * s->ax;
		o->vy_s = o->vy_e = (float)dr * s->ay;
		o->c_s = o->c_e = o->ux_s * o->ux_s + o->vy_s * o->vy_s;
		/* beyond the padding, or on the pixel itself (hbao_pixel's len2 = 0; not
		 * with radii of a pixel or more): never sampled */
		if (dc < -pl->max_offset || dc > pl->max_offset || (dc == 0 && dr == 0)) {
			o->o0 = o->o1 = o->oe = 0;
			o->dc_lo = o->dc_hi = INT32_MAX / 2;
		}
	}
}

/* Every direction's steps for block radius rp (NULL when they do not fit: the
 * lanes then make them per direction), and their reach (tile_cache_get). */
static const struct tile_step *hbao_cache_get(const struct dao_gtao_setup *s,
					      const struct dao_gtao_planes *pl,
					      const struct hbao_phase *ph, float rp,
					      struct tile_cache *c, int *reach_r, int *reach_c)
{
	int i, fresh;
	struct tile_step *st = tile_cache_slot(c, rp, &i, &fresh);
	if (!st)
		return NULL;
	if (fresh) {
		for (int d = 0; d < 2 * s->slices; d++)
			hbao_dir_make(s, pl, ph, rp, d, st + (size_t)d * (size_t)s->steps);
		tile_cache_reach(c, i, 0);
	}
	*reach_r = c->reach_r[i];
	*reach_c = c->reach_c[i];
	return st;
}

/*
 * One direction: the horizon from the biased tangent's elevation sin_h up,
 * each step above it adding W(r) (sin s - sin h) (hbao_pixel's inner loop).
 */
static inline __attribute__((always_inline)) vf
hbao_dir(const struct tile_px *t, const float *base, const struct tile_step *st, int steps,
	 vf sin_h, vf inv_r2, const int check)
{
	const vf one = v_set1(1.0f), zero = v_zero();
	const struct px *p = &t->p;
	vf ao = zero;
	for (int i = 0; i < steps; i++) {
		if (check && tile_skip(t, &st[i]))
			continue; /* off the image for every lane: no sample */
		const vf iz = v_load(base + st[i].o0);
		const vm has = v_gt(iz, zero);
		const vf Gz = v_fnma(p->Pz, iz, one);
		const vf B = v_fma(t->X0, v_set1(st[i].ux_s), v_mul(t->Y0, v_set1(st[i].vy_s)));
		/* |G|^2 = Gz (Gz Q + 2 B) + du^2 + dv^2: never 0, the offset is not */
		const vf g2 = v_fma(Gz, v_fma(Gz, t->Q, v_add(B, B)), v_set1(st[i].c_s));
		const vf zs = v_rcp(v_sel(has, iz, one));
		const vf r2 = v_mul(v_mul(g2, v_mul(zs, zs)), inv_r2);
		const vf sin_s = v_neg(v_mul(Gz, v_rsqrt(g2)));
		const vm up = m_and(m_and(has, v_lt(r2, one)), v_gt(sin_s, sin_h));
		ao = v_sel(up, v_fma(v_sub(one, r2), v_sub(sin_s, sin_h), ao), ao);
		sin_h = v_sel(up, sin_s, sin_h);
	}
	return ao;
}

static vf hbao_dir_any(const struct tile_px *t, const float *base, const struct tile_step *st,
		       int steps, vf sin_h, vf inv_r2, int inner)
{
	return inner ? hbao_dir(t, base, st, steps, sin_h, inv_r2, 0)
		     : hbao_dir(t, base, st, steps, sin_h, inv_r2, 1);
}

/* The depth (0: none) of the lanes' entries at `row` of the phase plane. */
static inline vf hbao_depth(const float *row)
{
	const vf iz = v_load(row);
	const vm has = v_gt(iz, v_zero());
	return v_sel(has, v_div(v_set1(1.0f), v_sel(has, iz, v_set1(1.0f))), v_zero());
}

/* min_diff of ao_variants.c over lanes: of the one-sided differences, the shorter
 * (where both neighbours have depth), else the one there is. */
static inline void hbao_min_diff(const vf P[3], const vf L[3], const vf R[3], vm have_l,
				 vm have_r, vf T[3])
{
	vf dl[3], dr[3];
	for (int c = 0; c < 3; c++) {
		dl[c] = v_sub(P[c], L[c]);
		dr[c] = v_sub(R[c], P[c]);
	}
	const vf l2 = v_add(v_add(v_mul(dl[0], dl[0]), v_mul(dl[1], dl[1])), v_mul(dl[2], dl[2]));
	const vf r2 = v_add(v_add(v_mul(dr[0], dr[0]), v_mul(dr[1], dr[1])), v_mul(dr[2], dr[2]));
	const vm left = m_or(m_andnot(have_l, have_r), m_and(have_l, v_lt(l2, r2)));
	for (int c = 0; c < 3; c++)
		T[c] = v_sel(left, dl[c], dr[c]);
}

/* The smallest 1/z with depth of the block of phase a at entry jb of row y
 * (INFINITY: none), as hbao_block_izmin of ao_variants.c. */
static inline float hbao_block_izmin(const struct dao_gtao_planes *pl, int y, int a, int jb)
{
	const float *izrow = dao_gtao_phase_row(pl, y, a);
	const vf ninf = v_set1(-INFINITY);
	vf m = ninf; /* the largest -1/z */
	for (int k = 0; k < DAO_GTAO_BLOCK; k += VN) {
		const vf iz = v_load(izrow + jb + k);
		m = v_max(m, v_sel(v_gt(iz, v_zero()), v_neg(iz), ninf));
	}
	return -v_hmax(m);
}

/* VN lanes of a block of phase a: columns x0, x0 + 4, ... (entries jb + h, ...). */
static void hbao_lanes(const struct dao_variant_setup *v, const struct dao_gtao_planes *pl,
		       float *ao, const struct hbao_phase *ph, const struct tile_step *tsteps,
		       int reach_r, int reach_c, float rp, int y, int jb, int h,
		       struct dao_tile_scratch *sc)
{
	const struct dao_gtao_setup *s = v->g;
	const int w = s->width, a = ph->a, x0 = 4 * (jb + h) + a, j = jb + h;
	float out[VN];
	int lanes = 0;
	while (lanes < VN && x0 + 4 * lanes < s->x_end)
		lanes++;
	struct tile_px t;
	struct px *p = &t.p;
	const vf one = v_set1(1.0f), zero = v_zero();
	t.y = y;
	t.h = s->height;
	t.w = w;
	t.x_first = x0;
	t.x_last = x0 + 4 * (VN - 1);
	const int inner = tsteps && y - reach_r >= 0 && y + reach_r < t.h && x0 - reach_c >= 0 &&
			  t.x_last + reach_c < t.w;
	p->x = v_fma(v_iota(), v_set1(4.0f), v_set1((float)x0));
	const vm in = v_lt(p->x, v_set1((float)s->x_end));
	const vf iz = v_sel(in, v_load(dao_gtao_phase_row(pl, y, a) + j), zero);
	const vm has_z = v_gt(iz, zero);
	p->Pz = v_sel(has_z, v_div(one, v_sel(has_z, iz, one)), zero);
	/* view_pos's (u ax + bx) and (v ay + by), for the pixel and its neighbours */
	t.X0 = v_add(v_mul(p->x, v_set1(s->ax)), v_set1(s->bx));
	const float y0f = (float)y * s->ay + s->by;
	t.Y0 = v_set1(y0f);
	t.Q = v_fma(t.X0, t.X0, v_fma(t.Y0, t.Y0, one));
	/* hbao_pixel's own radius decides whether it is searched at all */
	const vf r = v_mul(v_set1(s->search_radius * s->focal), iz);
	p->active = m_and(has_z, v_ge(r, one));
	vf vis = one;
	if (m_any(p->active)) {
		/* the MinDiff tangents: neighbours left and right (the phase before and
		 * after, one entry back or on at the phase's wrap), above and below
		 * (rows -1 and height of the plane hold no depth, as z_at) */
		const vf zl = hbao_depth(dao_gtao_phase_row(pl, y, (a + 3) & 3) + j + floor_div4(a - 1));
		const vf zr = hbao_depth(dao_gtao_phase_row(pl, y, (a + 1) & 3) + j + floor_div4(a + 1));
		const vf zu = hbao_depth(dao_gtao_phase_row(pl, y - 1, a) + j);
		const vf zd = hbao_depth(dao_gtao_phase_row(pl, y + 1, a) + j);
		const vf Xl = v_add(v_mul(v_sub(p->x, one), v_set1(s->ax)), v_set1(s->bx));
		const vf Xr = v_add(v_mul(v_add(p->x, one), v_set1(s->ax)), v_set1(s->bx));
		const vf Yu = v_set1((float)(y - 1) * s->ay + s->by);
		const vf Yd = v_set1((float)(y + 1) * s->ay + s->by);
		const vf P[3] = { v_mul(t.X0, p->Pz), v_mul(t.Y0, p->Pz), p->Pz };
		const vf Pl[3] = { v_mul(Xl, zl), v_mul(t.Y0, zl), zl };
		const vf Pr[3] = { v_mul(Xr, zr), v_mul(t.Y0, zr), zr };
		const vf Pu[3] = { v_mul(t.X0, zu), v_mul(Yu, zu), zu };
		const vf Pd[3] = { v_mul(t.X0, zd), v_mul(Yd, zd), zd };
		vf du[3], dv[3];
		hbao_min_diff(P, Pl, Pr, v_gt(zl, zero), v_gt(zr, zero), du);
		hbao_min_diff(P, Pu, Pd, v_gt(zu, zero), v_gt(zd, zero), dv);
		const float R = s->search_radius;
		const vf inv_r2 = v_set1(1.0f / (R * R));
		const float *base = dao_gtao_phase_row(pl, y, 0) + j;
		const int dirs = 2 * s->slices;
		vf occ = zero;
		for (int d = 0; d < dirs; d++) {
			const vf dx = v_set1(ph->dx[d]), dy = v_set1(ph->dy[d]);
			const vf Tx = v_add(v_mul(du[0], dx), v_mul(dv[0], dy));
			const vf Ty = v_add(v_mul(du[1], dx), v_mul(dv[1], dy));
			const vf Tz = v_add(v_mul(du[2], dx), v_mul(dv[2], dy));
			/* elevation towards the camera: tan t = -T.z / |T.xy|, plus the bias */
			const vf txy = v_sqrt(v_add(v_mul(Tx, Tx), v_mul(Ty, Ty)));
			const vm pos = v_gt(txy, zero);
			const vf tan_t = v_add(v_sel(pos, v_div(v_neg(Tz), v_sel(pos, txy, one)), zero),
					       v_set1(v->tan_bias));
			const vf sin_h = v_div(tan_t, v_sqrt(v_add(one, v_mul(tan_t, tan_t))));
			const struct tile_step *st;
			if (tsteps) {
				st = tsteps + (size_t)d * (size_t)s->steps;
			} else {
				hbao_dir_make(s, pl, ph, rp, d, sc->local);
				st = sc->local;
			}
			occ = v_add(occ, hbao_dir_any(&t, base, st, s->steps, sin_h, inv_r2, inner));
		}
		const vf o = v_div(v_mul(v_set1(v->strength), occ), v_set1((float)dirs));
		vis = v_sel(p->active, v_min(v_max(v_sub(one, o), zero), one), one);
	}
	v_store(out, v_sel(has_z, finish_lanes(s, vis), v_set1(s->invalid_value)));
	for (int k = 0; k < lanes; k++)
		ao[(size_t)y * w + (size_t)(x0 + 4 * k)] = out[k];
}

/* Rows [y0, y1), columns [x_begin, x_end) (x_begin a multiple of the block
 * span), by tile row as gtao_tile; sc: this thread's scratch. */
static void hbao_tile(const struct dao_variant_setup *v, const struct dao_gtao_planes *pl,
		      float *ao, int y0, int y1, struct dao_tile_scratch *sc)
{
	const struct dao_gtao_setup *s = v->g;
	struct hbao_phase ph[4];
	for (int cls = 0; cls < 4; cls++) {
		const int yc = y0 + ((cls - y0) & 3);
		if (yc >= y1)
			continue;
		for (int a = 0; a < 4; a++) {
			hbao_phase_init(s, a, yc, &ph[a]);
			tile_cache_reset(s, &sc->cache[a]);
		}
		for (int y = yc; y < y1; y += 4)
			for (int xb = s->x_begin; xb < s->x_end; xb += DAO_GTAO_BLOCK_SPAN)
				for (int a = 0; a < 4 && xb + a < s->x_end; a++) {
					const int jb = xb / 4;
					const float izmin = hbao_block_izmin(pl, y, a, jb);
					if (izmin == INFINITY) {
						tile_block_invalid(s, ao, y, xb + a);
						continue;
					}
					/* hbao_pixel's block radius: its farthest pixel's */
					const float rq = dao_gtao_quantize_radius(
						s->search_radius * s->focal * izmin);
					const float rp = rq < s->max_r_px ? rq : s->max_r_px;
					int reach_r = 0, reach_c = 0;
					const struct tile_step *tsteps = hbao_cache_get(
						s, pl, &ph[a], rp, &sc->cache[a], &reach_r, &reach_c);
					for (int h = 0; h < DAO_GTAO_BLOCK; h += VN)
						if (4 * (jb + h) + a < s->x_end)
							hbao_lanes(v, pl, ao, &ph[a], tsteps, reach_r,
								   reach_c, rp, y, jb, h, sc);
				}
	}
}

/* HBAO: the tile kernel with tile noise, the reference with any other. */
void DAO_ISA_FN(dao_hbao_simd)(const struct dao_variant_setup *v, const float *z,
			       const struct dao_gtao_planes *pl, const float *n, float *ao, int y0,
			       int y1, struct dao_tile_scratch *sc)
{
	if (v->g->noise != DAO_NOISE_TILE) {
		dao_hbao_ref(v, z, n, ao, y0, y1);
		return;
	}
	hbao_tile(v, pl, ao, y0, y1, sc);
}
