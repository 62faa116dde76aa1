/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target: the tf, odometry and pose parsers (ROS 1 in
 * bag/ros_msg.c, ROS 2 CDR in mcap/ros2_msg.c, Foxglove's FrameTransform(s)
 * and PoseInFrame(s) in mcap/foxglove_msg.c) and the tf buffer they fill.
 * The first byte picks the parser: without bits 3 and 5, bits 0-1 are 0
 * ROS 1 TFMessage, 1 ROS 1 Odometry, 2 ROS 2 TFMessage, 3 ROS 2 Odometry;
 * with bit 3 (8), 0 FrameTransform in protobuf, 1 FrameTransforms in
 * protobuf, 2 FrameTransform in JSON, 3 FrameTransforms in JSON; with bits
 * 5 and 3 (40) the same of PoseInFrame and PosesInFrame; with bit 5 alone
 * (32), foxglove_msgs/msg/ in CDR: 0 or 3 FrameTransform, 1 PoseInFrame, 2
 * PosesInFrame (a pose goes in as frame "pose").  Bit 2 marks the
 * transforms static, else bit 4 static if alone (DAO_TF_STATIC_IF_ALONE).
 * The rest is the message.  Every transform delivered goes into a small
 * buffer (so its limits are met); then every pair of frames is looked up
 * at the stamps seen.  Aborts on a name pointing outside the input (JSON's
 * names are in the parsed text: NUL-terminated at their length instead),
 * or a pose that is not finite and unit.  The odometry cases also read the
 * message as a sensor_msgs/Imu (ROS 1 or 2, the same bits) and, where it
 * parses, run the IMU track (tf/imu_track.c) on it repeated at stamps the
 * message's bytes give, in rate and orientation mode: aborts on a frame
 * pointing outside the input, or an input source_poses.c takes (rates below
 * 1e4 rad/s, an orientation within 1e-3 of unit) turned into a rotation
 * that is not unit or stamps that do not increase.
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "bag/ros_msg.h"
#include "mcap/foxglove_msg.h"
#include "mcap/ros2_msg.h"
#include "tf/imu_track.h"
#include "tf/tf_buffer.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

struct ctx {
	struct dao_tf_buffer *b;
	const uint8_t *d;
	size_t size;
	int time, json;
	uint64_t stamps[8];
	int n;
};

static void inside(const char *p, uint32_t n, const struct ctx *c)
{
	const uint8_t *u = (const uint8_t *)p;
	if (c->json ? p[n] != 0 : n && (u < c->d || u + n > c->d + c->size))
		abort();
}

/* t into the buffer, its stamp kept for the lookups. */
static int buffer_add(struct ctx *c, const struct dao_tf_msg_transform *t)
{
	struct dao_error err;
	if (c->n < 8)
		c->stamps[c->n++] = t->stamp_ns;
	int r = dao_tf_buffer_add(c->b, t->parent, t->parent_len, t->child, t->child_len,
				  t->stamp_ns, &t->tr, c->time, &err);
	return r < 0 ? r : 0;
}

static int add(void *user, const struct dao_tf_msg_transform *t)
{
	inside(t->parent, t->parent_len, user);
	inside(t->child, t->child_len, user);
	return buffer_add(user, t);
}

/* A pose (a transform of an empty child): the camera's frame "pose". */
static int add_pose(void *user, const struct dao_tf_msg_transform *t)
{
	struct dao_tf_msg_transform p = *t;
	inside(t->parent, t->parent_len, user);
	if (t->child_len)
		abort();
	p.child = "pose";
	p.child_len = 4;
	return buffer_add(user, &p);
}

/* Bit 5's parsers (the pose topics, Foxglove's CDR). */
static void foxglove_poses(struct ctx *c, uint8_t tag)
{
	if (tag & 8) {
		(void)dao_fg_poses_parse(c->json ? DAO_FG_JSON : DAO_FG_PROTOBUF, tag & 1, c->d,
					 c->size, add_pose, c);
		return;
	}
	if ((tag & 3) == 1 || (tag & 3) == 2)
		(void)dao_ros2_fg_pose_parse((tag & 3) == 2, c->d, c->size, add_pose, c);
	else
		(void)dao_ros2_fg_transform_parse(c->d, c->size, add, c);
}

static void lookups(struct ctx *c)
{
	struct dao_error err;
	uint32_t n = dao_tf_buffer_frame_count(c->b);
	for (uint32_t a = 0; a < n; a++)
		for (uint32_t s = 0; s < n; s++)
			for (int k = 0; k < c->n; k++) {
				struct dao_rigid r;
				if (dao_tf_buffer_lookup(c->b, (int)a, (int)s, c->stamps[k] + 1000 * k,
							 500000000u, &r, &err) < 0)
					continue;
				double q = 0;
				for (int i = 0; i < 4; i++)
					q += r.q[i] * r.q[i];
				if (!(fabs(q - 1.0) < 1e-6) || !isfinite(r.t[0] + r.t[1] + r.t[2]))
					abort();
			}
}

/* m repeated at stamps from the input's bytes, through the IMU track in both modes */
static void imu(const struct dao_imu_msg *m, const uint8_t *d, size_t size)
{
	if (m->frame_len && (m->frame < (const char *)d ||
			     m->frame + m->frame_len > (const char *)d + size))
		abort();
	enum { N = 8 };
	struct dao_imu_sample s[N];
	/* what source_poses.c lets through: rates finite and below 1e4 rad/s, orientations
	 * within 1e-3 of unit */
	const double qn = sqrt(m->q[0] * m->q[0] + m->q[1] * m->q[1] + m->q[2] * m->q[2] +
			       m->q[3] * m->q[3]);
	const int ok[2] = { fabs(m->w[0]) < 1e4 && fabs(m->w[1]) < 1e4 && fabs(m->w[2]) < 1e4,
			    fabs(qn - 1.0) <= 1e-3 };
	for (int mode = 0; mode < 2; mode++) {
		const int finite = ok[mode];
		for (int i = 0; i < N; i++) {
			s[i] = (struct dao_imu_sample){ .stamp_ns = m->stamp_ns + d[(size_t)i % size] *
									     1000000ull };
			memcpy(s[i].q, m->q, sizeof s[i].q);
			memcpy(s[i].w, m->w, sizeof s[i].w);
		}
		const size_t n = dao_imu_track(s, N, mode, 200000000ull);
		if (n < 1 || n > N)
			abort();
		for (size_t i = 0; finite && i < n; i++) {
			const double q = s[i].q[0] * s[i].q[0] + s[i].q[1] * s[i].q[1] +
					 s[i].q[2] * s[i].q[2] + s[i].q[3] * s[i].q[3];
			if (!(fabs(q - 1.0) < 1e-9) || (i && s[i].stamp_ns <= s[i - 1].stamp_ns))
				abort();
		}
	}
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct ctx c = { 0 };
	struct dao_error err;
	struct dao_tf_msg_transform t;
	struct dao_imu_msg im;
	if (size < 1 || dao_tf_buffer_create(&c.b, 6, 16, &err) < 0)
		return 0;
	c.d = data + 1;
	c.size = size - 1;
	c.time = data[0] & 4 ? DAO_TF_STATIC : data[0] & 16 ? DAO_TF_STATIC_IF_ALONE : DAO_TF_DYNAMIC;
	c.json = (data[0] & 8) && (data[0] & 2);
	switch (data[0] & 32 ? 32 : data[0] & 11) {
	case 32:
		foxglove_poses(&c, data[0]);
		break;
	case 0:
		(void)dao_ros_tf_parse(c.d, (uint32_t)c.size, add, &c);
		break;
	case 1:
		if (dao_ros_odometry_parse(c.d, (uint32_t)c.size, &t) == 0)
			(void)add(&c, &t);
		if (c.size && dao_ros_imu_parse(c.d, (uint32_t)c.size, &im) == 0)
			imu(&im, c.d, c.size);
		break;
	case 2:
		(void)dao_ros2_tf_parse(c.d, c.size, add, &c);
		break;
	case 3:
		if (dao_ros2_odometry_parse(c.d, c.size, &t) == 0)
			(void)add(&c, &t);
		if (c.size && dao_ros2_imu_parse(c.d, c.size, &im) == 0)
			imu(&im, c.d, c.size);
		break;
	default: /* 8-11: Foxglove */
		(void)dao_fg_frame_transforms_parse(c.json ? DAO_FG_JSON : DAO_FG_PROTOBUF,
						    data[0] & 1, c.d, c.size, add, &c);
	}
	if (dao_tf_buffer_finish(c.b, &err) == 0)
		lookups(&c);
	dao_tf_buffer_free(c.b);
	return 0;
}
