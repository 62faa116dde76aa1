/* SPDX-License-Identifier: MIT */
/*
 * v4l2loopback output against the emulated driver: format negotiation
 * (YUYV default, RGB24, GREY; Y16 for depth; even widths), the bytes that reach the
 * device, colour conversion, a device without room, and refusing nodes
 * that are not outputs.
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <linux/videodev2.h>

#include "v4l2_emu.h"
#include "v4l2_output.h"

/* A sink format with its size set (DAO_SINK_FORMAT_INIT) */
#define FMT(f, w, h, rate) \
	((struct dao_sink_format){.size = sizeof(struct dao_sink_format), .format = (f), \
				  .width = (w), .height = (h), .fps = (rate)})

static const uint32_t Z16[] = {V4L2_PIX_FMT_Z16};
static const struct emu_size vga[] = {{640, 480}};

static struct emu *rig(void)
{
	struct emu *e = emu_create();
	emu_add_output(e, "/dev/video10", "Dummy video device (0x0000)");
	emu_add_capture(e, "/dev/video2", "Depth", "usb-1", Z16, 1, vga, 1, 0);
	return e;
}

static struct dao_frame rgb_frame(uint32_t w, uint32_t h, const uint8_t px[3])
{
	struct dao_frame f;
	assert_int_equal(dao_frame_alloc(&f, DAO_PIXFMT_RGB24, w, h, NULL), 0);
	for (size_t i = 0; i < (size_t)w * h; i++)
		memcpy((uint8_t *)f.data + 3 * i, px, 3);
	return f;
}

static struct v4l2out *open_neg(struct emu *e, const char *uri, struct dao_sink_format *fmt)
{
	struct v4l2out *o = NULL;
	struct dao_error err = {0};
	int r = v4l2out_open(emu_io(e), uri, &o, &err);
	if (r)
		fprintf(stderr, "%s: %s\n", uri, err.message);
	assert_int_equal(r, 0);
	enum dao_pixfmt asked = fmt->format;
	r = v4l2out_negotiate(o, fmt, &err);
	if (r)
		fprintf(stderr, "%s: %s\n", uri, err.message);
	assert_int_equal(r, 0);
	assert_int_equal(fmt->format, asked);
	return o;
}

static void test_yuyv_default(void **state)
{
	(void)state;
	struct emu *e = rig();
	struct dao_sink_format fmt = FMT(DAO_PIXFMT_RGB24, 64, 48, 30);
	struct v4l2out *o = open_neg(e, "/dev/video10", &fmt);
	struct dao_error err;
	static const struct {
		uint8_t rgb[3], y, u, v;
	} cases[] = {{{255, 255, 255}, 235, 128, 128}, {{0, 0, 0}, 16, 128, 128},
		     {{255, 0, 0}, 82, 90, 240},       {{0, 0, 255}, 41, 240, 110}};
	for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
		struct dao_frame f = rgb_frame(64, 48, cases[k].rgb);
		assert_int_equal(v4l2out_write(o, &f, &err), 0);
		size_t size;
		uint32_t pf, w, h;
		const uint8_t *got = emu_output_last(e, "/dev/video10", &size, &pf, &w, &h);
		assert_int_equal(pf, V4L2_PIX_FMT_YUYV);
		assert_int_equal(size, 64 * 48 * 2);
		for (size_t i = 0; i < size; i += 4) {
			assert_in_range(got[i], cases[k].y - 1, cases[k].y + 1);
			assert_in_range(got[i + 1], cases[k].u - 1, cases[k].u + 1);
			assert_in_range(got[i + 2], cases[k].y - 1, cases[k].y + 1);
			assert_in_range(got[i + 3], cases[k].v - 1, cases[k].v + 1);
		}
		dao_frame_free(&f);
	}
	assert_int_equal(emu_output_frames(e, "/dev/video10"), 4);
	v4l2out_close(o);
	assert_int_equal(emu_protocol_errors(e), 0);
	emu_destroy(e);
}

static void test_rgb24_and_grey_round_trip(void **state)
{
	(void)state;
	struct emu *e = rig();
	struct dao_error err;
	struct dao_sink_format fmt = FMT(DAO_PIXFMT_RGB24, 33, 7, 15); /* odd width is fine */
	struct v4l2out *o = open_neg(e, "/dev/video10?format=RGB24&fps=15", &fmt);
	struct dao_frame f;
	assert_int_equal(dao_frame_alloc(&f, DAO_PIXFMT_RGB24, 33, 7, NULL), 0);
	for (size_t i = 0; i < 33 * 7 * 3; i++)
		((uint8_t *)f.data)[i] = (uint8_t)(i * 7);
	assert_int_equal(v4l2out_write(o, &f, &err), 0);
	size_t size;
	uint32_t pf, w, h;
	const uint8_t *got = emu_output_last(e, "/dev/video10", &size, &pf, &w, &h);
	assert_int_equal(pf, V4L2_PIX_FMT_RGB24);
	assert_int_equal(w, 33);
	assert_memory_equal(got, f.data, 33 * 7 * 3);
	dao_frame_free(&f);
	v4l2out_close(o);

	struct dao_sink_format g = FMT(DAO_PIXFMT_GRAY8, 16, 4, 0);
	o = open_neg(e, "/dev/video10?format=GREY", &g);
	assert_int_equal(dao_frame_alloc(&f, DAO_PIXFMT_GRAY8, 16, 4, NULL), 0);
	memset(f.data, 77, 64);
	assert_int_equal(v4l2out_write(o, &f, &err), 0);
	got = emu_output_last(e, "/dev/video10", &size, &pf, &w, &h);
	assert_int_equal(pf, V4L2_PIX_FMT_GREY);
	assert_int_equal(size, 64);
	assert_int_equal(got[63], 77);
	dao_frame_free(&f);
	v4l2out_close(o);
	assert_int_equal(emu_protocol_errors(e), 0);
	emu_destroy(e);
}

static void test_negotiation_rules(void **state)
{
	(void)state;
	struct emu *e = rig();
	struct v4l2out *o;
	struct dao_error err;
	/* YUYV pairs pixels: an odd width is refused with what to do */
	assert_int_equal(v4l2out_open(emu_io(e), "/dev/video10", &o, &err), 0);
	struct dao_sink_format fmt = FMT(DAO_PIXFMT_RGB24, 33, 7, 0);
	assert_int_equal(v4l2out_negotiate(o, &fmt, &err), -EINVAL);
	assert_non_null(strstr(err.message, "even width"));
	/* 16-bit AO: the nearest is the 8-bit stream */
	fmt = FMT(DAO_PIXFMT_GRAY16, 32, 8, 0);
	assert_int_equal(v4l2out_negotiate(o, &fmt, &err), 0);
	assert_int_equal(fmt.format, DAO_PIXFMT_GRAY8);
	v4l2out_close(o);
	/* depth with an 8-bit format named: refused, saying to use Y16 */
	assert_int_equal(v4l2out_open(emu_io(e), "/dev/video10?format=GREY", &o, &err), 0);
	fmt = FMT(DAO_PIXFMT_DEPTH16, 32, 8, 0);
	assert_int_equal(v4l2out_negotiate(o, &fmt, &err), -ENOTSUP);
	assert_non_null(strstr(err.message, "format=Y16"));
	v4l2out_close(o);
	/* a capture node is not an output */
	assert_int_equal(v4l2out_open(emu_io(e), "/dev/video2", &o, &err), -ENOTSUP);
	assert_non_null(strstr(err.message, "not a video output"));
	assert_int_equal(v4l2out_open(emu_io(e), "/dev/video99", &o, &err), -ENODEV);
	assert_non_null(strstr(err.message, "v4l2loopback"));
	assert_int_equal(v4l2out_open(emu_io(e), "/dev/video10?format=MJPG", &o, &err), -EINVAL);
	emu_destroy(e);
}

/* The depth and filtered-depth streams (DEPTH16) go out as Y16 without ?format; with
 * ?format=Y16 the 16-bit AO too, and pictures are asked to come as the 16-bit AO. */
static void test_y16(void **state)
{
	(void)state;
	struct emu *e = rig();
	struct dao_error err;
	struct dao_sink_format fmt = FMT(DAO_PIXFMT_DEPTH16, 33, 5, 30); /* odd width is fine */
	struct v4l2out *o = open_neg(e, "/dev/video10", &fmt);
	struct dao_frame f;
	assert_int_equal(dao_frame_alloc(&f, DAO_PIXFMT_DEPTH16, 33, 5, NULL), 0);
	for (uint32_t y = 0; y < 5; y++)
		for (uint32_t x = 0; x < 33; x++)
			((uint16_t *)((uint8_t *)f.data + y * (size_t)f.stride))[x] =
				(uint16_t)(x == 3 ? 0 : 0x1234 + 257 * x + 4099 * y);
	assert_int_equal(v4l2out_write(o, &f, &err), 0);
	size_t size;
	uint32_t pf, w, h;
	const uint8_t *got = emu_output_last(e, "/dev/video10", &size, &pf, &w, &h);
	assert_int_equal(pf, V4L2_PIX_FMT_Y16);
	assert_int_equal(w, 33);
	assert_int_equal(size, 33 * 5 * 2);
	for (uint32_t y = 0; y < 5; y++)
		for (uint32_t x = 0; x < 33; x++) {
			uint16_t want = ((const uint16_t *)((const uint8_t *)f.data +
							    y * (size_t)f.stride))[x];
			const uint8_t *p = got + 2 * ((size_t)y * 33 + x);
			assert_int_equal(p[0] | p[1] << 8, want); /* little-endian, 0 kept */
		}
	dao_frame_free(&f);
	v4l2out_close(o);
	/* ?format=Y16: the 16-bit AO as it is; a picture is asked to come as it */
	struct dao_sink_format g = FMT(DAO_PIXFMT_GRAY16, 16, 4, 0);
	o = open_neg(e, "/dev/video10?format=Y16", &g);
	v4l2out_close(o);
	assert_int_equal(v4l2out_open(emu_io(e), "/dev/video10?format=Y16", &o, &err), 0);
	g = FMT(DAO_PIXFMT_RGB24, 16, 4, 0);
	assert_int_equal(v4l2out_negotiate(o, &g, &err), 0);
	assert_int_equal(g.format, DAO_PIXFMT_GRAY16);
	v4l2out_close(o);
	/* negotiated again before a write: depth, then a picture, gets YUYV back */
	assert_int_equal(v4l2out_open(emu_io(e), "/dev/video10", &o, &err), 0);
	g = FMT(DAO_PIXFMT_DEPTH16, 16, 4, 0);
	assert_int_equal(v4l2out_negotiate(o, &g, &err), 0);
	g = FMT(DAO_PIXFMT_RGB24, 16, 4, 0);
	assert_int_equal(v4l2out_negotiate(o, &g, &err), 0);
	assert_int_equal(g.format, DAO_PIXFMT_RGB24);
	const uint8_t grey[3] = {9, 9, 9};
	f = rgb_frame(16, 4, grey);
	assert_int_equal(v4l2out_write(o, &f, &err), 0);
	emu_output_last(e, "/dev/video10", &size, &pf, &w, &h);
	assert_int_equal(pf, V4L2_PIX_FMT_YUYV);
	dao_frame_free(&f);
	v4l2out_close(o);
	assert_int_equal(emu_protocol_errors(e), 0);
	emu_destroy(e);
}

static void test_no_room(void **state)
{
	(void)state;
	struct emu *e = rig();
	struct dao_error err;
	const uint8_t grey[3] = {128, 128, 128};
	struct dao_sink_format fmt = FMT(DAO_PIXFMT_RGB24, 16, 4, 0);
	struct v4l2out *o = open_neg(e, "/dev/video10", &fmt);
	struct dao_frame f = rgb_frame(16, 4, grey);
	emu_set_no_room(e, "/dev/video10", 1);
	for (int i = 0; i < 3; i++)
		assert_int_equal(v4l2out_write(o, &f, &err), 0); /* skipped, not an error */
	assert_int_equal(v4l2out_dropped(o), 3);
	assert_int_equal(emu_output_frames(e, "/dev/video10"), 0);
	emu_set_no_room(e, "/dev/video10", 0);
	assert_int_equal(v4l2out_write(o, &f, &err), 0);
	assert_int_equal(emu_output_frames(e, "/dev/video10"), 1);
	dao_frame_free(&f);
	v4l2out_close(o);
	emu_destroy(e);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_yuyv_default),
		cmocka_unit_test(test_rgb24_and_grey_round_trip),
		cmocka_unit_test(test_negotiation_rules),
		cmocka_unit_test(test_y16),
		cmocka_unit_test(test_no_room),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
