/* SPDX-License-Identifier: MIT */
#ifndef DAO_TF_TF_MSG_H
#define DAO_TF_TF_MSG_H

/*
 * A transform as the message parsers deliver it (ROS 1 in bag/ros_msg.h,
 * ROS 2 CDR in mcap/ros2_msg.h, Foxglove in mcap/foxglove_msg.h):
 * geometry_msgs/TransformStamped of a tf2_msgs/TFMessage, the pose of a
 * nav_msgs/Odometry (its child_frame_id in its header's frame_id), or a
 * foxglove.FrameTransform.  The names point into the message (not
 * NUL-terminated; a JSON message's into its parsed form, valid during the
 * callback only); the values are as read, unchecked (dao_tf_buffer_add
 * checks them).
 */
#include <stdint.h>

#include "tf/rigid.h"

struct dao_tf_msg_transform {
	uint64_t stamp_ns;
	const char *parent;         /* header.frame_id */
	uint32_t parent_len;
	const char *child;          /* child_frame_id */
	uint32_t child_len;
	struct dao_rigid tr;        /* child -> parent */
};

/* Called per transform of a message; a value < 0 stops the parser, which returns it. */
typedef int (*dao_tf_msg_cb)(void *user, const struct dao_tf_msg_transform *t);

/*
 * What the poses take of a sensor_msgs/Imu (ROS 1 in bag/ros_msg.h, ROS 2
 * CDR in mcap/ros2_msg.h): the stamp, the IMU's frame (into the message, not
 * NUL-terminated), its orientation where it has one (orientation_covariance[0]
 * is not -1, the message's convention for "no orientation") and its angular
 * velocity (rad/s, in the IMU's frame); the linear acceleration is read past.
 * Values as read, unchecked (source_poses.c checks them).
 */
struct dao_imu_msg {
	uint64_t stamp_ns;
	const char *frame;          /* header.frame_id */
	uint32_t frame_len;
	int has_orientation;
	double q[4];                /* orientation x, y, z, w: the IMU's frame -> a fixed one */
	double w[3];                /* angular_velocity */
};

#endif
