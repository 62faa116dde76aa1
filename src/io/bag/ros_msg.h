/* SPDX-License-Identifier: MIT */
#ifndef DAO_BAG_ROS_MSG_H
#define DAO_BAG_ROS_MSG_H

/*
 * The few ROS 1 messages the bag source reads, from their serialized form
 * (little-endian; a string or variable array is a u32 length then the
 * items; http://wiki.ros.org/msg).  Parsers check every length against the
 * message and return -EINVAL for anything that does not fit.
 */
#include <stdint.h>

#include "tf/tf_msg.h"

/* std_msgs/Header (seq u32, stamp: sec u32 + nsec u32, frame_id string). */
struct dao_ros_header {
	uint32_t seq;
	uint64_t stamp_ns;
	const char *frame_id;       /* into the message, frame_id_len bytes, no NUL */
	uint32_t frame_id_len;
};

/* sensor_msgs/Image; data points into the message. */
struct dao_ros_image {
	struct dao_ros_header header;
	uint32_t height, width;
	char encoding[32];
	uint8_t is_bigendian;
	uint32_t step;
	const uint8_t *data;
	uint32_t data_len;
};

/* sensor_msgs/CameraInfo: the parts used (K, R, P row-major; binning and
 * roi, which follow P, are not read). */
#define DAO_ROS_MAX_DISTORTION 16

struct dao_ros_camera_info {
	struct dao_ros_header header;
	uint32_t height, width;
	uint32_t distortion_count; /* entries of D */
	double d[DAO_ROS_MAX_DISTORTION]; /* its first entries (no model has more) */
	double k[9];               /* the raw (distorted) image's camera matrix, 3x3 */
	double r[9];               /* rectification rotation, 3x3 */
	double p[12];              /* the rectified image's projection, 3x4 */
};

int dao_ros_image_parse(const uint8_t *msg, uint32_t len, struct dao_ros_image *img);
int dao_ros_camera_info_parse(const uint8_t *msg, uint32_t len, struct dao_ros_camera_info *ci);
/* std_msgs/Float32 */
int dao_ros_float32_parse(const uint8_t *msg, uint32_t len, float *value);

/*
 * tf2_msgs/TFMessage (or tf/tfMessage, the same layout): a u32 count of
 * geometry_msgs/TransformStamped (Header, child_frame_id string, Transform:
 * translation Vector3 and rotation Quaternion x, y, z, w, float64 each).  The
 * whole message is checked first, then `cb` gets each transform: 0, -EINVAL
 * (a message that does not fit the layout, or a nanosecond field of 1e9 or
 * more: nothing delivered), or cb's value.
 */
int dao_ros_tf_parse(const uint8_t *msg, uint32_t len, dao_tf_msg_cb cb, void *user);
/*
 * nav_msgs/Odometry: Header, child_frame_id, PoseWithCovariance (Pose:
 * position Point, orientation Quaternion; covariance float64[36]),
 * TwistWithCovariance (the twist and its covariance: read past, checked for
 * length).  0 or -EINVAL.
 */
int dao_ros_odometry_parse(const uint8_t *msg, uint32_t len, struct dao_tf_msg_transform *out);
/*
 * sensor_msgs/Imu: Header, orientation Quaternion, float64[9] its covariance,
 * angular_velocity Vector3, float64[9], linear_acceleration Vector3,
 * float64[9].  0 or -EINVAL.
 */
int dao_ros_imu_parse(const uint8_t *msg, uint32_t len, struct dao_imu_msg *out);

#endif
