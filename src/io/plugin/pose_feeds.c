/* SPDX-License-Identifier: MIT */
/* A ROS 1 bag and a ROS 2 store as feeds of camera poses (pose_feeds.h). */
#include "plugin/pose_feeds.h"

#include <errno.h>
#include <string.h>

#include "bag/ros_msg.h"
#include "mcap/ros2_msg.h"

static enum dao_pose_topic kind_of(const char *name, int tf, int odometry)
{
	size_t n = strlen(name);
	if (tf)
		return n >= 9 && !strcmp(name + n - 9, "tf_static") ? DAO_POSE_TOPIC_TF_STATIC
								    : DAO_POSE_TOPIC_TF;
	return odometry ? DAO_POSE_TOPIC_ODOMETRY : DAO_POSE_TOPIC_NONE;
}

static void bag_topic(void *impl, uint32_t i, const char **name, uint32_t *count,
		      enum dao_pose_topic *kind)
{
	const struct dao_bag_topic *t = dao_bag_topic(impl, i);
	*name = t->name;
	*count = t->message_count;
	*kind = kind_of(t->name, !strcmp(t->type, "tf2_msgs/TFMessage") ||
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

static int bag_tf(const uint8_t *msg, uint64_t len, dao_tf_msg_cb cb, void *user)
{
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

static void ros2_topic(void *impl, uint32_t i, const char **name, uint32_t *count,
		       enum dao_pose_topic *kind)
{
	const struct dao_ros2_store_ref *ref = impl;
	struct dao_ros2_topic t;
	ref->ops->topic(ref->store, i, &t);
	int cdr = !strcmp(t.encoding, "cdr");
	*name = t.name;
	*count = t.message_count;
	*kind = kind_of(t.name, cdr && !strcmp(t.schema, "tf2_msgs/msg/TFMessage"),
			cdr && !strcmp(t.schema, "nav_msgs/msg/Odometry"));
}

static int ros2_read(void *impl, uint32_t topic, uint32_t i, const uint8_t **data, uint64_t *len,
		     struct dao_error *err)
{
	const struct dao_ros2_store_ref *ref = impl;
	return ref->ops->read_message(ref->store, topic, i, data, len, NULL, err);
}

void dao_ros2_pose_feed(struct dao_ros2_store_ref *ref, struct dao_pose_feed *feed)
{
	*feed = (struct dao_pose_feed){ ref, ref->ops->path(ref->store),
					ref->ops->topic_count(ref->store), ros2_topic, ros2_read,
					dao_ros2_tf_parse, dao_ros2_odometry_parse };
}
