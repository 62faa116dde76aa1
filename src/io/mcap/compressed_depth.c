/* SPDX-License-Identifier: MIT */
/* compressedDepth images (compressed_depth.h): the header, PNG through libpng, RVL. */
#include "mcap/compressed_depth.h"

#include <errno.h>
#include <math.h>
#include <png.h>
#include <setjmp.h>
#include <stdio.h>
#include <string.h>

int dao_cdepth_parse_format(const char *format, struct dao_cdepth_format *f)
{
	const char *semi = strchr(format, ';');
	size_t enc = semi ? (size_t)(semi - format) : strlen(format);
	memset(f, 0, sizeof(*f));
	if ((enc == 5 && !strncmp(format, "16UC1", 5)) || (enc == 6 && !strncmp(format, "mono16", 6)))
		f->is_float = 0;
	else if (enc == 5 && !strncmp(format, "32FC1", 5))
		f->is_float = 1;
	else
		return -EINVAL;
	if (!semi)
		return -EINVAL;
	const char *rest = semi + 1;
	while (*rest == ' ')
		rest++;
	if (strncmp(rest, "compressedDepth", 15))
		return -EINVAL;
	rest += 15;
	if (!*rest || !strcmp(rest, " png"))
		f->codec = DAO_CDEPTH_PNG;
	else if (!strcmp(rest, " rvl"))
		f->codec = DAO_CDEPTH_RVL;
	else
		return -EINVAL;
	return 0;
}

static uint32_t be32(const uint8_t *p)
{
	return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

static uint32_t le32(const uint8_t *p)
{
	return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

int dao_cdepth_size(const struct dao_cdepth_format *f, const uint8_t *data, size_t len,
		    uint32_t *width, uint32_t *height)
{
	const size_t hdr = f->plain ? 0 : DAO_CDEPTH_CONFIG_HEADER;
	const uint8_t *p = data + hdr;
	*width = *height = 0;
	if (len < hdr + 8)
		return -EINVAL;
	len -= hdr;
	if (f->codec == DAO_CDEPTH_RVL) {
		*width = le32(p);
		*height = le32(p + 4);
	} else {
		/* signature, IHDR length and type, width, height */
		if (len < 24 || png_sig_cmp(p, 0, 8) || memcmp(p + 12, "IHDR", 4))
			return -EINVAL;
		if (f->plain && (len < 26 || p[24] != 16 || p[25] != 0))
			return -EINVAL; /* not 16-bit grey: not depth */
		*width = be32(p + 16);
		*height = be32(p + 20);
	}
	return *width && *height ? 0 : -EINVAL;
}

/* RVL's reader: 32-bit words, nibbles from the top. */
struct rvl {
	const uint8_t *p, *end;
	uint32_t word;
	int nibbles;
	int bad;
};

static uint32_t rvl_value(struct rvl *r)
{
	uint32_t v = 0;
	for (int shift = 0;; shift += 3) {
		if (!r->nibbles) {
			if (r->end - r->p < 4) {
				r->bad = 1;
				return 0;
			}
			r->word = le32(r->p);
			r->p += 4;
			r->nibbles = 8;
		}
		uint32_t nib = r->word >> 28;
		r->word <<= 4;
		r->nibbles--;
		if (shift > 30) { /* more nibbles than a 32-bit value has */
			r->bad = 1;
			return 0;
		}
		v |= (nib & 7u) << shift;
		if (!(nib & 8))
			return v;
	}
}

int dao_rvl_decode(const uint8_t *in, size_t len, uint16_t *out, size_t n)
{
	struct rvl r = {in, in + len, 0, 0, 0};
	size_t at = 0;
	uint16_t prev = 0;
	while (at < n) {
		uint32_t zeros = rvl_value(&r);
		if (r.bad || zeros > n - at)
			return -EINVAL;
		memset(out + at, 0, zeros * sizeof(*out));
		at += zeros;
		uint32_t nonzeros = rvl_value(&r);
		if (r.bad || nonzeros > n - at)
			return -EINVAL;
		for (uint32_t i = 0; i < nonzeros; i++) {
			uint32_t z = rvl_value(&r);
			if (r.bad)
				return -EINVAL;
			/* zig-zag: 0, -1, 1, -2 ... */
			int32_t delta = (int32_t)(z >> 1) ^ -(int32_t)(z & 1);
			prev = (uint16_t)(prev + delta);
			out[at++] = prev;
		}
	}
	return 0;
}

struct png_mem {
	const uint8_t *p;
	size_t left;
	char *why;
	size_t why_len;
};

static void png_mem_read(png_structp png, png_bytep dst, png_size_t n)
{
	struct png_mem *m = png_get_io_ptr(png);
	if (n > m->left)
		png_error(png, "the PNG data ends early");
	memcpy(dst, m->p, n);
	m->p += n;
	m->left -= n;
}

static void png_mem_error(png_structp png, png_const_charp msg)
{
	struct png_mem *m = png_get_error_ptr(png);
	snprintf(m->why, m->why_len, "PNG: %s", msg);
	png_longjmp(png, 1);
}

static void png_mem_warning(png_structp png, png_const_charp msg)
{
	(void)png;
	(void)msg;
}

/* A 16-bit grey PNG of width x height into rows of uint16 (host order). */
static int decode_png(const uint8_t *data, size_t len, uint32_t width, uint32_t height,
		      uint8_t *out, size_t stride, char *why, size_t why_len)
{
	struct png_mem m = {data, len, why, why_len};
	png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &m, png_mem_error,
						 png_mem_warning);
	png_infop info = png ? png_create_info_struct(png) : NULL;
	if (!info) {
		png_destroy_read_struct(&png, NULL, NULL);
		snprintf(why, why_len, "out of memory");
		return -EINVAL;
	}
	if (setjmp(png_jmpbuf(png))) {
		png_destroy_read_struct(&png, &info, NULL);
		return -EINVAL;
	}
	png_set_read_fn(png, &m, png_mem_read);
	png_set_user_limits(png, width, height);
	png_read_info(png, info);
	if (png_get_image_width(png, info) != width || png_get_image_height(png, info) != height ||
	    png_get_bit_depth(png, info) != 16 || png_get_color_type(png, info) != PNG_COLOR_TYPE_GRAY ||
	    png_get_interlace_type(png, info) != PNG_INTERLACE_NONE) {
		snprintf(why, why_len, "PNG: not a %ux%u 16-bit grey image", width, height);
		png_destroy_read_struct(&png, &info, NULL);
		return -EINVAL;
	}
	const uint16_t one = 1;
	uint8_t little;
	memcpy(&little, &one, 1);
	if (little)
		png_set_swap(png);
	for (uint32_t y = 0; y < height; y++)
		png_read_row(png, out + (size_t)y * stride, NULL);
	png_destroy_read_struct(&png, &info, NULL);
	return 0;
}

int dao_cdepth_decode(const struct dao_cdepth_format *f, const uint8_t *data, size_t len,
		      uint32_t width, uint32_t height, void *out, size_t stride,
		      uint16_t *scratch, char *why, size_t why_len)
{
	uint32_t w, h;
	if (dao_cdepth_size(f, data, len, &w, &h) < 0) {
		snprintf(why, why_len, "%s", f->plain ? "not a 16-bit grey PNG"
						     : "no compressedDepth header and image");
		return -EINVAL;
	}
	if (w != width || h != height) {
		snprintf(why, why_len, "a %ux%u image, not %ux%u", w, h, width, height);
		return -EINVAL;
	}
	const size_t hdr = f->plain ? 0 : DAO_CDEPTH_CONFIG_HEADER;
	const uint8_t *img = data + hdr;
	size_t img_len = len - hdr;
	/* 16UC1 straight into the output; 32FC1 through the scratch image */
	uint8_t *dst = f->is_float ? (uint8_t *)scratch : out;
	size_t dst_stride = f->is_float ? (size_t)width * 2 : stride;
	int r;
	if (f->codec == DAO_CDEPTH_PNG) {
		r = decode_png(img, img_len, width, height, dst, dst_stride, why, why_len);
	} else {
		/* RVL decodes a packed image */
		int packed = dst_stride == (size_t)width * 2;
		r = dao_rvl_decode(img + 8, img_len - 8, packed ? (uint16_t *)dst : scratch,
				   (size_t)width * height);
		if (r < 0)
			snprintf(why, why_len, "RVL: the data ends before %ux%u values", width, height);
		for (uint32_t y = 0; r == 0 && !packed && y < height; y++)
			memcpy(dst + (size_t)y * dst_stride, scratch + (size_t)y * width,
			       (size_t)width * 2);
	}
	if (r < 0 || !f->is_float)
		return r;
	float a, b;
	memcpy(&a, data + 4, 4); /* written in the sender's byte order: little-endian machines */
	memcpy(&b, data + 8, 4);
	for (uint32_t y = 0; y < height; y++) {
		float *row = (float *)((uint8_t *)out + (size_t)y * stride);
		const uint16_t *src = scratch + (size_t)y * width;
		for (uint32_t x = 0; x < width; x++)
			row[x] = src[x] ? a / ((float)src[x] - b) : NAN;
	}
	return 0;
}
