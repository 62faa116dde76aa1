/* SPDX-License-Identifier: MIT */
#include <math.h>
#include <stddef.h>

#include <depthao/params.h>

#include "core/math_util.h"
#include "shade/shade.h"

static void base_colour(const struct dao_shade_setup *s, int x, int y, float zc, const float *N,
			float rgb[3])
{
	switch (s->mode) {
	case DAO_SHADE_LAMBERT: {
		/* head light: the light sits at the camera, so l = V = -P/|P| */
		float P[3] = { ((float)x * s->ax + s->bx) * zc, ((float)y * s->ay + s->by) * zc, zc };
		float lp = sqrtf(P[0] * P[0] + P[1] * P[1] + P[2] * P[2]);
		float ndl = -(N[0] * P[0] + N[1] * P[1] + N[2] * P[2]) / lp;
		float g = 255.0f * (0.12f + 0.88f * dao_saturate(ndl));
		rgb[0] = rgb[1] = rgb[2] = g;
		return;
	}
	case DAO_SHADE_TURBO:
	case DAO_SHADE_JET:
	case DAO_SHADE_GRAY: {
		float t = dao_saturate((zc - s->near_m) / (s->far_m - s->near_m));
		const uint8_t *c = s->map->rgb[(int)lrintf(t * 255.0f)];
		rgb[0] = c[0], rgb[1] = c[1], rgb[2] = c[2];
		return;
	}
	default:
		rgb[0] = rgb[1] = rgb[2] = 255.0f;
		return;
	}
}

void dao_shade_pixel(const struct dao_shade_setup *s, const float *z, const float *n,
		     const float *ao, int x, int y, float rgb[3])
{
	const size_t i = (size_t)y * s->width + x;
	rgb[0] = rgb[1] = rgb[2] = 0.0f;
	if (z[i] > 0.0f) {
		base_colour(s, x, y, z[i], n + 3 * i, rgb);
		float v = dao_saturate(ao[i]);
		float k = s->power == 1.0f ? v : powf(v, s->power);
		for (int c = 0; c < 3; c++)
			rgb[c] = dao_lerpf(s->occ[c], rgb[c], k);
	}
}

void dao_shade(const struct dao_shade_setup *s, const float *z, const float *n, const float *ao,
	       const struct dao_frame *out, int y0, int y1)
{
	const int w = s->width;
	const int gray = out->format == DAO_PIXFMT_GRAY8;
	for (int y = y0; y < y1; y++) {
		uint8_t *row = (uint8_t *)out->data + (size_t)y * out->stride;
		for (int x = 0; x < w; x++) {
			float rgb[3];
			dao_shade_pixel(s, z, n, ao, x, y, rgb);
			if (gray) {
				row[x] = (uint8_t)lrintf(
					dao_clampf(0.299f * rgb[0] + 0.587f * rgb[1] + 0.114f * rgb[2], 0, 255));
			} else {
				for (int c = 0; c < 3; c++)
					row[3 * x + c] = (uint8_t)lrintf(dao_clampf(rgb[c], 0.0f, 255.0f));
			}
		}
	}
}
