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
	float fall_out;           /* ... 0 beyond this |D| (vbao_radius and a margin) */
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
 * A slice's steps in two passes: the first (vbao_front, every step) reads the
 * taps and tells whether some lane's front may mark a sector, without a
 * branch; the second (vbao_back) works out the fronts and backs of the steps
 * kept (about three in ten), one after the other.  tile_lanes runs a slice's
 * first pass before the previous slice's second (vbao_pipe), so that the
 * loads of the one overlap the arithmetic and the mispredicted branches of
 * the other.
 */

/* What the first pass keeps of a step for the second. */
struct vbao_front {
	struct tile_tap tp;
	vf B, c, GU, g2; /* tile_sample's terms */
};

/*
 * The first pass over a step of one side: its taps and the front's terms
 * into *o, and whether some lane's front may mark a sector.  A step where no
 * lane's front passes the test below marks nothing: told from the estimate of
 * 1/sqrt (relative error below 4e-4, |cf0| <= 1) against thr less a margin, a
 * superset of the lanes vbao_back keeps (a step kept here and by no lane there
 * marks nothing too); in tile_sample's units (thr_exit: (thr - 1e-3) nu, as
 * nu < 0 the test flips), and with g2 as it is on lanes without a sample
 * (there G = U, never 0).  Nor does a lane whose |D| = |G| / iz lies beyond
 * `out` (vbao_radius and a margin of 1e-3 of it: weight 0 in vbao_back), which
 * leaves a third of the steps kept without it to the first pass.
 */
static inline __attribute__((always_inline)) uint32_t
vbao_front(const float *base, const struct tile_px *t, const struct tile_step *st, vf thr_exit,
	   vf out, const int major_x, struct vbao_front *o)
{
	const vf one = v_set1(1.0f);
	const struct px *p = &t->p;
	const struct tile_tap tp = tile_tap_read(base, st);
	/* the line the next block of this tile phase (VN entries on, read a few
	 * blocks later) adds to these taps: each load moves along by VN entries
	 * from block to block, which the hardware's prefetchers do not follow
	 * (one address per step and slice from the same instructions) */
	__builtin_prefetch(base + st->o0 + 2 * VN - 1);
	__builtin_prefetch(base + st->o1 + 2 * VN - 1);
	const vm edge = tp.edge;
	const vf du = major_x ? v_set1(st->ux_s) : v_sel(edge, v_set1(st->ux_e), v_set1(st->ux_s));
	const vf dv = major_x ? v_sel(edge, v_set1(st->vy_e), v_set1(st->vy_s)) : v_set1(st->vy_s);
	const vf c = v_sel(edge, v_set1(st->c_e), v_set1(st->c_s));
	const vf B = v_fma(t->X0, du, v_mul(t->Y0, dv));
	const vf Gz = v_fnma(p->Pz, tp.iz, one);
	const vf GU = v_fma(Gz, t->Q, B);
	const vf g2 = v_fma(Gz, v_add(GU, B), c);
	o->tp = tp;
	o->B = B;
	o->c = c;
	o->GU = GU;
	o->g2 = g2;
	const vf r = v_mul(out, tp.iz);
	return (uint32_t)m_any(m_and(m_and(tp.ok, v_lt(g2, v_mul(r, r))),
				     v_lt(v_mul(GU, v_rsqrt_fast(g2)), thr_exit)));
}

/*
 * The rest of a step the first pass kept (f: its terms): the sectors
 * [round(a), round(b)) (clamped to 0 .. 32) between the sample's front and
 * back, a and b in sector units (t - lo) 32/pi (k_sgn = +-32/pi for the side,
 * k_lo = -lo 32/pi, edge_at: the side's edge, 32 or 0); none where there is no
 * sample or it lies beyond the radius.  Both cosines move towards the edge's
 * (low) by the falloff weight, as in dao_vbao_ref.  ORed into *mask.
 */
static inline __attribute__((always_inline)) void
vbao_back(const struct tile_vbao *vb, const uint16_t *tbase, const struct tile_px *t,
	  const struct tile_step *st, const struct vbao_front *f, vf k_sgn, vf k_lo, vf low,
	  vf thr, const float edge_at, const int plane, vi *mask)
{
	const vf one = v_set1(1.0f), zero = v_zero();
	const struct px *p = &t->p;
	const vf iz = f->tp.iz, B = f->B, c = f->c, GU = f->GU, g2 = f->g2;
	vm ok = f->tp.ok;
	/* the thickness at the same taps, the same way, read first, before the
	 * branches below */
	const vf T = plane ? tile_tap_follow(tbase, st, &f->tp) : v_set1(vb->thickness);
	if (plane) { /* the next block's, as vbao_front's (it keeps much the same steps) */
		__builtin_prefetch(tbase + st->o0 + 2 * VN - 1);
		__builtin_prefetch(tbase + st->o1 + 2 * VN - 1);
	}
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
	/* the back, `T` further */
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

/* steps per side the first pass takes at a time (the default preset's 6 in one) */
#define VBAO_CHUNK 8

/* A slice's constants of both sides' steps ([0]: the positive side, [1]: the negative). */
struct vbao_slice {
	vf k_lo;   /* -lo 32/pi, lo = n - pi/2: sector 0 starts at the hemisphere's edge */
	vf low[2]; /* the cosines of the edges, n + pi/2 and n - pi/2 */
	vf thr[2]; /* the fronts' and backs' test (vbao_back) */
	vf out[2]; /* the first pass's test (vbao_front) */
};

static inline __attribute__((always_inline)) void
vbao_slice_make(const struct tile_px *t, const struct slice_v *g, struct vbao_slice *c)
{
	const float k32 = (float)DAO_VBAO_SECTORS / DAO_PI_F;
	c->k_lo = v_fnma(g->n, v_set1(k32), v_set1(0.5f * (float)DAO_VBAO_SECTORS));
	c->low[0] = v_neg(g->sin_n);
	c->low[1] = g->sin_n;
	/* the cosines of the angles half a sector above the edges, n + pi/2 - d/2 and
	 * n - pi/2 + d/2 (d = pi/32), less 1e-3 of margin; no skipping where the
	 * normal is within 3 degrees of perpendicular to V, where the angles leave
	 * [0, pi] (no such lanes with normals that face the camera) */
	const float ch = cosf(0.5f * DAO_PI_F / (float)DAO_VBAO_SECTORS);
	const float sh = sinf(0.5f * DAO_PI_F / (float)DAO_VBAO_SECTORS);
	const vm facing = v_gt(g->cos_n, v_set1(0.05f));
	const vf margin = v_set1(1e-3f), never = v_set1(-2.0f);
	c->thr[0] = v_sel(facing, v_sub(v_fnma(g->sin_n, v_set1(ch), v_mul(g->cos_n, v_set1(sh))),
				       margin), never);
	c->thr[1] = v_sel(facing, v_sub(v_fma(g->sin_n, v_set1(ch), v_mul(g->cos_n, v_set1(sh))),
				       margin), never);
	c->out[0] = v_mul(v_sub(c->thr[0], margin), t->nu);
	c->out[1] = v_mul(v_sub(c->thr[1], margin), t->nu);
}

/*
 * The first pass over steps i0 .. i0 + n - 1 (n <= VBAO_CHUNK) of both sides
 * of a slice (st: its steps): into fr[2 j] the positive side's step i0 + j,
 * into fr[2 j + 1] the negative side's; bit 2 j, 2 j + 1 of the result where
 * some lane's front may mark a sector.
 */
static inline __attribute__((always_inline)) uint32_t
vbao_fronts(const struct tile_vbao *vb, const struct dao_gtao_setup *s, const float *base,
	    const struct tile_px *t, const struct tile_step *st, const struct vbao_slice *c,
	    int i0, int n, const int major_x, const int check, const int chk_p, const int chk_n,
	    struct vbao_front *fr)
{
	const struct tile_step *sn = st + s->steps;
	const vf out = v_set1(vb->fall_out);
	uint32_t keep = 0;
	for (int j = 0; j < n; j++) {
		const int i = i0 + j;
		if (!check || !chk_p || !tile_skip(t, &st[i]))
			keep |= vbao_front(base, t, &st[i], c->out[0], out, major_x, &fr[2 * j]) << (2 * j);
		if (!check || !chk_n || !tile_skip(t, &sn[i]))
			keep |= vbao_front(base, t, &sn[i], c->out[1], out, major_x, &fr[2 * j + 1])
				<< (2 * j + 1);
	}
	return keep;
}

/* The second pass over the steps the first kept (keep, fr: vbao_fronts' for
 * steps from i0), their sectors ORed into mask. */
static inline __attribute__((always_inline)) vi
vbao_backs(const struct tile_vbao *vb, const struct dao_gtao_setup *s, const uint16_t *tbase,
	   const struct tile_px *t, const struct tile_step *st, const struct vbao_slice *c, int i0,
	   uint32_t keep, const struct vbao_front *fr, vi mask, const int plane)
{
	const struct tile_step *sn = st + s->steps;
	const float k32 = (float)DAO_VBAO_SECTORS / DAO_PI_F;
	const vf kp = v_set1(k32), kn = v_set1(-k32);
	for (uint32_t pos = keep & 0x55555555u; pos; pos &= pos - 1) {
		const int b = __builtin_ctz(pos);
		vbao_back(vb, tbase, t, &st[i0 + b / 2], &fr[b], kp, c->k_lo, c->low[0], c->thr[0],
			  (float)DAO_VBAO_SECTORS, plane, &mask);
	}
	for (uint32_t neg = keep & 0xaaaaaaaau; neg; neg &= neg - 1) {
		const int b = __builtin_ctz(neg);
		vbao_back(vb, tbase, t, &sn[i0 + b / 2], &fr[b], kn, c->k_lo, c->low[1], c->thr[1],
			  0.0f, plane, &mask);
	}
	return mask;
}

/* vbao_fronts specialised on the major axis and the bounds test; chk_p, chk_n:
 * whether a step of the positive, the negative side may have to be skipped
 * (tile_side_checks). */
static uint32_t vbao_fronts_any(const struct tile_vbao *vb, const struct dao_gtao_setup *s,
				const float *base, const struct tile_px *t,
				const struct tile_step *st, const struct vbao_slice *c, int i0, int n,
				int major_x, int chk_p, int chk_n, struct vbao_front *fr)
{
	/* tests, not a switch: its table jump alternated between the cases with
	 * the slices' major axes and mispredicted */
	if (!chk_p && !chk_n)
		return major_x ? vbao_fronts(vb, s, base, t, st, c, i0, n, 1, 0, 0, 0, fr)
			       : vbao_fronts(vb, s, base, t, st, c, i0, n, 0, 0, 0, 0, fr);
	return major_x ? vbao_fronts(vb, s, base, t, st, c, i0, n, 1, 1, chk_p, chk_n, fr)
		       : vbao_fronts(vb, s, base, t, st, c, i0, n, 0, 1, chk_p, chk_n, fr);
}

/* vbao_backs specialised on the plane */
static vi vbao_backs_any(const struct tile_vbao *vb, const struct dao_gtao_setup *s,
			 const uint16_t *tbase, const struct tile_px *t, const struct tile_step *st,
			 const struct vbao_slice *c, int i0, uint32_t keep,
			 const struct vbao_front *fr, vi mask)
{
	return vb->plane ? vbao_backs(vb, s, tbase, t, st, c, i0, keep, fr, mask, 1)
			 : vbao_backs(vb, s, tbase, t, st, c, i0, keep, fr, mask, 0);
}

/* Two slices in flight (tile_lanes; tile_row keeps the room): slice k's
 * first pass in [k & 1], its second run after the next slice's first. */
struct vbao_pipe {
	int n; /* slices whose first pass ran */
	struct slice_v g[2];
	struct vbao_slice c[2];
	const struct tile_step *st[2];
	uint32_t keep[2];
	struct vbao_front fr[2][2 * VBAO_CHUNK];
};

/* The second pass of the slice in vp's [q], added to *vis, *norm. */
static void vbao_pipe_back(const struct tile_vbao *vb, const struct dao_gtao_setup *s,
			   const uint16_t *tbase, const struct tile_px *t,
			   const struct vbao_pipe *vp, int q, vf *vis, vf *norm);

/* A slice's first pass, then the previous slice's second (vbao_pipe_back):
 * the loads of the one overlap the arithmetic of the other.  Calls, not
 * inline: tile_lanes' loop stays as GTAO's code needs it. */
static __attribute__((noinline)) void
vbao_pipe_slice(const struct tile_vbao *vb, const struct dao_gtao_setup *s, const float *base,
		const uint16_t *tbase, const struct tile_px *t, const struct tile_step *st,
		const struct slice_v *g, int major_x, int chk_p, int chk_n, struct vbao_pipe *vp,
		vf *vis, vf *norm)
{
	const int q = vp->n & 1;
	vp->g[q] = *g;
	vp->st[q] = st;
	vbao_slice_make(t, g, &vp->c[q]);
	vp->keep[q] = vbao_fronts_any(vb, s, base, t, st, &vp->c[q], 0, s->steps, major_x, chk_p,
				      chk_n, vp->fr[q]);
	if (vp->n++)
		vbao_pipe_back(vb, s, tbase, t, vp, 1 - q, vis, norm);
}

/* The sectors both sides of a slice occlude, per lane, chunk by chunk of steps. */
static vi vbao_sides_any(const struct tile_vbao *vb, const struct dao_gtao_setup *s,
			 const float *base, const uint16_t *tbase, const struct tile_px *t,
			 const struct tile_step *st, const struct slice_v *g, int major_x, int chk_p,
			 int chk_n)
{
	struct vbao_slice c;
	vbao_slice_make(t, g, &c);
	struct vbao_front fr[2 * VBAO_CHUNK];
	vi mask = vi_set1(0);
	for (int i0 = 0; i0 < s->steps; i0 += VBAO_CHUNK) {
		const int n = s->steps - i0 < VBAO_CHUNK ? s->steps - i0 : VBAO_CHUNK;
		const uint32_t keep =
			vbao_fronts_any(vb, s, base, t, st, &c, i0, n, major_x, chk_p, chk_n, fr);
		mask = vbao_backs_any(vb, s, tbase, t, st, &c, i0, keep, fr, mask);
	}
	return mask;
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

static __attribute__((noinline)) void
vbao_pipe_back(const struct tile_vbao *vb, const struct dao_gtao_setup *s, const uint16_t *tbase,
	       const struct tile_px *t, const struct vbao_pipe *vp, int q, vf *vis, vf *norm)
{
	const vi mask = vbao_backs_any(vb, s, tbase, t, vp->st[q], &vp->c[q], 0, vp->keep[q],
				       vp->fr[q], vi_set1(0));
	vbao_accumulate(&vp->g[q], mask, vis, norm);
}
