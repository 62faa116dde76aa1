/* SPDX-License-Identifier: MIT */
/*
 * GTAO, scalar reference (Jimenez, Wu, Pesce, Jarabo 2016, "Practical
 * Real-Time Strategies for Accurate Indirect Occlusion"; seeds 000, 002).
 * Plain and exact (libm trig), kept as the oracle for optimised kernels.
 */
#include <math.h>
#include <stddef.h>

#include "core/math_util.h"
#include "kernels/gtao.h"
#include "kernels/gtao_sample.h"
#include "kernels/gtao_slice.h"

/*
 * Largest horizon cosine along one side of a slice.  `low` is the cosine of
 * the normal-hemisphere boundary on that side, the value of "no occluder".
 */
static float search_side(const struct dao_gtao_setup *s, const float *z, int x, int y,
			 float dx, float dy, float r_px, float jitter, const float P[3],
			 const float V[3], float low)
{
	float best = low;
	for (int i = 0; i < s->steps; i++) {
		float t = dao_gtao_step_t(s, i, jitter);
		float dist = 1.0f + t * (r_px - 1.0f);
		float u, v, zs;
		if (!dao_gtao_sample(z, s->width, s->height, x, y, dx, dy, dist, &u, &v, &zs))
			continue;
		float D[3] = { (u * s->ax + s->bx) * zs - P[0], (v * s->ay + s->by) * zs - P[1],
			       zs - P[2] };
		float len = sqrtf(dao_dot3(D, D));
		if (!(len > 0.0f))
			continue;
		float c = dao_dot3(D, V) / len;
		float wgt = dao_saturate(len * s->falloff_mul + s->falloff_add);
		c = dao_lerpf(low, c, wgt);
		/* thickness heuristic (UE4): a lower sample after a higher one means we
		 * may be looking past a thin occluder; pull the horizon towards it */
		best = c > best ? c : dao_lerpf(c, best, s->decay);
	}
	return best;
}

/*
 * Antiderivatives of cos t cos(t - n) sin t (towards V, which = 0) and of
 * sin^2 t cos(t - n) (towards the slice direction, which = 1), expanding
 * cos(t - n) = cos t cos n + sin t sin n.
 */
static float bent_f(float t, float n, int which)
{
	float c = cosf(t), s = sinf(t);
	if (which == 0)
		return (-cosf(n) * c * c * c + sinf(n) * s * s * s) / 3.0f;
	return (cosf(n) * s * s * s + sinf(n) * (c * c * c - 3.0f * c)) / 3.0f;
}

/* The integral over [a, b] with |sin t| (the sign flips below t = 0). */
static float bent_integral(float a, float b, float n, int which)
{
	if (a >= 0.0f)
		return bent_f(b, n, which) - bent_f(a, n, which);
	if (b <= 0.0f)
		return bent_f(a, n, which) - bent_f(b, n, which);
	float f0 = bent_f(0.0f, n, which);
	return (bent_f(b, n, which) - f0) + (bent_f(a, n, which) - f0);
}

/* Visibility of one pixel; with `bent` != NULL also its bent normal (unit, view space). */
static float gtao_pixel(const struct dao_gtao_setup *s, const float *z, const float *nrm, int x,
			int y, float bent[3])
{
	const float zc = z[(size_t)y * s->width + x];
	const float P[3] = { ((float)x * s->ax + s->bx) * zc, ((float)y * s->ay + s->by) * zc, zc };
	const float lp = sqrtf(dao_dot3(P, P));
	const float V[3] = { -P[0] / lp, -P[1] / lp, -P[2] / lp };
	const float *N = nrm + 3 * ((size_t)y * s->width + x);

	float r_px = s->search_radius * s->focal / zc;
	if (bent)
		bent[0] = N[0], bent[1] = N[1], bent[2] = N[2];
	if (r_px < s->min_r_px || r_px < 1.0f)
		return 1.0f;
	float bsum[3] = {0.0f, 0.0f, 0.0f};
	if (s->noise == DAO_NOISE_TILE)
		r_px = dao_gtao_block_radius(s, z, x, y);
	r_px = fminf(r_px, s->max_r_px);

	float n0, n1;
	dao_gtao_noise(s, x, y, &n0, &n1);

	float vis = 0.0f, norm = 0.0f;
	for (int sl = 0; sl < s->slices; sl++) {
		float dx, dy;
		dao_gtao_slice_dir(s, sl, n0, &dx, &dy);
		/* the screen line through the pixel is the image of the slice plane */
		struct dao_slice sf;
		if (!dao_slice_frame(s, dx, dy, V, N, &sf))
			continue;
		const float lpn = sf.lpn, cos_n = sf.cos_n, n = sf.n;
		const float *ortho = sf.ortho;
		float sin_n = sinf(n);

		/* side + (towards dir) and side - */
		float hc_pos = search_side(s, z, x, y, dx, dy, r_px, n1, P, V, cosf(n + DAO_HALF_PI_F));
		float hc_neg = search_side(s, z, x, y, -dx, -dy, r_px, n1, P, V, cosf(n - DAO_HALF_PI_F));
		float h1 = acosf(dao_clampf(hc_pos, -1.0f, 1.0f));
		float h0 = -acosf(dao_clampf(hc_neg, -1.0f, 1.0f));
		/* clamp to the hemisphere around the projected normal */
		h0 = n + fmaxf(h0 - n, -DAO_HALF_PI_F);
		h1 = n + fminf(h1 - n, DAO_HALF_PI_F);
		/* cosine-weighted slice integral, Jimenez 2016 eq. 7 */
		float a0 = 0.25f * (-cosf(2.0f * h0 - n) + cos_n + 2.0f * h0 * sin_n);
		float a1 = 0.25f * (-cosf(2.0f * h1 - n) + cos_n + 2.0f * h1 * sin_n);
		vis += lpn * (a0 + a1);
		/* the same integral unoccluded (h = n -+ pi/2) is cos n + n sin n; dividing
		 * by it makes an open surface exactly 1 for any slice set (a ratio estimator
		 * of the hemisphere average, with far less variance at few slices) */
		norm += lpn * (cos_n + n * sin_n);
		if (bent) {
			/* the cosine-weighted mean of the open directions of the slice:
			 * lpn * integral over [h0, h1] of (cos t V + sin t o) cos(t - n) |sin t| dt */
			float av = bent_integral(h0, h1, n, 0), ao = bent_integral(h0, h1, n, 1);
			float lo = sqrtf(dao_dot3(ortho, ortho));
			for (int k = 0; k < 3; k++)
				bsum[k] += lpn * (av * V[k] + ao * ortho[k] / lo);
		}
	}
	if (bent) {
		float lb = sqrtf(dao_dot3(bsum, bsum));
		if (lb > 1e-6f)
			bent[0] = bsum[0] / lb, bent[1] = bsum[1] / lb, bent[2] = bsum[2] / lb;
	}
	return norm > 0.0f ? vis / norm : 1.0f;
}

void dao_gtao_ref(const struct dao_gtao_setup *s, const float *z, const float *n, float *ao,
		  int y0, int y1)
{
	for (int y = y0; y < y1; y++)
		for (int x = 0; x < s->width; x++) {
			size_t i = (size_t)y * s->width + x;
			ao[i] = z[i] > 0.0f ? dao_gtao_finish(s, gtao_pixel(s, z, n, x, y, NULL))
					    : s->invalid_value;
		}
}

void dao_gtao_bent_ref(const struct dao_gtao_setup *s, const float *z, const float *n, float *bent,
		       int y0, int y1)
{
	for (int y = y0; y < y1; y++)
		for (int x = 0; x < s->width; x++) {
			size_t i = (size_t)y * s->width + x;
			if (z[i] > 0.0f) {
				gtao_pixel(s, z, n, x, y, bent + 3 * i);
			} else {
				bent[3 * i] = bent[3 * i + 1] = 0.0f;
				bent[3 * i + 2] = 0.0f;
			}
		}
}
