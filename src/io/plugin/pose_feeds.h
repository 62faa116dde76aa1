/* SPDX-License-Identifier: MIT */
#ifndef DAO_PLUGIN_POSE_FEEDS_H
#define DAO_PLUGIN_POSE_FEEDS_H

/*
 * The recordings as feeds of source_poses.h: a ROS 1 bag (tf2_msgs/
 * TFMessage or tf/tfMessage, nav_msgs/Odometry, sensor_msgs/Imu, ROS 1
 * serialization) and a store of the mcap and db3 sources
 * (tf2_msgs/msg/TFMessage, nav_msgs/msg/Odometry, sensor_msgs/msg/Imu in CDR;
 * foxglove.FrameTransform(s) and foxglove.PoseInFrame / PosesInFrame in
 * protobuf, schema encoding "protobuf", or in json, schema encoding
 * "jsonschema", and the same as foxglove_msgs/msg/... in cdr, schema
 * encoding "ros2msg", "ros2idl" or none
 * (a .db3): other encodings of these are DAO_POSE_TOPIC_REFUSED or
 * DAO_POSE_TOPIC_POSE_REFUSED).  A transform topic whose name ends in
 * "tf_static" is static.
 */
#include "bag/bag_reader.h"
#include "plugin/ros2_source.h"
#include "plugin/source_poses.h"

void dao_bag_pose_feed(struct dao_bag *bag, struct dao_pose_feed *feed);

/* A ROS 2 store as the feed's impl (it lives as long as the feed is used). */
struct dao_ros2_store_ref {
	const struct dao_ros2_store_ops *ops;
	void *store;
};

void dao_ros2_pose_feed(struct dao_ros2_store_ref *ref, struct dao_pose_feed *feed);

#endif
