/* SPDX-License-Identifier: MIT */
/*
 * depthao process --mcap-out FILE[?OPTIONS]: the AO, the shaded image, the
 * CameraInfo (and with ?cloud=true the point cloud) of every frame into one
 * MCAP file through the built-in "mcap" sink.  A recording: it never
 * replaces a file (FILE-1.mcap ... instead, said on stderr) unless
 * ?overwrite=true.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/depthao.h>
#include <depthao/plugin.h>

#include "process.h"

/* The sink's notes (the numbered name it records to) on stderr. */
static void host_log(void *user, int level, const char *message)
{
	(void)user;
	fprintf(stderr, "depthao: %s%s\n", level == DAO_LOG_WARN ? "warning: " : "", message);
}

/* The streams the sink asks for besides the AO (?filtered_depth=true: the filtered depth). */
static int host_want_streams(void *user, unsigned mask)
{
	struct run_state *st = user;
	st->mcap_streams = mask;
	return 0;
}

int process_mcap_open(const struct process_options *o, struct run_state *st,
		      const struct dao_camera *cam, double fps)
{
	struct dao_error err;
	if (!o->mcap_out)
		return 0;
	size_t n = strlen(o->mcap_out) + 6;
	char *uri = malloc(n);
	if (!uri) {
		fprintf(stderr, "depthao: out of memory\n");
		return 1;
	}
	snprintf(uri, n, "mcap:%s", o->mcap_out);
	struct dao_sink_host host = DAO_SINK_HOST_INIT;
	host.log = host_log;
	host.want_streams = host_want_streams;
	host.user = st;
	struct dao_sink_format fmt = DAO_SINK_FORMAT_INIT;
	fmt.format = DAO_PIXFMT_GRAY16;
	fmt.width = cam->width;
	fmt.height = cam->height;
	fmt.fps = fps;
	fmt.has_fov = 1;
	dao_camera_fov(cam, &fmt.hfov, &fmt.vfov);
	int r = dao_plugins_load(&st->mcap_plugins, "", &err);
	if (r == 0)
		r = dao_sink_open(st->mcap_plugins, uri, &st->mcap, &err);
	if (r == 0) {
		dao_sink_attach_host(st->mcap, &host);
		r = dao_sink_negotiate(st->mcap, &fmt, &err);
	}
	free(uri);
	if (r < 0) {
		fprintf(stderr, "depthao: --mcap-out %s: %s\n", o->mcap_out, err.message);
		return 1;
	}
	return 0;
}

static int put(struct run_state *st, enum dao_stream stream, const struct dao_frame *f,
	       struct dao_error *err)
{
	/* the pose after this frame's motion where it is this frame's (the track's
	 * origin, or its motion accepted), as depthaod's sinks have it */
	struct dao_pose_track pt = DAO_POSE_TRACK_INIT;
	dao_context_pose_track(st->ctx, &pt);
	struct dao_sink_frame_info info = {.size = sizeof(info), .stream = stream,
					   .has_pose = pt.current};
	dao_pose_matrix_to_quat(pt.rotation, info.pose_rotation);
	memcpy(info.pose_translation, pt.translation, sizeof info.pose_translation);
	return dao_sink_write_stream(st->mcap, &info, f, err);
}

/* The filtered depth in the input's unit (float-metre input: mm), as depthaod sends it. */
static int put_filtered_depth(struct run_state *st, const struct dao_frame *depth,
			      uint64_t index, struct dao_error *err)
{
	const struct dao_camera *cam = dao_context_camera(st->ctx);
	int r = 0;
	if (!st->depth16.data)
		r = dao_frame_alloc(&st->depth16, DAO_PIXFMT_DEPTH16, cam->width, cam->height, err);
	st->depth16.depth_unit = depth->format == DAO_PIXFMT_DEPTH16
					 ? depth->depth_unit : (float)PROCESS_FLOAT_DEPTH_OUT_UNIT;
	if (r == 0)
		r = dao_context_get_depth(st->ctx, &st->depth16, err);
	st->depth16.sequence = index;
	st->depth16.timestamp_ns = depth->timestamp_ns;
	return r ? r : put(st, DAO_STREAM_FILTERED_DEPTH, &st->depth16, err);
}

int process_mcap_write(struct run_state *st, const struct dao_frame *depth, int have_shaded,
		       uint64_t index)
{
	struct dao_error err;
	int r = 0;
	if (!st->mcap)
		return 0;
	if (!have_shaded)
		r = dao_context_shade(st->ctx, &st->rgb, &err);
	struct dao_frame d = *depth;
	d.sequence = st->ao.sequence = st->rgb.sequence = index;
	st->ao.timestamp_ns = st->rgb.timestamp_ns = depth->timestamp_ns;
	if (r == 0)
		r = put(st, DAO_STREAM_DEPTH, &d, &err);
	if (r == 0)
		r = put(st, DAO_STREAM_AO, &st->ao, &err);
	if (r == 0)
		r = put(st, DAO_STREAM_SHADED, &st->rgb, &err);
	if (r == 0 && (st->mcap_streams & (1u << DAO_STREAM_FILTERED_DEPTH)))
		r = put_filtered_depth(st, depth, index, &err);
	if (r < 0) {
		fprintf(stderr, "depthao: %s\n", err.message);
		return 1;
	}
	return 0;
}

int process_mcap_close(struct run_state *st, int status)
{
	struct dao_error err;
	if (st->mcap && dao_sink_close(st->mcap, &err) < 0) {
		fprintf(stderr, "depthao: %s\n", err.message);
		status = status ? status : 1;
	}
	st->mcap = NULL;
	dao_plugins_free(st->mcap_plugins);
	st->mcap_plugins = NULL;
	return status;
}
