/* SPDX-License-Identifier: MIT */
/*
 * Colour frames of .oni image nodes to RGB24.
 *
 * YUV to RGB is BT.601 with full-range Y, U, V (the JFIF equations, which
 * libjpeg applies to JPEG frames too), in 16.16 fixed point:
 *   R = Y + 1.402 (V - 128)
 *   G = Y - 0.344136 (U - 128) - 0.714136 (V - 128)
 *   B = Y + 1.772 (U - 128)
 */
#include "oni/oni_color.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <turbojpeg.h>

#include <depthao/oni.h>

int dao_oni_color_format_from_xn(uint64_t xn)
{
	switch (xn) {
	case 1: return DAO_ONI_PIXEL_RGB888;  /* XN_PIXEL_FORMAT_RGB24 */
	case 2: return DAO_ONI_PIXEL_YUV422;  /* XN_PIXEL_FORMAT_YUV422 (UYVY) */
	case 3: return DAO_ONI_PIXEL_GRAY8;   /* XN_PIXEL_FORMAT_GRAYSCALE_8_BIT */
	case 5: return DAO_ONI_PIXEL_JPEG;    /* XN_PIXEL_FORMAT_MJPEG */
	default: return 0;
	}
}

size_t dao_oni_color_raw_size(int pixel_format, uint32_t width, uint32_t height)
{
	size_t n = (size_t)width * height;
	switch (pixel_format) {
	case DAO_ONI_PIXEL_RGB888: return 3 * n;
	case DAO_ONI_PIXEL_YUV422:
	case DAO_ONI_PIXEL_YUYV: return width % 2 ? 0 : 2 * n;
	case DAO_ONI_PIXEL_GRAY8: return n;
	default: return 0;
	}
}

static uint8_t clamp8(int32_t v)
{
	return v < 0 ? 0 : v > 255 ? 255 : (uint8_t)v;
}

/* One pixel from Y and the pair's chroma (16.16 fixed point, rounded). */
static void yuv_pixel(uint8_t *o, int y, int u, int v)
{
	const int32_t rv = 91881, gu = 22554, gv = 46802, bu = 116130; /* x 65536 */
	int32_t yy = (int32_t)y << 16, du = u - 128, dv = v - 128;
	o[0] = clamp8((yy + rv * dv + 32768) >> 16);
	o[1] = clamp8((yy - gu * du - gv * dv + 32768) >> 16);
	o[2] = clamp8((yy + bu * du + 32768) >> 16);
}

void dao_oni_color_convert_raw(int pixel_format, const uint8_t *src, uint32_t width,
			       uint32_t height, struct dao_frame *out)
{
	for (uint32_t y = 0; y < height; y++) {
		uint8_t *o = (uint8_t *)out->data + (size_t)y * (size_t)out->stride;
		switch (pixel_format) {
		case DAO_ONI_PIXEL_RGB888:
			memcpy(o, src + (size_t)y * width * 3, (size_t)width * 3);
			break;
		case DAO_ONI_PIXEL_GRAY8: {
			const uint8_t *s = src + (size_t)y * width;
			for (uint32_t x = 0; x < width; x++)
				o[3 * x] = o[3 * x + 1] = o[3 * x + 2] = s[x];
			break;
		}
		case DAO_ONI_PIXEL_YUV422: /* U Y0 V Y1 */
		case DAO_ONI_PIXEL_YUYV: { /* Y0 U Y1 V */
			const uint8_t *s = src + (size_t)y * width * 2;
			const int uyvy = pixel_format == DAO_ONI_PIXEL_YUV422;
			for (uint32_t x = 0; x < width; x += 2, s += 4) {
				int y0 = uyvy ? s[1] : s[0], y1 = uyvy ? s[3] : s[2];
				int u = uyvy ? s[0] : s[1], v = uyvy ? s[2] : s[3];
				yuv_pixel(o + 3 * x, y0, u, v);
				yuv_pixel(o + 3 * x + 3, y1, u, v);
			}
			break;
		}
		default:
			break;
		}
	}
}

struct dao_jpeg {
	tjhandle tj;
};

int dao_jpeg_create(struct dao_jpeg **out)
{
	struct dao_jpeg *j = calloc(1, sizeof(*j));
	if (!j)
		return -ENOMEM;
	if (!(j->tj = tjInitDecompress())) {
		free(j);
		return -ENOMEM;
	}
	*out = j;
	return 0;
}

void dao_jpeg_destroy(struct dao_jpeg *j)
{
	if (!j)
		return;
	tjDestroy(j->tj);
	free(j);
}

/*
 * The JPEG's frame type (SOFn) before its first scan: 0, or the n of an
 * arithmetic-coded frame (SOF9..11, 13..15), which no depth camera writes;
 * a Huffman stream under such a marker decodes to noise without a warning.
 */
static int arithmetic_sof(const uint8_t *d, size_t n)
{
	size_t i = 2; /* after SOI */
	while (i + 4 <= n && d[i] == 0xFF) {
		uint8_t m = d[i + 1];
		if (m == 0xFF) { /* fill byte */
			i++;
			continue;
		}
		if (m == 0xDA || m == 0xD9) /* SOS, EOI: no arithmetic frame before */
			return 0;
		if (m >= 0xC9 && m <= 0xCF && m != 0xCC)
			return m - 0xC0;
		if ((m >= 0xD0 && m <= 0xD7) || m == 0x01) { /* no length */
			i += 2;
			continue;
		}
		i += 2 + (size_t)((d[i + 2] << 8) | d[i + 3]);
	}
	return 0;
}

int dao_jpeg_decode(struct dao_jpeg *j, const uint8_t *data, size_t size,
		    struct dao_frame *out, char *why, size_t why_len)
{
	int w = 0, h = 0, sub = 0, cs = 0;
	int sof = arithmetic_sof(data, size);
	if (sof) {
		snprintf(why, why_len, "an arithmetic-coded JPEG (SOF%d), which no camera writes "
			 "and depthao does not accept", sof);
		return -EINVAL;
	}
	if (tjDecompressHeader3(j->tj, data, (unsigned long)size, &w, &h, &sub, &cs) < 0) {
		snprintf(why, why_len, "bad JPEG header: %s", tjGetErrorStr2(j->tj));
		return -EINVAL;
	}
	if ((uint32_t)w != out->width || (uint32_t)h != out->height) {
		snprintf(why, why_len, "the JPEG image is %dx%d, the stream says %ux%u", w, h,
			 out->width, out->height);
		return -EINVAL;
	}
	/* accurate DCT and fancy upsampling: libjpeg's defaults, as other decoders use.
	 * A warning (corrupt entropy data, a premature end) leaves part of the image
	 * grey or garbled: the frame is as corrupt as after an error, and says so. */
	if (tjDecompress2(j->tj, data, (unsigned long)size, out->data, w, out->stride, h, TJPF_RGB,
			  TJFLAG_ACCURATEDCT | TJFLAG_STOPONWARNING) < 0) {
		snprintf(why, why_len, "%s JPEG data: %s",
			 tjGetErrorCode(j->tj) == TJERR_WARNING ? "damaged" : "corrupt",
			 tjGetErrorStr2(j->tj));
		return -EINVAL;
	}
	return 0;
}
