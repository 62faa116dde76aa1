/* SPDX-License-Identifier: MIT */
/*
 * The source of the "mcap" and "db3" plugins (ros2_source.h): depth images
 * from a store of messages by topic.
 *
 * Messages: ROS 2 in the "cdr" message encoding (sensor_msgs/msg/Image,
 * CompressedImage, CameraInfo), and Foxglove's schemas in the "protobuf"
 * or "json" encoding (foxglove.RawImage, foxglove.CompressedImage,
 * foxglove.CameraCalibration; mcap/foxglove_msg.h) or as ROS 2 messages in
 * "cdr" (foxglove_msgs/msg/RawImage, CompressedImage, CameraCalibration:
 * the same rules).  The depth topic is an image topic in 16UC1 or mono16
 * (counts of `unit` metres: ?unit=, else the caller's depth_unit, else
 * 0.001) or 32FC1 (metres; NaN and 0 are no data), a CompressedImage topic
 * of image_transport's compressedDepth (compressed_depth.h: PNG or RVL;
 * 16UC1 counts or 32FC1 quantised), or a Foxglove CompressedImage topic
 * (foxglove.CompressedImage or foxglove_msgs/msg/CompressedImage) of 16-bit
 * grey PNGs ("png": counts).  With one such topic it is taken; with
 * several, ?topic= chooses (the error lists them).  The intrinsics come
 * from the first CameraInfo or CameraCalibration of the topic's namespace:
 * ".../camera_info" (or ".../calibration") beside ".../image_raw" (beside
 * ".../image_raw/compressedDepth" too).
 *
 * Colour (want_color): an image topic in rgb8, bgr8, rgba8, bgra8 or mono8,
 * or a compressed topic in JPEG (?color= chooses; one such topic is taken),
 * delivered as RGB24 with each depth frame: the colour message whose stamp
 * is nearest to the depth's, among those logged around it.
 *
 * Frames are the topic's messages in log-time order; a frame's time is its
 * header stamp (timestamp), or its log time when the stamp is 0.
 *
 * Camera poses (frame_pose): the depth frame's header.frame_id (a Foxglove
 * image's frame_id) in the store's transforms or odometry at the frame's
 * time (source_poses.h, pose_feeds.h: tf2_msgs/msg/TFMessage and
 * nav_msgs/msg/Odometry in CDR, foxglove.FrameTransform(s) in protobuf or
 * JSON).
 */
#include "plugin/ros2_source.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error_internal.h"
#include "mcap/compressed_depth.h"
#include "mcap/foxglove_msg.h"
#include "mcap/ros2_msg.h"
#include "oni/oni_color.h"
#include "plugin/playback.h"
#include "plugin/pose_feeds.h"
#include "plugin/source_poses.h"

/* What a topic's schema and encoding make of its messages. */
enum schema { S_NONE, S_IMAGE, S_COMPRESSED, S_CAMERA_INFO, S_FG_RAW, S_FG_COMPRESSED, S_FG_CALIB };

/* What a topic's first message says it carries. */
enum kind { K_NONE, K_DEPTH, K_CDEPTH, K_COLOR, K_JPEG };

/* An image message of any schema, parsed; data points into the message or the JSON buffer. */
struct img {
	uint64_t stamp_ns;
	const char *frame_id;        /* header.frame_id (ROS 2), frame_id (Foxglove); frame_id_len bytes */
	uint32_t frame_id_len;
	char fg_frame_id[256];       /* a Foxglove image's, where frame_id points */
	char encoding[64];           /* Image encoding or CompressedImage format */
	uint32_t width, height, step;
	int big_endian, compressed;
	const uint8_t *data;
	size_t data_len;
};

struct desc {
	enum kind kind;
	char encoding[64];
	uint32_t width, height;
	struct dao_cdepth_format cdf;
};

struct ros2_source {
	const struct dao_ros2_store_ops *ops;
	void *store;
	const char *scheme;
	uint32_t topic;
	uint32_t count;
	struct dao_source_options opts;
	struct dao_source_info info;
	struct desc depth_desc;
	int is_float;
	float unit;
	struct dao_frame depth;
	uint16_t *scratch;           /* a compressedDepth image's values */
	uint64_t depth_log_ns;
	int color_topic;             /* -1: no colour delivered */
	uint32_t color_count;
	struct desc color_desc;
	struct dao_frame color;
	struct dao_jpeg *jpeg;
	struct dao_fg_buf buf;       /* the bytes of a JSON message */
	struct dao_playback_cursor play;
	struct dao_source_poses *poses;
	struct dao_ros2_store_ref ref;      /* the store, for the poses */
	char frame_id[DAO_TF_NAME_MAX + 1]; /* the depth frame's header.frame_id */
	uint32_t frame_id_len;
};

static const char *path_of(const struct ros2_source *s)
{
	return s->ops->path(s->store);
}

static struct dao_ros2_topic topic_of(const struct ros2_source *s, uint32_t i)
{
	struct dao_ros2_topic t;
	s->ops->topic(s->store, i, &t);
	return t;
}

static int find_topic(const struct ros2_source *s, const char *name)
{
	uint32_t n = s->ops->topic_count(s->store);
	for (uint32_t i = 0; i < n; i++)
		if (!strcmp(topic_of(s, i).name, name))
			return (int)i;
	return -1;
}

/* Foxglove's image schemas by name (after "foxglove." or "foxglove_msgs/msg/"). */
static enum schema fg_image_schema(const char *name)
{
	if (!strcmp(name, "RawImage"))
		return S_FG_RAW;
	if (!strcmp(name, "CompressedImage"))
		return S_FG_COMPRESSED;
	return !strcmp(name, "CameraCalibration") ? S_FG_CALIB : S_NONE;
}

static enum schema schema_of(const struct dao_ros2_topic *t, enum dao_fg_encoding *fg)
{
	if (!strcmp(t->encoding, "cdr")) {
		if (!strcmp(t->schema, "sensor_msgs/msg/Image"))
			return S_IMAGE;
		if (!strcmp(t->schema, "sensor_msgs/msg/CompressedImage"))
			return S_COMPRESSED;
		if (!strcmp(t->schema, "sensor_msgs/msg/CameraInfo"))
			return S_CAMERA_INFO;
		*fg = DAO_FG_CDR; /* Foxglove's schemas as ROS 2 messages */
		return strncmp(t->schema, "foxglove_msgs/msg/", 18) ? S_NONE
								     : fg_image_schema(t->schema + 18);
	}
	if (!strcmp(t->encoding, "protobuf"))
		*fg = DAO_FG_PROTOBUF;
	else if (!strcmp(t->encoding, "json"))
		*fg = DAO_FG_JSON;
	else
		return S_NONE;
	return strncmp(t->schema, "foxglove.", 9) ? S_NONE : fg_image_schema(t->schema + 9);
}

static int is_image_topic(const struct dao_ros2_topic *t)
{
	enum dao_fg_encoding fg;
	enum schema sc = schema_of(t, &fg);
	return t->message_count > 0 &&
	       (sc == S_IMAGE || sc == S_COMPRESSED || sc == S_FG_RAW || sc == S_FG_COMPRESSED);
}

static void from_fg(struct img *out, const struct dao_fg_image *fi)
{
	out->stamp_ns = fi->stamp_ns;
	memcpy(out->fg_frame_id, fi->frame_id, sizeof out->fg_frame_id);
	out->frame_id = out->fg_frame_id;
	out->frame_id_len = (uint32_t)strlen(out->fg_frame_id);
	memcpy(out->encoding, fi->encoding, sizeof out->encoding);
	out->width = fi->width;
	out->height = fi->height;
	out->step = fi->step;
	out->data = fi->data;
	out->data_len = fi->data_len;
}

/* A message of an image topic, parsed: 0, -EINVAL (not its schema), -ENOTSUP (a Foxglove
 * message in XCDR2), -ENOMEM/-EFBIG (JSON). */
static int parse_image(struct ros2_source *s, const struct dao_ros2_topic *t, const uint8_t *d,
		       uint64_t n, struct img *out)
{
	enum dao_fg_encoding fg = DAO_FG_PROTOBUF;
	enum schema sc = schema_of(t, &fg);
	size_t len = n > SIZE_MAX ? SIZE_MAX : (size_t)n;
	int r = -EINVAL;
	memset(out, 0, sizeof(*out));
	if (sc == S_IMAGE) {
		struct dao_ros2_image im;
		if ((r = dao_ros2_image_parse(d, n, &im)) < 0)
			return -EINVAL;
		out->stamp_ns = im.header.stamp_ns;
		out->frame_id = im.header.frame_id;
		out->frame_id_len = im.header.frame_id_len;
		snprintf(out->encoding, sizeof out->encoding, "%s", im.encoding);
		out->width = im.width;
		out->height = im.height;
		out->step = im.step;
		out->big_endian = im.is_bigendian;
		out->data = im.data;
		out->data_len = im.data_len;
	} else if (sc == S_COMPRESSED) {
		struct dao_ros2_compressed_image ci;
		if ((r = dao_ros2_compressed_image_parse(d, n, &ci)) < 0)
			return -EINVAL;
		out->stamp_ns = ci.header.stamp_ns;
		out->frame_id = ci.header.frame_id;
		out->frame_id_len = ci.header.frame_id_len;
		snprintf(out->encoding, sizeof out->encoding, "%s", ci.format);
		out->compressed = 1;
		out->data = ci.data;
		out->data_len = ci.data_len;
	} else if (sc == S_FG_RAW || sc == S_FG_COMPRESSED) {
		struct dao_fg_image fi;
		r = sc == S_FG_RAW ? dao_fg_raw_image_parse(fg, d, len, &s->buf, &fi)
				   : dao_fg_compressed_image_parse(fg, d, len, &s->buf, &fi);
		if (r < 0)
			return r;
		from_fg(out, &fi);
		out->compressed = sc == S_FG_COMPRESSED;
	}
	return r;
}

/* The size of a JPEG from its SOF marker; 0 or -EINVAL. */
static int jpeg_size(const uint8_t *d, size_t n, uint32_t *w, uint32_t *h)
{
	size_t at = 2;
	if (n < 4 || d[0] != 0xFF || d[1] != 0xD8)
		return -EINVAL;
	while (at + 4 <= n) {
		if (d[at] != 0xFF)
			return -EINVAL;
		uint8_t mk = d[at + 1];
		uint32_t len = (uint32_t)d[at + 2] << 8 | d[at + 3];
		if (mk >= 0xC0 && mk <= 0xCF && mk != 0xC4 && mk != 0xC8 && mk != 0xCC) {
			if (len < 7 || at + 9 > n)
				return -EINVAL;
			*h = (uint32_t)d[at + 5] << 8 | d[at + 6];
			*w = (uint32_t)d[at + 7] << 8 | d[at + 8];
			return *w && *h ? 0 : -EINVAL;
		}
		at += 2 + len;
	}
	return -EINVAL;
}

/* A parsed image message, described (kind K_NONE for what the source does not take). */
static int describe(const struct img *im, struct desc *out)
{
	memset(out, 0, sizeof(*out));
	memcpy(out->encoding, im->encoding, sizeof out->encoding);
	if (!im->compressed) {
		out->width = im->width;
		out->height = im->height;
		out->kind = dao_ros_depth_kind(im->encoding)   ? K_DEPTH
			    : dao_ros_color_bytes(im->encoding) ? K_COLOR
								: K_NONE;
		return 0;
	}
	if (dao_cdepth_parse_format(im->encoding, &out->cdf) == 0) {
		out->kind = K_CDEPTH;
		return dao_cdepth_size(&out->cdf, im->data, im->data_len, &out->width, &out->height);
	}
	if (!strcmp(im->encoding, "png")) { /* foxglove: depth if 16-bit grey */
		out->cdf.plain = 1;
		out->cdf.codec = DAO_CDEPTH_PNG;
		if (dao_cdepth_size(&out->cdf, im->data, im->data_len, &out->width, &out->height) == 0)
			out->kind = K_CDEPTH;
		return 0;
	}
	if (strstr(im->encoding, "jpeg") || strstr(im->encoding, "jpg")) {
		out->kind = K_JPEG;
		return jpeg_size(im->data, im->data_len, &out->width, &out->height);
	}
	return 0;
}

static int not_a(struct ros2_source *s, int r, uint32_t i, const struct dao_ros2_topic *t,
		 struct dao_error *err)
{
	if (r == -EFBIG || r == -ENOMEM)
		return dao_error_set(err, r, "%s: message %u of '%s' holds more bytes than the "
				     "limit (%zu)", path_of(s), i, t->name, s->buf.max);
	if (r == -ENOTSUP)
		return dao_error_set(err, -ENOTSUP, "%s: message %u of '%s' uses a CDR encapsulation "
				     "depthao does not read (XCDR2): record it with XCDR1, ROS 2's "
				     "default", path_of(s), i, t->name);
	return dao_error_set(err, -EINVAL, "%s: message %u of '%s' is not a %s (%s): cut short, "
			     "a field out of range or a name too long; fix or drop it",
			     path_of(s), i, t->name, t->schema, t->encoding);
}

/* Message i of a topic, parsed and described; its time (stamp, else log time). */
static int read_image(struct ros2_source *s, uint32_t topic, uint32_t i, struct img *im,
		      struct desc *dsc, uint64_t *t_ns, struct dao_error *err)
{
	const struct dao_ros2_topic t = topic_of(s, topic);
	const uint8_t *d;
	uint64_t n, log_ns;
	int r = s->ops->read_message(s->store, topic, i, &d, &n, &log_ns, err);
	if (r < 0)
		return r;
	if ((r = parse_image(s, &t, d, n, im)) < 0 || (r = describe(im, dsc)) < 0)
		return not_a(s, r, i, &t, err);
	*t_ns = im->stamp_ns ? im->stamp_ns : log_ns;
	if (topic == s->topic)
		s->depth_log_ns = log_ns;
	return 0;
}

static int first_desc(struct ros2_source *s, uint32_t t, struct desc *out, struct dao_error *err)
{
	struct img im;
	uint64_t ts;
	return read_image(s, t, 0, &im, out, &ts, err);
}

static int is_depth(const struct desc *d)
{
	return d->kind == K_DEPTH || d->kind == K_CDEPTH;
}

static int is_color(const struct desc *d)
{
	return d->kind == K_COLOR || d->kind == K_JPEG;
}

static int chosen_topic(struct ros2_source *s, const char *name, struct dao_error *err)
{
	int t = find_topic(s, name), r;
	if (t < 0)
		return 1;
	struct dao_ros2_topic tp = topic_of(s, (uint32_t)t);
	if (!is_image_topic(&tp))
		return 1;
	if ((r = first_desc(s, (uint32_t)t, &s->depth_desc, err)) < 0)
		return r;
	if (!is_depth(&s->depth_desc))
		return dao_error_set(err, -EINVAL,
				     "%s: topic '%s' has images of encoding '%s', not depth "
				     "(16UC1, mono16, 32FC1, compressedDepth or 16-bit PNG)", path_of(s),
				     name, s->depth_desc.encoding);
	s->topic = (uint32_t)t;
	return 0;
}

static int pick_topic(struct ros2_source *s, const struct dao_ros_uri *u, struct dao_error *err)
{
	const char *path = path_of(s);
	char depth[400] = "", other[400] = "";
	int found = -1, ndepth = 0, r;
	if (u->topic[0] && (r = chosen_topic(s, u->topic, err)) <= 0)
		return r;
	for (uint32_t t = 0; t < s->ops->topic_count(s->store); t++) {
		struct dao_ros2_topic tp = topic_of(s, t);
		struct desc d;
		if (!is_image_topic(&tp))
			continue;
		if ((r = first_desc(s, t, &d, err)) < 0)
			return r;
		if (is_depth(&d)) {
			dao_ros_topic_list_add(depth, sizeof(depth), tp.name, d.encoding);
			if (ndepth++ == 0) {
				found = (int)t;
				s->depth_desc = d;
			}
		} else {
			dao_ros_topic_list_add(other, sizeof(other), tp.name, d.encoding);
		}
	}
	if (u->topic[0])
		return dao_error_set(err, -ENOENT, "%s: no image topic '%s'; depth topics: %s", path,
				     u->topic, ndepth ? depth : "none");
	if (ndepth == 0)
		return dao_error_set(err, -EINVAL,
				     "%s: no depth image topic (sensor_msgs Image in 16UC1, mono16 or "
				     "32FC1, or compressedDepth; Foxglove RawImage or 16-bit PNG "
				     "CompressedImage); image topics: %s", path,
				     other[0] ? other : "none");
	if (ndepth > 1)
		return dao_error_set(err, -EINVAL,
				     "%s: %d depth topics, choose one with ?topic=NAME: %s", path,
				     ndepth, depth);
	s->topic = (uint32_t)found;
	return 0;
}

/* The intrinsics of a CameraInfo or CameraCalibration message. */
static int camera_message(struct ros2_source *s, const struct dao_ros2_topic *tp, enum schema sc,
			  enum dao_fg_encoding fg, const uint8_t *d, uint64_t n,
			  struct dao_error *err)
{
	const char *path = path_of(s);
	if (sc == S_CAMERA_INFO) {
		struct dao_ros2_camera_info ci;
		if (dao_ros2_camera_info_parse(d, n, &ci) < 0)
			return dao_error_set(err, -EINVAL, "%s: the first message of '%s' is not a %s",
					     path, tp->name, tp->schema);
		uint32_t nd = ci.distortion_count < DAO_ROS2_MAX_DISTORTION ? ci.distortion_count
									     : DAO_ROS2_MAX_DISTORTION;
		return dao_ros_camera_info_intrinsics(&s->info, path, tp->name, ci.width, ci.height,
						      ci.k, ci.p, ci.d, nd, err);
	}
	struct dao_fg_calibration c;
	const int cr = dao_fg_calibration_parse(fg, d, n > SIZE_MAX ? SIZE_MAX : (size_t)n, &c);
	if (cr == -ENOTSUP)
		return dao_error_set(err, -ENOTSUP, "%s: the first message of '%s' uses a CDR "
				     "encapsulation depthao does not read (XCDR2): record it with "
				     "XCDR1, ROS 2's default", path, tp->name);
	if (cr < 0)
		return dao_error_set(err, -EINVAL, "%s: the first message of '%s' is not a %s (%s%s",
				     path, tp->name, tp->schema, tp->encoding,
				     fg == DAO_FG_CDR ? "): cut short or a name too long"
						      : "; K must have 9 values, P 12 or none)");
	uint32_t nd = c.d_count < DAO_FG_MAX_DISTORTION ? c.d_count : DAO_FG_MAX_DISTORTION;
	return dao_ros_camera_info_intrinsics(&s->info, path, tp->name, c.width, c.height, c.k,
					      c.p, c.d, nd, err);
}

/* The calibration of `prefix` (prefix_len bytes of the depth topic) + "/camera_info" or
 * "/calibration": 1 if none. */
static int try_camera(struct ros2_source *s, const char *topic, size_t prefix_len,
		      struct dao_error *err)
{
	static const char *const names[] = {"camera_info", "calibration"};
	for (size_t k = 0; k < sizeof names / sizeof names[0]; k++) {
		char name[600];
		snprintf(name, sizeof(name), "%.*s/%s", (int)prefix_len, topic, names[k]);
		int t = find_topic(s, name);
		if (t < 0)
			continue;
		struct dao_ros2_topic tp = topic_of(s, (uint32_t)t);
		enum dao_fg_encoding fg = DAO_FG_PROTOBUF;
		enum schema sc = schema_of(&tp, &fg);
		if ((sc != S_CAMERA_INFO && sc != S_FG_CALIB) || !tp.message_count)
			continue;
		const uint8_t *d;
		uint64_t n;
		int r = s->ops->read_message(s->store, (uint32_t)t, 0, &d, &n, NULL, err);
		return r < 0 ? r : camera_message(s, &tp, sc, fg, d, n, err);
	}
	return 1;
}

static int find_camera(struct ros2_source *s, const struct dao_ros_uri *u,
		       struct dao_error *err)
{
	struct dao_ros2_topic tp = topic_of(s, s->topic);
	const char *topic = tp.name;
	const char *slash = strrchr(topic, '/');
	size_t n = slash ? (size_t)(slash - topic) : 0;
	int r = try_camera(s, topic, n, err);
	if (r == 1 && slash && (!strcmp(slash, "/compressedDepth") || !strcmp(slash, "/compressed"))) {
		/* ".../image_raw/compressedDepth": the camera_info beside image_raw */
		while (n > 0 && topic[n - 1] != '/')
			n--;
		r = try_camera(s, topic, n ? n - 1 : 0, err);
	}
	if (r < 0)
		return r;
	s->unit = u->unit;
	if (!s->unit)
		s->unit = s->opts.depth_unit > 0 ? s->opts.depth_unit : 0.001f;
	return 0;
}

static int check_pixels(const char *path, const char *what, const char *topic,
			const struct desc *d, uint64_t max_pixels, struct dao_error *err)
{
	if ((uint64_t)d->width * d->height > max_pixels || !d->width || !d->height)
		return dao_error_set(err, d->width && d->height ? -EFBIG : -EINVAL,
				     "%s: %stopic '%s' has %ux%u images; the limit is %llu pixels",
				     path, what, topic, d->width, d->height,
				     (unsigned long long)max_pixels);
	return 0;
}

static int pick_color(struct ros2_source *s, const struct dao_ros_uri *u, uint64_t max_pixels,
		      struct dao_error *err)
{
	const char *path = path_of(s);
	char list[400] = "";
	struct desc d;
	int found = -1, n = 0, r;
	for (uint32_t t = 0; t < s->ops->topic_count(s->store); t++) {
		struct dao_ros2_topic tp = topic_of(s, t);
		if (!is_image_topic(&tp) || (t == s->topic && !u->color[0]))
			continue;
		if (u->color[0] && strcmp(tp.name, u->color))
			continue;
		if ((r = first_desc(s, t, &d, err)) < 0)
			return r;
		if (u->color[0] && !is_color(&d))
			return dao_error_set(err, -EINVAL,
					     "%s: topic '%s' has images of encoding '%s', not colour "
					     "(rgb8, bgr8, rgba8, bgra8, mono8 or JPEG)", path, u->color,
					     d.encoding);
		if (!is_color(&d))
			continue;
		dao_ros_topic_list_add(list, sizeof(list), tp.name, d.encoding);
		if (n++ == 0) {
			found = (int)t;
			s->color_desc = d;
		}
	}
	if (u->color[0] && n == 0)
		return dao_error_set(err, -ENOENT, "%s: no image topic '%s' (color=)", path, u->color);
	if (n == 0) {
		snprintf(s->info.warning, sizeof(s->info.warning),
			 "no colour: the file has no image topic in rgb8, bgr8, rgba8, bgra8, mono8 "
			 "or JPEG");
		return 0;
	}
	if (n > 1)
		return dao_error_set(err, -EINVAL,
				     "%s: %d colour topics, choose one with ?color=NAME: %s", path, n,
				     list);
	struct dao_ros2_topic ct = topic_of(s, (uint32_t)found);
	if ((r = check_pixels(path, "colour ", ct.name, &s->color_desc, max_pixels, err)) < 0 ||
	    (r = dao_frame_alloc(&s->color, DAO_PIXFMT_RGB24, s->color_desc.width,
				 s->color_desc.height, err)) < 0)
		return r;
	if (s->color_desc.kind == K_JPEG && dao_jpeg_create(&s->jpeg) < 0)
		return dao_error_set(err, -ENOMEM, "out of memory");
	s->color_topic = found;
	s->color_count = ct.message_count;
	s->info.has_color = 1;
	s->info.color_width = s->color_desc.width;
	s->info.color_height = s->color_desc.height;
	return 0;
}

static void free_source(struct ros2_source *s)
{
	dao_frame_free(&s->depth);
	dao_frame_free(&s->color);
	if (s->jpeg)
		dao_jpeg_destroy(s->jpeg);
	free(s->scratch);
	dao_fg_buf_free(&s->buf);
	dao_source_poses_free(s->poses);
	if (s->store)
		s->ops->close(s->store);
	free(s);
}

/* The stream's description, format and buffers once the topics are chosen. */
static int setup(struct ros2_source *s, const char *path, struct dao_error *err)
{
	const struct dao_ros2_topic tp = topic_of(s, s->topic);
	const struct desc *dd = &s->depth_desc;
	const char *warning = s->ops->warning(s->store);
	s->info.registered = strstr(tp.name, "aligned_depth_to_color") != NULL ||
			     strstr(tp.name, "depth_registered") != NULL;
	if (warning)
		snprintf(s->info.warning, sizeof(s->info.warning), "%s", warning);
	if (s->opts.start_frame >= s->count)
		return dao_error_set(err, -EINVAL,
				     "%s: start frame %u is past the end (topic '%s' has %u frames)",
				     path, s->opts.start_frame, tp.name, s->count);
	s->info.format = s->is_float ? DAO_PIXFMT_DEPTH_F32 : DAO_PIXFMT_DEPTH16;
	s->info.depth_unit = s->is_float ? 0.0f : s->unit;
	s->info.frame_count = s->count;
	const char *base = strrchr(path, '/');
	snprintf(s->info.description, sizeof(s->info.description),
		 "%.40s: %.50s %ux%u %.30s, %u frames", base ? base + 1 : path, tp.name, dd->width,
		 dd->height, dd->encoding, s->count);
	int r = dao_frame_alloc(&s->depth, s->info.format, dd->width, dd->height, err);
	if (r < 0)
		return r;
	if (dd->kind == K_CDEPTH &&
	    !(s->scratch = malloc((size_t)dd->width * dd->height * sizeof(uint16_t))))
		return dao_error_set(err, -ENOMEM, "out of memory");
	dao_playback_init(&s->play, &s->opts, s->count);
	return 0;
}

int dao_ros2_source_open(const struct dao_ros2_store_ops *ops, void *impl,
			 const struct dao_ros_uri *u, const char *scheme,
			 const struct dao_source_options *opts, uint64_t max_pixels, void **state,
			 struct dao_error *err)
{
	struct ros2_source *s = calloc(1, sizeof(*s));
	int r;
	if (!s) {
		ops->close(impl);
		return dao_error_set(err, -ENOMEM, "out of memory");
	}
	s->ops = ops;
	s->store = impl;
	s->scheme = scheme;
	s->ref = (struct dao_ros2_store_ref){ ops, impl };
	s->opts = *opts;
	s->color_topic = -1;
	/* a JSON message's bytes: an image of up to 4 bytes a pixel, and room */
	s->buf.max = 4 * max_pixels + (1u << 20);
	if (!(opts->depth_unit >= 0 && opts->depth_unit <= 1)) {
		r = dao_error_set(err, -EINVAL, "%s: depth unit %g is not in (0, 1] metres", scheme,
				  (double)opts->depth_unit);
		goto fail;
	}
	if ((r = dao_source_poses_create(&s->poses, u, err)) < 0 || (r = pick_topic(s, u, err)) < 0)
		goto fail;
	const struct dao_ros2_topic tp = topic_of(s, s->topic);
	const struct desc *dd = &s->depth_desc;
	s->count = tp.message_count;
	if ((r = check_pixels(u->path, "", tp.name, dd, max_pixels, err)) < 0)
		goto fail;
	s->is_float = dd->kind == K_CDEPTH ? dd->cdf.is_float : dao_ros_depth_kind(dd->encoding) == 2;
	s->info.width = dd->width;
	s->info.height = dd->height;
	if ((r = find_camera(s, u, err)) < 0 ||
	    (opts->want_color && (r = pick_color(s, u, max_pixels, err)) < 0) ||
	    (r = setup(s, u->path, err)) < 0)
		goto fail;
	*state = s;
	return 0;
fail:
	free_source(s);
	return r;
}

void dao_ros2_source_get_info(void *state, struct dao_source_info *in)
{
	struct ros2_source *s = state;
	*in = s->info;
}

int dao_ros2_source_start(void *state, struct dao_error *err)
{
	struct ros2_source *s = state;
	(void)err;
	dao_playback_restart(&s->play);
	return 0;
}

/* Message i of a topic, described and checked against the topic's first. */
static int image_message(struct ros2_source *s, uint32_t topic, uint32_t i,
			 const struct desc *want, struct desc *got, struct img *im, uint64_t *t_ns,
			 struct dao_error *err)
{
	int r = read_image(s, topic, i, im, got, t_ns, err);
	if (r < 0)
		return r;
	if (got->width != want->width || got->height != want->height ||
	    strcmp(got->encoding, want->encoding))
		return dao_error_set(err, -EINVAL,
				     "%s: message %u of '%s' is %ux%u %s, the topic began with %ux%u "
				     "%s", path_of(s), i, topic_of(s, topic).name, got->width,
				     got->height, got->encoding, want->width, want->height,
				     want->encoding);
	return 0;
}

/* The rows of an uncompressed image: enough data for its step and size? */
static int check_rows(struct ros2_source *s, const struct img *im, uint32_t bpp, uint32_t i,
		      const char *topic, struct dao_error *err)
{
	if (im->step < (uint64_t)im->width * bpp || (uint64_t)im->step * im->height > im->data_len)
		return dao_error_set(err, -EINVAL,
				     "%s: message %u of '%s': %zu bytes of data for %u rows of "
				     "step %u (%ux%u, %u bytes a pixel)", path_of(s), i, topic,
				     im->data_len, im->height, im->step, im->width, im->height, bpp);
	return 0;
}

/* Decodes message i of the depth topic into s->depth. */
static int decode(struct ros2_source *s, uint32_t i, struct dao_error *err)
{
	const struct dao_ros2_topic tp = topic_of(s, s->topic);
	uint64_t t_ns;
	struct desc got;
	struct img im;
	int r = image_message(s, s->topic, i, &s->depth_desc, &got, &im, &t_ns, err);
	if (r < 0)
		return r;
	if (got.kind == K_CDEPTH) {
		char why[160];
		if (dao_cdepth_decode(&got.cdf, im.data, im.data_len, got.width, got.height,
				      s->depth.data, (size_t)s->depth.stride, s->scratch, why,
				      sizeof why) < 0)
			return dao_error_set(err, -EINVAL, "%s: message %u of '%s': %s", path_of(s),
					     i, tp.name, why);
	} else {
		uint32_t bpp = s->is_float ? 4 : 2;
		if ((r = check_rows(s, &im, bpp, i, tp.name, err)) < 0)
			return r;
		dao_ros_copy_depth(&s->depth, im.data, im.step, bpp,
				   !!im.big_endian != dao_ros_host_is_big_endian());
	}
	s->depth.depth_unit = s->is_float ? 0.0f : s->unit;
	s->depth.timestamp_ns = t_ns;
	s->depth.sequence = (uint64_t)i + 1;
	dao_ros_keep_frame_id(s->frame_id, &s->frame_id_len, im.frame_id, im.frame_id_len);
	return 0;
}

/* The colour frame nearest in time to the depth frame just decoded, into s->color. */
static int decode_color(struct ros2_source *s, struct dao_error *err)
{
	const uint32_t ct = (uint32_t)s->color_topic;
	const uint64_t t = s->depth.timestamp_ns;
	uint32_t lo = 0, hi = s->color_count;
	while (lo < hi) { /* the first colour message logged at or after the depth */
		uint32_t mid = lo + (hi - lo) / 2;
		if (s->ops->message_time(s->store, ct, mid) < s->depth_log_ns)
			lo = mid + 1;
		else
			hi = mid;
	}
	uint32_t first = lo >= 2 ? lo - 2 : 0;
	uint32_t last = lo + 2 < s->color_count ? lo + 2 : s->color_count;
	uint32_t best = first;
	uint64_t best_d = UINT64_MAX, ts;
	struct desc got;
	struct img im;
	int r;
	for (uint32_t i = first; i < last || i == first; i++) {
		if ((r = image_message(s, ct, i, &s->color_desc, &got, &im, &ts, err)) < 0)
			return r;
		uint64_t dist = ts > t ? ts - t : t - ts;
		if (dist < best_d) {
			best_d = dist;
			best = i;
		}
	}
	if ((r = image_message(s, ct, best, &s->color_desc, &got, &im, &ts, err)) < 0)
		return r;
	const char *topic = topic_of(s, ct).name;
	if (got.kind == K_JPEG) {
		char why[160];
		if (dao_jpeg_decode(s->jpeg, im.data, im.data_len, &s->color, why, sizeof why) < 0)
			return dao_error_set(err, -EINVAL, "%s: message %u of '%s': %s", path_of(s),
					     best, topic, why);
	} else {
		if ((r = check_rows(s, &im, dao_ros_color_bytes(im.encoding), best, topic, err)) < 0)
			return r;
		dao_ros_color_to_rgb(&s->color, im.data, im.step, im.encoding);
	}
	s->color.timestamp_ns = ts;
	s->color.sequence = (uint64_t)best + 1;
	return 0;
}

int dao_ros2_source_read(void *state, struct dao_source_frame *f, int timeout_ms,
			 struct dao_error *err)
{
	struct ros2_source *s = state;
	uint64_t i;
	int r = dao_playback_next(&s->play, &i, err);
	if (r)
		return r;
	if ((r = decode(s, (uint32_t)i, err)) < 0)
		return dao_playback_skip(&s->play, r, err);
	if ((r = dao_playback_pace(&s->play, s->depth.timestamp_ns / 1000, timeout_ms)) < 0)
		return r;
	f->color.format = DAO_PIXFMT_NONE;
	if (s->color_topic >= 0) {
		if ((r = decode_color(s, err)) < 0)
			return dao_playback_skip(&s->play, r, err);
		f->color = s->color;
	}
	f->depth = s->depth;
	f->index = dao_playback_advance(&s->play);
	return 0;
}

int dao_ros2_source_seek(void *state, uint64_t index, struct dao_error *err)
{
	struct ros2_source *s = state;
	if (index >= s->count)
		return dao_error_set(err, -EINVAL, "seek to frame %llu: the topic has %u frames",
				     (unsigned long long)index, s->count);
	dao_playback_seek(&s->play, index);
	return 0;
}

void dao_ros2_source_close(void *state)
{
	free_source(state);
}

int dao_ros2_source_frame_pose(void *state, const struct dao_source_frame *f,
			       struct dao_source_pose *pose, struct dao_error *err)
{
	struct ros2_source *s = state;
	struct dao_pose_feed feed;
	dao_ros2_pose_feed(&s->ref, &feed);
	return dao_source_poses_get(s->poses, &feed, s->frame_id, s->frame_id_len,
				    f->depth.timestamp_ns, pose, err);
}
