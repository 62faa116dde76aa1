/* SPDX-License-Identifier: MIT */
/*
 * Built-in sink "mcap": records the AO as ROS 2 messages in an MCAP file
 * (mcap/mcap_writer.h: chunked, zstd by default, indexes and a summary).
 * URI: "PATH.mcap" with options after a '?':
 *   compression=zstd|lz4|none  (default zstd)
 *   level=1..19                zstd's level (default 1)
 *   chunk=BYTES                uncompressed bytes a chunk holds (default 4 MiB,
 *                              4096 .. 1 GiB); what kill -9 can lose at most
 *   cloud=true                 also the AO point cloud (PointCloud2 x y z ao)
 *   filtered_depth=true        also the filtered depth (the host's filtered-depth stream)
 *   frame_id=NAME              the messages' header.frame_id (default
 *                              camera_depth_optical_frame)
 *   pose_frame=NAME            the fixed frame of the camera's poses on /tf (default
 *                              depthao_odom)
 *   overwrite=true             replace PATH (else PATH-1.mcap, PATH-2.mcap ...)
 *
 * Topics (the sensor_msgs/msg types, CDR):
 *   /depthao/ao           Image mono16: visibility x 65535
 *   /depthao/shaded       Image rgb8: the occlusion-shaded image
 *   /depthao/camera_info  CameraInfo: the pinhole of the field of view (one per AO frame,
 *                         just before it)
 *   /depthao/points       PointCloud2 (cloud=true): the pixels with depth, x y z in
 *                         metres (x right, y down, z forward) and ao 0..1
 *   /depthao/depth_filtered  Image (filtered_depth=true): the filtered depth, 16UC1
 *                         millimetres (REP 118) when its unit is 1 mm, else 32FC1 metres
 *   /tf                   tf2_msgs/TFMessage: the camera's pose (frame_id in pose_frame)
 *                         with each AO frame where the host tracks it (the frame info's
 *                         has_pose: depth-temporal-motion not off), just before it
 * The sink takes the stream it is configured for (ao, shaded or depth) and
 * asks its host for the others it records (want_streams); without a host
 * (depthao process) the program hands every stream to write_stream.  The
 * timestamps are the frames' (sequence / fps when a frame has none).
 *
 * The file rules are the .oni recorder's: nothing is created before the
 * format is known, a recording never replaces a file (PATH-N.mcap instead,
 * said in the host's log), a recording without messages leaves no file.
 * What survives kill -9, SIGTERM and a full disk: mcap_writer.h.
 */
#include <depthao/camera.h>
#include <depthao/plugin.h>

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error_internal.h"
#include "core/math_util.h"
#include "file/output_file_internal.h"
#include "mcap/mcap_writer.h"
#include "mcap/ros2_encode.h"
#include "plugin/builtin.h"
#include "plugin/recorder_sink.h"

#define MCAP_SINK_DEFAULT_FPS 30
#define MCAP_SINK_DEFAULT_HFOV_DEG 58.5
#define MCAP_SINK_DEFAULT_VFOV_DEG 45.6
#define MCAP_SINK_HELP                                                                  \
	"?compression=zstd|lz4|none&level=1..19&chunk=BYTES&cloud=true&filtered_depth=true" \
	"&frame_id=NAME&pose_frame=NAME&overwrite=true"

enum { CH_AO, CH_SHADED, CH_INFO, CH_CLOUD, CH_FDEPTH, CH_TF, CH_COUNT };

struct mcap_sink {
	struct dao_recorder rec; /* the path, the file written, the host */
	struct dao_mcap_writer_options wo;
	int cloud;
	int fdepth;           /* filtered_depth=true */
	struct dao_frame fdepth_m; /* its 32FC1 metres when the unit is not 1 mm */
	char frame_id[64];
	char pose_frame[64];
	struct dao_mcap_writer *w;
	uint16_t ch[CH_COUNT];
	struct dao_ros2_pinhole cam;
	double fps;
	enum dao_stream configured;
	/* the cloud: the last depth and AO frames, paired by sequence */
	uint16_t *depth, *ao;
	float depth_unit;
	uint64_t depth_seq, ao_seq, depth_ts;
	int have_depth, have_ao;
};

static const char *const mcap_sink_options[] = {"compression", "level", "chunk", "cloud",
						"frame_id", "overwrite", "filtered_depth", "pose_frame",
						NULL};

static int mcap_sink_probe(const char *uri)
{
	size_t n = dao_uri_path_len(uri, mcap_sink_options);
	return n > 5 && !strncasecmp(uri + n - 5, ".mcap", 5) ? 50 : 0;
}

static int parse_options(struct mcap_sink *s, const char *text, struct dao_error *err)
{
	static const char *const comps[] = {"zstd", "lz4", "none", NULL};
	struct dao_options *o;
	int r = dao_options_parse(&o, "mcap", text, mcap_sink_options, err);
	if (r < 0)
		return r;
	int comp = 0;
	int64_t level = 1, chunk = DAO_MCAP_DEFAULT_CHUNK_SIZE;
	if ((r = dao_options_get_enum(o, "compression", comps, &comp, err)) >= 0 &&
	    (r = dao_options_get_int(o, "level", 1, 19, &level, err)) >= 0 &&
	    (r = dao_options_get_int(o, "chunk", 4096, (int64_t)DAO_MCAP_MAX_MESSAGE, &chunk,
				     err)) >= 0 &&
	    (r = dao_options_get_bool(o, "cloud", &s->cloud, err)) >= 0 &&
	    (r = dao_options_get_bool(o, "filtered_depth", &s->fdepth, err)) >= 0 &&
	    (r = dao_options_get_bool(o, "overwrite", &s->wo.overwrite, err)) >= 0)
		r = dao_options_get_string(o, "frame_id", s->frame_id, sizeof s->frame_id, err);
	if (r >= 0)
		r = dao_options_get_string(o, "pose_frame", s->pose_frame, sizeof s->pose_frame, err);
	if (r >= 0 && (!s->frame_id[0] || !s->pose_frame[0] || !strcmp(s->frame_id, s->pose_frame)))
		r = dao_error_set(err, -EINVAL,
				  "mcap: frame_id '%s' and pose_frame '%s' must be two names (the "
				  "camera's frame and the fixed frame its poses are in)",
				  s->frame_id, s->pose_frame);
	s->wo.compression = (enum dao_mcap_compression)comp;
	s->wo.zstd_level = (int)level;
	s->wo.chunk_size = (uint64_t)chunk;
	dao_options_free(o);
	return r < 0 ? r : 0;
}

static int mcap_sink_open(const char *uri, void **state, struct dao_error *err)
{
	size_t n = dao_uri_path_len(uri, mcap_sink_options);
	struct mcap_sink *s = calloc(1, sizeof(*s));
	if (!s)
		return dao_error_set(err, -ENOMEM, "out of memory");
	snprintf(s->frame_id, sizeof s->frame_id, "camera_depth_optical_frame");
	snprintf(s->pose_frame, sizeof s->pose_frame, "depthao_odom");
	s->wo.profile = "ros2";
	int r = dao_recorder_init(&s->rec, "mcap", uri, n, MCAP_SINK_HELP, err);
	if (r == 0 && !strcmp(s->rec.path, "-"))
		r = dao_error_set(err, -EINVAL,
				  "mcap: a recording cannot go to standard output ('-'): its summary "
				  "and indexes are written at the end; give a file name (./- for one "
				  "named '-')");
	if (r == 0 && uri[n] == '?')
		r = parse_options(s, uri + n + 1, err);
	if (r == 0)
		r = dao_recorder_check_dir(&s->rec, 0, err);
	if (r < 0) {
		dao_recorder_free(&s->rec);
		free(s);
		return r;
	}
	*state = s;
	return 0;
}

static void mcap_sink_attach_host(void *state, const struct dao_sink_host *host)
{
	struct mcap_sink *s = state;
	s->rec.host = *host;
}

static int open_at(void *ctx, const char *name, int overwrite, struct dao_error *err)
{
	struct mcap_sink *s = ctx;
	struct dao_mcap_writer_options o = s->wo;
	o.overwrite = overwrite;
	return dao_mcap_writer_open(name, &o, &s->w, err);
}

/* Opens the writer at the path, or at the first free numbered name beside it. */
static int open_writer(struct mcap_sink *s, struct dao_error *err)
{
	struct stat st;
	/* the one rule for replacing a file (output_file.c) */
	if (s->wo.overwrite && stat(s->rec.path, &st) == 0 && S_ISREG(st.st_mode)) {
		int r = dao_output_file_check_replaceable(s->rec.path, &st, err);
		if (r < 0)
			return r;
	}
	return dao_recorder_open_numbered(&s->rec, s->wo.overwrite, open_at, s, err);
}

/* The schemas and channels, all before the first message. */
static int add_channels(struct mcap_sink *s, struct dao_error *err)
{
	uint16_t img, info, pc, tf;
	struct dao_mcap_writer *w = s->w;
	int r;
	if ((r = dao_mcap_writer_add_schema(w, "sensor_msgs/msg/Image", "ros2msg",
					    dao_ros2_image_schema, &img, err)) < 0 ||
	    (r = dao_mcap_writer_add_schema(w, "sensor_msgs/msg/CameraInfo", "ros2msg",
					    dao_ros2_camera_info_schema, &info, err)) < 0 ||
	    (r = dao_mcap_writer_add_channel(w, img, "/depthao/ao", "cdr", &s->ch[CH_AO], err)) < 0 ||
	    (r = dao_mcap_writer_add_channel(w, img, "/depthao/shaded", "cdr", &s->ch[CH_SHADED],
					     err)) < 0 ||
	    (r = dao_mcap_writer_add_channel(w, info, "/depthao/camera_info", "cdr",
					     &s->ch[CH_INFO], err)) < 0 ||
	    (r = dao_mcap_writer_add_schema(w, "tf2_msgs/msg/TFMessage", "ros2msg",
					    dao_ros2_tf_schema, &tf, err)) < 0 ||
	    (r = dao_mcap_writer_add_channel(w, tf, "/tf", "cdr", &s->ch[CH_TF], err)) < 0)
		return r;
	if (s->fdepth && (r = dao_mcap_writer_add_channel(w, img, "/depthao/depth_filtered", "cdr",
							  &s->ch[CH_FDEPTH], err)) < 0)
		return r;
	if (!s->cloud)
		return 0;
	if ((r = dao_mcap_writer_add_schema(w, "sensor_msgs/msg/PointCloud2", "ros2msg",
					    dao_ros2_point_cloud2_schema, &pc, err)) < 0)
		return r;
	return dao_mcap_writer_add_channel(w, pc, "/depthao/points", "cdr", &s->ch[CH_CLOUD], err);
}

static void drop_writer(struct mcap_sink *s)
{
	dao_mcap_writer_abort(s->w); /* no messages yet: the file goes */
	s->w = NULL;
	dao_recorder_forget_file(&s->rec);
	free(s->depth);
	free(s->ao);
	s->depth = s->ao = NULL;
	dao_frame_free(&s->fdepth_m);
	s->have_depth = s->have_ao = 0;
}

static int mcap_sink_negotiate(void *state, struct dao_sink_format *fmt, struct dao_error *err)
{
	struct mcap_sink *s = state;
	if (s->w) /* negotiated again before the first frame: start over */
		drop_writer(s);
	if (fmt->format == DAO_PIXFMT_GRAY16)
		s->configured = DAO_STREAM_AO;
	else if (fmt->format == DAO_PIXFMT_RGB24)
		s->configured = DAO_STREAM_SHADED;
	else if (fmt->format == DAO_PIXFMT_DEPTH16)
		s->configured = DAO_STREAM_DEPTH;
	else
		return dao_error_set(err, -ENOTSUP,
				     "mcap: the recorder takes the ao, shaded or depth stream, not "
				     "%s; it records the AO and shaded images either way",
				     dao_pixfmt_name(fmt->format));
	double hfov = fmt->has_fov ? fmt->hfov : MCAP_SINK_DEFAULT_HFOV_DEG * DAO_PI / 180;
	double vfov = fmt->has_fov ? fmt->vfov : MCAP_SINK_DEFAULT_VFOV_DEG * DAO_PI / 180;
	struct dao_camera cam; /* as the daemon makes its camera */
	int r = dao_camera_from_fov(&cam, fmt->width, fmt->height, hfov, vfov, err);
	if (r < 0)
		return r;
	s->cam = (struct dao_ros2_pinhole){cam.width, cam.height, cam.fx, cam.fy, cam.cx, cam.cy};
	s->fps = fmt->fps > 0 ? fmt->fps : MCAP_SINK_DEFAULT_FPS;
	size_t npix = (size_t)fmt->width * fmt->height;
	if (s->cloud && (!(s->depth = malloc(2 * npix)) || !(s->ao = malloc(2 * npix)))) {
		drop_writer(s);
		return dao_error_set(err, -ENOMEM, "out of memory");
	}
	r = open_writer(s, err);
	if (r == 0 && (r = add_channels(s, err)) < 0)
		drop_writer(s);
	if (r < 0)
		return r;
	unsigned want = (1u << DAO_STREAM_AO) | (1u << DAO_STREAM_SHADED) |
			(s->cloud ? 1u << DAO_STREAM_DEPTH : 0) |
			(s->fdepth ? 1u << DAO_STREAM_FILTERED_DEPTH : 0);
	want &= ~(1u << s->configured);
	if (s->rec.host.want_streams && want)
		s->rec.host.want_streams(s->rec.host.user, want);
	return 0;
}

static uint64_t stamp(const struct mcap_sink *s, const struct dao_frame *f)
{
	return f->timestamp_ns ? f->timestamp_ns : (uint64_t)(f->sequence * 1e9 / s->fps);
}

/* The camera's pose at stamp t on /tf (the frame info's, when it has one). */
static int put_pose(struct mcap_sink *s, const struct dao_sink_frame_info *info, uint64_t t,
		    struct dao_error *err)
{
	if (!DAO_STRUCT_HAS(struct dao_sink_frame_info, info, pose_translation) || !info->has_pose)
		return 0;
	uint8_t *p;
	size_t n = dao_ros2_tf_size(s->pose_frame, s->frame_id);
	int r = dao_mcap_writer_message(s->w, s->ch[CH_TF], t, t, n, &p, err);
	if (r == 0)
		dao_ros2_tf_encode(p, t, s->pose_frame, s->frame_id, info->pose_rotation,
				   info->pose_translation);
	return r;
}

/* An image; the AO's pose and CameraInfo go first, so that a message refused on a full
 * disk never leaves an AO image without them. */
static int put_image(struct mcap_sink *s, int ch, const char *encoding, const struct dao_frame *f,
		     const struct dao_sink_frame_info *info, struct dao_error *err)
{
	uint8_t *p;
	uint64_t t = stamp(s, f);
	int r;
	if (ch == CH_AO && (r = put_pose(s, info, t, err)) < 0)
		return r;
	if (ch == CH_AO) {
		size_t n = dao_ros2_camera_info_size(s->frame_id);
		if ((r = dao_mcap_writer_message(s->w, s->ch[CH_INFO], t, t, n, &p, err)) < 0)
			return r;
		dao_ros2_camera_info_encode(p, t, s->frame_id, &s->cam);
	}
	size_t n = dao_ros2_image_size(s->frame_id, encoding, f);
	if ((r = dao_mcap_writer_message(s->w, s->ch[ch], t, t, n, &p, err)) < 0)
		return r;
	dao_ros2_image_encode(p, t, s->frame_id, encoding, f);
	return 0;
}

static void copy_rows(uint16_t *dst, const struct dao_frame *f)
{
	for (uint32_t y = 0; y < f->height; y++)
		memcpy(dst + (size_t)y * f->width, (const uint8_t *)f->data + (size_t)y * (size_t)f->stride,
		       2 * (size_t)f->width);
}

/* The cloud of the depth and AO frames of one sequence number, once both are here. */
static int put_cloud(struct mcap_sink *s, struct dao_error *err)
{
	if (!s->have_depth || !s->have_ao || s->depth_seq != s->ao_seq)
		return 0;
	s->have_depth = s->have_ao = 0;
	size_t npix = (size_t)s->cam.width * s->cam.height;
	uint32_t n = 0;
	for (size_t i = 0; i < npix; i++)
		n += s->depth[i] != 0;
	uint8_t *p;
	size_t len = dao_ros2_cloud_size(s->frame_id, n);
	int r = dao_mcap_writer_message(s->w, s->ch[CH_CLOUD], s->depth_ts, s->depth_ts, len, &p, err);
	if (r < 0)
		return r;
	uint8_t *q = dao_ros2_cloud_encode(p, s->depth_ts, s->frame_id, n);
	float pts[4];
	const double ifx = 1 / s->cam.fx, ify = 1 / s->cam.fy;
	for (uint32_t v = 0, i = 0; v < s->cam.height; v++)
		for (uint32_t u = 0; u < s->cam.width; u++, i++) {
			if (!s->depth[i])
				continue;
			float z = s->depth[i] * s->depth_unit;
			pts[0] = (float)((u - s->cam.cx) * ifx * z);
			pts[1] = (float)((v - s->cam.cy) * ify * z);
			pts[2] = z;
			pts[3] = s->ao[i] / 65535.0f;
			memcpy(q, pts, sizeof pts); /* little-endian hosts: the field layout */
			q += DAO_ROS2_CLOUD_POINT_STEP;
		}
	return 0;
}

/*
 * The filtered depth: 16UC1 as it is when its counts are millimetres (what ROS
 * consumers take 16UC1 to be), else 32FC1 metres (0 stays 0: no depth).
 */
static int put_filtered_depth(struct mcap_sink *s, const struct dao_frame *f,
			      struct dao_error *err)
{
	if (fabsf(f->depth_unit - 0.001f) <= 1e-9f)
		return put_image(s, CH_FDEPTH, "16UC1", f, NULL, err);
	if (!s->fdepth_m.data &&
	    dao_frame_alloc(&s->fdepth_m, DAO_PIXFMT_DEPTH_F32, f->width, f->height, err) < 0)
		return -ENOMEM;
	for (uint32_t y = 0; y < f->height; y++) {
		const uint16_t *src = (const uint16_t *)((const uint8_t *)f->data +
							  (size_t)y * (size_t)f->stride);
		float *dst = (float *)((uint8_t *)s->fdepth_m.data +
				       (size_t)y * (size_t)s->fdepth_m.stride);
		for (uint32_t x = 0; x < f->width; x++)
			dst[x] = (float)src[x] * f->depth_unit;
	}
	s->fdepth_m.sequence = f->sequence;
	s->fdepth_m.timestamp_ns = f->timestamp_ns;
	return put_image(s, CH_FDEPTH, "32FC1", &s->fdepth_m, NULL, err);
}

static int mcap_sink_write_stream(void *state, const struct dao_sink_frame_info *info,
				  const struct dao_frame *f, struct dao_error *err)
{
	struct mcap_sink *s = state;
	static const enum dao_pixfmt want[DAO_STREAM_COUNT] = {
		DAO_PIXFMT_RGB24, DAO_PIXFMT_GRAY16, DAO_PIXFMT_GRAY8, DAO_PIXFMT_DEPTH16,
		DAO_PIXFMT_RGB24, DAO_PIXFMT_DEPTH16};
	if (!s->w)
		return dao_error_set(err, -EINVAL, "mcap: write before negotiate");
	enum dao_stream st = info->stream;
	if ((unsigned)st >= DAO_STREAM_COUNT || f->format != want[st] ||
	    f->width != s->cam.width || f->height != s->cam.height)
		return dao_error_set(err, -EINVAL,
				     "mcap: a %ux%u %s frame for stream %d; the recording is %ux%u",
				     f->width, f->height, dao_pixfmt_name(f->format), (int)st,
				     s->cam.width, s->cam.height);
	int r = 0;
	if (st == DAO_STREAM_AO) {
		r = put_image(s, CH_AO, "mono16", f, info, err);
		if (r == 0 && s->cloud) {
			copy_rows(s->ao, f);
			s->ao_seq = f->sequence;
			s->have_ao = 1;
		}
	} else if (st == DAO_STREAM_SHADED) {
		r = put_image(s, CH_SHADED, "rgb8", f, NULL, err);
	} else if (st == DAO_STREAM_FILTERED_DEPTH && s->fdepth) {
		r = put_filtered_depth(s, f, err);
	} else if (st == DAO_STREAM_DEPTH && s->cloud) {
		copy_rows(s->depth, f);
		s->depth_seq = f->sequence;
		s->depth_unit = f->depth_unit;
		s->depth_ts = stamp(s, f);
		s->have_depth = 1;
	}
	if (r == 0 && s->cloud)
		r = put_cloud(s, err);
	return r;
}

static int mcap_sink_write(void *state, const struct dao_frame *frame, struct dao_error *err)
{
	struct mcap_sink *s = state;
	const struct dao_sink_frame_info info = {.size = sizeof(info), .stream = s->configured};
	return mcap_sink_write_stream(state, &info, frame, err);
}

static int mcap_sink_flush(void *state, struct dao_error *err)
{
	struct mcap_sink *s = state;
	return s->w && dao_mcap_writer_messages(s->w) ? dao_mcap_writer_flush(s->w, err) : 0;
}

static int mcap_sink_close(void *state, struct dao_error *err)
{
	struct mcap_sink *s = state;
	int r = 0;
	if (s->w && dao_mcap_writer_messages(s->w) == 0)
		dao_mcap_writer_abort(s->w); /* nothing to save: no file */
	else if (s->w)
		r = dao_mcap_writer_finish(s->w, err); /* also after a failed write */
	free(s->depth);
	free(s->ao);
	dao_frame_free(&s->fdepth_m);
	dao_recorder_free(&s->rec);
	free(s);
	return r;
}

const struct dao_sink_ops dao_mcap_sink_ops = {
	.version = DAO_SINK_OPS_VERSION,
	.probe = mcap_sink_probe,
	.open = mcap_sink_open,
	.negotiate = mcap_sink_negotiate,
	.write = mcap_sink_write,
	.flush = mcap_sink_flush,
	.close = mcap_sink_close,
	.attach_host = mcap_sink_attach_host,
	.write_stream = mcap_sink_write_stream,
};
