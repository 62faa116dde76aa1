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

static enum dao_pose_topic kind_of(const char *name, int tf, int odometry)
{
	if (tf)
		return ends_static(name) ? DAO_POSE_TOPIC_TF_STATIC : DAO_POSE_TOPIC_TF;
	return odometry ? DAO_POSE_TOPIC_ODOMETRY : DAO_POSE_TOPIC_NONE;
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
			    !strcmp(t->type, "nav_msgs/Odometry"));
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

static int bag_odometry(const uint8_t *msg, uint64_t len, struct dao_tf_msg_transform *out)
{
	return len > UINT32_MAX ? -EINVAL : dao_ros_odometry_parse(msg, (uint32_t)len, out);
}

void dao_bag_pose_feed(struct dao_bag *bag, struct dao_pose_feed *feed)
{
	*feed = (struct dao_pose_feed){ bag, dao_bag_path(bag), dao_bag_topic_count(bag), bag_topic,
					bag_read, bag_tf, bag_odometry };
}

/* Foxglove's transforms: 1 FrameTransform, 2 FrameTransforms, else 0. */
static int foxglove_tf(const char *schema)
{
	return !strcmp(schema, "foxglove.FrameTransform")    ? 1
	       : !strcmp(schema, "foxglove.FrameTransforms") ? 2
							      : 0;
}

/* The encodings of Foxglove's transforms read: 0 protobuf, 1 JSON, -1 neither. */
static int foxglove_encoding(const struct dao_ros2_topic *t)
{
	const char *se = t->schema_encoding ? t->schema_encoding : "";
	if (!strcmp(t->encoding, "protobuf") && !strcmp(se, "protobuf"))
		return 0;
	return !strcmp(t->encoding, "json") && !strcmp(se, "jsonschema") ? 1 : -1;
}

static void ros2_topic(void *impl, uint32_t i, struct dao_pose_topic_info *out)
{
	const struct dao_ros2_store_ref *ref = impl;
	struct dao_ros2_topic t;
	ref->ops->topic(ref->store, i, &t);
	int cdr = !strcmp(t.encoding, "cdr");
	*out = (struct dao_pose_topic_info){ .name = t.name, .count = t.message_count,
					     .type = t.schema, .encoding = t.encoding,
					     .schema_encoding = t.schema_encoding ? t.schema_encoding : "",
					     .static_name = ends_static(t.name) };
	out->kind = kind_of(t.name, cdr && !strcmp(t.schema, "tf2_msgs/msg/TFMessage"),
			    cdr && !strcmp(t.schema, "nav_msgs/msg/Odometry"));
	if (foxglove_tf(t.schema))
		out->kind = foxglove_encoding(&t) < 0 ? DAO_POSE_TOPIC_REFUSED
			    : out->static_name        ? DAO_POSE_TOPIC_TF_STATIC
						      : DAO_POSE_TOPIC_FOXGLOVE;
}

static int ros2_read(void *impl, uint32_t topic, uint32_t i, const uint8_t **data, uint64_t *len,
		     struct dao_error *err)
{
	const struct dao_ros2_store_ref *ref = impl;
	return ref->ops->read_message(ref->store, topic, i, data, len, NULL, err);
}

static int ros2_tf(void *impl, uint32_t topic, const uint8_t *msg, uint64_t len, dao_tf_msg_cb cb,
		   void *user)
{
	const struct dao_ros2_store_ref *ref = impl;
	struct dao_ros2_topic t;
	ref->ops->topic(ref->store, topic, &t);
	int fg = foxglove_tf(t.schema), enc = foxglove_encoding(&t);
	if (!fg)
		return dao_ros2_tf_parse(msg, len, cb, user);
	if (enc < 0 || len > SIZE_MAX)
		return -EINVAL;
	return dao_fg_frame_transforms_parse(enc ? DAO_FG_JSON : DAO_FG_PROTOBUF, fg == 2, msg,
					     (size_t)len, cb, user);
}

void dao_ros2_pose_feed(struct dao_ros2_store_ref *ref, struct dao_pose_feed *feed)
{
	*feed = (struct dao_pose_feed){ ref, ref->ops->path(ref->store),
					ref->ops->topic_count(ref->store), ros2_topic, ros2_read,
					ros2_tf, dao_ros2_odometry_parse };
}
