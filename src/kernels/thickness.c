/* SPDX-License-Identifier: MIT */
/*
 * Thickness from the image: the extent of each surface's run along rows and
 * columns (thickness.h).  Two passes, O(1) per pixel, no allocation.
 */
#include "kernels/thickness.h"

#include <math.h>
#include <stddef.h>

void dao_thickness_setup_init(struct dao_thickness_setup *t, const struct dao_camera *cam,
			      float max)
{
	t->width = (int)cam->width;
	t->height = (int)cam->height;
	t->ax = cam->ax;
	t->ay = cam->ay;
	t->bx = cam->bx;
	t->by = cam->by;
	t->max = max;
}

/* (comparisons, not fminf: libm's is a call per pixel, a sixth of the time) */
static inline int same_surface(float a, float b)
{
	return a > 0.0f && b > 0.0f && fabsf(a - b) <= DAO_THICKNESS_JUMP * (a < b ? a : b);
}

/* A run ends on the outline of its object when the next pixel is farther or has no
 * data; at the border or in front of an occluder the surface goes on unseen. */
static inline int outline(float inside, float next)
{
	return !(next > 0.0f) || next > inside;
}

/*
 * One line of n pixels, the k-th at z[k * step] and at pixel coordinates
 * (u0 + k du, v0 + k dv).  Each run's chord spans from the outer edge of its
 * first pixel to the outer edge of its last (a run of one pixel is a pixel
 * wide), each end at its own depth.
 */
static void line(const struct dao_thickness_setup *t, const float *z, float *thick, int n,
		 size_t step, float u0, float v0, float du, float dv, int take_min)
{
	int i = 0;
	while (i < n) {
		const float zs = z[(size_t)i * step];
		if (!(zs > 0.0f)) {
			if (!take_min)
				thick[(size_t)i * step] = t->max;
			i++;
			continue;
		}
		const int s = i;
		while (i + 1 < n && same_surface(z[(size_t)i * step], z[(size_t)(i + 1) * step]))
			i++;
		const int e = i;
		const float ze = z[(size_t)e * step];
		float value = t->max;
		if (s > 0 && e + 1 < n && outline(zs, z[(size_t)(s - 1) * step]) &&
		    outline(ze, z[(size_t)(e + 1) * step])) {
			const float us = u0 + ((float)s - 0.5f) * du, vs = v0 + ((float)s - 0.5f) * dv;
			const float ue = u0 + ((float)e + 0.5f) * du, ve = v0 + ((float)e + 0.5f) * dv;
			const float dx = (ue * t->ax + t->bx) * ze - (us * t->ax + t->bx) * zs;
			const float dy = (ve * t->ay + t->by) * ze - (vs * t->ay + t->by) * zs;
			const float dz = ze - zs;
			const float chord = sqrtf(dx * dx + dy * dy + dz * dz);
			if (chord < value)
				value = chord;
		}
		if (take_min) {
			for (int k = s; k <= e; k++) {
				float *o = &thick[(size_t)k * step];
				if (value < *o)
					*o = value;
			}
		} else {
			for (int k = s; k <= e; k++)
				thick[(size_t)k * step] = value;
		}
		i = e + 1;
	}
}

void dao_thickness_rows(const struct dao_thickness_setup *t, const float *z, float *thick,
			int y0, int y1)
{
	for (int y = y0; y < y1; y++) {
		const size_t o = (size_t)y * t->width;
		line(t, z + o, thick + o, t->width, 1, 0.0f, (float)y, 1.0f, 0.0f, 0);
	}
}

void dao_thickness_cols(const struct dao_thickness_setup *t, const float *z, float *thick,
			int x0, int x1)
{
	for (int x = x0; x < x1; x++)
		line(t, z + x, thick + x, t->height, (size_t)t->width, (float)x, 0.0f, 0.0f, 1.0f, 1);
}
