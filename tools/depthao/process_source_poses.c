/* SPDX-License-Identifier: MIT */
/*
 * depthao process on a recording with depth-temporal-motion source or
 * source+icp: the camera pose of each frame from the source (a ROS
 * recording's tf, odometry or IMU, a Foxglove MCAP's FrameTransform(s),
 * dao_source_frame_pose) given to the context.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "process.h"

int process_wants_source_poses(const struct process_options *o)
{
	return !o->poses && (o->params.depth_temporal_motion == DAO_DEPTH_MOTION_SOURCE ||
			     o->params.depth_temporal_motion == DAO_DEPTH_MOTION_SOURCE_ICP);
}

/* The options of the ROS sources' URIs: where the input's own begin, if it has any. */
static const char *const ros_options[] = { "topic", "unit", "color", "pose_frame", "pose_topic",
					   "pose_gap", NULL };

char *process_source_uri(const struct process_options *o)
{
	const char *keys[] = { "pose_frame", "pose_topic", "pose_gap" };
	const char *vals[] = { o->pose_frame, o->pose_topic, o->pose_gap };
	size_t n = strlen(o->input) + 1;
	for (int k = 0; k < 3; k++)
		n += vals[k] ? strlen(keys[k]) + strlen(vals[k]) + 2 : 0;
	char *uri = malloc(n);
	if (!uri)
		return NULL;
	strcpy(uri, o->input);
	int has_query = dao_uri_path_len(o->input, ros_options) < strlen(o->input);
	for (int k = 0; k < 3; k++) {
		if (!vals[k])
			continue;
		strcat(uri, has_query ? "&" : "?");
		strcat(uri, keys[k]);
		strcat(uri, "=");
		strcat(uri, vals[k]);
		has_query = 1;
	}
	return uri;
}

int process_source_pose(const struct process_options *o, struct run_state *st,
			struct dao_source *src, const struct dao_source_frame *f)
{
	struct dao_source_pose pose = DAO_SOURCE_POSE_INIT;
	struct dao_error err;
	int r = dao_source_frame_pose(src, f, &pose, &err);
	if (r < 0 && r != -ENOENT) {
		fprintf(stderr, "depthao: depth-temporal-motion %s needs the camera's poses from "
			"the source: %s\n", o->params.depth_temporal_motion ==
			DAO_DEPTH_MOTION_SOURCE ? "source" : "source+icp", err.message);
		if (r == -ENOTSUP)
			fprintf(stderr, "depthao: ROS recordings (.bag, .mcap, .db3) carry them in "
				"their tf, odometry or IMU (--pose-topic), Foxglove's in "
				"FrameTransform(s) or PoseInFrame(s); for others give "
				"--depth-temporal-motion icp\n");
		return 1;
	}
	if (r == 0 && st->source_posed++ == 0 && !o->quiet)
		fprintf(stderr, "depthao: camera poses: %s\n", pose.description);
	if (r == 0 && pose.warning[0])
		fprintf(stderr, "depthao: warning: %s\n", pose.warning);
	if (r == -ENOENT && st->source_unposed++ == 0)
		snprintf(st->first_gap, sizeof st->first_gap, "%s", err.message);
	if (dao_context_set_pose(st->ctx, r == 0 ? pose.rotation : NULL, pose.translation,
				 &err)) {
		fprintf(stderr, "depthao: frame %llu: %s\n", (unsigned long long)f->index,
			err.message);
		return 1;
	}
	return 0;
}

void process_source_poses_report(const struct process_options *o, const struct run_state *st)
{
	if (!process_wants_source_poses(o) || !st->source_unposed)
		return;
	fprintf(stderr, "depthao: warning: no camera pose for %zu of %zu frames (filtered "
		"without motion, as after a gap); the first: %s\n", st->source_unposed,
		st->source_unposed + st->source_posed, st->first_gap);
}
