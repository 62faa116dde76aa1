/* SPDX-License-Identifier: MIT */
#ifndef DAO_PLUGIN_SOURCE_POSES_H
#define DAO_PLUGIN_SOURCE_POSES_H

/*
 * The camera poses of a recording (the bag, mcap and db3 sources'
 * frame_pose): read at the first call from the recording's transforms
 * (tf2_msgs/TFMessage topics: those named .../tf_static static, the others
 * dynamic; foxglove.FrameTransform and FrameTransforms topics: named
 * .../tf_static static, else a transform stamped 0, or the only stamp of
 * its child frame, static, the others dynamic) or, with ?pose_topic=, from
 * a nav_msgs/Odometry topic, a Foxglove PoseInFrame(s) topic (the pose is
 * the camera's: the depth frame's in its frame_id), a sensor_msgs/Imu topic
 * (the IMU's rotation: its orientation, or its angular velocity integrated
 * from the first message on; no translation) or one transform topic, and the
 * static ones;
 * then the pose of each depth frame's frame_id in the fixed frame
 * (?pose_frame=, default the root of the depth frame's tree) at its stamp
 * (tf/tf_buffer.h; ?pose_gap= seconds, default 0.5, the longest
 * interpolation).  A load that fails (no transform topic, one in an
 * encoding not read, a frame not connected, too many transforms) fails
 * every later call the same way.
 */
#include <stdint.h>

#include <depthao/error.h>
#include <depthao/plugin.h>

#include "plugin/ros_image.h"
#include "tf/tf_msg.h"

/* At most this many frames and dynamic transforms are held (about 150 MB). */
#define DAO_POSES_MAX_FRAMES 4096
#define DAO_POSES_MAX_SAMPLES (1u << 21)

/* What a topic is for the poses. */
enum dao_pose_topic {
	DAO_POSE_TOPIC_NONE,
	DAO_POSE_TOPIC_TF,          /* ROS tf: dynamic transforms */
	DAO_POSE_TOPIC_TF_STATIC,   /* static transforms (a ROS or Foxglove .../tf_static) */
	DAO_POSE_TOPIC_ODOMETRY,    /* nav_msgs/Odometry */
	DAO_POSE_TOPIC_FOXGLOVE,    /* Foxglove transforms: stamped 0 or alone static */
	DAO_POSE_TOPIC_REFUSED,     /* transforms in an encoding not read */
	DAO_POSE_TOPIC_POSE,        /* Foxglove PoseInFrame(s): the camera's pose */
	DAO_POSE_TOPIC_POSE_REFUSED, /* ... in an encoding not read */
	DAO_POSE_TOPIC_IMU,         /* sensor_msgs/Imu: the rotation (pose_topic only) */
};

struct dao_pose_topic_info {
	const char *name;
	uint32_t count;             /* messages */
	enum dao_pose_topic kind;
	const char *type;           /* the schema: "tf2_msgs/msg/TFMessage" ... */
	const char *encoding;       /* the message encoding ("" where the format has one) */
	const char *schema_encoding; /* "" where the format has none */
	int static_name;            /* the name ends in "tf_static" */
};

/* What a recording gives the poses: its topics, messages and parsers. */
struct dao_pose_feed {
	void *impl;
	const char *path;
	uint32_t topic_count;
	/* topic i: its name, message count and what it is for poses */
	void (*topic)(void *impl, uint32_t i, struct dao_pose_topic_info *out);
	/* message i of a topic, valid until the next call */
	int (*read)(void *impl, uint32_t topic, uint32_t i, const uint8_t **data, uint64_t *len,
		    struct dao_error *err);
	/* a message of a transform topic: cb per transform; -EINVAL when it is not its type */
	int (*parse_tf)(void *impl, uint32_t topic, const uint8_t *msg, uint64_t len,
			dao_tf_msg_cb cb, void *user);
	/* a message of an odometry or pose topic: cb once (a pose's child is empty);
	 * -EINVAL when it is not its type, -ERANGE for a PosesInFrame not of one pose */
	int (*parse_pose)(void *impl, uint32_t topic, const uint8_t *msg, uint64_t len,
			  dao_tf_msg_cb cb, void *user);
	/* a message of an IMU topic: 0, or -EINVAL (-ENOTSUP: an encoding not read) when it
	 * is not its type */
	int (*parse_imu)(void *impl, uint32_t topic, const uint8_t *msg, uint64_t len,
			 struct dao_imu_msg *out);
};

struct dao_source_poses;

/* The options of u (pose_frame, pose_topic, pose_gap) kept; nothing read yet. */
int dao_source_poses_create(struct dao_source_poses **out, const struct dao_ros_uri *u,
			    struct dao_error *err);
void dao_source_poses_free(struct dao_source_poses *p);

/*
 * The pose of the frame named frame_id (len bytes; the depth image's
 * header.frame_id) at stamp_ns, as frame_pose returns it (plugin.h).
 */
int dao_source_poses_get(struct dao_source_poses *p, const struct dao_pose_feed *feed,
			 const char *frame_id, uint32_t len, uint64_t stamp_ns,
			 struct dao_source_pose *pose, struct dao_error *err);

#endif
