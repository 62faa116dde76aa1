/* SPDX-License-Identifier: MIT */
#ifndef DAO_MCAP_ROS2_MSG_H
#define DAO_MCAP_ROS2_MSG_H

/*
 * The ROS 2 messages the MCAP source reads, from their CDR form (cdr.h):
 * sensor_msgs/msg/Image, CompressedImage and CameraInfo.  A ROS 2
 * std_msgs/msg/Header has no seq: stamp (builtin_interfaces/Time: sec
 * int32, nanosec uint32) then frame_id.  The parsers return 0, -EINVAL
 * for a message that does not fit its type, or -ENOTSUP for an
 * encapsulation other than XCDR1.
 */
#include <stdint.h>

#include "mcap/foxglove_msg.h"
#include "tf/tf_msg.h"

struct dao_ros2_header {
	uint64_t stamp_ns; /* 0 for a stamp before 1970 */
	const char *frame_id; /* into the message, frame_id_len bytes (NUL after them) */
	uint32_t frame_id_len;
};

/* sensor_msgs/msg/Image; data points into the message. */
struct dao_ros2_image {
	struct dao_ros2_header header;
	uint32_t height, width;
	char encoding[32];
	uint8_t is_bigendian;
	uint32_t step;
	const uint8_t *data;
	uint32_t data_len;
};

/* sensor_msgs/msg/CompressedImage; data points into the message. */
struct dao_ros2_compressed_image {
	struct dao_ros2_header header;
	char format[64]; /* "jpeg", "16UC1; compressedDepth png" ... */
	const uint8_t *data;
	uint32_t data_len;
};

#define DAO_ROS2_MAX_DISTORTION 16

/* sensor_msgs/msg/CameraInfo: the parts used (K, R, P row-major). */
struct dao_ros2_camera_info {
	struct dao_ros2_header header;
	uint32_t height, width;
	char distortion_model[32];
	uint32_t distortion_count;
	double d[DAO_ROS2_MAX_DISTORTION];
	double k[9], r[9], p[12];
};

int dao_ros2_image_parse(const uint8_t *msg, uint64_t len, struct dao_ros2_image *img);
int dao_ros2_compressed_image_parse(const uint8_t *msg, uint64_t len,
				    struct dao_ros2_compressed_image *img);
int dao_ros2_camera_info_parse(const uint8_t *msg, uint64_t len, struct dao_ros2_camera_info *ci);

/*
 * tf2_msgs/msg/TFMessage: a sequence of geometry_msgs/msg/TransformStamped
 * (Header, child_frame_id, Transform: translation Vector3, rotation
 * Quaternion x, y, z, w).  The whole message is checked first (a stamp
 * before 1970 or a nanosec of 1e9 or more refuses it), then `cb` gets each
 * transform: 0, -EINVAL, -ENOTSUP (encapsulation) or cb's value.
 */
int dao_ros2_tf_parse(const uint8_t *msg, uint64_t len, dao_tf_msg_cb cb, void *user);
/* nav_msgs/msg/Odometry: its pose (child_frame_id in header.frame_id); the covariances and
 * the twist are read past.  0, -EINVAL or -ENOTSUP. */
int dao_ros2_odometry_parse(const uint8_t *msg, uint64_t len, struct dao_tf_msg_transform *out);
/* sensor_msgs/msg/Imu: its stamp, frame, orientation (where it has one) and angular
 * velocity; the covariances and the linear acceleration are read past.  0, -EINVAL or
 * -ENOTSUP. */
int dao_ros2_imu_parse(const uint8_t *msg, uint64_t len, struct dao_imu_msg *out);

/*
 * Foxglove's ROS 2 messages (foxglove_msgs/msg/...), cb per transform as
 * dao_ros2_tf_parse: FrameTransform is a TransformStamped (timestamp
 * builtin_interfaces/Time, parent_frame_id, child_frame_id, translation,
 * rotation), so a FrameTransforms is a TFMessage (dao_ros2_tf_parse reads
 * it); PoseInFrame (list 0: timestamp, frame_id, geometry_msgs/Pose pose)
 * or PosesInFrame (list 1: ... Pose[] poses) gives its pose as frame_id's
 * transform with an empty child.  0, -EINVAL, -ENOTSUP, -ERANGE for a
 * PosesInFrame whose poses are not exactly one, or cb's value.
 */
int dao_ros2_fg_transform_parse(const uint8_t *msg, uint64_t len, dao_tf_msg_cb cb, void *user);
int dao_ros2_fg_pose_parse(int list, const uint8_t *msg, uint64_t len, dao_tf_msg_cb cb,
			   void *user);

/*
 * Foxglove's image schemas as ROS 2 messages (foxglove_msgs/msg/..., what
 * `ros2 bag record` stores of a node publishing them), into the structs of
 * their protobuf and JSON forms (foxglove_msg.h; dao_fg_*_parse call these
 * for DAO_FG_CDR), with the same rules: timestamp builtin_interfaces/Time
 * (a sec before 1970 is 0, a nanosec of 1e9 or more refuses the message),
 * frame_id and encoding copied whole (too long or holding a NUL refuses it),
 * the pixels little-endian whatever the encapsulation (RawImage has no
 * byte-order field).
 *   RawImage: timestamp, frame_id, width, height (uint32), encoding, step
 *     (uint32), data (uint8[]);
 *   CompressedImage: timestamp, frame_id, data (uint8[]), format;
 *   CameraCalibration: timestamp, frame_id, width, height (uint32),
 *     distortion_model, d (float64[]), k (float64[9]), r (float64[9]), p
 *     (float64[12]: all 0 reads as no P).
 * data points into the message.  0, -EINVAL or -ENOTSUP (encapsulation).
 */
int dao_ros2_fg_image_parse(int compressed, const uint8_t *msg, uint64_t len,
			    struct dao_fg_image *img);
int dao_ros2_fg_calibration_parse(const uint8_t *msg, uint64_t len,
				  struct dao_fg_calibration *cal);

#endif
