/* SPDX-License-Identifier: MIT */
/*
 * VBAO with tile noise (included by gtao_tile.inc.c): the visibility
 * bitmask of dao_vbao_ref (ao_variants.c, read that first) on the taps of
 * the GTAO tile kernel.  Per step the same two loads and depth-edge rule as
 * tile_sample; then instead of a horizon each lane marks the sectors between
 * the sample's front and its back, the point `thickness` further along the
 * sample's camera ray, in a 32-bit mask per lane and slice.
 *
 * In tile_sample's terms (D = z_s G, G = Gz U0 + (du, dv, 0)): the front's
 * cosine from V is (G.U0 / |G|) (-1 / |U0|); the back lies on the ray of
 * U = U0 + (du, dv, 0) at depth z_s + T / |U| (a distance T further along
 * it), so it is the same sample with 1 / z_b = iz / (1 + T iz / |U|) and
 * |U|^2 = Q + 2 B + du^2 + dv^2.  The falloff weighs |D| = |G| / iz.
 *
 * The sector a point falls in is round((t - lo) 32 / pi) with t = +-acos of
 * its cosine: a sample near a sector boundary that rounds differently from
 * the reference covers one sector more or less, so the cosines and the acos
 * are the precise ones (refined 1/sqrt, 8-term acos), not the estimates
 * the GTAO horizon makes do with.
 */

/* What VBAO adds to a tile kernel run (tile_lanes: NULL for GTAO). */
struct tile_vbao {
	float fall_mul, fall_add; /* the falloff weight saturate(|D| mul + add), 0 beyond
				   * vbao_radius */
	float fall_full;          /* ... 1 up to this |D| */
	float thickness; /* of every occluder, without a thickness plane */
	int plane;       /* the thickness from pl->thick, at the sample's taps */
};

/*
 * Per sector boundary k = 0 .. 32, at angle a_k = n - pi/2 + k pi/32 from V:
 * cos(2 k pi/32) / 4, sin(2 k pi/32) / 4 and k pi/32 - pi/2, so that
 * cos(2 a_k - n) = -(cos n cos(2 k pi/32) - sin n sin(2 k pi/32)) needs no
 * trigonometry per lane.
 */
static const float vbao_bound[DAO_VBAO_SECTORS + 1][3] = {
	{ 2.500000000e-01f, 0.000000000e+00f, -1.570796327e+00f },
	{ 2.451963201e-01f, 4.877258050e-02f, -1.472621556e+00f },
	{ 2.309698831e-01f, 9.567085809e-02f, -1.374446786e+00f },
	{ 2.078674031e-01f, 1.388925583e-01f, -1.276272016e+00f },
	{ 1.767766953e-01f, 1.767766953e-01f, -1.178097245e+00f },
	{ 1.388925583e-01f, 2.078674031e-01f, -1.079922475e+00f },
	{ 9.567085809e-02f, 2.309698831e-01f, -9.817477042e-01f },
	{ 4.877258050e-02f, 2.451963201e-01f, -8.835729338e-01f },
	{ 1.530808499e-17f, 2.500000000e-01f, -7.853981634e-01f },
	{ -4.877258050e-02f, 2.451963201e-01f, -6.872233930e-01f },
	{ -9.567085809e-02f, 2.309698831e-01f, -5.890486225e-01f },
	{ -1.388925583e-01f, 2.078674031e-01f, -4.908738521e-01f },
	{ -1.767766953e-01f, 1.767766953e-01f, -3.926990817e-01f },
	{ -2.078674031e-01f, 1.388925583e-01f, -2.945243113e-01f },
	{ -2.309698831e-01f, 9.567085809e-02f, -1.963495408e-01f },
	{ -2.451963201e-01f, 4.877258050e-02f, -9.817477042e-02f },
	{ -2.500000000e-01f, 3.061616998e-17f, 0.000000000e+00f },
	{ -2.451963201e-01f, -4.877258050e-02f, 9.817477042e-02f },
	{ -2.309698831e-01f, -9.567085809e-02f, 1.963495408e-01f },
	{ -2.078674031e-01f, -1.388925583e-01f, 2.945243113e-01f },
	{ -1.767766953e-01f, -1.767766953e-01f, 3.926990817e-01f },
	{ -1.388925583e-01f, -2.078674031e-01f, 4.908738521e-01f },
	{ -9.567085809e-02f, -2.309698831e-01f, 5.890486225e-01f },
	{ -4.877258050e-02f, -2.451963201e-01f, 6.872233930e-01f },
	{ -4.592425497e-17f, -2.500000000e-01f, 7.853981634e-01f },
	{ 4.877258050e-02f, -2.451963201e-01f, 8.835729338e-01f },
	{ 9.567085809e-02f, -2.309698831e-01f, 9.817477042e-01f },
	{ 1.388925583e-01f, -2.078674031e-01f, 1.079922475e+00f },
	{ 1.767766953e-01f, -1.767766953e-01f, 1.178097245e+00f },
	{ 2.078674031e-01f, -1.388925583e-01f, 1.276272016e+00f },
	{ 2.309698831e-01f, -9.567085809e-02f, 1.374446786e+00f },
	{ 2.451963201e-01f, -4.877258050e-02f, 1.472621556e+00f },
	{ 2.500000000e-01f, -6.123233996e-17f, 1.570796327e+00f },
};

/*
 * Per sector k: G(a_k+1) - G(a_k) = cos n P_k + sin n Q_k (G below), with
 * P_k = (cos(2 (k+1) pi/32) - cos(2 k pi/32)) / 4 and
 * Q_k = pi/64 - (sin(2 (k+1) pi/32) - sin(2 k pi/32)) / 4.
 */
static const float vbao_sector[DAO_VBAO_SECTORS][2] = {
	{ -4.803679899e-03f, 3.148047083e-04f },
	{ -1.422643697e-02f, 2.189107625e-03f },
	{ -2.310248005e-02f, 5.865685049e-03f },
	{ -3.109070778e-02f, 1.120324817e-02f },
	{ -3.788413704e-02f, 1.799667743e-02f },
	{ -4.322170016e-02f, 2.598490516e-02f },
	{ -4.689827759e-02f, 3.486094824e-02f },
	{ -4.877258050e-02f, 4.428370531e-02f },
	{ -4.877258050e-02f, 5.389106511e-02f },
	{ -4.689827759e-02f, 6.331382219e-02f },
	{ -4.322170016e-02f, 7.218986526e-02f },
	{ -3.788413704e-02f, 8.017809299e-02f },
	{ -3.109070778e-02f, 8.697152225e-02f },
	{ -2.310248005e-02f, 9.230908538e-02f },
	{ -1.422643697e-02f, 9.598566280e-02f },
	{ -4.803679899e-03f, 9.785996572e-02f },
	{ 4.803679899e-03f, 9.785996572e-02f },
	{ 1.422643697e-02f, 9.598566280e-02f },
	{ 2.310248005e-02f, 9.230908538e-02f },
	{ 3.109070778e-02f, 8.697152225e-02f },
	{ 3.788413704e-02f, 8.017809299e-02f },
	{ 4.322170016e-02f, 7.218986526e-02f },
	{ 4.689827759e-02f, 6.331382219e-02f },
	{ 4.877258050e-02f, 5.389106511e-02f },
	{ 4.877258050e-02f, 4.428370531e-02f },
	{ 4.689827759e-02f, 3.486094824e-02f },
	{ 4.322170016e-02f, 2.598490516e-02f },
	{ 3.788413704e-02f, 1.799667743e-02f },
	{ 3.109070778e-02f, 1.120324817e-02f },
	{ 2.310248005e-02f, 5.865685049e-03f },
	{ 1.422643697e-02f, 2.189107625e-03f },
	{ 4.803679899e-03f, 3.148047083e-04f },
};

/* 1 << k per sector k, loaded (and broadcast) rather than made per sector */
static const int32_t vbao_bit[DAO_VBAO_SECTORS] = {
	1 << 0,  1 << 1,  1 << 2,  1 << 3,  1 << 4,  1 << 5,  1 << 6,  1 << 7,
	1 << 8,  1 << 9,  1 << 10, 1 << 11, 1 << 12, 1 << 13, 1 << 14, 1 << 15,
	1 << 16, 1 << 17, 1 << 18, 1 << 19, 1 << 20, 1 << 21, 1 << 22, 1 << 23,
	1 << 24, 1 << 25, 1 << 26, 1 << 27, 1 << 28, 1 << 29, 1 << 30, INT32_MIN,
};

/*
 * The slice measure from 0 to boundary k (dao_vbao_ref's slice_measure in
 * closed form): G(t) = -cos(2t - n)/4 + t sin(n)/2 is the antiderivative of
 * cos(t - n) sin t, and below t = 0 the |sin t| of the slice's solid angle
 * flips its sign, so H(t) = G(t) for t >= 0 and 2 G(0) - G(t) below, with
 * G(0) = -cos(n)/4; a sector [a_k, a_k+1] measures H(a_k+1) - H(a_k).
 */
static inline vf vbao_h(const struct slice_v *g, vf half_sin, int k)
{
	const vf a = v_add(g->n, v_set1(vbao_bound[k][2]));
	const vf G = v_fma(g->cos_n, v_set1(vbao_bound[k][0]),
			   v_fma(a, half_sin, v_mul(g->sin_n, v_set1(-vbao_bound[k][1]))));
	return v_sel(v_ge(a, v_zero()), G, v_fnma(g->cos_n, v_set1(0.5f), v_neg(G)));
}

/* acos(x) = sqrt(1 - |x|) P(|x|) with P of degree 5 fitted for the least
 * largest error (6.7e-7 absolute; v_acos's degree 7 has 2e-8), the square
 * root from the refined hardware 1/sqrt (relative 3e-7) instead of the
 * divider, and acos(-x) = pi - acos(x) */
static inline vf vbao_acos(vf x)
{
	const vf ax = v_min(v_abs(x), v_set1(1.0f));
	vf p = v_set1(-4.910309333e-03f);
	p = v_fma(p, ax, v_set1(2.061796002e-02f));
	p = v_fma(p, ax, v_set1(-4.592540860e-02f));
	p = v_fma(p, ax, v_set1(8.817038685e-02f));
	p = v_fma(p, ax, v_set1(-2.145427167e-01f));
	p = v_fma(p, ax, v_set1(1.570795655e+00f));
	const vf s2 = v_sub(v_set1(1.0f), ax);
	const vm pos = v_gt(s2, v_zero());
	const vf r = v_keep(pos, v_mul(v_mul(s2, v_rsqrt(v_sel(pos, s2, v_set1(1.0f)))), p));
	return v_sel(v_lt(x, v_zero()), v_sub(v_set1(3.14159265358979f), r), r);
}

/*
 * One step of one side: the sectors [round(a), round(b)) (clamped to 0 .. 32)
 * between the sample's front and back, a and b in sector units (t - lo) 32/pi
 * (k_sgn = +-32/pi for the side, k_lo = -lo 32/pi, edge_at: the side's edge, 32
 * or 0); none where there is no sample or it lies beyond the radius.  Both
 * cosines move towards the edge's (low) by the falloff weight, as in
 * dao_vbao_ref.  ORed into *mask by the steps that mark something: the three
 * in four that exit early leave it alone (no OR and store of a zero).
 */
static inline __attribute__((always_inline)) void
vbao_sample(const struct tile_vbao *vb, const float *base, const uint16_t *tbase,
	    const struct tile_px *t, const struct tile_step *st, vf k_sgn, vf k_lo, vf low, vf thr,
	    vf thr_exit, const float edge_at, const int major_x, const int plane, vi *mask)
{
	const vf one = v_set1(1.0f), zero = v_zero();
	const struct px *p = &t->p;
	const struct tile_tap tp = tile_tap_read(base, st);
	const vf iz = tp.iz;
	vm ok = tp.ok;
	const vm edge = tp.edge;
	const vf du = major_x ? v_set1(st->ux_s) : v_sel(edge, v_set1(st->ux_e), v_set1(st->ux_s));
	const vf dv = major_x ? v_sel(edge, v_set1(st->vy_e), v_set1(st->vy_s)) : v_set1(st->vy_s);
	const vf c = v_sel(edge, v_set1(st->c_e), v_set1(st->c_s));
	const vf B = v_fma(t->X0, du, v_mul(t->Y0, dv));
	/* the front */
	const vf Gz = v_fnma(p->Pz, iz, one);
	const vf GU = v_fma(Gz, t->Q, B);
	const vf g2 = v_fma(Gz, v_add(GU, B), c);
	/* a step where no lane's front passes the test below marks nothing: told
	 * from the estimate of 1/sqrt (relative error below 4e-4, |cf0| <= 1)
	 * against thr less a margin, a superset of the lanes the test keeps, so
	 * that the branch, which mispredicts often, need not wait for the
	 * refinement (a step kept here and by no lane there marks nothing too);
	 * in tile_sample's units (thr_exit: (thr - 1e-3) nu, as nu < 0 the test
	 * flips), and with g2 as it is on lanes without a sample (there G = U,
	 * never 0) */
	if (!m_any(m_and(ok, v_lt(v_mul(GU, v_rsqrt_fast(g2)), thr_exit))))
		return;
	const vf g2s = v_sel(ok, g2, one);
	const vf rg = v_rsqrt(g2s);
	const vf cf0 = v_mul(v_mul(GU, rg), t->inu);
	/* seen from P, the points of the sample's camera ray sweep away from V
	 * monotonically, so its back lies further from V than its front: a front
	 * within half a sector of the hemisphere's edge or below marks nothing
	 * (thr: that edge's cosine, lowered by a margin), nor does it once the
	 * falloff has moved it further towards the edge */
	ok = m_and(ok, v_gt(cf0, thr));
	/* the falloff weight of |D| = |G| / iz (0 beyond vbao_radius: no sample),
	 * with the refined 1/iz (the estimate's 3.7e-4 moves sector ends); only
	 * where some lane lies beyond fall_full (most steps lie within it) */
	const vf Fiz = v_mul(v_set1(vb->fall_full), iz);
	const int weigh = m_any(m_and(ok, v_gt(g2, v_mul(Fiz, Fiz))));
	vf wgt = one, cf = cf0;
	if (weigh) {
		const vf len = v_mul(v_mul(g2, rg), v_rcp(v_sel(ok, iz, one)));
		wgt = v_min(v_max(v_fma(len, v_set1(vb->fall_mul), v_set1(vb->fall_add)), zero), one);
		ok = m_and(ok, v_gt(wgt, zero));
		if (!m_any(ok))
			return;
		cf = v_fma(v_sub(cf0, low), wgt, low);
	}
	/* the back, `T` further: the thickness at the same taps, the same way (read
	 * only here, by the steps that passed the exits above) */
	const vf T = plane ? tile_tap_follow(tbase, st, &tp) : v_set1(vb->thickness);
	const vf U2 = v_add(v_add(t->Q, c), v_add(B, B));
	const vf k = v_mul(v_mul(T, iz), v_rsqrt(U2));
	const vf izb = v_mul(iz, v_rcp(v_add(one, k)));
	const vf Gzb = v_fnma(p->Pz, izb, one);
	const vf GUb = v_fma(Gzb, t->Q, B);
	const vf g2b = v_fma(Gzb, v_add(GUb, B), c);
	const vf cb0 = v_mul(v_mul(GUb, v_rsqrt(v_sel(ok, g2b, one))), t->inu);
	const vf cb = weigh ? v_fma(v_sub(cb0, low), wgt, low) : cb0;
	const vf af = v_fma(vbao_acos(cf), k_sgn, k_lo);
	/* a back within half a sector of the edge or beyond it (thr, as the front's
	 * test) is at the edge once rounded: its acos only where some lane's is not */
	const vf ab = m_any(m_andnot(ok, v_le(cb, thr))) ? v_fma(vbao_acos(cb), k_sgn, k_lo)
							  : v_set1(edge_at);
	/* rounded, so a sample exactly on the hemisphere's edge (a plane) marks nothing
	 * (clamped to whole bounds before the rounding: the same as after) */
	const vf top = v_set1((float)DAO_VBAO_SECTORS);
	const vi a = vi_from_nearest(v_min(v_max(v_min(af, ab), zero), top));
	const vi b = vi_from_nearest(v_min(v_max(v_max(af, ab), zero), top));
	*mask = vi_or(*mask, vi_keep(ok, vi_andnot(vi_low_bits(b), vi_low_bits(a))));
}

/* The sectors both sides of a slice occlude, per lane. */
static inline __attribute__((always_inline)) vi
vbao_sides(const struct tile_vbao *vb, const struct dao_gtao_setup *s, const float *base,
	   const uint16_t *tbase, const struct tile_px *t, const struct tile_step *st,
	   const struct slice_v *g, const int major_x, const int check, const int chk_p,
	   const int chk_n, const int plane)
{
	const float k32 = (float)DAO_VBAO_SECTORS / DAO_PI_F;
	/* lo = n - pi/2: sector 0 starts at the hemisphere's edge */
	const vf k_lo = v_fnma(g->n, v_set1(k32), v_set1(0.5f * (float)DAO_VBAO_SECTORS));
	const vf kp = v_set1(k32), kn = v_set1(-k32);
	/* the cosines of the edges, n + pi/2 and n - pi/2 */
	const vf low_p = v_neg(g->sin_n), low_n = g->sin_n;
	/* the cosines of the angles half a sector above the edges, n + pi/2 - d/2 and
	 * n - pi/2 + d/2 (d = pi/32), less 1e-3 of margin; no skipping where the
	 * normal is within 3 degrees of perpendicular to V, where the angles leave
	 * [0, pi] (no such lanes with normals that face the camera) */
	const float ch = cosf(0.5f * DAO_PI_F / (float)DAO_VBAO_SECTORS);
	const float sh = sinf(0.5f * DAO_PI_F / (float)DAO_VBAO_SECTORS);
	const vm facing = v_gt(g->cos_n, v_set1(0.05f));
	const vf margin = v_set1(1e-3f), never = v_set1(-2.0f);
	const vf thr_p = v_sel(facing, v_sub(v_fnma(g->sin_n, v_set1(ch), v_mul(g->cos_n, v_set1(sh))),
					    margin), never);
	const vf thr_n = v_sel(facing, v_sub(v_fma(g->sin_n, v_set1(ch), v_mul(g->cos_n, v_set1(sh))),
					    margin), never);
	const vf exit_p = v_mul(v_sub(thr_p, margin), t->nu);
	const vf exit_n = v_mul(v_sub(thr_n, margin), t->nu);
	const struct tile_step *sn = st + s->steps;
	vi mask = vi_set1(0);
	for (int i = 0; i < s->steps; i++) {
		if (!check || !chk_p || !tile_skip(t, &st[i]))
			vbao_sample(vb, base, tbase, t, &st[i], kp, k_lo, low_p, thr_p, exit_p,
				    (float)DAO_VBAO_SECTORS, major_x, plane, &mask);
		if (!check || !chk_n || !tile_skip(t, &sn[i]))
			vbao_sample(vb, base, tbase, t, &sn[i], kn, k_lo, low_n, thr_n, exit_n, 0.0f,
				    major_x, plane, &mask);
	}
	return mask;
}

/* vbao_sides specialised on the major axis, the bounds test and the plane;
 * chk_p, chk_n: whether a step of the positive, the negative side may have to
 * be skipped (tile_side_checks). */
static vi vbao_sides_any(const struct tile_vbao *vb, const struct dao_gtao_setup *s,
			 const float *base, const uint16_t *tbase, const struct tile_px *t,
			 const struct tile_step *st, const struct slice_v *g, int major_x, int chk_p,
			 int chk_n)
{
	const int inner = !chk_p && !chk_n;
#define VBAO_SIDES(mx, check, plane) \
	vbao_sides(vb, s, base, tbase, t, st, g, mx, check, chk_p, chk_n, plane)
	/* tests, not a switch: its table jump alternated between the cases with
	 * the slices' major axes and mispredicted */
	if (vb->plane) {
		if (major_x)
			return inner ? VBAO_SIDES(1, 0, 1) : VBAO_SIDES(1, 1, 1);
		return inner ? VBAO_SIDES(0, 0, 1) : VBAO_SIDES(0, 1, 1);
	}
	if (major_x)
		return inner ? VBAO_SIDES(1, 0, 0) : VBAO_SIDES(1, 1, 0);
	return inner ? VBAO_SIDES(0, 0, 0) : VBAO_SIDES(0, 1, 0);
#undef VBAO_SIDES
}

/*
 * Adds one slice's open measure (all sectors but those in `mask`) and its
 * whole measure, weighted by lpn, to *vis and *norm, as dao_vbao_ref sums
 * them.  A sector below t = 0 measures -(G(a_k+1) - G(a_k)), one above
 * +(G(a_k+1) - G(a_k)) = cos n P_k + sin n Q_k, so the occluded ones add up
 * as sums of the constants P_k, Q_k over the lanes' bits, visiting only the
 * sectors some lane occludes; the one sector across t = 0 (around V, which
 * is rarely occluded) takes H from its ends.
 */
static inline void vbao_accumulate(const struct slice_v *g, vi mask, vf *vis, vf *norm)
{
	const vf zero = v_zero(), half_sin = v_mul(g->sin_n, v_set1(0.5f));
	const vf all = v_sub(vbao_h(g, half_sin, DAO_VBAO_SECTORS), vbao_h(g, half_sin, 0));
	if (!vi_any(mask)) { /* no lane occluded (about half the slices): all - 0 */
		const vf w = v_keep(g->ok, v_mul(g->lpn, all));
		*vis = v_add(*vis, w);
		*norm = v_add(*norm, w);
		return;
	}
	const float k32 = (float)DAO_VBAO_SECTORS / DAO_PI_F;
	/* the sector across t = 0: a_k0 <= 0 < a_k0+1, k0 = floor((pi/2 - n) 32/pi) */
	const vf k0 = v_min(v_max(v_floor(v_fnma(g->n, v_set1(k32),
						   v_set1(0.5f * (float)DAO_VBAO_SECTORS))),
				  v_set1(-1.0f)), v_set1((float)DAO_VBAO_SECTORS));
	const vi below = vi_low_bits(vi_from_whole(v_max(k0, zero)));
	const vi upto = vi_low_bits(vi_from_whole(v_min(v_add(k0, v_set1(1.0f)),
							v_set1((float)DAO_VBAO_SECTORS))));
	const vi neg = vi_andnot(mask, vi_andnot(vi_set1(-1), below)); /* mask & below */
	const vi pos = vi_andnot(mask, upto);
	const vi across = vi_andnot(vi_andnot(mask, vi_andnot(vi_set1(-1), upto)), below);
	/* the sectors above t = 0 and those below in loops of their own: few
	 * sectors are above in one lane and below in another */
	vf pp = zero, qp = zero, pn = zero, qn = zero;
	for (uint32_t any = vi_hor(pos); any; any &= any - 1) {
		const int k = __builtin_ctz(any);
		const vm m = m_bit(pos, vbao_bit[k]);
		pp = v_add(pp, v_keep(m, v_set1(vbao_sector[k][0])));
		qp = v_add(qp, v_keep(m, v_set1(vbao_sector[k][1])));
	}
	for (uint32_t any = vi_hor(neg); any; any &= any - 1) {
		const int k = __builtin_ctz(any);
		const vm m = m_bit(neg, vbao_bit[k]);
		pn = v_add(pn, v_keep(m, v_set1(vbao_sector[k][0])));
		qn = v_add(qn, v_keep(m, v_set1(vbao_sector[k][1])));
	}
	vf occ = v_fma(g->cos_n, v_sub(pp, pn), v_mul(g->sin_n, v_sub(qp, qn)));
	const vm has = m_nonzero(across);
	if (m_any(has)) {
		/* H(a_k0+1) - H(a_k0) = G(a_k0+1) + G(a_k0) + cos(n)/2, G(t) = -cos(2t - n)/4 + t sin(n)/2 */
		const vf a0 = v_add(g->n, v_fma(k0, v_set1(DAO_PI_F / (float)DAO_VBAO_SECTORS),
						  v_set1(-DAO_HALF_PI_F)));
		const vf a1 = v_add(a0, v_set1(DAO_PI_F / (float)DAO_VBAO_SECTORS));
		vf s0, c0, s1, c1;
		v_sincos(v_fnma(v_set1(-2.0f), a0, v_neg(g->n)), &s0, &c0);
		v_sincos(v_fnma(v_set1(-2.0f), a1, v_neg(g->n)), &s1, &c1);
		const vf G0 = v_fma(a0, half_sin, v_mul(v_set1(-0.25f), c0));
		const vf G1 = v_fma(a1, half_sin, v_mul(v_set1(-0.25f), c1));
		const vf w = v_fma(g->cos_n, v_set1(0.5f), v_add(G0, G1));
		occ = v_add(occ, v_keep(has, w));
	}
	*vis = v_add(*vis, v_keep(g->ok, v_mul(g->lpn, v_sub(all, occ))));
	*norm = v_add(*norm, v_keep(g->ok, v_mul(g->lpn, all)));
}
