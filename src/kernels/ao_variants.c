/* SPDX-License-Identifier: MIT */
/*
 * HBAO, SSAO and eye-dome lighting (README.md, "Algorithms").
 */
#include "kernels/ao_variants.h"

#include <math.h>
#include <stddef.h>

#include "core/half.h"
#include "core/math_util.h"
#include "kernels/gtao_sample.h"
#include "kernels/gtao_slice.h"

static inline void view_pos(const struct dao_gtao_setup *s, float u, float v, float z, float P[3])
{
	P[0] = (u * s->ax + s->bx) * z;
	P[1] = (v * s->ay + s->by) * z;
	P[2] = z;
}

/* Van der Corput radical inverse in base 2 (for the SSAO kernel's points). */
static float radical_inverse2(unsigned i)
{
	float r = 0.0f, f = 0.5f;
	for (; i; i >>= 1, f *= 0.5f)
		if (i & 1)
			r += f;
	return r;
}

void dao_variant_setup_init(struct dao_variant_setup *v, const struct dao_gtao_setup *g,
			    const struct dao_params *p)
{
	v->g = g;
	v->strength = p->strength;
	v->tan_bias = tanf(p->hbao_bias * DAO_PI_F / 180.0f);
	v->ssao_min = p->ssao_min;
	v->ssao_max = p->ssao_max;
	v->edl_radius = p->edl_radius;
	v->vbao_thickness = p->vbao_thickness;
	{
		/* GTAO's band is R_eff (1 -+ falloff / 2) (dao_gtao_setup_init) */
		const float R = dao_gtao_effective_radius(p->radius, p->steps);
		const float half = 0.5f * DAO_VBAO_FALLOFF_SHARE * p->falloff * R;
		v->vbao_radius = R + half;
		if (half > 0.0f) {
			v->vbao_fall_mul = -1.0f / (2.0f * half);
			v->vbao_fall_add = (R + half) / (2.0f * half);
		} else { /* hard cut at R */
			v->vbao_fall_mul = -1e30f;
			v->vbao_fall_add = R * 1e30f;
		}
	}
	v->thickness = NULL;
	int n = 2 * p->slices * p->steps;
	v->ssao_samples = n > DAO_SSAO_MAX_SAMPLES ? DAO_SSAO_MAX_SAMPLES : n;
	/* Hammersley points on the hemisphere (z up), pushed inside it with the
	 * classic scale lerp(0.1, 1, (i/N)^2) so most land near the centre (seed 004) */
	for (int i = 0; i < v->ssao_samples; i++) {
		float u = ((float)i + 0.5f) / (float)v->ssao_samples, w = radical_inverse2((unsigned)i);
		float cz = u, sz = sqrtf(1.0f - cz * cz), phi = 2.0f * DAO_PI_F * w;
		float t = (float)i / (float)v->ssao_samples;
		float scale = 0.1f + 0.9f * t * t;
		v->ssao_kernel[i][0] = cosf(phi) * sz * scale;
		v->ssao_kernel[i][1] = sinf(phi) * sz * scale;
		v->ssao_kernel[i][2] = cz * scale;
	}
}

static float z_at(const struct dao_gtao_setup *s, const float *z, int x, int y)
{
	if (x < 0 || y < 0 || x >= s->width || y >= s->height)
		return 0.0f;
	return z[(size_t)y * s->width + x];
}

/* MinDiff tangent (seed 003): of the two one-sided differences, the shorter. */
static void min_diff(const float P[3], const float Pl[3], const float Pr[3], int have_l,
		     int have_r, float T[3])
{
	float dl[3] = {P[0] - Pl[0], P[1] - Pl[1], P[2] - Pl[2]};
	float dr[3] = {Pr[0] - P[0], Pr[1] - P[1], Pr[2] - P[2]};
	const float *d = !have_l ? dr : !have_r ? dl : dao_dot3(dl, dl) < dao_dot3(dr, dr) ? dl : dr;
	T[0] = d[0], T[1] = d[1], T[2] = d[2];
}

/*
 * The smallest 1/z with depth of the block of pixel (x, y) (dao_gtao_block_izmax's
 * block, 1/z as the kernels store it).  HBAO's blocks search the radius of
 * their farthest pixel: a step beyond a pixel's own radius samples nothing
 * (r >= 1), so a block searching its nearest pixel's radius (GTAO's choice,
 * where the highest horizon needs the full reach) leaves the others few
 * samples -- at a wall rising towards the camera beside a floor, most of them
 * -- while one short of it misses only the far end, where W(r) = 1 - r^2 is
 * small.
 */
static float hbao_block_izmin(const struct dao_gtao_setup *s, const float *z, int x, int y)
{
	const int x0 = (x & ~(DAO_GTAO_BLOCK_SPAN - 1)) + (x & 3);
	float izmin = INFINITY;
	for (int k = 0; k < DAO_GTAO_BLOCK && x0 + 4 * k < s->width; k++) {
		const float zz = z[(size_t)y * s->width + x0 + 4 * k];
		if (zz > 0.0f && 1.0f / zz < izmin)
			izmin = 1.0f / zz;
	}
	return izmin;
}

/*
 * HBAO (Bavoil, Sainz, Dimitrov 2008): per direction, the elevation above the
 * image plane of the biased tangent starts the horizon; each sample above it
 * adds W(r) (sin h - sin h_prev), W(r) = 1 - r^2, r = |S - P| / R.
 */
static float hbao_pixel(const struct dao_variant_setup *v, const float *z, int x, int y)
{
	const struct dao_gtao_setup *s = v->g;
	const float zc = z[(size_t)y * s->width + x];
	float P[3], Q[3], Pl[3], Pr[3], Pu[3], Pd[3];
	view_pos(s, (float)x, (float)y, zc, P);
	float zl = z_at(s, z, x - 1, y), zr = z_at(s, z, x + 1, y);
	float zu = z_at(s, z, x, y - 1), zd = z_at(s, z, x, y + 1);
	view_pos(s, (float)x - 1, (float)y, zl, Pl);
	view_pos(s, (float)x + 1, (float)y, zr, Pr);
	view_pos(s, (float)x, (float)y - 1, zu, Pu);
	view_pos(s, (float)x, (float)y + 1, zd, Pd);
	float dPdu[3], dPdv[3];
	min_diff(P, Pl, Pr, zl > 0, zr > 0, dPdu);
	min_diff(P, Pu, Pd, zu > 0, zd > 0, dPdv);

	const float R = s->search_radius;
	float r_px = R * s->focal / zc;
	if (r_px < 1.0f)
		return 1.0f;
	/* with tile noise the block's radius (the SIMD kernel's taps): unlike GTAO's
	 * the smallest of its pixels' (the farthest depth), on the grid */
	if (s->noise == DAO_NOISE_TILE)
		r_px = dao_gtao_quantize_radius(s->search_radius * s->focal *
						hbao_block_izmin(s, z, x, y));
	r_px = fminf(r_px, s->max_r_px);
	float n0, n1;
	dao_gtao_noise(s, x, y, &n0, &n1);
	const int dirs = 2 * s->slices; /* directions over the full circle */
	float occ = 0.0f;
	for (int d = 0; d < dirs; d++) {
		float phi = 2.0f * DAO_PI_F * ((float)d + n0) / (float)dirs;
		float dx = cosf(phi), dy = sinf(phi);
		float T[3] = {dPdu[0] * dx + dPdv[0] * dy, dPdu[1] * dx + dPdv[1] * dy,
			      dPdu[2] * dx + dPdv[2] * dy};
		/* elevation towards the camera (-z): tan t = -T.z / |T.xy|, plus the bias */
		float txy = sqrtf(T[0] * T[0] + T[1] * T[1]);
		float tan_t = (txy > 0 ? -T[2] / txy : 0.0f) + v->tan_bias;
		float sin_h = tan_t / sqrtf(1.0f + tan_t * tan_t);
		float ao_d = 0.0f;
		for (int i = 0; i < s->steps; i++) {
			float dist = 1.0f + ((float)i + n1) / (float)s->steps * (r_px - 1.0f);
			/* the offset rounded first (as dao_gtao_sample_taps), so that pixels
			 * sharing it (the SIMD kernel's blocks) sample alike */
			int sx = x + (int)lrintf(dx * dist), sy = y + (int)lrintf(dy * dist);
			float zs = z_at(s, z, sx, sy);
			if (!(zs > 0.0f))
				continue;
			view_pos(s, (float)sx, (float)sy, zs, Q);
			float D[3] = {Q[0] - P[0], Q[1] - P[1], Q[2] - P[2]};
			float len2 = dao_dot3(D, D);
			float r2 = len2 / (R * R);
			if (r2 >= 1.0f || !(len2 > 0.0f))
				continue;
			float dxy = sqrtf(D[0] * D[0] + D[1] * D[1]);
			float tan_s = dxy > 0 ? -D[2] / dxy : 0.0f;
			float sin_s = tan_s / sqrtf(1.0f + tan_s * tan_s);
			if (sin_s > sin_h) {
				ao_d += (1.0f - r2) * (sin_s - sin_h);
				sin_h = sin_s;
			}
		}
		occ += ao_d;
	}
	return dao_saturate(1.0f - v->strength * occ / (float)dirs);
}

void dao_hbao_ref(const struct dao_variant_setup *v, const float *z, const float *n, float *ao,
		  int y0, int y1)
{
	(void)n; /* HBAO takes its tangents from the depth itself */
	const struct dao_gtao_setup *s = v->g;
	for (int y = y0; y < y1; y++)
		for (int x = 0; x < s->width; x++) {
			size_t i = (size_t)y * s->width + x;
			ao[i] = z[i] > 0 ? dao_gtao_finish(s, hbao_pixel(v, z, x, y)) : s->invalid_value;
		}
}

/*
 * SSAO (Crytek 2007, with the normal-oriented hemisphere of seed 004): kernel
 * points around P in the hemisphere of N, rotated per pixel; a point is
 * occluded when the surface seen at its pixel lies in front of it by more
 * than ssao_min (noise) and less than ssao_max (far objects do not occlude).
 */
static float ssao_pixel(const struct dao_variant_setup *v, const float *z, const float *nrm, int x,
			int y)
{
	const struct dao_gtao_setup *s = v->g;
	const float zc = z[(size_t)y * s->width + x];
	float P[3];
	view_pos(s, (float)x, (float)y, zc, P);
	const float *N = nrm + 3 * ((size_t)y * s->width + x);
	float n0, n1;
	dao_gtao_noise(s, x, y, &n0, &n1);
	/* a tangent frame around N, rotated by the per-pixel noise */
	float a = 2.0f * DAO_PI_F * n0, r[3] = {cosf(a), sinf(a), 0.0f};
	float rn = dao_dot3(r, N);
	float T[3] = {r[0] - N[0] * rn, r[1] - N[1] * rn, r[2] - N[2] * rn};
	float lt = sqrtf(dao_dot3(T, T));
	if (!(lt > 1e-6f)) { /* N along z: any perpendicular */
		T[0] = 1, T[1] = 0, T[2] = 0;
		lt = 1;
	}
	T[0] /= lt, T[1] /= lt, T[2] /= lt;
	float B[3] = {N[1] * T[2] - N[2] * T[1], N[2] * T[0] - N[0] * T[2], N[0] * T[1] - N[1] * T[0]};
	const float R = s->search_radius;
	int occluded = 0, counted = 0;
	for (int i = 0; i < v->ssao_samples; i++) {
		const float *k = v->ssao_kernel[i];
		float Q[3];
		for (int c = 0; c < 3; c++)
			Q[c] = P[c] + R * (T[c] * k[0] + B[c] * k[1] + N[c] * k[2]);
		if (!(Q[2] > 0.0f))
			continue;
		float u = (Q[0] / Q[2] - s->bx) / s->ax, vv = (Q[1] / Q[2] - s->by) / s->ay;
		float zs = z_at(s, z, (int)lrintf(u), (int)lrintf(vv));
		counted++;
		if (!(zs > 0.0f))
			continue;
		float in_front = Q[2] - zs;
		occluded += in_front > v->ssao_min && in_front < v->ssao_max;
	}
	return counted ? dao_saturate(1.0f - v->strength * (float)occluded / (float)counted) : 1.0f;
}

void dao_ssao_ref(const struct dao_variant_setup *v, const float *z, const float *n, float *ao,
		  int y0, int y1)
{
	const struct dao_gtao_setup *s = v->g;
	for (int y = y0; y < y1; y++)
		for (int x = 0; x < s->width; x++) {
			size_t i = (size_t)y * s->width + x;
			ao[i] = z[i] > 0 ? dao_gtao_finish(s, ssao_pixel(v, z, n, x, y)) : s->invalid_value;
		}
}

/*
 * The slice measure up to angle t from the view vector, for projected-normal
 * angle n: G(t) = -cos(2t - n)/4 + t sin(n)/2, the antiderivative of
 * cos(t - n) sin t (Jimenez 2016 eq. 7 integrates the same); over negative t
 * the |sin t| of the slice's solid angle flips its sign.
 */
static inline float slice_g(float t, float n)
{
	return -0.25f * cosf(2.0f * t - n) + 0.5f * t * sinf(n);
}

static float slice_measure(float a, float b, float n)
{
	if (a >= 0.0f)
		return slice_g(b, n) - slice_g(a, n);
	if (b <= 0.0f)
		return slice_g(a, n) - slice_g(b, n);
	return (slice_g(b, n) - slice_g(0.0f, n)) + (slice_g(a, n) - slice_g(0.0f, n));
}

/* The thickness plane at a sample's taps as dao_gtao_taps_value reads a plane,
 * each tap rounded to the nearest half: the SIMD kernel's plane holds halves
 * (gtao_planes.h), so that it reads half the bytes. */
static inline float thickness_at(const float *t, const struct dao_gtao_taps *tp)
{
	const float t0 = dao_half_round(t[tp->i0]), t1 = dao_half_round(t[tp->i1]);
	if (tp->pick < 0)
		return t0 + tp->f * (t1 - t0);
	return tp->pick ? t1 : t0;
}

/* Marks the sectors an occluder spanning angles [t0, t1] covers (angles from V). */
static uint32_t sectors(float t0, float t1, float lo)
{
	float a = (fminf(t0, t1) - lo) / DAO_PI_F * DAO_VBAO_SECTORS;
	float b = (fmaxf(t0, t1) - lo) / DAO_PI_F * DAO_VBAO_SECTORS;
	/* rounded, so a sample exactly on the hemisphere's edge (a tilted plane) marks nothing */
	int i0 = (int)lrintf(a), i1 = (int)lrintf(b);
	if (i0 < 0)
		i0 = 0;
	if (i1 > DAO_VBAO_SECTORS)
		i1 = DAO_VBAO_SECTORS;
	if (i1 <= i0)
		return 0;
	uint64_t m = ((uint64_t)1 << (i1 - i0)) - 1;
	return (uint32_t)(m << i0);
}

static float vbao_pixel(const struct dao_variant_setup *v, const float *z, const float *nrm, int x,
			int y)
{
	const struct dao_gtao_setup *s = v->g;
	const float zc = z[(size_t)y * s->width + x];
	float P[3];
	view_pos(s, (float)x, (float)y, zc, P);
	const float lp = sqrtf(dao_dot3(P, P));
	const float V[3] = {-P[0] / lp, -P[1] / lp, -P[2] / lp};
	const float *N = nrm + 3 * ((size_t)y * s->width + x);
	float r_px = s->search_radius * s->focal / zc;
	if (r_px < s->min_r_px || r_px < 1.0f)
		return 1.0f;
	if (s->noise == DAO_NOISE_TILE)
		r_px = dao_gtao_block_radius(s, z, x, y);
	r_px = fminf(r_px, s->max_r_px);
	float n0, n1;
	dao_gtao_noise(s, x, y, &n0, &n1);
	const float R = v->vbao_radius; /* where the falloff weight reaches 0 */
	float vis = 0.0f, norm = 0.0f;
	for (int sl = 0; sl < s->slices; sl++) {
		float dx, dy;
		dao_gtao_slice_dir(s, sl, n0, &dx, &dy);
		struct dao_slice sf;
		if (!dao_slice_frame(s, dx, dy, V, N, &sf))
			continue;
		const float lpn = sf.lpn, n = sf.n;
		const float lo = n - DAO_HALF_PI_F; /* sector 0 starts at the hemisphere's edge */
		const float sin_n = sinf(n);
		uint32_t mask = 0;
		for (int side = 0; side < 2; side++) {
			const float sx = side ? -dx : dx, sy = side ? -dy : dy, sign = side ? -1.0f : 1.0f;
			/* the cosine of this side's hemisphere edge, n -+ pi/2 from V */
			const float low = side ? sin_n : -sin_n;
			for (int i = 0; i < s->steps; i++) {
				float t = dao_gtao_step_t(s, i, n1);
				float dist = 1.0f + t * (r_px - 1.0f), u, vv, zs;
				struct dao_gtao_taps tp;
				if (!dao_gtao_sample_taps(z, s->width, s->height, x, y, sx, sy, dist, &u,
							  &vv, &zs, &tp))
					continue;
				const float T = v->thickness ? thickness_at(v->thickness, &tp)
							     : v->vbao_thickness;
				float S[3];
				view_pos(s, u, vv, zs, S);
				float D[3] = {S[0] - P[0], S[1] - P[1], S[2] - P[2]};
				float len = sqrtf(dao_dot3(D, D));
				if (!(len > 0.0f) || len > R)
					continue;
				/* the back of the sample: thickness T further along its camera ray
				 * (which lies in the slice plane, through the camera centre) */
				float ls = sqrtf(dao_dot3(S, S)), k = T / ls;
				float B[3] = {S[0] * (1 + k) - P[0], S[1] * (1 + k) - P[1], S[2] * (1 + k) - P[2]};
				float lb = sqrtf(dao_dot3(B, B));
				/* the falloff: as search_side moves a far sample's horizon
				 * cosine towards the edge's by its weight, both ends of the
				 * occluder move, so it shrinks into the edge; with infinitely
				 * thick occluders this is a horizon with that falloff (issue #17:
				 * the hard cut at the radius over-occluded the room corner) */
				const float wgt = dao_saturate(len * v->vbao_fall_mul + v->vbao_fall_add);
				const float cf = dao_clampf(dao_dot3(D, V) / len, -1.0f, 1.0f);
				const float cb = dao_clampf(dao_dot3(B, V) / lb, -1.0f, 1.0f);
				float tf = sign * acosf(dao_lerpf(low, cf, wgt));
				float tb = sign * acosf(dao_lerpf(low, cb, wgt));
				mask |= sectors(tf, tb, lo);
			}
		}
		float open = 0.0f, all = 0.0f;
		for (int k = 0; k < DAO_VBAO_SECTORS; k++) {
			float a = lo + DAO_PI_F * (float)k / DAO_VBAO_SECTORS;
			float w = slice_measure(a, a + DAO_PI_F / DAO_VBAO_SECTORS, n);
			all += w;
			if (!(mask & (1u << k)))
				open += w;
		}
		vis += lpn * open;
		norm += lpn * all;
	}
	return norm > 0.0f ? vis / norm : 1.0f;
}

void dao_vbao_ref(const struct dao_variant_setup *v, const float *z, const float *n, float *ao,
		  int y0, int y1)
{
	const struct dao_gtao_setup *s = v->g;
	for (int y = y0; y < y1; y++)
		for (int x = 0; x < s->width; x++) {
			size_t i = (size_t)y * s->width + x;
			ao[i] = z[i] > 0 ? dao_gtao_finish(s, vbao_pixel(v, z, n, x, y)) : s->invalid_value;
		}
}

/*
 * Eye-dome lighting (Boucheny 2009, as CloudCompare and Potree do it): how
 * much the log-depth of the pixel lies behind its 8 neighbours at edl_radius
 * px, shade = exp(-300 strength mean(max(0, log2 z - log2 z_n))).  A shading
 * cue for depth edges, not ambient occlusion.
 */
void dao_edl_ref(const struct dao_variant_setup *v, const float *z, float *ao, int y0, int y1)
{
	const struct dao_gtao_setup *s = v->g;
	static const float dirs[8][2] = {{1, 0}, {0.70710678f, 0.70710678f}, {0, 1},
					 {-0.70710678f, 0.70710678f}, {-1, 0},
					 {-0.70710678f, -0.70710678f}, {0, -1},
					 {0.70710678f, -0.70710678f}};
	for (int y = y0; y < y1; y++)
		for (int x = 0; x < s->width; x++) {
			size_t i = (size_t)y * s->width + x;
			if (!(z[i] > 0)) {
				ao[i] = s->invalid_value;
				continue;
			}
			float lz = log2f(z[i]), sum = 0.0f;
			for (int k = 0; k < 8; k++) {
				int nx = (int)lrintf((float)x + dirs[k][0] * v->edl_radius);
				int ny = (int)lrintf((float)y + dirs[k][1] * v->edl_radius);
				float zn = z_at(s, z, nx, ny);
				/* no depth behind a neighbour: treat it as far away (an edge) */
				float ln = zn > 0 ? log2f(zn) : lz + 1.0f;
				sum += fmaxf(0.0f, lz - ln);
			}
			ao[i] = expf(-300.0f * v->strength * sum / 8.0f);
		}
}
