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
	const double ru = rint(u), rv = rint(v);
	if (fabs(u - ru) < SNAP_PX && fabs(v - rv) < SNAP_PX) {
		const size_t j = (size_t)rv * (size_t)w + (size_t)ru;
		if (!(hist_z[j] > 0.0f) || !(fabs(hist_z[j] - qz) <= reject * qz))
			return 0;
		*ao = hist_ao[j];
		*hz = hist_z[j];
		return 1;
	}
	const double fu = floor(u), fv = floor(v);
	const double a = u - fu, b = v - fv;
	const int x0 = (int)fu, y0 = (int)fv;
	double sw = 0.0, sao = 0.0, sz = 0.0;
	for (int k = 0; k < 4; k++) {
		const int x = x0 + (k & 1), y = y0 + (k >> 1);
		const double wt = ((k & 1) ? a : 1.0 - a) * ((k >> 1) ? b : 1.0 - b);
		if (x < 0 || y < 0 || x >= w || y >= h || !(wt > 0.0))
			continue;
		const size_t j = (size_t)y * (size_t)w + (size_t)x;
		if (!(hist_z[j] > 0.0f) || !(fabs(hist_z[j] - qz) <= reject * qz))
			continue;
		sw += wt;
		sao += wt * hist_ao[j];
		sz += wt * hist_z[j];
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
	for (int y = y0; y < y1; y++) {
		const double ry = ((double)y - cam->cy) / cam->fy;
		for (int x = 0; x < w; x++) {
			const size_t i = (size_t)y * (size_t)w + (size_t)x;
			const double zc = z[i];
			ao_out[i] = 0.0f;
			z_out[i] = 0.0f;
			if (!(zc > 0.0))
				continue;
			const double p[3] = {((double)x - cam->cx) / cam->fx * zc, ry * zc, zc};
			const double qx = R[0] * p[0] + R[1] * p[1] + R[2] * p[2] + t[0];
			const double qy = R[3] * p[0] + R[4] * p[1] + R[5] * p[2] + t[1];
			const double qz = R[6] * p[0] + R[7] * p[1] + R[8] * p[2] + t[2];
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
