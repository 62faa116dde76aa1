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
	/* implausible for the image (issue 38): named with the value and the range */
	expect_invalid(dao_camera_from_intrinsics(&cam, 640, 480, 1e308, 525, 319.5, 239.5, &err),
		       &err, "fx=1e+308 is implausible for 640x480 images");
	expect_invalid(dao_camera_from_intrinsics(&cam, 640, 480, 525, 5e-324, 319.5, 239.5, &err),
		       &err, "fy=4.94066e-324");
	expect_invalid(dao_camera_from_intrinsics(&cam, 640, 480, 525, 525, 1e9, 239.5, &err),
		       &err, "cx=1e+09");
	expect_invalid(dao_camera_from_intrinsics(&cam, 640, 480, 525, 525, 319.5, -1e9, &err),
		       &err, "cy=-1e+09");
	expect_invalid(dao_camera_from_intrinsics(&cam, 640, 480, 525, 525, 319.5, 239.5 + 3 * 480,
						  &err), &err, "from -480 to 960");
	expect_invalid(dao_camera_from_intrinsics(&cam, 640, 480, 640 * 1000.5, 525, 319.5, 239.5,
						  &err), &err, "from 3.2 to 640000");
	expect_invalid(dao_camera_from_intrinsics(&cam, 640, 480, 3.1, 525, 319.5, 239.5, &err),
		       &err, "fx=3.1");
	/* the edges are inside: 1/200 and 1000 times the larger side, one image size out */
	assert_int_equal(dao_camera_from_intrinsics(&cam, 640, 480, 3.2, 640000, -640, 960, &err), 0);
	assert_int_equal(dao_camera_from_intrinsics(&cam, 640, 480, 525, 525, 1280, -480, &err), 0);
	/* a CameraInfo goes through the same rule */
	const double k_big[9] = { 1e308, 0, 319.5, 0, 525, 239.5, 0, 0, 1 };
	expect_invalid(dao_camera_from_camera_info(&cam, 640, 480, k_big, NULL, NULL, 0, NULL, &err),
		       &err, "fx=1e+308");
	dao_camera_from_intrinsics(&cam, 640, 480, 525, 525, 319.5, 239.5, NULL);
	assert_int_equal(dao_camera_view_to_pixel(&cam, p, &u, &v), -EDOM);
	p[2] = -1;
	assert_int_equal(dao_camera_view_to_pixel(&cam, p, &u, &v), -EDOM);
	p[2] = NAN;
	assert_int_equal(dao_camera_view_to_pixel(&cam, p, &u, &v), -EDOM);
}

/*
 * A CameraInfo's intrinsics: K without distortion; with distortion P (the
 * rectified image's camera), or K when P is not usable; refused values say
 * which matrix was wrong.
 */
static void test_camera_info(void **state)
{
	(void)state;
	const double k[9] = { 50, 0, 31, 0, 51, 23, 0, 0, 1 };
	const double p[12] = { 45, 0, 30, 0, 0, 46.5, 22, 0, 0, 0, 1, 0 };
	const double none[5] = { 0, 0, 0, 0, 0 }, plumb[5] = { -0.1, 0.02, 0, 0, 0 };
	struct dao_camera cam;
	struct dao_error err;
	enum dao_camera_info_matrix from = DAO_CAMERA_INFO_P_RECTIFIED;
	/* no distortion: K, whatever P says */
	assert_int_equal(dao_camera_from_camera_info(&cam, 64, 48, k, p, none, 5, &from, &err), 0);
	assert_int_equal(from, DAO_CAMERA_INFO_K);
	assert_true(cam.fx == 50 && cam.fy == 51 && cam.cx == 31 && cam.cy == 23);
	assert_true(cam.width == 64 && cam.height == 48);
	assert_int_equal(dao_camera_from_camera_info(&cam, 64, 48, k, NULL, NULL, 0, &from, &err), 0);
	assert_int_equal(from, DAO_CAMERA_INFO_K);
	assert_true(cam.fx == 50 && cam.cy == 23);
	/* distortion and a usable P: P's, the same camera as from its intrinsics */
	assert_int_equal(dao_camera_from_camera_info(&cam, 64, 48, k, p, plumb, 5, &from, &err), 0);
	assert_int_equal(from, DAO_CAMERA_INFO_P_RECTIFIED);
	struct dao_camera want;
	assert_int_equal(dao_camera_from_intrinsics(&want, 64, 48, 45, 46.5, 30, 22, NULL), 0);
	assert_memory_equal(&cam, &want, sizeof cam);
	/* one coefficient not 0 is distortion (the last of 8, rational_polynomial) */
	const double rational[8] = { 0, 0, 0, 0, 0, 0, 0, 1e-6 };
	assert_int_equal(dao_camera_from_camera_info(&cam, 64, 48, k, p, rational, 8, &from, &err), 0);
	assert_int_equal(from, DAO_CAMERA_INFO_P_RECTIFIED);
	/* distortion and an unusable P (an uncalibrated driver's zeros, none, not
	 * finite, a negative focal length): K's, and the caller is told */
	const double zeros[12] = { 0 };
	double bad_p[12];
	const double bad_values[] = { NAN, INFINITY, -45 };
	const int where[] = { 0, 5, 2, 6 };
	assert_int_equal(dao_camera_from_camera_info(&cam, 64, 48, k, zeros, plumb, 5, &from, &err), 0);
	assert_int_equal(from, DAO_CAMERA_INFO_K_DISTORTED);
	assert_true(cam.fx == 50 && cam.fy == 51 && cam.cx == 31 && cam.cy == 23);
	from = DAO_CAMERA_INFO_K;
	assert_int_equal(dao_camera_from_camera_info(&cam, 64, 48, k, NULL, plumb, 5, &from, &err), 0);
	assert_int_equal(from, DAO_CAMERA_INFO_K_DISTORTED);
	for (int w = 0; w < 4; w++)
		for (int b = 0; b < 3; b++) {
			if (b == 2 && (where[w] == 2 || where[w] == 6))
				continue; /* a negative principal point is a camera */
			memcpy(bad_p, p, sizeof bad_p);
			bad_p[where[w]] = bad_values[b];
			from = DAO_CAMERA_INFO_P_RECTIFIED;
			assert_int_equal(dao_camera_from_camera_info(&cam, 64, 48, k, bad_p, plumb, 5,
								     &from, &err), 0);
			assert_int_equal(from, DAO_CAMERA_INFO_K_DISTORTED);
			assert_true(cam.fx == 50);
		}
	/* K refused: zero, negative or not finite, with a message naming K */
	double bad_k[9];
	const int kwhere[] = { 0, 4, 2, 5 };
	const double kbad[] = { 0, -50, NAN, INFINITY };
	for (int w = 0; w < 4; w++)
		for (int b = 0; b < 4; b++) {
			if (b < 2 && (kwhere[w] == 2 || kwhere[w] == 5))
				continue;
			memcpy(bad_k, k, sizeof bad_k);
			bad_k[kwhere[w]] = kbad[b];
			expect_invalid(dao_camera_from_camera_info(&cam, 64, 48, bad_k, p, none, 5, NULL,
								   &err), &err, "K (camera_matrix)");
			assert_non_null(strstr(err.message, kwhere[w] == 2 || kwhere[w] == 5
								    ? "principal point" : "focal"));
			/* with distortion and a usable P, K is not what is used */
			assert_int_equal(dao_camera_from_camera_info(&cam, 64, 48, bad_k, p, plumb, 5,
								     NULL, &err), 0);
			assert_true(cam.fx == 45);
		}
	expect_invalid(dao_camera_from_camera_info(&cam, 0, 48, k, p, none, 5, NULL, &err), &err,
		       "size");
	expect_invalid(dao_camera_from_camera_info(&cam, 64, 48, NULL, p, none, 5, NULL, &err), &err,
		       "no K");
	expect_invalid(dao_camera_from_camera_info(&cam, 64, 48, k, p, NULL, 5, NULL, &err), &err,
		       "distortion");
	expect_invalid(dao_camera_from_camera_info(NULL, 64, 48, k, p, none, 5, NULL, &err), &err,
		       "NULL");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_round_trip),
		cmocka_unit_test(test_uv_to_view_params),
		cmocka_unit_test(test_fov),
		cmocka_unit_test(test_errors),
		cmocka_unit_test(test_camera_info),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
