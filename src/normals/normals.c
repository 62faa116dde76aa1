/* SPDX-License-Identifier: MIT */
#include <math.h>
#include <stddef.h>

#include "normals/normals.h"

static inline void view_pos(const struct dao_camera *c, int x, int y, float z, float p[3])
{
	p[0] = ((float)x * c->ax + c->bx) * z;
	p[1] = ((float)y * c->ay + c->by) * z;
	p[2] = z;
}

/*
 * One-sided derivative along (sx, sy) at pixel (x, y) with depth zc: fills
 * d with P(+r) - P or P - P(-r), whichever has the smaller |dz|, falling
 * back to shorter offsets near holes and borders.  Returns 0 if no
 * neighbour on the axis has data.
 */
static int axis_delta(const struct dao_camera *c, const float *z, int x, int y, int sx, int sy,
		      int r, const float p[3], float d[3])
{
	const int w = (int)c->width, h = (int)c->height;
	for (int k = r; k >= 1; k--) {
		int xm = x - sx * k, ym = y - sy * k, xp = x + sx * k, yp = y + sy * k;
		float zm = (xm >= 0 && ym >= 0) ? z[(size_t)ym * w + xm] : 0.0f;
		float zp = (xp < w && yp < h) ? z[(size_t)yp * w + xp] : 0.0f;
		if (zm <= 0.0f && zp <= 0.0f)
			continue;
		float q[3];
		if (zp > 0.0f && (zm <= 0.0f || fabsf(zp - p[2]) < fabsf(p[2] - zm))) {
			view_pos(c, xp, yp, zp, q);
			d[0] = q[0] - p[0], d[1] = q[1] - p[1], d[2] = q[2] - p[2];
		} else {
			view_pos(c, xm, ym, zm, q);
			d[0] = p[0] - q[0], d[1] = p[1] - q[1], d[2] = p[2] - q[2];
		}
		return 1;
	}
	return 0;
}

void dao_normal_pixel(const struct dao_camera *cam, const float *z, int r, int x, int y,
		      float out[3])
{
	const int w = (int)cam->width;
	const float zc = z[(size_t)y * w + x];
	if (zc <= 0.0f) {
		out[0] = 0.0f, out[1] = 0.0f, out[2] = -1.0f;
		return;
	}
	float p[3], dx[3], dy[3];
	view_pos(cam, x, y, zc, p);
	float len_p = sqrtf(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
	if (!axis_delta(cam, z, x, y, 1, 0, r, p, dx) || !axis_delta(cam, z, x, y, 0, 1, r, p, dy)) {
		out[0] = -p[0] / len_p, out[1] = -p[1] / len_p, out[2] = -p[2] / len_p;
		return;
	}
	/* dPdx x dPdy points away from the camera in the optical frame
	 * (x right, y down, z forward); flip so N faces the viewer */
	float c0 = dx[1] * dy[2] - dx[2] * dy[1];
	float c1 = dx[2] * dy[0] - dx[0] * dy[2];
	float c2 = dx[0] * dy[1] - dx[1] * dy[0];
	float len = sqrtf(c0 * c0 + c1 * c1 + c2 * c2);
	if (!(len > 0.0f)) {
		out[0] = -p[0] / len_p, out[1] = -p[1] / len_p, out[2] = -p[2] / len_p;
		return;
	}
	if (c0 * p[0] + c1 * p[1] + c2 * p[2] > 0.0f)
		len = -len;
	out[0] = c0 / len, out[1] = c1 / len, out[2] = c2 / len;
}

void dao_normals_from_depth(const struct dao_camera *cam, const float *z, int r, float *n,
			    int y0, int y1)
{
	const int w = (int)cam->width;
	for (int y = y0; y < y1; y++)
		for (int x = 0; x < w; x++)
			dao_normal_pixel(cam, z, r, x, y, n + 3 * ((size_t)y * w + x));
}
