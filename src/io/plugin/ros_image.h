/* SPDX-License-Identifier: MIT */
#ifndef DAO_PLUGIN_ROS_IMAGE_H
#define DAO_PLUGIN_ROS_IMAGE_H

/*
 * What the ROS recording sources (bag: ROS 1, mcap: ROS 2) share once a
 * sensor_msgs Image or CameraInfo is parsed: the encodings they take, the
 * pixel copies into depthao's frames and the intrinsics from a CameraInfo.
 */
#include <stddef.h>
#include <stdint.h>

#include <depthao/error.h>

#include <depthao/frame.h>
#include <depthao/plugin.h>

#include "tf/tf_buffer.h"

/*
 * "FILE?topic=T&unit=M&color=C&pose_frame=F&pose_topic=O&pose_gap=S" in parts (the options in any order, all
 * optional); the options start at the last '?' followed by one of them (a
 * file name may hold a '?'; dao_uri_path_len()).  `scheme` names the source
 * in errors.  path is allocated: dao_ros_uri_free().
 */
struct dao_ros_uri {
	char *path;
	char topic[256];
	char color[256];
	float unit; /* metres per count, 0: not given */
	char pose_frame[256]; /* the fixed frame of the poses, "": the depth frame's tf root */
	char pose_topic[256]; /* an odometry topic instead of /tf, or the transform topic to read */
	double pose_gap;      /* seconds: the longest interpolation between transforms */
};

extern const char *const dao_ros_uri_options[];
int dao_ros_uri_parse(const char *uri, const char *scheme, struct dao_ros_uri *u,
		      struct dao_error *err);
void dao_ros_uri_free(struct dao_ros_uri *u);

/* A header.frame_id of n bytes kept in buf (DAO_TF_NAME_MAX + 1 bytes); *len = n (longer
 * than DAO_TF_NAME_MAX: not copied, the length says it was too long). */
void dao_ros_keep_frame_id(char *buf, uint32_t *len, const char *id, uint32_t n);

/* Appends "name (encoding)" to a comma-separated list of topics in buf (cap bytes). */
void dao_ros_topic_list_add(char *buf, size_t cap, const char *name, const char *encoding);

/* A depth encoding: 1 for 16-bit counts (16UC1, mono16), 2 for float metres (32FC1), else 0. */
int dao_ros_depth_kind(const char *encoding);
/* Bytes a pixel of a colour encoding (rgb8, bgr8, rgba8, bgra8, mono8), 0 for others. */
uint32_t dao_ros_color_bytes(const char *encoding);

/* Rows of `bpp`-byte depth values (step bytes apart) into `dst`, byte-swapped if `swap`. */
void dao_ros_copy_depth(struct dao_frame *dst, const uint8_t *src, uint32_t step, uint32_t bpp,
			int swap);
/* Rows of a colour encoding into an RGB24 frame of the same size. */
void dao_ros_color_to_rgb(struct dao_frame *dst, const uint8_t *src, uint32_t step,
			  const char *encoding);
int dao_ros_host_is_big_endian(void);

/*
 * The intrinsics of a CameraInfo (`name` for messages) into `info` (of
 * width x height depth): has_intrinsics and the FOV set, or a warning
 * saying why not (another size) or that the depth must be rectified.
 * Implausible numbers (dao_camera_from_camera_info refuses them) are a
 * damaged calibration: -EINVAL with `err` naming `path`, `name` and the value.
 */
int dao_ros_camera_info_intrinsics(struct dao_source_info *info, const char *path,
				   const char *name, uint32_t width, uint32_t height,
				   const double k[9], const double p[12], const double *d, uint32_t nd,
				   struct dao_error *err);

#endif
