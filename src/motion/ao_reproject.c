/* SPDX-License-Identifier: MIT */
#include <math.h>
#include <stddef.h>

#include "motion/ao_reproject.h"

#define SNAP_PX 1e-3 /* a landing point this close to a pixel centre takes that pixel */

/* The history read at (u, v) of the previous image for a point at depth qz
 * there: 1 with *ao and *hz set, 0 if no tap agrees or lies in the image. */
static int fetch(const float *hist_ao, const float *hist_z, int w, int h, double u, double v,
		 double qz, double reject, double *ao, double *hz)
{
	/* u, v > -0.5 (the caller's test): truncating u + 1 floors it, without a libm
	 * call where the baseline has no rounding instruction */
	const int x0 = (int)(u + 1.0) - 1, y0 = (int)(v + 1.0) - 1;
	const double a = u - x0, b = v - y0;
	const int xn = x0 + (a >= 0.5), yn = y0 + (b >= 0.5); /* the nearest pixel */
	if (fabs(u - xn) < SNAP_PX && fabs(v - yn) < SNAP_PX) {
		const size_t j = (size_t)yn * (size_t)w + (size_t)xn;
		if (!(hist_z[j] > 0.0f) || !(fabs(hist_z[j] - qz) <= reject * qz))
			return 0;
		*ao = hist_ao[j];
		*hz = hist_z[j];
		return 1;
	}
	const double rq = reject * qz;
	const double wx[2] = {1.0 - a, a}, wy[2] = {1.0 - b, b};
	double sw = 0.0, sao = 0.0, sz = 0.0;
	for (int dy = 0; dy < 2; dy++) {
		const int y = y0 + dy;
		if (y < 0 || y >= h || !(wy[dy] > 0.0))
			continue;
		const float *rz = hist_z + (size_t)y * (size_t)w, *ra = hist_ao + (size_t)y * (size_t)w;
		for (int dx = 0; dx < 2; dx++) {
			const int x = x0 + dx;
			if (x < 0 || x >= w || !(wx[dx] > 0.0))
				continue;
			const double hzt = rz[x];
			if (!(hzt > 0.0) || !(fabs(hzt - qz) <= rq))
				continue;
			const double wt = wy[dy] * wx[dx];
			sw += wt;
			sao += wt * ra[x];
			sz += wt * hzt;
		}
	}
	if (!(sw > 1e-6))
		return 0;
	*ao = sao / sw;
	*hz = sz / sw;
	return 1;
}

void dao_ao_history_reproject_rows(const struct dao_camera *cam,
				   const struct dao_pose *cur_to_prev, float reject, const float *z,
				   const float *hist_ao, const float *hist_z, float *ao_out,
				   float *z_out, int y0, int y1)
{
	const int w = (int)cam->width, h = (int)cam->height;
	const double *R = cur_to_prev->r, *t = cur_to_prev->t;
	/* the z of R^T t: where the previous camera's offset lies along the current view */
	const double c = R[2] * t[0] + R[5] * t[1] + R[8] * t[2];
	const double ax = 1.0 / cam->fx, bx = -cam->cx / cam->fx;
	for (int y = y0; y < y1; y++) {
		const double ry = ((double)y - cam->cy) / cam->fy;
		/* R times the ray of pixel (x, y), (x ax + bx, ry, 1): rb + x rd */
		double rb[3], rd[3];
		for (int k = 0; k < 3; k++) {
			rb[k] = R[k * 3] * bx + R[k * 3 + 1] * ry + R[k * 3 + 2];
			rd[k] = R[k * 3] * ax;
		}
		for (int x = 0; x < w; x++) {
			const size_t i = (size_t)y * (size_t)w + (size_t)x;
			const double zc = z[i];
			ao_out[i] = 0.0f;
			z_out[i] = 0.0f;
			if (!(zc > 0.0))
				continue;
			/* q = R p + t, p = zc ray */
			const double qx = zc * (rb[0] + x * rd[0]) + t[0];
			const double qy = zc * (rb[1] + x * rd[1]) + t[1];
			const double qz = zc * (rb[2] + x * rd[2]) + t[2];
			if (!(qz > 0.0))
				continue; /* behind the previous camera */
			const double u = cam->fx * qx / qz + cam->cx, v = cam->fy * qy / qz + cam->cy;
			if (!(u > -0.5 && v > -0.5 && u < w - 0.5 && v < h - 0.5))
				continue; /* outside the previous image */
			double ao, hz;
			if (!fetch(hist_ao, hist_z, w, h, u, v, qz, reject, &ao, &hz))
				continue; /* disoccluded */
			/* the history's point (on the previous ray through q, at hz) in
			 * the current view: p_h = s p + (s - 1) R^T t, s = hz / qz */
			const double s = hz / qz;
			const double zh = s * zc + (s - 1.0) * c;
			if (!(zh > 0.0))
				continue;
			ao_out[i] = (float)ao;
			z_out[i] = (float)zh;
		}
	}
}
