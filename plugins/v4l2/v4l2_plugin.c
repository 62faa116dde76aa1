/* SPDX-License-Identifier: MIT */
/*
 * Plugin "v4l2": depth cameras through V4L2 (source) and v4l2loopback
 * virtual cameras (sink), over libv4l2.  The logic is in v4l2_capture.c and
 * v4l2_output.c, which take the system-call table; this file binds them to
 * the real one.
 */
#include <errno.h>
#include <string.h>

#include <depthao/plugin.h>

#include "v4l2_capture.h"
#include "v4l2_output.h"

static int src_probe(const char *uri)
{
	return !strncmp(uri, "/dev/video", 10) ? 50 : 0;
}

static int src_list(dao_device_cb cb, void *user, struct dao_error *err)
{
	return v4l2cap_list(v4l2_io_system(), cb, user, err);
}

static int src_open(const char *uri, const struct dao_source_options *o, void **state,
		    struct dao_error *err)
{
	return v4l2cap_open(v4l2_io_system(), uri, o, (struct v4l2cap **)state, err);
}

static void src_info(void *state, struct dao_source_info *in)
{
	v4l2cap_info(state, in);
}

static int src_start(void *state, struct dao_error *err)
{
	return v4l2cap_start(state, err);
}

static int src_read(void *state, struct dao_source_frame *f, int timeout_ms, struct dao_error *err)
{
	return v4l2cap_read(state, f, timeout_ms, err);
}

static void src_stop(void *state)
{
	v4l2cap_stop(state);
}

static void src_close(void *state)
{
	v4l2cap_close(state);
}

static int sink_probe(const char *uri)
{
	(void)uri;
	return 0; /* a /dev/video node is a camera unless the URI says v4l2: */
}

static int sink_open(const char *uri, void **state, struct dao_error *err)
{
	return v4l2out_open(v4l2_io_system(), uri, (struct v4l2out **)state, err);
}

static int sink_negotiate(void *state, struct dao_sink_format *fmt, struct dao_error *err)
{
	return v4l2out_negotiate(state, fmt, err);
}

static int sink_write(void *state, const struct dao_frame *f, struct dao_error *err)
{
	return v4l2out_write(state, f, err);
}

static int sink_close(void *state, struct dao_error *err)
{
	(void)err;
	v4l2out_close(state);
	return 0;
}

static const struct dao_source_ops v4l2_source_ops = {
	.version = DAO_SOURCE_OPS_VERSION,
	.probe = src_probe,
	.list_devices = src_list,
	.open = src_open,
	.get_info = src_info,
	.start = src_start,
	.read = src_read,
	.stop = src_stop,
	.close = src_close,
};

static const struct dao_sink_ops v4l2_sink_ops = {
	.version = DAO_SINK_OPS_VERSION,
	.probe = sink_probe,
	.open = sink_open,
	.negotiate = sink_negotiate,
	.write = sink_write,
	.close = sink_close,
};

static const struct dao_plugin v4l2_plugin = {
	DAO_PLUGIN_HEADER,
	.name = "v4l2",
	.description = "V4L2 depth cameras (Z16, Y16, Kinect Y10B) and v4l2loopback output (YUYV, "
		       "RGB24, GREY; Y16 for the depth streams)",
	.source = &v4l2_source_ops,
	.sink = &v4l2_sink_ops,
};

DAO_PLUGIN_DEFINE(v4l2_plugin)
