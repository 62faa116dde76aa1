/* SPDX-License-Identifier: MIT */
/*
 * <depthao/pose.h> (src/motion/pose_math.c), through the shared library's
 * public API: quaternion -> matrix -> quaternion on random rotations, near
 * and at half turns (up to sign), the matrices orthonormal with determinant
 * +1, w >= 0; a matrix that drifted gives a unit quaternion; interpolation
 * exact at its ends, against a rotation built here independently from the
 * axis and angle of Ra^T Rb (Rodrigues) in between and outside [0, 1], along
 * the shorter arc when qa . qb < 0, within the documented bound where it is
 * linear, and with its outputs on its inputs.  dao_motion_accumulate
 * (<depthao/context.h>): a chain of 2000 small motions between random poses
 * ends at the last pose seen from the first (within 1e-9, still a
 * rotation); a motion that was not accepted (NONE, REFUSED, a NaN) leaves
 * the pose alone; bad arguments are refused.
 */
#include <errno.h>
#include <math.h>
#include <string.h>

#include <depthao/context.h>
#include <depthao/pose.h>

#include "common/cmocka_all.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static double uniform(uint64_t *st)
{
	*st = *st * 6364136223846793005ull + 1442695040888963407ull;
	return ((double)(*st >> 11) + 0.5) / 9007199254740992.0;
}

static double gauss(uint64_t *st)
{
	const double u0 = uniform(st), u1 = uniform(st);
	return sqrt(-2.0 * log(u0)) * cos(2.0 * M_PI * u1);
}

/* the unit quaternion of `angle` radians about the axis a (any length) */
static void quat_axis(const double a[3], double angle, double q[4])
{
	const double n = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]), s = sin(angle / 2);
	q[0] = s * a[0] / n, q[1] = s * a[1] / n, q[2] = s * a[2] / n, q[3] = cos(angle / 2);
}

/* a random unit quaternion; kind 1: near a half turn (|w| from 1e-12 to 1e-3), 2: a half turn */
static void random_quat(uint64_t *st, int kind, double q[4])
{
	double n = 0.0;
	for (int i = 0; i < 4; i++)
		q[i] = gauss(st);
	if (kind)
		q[3] = kind == 1 ? copysign(pow(10.0, -12.0 + 9.0 * uniform(st)), q[3]) : 0.0;
	for (int i = 0; i < 4; i++)
		n += q[i] * q[i];
	if (kind == 1) /* keep w as drawn: scale x, y, z to the rest of the norm */
		for (int i = 0; i < 3; i++)
			q[i] *= sqrt((1.0 - q[3] * q[3]) / (n - q[3] * q[3]));
	else
		for (int i = 0; i < 4; i++)
			q[i] /= sqrt(n);
}

/* a random pose: a unit quaternion and a translation of sigma `scale` m */
static void random_pose(uint64_t *st, double q[4], double t[3], double scale)
{
	random_quat(st, 0, q);
	for (int i = 0; i < 3; i++)
		t[i] = scale * gauss(st);
}

static double dot4(const double a[4], const double b[4])
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
}

static void mat_mul(const double a[9], const double b[9], double out[9])
{
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			out[i * 3 + j] = a[i * 3] * b[j] + a[i * 3 + 1] * b[3 + j] + a[i * 3 + 2] * b[6 + j];
}

static void mat_transpose(const double a[9], double out[9])
{
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			out[j * 3 + i] = a[i * 3 + j];
}

/* R R^T = I and det R = +1, within tol */
static void assert_rotation(const double r[9], double tol)
{
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++) {
			const double d = r[i * 3] * r[j * 3] + r[i * 3 + 1] * r[j * 3 + 1] +
					 r[i * 3 + 2] * r[j * 3 + 2];
			assert_true(fabs(d - (i == j)) < tol);
		}
	const double det = r[0] * (r[4] * r[8] - r[5] * r[7]) - r[1] * (r[3] * r[8] - r[5] * r[6]) +
			   r[2] * (r[3] * r[7] - r[4] * r[6]);
	assert_true(fabs(det - 1.0) < tol);
}

/* q = +-want (the same rotation), within tol */
static void assert_same_quat(const double q[4], const double want[4], double tol)
{
	const double s = dot4(q, want) < 0.0 ? -1.0 : 1.0;
	for (int i = 0; i < 4; i++)
		assert_true(fabs(q[i] - s * want[i]) < tol);
}

/* Rodrigues: the rotation of `angle` radians about the unit axis a */
static void rodrigues(const double a[3], double angle, double r[9])
{
	const double c = cos(angle), s = sin(angle), C = 1.0 - c;
	const double m[9] = {c + a[0] * a[0] * C,        a[0] * a[1] * C - a[2] * s, a[0] * a[2] * C + a[1] * s,
			     a[1] * a[0] * C + a[2] * s, c + a[1] * a[1] * C,        a[1] * a[2] * C - a[0] * s,
			     a[2] * a[0] * C - a[1] * s, a[2] * a[1] * C + a[0] * s, c + a[2] * a[2] * C};
	memcpy(r, m, sizeof m);
}

/* the axis and angle (0..pi) of a rotation matrix, not near a half turn */
static void axis_angle(const double r[9], double axis[3], double *angle)
{
	const double v[3] = {r[7] - r[5], r[2] - r[6], r[3] - r[1]}; /* 2 sin(angle) axis */
	const double s = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
	*angle = atan2(0.5 * s, 0.5 * (r[0] + r[4] + r[8] - 1.0));
	for (int i = 0; i < 3; i++)
		axis[i] = s > 0.0 ? v[i] / s : (i == 0);
}

/* quaternion -> matrix -> quaternion: random rotations, near half turns, half turns */
static void test_round_trip(void **state)
{
	(void)state;
	uint64_t st = 7;
	for (int kind = 0; kind < 3; kind++)
		for (int k = 0; k < 2000; k++) {
			double q[4], r[9], b[4], r2[9];
			random_quat(&st, kind, q);
			dao_pose_quat_to_matrix(q, r);
			assert_rotation(r, 1e-12);
			dao_pose_matrix_to_quat(r, b);
			assert_true(b[3] >= 0.0);
			assert_true(fabs(dot4(b, b) - 1.0) < 1e-15);
			assert_same_quat(b, q, 1e-12);
			/* -q: the same matrix to rounding */
			const double m[4] = {-q[0], -q[1], -q[2], -q[3]};
			dao_pose_quat_to_matrix(m, r2);
			for (int i = 0; i < 9; i++)
				assert_true(fabs(r[i] - r2[i]) < 1e-15);
		}
}

/* rotation -> quaternion -> rotation on axes and angles up to 180 degrees (the trace
 * above and below 0, every branch) */
static void test_axes_and_angles(void **state)
{
	(void)state;
	const double axes[4][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.48, -0.6, 0.64}};
	const double angles[5] = {0.0, 0.3, 2.0, 3.0, M_PI};
	for (int a = 0; a < 4; a++)
		for (int b = 0; b < 5; b++) {
			double q0[4], r[9], q[4], r2[9];
			quat_axis(axes[a], angles[b], q0);
			dao_pose_quat_to_matrix(q0, r);
			dao_pose_matrix_to_quat(r, q);
			assert_true(q[3] >= 0.0);
			dao_pose_quat_to_matrix(q, r2);
			for (int i = 0; i < 9; i++)
				assert_true(fabs(r[i] - r2[i]) < 1e-12);
			/* the same rotation as q0 (q or -q) */
			assert_true(fabs(fabs(dot4(q, q0)) - 1.0) < 1e-12);
		}
	/* the matrix of a half turn about x, written out: q = (1, 0, 0, 0) */
	const double rx[9] = {1, 0, 0, 0, -1, 0, 0, 0, -1};
	double q[4];
	dao_pose_matrix_to_quat(rx, q);
	assert_true(q[0] == 1.0 && q[1] == 0.0 && q[2] == 0.0 && q[3] == 0.0);
}

/* a rotation that drifted (scaled, and skewed by 1e-9): still a unit quaternion,
 * of a rotation within 1e-8 of it */
static void test_drifted_matrix(void **state)
{
	(void)state;
	uint64_t st = 11;
	for (int k = 0; k < 500; k++) {
		double q[4], r[9], b[4], rb[9];
		random_quat(&st, 0, q);
		dao_pose_quat_to_matrix(q, r);
		for (int i = 0; i < 9; i++)
			r[i] = r[i] * (1.0 + 1e-7) + 1e-9 * gauss(&st);
		dao_pose_matrix_to_quat(r, b);
		assert_true(fabs(dot4(b, b) - 1.0) < 1e-15 && b[3] >= 0.0);
		dao_pose_quat_to_matrix(b, rb);
		for (int i = 0; i < 9; i++)
			assert_true(fabs(rb[i] - r[i]) < 1e-6);
		assert_same_quat(b, q, 1e-6);
	}
}

/* s = 0 and s = 1: the ends, the translations bit for bit */
static void test_interpolate_ends(void **state)
{
	(void)state;
	uint64_t st = 23;
	for (int k = 0; k < 1000; k++) {
		double qa[4], qb[4], ta[3], tb[3], q[4], t[3];
		random_pose(&st, qa, ta, 10.0);
		random_pose(&st, qb, tb, 10.0);
		if (k % 4 == 1) { /* nearly the same rotation: the linear branch */
			for (int i = 0; i < 4; i++)
				qb[i] = qa[i] + 1e-5 * gauss(&st);
			const double n = sqrt(dot4(qb, qb));
			for (int i = 0; i < 4; i++)
				qb[i] /= n;
		}
		dao_pose_interpolate(qa, ta, qb, tb, 0.0, q, t);
		assert_memory_equal(t, ta, sizeof t);
		for (int i = 0; i < 4; i++)
			assert_true(fabs(q[i] - qa[i]) < 1e-15);
		dao_pose_interpolate(qa, ta, qb, tb, 1.0, q, t);
		assert_memory_equal(t, tb, sizeof t);
		assert_same_quat(q, qb, 1e-15);
		assert_true(fabs(dot4(q, q) - 1.0) < 1e-15);
	}
}

/*
 * Between the ends and beyond them: the rotation Ra Rod(axis, s angle), the
 * axis and angle those of Ra^T Rb, computed here from the matrices; the
 * translation ta + s (tb - ta).
 */
static void check_against_axis_angle(const double qa[4], const double qb[4], double s,
				     double tol)
{
	const double ta[3] = {0.5, -1.0, 2.0}, tb[3] = {-0.25, 3.0, 2.5};
	double ra[9], rb[9], rat[9], rel[9], axis[3], angle, rs[9], want[9], q[4], t[3], r[9];
	dao_pose_quat_to_matrix(qa, ra);
	dao_pose_quat_to_matrix(qb, rb);
	mat_transpose(ra, rat);
	mat_mul(rat, rb, rel);
	axis_angle(rel, axis, &angle);
	rodrigues(axis, s * angle, rs);
	mat_mul(ra, rs, want);
	dao_pose_interpolate(qa, ta, qb, tb, s, q, t);
	assert_true(fabs(dot4(q, q) - 1.0) < 1e-15);
	dao_pose_quat_to_matrix(q, r);
	for (int i = 0; i < 9; i++)
		if (!(fabs(r[i] - want[i]) < tol))
			fail_msg("s = %g, angle %.17g rad: r[%d] = %.17g, want %.17g (tolerance %g)", s,
				 angle, i, r[i], want[i], tol);
	for (int i = 0; i < 3; i++)
		assert_true(fabs(t[i] - (ta[i] + s * (tb[i] - ta[i]))) < 1e-14);
}

static void test_interpolate_axis_angle(void **state)
{
	(void)state;
	uint64_t st = 31;
	const double s[] = {0.5, 0.25, 0.75, 0.1, -0.5, 1.5, 2.0, -1.0};
	for (int k = 0; k < 500; k++) {
		double qa[4], qb[4], qd[4], axis[3];
		random_quat(&st, 0, qa);
		for (int i = 0; i < 3; i++)
			axis[i] = gauss(&st);
		/* b = a turned by 0.5 to 170 degrees (the shorter arc: Ra^T Rb's angle) */
		quat_axis(axis, (0.5 + 169.5 * uniform(&st)) * M_PI / 180.0, qd);
		const double x = qa[0], y = qa[1], z = qa[2], w = qa[3]; /* qb = qa qd */
		qb[0] = w * qd[0] + x * qd[3] + y * qd[2] - z * qd[1];
		qb[1] = w * qd[1] - x * qd[2] + y * qd[3] + z * qd[0];
		qb[2] = w * qd[2] + x * qd[1] - y * qd[0] + z * qd[3];
		qb[3] = w * qd[3] - x * qd[0] - y * qd[1] - z * qd[2];
		if (k % 2) /* the other sign of the same rotation: the same arc */
			for (int i = 0; i < 4; i++)
				qb[i] = -qb[i];
		for (size_t j = 0; j < sizeof s / sizeof s[0]; j++)
			check_against_axis_angle(qa, qb, s[j], 1e-12);
	}
}

/* rotations less than 0.1 degree apart: the linear branch, within 4e-11 rad of slerp
 * (the matrices within twice that), for s in [0, 1] */
static void test_interpolate_nearly_equal(void **state)
{
	(void)state;
	uint64_t st = 47;
	for (int k = 0; k < 200; k++) {
		double qa[4], qb[4], axis[3];
		random_quat(&st, 0, qa);
		for (int i = 0; i < 3; i++)
			axis[i] = gauss(&st);
		const double angle = (k % 2 ? 0.1145 : 1e-6 * uniform(&st)) * M_PI / 180.0;
		double ra[9], rd[9], rb[9], n = sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
		for (int i = 0; i < 3; i++)
			axis[i] /= n;
		dao_pose_quat_to_matrix(qa, ra);
		rodrigues(axis, angle, rd);
		mat_mul(ra, rd, rb);
		dao_pose_matrix_to_quat(rb, qb);
		for (int j = 0; j <= 8; j++)
			check_against_axis_angle(qa, qb, j / 8.0, 8e-11);
	}
}

/* qa . qb < 0: the shorter arc; a turn of 300 degrees about z is one of 60 the other way */
static void test_shorter_arc(void **state)
{
	(void)state;
	const double z[3] = {0, 0, 1}, id[4] = {0, 0, 0, 1}, t0[3] = {0, 0, 0};
	double qb[4], q[4], t[3], r[9], want[9];
	quat_axis(z, 300.0 * M_PI / 180.0, qb);
	assert_true(dot4(id, qb) < 0.0);
	dao_pose_interpolate(id, t0, qb, t0, 0.5, q, t);
	dao_pose_quat_to_matrix(q, r);
	rodrigues(z, -30.0 * M_PI / 180.0, want);
	for (int i = 0; i < 9; i++)
		assert_true(fabs(r[i] - want[i]) < 1e-15);
	/* qb and -qb: the same result */
	const double nb[4] = {-qb[0], -qb[1], -qb[2], -qb[3]};
	double q2[4];
	dao_pose_interpolate(id, t0, nb, t0, 0.5, q2, t);
	for (int i = 0; i < 4; i++)
		assert_true(fabs(q[i] - q2[i]) < 1e-15);
	/* -qa itself: the same rotation all the way */
	const double ni[4] = {0, 0, 0, -1};
	for (int j = -2; j <= 4; j++) {
		dao_pose_interpolate(id, t0, ni, t0, j / 2.0, q, t);
		assert_true(fabs(q[3]) == 1.0 && q[0] == 0.0 && q[1] == 0.0 && q[2] == 0.0);
	}
}

/* the outputs on the inputs: the same numbers */
static void test_interpolate_in_place(void **state)
{
	(void)state;
	uint64_t st = 59;
	for (int k = 0; k < 100; k++) {
		double qa[4], qb[4], ta[3], tb[3], q[4], t[3];
		random_pose(&st, qa, ta, 1.0);
		random_pose(&st, qb, tb, 1.0);
		const double s = 2.0 * uniform(&st) - 0.5;
		dao_pose_interpolate(qa, ta, qb, tb, s, q, t);
		double qa2[4], ta2[3], qb2[4], tb2[3];
		memcpy(qa2, qa, sizeof qa), memcpy(ta2, ta, sizeof ta);
		memcpy(qb2, qb, sizeof qb), memcpy(tb2, tb, sizeof tb);
		dao_pose_interpolate(qa2, ta2, qb, tb, s, qa2, ta2);
		dao_pose_interpolate(qa, ta, qb2, tb2, s, qb2, tb2);
		assert_memory_equal(qa2, q, sizeof q);
		assert_memory_equal(ta2, t, sizeof t);
		assert_memory_equal(qb2, q, sizeof q);
		assert_memory_equal(tb2, t, sizeof t);
	}
}

/* The motion from pose b's camera to pose a's (p_a = M p_b + m), as
 * dao_context_motion reports the last frame's: M = Ra^T Rb, m = Ra^T (tb - ta). */
static void motion_between(const double ra[9], const double ta[3], const double rb[9],
			   const double tb[3], struct dao_motion_info *mi)
{
	double rat[9];
	mat_transpose(ra, rat);
	mat_mul(rat, rb, mi->rotation);
	for (int i = 0; i < 3; i++)
		mi->translation[i] = rat[i * 3] * (tb[0] - ta[0]) + rat[i * 3 + 1] * (tb[1] - ta[1]) +
				     rat[i * 3 + 2] * (tb[2] - ta[2]);
}

static void test_accumulate_chain(void **state)
{
	(void)state;
	uint64_t st = 71;
	/* a camera wandering from a random first pose: about a degree and a
	 * centimetre a frame, 2000 frames; every 7th frame's estimate refused and
	 * every 11th unknown (cut): their motion is taken as none, so the truth
	 * the pose is compared with skips it too */
	double q0[4], t0[3], r0[9];
	random_pose(&st, q0, t0, 1.0);
	dao_pose_quat_to_matrix(q0, r0);
	double rp[9], tp[3], r[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 }, t[3] = { 0, 0, 0 };
	memcpy(rp, r0, sizeof rp), memcpy(tp, t0, sizeof tp);
	double want_r[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 }, want_t[3] = { 0, 0, 0 };
	for (int k = 1; k <= 2000; k++) {
		const double axis[3] = { gauss(&st), gauss(&st), gauss(&st) };
		double dq[4], dr[9], rn[9], tn[3];
		quat_axis(axis, 0.02 * uniform(&st), dq);
		dao_pose_quat_to_matrix(dq, dr);
		mat_mul(rp, dr, rn);
		for (int i = 0; i < 3; i++)
			tn[i] = tp[i] + 0.01 * gauss(&st);
		struct dao_motion_info mi = DAO_MOTION_INFO_INIT;
		motion_between(rp, tp, rn, tn, &mi);
		mi.state = k % 11 == 0 ? DAO_MOTION_NONE
			   : k % 7 == 0 ? DAO_MOTION_REFUSED
			   : k % 3 == 0 ? DAO_MOTION_STILL
					: DAO_MOTION_APPLIED;
		const int accepted = mi.state == DAO_MOTION_STILL || mi.state == DAO_MOTION_APPLIED;
		const double keep_r[9] = { r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8] };
		const double keep_t[3] = { t[0], t[1], t[2] };
		assert_int_equal(dao_motion_accumulate(&mi, r, t), accepted);
		if (!accepted) {
			assert_memory_equal(r, keep_r, sizeof r);
			assert_memory_equal(t, keep_t, sizeof t);
		} else { /* the truth: the same step composed here, want = want M, want m + t */
			double wr[9];
			mat_mul(want_r, mi.rotation, wr);
			for (int i = 0; i < 3; i++)
				want_t[i] += want_r[i * 3] * mi.translation[0] +
					     want_r[i * 3 + 1] * mi.translation[1] +
					     want_r[i * 3 + 2] * mi.translation[2];
			memcpy(want_r, wr, sizeof wr);
		}
		memcpy(rp, rn, sizeof rp), memcpy(tp, tn, sizeof tp);
	}
	for (int i = 0; i < 9; i++)
		assert_true(fabs(r[i] - want_r[i]) < 1e-9);
	for (int i = 0; i < 3; i++)
		assert_true(fabs(t[i] - want_t[i]) < 1e-9);
	assert_rotation(r, 1e-12);
	/* every motion accepted: the last pose seen from the first, r0^T (rp, tp - t0) */
	double ra[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 }, ta[3] = { 0, 0, 0 };
	memcpy(rp, r0, sizeof rp), memcpy(tp, t0, sizeof tp);
	for (int k = 1; k <= 2000; k++) {
		double q[4], rn[9], tn[3];
		random_pose(&st, q, tn, 1.0);
		/* a random pose, brought within 2 degrees and 2 cm of the last */
		dao_pose_interpolate((double[4]){ 0, 0, 0, 1 }, (double[3]){ 0, 0, 0 }, q, tn,
				     0.01 * uniform(&st), q, tn);
		double dr[9];
		dao_pose_quat_to_matrix(q, dr);
		mat_mul(rp, dr, rn);
		for (int i = 0; i < 3; i++)
			tn[i] += tp[i];
		struct dao_motion_info mi = DAO_MOTION_INFO_INIT;
		motion_between(rp, tp, rn, tn, &mi);
		mi.state = DAO_MOTION_APPLIED;
		assert_int_equal(dao_motion_accumulate(&mi, ra, ta), 1);
		memcpy(rp, rn, sizeof rp), memcpy(tp, tn, sizeof tp);
	}
	double r0t[9], want[9];
	mat_transpose(r0, r0t);
	mat_mul(r0t, rp, want);
	for (int i = 0; i < 9; i++)
		assert_true(fabs(ra[i] - want[i]) < 1e-9);
	for (int i = 0; i < 3; i++) {
		const double w = r0t[i * 3] * (tp[0] - t0[0]) + r0t[i * 3 + 1] * (tp[1] - t0[1]) +
				 r0t[i * 3 + 2] * (tp[2] - t0[2]);
		assert_true(fabs(ta[i] - w) < 1e-9);
	}
	assert_rotation(ra, 1e-12);
}

static void test_accumulate_refuses(void **state)
{
	(void)state;
	double r[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 }, t[3] = { 1, 2, 3 };
	const double r_in[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 }, t_in[3] = { 1, 2, 3 };
	struct dao_motion_info mi = DAO_MOTION_INFO_INIT;
	mi.state = DAO_MOTION_APPLIED;
	mi.rotation[0] = mi.rotation[4] = mi.rotation[8] = 1.0;
	mi.translation[2] = NAN; /* not finite: as none */
	assert_int_equal(dao_motion_accumulate(&mi, r, t), 0);
	mi.translation[2] = 0.5;
	mi.rotation[1] = INFINITY;
	assert_int_equal(dao_motion_accumulate(&mi, r, t), 0);
	assert_memory_equal(r, r_in, sizeof r);
	assert_memory_equal(t, t_in, sizeof t);
	mi.rotation[1] = 0.0;
	assert_int_equal(dao_motion_accumulate(NULL, r, t), -EINVAL);
	assert_int_equal(dao_motion_accumulate(&mi, NULL, t), -EINVAL);
	assert_int_equal(dao_motion_accumulate(&mi, r, NULL), -EINVAL);
	mi.size = (uint32_t)offsetof(struct dao_motion_info, translation); /* an older, shorter struct */
	assert_int_equal(dao_motion_accumulate(&mi, r, t), -EINVAL);
	assert_memory_equal(t, t_in, sizeof t);
	mi.size = sizeof mi;
	assert_int_equal(dao_motion_accumulate(&mi, r, t), 1);
	assert_true(t[2] == 3.5);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_round_trip),
		cmocka_unit_test(test_axes_and_angles),
		cmocka_unit_test(test_drifted_matrix),
		cmocka_unit_test(test_interpolate_ends),
		cmocka_unit_test(test_interpolate_axis_angle),
		cmocka_unit_test(test_interpolate_nearly_equal),
		cmocka_unit_test(test_shorter_arc),
		cmocka_unit_test(test_interpolate_in_place),
		cmocka_unit_test(test_accumulate_chain),
		cmocka_unit_test(test_accumulate_refuses),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
