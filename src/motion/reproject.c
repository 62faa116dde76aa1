/* SPDX-License-Identifier: MIT */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "motion/reproject.h"

void dao_history_reproject(const struct dao_camera *cam, const struct dao_pose *cur_to_prev,
			   const float *hist, const uint8_t *count, const uint8_t *age,
			   float *hist_out, uint8_t *count_out, uint8_t *age_out, int32_t *scratch)
{
	const int w = (int)cam->width, h = (int)cam->height;
	const size_t npix = (size_t)w * (size_t)h;
	/* prev -> cur: R^T, -R^T t */
	const double *r = cur_to_prev->r, *t = cur_to_prev->t;
	float R[9], T[3];
	for (int i = 0; i < 3; i++) {
		for (int j = 0; j < 3; j++)
			R[i * 3 + j] = (float)r[j * 3 + i];
		T[i] = (float)-(r[i] * t[0] + r[3 + i] * t[1] + r[6 + i] * t[2]);
	}
	const float inv_ax = 1.0f / cam->ax, inv_ay = 1.0f / cam->ay;
	memset(hist_out, 0, npix * sizeof(float));
	memset(count_out, 0, npix);
	memset(age_out, 255, npix);
	/* pixel (x, y) at 1/z = h is z (ray(x, y)) with ray = (x ax + bx, y ay + by, 1);
	 * moved, q = z (R ray + T h) = z (g + T h) where g = R ray is linear in x
	 * along a row: g = g0 + x dg.  So u = (g_0 + T_0 h) / (g_2 + T_2 h) and
	 * 1/q_z = h / (g_2 + T_2 h): one division a pixel */
	const float dg[3] = {R[0] * cam->ax, R[3] * cam->ax, R[6] * cam->ax};
	const float ub = cam->bx * inv_ax, vb = cam->by * inv_ay;
	const float umax = (float)w - 0.5f, vmax = (float)h - 0.5f;
	int32_t *dest = scratch;
	float *zinv = (float *)(scratch + npix);
	/* where every pixel lands (branch-free, so that the compiler runs it
	 * over vector lanes), then the splat in row order */
	for (int y = 0; y < h; y++) {
		const float vy = (float)y * cam->ay + cam->by;
		const float g0[3] = {R[0] * cam->bx + R[1] * vy + R[2], R[3] * cam->bx + R[4] * vy + R[5],
				     R[6] * cam->bx + R[7] * vy + R[8]};
		const size_t row = (size_t)y * (size_t)w;
		for (int x = 0; x < w; x++) {
			const size_t i = row + (size_t)x;
			const float hv = hist[i];
			const float fx = (float)x;
			const float den = g0[2] + fx * dg[2] + T[2] * hv;
			const float d = 1.0f / (den > 0.0f ? den : 1.0f);
			const float u = (g0[0] + fx * dg[0] + T[0] * hv) * d * inv_ax - ub;
			const float v = (g0[1] + fx * dg[1] + T[1] * hv) * d * inv_ay - vb;
			const int ok = (count[i] != 0) & (hv > 0.0f) & (den > 0.0f) & (u > -0.5f) &
				       (v > -0.5f) & (u < umax) & (v < vmax);
			/* nearest pixel: u > -0.5, so floor(u + 0.5) is the truncation */
			const int32_t xu = (int32_t)(ok ? u + 0.5f : 0.0f);
			const int32_t yv = (int32_t)(ok ? v + 0.5f : 0.0f);
			dest[i] = ok && xu < w && yv < h ? yv * w + xu : -1;
			zinv[i] = hv * d;
		}
	}
	for (size_t i = 0; i < npix; i++) {
		const int32_t o = dest[i];
		if (o < 0)
			continue;
		const float iz = zinv[i];
		if (count_out[o] && !(iz > hist_out[o]))
			continue;
		hist_out[o] = iz;
		count_out[o] = count[i];
		age_out[o] = age[i];
	}
}
