/* SPDX-License-Identifier: MIT */
/*
 * V4L2 depth capture against the emulated driver: negotiation (formats,
 * sizes, driver adjustment, fps), streamed values and units, Kinect Y10B
 * disparity, device lookup by card/bus/any, listing, unplug mid-stream, and
 * no ioctl that breaks the specification's rules.
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include <linux/videodev2.h>

#include "v4l2_capture.h"
#include "v4l2_emu.h"

static const uint32_t Z16[] = {V4L2_PIX_FMT_Z16};
static const uint32_t Y16_Z16[] = {V4L2_PIX_FMT_Y16, V4L2_PIX_FMT_Z16};
static const uint32_t Y10B[] = {V4L2_PIX_FMT_Y10BPACK};
static const uint32_t YUYV[] = {V4L2_PIX_FMT_YUYV};
static const struct emu_size sizes[] = {{640, 480}, {320, 240}, {1280, 720}};

static struct emu *rig(unsigned fail_after)
{
	struct emu *e = emu_create();
	emu_add_capture(e, "/dev/video0", "Integrated Webcam", "usb-0000:00:14.0-5", YUYV, 1, sizes,
			2, 0);
	emu_add_capture(e, "/dev/video2", "Intel(R) RealSense(TM) Depth Ca", "usb-0000:00:14.0-2",
			Z16, 1, sizes, 3, fail_after);
	emu_add_capture(e, "/dev/video4", "Kinect Depth", "usb-0000:00:14.0-3", Y10B, 1, sizes, 1, 0);
	emu_add_capture(e, "/dev/video6", "Stepwise Depth", "platform:tof", Y16_Z16, 2, NULL, 0, 0);
	return e;
}

static struct v4l2cap *open_ok(struct emu *e, const char *uri, float unit)
{
	struct dao_source_options o = {.size = sizeof(struct dao_source_options), .depth_unit = unit};
	struct dao_error err = {0};
	struct v4l2cap *c = NULL;
	int r = v4l2cap_open(emu_io(e), uri, &o, &c, &err);
	if (r)
		fprintf(stderr, "%s: %s\n", uri, err.message);
	assert_int_equal(r, 0);
	assert_int_equal(v4l2cap_start(c, &err), 0);
	return c;
}

static void test_z16_stream(void **state)
{
	(void)state;
	struct emu *e = rig(0);
	struct v4l2cap *c = open_ok(e, "/dev/video2", 0);
	struct dao_source_info in;
	memset(&in, 0, sizeof in);
	v4l2cap_info(c, &in);
	assert_int_equal(in.width, 640);
	assert_int_equal(in.height, 480);
	assert_float_equal(in.depth_unit, 0.001, 1e-9); /* RealSense default */
	assert_int_equal(in.live, 1);
	assert_int_equal(in.has_fov, 0); /* V4L2 does not know it */
	assert_float_equal(in.fps, 30, 0);
	assert_non_null(strstr(in.description, "RealSense"));
	struct dao_error err;
	for (uint32_t n = 0; n < 10; n++) { /* more frames than buffers: the ring turns */
		struct dao_source_frame f;
		assert_int_equal(v4l2cap_read(c, &f, 100, &err), 0);
		assert_int_equal(f.index, n);
		assert_int_equal(f.depth.sequence, n);
		assert_int_equal(f.depth.format, DAO_PIXFMT_DEPTH16);
		const uint16_t *d = f.depth.data;
		for (uint32_t y = 0; y < 480; y += 37)
			for (uint32_t x = 0; x < 640; x += 41)
				assert_int_equal(d[y * 640 + x], emu_depth_at(n, x, y));
	}
	v4l2cap_close(c);
	assert_int_equal(emu_protocol_errors(e), 0);
	emu_destroy(e);
}

static void test_size_fps_unit_options(void **state)
{
	(void)state;
	struct emu *e = rig(0);
	struct dao_source_info in;
	struct v4l2cap *c = open_ok(e, "/dev/video2?size=320x240&fps=60&unit=0.0001", 0.001f);
	v4l2cap_info(c, &in);
	assert_int_equal(in.width, 320);
	assert_float_equal(in.fps, 60, 0);
	assert_float_equal(in.depth_unit, 0.0001, 1e-9); /* D405-style, the URI wins */
	v4l2cap_close(c);
	/* a size the camera does not offer: the nearest one it does */
	c = open_ok(e, "/dev/video2?size=1270x700", 0);
	v4l2cap_info(c, &in);
	assert_int_equal(in.width, 1280);
	assert_int_equal(in.height, 720);
	v4l2cap_close(c);
	/* stepwise: an odd size is adjusted by the driver to its steps */
	c = open_ok(e, "/dev/video6?size=333x211", 0);
	v4l2cap_info(c, &in);
	assert_int_equal(in.width, 332);
	assert_int_equal(in.height, 210);
	struct dao_source_frame f;
	struct dao_error err;
	assert_int_equal(v4l2cap_read(c, &f, 100, &err), 0);
	assert_int_equal(((const uint16_t *)f.depth.data)[209 * 332 + 331], emu_depth_at(0, 331, 209));
	v4l2cap_close(c);
	/* format choice: Z16 is preferred over Y16; format= picks */
	c = open_ok(e, "/dev/video6?format=y16", 0);
	v4l2cap_info(c, &in);
	assert_non_null(strstr(in.description, "Y16"));
	v4l2cap_close(c);
	c = open_ok(e, "/dev/video6", 0);
	v4l2cap_info(c, &in);
	assert_non_null(strstr(in.description, "Z16"));
	v4l2cap_close(c);
	assert_int_equal(emu_protocol_errors(e), 0);
	emu_destroy(e);
}

static void test_kinect_y10b(void **state)
{
	(void)state;
	/* the conversion itself: Burrus' fit, 2047 = no data */
	assert_int_equal(v4l2_kinect_disparity_to_mm(2047), 0);
	assert_int_equal(v4l2_kinect_disparity_to_mm(0), 300); /* 1 / 3.3309 m */
	assert_int_equal(v4l2_kinect_disparity_to_mm(800), 1144);  /* 1 / 0.874068 m */
	assert_int_equal(v4l2_kinect_disparity_to_mm(1000), 3848); /* 1 / 0.259848 m */
	assert_int_equal(v4l2_kinect_disparity_to_mm(1084), 0);    /* beyond 10 m (z < 0 at 1085) */
	struct emu *e = rig(0);
	struct v4l2cap *c = open_ok(e, "/dev/video4", 0.0001f /* ignored: Y10B is converted to mm */);
	struct dao_source_info in;
	v4l2cap_info(c, &in);
	assert_float_equal(in.depth_unit, 0.001, 1e-9);
	struct dao_error err;
	for (uint32_t n = 0; n < 3; n++) {
		struct dao_source_frame f;
		assert_int_equal(v4l2cap_read(c, &f, 100, &err), 0);
		const uint16_t *d = f.depth.data;
		for (uint32_t y = 0; y < 480; y += 13)
			for (uint32_t x = 0; x < 640; x++)
				assert_int_equal(d[y * 640 + x],
						 v4l2_kinect_disparity_to_mm(emu_disparity_at(n, x, y)));
	}
	v4l2cap_close(c);
	emu_destroy(e);
}

static void test_lookup_and_list(void **state)
{
	(void)state;
	struct emu *e = rig(0);
	struct dao_source_info in;
	struct v4l2cap *c = open_ok(e, "any", 0); /* not the webcam: the first depth camera */
	v4l2cap_info(c, &in);
	assert_non_null(strstr(in.description, "/dev/video2"));
	v4l2cap_close(c);
	c = open_ok(e, "card=Kinect Depth", 0);
	v4l2cap_info(c, &in);
	assert_non_null(strstr(in.description, "/dev/video4"));
	v4l2cap_close(c);
	c = open_ok(e, "bus=platform:tof", 0);
	v4l2cap_info(c, &in);
	assert_non_null(strstr(in.description, "/dev/video6"));
	v4l2cap_close(c);
	struct dao_error err;
	struct dao_source_options o = {.size = sizeof(struct dao_source_options)};
	assert_int_equal(v4l2cap_open(emu_io(e), "card=Nothing", &o, &c, &err), -ENODEV);
	assert_non_null(strstr(err.message, "no depth camera matches 'card=Nothing'"));
	assert_int_equal(v4l2cap_open(emu_io(e), "/dev/video0", &o, &c, &err), -ENOTSUP);
	assert_non_null(strstr(err.message, "no depth format"));
	assert_int_equal(v4l2cap_open(emu_io(e), "/dev/video2?format=Y10B", &o, &c, &err), -ENOTSUP);
	assert_non_null(strstr(err.message, "does not offer Y10B"));
	assert_int_equal(v4l2cap_open(emu_io(e), "/dev/video9", &o, &c, &err), -ENODEV);
	assert_int_equal(v4l2cap_open(emu_io(e), "/dev/video2?size=big", &o, &c, &err), -EINVAL);
	assert_int_equal(v4l2cap_open(emu_io(e), "/dev/video2?unit=7", &o, &c, &err), -EINVAL);
	assert_int_equal(v4l2cap_open(emu_io(e), "/dev/video2?color=red", &o, &c, &err), -EINVAL);
	assert_int_equal(emu_protocol_errors(e), 0);
	emu_destroy(e);
}

struct listing {
	int n;
	char text[1024];
};

static void on_device(void *user, const struct dao_device_entry *d)
{
	struct listing *l = user;
	size_t len = strlen(l->text);
	snprintf(l->text + len, sizeof l->text - len, "%s|%s|%s\n", d->uri, d->name, d->detail);
	l->n++;
}

static void test_listing(void **state)
{
	(void)state;
	struct emu *e = rig(0);
	struct listing l = {0, ""};
	struct dao_error err;
	assert_int_equal(v4l2cap_list(emu_io(e), on_device, &l, &err), 3);
	assert_int_equal(l.n, 3);
	assert_null(strstr(l.text, "Webcam")); /* no depth format: not listed */
	assert_non_null(strstr(l.text, "/dev/video2|Intel(R) RealSense(TM) Depth Ca (usb-0000:00:14.0-2)|Z16 640x480"));
	assert_non_null(strstr(l.text, "/dev/video4|Kinect Depth"));
	assert_non_null(strstr(l.text, "Y16 640x480, Z16 640x480"));
	emu_destroy(e);
}

static void test_unplug(void **state)
{
	(void)state;
	struct emu *e = rig(5);
	struct v4l2cap *c = open_ok(e, "/dev/video2", 0);
	struct dao_error err;
	struct dao_source_frame f;
	int got = 0, r;
	while ((r = v4l2cap_read(c, &f, 100, &err)) == 0)
		got++;
	assert_int_equal(got, 5); /* every frame the device delivered */
	assert_int_equal(r, -ENODEV);
	assert_non_null(strstr(err.message, "/dev/video2"));
	assert_non_null(strstr(err.message, "disconnected"));
	assert_int_equal(v4l2cap_read(c, &f, 100, &err), -ENODEV); /* and it stays gone */
	v4l2cap_close(c);
	/* reopening a device that is gone: -ENODEV, which the daemon retries */
	struct dao_source_options o = {.size = sizeof(struct dao_source_options)};
	assert_int_equal(v4l2cap_open(emu_io(e), "/dev/video2", &o, &c, &err), -ENODEV);
	emu_destroy(e);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_z16_stream),   cmocka_unit_test(test_size_fps_unit_options),
		cmocka_unit_test(test_kinect_y10b),  cmocka_unit_test(test_lookup_and_list),
		cmocka_unit_test(test_listing),      cmocka_unit_test(test_unplug),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
