/* SPDX-License-Identifier: MIT */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "motion/reproject.h"

void dao_history_reproject(const struct dao_camera *cam, const struct dao_pose *cur_to_prev,
			   const float *hist, const uint8_t *count, const uint8_t *age,
			   float *hist_out, uint8_t *count_out, uint8_t *age_out)
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
	for (int y = 0; y < h; y++) {
		const float vy = (float)y * cam->ay + cam->by;
		for (int x = 0; x < w; x++) {
			const size_t i = (size_t)y * (size_t)w + (size_t)x;
			if (!count[i] || !(hist[i] > 0.0f))
				continue;
			const float z = 1.0f / hist[i];
			const float p[3] = {((float)x * cam->ax + cam->bx) * z, vy * z, z};
			const float q[3] = {R[0] * p[0] + R[1] * p[1] + R[2] * p[2] + T[0],
					    R[3] * p[0] + R[4] * p[1] + R[5] * p[2] + T[1],
					    R[6] * p[0] + R[7] * p[1] + R[8] * p[2] + T[2]};
			if (!(q[2] > 0.0f))
				continue;
			const float iz = 1.0f / q[2];
			const float u = (q[0] * iz - cam->bx) * inv_ax;
			const float v = (q[1] * iz - cam->by) * inv_ay;
			if (!(u > -0.5f && v > -0.5f && u < (float)w - 0.5f && v < (float)h - 0.5f))
				continue;
			const long xu = lrintf(u), yv = lrintf(v);
			if (xu < 0 || yv < 0 || xu >= w || yv >= h)
				continue;
			const size_t o = (size_t)yv * (size_t)w + (size_t)xu;
			if (count_out[o] && !(iz > hist_out[o]))
				continue;
			hist_out[o] = iz;
			count_out[o] = count[i];
			age_out[o] = age[i];
		}
	}
}
