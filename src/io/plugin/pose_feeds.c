/* SPDX-License-Identifier: MIT */
/* A ROS 1 bag and a ROS 2 or Foxglove store as feeds of camera poses (pose_feeds.h). */
#include "plugin/pose_feeds.h"

#include <errno.h>
#include <string.h>

#include "bag/ros_msg.h"
#include "mcap/foxglove_msg.h"
#include "mcap/ros2_msg.h"

static int ends_static(const char *name)
{
	size_t n = strlen(name);
	return n >= 9 && !strcmp(name + n - 9, "tf_static");
}

static enum dao_pose_topic kind_of(const char *name, int tf, int odometry, int imu)
{
	if (tf)
		return ends_static(name) ? DAO_POSE_TOPIC_TF_STATIC : DAO_POSE_TOPIC_TF;
	return odometry ? DAO_POSE_TOPIC_ODOMETRY : imu ? DAO_POSE_TOPIC_IMU : DAO_POSE_TOPIC_NONE;
}

static void bag_topic(void *impl, uint32_t i, struct dao_pose_topic_info *out)
{
	const struct dao_bag_topic *t = dao_bag_topic(impl, i);
	*out = (struct dao_pose_topic_info){ .name = t->name, .count = t->message_count,
					     .type = t->type, .encoding = "",
					     .schema_encoding = "",
					     .static_name = ends_static(t->name) };
	out->kind = kind_of(t->name, !strcmp(t->type, "tf2_msgs/TFMessage") ||
				     !strcmp(t->type, "tf/tfMessage"),
			    !strcmp(t->type, "nav_msgs/Odometry"), !strcmp(t->type, "sensor_msgs/Imu"));
}

static int bag_read(void *impl, uint32_t topic, uint32_t i, const uint8_t **data, uint64_t *len,
		    struct dao_error *err)
{
	uint32_t n;
	int r = dao_bag_read_message(impl, topic, i, data, &n, NULL, err);
	*len = n;
	return r;
}

static int bag_tf(void *impl, uint32_t topic, const uint8_t *msg, uint64_t len, dao_tf_msg_cb cb,
		  void *user)
{
	(void)impl;
	(void)topic;
	return len > UINT32_MAX ? -EINVAL : dao_ros_tf_parse(msg, (uint32_t)len, cb, user);
}

/* An odometry message's pose to cb: 0, parse's error or cb's value. */
static int odometry(int (*parse)(const uint8_t *, uint64_t, struct dao_tf_msg_transform *),
		    const uint8_t *msg, uint64_t len, dao_tf_msg_cb cb, void *user)
{
	struct dao_tf_msg_transform t;
	int r = parse(msg, len, &t);
	return r < 0 ? r : (r = cb(user, &t)) < 0 ? r : 0;
}

static int ros_odometry(const uint8_t *msg, uint64_t len, struct dao_tf_msg_transform *out)
{
	return len > UINT32_MAX ? -EINVAL : dao_ros_odometry_parse(msg, (uint32_t)len, out);
}

static int bag_pose(void *impl, uint32_t topic, const uint8_t *msg, uint64_t len,
		    dao_tf_msg_cb cb, void *user)
{
	(void)impl;
	(void)topic;
	return odometry(ros_odometry, msg, len, cb, user);
}

static int bag_imu(void *impl, uint32_t topic, const uint8_t *msg, uint64_t len,
		   struct dao_imu_msg *out)
{
	(void)impl;
	(void)topic;
	return len > UINT32_MAX ? -EINVAL : dao_ros_imu_parse(msg, (uint32_t)len, out);
}

void dao_bag_pose_feed(struct dao_bag *bag, struct dao_pose_feed *feed)
{
	*feed = (struct dao_pose_feed){ bag, dao_bag_path(bag), dao_bag_topic_count(bag), bag_topic,
					bag_read, bag_tf, bag_pose, bag_imu };
}

/* Foxglove's schemas read for poses. */
enum fg_schema { FG_NONE, FG_TRANSFORM, FG_TRANSFORMS, FG_POSE, FG_POSES };

/* The schema as Foxglove's, *ros2 set for its ROS 2 name (foxglove_msgs/msg/...). */
static enum fg_schema fg_schema(const char *schema, int *ros2)
{
	static const char *const names[] = { "FrameTransform", "FrameTransforms", "PoseInFrame",
					     "PosesInFrame" };
	*ros2 = !strncmp(schema, "foxglove_msgs/msg/", 18);
	const char *n = *ros2 ? schema + 18 : !strncmp(schema, "foxglove.", 9) ? schema + 9 : "";
	for (int i = 0; i < 4; i++)
		if (!strcmp(n, names[i]))
			return (enum fg_schema)(FG_TRANSFORM + i);
	return FG_NONE;
}

/* A Foxglove topic's encoding as read (an enum dao_fg_encoding), -1 none of them. */
static int fg_encoding(const struct dao_ros2_topic *t, int ros2)
{
	const char *se = t->schema_encoding ? t->schema_encoding : "";
	if (ros2)
		return !strcmp(t->encoding, "cdr") && (!strcmp(se, "ros2msg") ||
						       !strcmp(se, "ros2idl") || !se[0])
			       ? DAO_FG_CDR
			       : -1;
	if (!strcmp(t->encoding, "protobuf") && !strcmp(se, "protobuf"))
		return DAO_FG_PROTOBUF;
	return !strcmp(t->encoding, "json") && !strcmp(se, "jsonschema") ? DAO_FG_JSON : -1;
}

static enum dao_pose_topic fg_kind(enum fg_schema fg, int enc, int static_name)
{
	if (fg >= FG_POSE)
		return enc < 0 ? DAO_POSE_TOPIC_POSE_REFUSED : DAO_POSE_TOPIC_POSE;
	return enc < 0 ? DAO_POSE_TOPIC_REFUSED
	       : static_name ? DAO_POSE_TOPIC_TF_STATIC : DAO_POSE_TOPIC_FOXGLOVE;
}

static void ros2_topic(void *impl, uint32_t i, struct dao_pose_topic_info *out)
{
	const struct dao_ros2_store_ref *ref = impl;
	struct dao_ros2_topic t;
	ref->ops->topic(ref->store, i, &t);
	int cdr = !strcmp(t.encoding, "cdr"), ros2;
	*out = (struct dao_pose_topic_info){ .name = t.name, .count = t.message_count,
					     .type = t.schema, .encoding = t.encoding,
					     .schema_encoding = t.schema_encoding ? t.schema_encoding : "",
					     .static_name = ends_static(t.name) };
	out->kind = kind_of(t.name, cdr && !strcmp(t.schema, "tf2_msgs/msg/TFMessage"),
			    cdr && !strcmp(t.schema, "nav_msgs/msg/Odometry"),
			    cdr && !strcmp(t.schema, "sensor_msgs/msg/Imu"));
	enum fg_schema fg = fg_schema(t.schema, &ros2);
	if (fg != FG_NONE)
		out->kind = fg_kind(fg, fg_encoding(&t, ros2), out->static_name);
}

static int ros2_read(void *impl, uint32_t topic, uint32_t i, const uint8_t **data, uint64_t *len,
		     struct dao_error *err)
{
	const struct dao_ros2_store_ref *ref = impl;
	return ref->ops->read_message(ref->store, topic, i, data, len, NULL, err);
}

/* A message of a Foxglove topic (transforms or poses) or of a ROS 2 one (tf or odometry). */
static int ros2_parse(void *impl, uint32_t topic, const uint8_t *msg, uint64_t len,
		      dao_tf_msg_cb cb, void *user)
{
	const struct dao_ros2_store_ref *ref = impl;
	struct dao_ros2_topic t;
	ref->ops->topic(ref->store, topic, &t);
	int ros2, enc;
	enum fg_schema fg = fg_schema(t.schema, &ros2);
	if (fg == FG_NONE)
		return strcmp(t.schema, "nav_msgs/msg/Odometry")
			       ? dao_ros2_tf_parse(msg, len, cb, user)
			       : odometry(dao_ros2_odometry_parse, msg, len, cb, user);
	if ((enc = fg_encoding(&t, ros2)) < 0 || len > SIZE_MAX)
		return -EINVAL;
	const enum dao_fg_encoding e = (enum dao_fg_encoding)enc;
	return fg >= FG_POSE ? dao_fg_poses_parse(e, fg == FG_POSES, msg, (size_t)len, cb, user)
			     : dao_fg_frame_transforms_parse(e, fg == FG_TRANSFORMS, msg, (size_t)len,
							     cb, user);
}

static int ros2_imu(void *impl, uint32_t topic, const uint8_t *msg, uint64_t len,
		    struct dao_imu_msg *out)
{
	(void)impl;
	(void)topic;
	return dao_ros2_imu_parse(msg, len, out);
}

void dao_ros2_pose_feed(struct dao_ros2_store_ref *ref, struct dao_pose_feed *feed)
{
	*feed = (struct dao_pose_feed){ ref, ref->ops->path(ref->store),
					ref->ops->topic_count(ref->store), ros2_topic, ros2_read,
					ros2_parse, ros2_parse, ros2_imu };
}
