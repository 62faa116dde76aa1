/* SPDX-License-Identifier: MIT */
#ifndef DAO_PLUGIN_ROS2_SOURCE_H
#define DAO_PLUGIN_ROS2_SOURCE_H

/*
 * The source behind "mcap" and "db3": depth (and colour) images from a log
 * of messages by topic, whatever holds them (an MCAP file, a rosbag2 sqlite3
 * database).  The container is a store: its topics, each with a schema and
 * a message encoding, and message i of a topic in log-time order.
 *
 * Messages read: ROS 2 in CDR (sensor_msgs/msg/Image, CompressedImage,
 * CameraInfo) and Foxglove's schemas in protobuf or JSON (foxglove.RawImage,
 * foxglove.CompressedImage, foxglove.CameraCalibration) or as ROS 2 messages in
 * CDR (foxglove_msgs/msg/RawImage, ...).  The rules (topic
 * choice, unit, intrinsics, colour pairing) are in ros2_source.c's head.
 */
#include <stdint.h>

#include <depthao/error.h>
#include <depthao/plugin.h>

#include "plugin/ros_image.h"

/* A topic of a store: the strings live as long as the store. */
struct dao_ros2_topic {
	const char *name;     /* "/camera/depth/image_raw" */
	const char *schema;   /* "sensor_msgs/msg/Image", "foxglove.RawImage" */
	const char *encoding; /* message encoding: "cdr", "protobuf", "json" */
	const char *schema_encoding; /* "ros2msg", "protobuf", "jsonschema"; "" where unknown */
	uint32_t message_count;
};

/* What a container gives the source; `impl` is the container's reader. */
struct dao_ros2_store_ops {
	const char *(*path)(const void *impl);
	/* NULL, or a line saying the file was read only in part */
	const char *(*warning)(const void *impl);
	uint32_t (*topic_count)(const void *impl);
	void (*topic)(const void *impl, uint32_t i, struct dao_ros2_topic *t);
	/* message i of a topic: its bytes, valid until the next call, and its log time (ns) */
	int (*read_message)(void *impl, uint32_t topic, uint32_t i, const uint8_t **data,
			    uint64_t *len, uint64_t *log_time, struct dao_error *err);
	/* the log time of message i, without reading it */
	uint64_t (*message_time)(const void *impl, uint32_t topic, uint32_t i);
	void (*close)(void *impl);
};

/*
 * Opens the source on an opened store (the source owns it from here, and
 * closes it on failure too), with the options of `u` (its path is the
 * store's).  `scheme` names the source in errors.
 */
int dao_ros2_source_open(const struct dao_ros2_store_ops *ops, void *impl,
			 const struct dao_ros_uri *u, const char *scheme,
			 const struct dao_source_options *opts, uint64_t max_pixels, void **state,
			 struct dao_error *err);

/* The mcap source on the file u->path (a rosbag2 directory of MCAP storage). */
int dao_mcap_source_open_path(const struct dao_ros_uri *u, const struct dao_source_options *opts,
			      uint64_t max_pixels, void **state, struct dao_error *err);

/* The source ops (but probe and open) every store's plugin shares. */
void dao_ros2_source_get_info(void *state, struct dao_source_info *in);
int dao_ros2_source_start(void *state, struct dao_error *err);
int dao_ros2_source_read(void *state, struct dao_source_frame *f, int timeout_ms,
			 struct dao_error *err);
int dao_ros2_source_seek(void *state, uint64_t index, struct dao_error *err);
void dao_ros2_source_close(void *state);
/* The camera pose of the frame last read (source_poses.h). */
int dao_ros2_source_frame_pose(void *state, const struct dao_source_frame *f,
			       struct dao_source_pose *pose, struct dao_error *err);

#endif
