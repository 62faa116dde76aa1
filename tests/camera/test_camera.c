/* SPDX-License-Identifier: MIT */
#include <errno.h>
#include <math.h>
#include <string.h>

#include "common/cmocka_all.h"
#include "common/test_common.h"

#define PI 3.14159265358979323846

static void round_trip(uint32_t w, uint32_t h, double fx, double fy, double cx, double cy)
{
	struct dao_camera cam;
	assert_int_equal(dao_camera_from_intrinsics(&cam, w, h, fx, fy, cx, cy, NULL), 0);
	double worst = 0;
	for (uint32_t v = 0; v < h; v += 7)
		for (uint32_t u = 0; u < w; u += 5) {
			double z = 0.4 + 0.013 * ((u * 31 + v * 17) % 400); /* 0.4 .. 5.6 m */
			double p[3], uu, vv;
			dao_camera_pixel_to_view(&cam, u, v, z, p);
			assert_true(p[2] == z);
			assert_int_equal(dao_camera_view_to_pixel(&cam, p, &uu, &vv), 0);
			worst = fmax(worst, fmax(fabs(uu - u), fabs(vv - v)));
		}
	print_message("round trip %ux%u: worst %.2e px\n", w, h, worst);
	assert_true(worst < 1e-4);
}

static void test_round_trip(void **state)
{
	(void)state;
	round_trip(640, 480, 525, 525, 319.5, 239.5);
	round_trip(640, 480, 622.439, 622.439, 315.746, 250.804);
	round_trip(1280, 720, 910.3, 905.1, 650.2, 355.9); /* fx != fy, off-centre */
	round_trip(320, 240, 200, 260, 100, 200);
}

static void test_uv_to_view_params(void **state)
{
	(void)state;
	struct dao_camera cam;
	assert_int_equal(dao_camera_from_intrinsics(&cam, 640, 480, 500, 400, 320, 240, NULL), 0);
	assert_true(fabsf(cam.ax - 1.0f / 500) < 1e-9f && fabsf(cam.ay - 1.0f / 400) < 1e-9f);
	assert_true(fabsf(cam.bx + 320.0f / 500) < 1e-7f && fabsf(cam.by + 240.0f / 400) < 1e-7f);
	/* the principal point looks straight ahead; x grows right, y down (optical frame) */
	double p[3];
	dao_camera_pixel_to_view(&cam, 320, 240, 2, p);
	assert_true(fabs(p[0]) < 1e-12 && fabs(p[1]) < 1e-12);
	dao_camera_pixel_to_view(&cam, 570, 40, 2, p);
	assert_true(fabs(p[0] - 1.0) < 1e-12 && fabs(p[1] + 1.0) < 1e-12);
	/* the float UvToViewParams the kernels use agree with it */
	float xf = (570 * cam.ax + cam.bx) * 2.0f;
	assert_true(fabsf(xf - 1.0f) < 1e-5f);
}

static void test_fov(void **state)
{
	(void)state;
	struct dao_camera cam;
	/* the Kinect recording in ../shared/data: HFOV 1.01447, VFOV 0.78980 rad */
	assert_int_equal(dao_camera_from_fov(&cam, 640, 480, 1.01447, 0.78980, NULL), 0);
	assert_true(fabs(cam.fx - 575.8) < 0.1 && fabs(cam.fy - 575.8) < 0.2);
	assert_true(cam.cx == 319.5 && cam.cy == 239.5);
	assert_true(fabs(cam.fx - 320.0 / tan(1.01447 / 2)) < 1e-9);
	double h, v;
	dao_camera_fov(&cam, &h, &v);
	assert_true(fabs(h - 1.01447) < 1e-9 && fabs(v - 0.78980) < 1e-9);
	/* intrinsics -> fov -> intrinsics */
	struct dao_camera a, b;
	dao_camera_from_intrinsics(&a, 1280, 720, 910, 905, 639.5, 359.5, NULL);
	dao_camera_fov(&a, &h, &v);
	dao_camera_from_fov(&b, 1280, 720, h, v, NULL);
	assert_true(fabs(b.fx - 910) < 1e-9 && fabs(b.fy - 905) < 1e-9);
}

static void expect_invalid(int r, const struct dao_error *err, const char *needle)
{
	assert_int_equal(r, -EINVAL);
	assert_int_equal(err->code, -EINVAL);
	if (!strstr(err->message, needle))
		fail_msg("message '%s' lacks '%s'", err->message, needle);
}

static void test_errors(void **state)
{
	(void)state;
	struct dao_camera cam;
	struct dao_error err;
	expect_invalid(dao_camera_from_intrinsics(&cam, 640, 480, 0, 525, 1, 1, &err), &err, "focal");
	expect_invalid(dao_camera_from_intrinsics(&cam, 640, 480, -5, 525, 1, 1, &err), &err, "focal");
	expect_invalid(dao_camera_from_intrinsics(&cam, 640, 480, NAN, 525, 1, 1, &err), &err, "focal");
	expect_invalid(dao_camera_from_intrinsics(&cam, 640, 480, 525, INFINITY, 1, 1, &err), &err, "focal");
	expect_invalid(dao_camera_from_intrinsics(&cam, 640, 480, 525, 525, NAN, 1, &err), &err, "principal");
	expect_invalid(dao_camera_from_intrinsics(&cam, 0, 480, 525, 525, 1, 1, &err), &err, "size");
	expect_invalid(dao_camera_from_intrinsics(&cam, 640, 20000, 525, 525, 1, 1, &err), &err, "size");
	expect_invalid(dao_camera_from_intrinsics(NULL, 640, 480, 525, 525, 1, 1, &err), &err, "NULL");
	expect_invalid(dao_camera_from_fov(&cam, 640, 480, 0, 1, &err), &err, "field of view");
	expect_invalid(dao_camera_from_fov(&cam, 640, 480, 1, PI, &err), &err, "field of view");
	expect_invalid(dao_camera_from_fov(&cam, 640, 480, NAN, 1, &err), &err, "field of view");
	double u, v, p[3] = { 1, 1, 0 };
	dao_camera_from_intrinsics(&cam, 640, 480, 525, 525, 319.5, 239.5, NULL);
	assert_int_equal(dao_camera_view_to_pixel(&cam, p, &u, &v), -EDOM);
	p[2] = -1;
	assert_int_equal(dao_camera_view_to_pixel(&cam, p, &u, &v), -EDOM);
	p[2] = NAN;
	assert_int_equal(dao_camera_view_to_pixel(&cam, p, &u, &v), -EDOM);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_round_trip),
		cmocka_unit_test(test_uv_to_view_params),
		cmocka_unit_test(test_fov),
		cmocka_unit_test(test_errors),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
