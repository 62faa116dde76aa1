/* SPDX-License-Identifier: MIT */
/* The pair kernel's reference (motion/icp_pairs.h): geometry in floats, sums in doubles. */
#include <math.h>
#include <string.h>

#include "motion/icp_pairs.h"

/* One pair: 0 and its residual, weight and Jacobian, or -1 if refused. */
static int pair(const struct dao_icp_step *st, int i, float *res, float *wt, float *e,
		float *wgt, float j[6])
{
	const size_t cap = st->cap;
	const float *s = st->src;
	const float sx = s[i], sy = s[cap + i], sz = s[2 * cap + i];
	const float *R = st->R;
	const float p0 = R[0] * sx + R[1] * sy + R[2] * sz + st->t[0];
	const float p1 = R[3] * sx + R[4] * sy + R[5] * sz + st->t[1];
	const float p2 = R[6] * sx + R[7] * sy + R[8] * sz + st->t[2];
	if (!(p2 > 0.0f))
		return -1;
	const float iz = 1.0f / p2;
	const float u = (p0 * iz - st->bx) * st->inv_ax, v = (p1 * iz - st->by) * st->inv_ay;
	const int w = st->w, r = st->r;
	if (!(u > (float)r - 0.5f && v > (float)r - 0.5f && u < (float)(w - r) - 0.5f &&
	      v < (float)(st->h - r) - 0.5f))
		return -1;
	const int x = (int)rintf(u), y = (int)rintf(v);
	const int k = y * w + x;
	const float z = st->tz[k], zl = st->tz[k - r], zr = st->tz[k + r];
	const float zu = st->tz[k - r * w], zd = st->tz[k + r * w];
	const float tol = st->edge * (float)r * z;
	if (!(z > 0.0f) || !(fabsf(zl - z) <= tol) || !(fabsf(zr - z) <= tol) ||
	    !(fabsf(zu - z) <= tol) || !(fabsf(zd - z) <= tol))
		return -1;

	const float ux = (float)x * st->ax + st->bx, vy = (float)y * st->ay + st->by;
	const float ra = (float)r * st->ax, rb = (float)r * st->ay;
	const float ul = ux - ra, ur = ux + ra, vu = vy - rb, vd = vy + rb;
	const float q0 = ux * z, q1 = vy * z;
	const float dx0 = ur * zr - ul * zl, dx1 = vy * (zr - zl), dx2 = zr - zl;
	const float dy0 = ux * (zd - zu), dy1 = vd * zd - vu * zu, dy2 = zd - zu;
	float c0 = dx1 * dy2 - dx2 * dy1, c1 = dx2 * dy0 - dx0 * dy2, c2 = dx0 * dy1 - dx1 * dy0;
	const float len2 = c0 * c0 + c1 * c1 + c2 * c2;
	if (!(len2 > 0.0f))
		return -1;
	/* towards the camera */
	const float il = ((c0 * q0 + c1 * q1 + c2 * z) > 0.0f ? -1.0f : 1.0f) / sqrtf(len2);
	const float m0 = c0 * il, m1 = c1 * il, m2 = c2 * il;
	const float d0 = p0 - q0, d1 = p1 - q1, d2 = p2 - z;
	if (!(d0 * d0 + d1 * d1 + d2 * d2 <= st->gate2))
		return -1;
	const float nx = s[3 * cap + i], ny = s[4 * cap + i], nz = s[5 * cap + i];
	const float rn0 = R[0] * nx + R[1] * ny + R[2] * nz;
	const float rn1 = R[3] * nx + R[4] * ny + R[5] * nz;
	const float rn2 = R[6] * nx + R[7] * ny + R[8] * nz;
	if (!(rn0 * m0 + rn1 * m1 + rn2 * m2 >= st->cos_gate))
		return -1;
	const float rr = m0 * d0 + m1 * d1 + m2 * d2;
	/* the noise along the rays: sigma_z of each end times m . ray */
	const float mp = (m0 * p0 + m1 * p1 + m2 * p2) * iz, mq = (m0 * q0 + m1 * q1 + m2 * z) / z;
	const float vp = st->k2 * (p2 * p2) * (p2 * p2) + st->q2;
	const float vq = st->k2 * (z * z) * (z * z) + st->q2;
	/* at most 60 degrees of incidence: the noise grows at grazing angles */
	const float var = fmaxf(mp * mp, 0.25f) * vp + fmaxf(mq * mq, 0.25f) * vq;
	const float ee = rr / sqrtf(var);
	const float f = ee / st->tukey_c;
	if (!(f * f < 1.0f))
		return -1;
	const float bw = (1.0f - f * f) * (1.0f - f * f);
	/* d res / d omega = c x m, d res / d v = m, the lever arm c at the
	 * pair's midpoint (at p its noise along the ray would correlate with
	 * res's and bias the rotation) */
	const float cx = 0.5f * (p0 + q0), cy = 0.5f * (p1 + q1), cz = 0.5f * (p2 + z);
	j[0] = (cy * m2 - cz * m1) * st->inv_scale;
	j[1] = (cz * m0 - cx * m2) * st->inv_scale;
	j[2] = (cx * m1 - cy * m0) * st->inv_scale;
	j[3] = m0, j[4] = m1, j[5] = m2;
	*res = rr, *wt = bw, *e = ee, *wgt = st->noise_weight ? bw / var : bw;
	return 0;
}

void dao_icp_pairs_ref(const struct dao_icp_step *st, int i0, int i1, struct dao_icp_sums *out)
{
	memset(out, 0, sizeof *out);
	for (int i = i0; i < i1; i++) {
		float res, bw, e, wgt, j[6];
		if (pair(st, i, &res, &bw, &e, &wgt, j))
			continue;
		int k = 0;
		for (int a = 0; a < 6; a++) {
			for (int b = a; b < 6; b++)
				out->a[k++] += (double)(wgt * j[a]) * j[b];
			out->b[a] -= (double)(wgt * j[a]) * res;
		}
		out->r2 += (double)res * res;
		out->e2w += (double)(bw * e) * e;
		out->wsum += bw;
		out->n++;
	}
}
