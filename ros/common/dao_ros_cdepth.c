/* SPDX-License-Identifier: MIT */
/*
 * compressedDepth encoding of a depth image (dao_ros_cdepth.h): the
 * ConfigHeader, PNG through libdepthao-io's dao_png_encode, RVL written here
 * from Wilson's description of the algorithm.
 */
#include "dao_ros_cdepth.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/png.h>

#define CONFIG_HEADER 12

void dao_ros_cdepth_init(struct dao_ros_cdepth *c)
{
	memset(c, 0, sizeof *c);
	c->codec = DAO_ROS_CDEPTH_PNG;
	c->png_level = 1;
	c->depth_max = 10.0;
	c->depth_quantization = 100.0;
}

void dao_ros_cdepth_free(struct dao_ros_cdepth *c)
{
	free(c->buf);
	c->buf = NULL;
	c->cap = c->len = 0;
}

static int number(const char *name, const char *value, double lo, double hi, double *out,
		  struct dao_error *err)
{
	char *end;
	double v = strtod(value, &end);
	if (end == value || *end || !(v >= lo && v <= hi))
		return dao_error_set(err, -EINVAL, "compressedDepth/%s: '%s' is not a number in [%g, %g]",
			    name, value, lo, hi);
	*out = v;
	return 0;
}

int dao_ros_cdepth_set(struct dao_ros_cdepth *c, const char *name, const char *value,
		       struct dao_error *err)
{
	double v = 0.0;
	int r;
	if (!strcmp(name, "format")) {
		if (!strcmp(value, "png"))
			c->codec = DAO_ROS_CDEPTH_PNG;
		else if (!strcmp(value, "rvl"))
			c->codec = DAO_ROS_CDEPTH_RVL;
		else
			return dao_error_set(err, -EINVAL, "compressedDepth/format: '%s' is not png or rvl",
				    value);
		return 0;
	}
	if (!strcmp(name, "png_level")) {
		if ((r = number(name, value, 1, 9, &v, err)))
			return r;
		if (v != floor(v))
			return dao_error_set(err, -EINVAL, "compressedDepth/png_level: '%s' is not an "
				    "integer in [1, 9]", value);
		c->png_level = (int)v;
		return 0;
	}
	if (!strcmp(name, "depth_max"))
		return number(name, value, 1, 100, &c->depth_max, err);
	if (!strcmp(name, "depth_quantization"))
		return number(name, value, 1, 150, &c->depth_quantization, err);
	return dao_error_set(err, -ENOENT, "'%s' is not a compressedDepth setting", name);
}

/* RVL's writer: nibbles into a 32-bit word from the bottom up, the word stored
 * little-endian when full (so the first nibble is the word's top one). */
struct rvl_out {
	uint8_t *p;
	uint32_t word;
	int nibbles;
};

static void put_word(struct rvl_out *o, uint32_t w)
{
	o->p[0] = (uint8_t)w;
	o->p[1] = (uint8_t)(w >> 8);
	o->p[2] = (uint8_t)(w >> 16);
	o->p[3] = (uint8_t)(w >> 24);
	o->p += 4;
}

static void put_value(struct rvl_out *o, uint32_t v)
{
	do {
		uint32_t nib = v & 7u;
		v >>= 3;
		if (v)
			nib |= 8u;
		o->word = o->word << 4 | nib;
		if (++o->nibbles == 8) {
			put_word(o, o->word);
			o->word = 0;
			o->nibbles = 0;
		}
	} while (v);
}

size_t dao_ros_rvl_encode(const uint16_t *in, size_t n, uint8_t *out)
{
	struct rvl_out o = {out, 0, 0};
	size_t i = 0;
	uint16_t prev = 0;
	while (i < n) {
		size_t z = i;
		while (z < n && !in[z])
			z++;
		put_value(&o, (uint32_t)(z - i));
		size_t nz = z;
		while (nz < n && in[nz])
			nz++;
		put_value(&o, (uint32_t)(nz - z));
		for (size_t k = z; k < nz; k++) {
			int32_t d = (int32_t)in[k] - (int32_t)prev;
			/* zig-zag: 0, -1, 1, -2, 2 ... -> 0, 1, 2, 3, 4 ... */
			put_value(&o, d >= 0 ? (uint32_t)d << 1 : ((uint32_t)(-d) << 1) - 1u);
			prev = in[k];
		}
		i = nz;
	}
	if (o.nibbles)
		put_word(&o, o.word << (4 * (8 - o.nibbles)));
	return (size_t)(o.p - out);
}

static void put_f32(uint8_t *p, float f)
{
	uint32_t u;
	memcpy(&u, &f, 4);
	for (int i = 0; i < 4; i++)
		p[i] = (uint8_t)(u >> (8 * i));
}

static int reserve(struct dao_ros_cdepth *c, size_t need, struct dao_error *err)
{
	if (need <= c->cap)
		return 0;
	uint8_t *b = realloc(c->buf, need);
	if (!b)
		return dao_error_set(err, -ENOMEM, "compressedDepth: out of memory for %zu bytes", need);
	c->buf = b;
	c->cap = need;
	return 0;
}

/* The 16-bit values to compress into c->buf + off (packed rows): the counts, or
 * 32FC1 metres as quantised inverse depth. */
static void values(const struct dao_ros_cdepth *c, const struct dao_ros_output *d, float qa,
		   float qb, uint16_t *v)
{
	const int f32 = !strcmp(d->encoding, "32FC1");
	const float zmax = (float)c->depth_max;
	for (uint32_t y = 0; y < d->height; y++) {
		const uint8_t *row = (const uint8_t *)d->data + (size_t)y * d->step;
		for (uint32_t x = 0; x < d->width; x++) {
			if (!f32) {
				memcpy(&v[(size_t)y * d->width + x], row + 2 * (size_t)x, 2);
				continue;
			}
			float z;
			memcpy(&z, row + 4 * (size_t)x, 4);
			float q = z > 0.0f && z < zmax ? qa / z + qb : 0.0f; /* NaN: no depth */
			v[(size_t)y * d->width + x] = q >= 65535.0f ? 65535 : (uint16_t)q;
		}
	}
}

int dao_ros_cdepth_encode(struct dao_ros_cdepth *c, const struct dao_ros_output *depth,
			  struct dao_error *err)
{
	const int f32 = depth->encoding && !strcmp(depth->encoding, "32FC1");
	if (!depth->data || !depth->width || !depth->height || !depth->encoding ||
	    (!f32 && strcmp(depth->encoding, "16UC1")) ||
	    depth->step < depth->width * (f32 ? 4u : 2u))
		return dao_error_set(err, -EINVAL, "compressedDepth: not a 16UC1 or 32FC1 depth image");
	const size_t n = (size_t)depth->width * depth->height;
	/* the values first, at the end of the buffer, then the header and data before them */
	const size_t vals = CONFIG_HEADER + 8 + dao_ros_rvl_bound(n);
	int r = reserve(c, vals + 2 * n, err);
	if (r)
		return r;
	const float qa = f32 ? (float)(c->depth_quantization * (c->depth_quantization + 1.0)) : 0.0f;
	const float qb = f32 ? 1.0f - qa / (float)c->depth_max : 0.0f;
	uint16_t *v = (uint16_t *)(void *)(c->buf + vals); /* vals is even */
	values(c, depth, qa, qb, v);
	memset(c->buf, 0, 4); /* format 0: inverse depth, as the publisher writes */
	put_f32(c->buf + 4, qa);
	put_f32(c->buf + 8, qb);
	snprintf(c->format, sizeof c->format, "%s; compressedDepth %s", f32 ? "32FC1" : "16UC1",
		 c->codec == DAO_ROS_CDEPTH_RVL ? "rvl" : "png");
	if (c->codec == DAO_ROS_CDEPTH_RVL) {
		uint8_t *p = c->buf + CONFIG_HEADER;
		for (int i = 0; i < 4; i++) {
			p[i] = (uint8_t)(depth->width >> (8 * i));
			p[4 + i] = (uint8_t)(depth->height >> (8 * i));
		}
		c->len = CONFIG_HEADER + 8 + dao_ros_rvl_encode(v, n, p + 8);
		return 0;
	}
	struct dao_frame f = {
		.size = DAO_FRAME_SIZE, .format = DAO_PIXFMT_GRAY16, .width = depth->width,
		.height = depth->height, .stride = (int32_t)(depth->width * 2), .data = v,
	};
	void *png = NULL;
	size_t len = 0;
	if ((r = dao_png_encode(&f, c->png_level, &png, &len, err)))
		return r;
	r = reserve(c, CONFIG_HEADER + len > vals ? CONFIG_HEADER + len : 0, err);
	if (!r) {
		memcpy(c->buf + CONFIG_HEADER, png, len);
		c->len = CONFIG_HEADER + len;
	}
	free(png);
	return r;
}
