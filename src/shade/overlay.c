/* SPDX-License-Identifier: MIT */
/*
 * AO over colour (include/depthao/overlay.h).
 */
#include <depthao/overlay.h>

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error_internal.h"

int dao_overlay_check(uint32_t cw, uint32_t ch, uint32_t aw, uint32_t ah, struct dao_error *err)
{
	if (!cw || !ch || !aw || !ah)
		return dao_error_set(err, -EINVAL, "overlay: an empty image (colour %ux%u, AO %ux%u)",
				     cw, ch, aw, ah);
	if (cw == aw && ch == ah)
		return 0;
	/* the same aspect ratio within 1 %: cw/ch against aw/ah */
	double ratio = ((double)cw * ah) / ((double)ch * aw);
	if (fabs(ratio - 1.0) <= 0.01)
		return 0;
	return dao_error_set(err, -EINVAL,
			     "overlay: the colour images are %ux%u and the depth %ux%u, different "
			     "aspect ratios (%.3f and %.3f): they do not show the same view; "
			     "depthao scales colour of the depth's aspect ratio but does not "
			     "reproject between cameras (register the depth to the colour camera)",
			     cw, ch, aw, ah, (double)cw / ch, (double)aw / ah);
}

/* The visibility of row y as 16 bits, into a16[0..w). */
static void ao_row16(const struct dao_frame *ao, uint32_t y, uint16_t *a16)
{
	const uint8_t *row = (const uint8_t *)ao->data + (size_t)y * (size_t)ao->stride;
	for (uint32_t x = 0; x < ao->width; x++) {
		switch (ao->format) {
		case DAO_PIXFMT_GRAY16: {
			uint16_t v;
			memcpy(&v, row + 2 * (size_t)x, 2);
			a16[x] = v;
			break;
		}
		case DAO_PIXFMT_GRAY8:
			a16[x] = (uint16_t)(row[x] * 257u);
			break;
		default: {
			float v;
			memcpy(&v, row + 4 * (size_t)x, 4);
			v = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f; /* NaN -> 0 */
			a16[x] = (uint16_t)lrintf(v * 65535.0f); /* as the PNG writer rounds */
			break;
		}
		}
	}
}

static uint8_t shade(uint32_t c, uint32_t a)
{
	return (uint8_t)((c * a + 32767u) / 65535u);
}

/* Colour sample at the centre of AO pixel (x, y), bilinear in the colour image. */
static void sample(const struct dao_frame *c, double sx, double sy, uint32_t x, uint32_t y,
		   uint8_t rgb[3])
{
	double fx = (x + 0.5) * sx - 0.5, fy = (y + 0.5) * sy - 0.5;
	if (fx < 0)
		fx = 0;
	if (fy < 0)
		fy = 0;
	uint32_t x0 = (uint32_t)fx, y0 = (uint32_t)fy;
	if (x0 > c->width - 1)
		x0 = c->width - 1;
	if (y0 > c->height - 1)
		y0 = c->height - 1;
	uint32_t x1 = x0 + 1 < c->width ? x0 + 1 : x0, y1 = y0 + 1 < c->height ? y0 + 1 : y0;
	double wx = fx - x0, wy = fy - y0;
	if (wx > 1)
		wx = 1;
	if (wy > 1)
		wy = 1;
	const uint8_t *r0 = (const uint8_t *)c->data + (size_t)y0 * (size_t)c->stride;
	const uint8_t *r1 = (const uint8_t *)c->data + (size_t)y1 * (size_t)c->stride;
	for (int k = 0; k < 3; k++) {
		double top = r0[3 * x0 + k] * (1 - wx) + r0[3 * x1 + k] * wx;
		double bot = r1[3 * x0 + k] * (1 - wx) + r1[3 * x1 + k] * wx;
		rgb[k] = (uint8_t)(top * (1 - wy) + bot * wy + 0.5);
	}
}

int dao_overlay(const struct dao_frame *color, const struct dao_frame *ao, struct dao_frame *out,
		struct dao_error *err)
{
	int r;
	if (!color || !ao || !out)
		return dao_error_set(err, -EINVAL, "dao_overlay: colour, AO and output are required");
	if ((r = dao_frame_check(color, "overlay colour input", 0, 0, err)) < 0 ||
	    (r = dao_frame_check(ao, "overlay AO input", 0, 0, err)) < 0 ||
	    (r = dao_frame_check(out, "overlay output", ao->width, ao->height, err)) < 0)
		return r;
	if (color->format != DAO_PIXFMT_RGB24 || out->format != DAO_PIXFMT_RGB24)
		return dao_error_set(err, -EINVAL, "overlay: colour and output must be rgb24, not %s "
				     "and %s", dao_pixfmt_name(color->format),
				     dao_pixfmt_name(out->format));
	if (ao->format != DAO_PIXFMT_GRAY16 && ao->format != DAO_PIXFMT_GRAY8 &&
	    ao->format != DAO_PIXFMT_GRAY_F32)
		return dao_error_set(err, -EINVAL, "overlay: the AO must be gray16, gray8 or gray_f32, "
				     "not %s", dao_pixfmt_name(ao->format));
	if ((r = dao_overlay_check(color->width, color->height, ao->width, ao->height, err)) < 0)
		return r;
	const int same = color->width == ao->width && color->height == ao->height;
	const double sx = (double)color->width / ao->width, sy = (double)color->height / ao->height;
	uint16_t a16[512];
	for (uint32_t y = 0; y < ao->height; y++) {
		uint8_t *o = (uint8_t *)out->data + (size_t)y * (size_t)out->stride;
		const uint8_t *c = (const uint8_t *)color->data + (size_t)y * (size_t)color->stride;
		/* the row in pieces of a16's size: no allocation */
		for (uint32_t x0 = 0; x0 < ao->width; x0 += 512) {
			uint32_t n = ao->width - x0 < 512 ? ao->width - x0 : 512;
			struct dao_frame piece = *ao;
			piece.width = n;
			piece.data = (uint8_t *)ao->data + (size_t)x0 * dao_pixfmt_bytes_per_pixel(ao->format);
			ao_row16(&piece, y, a16);
			for (uint32_t i = 0; i < n; i++) {
				uint32_t x = x0 + i;
				uint8_t rgb[3];
				if (same)
					memcpy(rgb, c + 3 * (size_t)x, 3);
				else
					sample(color, sx, sy, x, y, rgb);
				for (int k = 0; k < 3; k++)
					o[3 * (size_t)x + k] = shade(rgb[k], a16[i]);
			}
		}
	}
	return 0;
}
