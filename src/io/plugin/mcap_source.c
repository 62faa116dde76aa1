/* SPDX-License-Identifier: MIT */
/*
 * Built-in source "mcap": depth images from an MCAP file (ROS 2's default
 * bag format) through depthao's own reader (mcap/mcap_reader.c).  URI:
 * FILE.mcap[?topic=T][&unit=M][&color=C] (the options in any order).
 *
 * Channels in the "cdr" message encoding are read (ROS 2, ros2msg schemas).
 * The depth topic is a sensor_msgs/msg/Image topic in 16UC1 or mono16
 * (counts of `unit` metres: ?unit=, else the caller's depth_unit, else
 * 0.001) or 32FC1 (metres; NaN and 0 are no data), or a
 * sensor_msgs/msg/CompressedImage topic of image_transport's compressedDepth
 * (compressed_depth.h: PNG or RVL; 16UC1 counts or 32FC1 quantised).  With
 * one such topic it is taken; with several, ?topic= chooses (the error
 * lists them).  The intrinsics come from the first sensor_msgs/msg/
 * CameraInfo of the topic's namespace: ".../camera_info" beside
 * ".../image_raw" (beside ".../image_raw/compressedDepth" too).
 *
 * Colour (want_color): an Image topic in rgb8, bgr8, rgba8, bgra8 or mono8,
 * or a CompressedImage topic in JPEG (?color= chooses; one such topic is
 * taken), delivered as RGB24 with each depth frame: the colour message whose
 * header stamp is nearest to the depth's, among those logged around it.
 *
 * Frames are the topic's messages in log-time order; a frame's time is its
 * header stamp, or its log time when the stamp is 0.  A file cut short is
 * read as far as it goes, with the reader's warning.
 */
#include <depthao/plugin.h>

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "core/error_internal.h"
#include "mcap/compressed_depth.h"
#include "mcap/mcap_reader.h"
#include "mcap/ros2_msg.h"
#include "oni/oni_color.h"
#include "plugin/builtin.h"
#include "plugin/playback.h"
#include "plugin/ros_image.h"

#define SCHEMA_IMAGE "sensor_msgs/msg/Image"
#define SCHEMA_COMPRESSED "sensor_msgs/msg/CompressedImage"
#define SCHEMA_CAMERA_INFO "sensor_msgs/msg/CameraInfo"

/* What a topic's first message says it carries. */
enum kind { K_NONE, K_DEPTH, K_CDEPTH, K_COLOR, K_JPEG };

struct desc {
	enum kind kind;
	char encoding[64];           /* Image encoding or CompressedImage format */
	uint32_t width, height;
	struct dao_cdepth_format cdf;
};

struct mcap_source {
	struct dao_mcap *m;
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
	struct dao_playback_cursor play;
};

static int mcap_probe(const char *uri)
{
	size_t n = dao_uri_path_len(uri, dao_ros_uri_options);
	return n > 5 && !strncasecmp(uri + n - 5, ".mcap", 5) ? 60 : 0;
}

static int is_cdr_image_topic(const struct dao_mcap_topic *t)
{
	return t->message_count > 0 && !strcmp(t->encoding, "cdr") &&
	       (!strcmp(t->schema, SCHEMA_IMAGE) || !strcmp(t->schema, SCHEMA_COMPRESSED));
}

/* The size of a JPEG from its SOF marker; 0 or -EINVAL. */
static int jpeg_size(const uint8_t *d, uint32_t n, uint32_t *w, uint32_t *h)
{
	uint32_t at = 2;
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

/* A message of an image topic, described (kind K_NONE for what the source does not take). */
static int describe(const struct dao_mcap_topic *t, const uint8_t *d, uint64_t n,
		    struct desc *out, uint64_t *stamp)
{
	memset(out, 0, sizeof(*out));
	if (!strcmp(t->schema, SCHEMA_IMAGE)) {
		struct dao_ros2_image img;
		if (dao_ros2_image_parse(d, n, &img) < 0)
			return -EINVAL;
		snprintf(out->encoding, sizeof out->encoding, "%s", img.encoding);
		out->width = img.width;
		out->height = img.height;
		out->kind = dao_ros_depth_kind(img.encoding)   ? K_DEPTH
			    : dao_ros_color_bytes(img.encoding) ? K_COLOR
								: K_NONE;
		*stamp = img.header.stamp_ns;
		return 0;
	}
	struct dao_ros2_compressed_image ci;
	if (dao_ros2_compressed_image_parse(d, n, &ci) < 0)
		return -EINVAL;
	snprintf(out->encoding, sizeof out->encoding, "%s", ci.format);
	*stamp = ci.header.stamp_ns;
	if (dao_cdepth_parse_format(ci.format, &out->cdf) == 0) {
		out->kind = K_CDEPTH;
		return dao_cdepth_size(&out->cdf, ci.data, ci.data_len, &out->width, &out->height);
	}
	if (strstr(ci.format, "jpeg") || strstr(ci.format, "jpg")) {
		out->kind = K_JPEG;
		return jpeg_size(ci.data, ci.data_len, &out->width, &out->height);
	}
	return 0;
}

static int first_desc(struct dao_mcap *m, uint32_t t, struct desc *out, struct dao_error *err)
{
	const uint8_t *d;
	uint64_t n, stamp;
	int r = dao_mcap_read_message(m, t, 0, &d, &n, NULL, err);
	if (r < 0)
		return r;
	const struct dao_mcap_topic *tp = dao_mcap_topic(m, t);
	if (describe(tp, d, n, out, &stamp) < 0)
		return dao_error_set(err, -EINVAL, "%s: the first message of '%s' is not a %s",
				     dao_mcap_path(m), tp->name, tp->schema);
	return 0;
}

static int is_depth(const struct desc *d)
{
	return d->kind == K_DEPTH || d->kind == K_CDEPTH;
}

static int is_color(const struct desc *d)
{
	return d->kind == K_COLOR || d->kind == K_JPEG;
}

static int pick_topic(struct mcap_source *s, const struct dao_ros_uri *u,
		      struct dao_error *err)
{
	struct dao_mcap *m = s->m;
	const char *path = dao_mcap_path(m);
	char depth[400] = "", other[400] = "";
	int found = -1, ndepth = 0, r;
	if (u->topic[0]) {
		int t = dao_mcap_find_topic(m, u->topic);
		if (t < 0 || !is_cdr_image_topic(dao_mcap_topic(m, (uint32_t)t)))
			goto list;
		if ((r = first_desc(m, (uint32_t)t, &s->depth_desc, err)) < 0)
			return r;
		if (!is_depth(&s->depth_desc))
			return dao_error_set(err, -EINVAL,
					     "%s: topic '%s' has images of encoding '%s', not depth "
					     "(16UC1, mono16, 32FC1 or compressedDepth)", path, u->topic,
					     s->depth_desc.encoding);
		s->topic = (uint32_t)t;
		return 0;
	}
list:
	for (uint32_t t = 0; t < dao_mcap_topic_count(m); t++) {
		const struct dao_mcap_topic *tp = dao_mcap_topic(m, t);
		struct desc d;
		if (!is_cdr_image_topic(tp))
			continue;
		if ((r = first_desc(m, t, &d, err)) < 0)
			return r;
		if (is_depth(&d)) {
			dao_ros_topic_list_add(depth, sizeof(depth), tp->name, d.encoding);
			if (ndepth++ == 0) {
				found = (int)t;
				s->depth_desc = d;
			}
		} else {
			dao_ros_topic_list_add(other, sizeof(other), tp->name, d.encoding);
		}
	}
	if (u->topic[0])
		return dao_error_set(err, -ENOENT, "%s: no image topic '%s'; depth topics: %s", path,
				     u->topic, ndepth ? depth : "none");
	if (ndepth == 0)
		return dao_error_set(err, -EINVAL,
				     "%s: no depth image topic (sensor_msgs/msg/Image in 16UC1, mono16 "
				     "or 32FC1, or compressedDepth, in CDR); image topics: %s", path,
				     other[0] ? other : "none");
	if (ndepth > 1)
		return dao_error_set(err, -EINVAL,
				     "%s: %d depth topics, choose one with ?topic=NAME: %s", path,
				     ndepth, depth);
	s->topic = (uint32_t)found;
	return 0;
}

/* The CameraInfo of `prefix` (prefix_len bytes of the depth topic) + "/camera_info": 1 if none. */
static int try_camera(struct mcap_source *s, const char *topic, size_t prefix_len,
		      struct dao_error *err)
{
	char name[600];
	snprintf(name, sizeof(name), "%.*s/camera_info", (int)prefix_len, topic);
	int t = dao_mcap_find_topic(s->m, name);
	if (t < 0)
		return 1;
	const struct dao_mcap_topic *tp = dao_mcap_topic(s->m, (uint32_t)t);
	if (strcmp(tp->schema, SCHEMA_CAMERA_INFO) || strcmp(tp->encoding, "cdr") ||
	    !tp->message_count)
		return 1;
	const uint8_t *d;
	uint64_t n;
	int r = dao_mcap_read_message(s->m, (uint32_t)t, 0, &d, &n, NULL, err);
	if (r < 0)
		return r;
	struct dao_ros2_camera_info ci;
	if (dao_ros2_camera_info_parse(d, n, &ci) < 0)
		return dao_error_set(err, -EINVAL, "%s: the first message of '%s' is not a %s",
				     dao_mcap_path(s->m), name, SCHEMA_CAMERA_INFO);
	uint32_t nd = ci.distortion_count < DAO_ROS2_MAX_DISTORTION ? ci.distortion_count
								     : DAO_ROS2_MAX_DISTORTION;
	return dao_ros_camera_info_intrinsics(&s->info, dao_mcap_path(s->m), name, ci.width,
					      ci.height, ci.k, ci.p, ci.d, nd, err);
}

static int find_camera(struct mcap_source *s, const struct dao_ros_uri *u,
		       struct dao_error *err)
{
	const char *topic = dao_mcap_topic(s->m, s->topic)->name;
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

static int pick_color(struct mcap_source *s, const struct dao_ros_uri *u, uint64_t max_pixels,
		      struct dao_error *err)
{
	struct dao_mcap *m = s->m;
	const char *path = dao_mcap_path(m);
	char list[400] = "";
	struct desc d;
	int found = -1, n = 0, r;
	for (uint32_t t = 0; t < dao_mcap_topic_count(m); t++) {
		const struct dao_mcap_topic *tp = dao_mcap_topic(m, t);
		if (!is_cdr_image_topic(tp) || (t == s->topic && !u->color[0]))
			continue;
		if (u->color[0] && strcmp(tp->name, u->color))
			continue;
		if ((r = first_desc(m, t, &d, err)) < 0)
			return r;
		if (u->color[0] && !is_color(&d))
			return dao_error_set(err, -EINVAL,
					     "%s: topic '%s' has images of encoding '%s', not colour "
					     "(rgb8, bgr8, rgba8, bgra8, mono8 or JPEG)", path, u->color,
					     d.encoding);
		if (!is_color(&d))
			continue;
		dao_ros_topic_list_add(list, sizeof(list), tp->name, d.encoding);
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
	const char *name = dao_mcap_topic(m, (uint32_t)found)->name;
	if ((r = check_pixels(path, "colour ", name, &s->color_desc, max_pixels, err)) < 0 ||
	    (r = dao_frame_alloc(&s->color, DAO_PIXFMT_RGB24, s->color_desc.width,
				 s->color_desc.height, err)) < 0)
		return r;
	if (s->color_desc.kind == K_JPEG && dao_jpeg_create(&s->jpeg) < 0)
		return dao_error_set(err, -ENOMEM, "out of memory");
	s->color_topic = found;
	s->color_count = dao_mcap_topic(m, (uint32_t)found)->message_count;
	s->info.has_color = 1;
	s->info.color_width = s->color_desc.width;
	s->info.color_height = s->color_desc.height;
	return 0;
}

static void free_source(struct mcap_source *s)
{
	dao_frame_free(&s->depth);
	dao_frame_free(&s->color);
	if (s->jpeg)
		dao_jpeg_destroy(s->jpeg);
	free(s->scratch);
	dao_mcap_close(s->m);
	free(s);
}

int dao_mcap_source_open(const char *uri, const struct dao_source_options *opts,
			 uint64_t max_pixels, void **state, struct dao_error *err)
{
	struct mcap_source *s = calloc(1, sizeof(*s));
	struct dao_ros_uri u = {0};
	int r;
	if (!s)
		return dao_error_set(err, -ENOMEM, "out of memory");
	s->opts = *opts;
	s->color_topic = -1;
	if (!(opts->depth_unit >= 0 && opts->depth_unit <= 1)) {
		r = dao_error_set(err, -EINVAL, "mcap: depth unit %g is not in (0, 1] metres",
				  (double)opts->depth_unit);
		goto fail;
	}
	if ((r = dao_ros_uri_parse(uri, "mcap", &u, err)) < 0)
		goto fail;
	/* a chunk holds at least one image (up to 4 bytes a pixel), maybe colour beside it */
	if ((r = dao_mcap_open(u.path, 8 * max_pixels + (64u << 20), &s->m, err)) < 0 ||
	    (r = pick_topic(s, &u, err)) < 0)
		goto fail;
	const struct dao_mcap_topic *tp = dao_mcap_topic(s->m, s->topic);
	const struct desc *dd = &s->depth_desc;
	s->count = tp->message_count;
	if ((r = check_pixels(u.path, "", tp->name, dd, max_pixels, err)) < 0)
		goto fail;
	s->is_float = dd->kind == K_CDEPTH ? dd->cdf.is_float : dao_ros_depth_kind(dd->encoding) == 2;
	s->info.width = dd->width;
	s->info.height = dd->height;
	if ((r = find_camera(s, &u, err)) < 0)
		goto fail;
	if (opts->want_color && (r = pick_color(s, &u, max_pixels, err)) < 0)
		goto fail;
	s->info.registered = strstr(tp->name, "aligned_depth_to_color") != NULL ||
			     strstr(tp->name, "depth_registered") != NULL;
	if (dao_mcap_warning(s->m))
		snprintf(s->info.warning, sizeof(s->info.warning), "%s", dao_mcap_warning(s->m));
	if (opts->start_frame >= s->count) {
		r = dao_error_set(err, -EINVAL,
				  "%s: start frame %u is past the end (topic '%s' has %u frames)",
				  u.path, opts->start_frame, tp->name, s->count);
		goto fail;
	}
	s->info.format = s->is_float ? DAO_PIXFMT_DEPTH_F32 : DAO_PIXFMT_DEPTH16;
	s->info.depth_unit = s->is_float ? 0.0f : s->unit;
	s->info.frame_count = s->count;
	const char *base = strrchr(u.path, '/');
	snprintf(s->info.description, sizeof(s->info.description),
		 "%.40s: %.50s %ux%u %.30s, %u frames", base ? base + 1 : u.path, tp->name,
		 dd->width, dd->height, dd->encoding, s->count);
	if ((r = dao_frame_alloc(&s->depth, s->info.format, dd->width, dd->height, err)) < 0)
		goto fail;
	if (dd->kind == K_CDEPTH &&
	    !(s->scratch = malloc((size_t)dd->width * dd->height * sizeof(uint16_t)))) {
		r = dao_error_set(err, -ENOMEM, "out of memory");
		goto fail;
	}
	dao_playback_init(&s->play, opts, s->count);
	dao_ros_uri_free(&u);
	*state = s;
	return 0;
fail:
	dao_ros_uri_free(&u);
	free_source(s);
	return r;
}

static int mcap_open(const char *uri, const struct dao_source_options *opts, void **state,
		     struct dao_error *err)
{
	return dao_mcap_source_open(uri, opts, DAO_DEFAULT_MAX_PIXELS, state, err);
}

static void mcap_get_info(void *state, struct dao_source_info *in)
{
	struct mcap_source *s = state;
	*in = s->info;
}

static int mcap_start(void *state, struct dao_error *err)
{
	struct mcap_source *s = state;
	(void)err;
	dao_playback_restart(&s->play);
	return 0;
}

/* Message i of a topic, described and checked against the topic's first. */
static int image_message(struct mcap_source *s, uint32_t topic, uint32_t i,
			 const struct desc *want, struct desc *got, uint64_t *t_ns,
			 const uint8_t **msg, uint64_t *len, struct dao_error *err)
{
	const char *path = dao_mcap_path(s->m);
	const struct dao_mcap_topic *tp = dao_mcap_topic(s->m, topic);
	uint64_t log_ns, stamp;
	int r = dao_mcap_read_message(s->m, topic, i, msg, len, &log_ns, err);
	if (r < 0)
		return r;
	if (describe(tp, *msg, *len, got, &stamp) < 0)
		return dao_error_set(err, -EINVAL, "%s: message %u of '%s' is not a %s", path, i,
				     tp->name, tp->schema);
	if (got->width != want->width || got->height != want->height ||
	    strcmp(got->encoding, want->encoding))
		return dao_error_set(err, -EINVAL,
				     "%s: message %u of '%s' is %ux%u %s, the topic began with %ux%u "
				     "%s", path, i, tp->name, got->width, got->height, got->encoding,
				     want->width, want->height, want->encoding);
	*t_ns = stamp ? stamp : log_ns;
	if (topic == s->topic)
		s->depth_log_ns = log_ns;
	return 0;
}

/* Decodes message i of the depth topic into s->depth. */
static int decode(struct mcap_source *s, uint32_t i, struct dao_error *err)
{
	const char *path = dao_mcap_path(s->m), *topic = dao_mcap_topic(s->m, s->topic)->name;
	const uint8_t *d;
	uint64_t n, t_ns;
	struct desc got;
	int r = image_message(s, s->topic, i, &s->depth_desc, &got, &t_ns, &d, &n, err);
	if (r < 0)
		return r;
	if (got.kind == K_CDEPTH) {
		struct dao_ros2_compressed_image ci;
		char why[160];
		dao_ros2_compressed_image_parse(d, n, &ci);
		if (dao_cdepth_decode(&got.cdf, ci.data, ci.data_len, got.width, got.height,
				      s->depth.data, (size_t)s->depth.stride, s->scratch, why,
				      sizeof why) < 0)
			return dao_error_set(err, -EINVAL, "%s: message %u of '%s': %s", path, i,
					     topic, why);
	} else {
		struct dao_ros2_image img;
		dao_ros2_image_parse(d, n, &img);
		uint32_t bpp = s->is_float ? 4 : 2;
		if (img.step < (uint64_t)img.width * bpp ||
		    (uint64_t)img.step * img.height > img.data_len)
			return dao_error_set(err, -EINVAL,
					     "%s: message %u of '%s': %u bytes of data for %u rows of "
					     "step %u (%ux%u, %u bytes a pixel)", path, i, topic,
					     img.data_len, img.height, img.step, img.width, img.height,
					     bpp);
		dao_ros_copy_depth(&s->depth, img.data, img.step, bpp,
				   !!img.is_bigendian != dao_ros_host_is_big_endian());
	}
	s->depth.depth_unit = s->is_float ? 0.0f : s->unit;
	s->depth.timestamp_ns = t_ns;
	s->depth.sequence = (uint64_t)i + 1;
	return 0;
}

/* The colour frame nearest in time to the depth frame just decoded, into s->color. */
static int decode_color(struct mcap_source *s, struct dao_error *err)
{
	const uint32_t ct = (uint32_t)s->color_topic;
	const uint64_t t = s->depth.timestamp_ns;
	const char *path = dao_mcap_path(s->m), *topic = dao_mcap_topic(s->m, ct)->name;
	uint32_t lo = 0, hi = s->color_count;
	while (lo < hi) { /* the first colour message logged at or after the depth */
		uint32_t mid = lo + (hi - lo) / 2;
		if (dao_mcap_message_time(s->m, ct, mid) < s->depth_log_ns)
			lo = mid + 1;
		else
			hi = mid;
	}
	uint32_t first = lo >= 2 ? lo - 2 : 0;
	uint32_t last = lo + 2 < s->color_count ? lo + 2 : s->color_count;
	uint32_t best = first;
	uint64_t best_d = UINT64_MAX, ts;
	const uint8_t *d;
	uint64_t n;
	struct desc got;
	int r;
	for (uint32_t i = first; i < last || i == first; i++) {
		if ((r = image_message(s, ct, i, &s->color_desc, &got, &ts, &d, &n, err)) < 0)
			return r;
		uint64_t dist = ts > t ? ts - t : t - ts;
		if (dist < best_d) {
			best_d = dist;
			best = i;
		}
	}
	if ((r = image_message(s, ct, best, &s->color_desc, &got, &ts, &d, &n, err)) < 0)
		return r;
	if (got.kind == K_JPEG) {
		struct dao_ros2_compressed_image ci;
		char why[160];
		dao_ros2_compressed_image_parse(d, n, &ci);
		if (dao_jpeg_decode(s->jpeg, ci.data, ci.data_len, &s->color, why, sizeof why) < 0)
			return dao_error_set(err, -EINVAL, "%s: message %u of '%s': %s", path, best,
					     topic, why);
	} else {
		struct dao_ros2_image img;
		dao_ros2_image_parse(d, n, &img);
		uint32_t bpp = dao_ros_color_bytes(img.encoding);
		if (img.step < (uint64_t)img.width * bpp ||
		    (uint64_t)img.step * img.height > img.data_len)
			return dao_error_set(err, -EINVAL,
					     "%s: message %u of '%s': %u bytes of data for %u rows of "
					     "step %u", path, best, topic, img.data_len, img.height,
					     img.step);
		dao_ros_color_to_rgb(&s->color, img.data, img.step, img.encoding);
	}
	s->color.timestamp_ns = ts;
	s->color.sequence = (uint64_t)best + 1;
	return 0;
}

static int mcap_read(void *state, struct dao_source_frame *f, int timeout_ms,
		     struct dao_error *err)
{
	struct mcap_source *s = state;
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

static int mcap_seek(void *state, uint64_t index, struct dao_error *err)
{
	struct mcap_source *s = state;
	if (index >= s->count)
		return dao_error_set(err, -EINVAL, "seek to frame %llu: the topic has %u frames",
				     (unsigned long long)index, s->count);
	dao_playback_seek(&s->play, index);
	return 0;
}

static void mcap_close(void *state)
{
	free_source(state);
}

static const struct dao_source_ops mcap_source_ops = {
	.version = DAO_SOURCE_OPS_VERSION,
	.probe = mcap_probe,
	.open = mcap_open,
	.get_info = mcap_get_info,
	.start = mcap_start,
	.read = mcap_read,
	.seek = mcap_seek,
	.close = mcap_close,
};

const struct dao_plugin dao_builtin_mcap_plugin = {
	DAO_PLUGIN_HEADER,
	.name = "mcap",
	.description = "MCAP files (ROS 2 bags; chunks none/zstd/lz4), CDR messages: depth "
		       "Image 16UC1, mono16, 32FC1 and compressedDepth (PNG, RVL), colour rgb8, "
		       "bgr8, rgba8, bgra8, mono8, JPEG; FILE.mcap[?topic=T][&unit=M][&color=C]; "
		       "records the AO (Image mono16, rgb8, CameraInfo, PointCloud2) as a sink",
	.source = &mcap_source_ops,
	.sink = &dao_mcap_sink_ops,
};
