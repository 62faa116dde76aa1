/* SPDX-License-Identifier: MIT */
/* Small .oni recordings whose frames say which frame they are. */
#ifndef DAO_TEST_SOURCE_UTIL_H
#define DAO_TEST_SOURCE_UTIL_H

#include <stdint.h>
#include <stdio.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

#define TEST_W 37
#define TEST_H 23
#define TEST_FPS 30

/* Depth of pixel (x, y) in frame f: distinct per frame, some holes. */
static inline uint16_t test_depth(uint32_t f, uint32_t x, uint32_t y)
{
	if ((x * 7 + y * 3 + f) % 29 == 0)
		return 0;
	return (uint16_t)(800 + 40 * f + 3 * x + 5 * y + (x * y) % 7);
}

/* Writes `frames` frames with codec `codec` to `path`; 0 or a negative code. */
static inline int test_write_oni(const char *path, uint32_t frames, enum dao_oni_codec codec)
{
	struct dao_oni_writer_options o = DAO_ONI_WRITER_OPTIONS_INIT;
	o.width = TEST_W;
	o.height = TEST_H;
	o.fps = TEST_FPS;
	o.codec = codec;
	o.pixel_format = DAO_ONI_PIXEL_DEPTH_1_MM;
	o.hfov = 1.0;
	o.vfov = 0.75;
	o.overwrite = 1;
	struct dao_oni_writer *w;
	struct dao_frame d;
	struct dao_error err;
	int r = dao_oni_writer_open(path, &o, &w, &err);
	if (r < 0)
		return r;
	if ((r = dao_frame_alloc(&d, DAO_PIXFMT_DEPTH16, TEST_W, TEST_H, &err)) < 0) {
		dao_oni_writer_abort(w);
		return r;
	}
	d.depth_unit = 0.001f;
	for (uint32_t f = 0; f < frames && r == 0; f++) {
		for (uint32_t y = 0; y < TEST_H; y++)
			for (uint32_t x = 0; x < TEST_W; x++)
				((uint16_t *)d.data)[y * TEST_W + x] = test_depth(f, x, y);
		r = dao_oni_writer_write_depth(w, &d, 1000 + (uint64_t)f * 33333, &err);
	}
	dao_frame_free(&d);
	if (r < 0) {
		dao_oni_writer_abort(w);
		return r;
	}
	return dao_oni_writer_finish(w, &err);
}

/* 1 if `frame` holds recorded frame f exactly. */
static inline int test_is_frame(const struct dao_frame *d, uint32_t f)
{
	if (d->format != DAO_PIXFMT_DEPTH16 || d->width != TEST_W || d->height != TEST_H)
		return 0;
	for (uint32_t y = 0; y < TEST_H; y++) {
		const uint16_t *row = (const uint16_t *)((const uint8_t *)d->data + (size_t)y * (size_t)d->stride);
		for (uint32_t x = 0; x < TEST_W; x++)
			if (row[x] != test_depth(f, x, y))
				return 0;
	}
	return 1;
}

/* Opens and starts a source (cmocka asserts; needs <cmocka.h> first). */
static inline struct dao_source *test_open_started(const struct dao_plugins *p, const char *uri,
						    const struct dao_source_options *o)
{
	struct dao_source *s = NULL;
	struct dao_error err;
	int r = dao_source_open(p, uri, o, &s, &err);
	if (r)
		fprintf(stderr, "open %s: %s\n", uri, err.message);
	assert_int_equal(r, 0);
	assert_int_equal(dao_source_start(s, &err), 0);
	return s;
}

#endif
