/* SPDX-License-Identifier: MIT */
/*
 * Built-in source "mcap": depth images from an MCAP file (ROS 2's default
 * bag format) through depthao's own reader (mcap/mcap_reader.c).  URI:
 * FILE.mcap[?topic=T][&unit=M][&color=C] (the options in any order).
 *
 * The messages (ROS 2 CDR, Foxglove protobuf and JSON), the topic choice,
 * the unit, the intrinsics and the colour pairing are ros2_source.c's; this
 * file makes the reader a store of it.  A file cut short is read as far as
 * it goes, with the reader's warning.
 */
#include <depthao/plugin.h>

#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "mcap/mcap_reader.h"
#include "plugin/builtin.h"
#include "plugin/ros2_source.h"
#include "plugin/ros_image.h"

static int mcap_probe(const char *uri)
{
	size_t n = dao_uri_path_len(uri, dao_ros_uri_options);
	return n > 5 && !strncasecmp(uri + n - 5, ".mcap", 5) ? 60 : 0;
}

/* The reader as a store of the ROS 2 source. */
static const char *store_path(const void *m)
{
	return dao_mcap_path(m);
}

static const char *store_warning(const void *m)
{
	return dao_mcap_warning(m);
}

static uint32_t store_topic_count(const void *m)
{
	return dao_mcap_topic_count(m);
}

static void store_topic(const void *m, uint32_t i, struct dao_ros2_topic *t)
{
	const struct dao_mcap_topic *mt = dao_mcap_topic(m, i);
	t->name = mt->name;
	t->schema = mt->schema;
	t->encoding = mt->encoding;
	t->schema_encoding = mt->schema_encoding;
	t->message_count = mt->message_count;
}

static int store_read(void *m, uint32_t topic, uint32_t i, const uint8_t **data, uint64_t *len,
		      uint64_t *log_time, struct dao_error *err)
{
	return dao_mcap_read_message(m, topic, i, data, len, log_time, err);
}

static uint64_t store_time(const void *m, uint32_t topic, uint32_t i)
{
	return dao_mcap_message_time(m, topic, i);
}

static void store_close(void *m)
{
	dao_mcap_close(m);
}

static const struct dao_ros2_store_ops mcap_store = {
	.path = store_path,
	.warning = store_warning,
	.topic_count = store_topic_count,
	.topic = store_topic,
	.read_message = store_read,
	.message_time = store_time,
	.close = store_close,
};

int dao_mcap_source_open_path(const struct dao_ros_uri *u, const struct dao_source_options *opts,
			      uint64_t max_pixels, void **state, struct dao_error *err)
{
	struct dao_mcap *m;
	/* a chunk holds at least one image (up to 4 bytes a pixel), maybe colour beside it */
	int r = dao_mcap_open(u->path, 8 * max_pixels + (64u << 20), &m, err);
	if (r < 0)
		return r;
	return dao_ros2_source_open(&mcap_store, m, u, "mcap", opts, max_pixels, state, err);
}

int dao_mcap_source_open(const char *uri, const struct dao_source_options *opts,
			 uint64_t max_pixels, void **state, struct dao_error *err)
{
	struct dao_ros_uri u;
	int r = dao_ros_uri_parse(uri, "mcap", &u, err);
	if (r == 0)
		r = dao_mcap_source_open_path(&u, opts, max_pixels, state, err);
	dao_ros_uri_free(&u);
	return r;
}

static int mcap_open(const char *uri, const struct dao_source_options *opts, void **state,
		     struct dao_error *err)
{
	return dao_mcap_source_open(uri, opts, DAO_DEFAULT_MAX_PIXELS, state, err);
}

static const struct dao_source_ops mcap_source_ops = {
	.version = DAO_SOURCE_OPS_VERSION,
	.probe = mcap_probe,
	.open = mcap_open,
	.get_info = dao_ros2_source_get_info,
	.start = dao_ros2_source_start,
	.read = dao_ros2_source_read,
	.seek = dao_ros2_source_seek,
	.close = dao_ros2_source_close,
	.frame_pose = dao_ros2_source_frame_pose,
};

const struct dao_plugin dao_builtin_mcap_plugin = {
	DAO_PLUGIN_HEADER,
	.name = "mcap",
	.description = "MCAP files (ROS 2 bags; chunks none/zstd/lz4): CDR depth Image 16UC1, "
		       "mono16, 32FC1 and compressedDepth (PNG, RVL), colour rgb8, bgr8, rgba8, "
		       "bgra8, mono8, JPEG; Foxglove RawImage, CompressedImage (16-bit PNG, JPEG), "
		       "CameraCalibration in protobuf or JSON; camera poses from tf, odometry, an IMU or "
		       "Foxglove FrameTransform(s) in protobuf or JSON; "
		       "FILE.mcap[?topic=T][&unit=M][&color=C][&pose_frame=F][&pose_topic=O]; "
		       "records the AO (Image mono16, rgb8, CameraInfo, PointCloud2) as a sink",
	.source = &mcap_source_ops,
	.sink = &dao_mcap_sink_ops,
};
