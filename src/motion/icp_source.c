/* SPDX-License-Identifier: MIT */
/* The source grid's and the target's reference kernels (motion/icp_source.h). */
#include <math.h>
#include <string.h>

#include "motion/icp_pairs.h"
#include "motion/icp_source.h"

/* Position and normal of pixel (x, y); 0, or -1 where it has none. */
static int point_normal(const struct dao_icp_grid *g, int x, int y, float p[3], float n[3])
{
	const int w = g->w, h = g->h, r = g->r;
	if (x < r || y < r || x >= w - r || y >= h - r)
		return -1;
	const float *plane = g->z;
	const size_t i = (size_t)y * (size_t)w + (size_t)x;
	const float z = plane[i], zl = plane[i - (size_t)r], zr = plane[i + (size_t)r];
	const float zu = plane[i - (size_t)r * (size_t)w], zd = plane[i + (size_t)r * (size_t)w];
	const float tol = g->edge_r * z;
	if (!(z > 0.0f) || !(fabsf(zl - z) <= tol) || !(fabsf(zr - z) <= tol) ||
	    !(fabsf(zu - z) <= tol) || !(fabsf(zd - z) <= tol))
		return -1;
	const float ux = (float)x * g->ax + g->bx, vy = (float)y * g->ay + g->by;
	const float ul = ux - g->rax, ur = ux + g->rax;
	const float vu = vy - g->ray, vd = vy + g->ray;
	p[0] = ux * z;
	p[1] = vy * z;
	p[2] = z;
	/* dx = P(x+r) - P(x-r), dy = P(y+r) - P(y-r) */
	const float dx[3] = {ur * zr - ul * zl, vy * (zr - zl), zr - zl};
	const float dy[3] = {ux * (zd - zu), vd * zd - vu * zu, zd - zu};
	float c[3] = {dx[1] * dy[2] - dx[2] * dy[1], dx[2] * dy[0] - dx[0] * dy[2],
		      dx[0] * dy[1] - dx[1] * dy[0]};
	const float len = sqrtf(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
	if (!(len > 0.0f))
		return -1;
	/* towards the camera */
	const float sgn = (c[0] * p[0] + c[1] * p[1] + c[2] * p[2]) > 0.0f ? -1.0f : 1.0f;
	for (int k = 0; k < 3; k++)
		n[k] = sgn * c[k] / len;
	return 0;
}

void dao_icp_source_ref(const struct dao_icp_grid *g, int y, float *out)
{
	const int end = (g->gw + DAO_ICP_PAD - 1) / DAO_ICP_PAD * DAO_ICP_PAD;
	for (int gx = 0; gx < end; gx++) {
		float p[3] = {0}, n[3] = {0};
		if (gx >= g->gw || point_normal(g, gx * g->step, y, p, n)) {
			memset(p, 0, sizeof p);
			memset(n, 0, sizeof n);
		}
		for (int k = 0; k < 3; k++) {
			out[(size_t)k * g->stride + (size_t)gx] = p[k];
			out[(size_t)(3 + k) * g->stride + (size_t)gx] = n[k];
		}
	}
}

void dao_icp_target_ref(const float *inv, const uint8_t *count, float *tz, size_t i0, size_t i1)
{
	for (size_t i = i0; i < i1; i++) {
		const float v = inv[i];
		const int has = v > 0.0f && (!count || count[i]);
		tz[i] = has ? 1.0f / v : 0.0f;
	}
}
