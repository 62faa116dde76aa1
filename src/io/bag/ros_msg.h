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

/* std_msgs/Header (seq u32, stamp: sec u32 + nsec u32, frame_id string). */
struct dao_ros_header {
	uint32_t seq;
	uint64_t stamp_ns;
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

#endif
