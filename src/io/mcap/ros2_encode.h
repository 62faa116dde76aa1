/* SPDX-License-Identifier: MIT */
#ifndef DAO_MCAP_ROS2_ENCODE_H
#define DAO_MCAP_ROS2_ENCODE_H

/*
 * ROS 2 messages in CDR (XCDR1, little-endian; cdr.h describes the layout)
 * for the MCAP sink: sensor_msgs/msg/Image, CameraInfo and PointCloud2,
 * with their ros2msg schemas (the .msg text and its dependencies, each
 * after a line of 80 '=' and "MSG: pkg/Type", as ROS 2 bags store them).
 * Each message has a size function and an encoder that writes exactly that
 * many bytes to `out`.
 */
#include <stddef.h>
#include <stdint.h>

#include <depthao/frame.h>

extern const char dao_ros2_image_schema[];
extern const char dao_ros2_camera_info_schema[];
extern const char dao_ros2_point_cloud2_schema[];

/* Image: `img`'s rows (width x bytes_per_pixel bytes each) as step-packed data. */
size_t dao_ros2_image_size(const char *frame_id, const char *encoding, const struct dao_frame *img);
void dao_ros2_image_encode(uint8_t *out, uint64_t stamp_ns, const char *frame_id,
			   const char *encoding, const struct dao_frame *img);

/* CameraInfo of a pinhole camera without distortion ("plumb_bob", d = 0). */
struct dao_ros2_pinhole {
	uint32_t width, height;
	double fx, fy, cx, cy;
};
size_t dao_ros2_camera_info_size(const char *frame_id);
void dao_ros2_camera_info_encode(uint8_t *out, uint64_t stamp_ns, const char *frame_id,
				 const struct dao_ros2_pinhole *cam);

/*
 * PointCloud2 of `npoints` points (height 1, dense) with float32 fields
 * x, y, z, ao (16 bytes a point): the encoder writes everything but the
 * points and returns where their npoints x 16 bytes go.
 */
#define DAO_ROS2_CLOUD_POINT_STEP 16
size_t dao_ros2_cloud_size(const char *frame_id, uint32_t npoints);
uint8_t *dao_ros2_cloud_encode(uint8_t *out, uint64_t stamp_ns, const char *frame_id,
			       uint32_t npoints);

/*
 * tf2_msgs/msg/TFMessage with one transform: `child` in `parent` at stamp_ns,
 * rotation q (x, y, z, w) and translation t (m), as geometry_msgs/Transform
 * has them (x_parent = R x_child + t).
 */
extern const char dao_ros2_tf_schema[];
size_t dao_ros2_tf_size(const char *parent, const char *child);
void dao_ros2_tf_encode(uint8_t *out, uint64_t stamp_ns, const char *parent, const char *child,
			const double q[4], const double t[3]);

#endif
