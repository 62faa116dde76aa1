/* SPDX-License-Identifier: MIT */
/*
 * An IMU's rotation from its messages (src/io/tf/imu_track.c): a constant
 * rate turned exactly; a hand's coning motion at 200 Hz against the same
 * rates integrated 1000 times finer; a turn about an axis that turns
 * against its closed form; samples out of order and repeated;
 * a gap not integrated across; orientations normalised.  And the
 * sensor_msgs/Imu parsers (ROS 1, ROS 2 CDR) on hand-made and truncated
 * messages.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include <errno.h>
#include <math.h>

#include "bag/ros_msg.h"
#include "mcap/ros2_msg.h"
#include "tf/imu_track.h"

#define MS 1000000ull
#define PI 3.14159265358979323846

/* the angle between two rotations, rad */
static double angle_between(const double a[4], const double b[4])
{
	double d = fabs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]);
	return 2.0 * acos(d > 1.0 ? 1.0 : d);
}

static void test_constant_rate(void **state)
{
	(void)state;
	enum { N = 401 };
	static struct dao_imu_sample s[N];
	const double w[3] = { 0.3, -0.2, 0.5 }, rate = sqrt(0.09 + 0.04 + 0.25);
	for (int i = 0; i < N; i++) {
		s[i] = (struct dao_imu_sample){ .stamp_ns = 1000 * MS + (uint64_t)i * 5 * MS };
		memcpy(s[i].w, w, sizeof w);
	}
	assert_int_equal(dao_imu_track(s, N, 0, 500 * MS), N);
	for (int i = 0; i < N; i += 50) { /* exp(w t / 2) */
		const double a = rate * (double)i * 0.005, k = sin(a / 2) / rate;
		const double want[4] = { w[0] * k, w[1] * k, w[2] * k, cos(a / 2) };
		assert_true(angle_between(s[i].q, want) < 1e-12);
	}
}

/* the Hamilton product, written here rather than taken from tf/rigid.c, which the code
 * under test uses: the reference stays independent of it */
static void quat_mul(const double a[4], const double b[4], double out[4])
{
	out[0] = a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1];
	out[1] = a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0];
	out[2] = a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3];
	out[3] = a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2];
}

/* a hand's coning motion: rates of a few Hz about axes that turn */
static void coning(double t, double w[3])
{
	w[0] = 0.8 * sin(2 * PI * 3.0 * t);
	w[1] = 0.8 * cos(2 * PI * 3.0 * t);
	w[2] = 0.2 * sin(2 * PI * 1.3 * t + 0.4);
}

static void test_coning_against_fine(void **state)
{
	(void)state;
	enum { N = 401, FINE = 1000 }; /* 2 s at 200 Hz */
	struct dao_imu_sample *s = malloc(N * sizeof(*s));
	struct dao_imu_sample *f = malloc((size_t)((N - 1) * FINE + 1) * sizeof(*f));
	assert_non_null(s);
	assert_non_null(f);
	for (int i = 0; i < N; i++) {
		s[i] = (struct dao_imu_sample){ .stamp_ns = (uint64_t)i * 5 * MS };
		coning((double)i * 0.005, s[i].w);
	}
	for (int i = 0; i <= (N - 1) * FINE; i++) {
		f[i] = (struct dao_imu_sample){ .stamp_ns = (uint64_t)i * 5000 };
		coning((double)i * 5e-6, f[i].w);
	}
	assert_int_equal(dao_imu_track(s, N, 0, 500 * MS), N);
	assert_int_equal(dao_imu_track(f, (size_t)(N - 1) * FINE + 1, 0, 500 * MS),
			 (N - 1) * FINE + 1);
	double worst = 0.0, frame = 0.0, step = 0.0;
	for (int i = 0; i < N; i++) {
		const double e = angle_between(s[i].q, f[(size_t)i * FINE].q);
		worst = e > worst ? e : worst;
		if (i)
			step = fmax(step, angle_between(s[i].q, s[i - 1].q));
		if (i < 7)
			continue;
		/* what a seed takes: the rotation between two frames 35 ms apart */
		double r[4], rf[4];
		const double *a = s[i - 7].q, *b = s[i].q;
		const double *af = f[(size_t)(i - 7) * FINE].q, *bf = f[(size_t)i * FINE].q;
		const double ai[4] = { -a[0], -a[1], -a[2], a[3] }, afi[4] = { -af[0], -af[1], -af[2], af[3] };
		quat_mul(ai, b, r);
		quat_mul(afi, bf, rf);
		frame = fmax(frame, angle_between(r, rf));
	}
	/* 2 s of 0.8 rad/s at 3 Hz: 1.1e-4 rad apart after 2 s, 2.1e-5 rad (0.0012 degrees)
	 * between two frames, where a motion seed needs a tenth of a degree; and the motion
	 * is real */
	print_message("coning: %.2e rad apart after 2 s, %.2e rad between frames 35 ms apart, "
		      "steps up to %.4f rad\n", worst, frame, step);
	assert_true(worst < 2e-4);
	assert_true(frame < 5e-5);
	assert_true(step > 0.003);
	free(s);
	free(f);
}

/* q(t) = qz(a t) qx(b t): a turn about z of a body that rolls about its own x.  Its body
 * rate is Rx(b t)^T (0, 0, a) + (b, 0, 0), an axis that turns: the rates of a body
 * multiply on the right (multiplied on the left they end 0.98 rad off after 2 s). */
static void test_turning_axis(void **state)
{
	(void)state;
	enum { N = 401 };
	const double a = 0.7, b = 1.1;
	static struct dao_imu_sample s[N];
	for (int i = 0; i < N; i++) {
		const double t = (double)i * 0.005;
		s[i] = (struct dao_imu_sample){ .stamp_ns = (uint64_t)i * 5 * MS };
		s[i].w[0] = b;
		s[i].w[1] = a * sin(b * t);
		s[i].w[2] = a * cos(b * t);
	}
	assert_int_equal(dao_imu_track(s, N, 0, 500 * MS), N);
	double worst = 0.0;
	for (int i = 0; i < N; i++) {
		const double t = (double)i * 0.005;
		const double qz[4] = { 0, 0, sin(a * t / 2), cos(a * t / 2) };
		const double qx[4] = { sin(b * t / 2), 0, 0, cos(b * t / 2) };
		double want[4];
		quat_mul(qz, qx, want);
		worst = fmax(worst, angle_between(s[i].q, want));
	}
	print_message("turning axis: %.2e rad from the truth after 2 s\n", worst);
	assert_true(worst < 1e-4);
}

static void test_order_repeats_gap(void **state)
{
	(void)state;
	enum { N = 60 };
	struct dao_imu_sample a[N], b[N + 3];
	for (int i = 0; i < N; i++) {
		/* a 2 s gap after sample 29 */
		a[i] = (struct dao_imu_sample){ .stamp_ns = (uint64_t)i * 5 * MS +
							    (i >= 30 ? 2000 * MS : 0) };
		a[i].w[1] = 0.5 + 0.01 * i;
	}
	/* b: a shuffled, and three repeated stamps with other rates (the first is kept) */
	for (int i = 0; i < N; i++)
		b[i] = a[(i * 7) % N];
	for (int k = 0; k < 3; k++) {
		b[N + k] = a[10 + k];
		b[N + k].w[1] = 99.0;
	}
	/* a stable sort puts the repeats after the originals they follow in b */
	assert_int_equal(dao_imu_track(a, N, 0, 500 * MS), N);
	assert_int_equal(dao_imu_track(b, N + 3, 0, 500 * MS), N);
	for (int i = 0; i < N; i++) { /* the same operations in the same order: the same bits */
		assert_int_equal(a[i].stamp_ns, b[i].stamp_ns);
		assert_memory_equal(a[i].q, b[i].q, sizeof a[i].q);
	}
	/* across the gap nothing is integrated: sample 30 keeps sample 29's rotation and
	 * starts the second segment */
	assert_memory_equal(a[29].q, a[30].q, sizeof a[29].q);
	assert_int_equal(a[29].segment, 0);
	assert_int_equal(a[30].segment, 1);
	assert_int_equal(a[N - 1].segment, 1);
	assert_true(angle_between(a[28].q, a[29].q) > 0.002);
	assert_true(angle_between(a[30].q, a[31].q) > 0.002);
}

static void test_orientation(void **state)
{
	(void)state;
	struct dao_imu_sample s[2] = { { .stamp_ns = 20 * MS, .q = { 0, 0, 2, 0 } },
				       { .stamp_ns = 10 * MS, .q = { 0, 3, 0, 4 } } };
	assert_int_equal(dao_imu_track(s, 2, 1, 500 * MS), 2);
	assert_int_equal(s[0].stamp_ns, 10 * MS);
	assert_true(fabs(s[0].q[1] - 0.6) < 1e-15 && fabs(s[0].q[3] - 0.8) < 1e-15);
	assert_true(fabs(s[1].q[2] - 1.0) < 1e-15);
	assert_int_equal(dao_imu_track(s, 0, 0, 500 * MS), 0);
}

static size_t put(uint8_t *m, const void *v, size_t n)
{
	memcpy(m, v, n);
	return n;
}

/* sensor_msgs/Imu, ROS 1: header, orientation, 9, rates, 9, acceleration, 9 */
static void test_ros1_imu(void **state)
{
	(void)state;
	uint8_t m[512];
	uint32_t seq = 7, sec = 100, nsec = 5, len = 3;
	size_t n = put(m, &seq, 4);
	n += put(m + n, &sec, 4);
	n += put(m + n, &nsec, 4);
	n += put(m + n, &len, 4);
	n += put(m + n, "imu", 3);
	double v[37] = { 0, 0, 0.6, 0.8, -1.0 };
	v[13] = 0.1, v[14] = 0.2, v[15] = 0.3;
	n += put(m + n, v, sizeof v);
	struct dao_imu_msg im;
	assert_int_equal(dao_ros_imu_parse(m, (uint32_t)n, &im), 0);
	assert_int_equal(im.stamp_ns, 100 * 1000 * MS + 5);
	assert_int_equal(im.frame_len, 3);
	assert_memory_equal(im.frame, "imu", 3);
	assert_int_equal(im.has_orientation, 0); /* covariance[0] -1: none */
	assert_true(im.w[0] == 0.1 && im.w[1] == 0.2 && im.w[2] == 0.3);
	assert_true(im.q[2] == 0.6 && im.q[3] == 0.8);
	for (size_t cut = 0; cut < n; cut++)
		assert_int_equal(dao_ros_imu_parse(m, (uint32_t)cut, &im), -EINVAL);
	assert_int_equal(dao_ros_imu_parse(m, (uint32_t)n + 1, &im), -EINVAL);
	v[4] = 0.01; /* a covariance: the orientation is there */
	memcpy(m + n - sizeof v, v, sizeof v);
	assert_int_equal(dao_ros_imu_parse(m, (uint32_t)n, &im), 0);
	assert_int_equal(im.has_orientation, 1);
}

/* ROS 2 CDR: the encapsulation header, the header, then float64s aligned to 8 */
static void test_ros2_imu(void **state)
{
	(void)state;
	uint8_t m[512] = { 0, 1, 0, 0 };
	int32_t sec = 100;
	uint32_t nsec = 5, len = 9;
	size_t n = 4;
	n += put(m + n, &sec, 4);
	n += put(m + n, &nsec, 4);
	n += put(m + n, &len, 4);
	n += put(m + n, "imu_link", 9);
	n = 4 + ((n - 4 + 7) & ~(size_t)7); /* 21 bytes: 3 of padding before the float64s */
	double v[37] = { 0, 0, 0.6, 0.8, 0.0 };
	v[13] = -0.1, v[14] = 0.2, v[15] = -0.3;
	n += put(m + n, v, sizeof v);
	struct dao_imu_msg im;
	assert_int_equal(dao_ros2_imu_parse(m, n, &im), 0);
	assert_int_equal(im.stamp_ns, 100 * 1000 * MS + 5);
	assert_int_equal(im.frame_len, 8);
	assert_memory_equal(im.frame, "imu_link", 8);
	assert_int_equal(im.has_orientation, 1);
	assert_true(im.w[0] == -0.1 && im.w[1] == 0.2 && im.w[2] == -0.3);
	for (size_t cut = 0; cut < n; cut++)
		assert_int_not_equal(dao_ros2_imu_parse(m, cut, &im), 0);
	sec = -1; /* a time before 1970: refused */
	memcpy(m + 4, &sec, 4);
	assert_int_equal(dao_ros2_imu_parse(m, n, &im), -EINVAL);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_constant_rate),
		cmocka_unit_test(test_coning_against_fine),
		cmocka_unit_test(test_turning_axis),
		cmocka_unit_test(test_order_repeats_gap),
		cmocka_unit_test(test_orientation),
		cmocka_unit_test(test_ros1_imu),
		cmocka_unit_test(test_ros2_imu),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
