/* SPDX-License-Identifier: MIT */
/*
 * The tf buffer (src/io/tf): composition against poses composed by hand,
 * interpolation (slerp exact on a constant-rate turn, lerp on a line),
 * static against dynamic transforms, gaps, two parents, cycles, frames not
 * connected, quaternions normalised or refused, the limits, a lone
 * Foxglove transform made static; and the ROS 1 and ROS 2 tf / odometry
 * parsers and Foxglove's FrameTransform(s) and PoseInFrame(s) (protobuf,
 * JSON, ROS 2 CDR) on hand-made, damaged and truncated messages.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>
#include <errno.h>
#include <math.h>

#include "bag/ros_msg.h"
#include "mcap/foxglove_msg.h"
#include "mcap/ros2_msg.h"
#include "tf/tf_buffer.h"

#define S 1000000000ull

static struct dao_rigid yaw(double deg, double x, double y, double z)
{
	double h = deg * 3.14159265358979323846 / 360.0;
	return (struct dao_rigid){ { 0, 0, sin(h), cos(h) }, { x, y, z } };
}

static int add(struct dao_tf_buffer *b, const char *p, const char *c, uint64_t t,
	       struct dao_rigid tr, int st)
{
	struct dao_error err;
	return dao_tf_buffer_add(b, p, strlen(p), c, strlen(c), t, &tr, st, &err);
}

static void near(const struct dao_rigid *a, const struct dao_rigid *b, double tol)
{
	double s = a->q[0] * b->q[0] + a->q[1] * b->q[1] + a->q[2] * b->q[2] + a->q[3] * b->q[3];
	assert_true(fabs(fabs(s) - 1.0) < tol);
	for (int i = 0; i < 3; i++)
		assert_true(fabs(a->t[i] - b->t[i]) < tol);
}

static struct dao_tf_buffer *tree(void)
{
	struct dao_tf_buffer *b;
	struct dao_error err;
	assert_int_equal(dao_tf_buffer_create(&b, 16, 100, &err), 0);
	/* map -> odom static; odom -> base dynamic, turning 90 deg/s about z at 1 m/s in x;
	 * base -> cam static ("/" prefixes as ROS 1 writes them) */
	assert_int_equal(add(b, "/map", "odom", 0, yaw(90, 1, 2, 0), 1), 0);
	for (int i = 0; i <= 4; i++)
		assert_int_equal(add(b, "odom", "base", (uint64_t)i * S / 4,
				     yaw(22.5 * i, 0.25 * i, 0, 0), 0), 0);
	assert_int_equal(add(b, "base", "/cam", 0, yaw(-90, 0, 0, 0.5), 1), 0);
	assert_int_equal(dao_tf_buffer_finish(b, &err), 0);
	return b;
}

static void test_compose_interpolate(void **state)
{
	(void)state;
	struct dao_tf_buffer *b = tree();
	struct dao_error err;
	struct dao_rigid got, want, base;
	int map = dao_tf_buffer_find(b, "map"), cam = dao_tf_buffer_find(b, "cam"), root;
	assert_true(map >= 0 && cam >= 0);
	assert_int_equal(dao_tf_buffer_root(b, cam, &root, &err), 0);
	assert_int_equal(root, map);
	/* at 0.3 s, between the samples of 0.25 and 0.5 s: yaw 27 deg, x 0.3 m (exact) */
	base = yaw(27, 0.3, 0, 0);
	struct dao_rigid m = yaw(90, 1, 2, 0), c = yaw(-90, 0, 0, 0.5);
	dao_rigid_compose(&m, &base, &want);
	dao_rigid_compose(&want, &c, &want);
	assert_int_equal(dao_tf_buffer_lookup(b, map, cam, 3 * S / 10, S, &got, &err), 0);
	near(&got, &want, 1e-12);
	/* the camera in base: static only, any time */
	assert_int_equal(dao_tf_buffer_lookup(b, dao_tf_buffer_find(b, "base"), cam, 99 * S, 1, &got,
					      &err), 0);
	near(&got, &c, 1e-15);
	/* cam in cam; odom in cam (the inverse) */
	assert_int_equal(dao_tf_buffer_lookup(b, cam, dao_tf_buffer_find(b, "odom"), S / 2, S, &got,
					      &err), 0);
	base = yaw(45, 0.5, 0, 0);
	dao_rigid_compose(&base, &c, &want);
	dao_rigid_inverse(&want, &want);
	near(&got, &want, 1e-12);
	dao_tf_buffer_free(b);
}

static void test_gaps(void **state)
{
	(void)state;
	struct dao_tf_buffer *b = tree();
	struct dao_error err;
	struct dao_rigid got;
	int map = dao_tf_buffer_find(b, "map"), cam = dao_tf_buffer_find(b, "cam");
	/* samples 0.25 s apart: a limit of 0.2 s refuses between them, not at them */
	assert_int_equal(dao_tf_buffer_lookup(b, map, cam, 3 * S / 10, S / 5, &got, &err), -ENOENT);
	assert_non_null(strstr(err.message, "no transform 'odom' -> 'base' at 0.300000 s"));
	assert_non_null(strstr(err.message, "farther apart than 0.200 s"));
	assert_int_equal(dao_tf_buffer_lookup(b, map, cam, S / 4 + 500, S / 5, &got, &err), 0);
	/* no extrapolation */
	assert_int_equal(dao_tf_buffer_lookup(b, map, cam, S + 2000, S, &got, &err), -ENOENT);
	assert_non_null(strstr(err.message, "after its last (1.000000 s)"));
	dao_tf_buffer_free(b);
}

static void test_structure(void **state)
{
	(void)state;
	struct dao_tf_buffer *b = tree();
	struct dao_error err;
	struct dao_rigid got, id;
	dao_rigid_identity(&id);
	/* a second parent is refused; a frame its own parent skipped */
	assert_int_equal(dao_tf_buffer_add(b, "map", 3, "base", 4, 0, &id, 1, &err), -EINVAL);
	assert_non_null(strstr(err.message, "frame 'base' has two parents in the tf, 'odom' and 'map'"));
	assert_int_equal(add(b, "x", "x", 0, id, 1), 1);
	/* another tree: not connected */
	assert_int_equal(add(b, "world", "other", 0, id, 1), 0);
	assert_int_equal(dao_tf_buffer_lookup(b, dao_tf_buffer_find(b, "world"),
					      dao_tf_buffer_find(b, "cam"), 0, S, &got, &err), -ENOTCONN);
	char list[200];
	dao_tf_buffer_list(b, list, sizeof list);
	assert_string_equal(list, "'map', 'odom', 'base', 'cam', 'x', 'world', 'other'");
	dao_tf_buffer_free(b);
	/* a cycle */
	assert_int_equal(dao_tf_buffer_create(&b, 4, 4, &err), 0);
	assert_int_equal(add(b, "a", "b", 0, id, 1), 0);
	assert_int_equal(add(b, "b", "c", 0, id, 1), 0);
	assert_int_equal(add(b, "c", "a", 0, id, 1), 0);
	int root;
	assert_int_equal(dao_tf_buffer_root(b, 0, &root, &err), -ELOOP);
	assert_non_null(strstr(err.message, "the tf has a cycle"));
	assert_int_equal(dao_tf_buffer_lookup(b, 0, 1, 0, S, &got, &err), -ELOOP);
	/* the limits: frames, samples */
	assert_int_equal(add(b, "a", "d", 0, id, 1), 0);
	assert_int_equal(add(b, "a", "e", 0, id, 1), -E2BIG);
	for (int i = 0; i < 4; i++)
		assert_int_equal(add(b, "a", "d", (uint64_t)i, id, 0), 0);
	assert_int_equal(add(b, "a", "d", 9, id, 0), -E2BIG);
	dao_tf_buffer_free(b);
}

static void test_values(void **state)
{
	(void)state;
	struct dao_tf_buffer *b;
	struct dao_error err;
	struct dao_rigid got, tr = yaw(30, 1, 0, 0), want = tr;
	assert_int_equal(dao_tf_buffer_create(&b, 8, 8, &err), 0);
	for (int i = 0; i < 4; i++)
		tr.q[i] *= 1 + 5e-4; /* drift: normalised */
	assert_int_equal(add(b, "w", "c", 5, tr, 0), 0);
	tr.q[3] *= 1.5; /* refused */
	assert_int_equal(add(b, "w", "c", 6, tr, 0), 1);
	tr = want;
	tr.t[1] = NAN;
	assert_int_equal(add(b, "w", "c", 7, tr, 0), 1);
	assert_int_equal(add(b, "", "c", 7, want, 0), 1);
	/* out of order and a repeated stamp: sorted, the later one kept */
	assert_int_equal(add(b, "w", "c", 1, yaw(0, 0, 0, 0), 0), 0);
	assert_int_equal(add(b, "w", "c", 1, yaw(10, 0, 0, 0), 0), 0);
	assert_int_equal(dao_tf_buffer_finish(b, &err), 0);
	assert_int_equal(dao_tf_buffer_samples(b), 2);
	assert_int_equal(dao_tf_buffer_lookup(b, 0, 1, 5, S, &got, &err), 0);
	near(&got, &want, 1e-12);
	struct dao_rigid ten = yaw(10, 0, 0, 0);
	assert_int_equal(dao_tf_buffer_lookup(b, 0, 1, 1, S, &got, &err), 0);
	near(&got, &ten, 1e-12);
	dao_tf_buffer_free(b);
}

/* ROS 1: a TFMessage of two transforms; then every truncation refused. */
static size_t put(uint8_t *p, const void *v, size_t n)
{
	memcpy(p, v, n);
	return n;
}

static size_t ros1_transform(uint8_t *p, const char *parent, const char *child, uint32_t nsec)
{
	size_t n = 0;
	uint32_t u[3] = { 7, 100, nsec }, len = (uint32_t)strlen(parent);
	n += put(p + n, u, 12);
	n += put(p + n, &len, 4);
	n += put(p + n, parent, len);
	len = (uint32_t)strlen(child);
	n += put(p + n, &len, 4);
	n += put(p + n, child, len);
	double v[7] = { 1, 2, 3, 0, 0, 0, 1 };
	return n + put(p + n, v, sizeof v);
}

static int count_cb(void *user, const struct dao_tf_msg_transform *t)
{
	int *n = user;
	assert_int_equal(t->stamp_ns, 100 * S + 5);
	assert_true(t->tr.t[2] == 3.0 && t->tr.q[3] == 1.0);
	(*n)++;
	return 0;
}

static void test_ros1_messages(void **state)
{
	(void)state;
	uint8_t m[1024];
	uint32_t two = 2;
	size_t n = put(m, &two, 4);
	n += ros1_transform(m + n, "/odom", "base_link", 5);
	n += ros1_transform(m + n, "base_link", "cam", 5);
	int got = 0;
	assert_int_equal(dao_ros_tf_parse(m, (uint32_t)n, count_cb, &got), 0);
	assert_int_equal(got, 2);
	for (size_t cut = 0; cut < n; cut++) {
		got = 0;
		assert_int_equal(dao_ros_tf_parse(m, (uint32_t)cut, count_cb, &got), -EINVAL);
		assert_int_equal(got, 0); /* nothing delivered from a bad message */
	}
	two = 0x40000000u; /* a count the bytes cannot hold */
	memcpy(m, &two, 4);
	assert_int_equal(dao_ros_tf_parse(m, (uint32_t)n, count_cb, &got), -EINVAL);
	/* a nanosecond field of 1e9 */
	two = 1;
	n = put(m, &two, 4) + ros1_transform(m + 4, "a", "b", 1000000000u);
	assert_int_equal(dao_ros_tf_parse(m, (uint32_t)n, count_cb, &got), -EINVAL);
	/* Odometry: the pose, then 78 float64 */
	struct dao_tf_msg_transform t;
	n = ros1_transform(m, "odom", "base_link", 5);
	memset(m + n, 0, 8 * 78);
	assert_int_equal(dao_ros_odometry_parse(m, (uint32_t)(n + 8 * 78), &t), 0);
	assert_int_equal(t.child_len, 9);
	assert_memory_equal(t.child, "base_link", 9);
	assert_int_equal(dao_ros_odometry_parse(m, (uint32_t)(n + 8 * 78 - 1), &t), -EINVAL);
}

/* ROS 2 CDR: an encapsulation header, then the fields aligned. */
static void test_ros2_messages(void **state)
{
	(void)state;
	uint8_t m[256] = { 0, 1, 0, 0 };
	size_t n = 4;
	uint32_t one = 1;
	int32_t sec = 100;
	uint32_t nsec = 5, l1 = 5, l2 = 4;
	n += put(m + n, &one, 4);
	n += put(m + n, &sec, 4);
	n += put(m + n, &nsec, 4);
	n += put(m + n, &l1, 4);
	n += put(m + n, "odom", 5);
	n = 4 + ((n - 4 + 3) & ~(size_t)3);
	n += put(m + n, &l2, 4);
	n += put(m + n, "cam", 4);
	n = 4 + ((n - 4 + 7) & ~(size_t)7);
	double v[7] = { 1, 2, 3, 0, 0, 0, 1 };
	n += put(m + n, v, sizeof v);
	int got = 0;
	assert_int_equal(dao_ros2_tf_parse(m, n, count_cb, &got), 0);
	assert_int_equal(got, 1);
	for (size_t cut = 0; cut < n; cut++)
		assert_true(dao_ros2_tf_parse(m, cut, count_cb, &got) < 0);
	assert_int_equal(got, 1);
	sec = -1;
	memcpy(m + 8, &sec, 4);
	assert_int_equal(dao_ros2_tf_parse(m, n, count_cb, &got), -EINVAL);
}

/* DAO_TF_STATIC_IF_ALONE: static when it is its frame's only stamp, else dynamic. */
static void test_lone_static(void **state)
{
	(void)state;
	struct dao_tf_buffer *b;
	struct dao_error err;
	struct dao_rigid got, tr = yaw(30, 1, 0, 0), other = yaw(40, 0, 1, 0);
	assert_int_equal(dao_tf_buffer_create(&b, 8, 8, &err), 0);
	assert_int_equal(add(b, "w", "lone", 10 * S, tr, DAO_TF_STATIC_IF_ALONE), 0);
	assert_int_equal(add(b, "w", "twice", 10 * S, other, DAO_TF_STATIC_IF_ALONE), 0);
	assert_int_equal(add(b, "w", "twice", 10 * S, tr, DAO_TF_STATIC_IF_ALONE), 0);
	assert_int_equal(add(b, "w", "moving", 10 * S, tr, DAO_TF_STATIC_IF_ALONE), 0);
	assert_int_equal(add(b, "w", "moving", 11 * S, tr, DAO_TF_STATIC_IF_ALONE), 0);
	assert_int_equal(add(b, "w", "ros", 10 * S, tr, DAO_TF_DYNAMIC), 0);
	assert_int_equal(dao_tf_buffer_finish(b, &err), 0);
	assert_int_equal(dao_tf_buffer_samples(b), 3); /* moving's two, ros' one */
	int w = dao_tf_buffer_find(b, "w");
	/* the lone ones hold at every time, the later of one stamp */
	assert_int_equal(dao_tf_buffer_lookup(b, w, dao_tf_buffer_find(b, "lone"), 0, S, &got,
					      &err), 0);
	near(&got, &tr, 1e-12);
	assert_int_equal(dao_tf_buffer_lookup(b, w, dao_tf_buffer_find(b, "twice"), 99 * S, S,
					      &got, &err), 0);
	near(&got, &tr, 1e-12);
	/* two stamps, or a ROS sample: dynamic, no extrapolation */
	assert_int_equal(dao_tf_buffer_lookup(b, w, dao_tf_buffer_find(b, "moving"), 12 * S, S,
					      &got, &err), -ENOENT);
	assert_int_equal(dao_tf_buffer_lookup(b, w, dao_tf_buffer_find(b, "ros"), 0, S, &got, &err),
			 -ENOENT);
	dao_tf_buffer_free(b);
}

/* The protobuf wire format, written by hand (field numbers of foxglove_msg.h). */
static size_t pb_varint(uint8_t *p, uint64_t v)
{
	size_t n = 0;
	do {
		p[n++] = (uint8_t)((v & 0x7F) | (v > 0x7F ? 0x80 : 0));
		v >>= 7;
	} while (v);
	return n;
}

static size_t pb_f64(uint8_t *p, uint32_t field, double v)
{
	size_t n = pb_varint(p, field << 3 | 1);
	return n + put(p + n, &v, 8);
}

static size_t pb_len(uint8_t *p, uint32_t field, const void *d, size_t len)
{
	size_t n = pb_varint(p, field << 3 | 2);
	n += pb_varint(p + n, len);
	return n + put(p + n, d, len);
}

/* Fields 1 (a Timestamp of 100 s + 5 ns) and 2 ("odom"): their bytes. */
static size_t pb_stamp_odom(uint8_t *p)
{
	uint8_t ts[16];
	size_t k = pb_varint(ts, 1 << 3);
	k += pb_varint(ts + k, 100);
	k += pb_varint(ts + k, 2 << 3);
	k += pb_varint(ts + k, 5);
	size_t n = pb_len(p, 1, ts, k);
	return n + pb_len(p + n, 2, "odom", 4);
}

/* A FrameTransform of count_cb's values: 100 s + 5 ns, odom -> cam, (1, 2, 3), identity. */
static size_t pb_transform(uint8_t *p, int rotation)
{
	uint8_t v[64];
	size_t n = pb_stamp_odom(p), k;
	n += pb_len(p + n, 3, "cam", 3);
	k = pb_f64(v, 1, 1) + pb_f64(v + 9, 2, 2);
	k += pb_f64(v + k, 3, 3);
	n += pb_len(p + n, 4, v, k);
	if (rotation) { /* w alone (x, y, z left out: 0) */
		k = pb_f64(v, 4, 1);
		n += pb_len(p + n, 5, v, k);
	}
	return n;
}

static int any_cb(void *user, const struct dao_tf_msg_transform *t)
{
	(void)t;
	(*(int *)user)++;
	return 0;
}

static int keep_cb(void *user, const struct dao_tf_msg_transform *t)
{
	*(struct dao_tf_msg_transform *)user = *t;
	return 0;
}

static void test_foxglove_protobuf(void **state)
{
	(void)state;
	uint8_t m[512], l[1024];
	int got = 0;
	size_t n = pb_transform(m, 1);
	assert_int_equal(dao_fg_frame_transforms_parse(DAO_FG_PROTOBUF, 0, m, n, count_cb, &got), 0);
	assert_int_equal(got, 1);
	/* cut short inside the rotation (its length past the end): refused */
	for (size_t cut = n - 9; cut < n; cut++)
		assert_int_equal(dao_fg_frame_transforms_parse(DAO_FG_PROTOBUF, 0, m, cut, count_cb,
							       &got), -EINVAL);
	/* any cut: refused or a shorter message, never more */
	for (size_t cut = 0; cut < n; cut++) {
		int k = 0;
		int r = dao_fg_frame_transforms_parse(DAO_FG_PROTOBUF, 0, m, cut, any_cb, &k);
		assert_true((r == 0 && k == 1) || (r == -EINVAL && k == 0));
	}
	/* no rotation: the identity; a rotation of x alone: w 0 */
	struct dao_tf_msg_transform t;
	n = pb_transform(m, 0);
	assert_int_equal(dao_fg_frame_transforms_parse(DAO_FG_PROTOBUF, 0, m, n, keep_cb, &t), 0);
	assert_true(t.tr.q[3] == 1.0 && t.tr.q[0] == 0.0 && t.child_len == 3);
	uint8_t x[16];
	n += pb_len(m + n, 5, x, pb_f64(x, 1, 1));
	assert_int_equal(dao_fg_frame_transforms_parse(DAO_FG_PROTOBUF, 0, m, n, keep_cb, &t), 0);
	assert_true(t.tr.q[3] == 0.0 && t.tr.q[0] == 1.0);
	/* a component of the wrong wire type; a translation as a varint */
	x[0] = 3 << 3;
	x[1] = 1;
	n = pb_transform(m, 0);
	assert_int_equal(dao_fg_frame_transforms_parse(DAO_FG_PROTOBUF, 0, m, n + pb_len(m + n, 5, x, 2),
						       keep_cb, &t), -EINVAL);
	n += pb_varint(m + n, 4 << 3);
	n += pb_varint(m + n, 7);
	assert_int_equal(dao_fg_frame_transforms_parse(DAO_FG_PROTOBUF, 0, m, n, keep_cb, &t), -EINVAL);
	/* FrameTransforms: two delivered; with a third cut short, none */
	size_t k = pb_transform(m, 1), ln = pb_len(l, 1, m, k);
	ln += pb_len(l + ln, 1, m, k);
	got = 0;
	assert_int_equal(dao_fg_frame_transforms_parse(DAO_FG_PROTOBUF, 1, l, ln, count_cb, &got), 0);
	assert_int_equal(got, 2);
	size_t bad = ln + pb_len(l + ln, 1, m, k - 3);
	assert_int_equal(dao_fg_frame_transforms_parse(DAO_FG_PROTOBUF, 1, l, bad, count_cb, &got),
			 -EINVAL);
	assert_int_equal(got, 2);
	/* nanoseconds of 1e9 */
	uint8_t ts[16];
	size_t tn = pb_varint(ts, 2 << 3);
	tn += pb_varint(ts + tn, 1000000000u);
	n = pb_len(m, 1, ts, tn);
	assert_int_equal(dao_fg_frame_transforms_parse(DAO_FG_PROTOBUF, 0, m, n, keep_cb, &t), -EINVAL);
}

static int json(const char *text, int list, dao_tf_msg_cb cb, void *user)
{
	return dao_fg_frame_transforms_parse(DAO_FG_JSON, list, (const uint8_t *)text, strlen(text),
					     cb, user);
}

#define FT "{\"timestamp\": {\"sec\": 100, \"nsec\": 5}, \"parent_frame_id\": \"odom\", " \
	"\"child_frame_id\": \"cam\", \"translation\": {\"x\": 1, \"y\": 2.0, \"z\": 3}, " \
	"\"rotation\": {\"x\": 0, \"y\": 0, \"z\": 0, \"w\": 1}}"

/* Adds a transform to a buffer while its names are valid (a JSON message's: in the call). */
struct adding {
	struct dao_tf_buffer *b;
	int ret;
	struct dao_error err;
	struct dao_tf_msg_transform t;
};

static int add_cb(void *user, const struct dao_tf_msg_transform *t)
{
	struct adding *a = user;
	a->t = *t;
	a->ret = dao_tf_buffer_add(a->b, t->parent, t->parent_len, t->child, t->child_len, 1,
				   &t->tr, DAO_TF_DYNAMIC, &a->err);
	return 0;
}

static void test_foxglove_json(void **state)
{
	(void)state;
	int got = 0;
	assert_int_equal(json(FT, 0, count_cb, &got), 0);
	assert_int_equal(got, 1);
	assert_int_equal(json("{\"transforms\": [" FT ", " FT "]}", 1, count_cb, &got), 0);
	assert_int_equal(got, 3);
	/* cut short anywhere: not JSON; nothing delivered from a list with a bad member */
	char cut[sizeof(FT)];
	for (size_t k = 0; k + 1 < sizeof(FT); k++) {
		memcpy(cut, FT, k);
		cut[k] = 0;
		assert_int_equal(json(cut, 0, count_cb, &got), -EINVAL);
	}
	assert_int_equal(json("{\"transforms\": [" FT ", 5]}", 1, count_cb, &got), -EINVAL);
	assert_int_equal(json("{\"transforms\": " FT "}", 1, count_cb, &got), -EINVAL);
	assert_int_equal(got, 3);
	/* a number as a string; nanoseconds of 1e9 */
	assert_int_equal(json("{\"translation\": {\"x\": \"1\"}}", 0, any_cb, &got), -EINVAL);
	assert_int_equal(json("{\"timestamp\": {\"sec\": 1, \"nsec\": 1000000000}}", 0, any_cb,
			      &got), -EINVAL);
	/* left out: 0, "", the identity; NaN read as it is, then refused by the buffer */
	struct adding a = { 0 };
	assert_int_equal(dao_tf_buffer_create(&a.b, 8, 8, &a.err), 0);
	assert_int_equal(json("{\"parent_frame_id\": \"odom\"}", 0, add_cb, &a), 0);
	assert_true(a.t.stamp_ns == 0 && a.t.child_len == 0 && a.t.tr.q[3] == 1.0 &&
		    a.t.tr.t[0] == 0.0);
	assert_int_equal(a.ret, 1);
	assert_non_null(strstr(a.err.message, "empty"));
	assert_int_equal(json("{\"parent_frame_id\": \"odom\", \"child_frame_id\": \"c\", "
			      "\"rotation\": {\"x\": 0, \"y\": 0, \"z\": 0, \"w\": NaN}}", 0,
			      add_cb, &a), 0);
	assert_true(isnan(a.t.tr.q[3]));
	assert_int_equal(a.ret, 1);
	assert_non_null(strstr(a.err.message, "not a finite number"));
	dao_tf_buffer_free(a.b);
}

/* A CDR message: header, sec 100, nsec 5, frame_id "odom", then (list) a count of poses, then
 * poses of translation 1 2 3 and the identity; its length. */
static size_t cdr_pose(uint8_t *m, int list, uint32_t poses)
{
	int32_t sec = 100;
	uint32_t nsec = 5, l1 = 5;
	size_t n = 4;
	memcpy(m, (uint8_t[]){ 0, 1, 0, 0 }, 4);
	n += put(m + n, &sec, 4);
	n += put(m + n, &nsec, 4);
	n += put(m + n, &l1, 4);
	n += put(m + n, "odom", 5);
	n = 4 + ((n - 4 + 3) & ~(size_t)3);
	if (list)
		n += put(m + n, &poses, 4);
	if (poses)
		n = 4 + ((n - 4 + 7) & ~(size_t)7);
	double v[7] = { 1, 2, 3, 0, 0, 0, 1 };
	for (uint32_t i = 0; i < poses; i++)
		n += put(m + n, v, sizeof v);
	return n;
}

/* foxglove_msgs/msg/ in CDR: PoseInFrame(s) (one pose only), FrameTransform. */
static void test_foxglove_cdr(void **state)
{
	(void)state;
	uint8_t m[256];
	struct dao_tf_msg_transform t;
	int got = 0;
	for (int list = 0; list < 2; list++) {
		size_t n = cdr_pose(m, list, 1);
		assert_int_equal(dao_ros2_fg_pose_parse(list, m, n, keep_cb, &t), 0);
		assert_true(t.parent_len == 4 && !memcmp(t.parent, "odom", 4) && t.child_len == 0);
		assert_int_equal(dao_ros2_fg_pose_parse(list, m, n, count_cb, &got), 0);
		for (size_t cut = 0; cut < n; cut++)
			assert_true(dao_ros2_fg_pose_parse(list, m, cut, count_cb, &got) < 0);
		assert_int_equal(got, list + 1);
	}
	/* two poses or none: which is the camera's is unknown */
	assert_int_equal(dao_ros2_fg_pose_parse(1, m, cdr_pose(m, 1, 2), count_cb, &got), -ERANGE);
	assert_int_equal(dao_ros2_fg_pose_parse(1, m, cdr_pose(m, 1, 0), count_cb, &got), -ERANGE);
	/* a count past the bytes: not the type */
	assert_int_equal(dao_ros2_fg_pose_parse(1, m, cdr_pose(m, 1, 2) - 8, count_cb, &got), -EINVAL);
	assert_int_equal(got, 2);
	/* FrameTransform: a TransformStamped alone (frame_id then child_frame_id) */
	size_t n = cdr_pose(m, 0, 0); /* up to frame_id, aligned to 4 */
	uint32_t l2 = 4;
	n += put(m + n, &l2, 4);
	n += put(m + n, "cam", 4);
	n = 4 + ((n - 4 + 7) & ~(size_t)7);
	double v[7] = { 1, 2, 3, 0, 0, 0, 1 };
	n += put(m + n, v, sizeof v);
	assert_int_equal(dao_ros2_fg_transform_parse(m, n, keep_cb, &t), 0);
	assert_true(t.child_len == 3 && !memcmp(t.child, "cam", 3) && t.tr.t[1] == 2.0);
	for (size_t cut = 0; cut < n; cut++)
		assert_true(dao_ros2_fg_transform_parse(m, cut, count_cb, &got) < 0);
	assert_int_equal(got, 2);
}

/* foxglove.PoseInFrame(s) in protobuf: timestamp 1, frame_id 2, pose(s) 3 (position 1,
 * orientation 2). */
static size_t pb_pose_in_frame(uint8_t *p, int poses, int orientation)
{
	uint8_t v[64], pose[160];
	size_t n = pb_stamp_odom(p), k = pb_f64(v, 1, 1) + pb_f64(v + 9, 2, 2);
	k += pb_f64(v + k, 3, 3);
	size_t pn = pb_len(pose, 1, v, k);
	if (orientation)
		pn += pb_len(pose + pn, 2, v, pb_f64(v, 4, 1));
	for (int i = 0; i < poses; i++)
		n += pb_len(p + n, 3, pose, pn);
	return n;
}

static int json_poses(const char *text, int list, dao_tf_msg_cb cb, void *user)
{
	return dao_fg_poses_parse(DAO_FG_JSON, list, (const uint8_t *)text, strlen(text), cb, user);
}

#define FP "{\"position\": {\"x\": 1, \"y\": 2, \"z\": 3}, \"orientation\": {\"w\": 1}}"
#define PIF "{\"timestamp\": {\"sec\": 100, \"nsec\": 5}, \"frame_id\": \"odom\", "

static void test_foxglove_poses(void **state)
{
	(void)state;
	uint8_t m[512];
	struct dao_tf_msg_transform t;
	int got = 0;
	size_t n = pb_pose_in_frame(m, 1, 1);
	for (int list = 0; list < 2; list++)
		assert_int_equal(dao_fg_poses_parse(DAO_FG_PROTOBUF, list, m, n, count_cb, &got), 0);
	assert_int_equal(dao_fg_poses_parse(DAO_FG_PROTOBUF, 0, m, n, keep_cb, &t), 0);
	assert_true(t.parent_len == 4 && t.child_len == 0 && t.tr.t[0] == 1.0);
	for (size_t cut = n - 9; cut < n; cut++) /* inside the pose */
		assert_int_equal(dao_fg_poses_parse(DAO_FG_PROTOBUF, 0, m, cut, count_cb, &got),
				 -EINVAL);
	assert_int_equal(got, 2);
	/* PosesInFrame of two or none: refused as such */
	n = pb_pose_in_frame(m, 2, 1);
	assert_int_equal(dao_fg_poses_parse(DAO_FG_PROTOBUF, 1, m, n, count_cb, &got), -ERANGE);
	n = pb_pose_in_frame(m, 0, 1);
	assert_int_equal(dao_fg_poses_parse(DAO_FG_PROTOBUF, 1, m, n, count_cb, &got), -ERANGE);
	/* the pose or its orientation left out: the identity */
	assert_int_equal(dao_fg_poses_parse(DAO_FG_PROTOBUF, 0, m, n, keep_cb, &t), 0);
	assert_true(t.tr.q[3] == 1.0 && t.tr.t[0] == 0.0);
	n = pb_pose_in_frame(m, 1, 0);
	assert_int_equal(dao_fg_poses_parse(DAO_FG_PROTOBUF, 0, m, n, keep_cb, &t), 0);
	assert_true(t.tr.q[3] == 1.0 && t.tr.t[2] == 3.0);
	/* JSON */
	assert_int_equal(json_poses(PIF "\"pose\": " FP "}", 0, count_cb, &got), 0);
	assert_int_equal(json_poses(PIF "\"poses\": [" FP "]}", 1, count_cb, &got), 0);
	assert_int_equal(got, 4);
	assert_int_equal(json_poses(PIF "\"poses\": [" FP ", " FP "]}", 1, count_cb, &got), -ERANGE);
	assert_int_equal(json_poses(PIF "\"poses\": []}", 1, count_cb, &got), -ERANGE);
	assert_int_equal(json_poses(PIF "\"poses\": [5]}", 1, count_cb, &got), -EINVAL);
	assert_int_equal(json_poses(PIF "\"pose\": 5}", 0, count_cb, &got), -EINVAL);
	assert_int_equal(json_poses(PIF "\"pose\": " FP, 0, count_cb, &got), -EINVAL);
	assert_int_equal(got, 4);
	assert_int_equal(json_poses("{\"frame_id\": \"odom\", \"pose\": {\"orientation\": "
				    "{\"x\": 1}}}", 0, keep_cb, &t), 0);
	assert_true(t.tr.q[3] == 0.0 && t.tr.q[0] == 1.0 && t.stamp_ns == 0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_compose_interpolate),
		cmocka_unit_test(test_gaps),
		cmocka_unit_test(test_structure),
		cmocka_unit_test(test_values),
		cmocka_unit_test(test_ros1_messages),
		cmocka_unit_test(test_ros2_messages),
		cmocka_unit_test(test_lone_static),
		cmocka_unit_test(test_foxglove_protobuf),
		cmocka_unit_test(test_foxglove_json),
		cmocka_unit_test(test_foxglove_cdr),
		cmocka_unit_test(test_foxglove_poses),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
