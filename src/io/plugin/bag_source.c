/* SPDX-License-Identifier: MIT */
/*
 * Built-in source "bag": depth images from a ROS 1 bag (format 2.0) through
 * depthao's own reader (bag/bag_reader.c).  URI:
 * FILE.bag[?topic=T][&unit=M][&color=C][&pose_frame=F][&pose_topic=O][&pose_gap=S]
 * (the options in any order).
 *
 * The depth topic is a sensor_msgs/Image topic whose encoding is 16UC1 or
 * mono16 (counts of `unit` metres: ?unit=, else the RealSense option topic
 * below, else the caller's depth_unit, else 0.001) or 32FC1 (metres; NaN
 * and 0 are no data).  With one such topic it is taken; with several,
 * ?topic= chooses (the error lists them).  The intrinsics come from the
 * first sensor_msgs/CameraInfo of the topic's namespace: ".../camera_info"
 * beside ".../image_raw", or for a RealSense recording (realsense-viewer,
 * rs-record) "/device_0/sensor_N/Depth_0/info/camera_info" beside
 * "/device_0/sensor_N/Depth_0/image/data", whose unit is the std_msgs/
 * Float32 "/device_0/sensor_N/option/Depth Units/value".  A CameraInfo for
 * another image size is ignored with a warning; one with implausible numbers
 * (dao_camera_from_intrinsics' rule) is an error.
 *
 * Colour (want_color): a sensor_msgs/Image topic in rgb8, bgr8, rgba8, bgra8
 * or mono8 (?color= chooses; one such topic is taken, e.g. a RealSense
 * ".../Color_0/image/data"), delivered as RGB24 with each depth frame: the
 * colour message whose header stamp is nearest to the depth's (the earlier
 * one on a tie), found among the messages recorded around the depth
 * message, as ROS's approximate-time pairing of the two topics would.
 * Depth on an "aligned_depth_to_color" or "depth_registered" topic counts
 * as registered to the colour camera; other depth may not be.
 *
 * A bag without an index (a recording that was not finished) is read up
 * to its last complete chunk, with the reader's warning (info.warning).
 * Frames are the topic's messages in time order; a frame's time is its
 * header stamp, or the time it was recorded when the stamp is 0; real-time
 * playback waits for it (relative to the first frame delivered).
 *
 * Camera poses (frame_pose): the depth frame's header.frame_id in the tf or
 * odometry of the bag at the frame's time (source_poses.h, pose_feeds.h).
 */
#include <depthao/camera.h>
#include <depthao/plugin.h>

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>

#include "bag/bag_reader.h"
#include "bag/ros_msg.h"
#include "core/error_internal.h"
#include "plugin/builtin.h"
#include "plugin/playback.h"
#include "plugin/pose_feeds.h"
#include "plugin/ros_image.h"
#include "plugin/source_poses.h"


struct bag_source {
	struct dao_bag *bag;
	uint32_t topic;
	uint32_t count;
	struct dao_source_options opts;
	struct dao_source_info info;
	char encoding[32];
	int is_float;
	float unit;
	struct dao_frame depth;
	uint64_t depth_rec_ns;      /* when the depth frame was recorded */
	int color_topic;            /* -1: no colour delivered */
	uint32_t color_count;
	char color_encoding[32];
	struct dao_frame color;
	struct dao_playback_cursor play;
	struct dao_source_poses *poses;
	char frame_id[DAO_TF_NAME_MAX + 1]; /* the depth frame's header.frame_id */
	uint32_t frame_id_len;              /* > DAO_TF_NAME_MAX: too long to keep */
};

static int has_bag_suffix(const char *s, size_t n)
{
	return n > 4 && !strncasecmp(s + n - 4, ".bag", 4);
}

static int bag_probe(const char *uri)
{
	return has_bag_suffix(uri, dao_uri_path_len(uri, dao_ros_uri_options)) ? 60 : 0;
}

static int is_image_topic(const struct dao_bag_topic *t)
{
	return !strcmp(t->type, "sensor_msgs/Image") && t->message_count > 0;
}

/* The first message of an image topic, parsed; -EINVAL with a message if it is not one. */
static int first_image(struct dao_bag *bag, uint32_t t, struct dao_ros_image *img,
		       struct dao_error *err)
{
	const uint8_t *d;
	uint32_t n;
	int r = dao_bag_read_message(bag, t, 0, &d, &n, NULL, err);
	if (r < 0)
		return r;
	if (dao_ros_image_parse(d, n, img) < 0)
		return dao_error_set(err, -EINVAL, "%s: the first message of '%s' is not a "
				     "sensor_msgs/Image", dao_bag_path(bag),
				     dao_bag_topic(bag, t)->name);
	return 0;
}

static int pick_topic(struct bag_source *s, const struct dao_ros_uri *u,
		      struct dao_ros_image *img, struct dao_error *err)
{
	struct dao_bag *bag = s->bag;
	const char *path = dao_bag_path(bag);
	char depth[400] = "", other[400] = "";
	int found = -1, ndepth = 0, r;
	if (u->topic[0]) {
		int t = dao_bag_find_topic(bag, u->topic);
		if (t < 0 || !is_image_topic(dao_bag_topic(bag, (uint32_t)t)))
			goto list;
		if ((r = first_image(bag, (uint32_t)t, img, err)) < 0)
			return r;
		if (!dao_ros_depth_kind(img->encoding))
			return dao_error_set(err, -EINVAL,
					     "%s: topic '%s' has images of encoding '%s', not depth "
					     "(16UC1, mono16 or 32FC1)", path, u->topic, img->encoding);
		s->topic = (uint32_t)t;
		return 0;
	}
list:
	for (uint32_t t = 0; t < dao_bag_topic_count(bag); t++) {
		const struct dao_bag_topic *tp = dao_bag_topic(bag, t);
		if (!is_image_topic(tp))
			continue;
		struct dao_ros_image im;
		if ((r = first_image(bag, t, &im, err)) < 0)
			return r;
		if (dao_ros_depth_kind(im.encoding)) {
			dao_ros_topic_list_add(depth, sizeof(depth), tp->name, im.encoding);
			if (ndepth++ == 0) {
				found = (int)t;
				*img = im;
			}
		} else {
			dao_ros_topic_list_add(other, sizeof(other), tp->name, im.encoding);
		}
	}
	if (u->topic[0])
		return dao_error_set(err, -ENOENT,
				     "%s: no image topic '%s'; depth topics: %s", path, u->topic,
				     ndepth ? depth : "none");
	if (ndepth == 0)
		return dao_error_set(err, -EINVAL,
				     "%s: no depth image topic (sensor_msgs/Image in 16UC1, mono16 or "
				     "32FC1); image topics: %s", path, other[0] ? other : "none");
	if (ndepth > 1)
		return dao_error_set(err, -EINVAL,
				     "%s: %d depth topics, choose one with ?topic=NAME: %s", path,
				     ndepth, depth);
	s->topic = (uint32_t)found;
	return 0;
}

/* "/device_0/sensor_1/Depth_0/image/data" -> its prefix length up to "/Depth_0", or 0. */
static size_t realsense_stream_prefix(const char *topic)
{
	size_t n = strlen(topic);
	static const char tail[] = "/image/data";
	if (strncmp(topic, "/device_", 8) || n <= sizeof(tail) - 1 ||
	    strcmp(topic + n - (sizeof(tail) - 1), tail))
		return 0;
	return n - (sizeof(tail) - 1);
}

static int first_message(struct dao_bag *bag, const char *topic, const char *type,
			 const uint8_t **d, uint32_t *n, struct dao_error *err)
{
	int t = dao_bag_find_topic(bag, topic);
	if (t < 0 || strcmp(dao_bag_topic(bag, (uint32_t)t)->type, type) ||
	    dao_bag_topic(bag, (uint32_t)t)->message_count == 0)
		return 1; /* not there */
	return dao_bag_read_message(bag, (uint32_t)t, 0, d, n, NULL, err);
}

/* Intrinsics from the CameraInfo beside the depth topic, if there is one; the unit. */
static int find_camera(struct bag_source *s, const struct dao_ros_uri *u,
		       struct dao_error *err)
{
	const char *topic = dao_bag_topic(s->bag, s->topic)->name;
	const char *path = dao_bag_path(s->bag);
	char name[600];
	const uint8_t *d;
	uint32_t n;
	int r;
	size_t rs = realsense_stream_prefix(topic);
	if (rs) {
		snprintf(name, sizeof(name), "%.*s/info/camera_info", (int)rs, topic);
	} else {
		const char *slash = strrchr(topic, '/');
		snprintf(name, sizeof(name), "%.*s/camera_info", (int)(slash ? slash - topic : 0),
			 topic);
	}
	if ((r = first_message(s->bag, name, "sensor_msgs/CameraInfo", &d, &n, err)) < 0)
		return r;
	if (r == 0) {
		struct dao_ros_camera_info ci;
		if (dao_ros_camera_info_parse(d, n, &ci) < 0)
			return dao_error_set(err, -EINVAL, "%s: the first message of '%s' is not a "
					     "sensor_msgs/CameraInfo", path, name);
		uint32_t nd = ci.distortion_count < DAO_ROS_MAX_DISTORTION ? ci.distortion_count
									   : DAO_ROS_MAX_DISTORTION;
		r = dao_ros_camera_info_intrinsics(&s->info, path, name, ci.width, ci.height, ci.k,
						   ci.p, ci.d, nd, err);
		if (r < 0)
			return r;
	}
	s->unit = u->unit;
	if (rs && !s->unit) {
		/* "/device_0/sensor_1" of ".../sensor_1/Depth_0" */
		const char *cut = topic + rs;
		while (cut > topic && cut[-1] != '/')
			cut--;
		snprintf(name, sizeof(name), "%.*s/option/Depth Units/value",
			 (int)(cut > topic ? cut - topic - 1 : 0), topic);
		if ((r = first_message(s->bag, name, "std_msgs/Float32", &d, &n, err)) < 0)
			return r;
		float v;
		if (r == 0 && (dao_ros_float32_parse(d, n, &v) < 0 || !(v > 0 && v <= 1)))
			return dao_error_set(err, -EINVAL, "%s: '%s' is not a unit in (0, 1] metres",
					     path, name);
		if (r == 0)
			s->unit = v;
	}
	if (!s->unit)
		s->unit = s->opts.depth_unit > 0 ? s->opts.depth_unit : 0.001f;
	return 0;
}

/* The colour topic: ?color=, else the one image topic in a colour encoding. */
static int pick_color(struct bag_source *s, const struct dao_ros_uri *u, uint64_t max_pixels,
		      struct dao_error *err)
{
	struct dao_bag *bag = s->bag;
	const char *path = dao_bag_path(bag);
	char list[400] = "";
	struct dao_ros_image img, im;
	int found = -1, n = 0, r;
	for (uint32_t t = 0; t < dao_bag_topic_count(bag); t++) {
		const struct dao_bag_topic *tp = dao_bag_topic(bag, t);
		if (!is_image_topic(tp) || (t == s->topic && !u->color[0]))
			continue;
		if (u->color[0] && strcmp(tp->name, u->color))
			continue;
		if ((r = first_image(bag, t, &im, err)) < 0)
			return r;
		if (u->color[0] && !dao_ros_color_bytes(im.encoding))
			return dao_error_set(err, -EINVAL,
					     "%s: topic '%s' has images of encoding '%s', not colour "
					     "(rgb8, bgr8, rgba8, bgra8 or mono8)", path, u->color,
					     im.encoding);
		if (!dao_ros_color_bytes(im.encoding))
			continue;
		dao_ros_topic_list_add(list, sizeof(list), tp->name, im.encoding);
		if (n++ == 0) {
			found = (int)t;
			img = im;
		}
	}
	if (u->color[0] && n == 0)
		return dao_error_set(err, -ENOENT, "%s: no image topic '%s' (color=)", path, u->color);
	if (n == 0) {
		snprintf(s->info.warning, sizeof(s->info.warning),
			 "no colour: the bag has no image topic in rgb8, bgr8, rgba8, bgra8 or mono8");
		return 0;
	}
	if (n > 1)
		return dao_error_set(err, -EINVAL,
				     "%s: %d colour topics, choose one with ?color=NAME: %s", path, n,
				     list);
	if ((uint64_t)img.width * img.height > max_pixels || !img.width || !img.height)
		return dao_error_set(err, img.width && img.height ? -EFBIG : -EINVAL,
				     "%s: colour topic '%s' has %ux%u images; the limit is %llu pixels",
				     path, dao_bag_topic(bag, (uint32_t)found)->name, img.width,
				     img.height, (unsigned long long)max_pixels);
	if ((r = dao_frame_alloc(&s->color, DAO_PIXFMT_RGB24, img.width, img.height, err)) < 0)
		return r;
	s->color_topic = found;
	s->color_count = dao_bag_topic(bag, (uint32_t)found)->message_count;
	snprintf(s->color_encoding, sizeof(s->color_encoding), "%s", img.encoding);
	s->info.has_color = 1;
	s->info.color_width = img.width;
	s->info.color_height = img.height;
	return 0;
}

int dao_bag_source_open(const char *uri, const struct dao_source_options *opts,
			uint64_t max_pixels, void **state, struct dao_error *err)
{
	struct bag_source *s = calloc(1, sizeof(*s));
	struct dao_ros_uri u = {0};
	struct dao_ros_image img;
	int r;
	if (!s)
		return dao_error_set(err, -ENOMEM, "out of memory");
	s->opts = *opts;
	if (!(opts->depth_unit >= 0 && opts->depth_unit <= 1)) {
		r = dao_error_set(err, -EINVAL, "bag: depth unit %g is not in (0, 1] metres",
				  (double)opts->depth_unit);
		goto fail;
	}
	if ((r = dao_ros_uri_parse(uri, "bag", &u, err)) < 0 ||
	    (r = dao_source_poses_create(&s->poses, &u, err)) < 0)
		goto fail;
	/* a chunk holds at least one image (up to 4 bytes a pixel), maybe colour beside it */
	if ((r = dao_bag_open(u.path, 8 * max_pixels + (16u << 20), &s->bag, err)) < 0)
		goto fail;
	if ((r = pick_topic(s, &u, &img, err)) < 0)
		goto fail;
	const struct dao_bag_topic *tp = dao_bag_topic(s->bag, s->topic);
	s->count = tp->message_count;
	if ((uint64_t)img.width * img.height > max_pixels || !img.width || !img.height) {
		r = dao_error_set(err, img.width && img.height ? -EFBIG : -EINVAL,
				  "%s: topic '%s' has %ux%u images; the limit is %llu pixels", u.path,
				  tp->name, img.width, img.height, (unsigned long long)max_pixels);
		goto fail;
	}
	snprintf(s->encoding, sizeof(s->encoding), "%s", img.encoding);
	s->is_float = dao_ros_depth_kind(img.encoding) == 2;
	s->info.width = img.width;
	s->info.height = img.height;
	if ((r = find_camera(s, &u, err)) < 0)
		goto fail;
	s->color_topic = -1;
	if (opts->want_color && (r = pick_color(s, &u, max_pixels, err)) < 0)
		goto fail;
	s->info.registered = strstr(tp->name, "aligned_depth_to_color") != NULL ||
			     strstr(tp->name, "depth_registered") != NULL;
	if (dao_bag_warning(s->bag)) /* an unfinished recording, read as far as it goes */
		snprintf(s->info.warning, sizeof(s->info.warning), "%s", dao_bag_warning(s->bag));
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
	if (s->color_topic >= 0)
		snprintf(s->info.description, sizeof(s->info.description),
			 "%.30s: %.40s %ux%u %.8s + %.40s %ux%u %.6s, %u frames",
			 base ? base + 1 : u.path, tp->name, img.width, img.height, img.encoding,
			 dao_bag_topic(s->bag, (uint32_t)s->color_topic)->name, s->info.color_width,
			 s->info.color_height, s->color_encoding, s->count);
	else
		snprintf(s->info.description, sizeof(s->info.description),
			 "%.40s: %.50s %ux%u %.12s, %u frames", base ? base + 1 : u.path, tp->name,
			 img.width, img.height, img.encoding, s->count);
	if ((r = dao_frame_alloc(&s->depth, s->info.format, img.width, img.height, err)) < 0)
		goto fail;
	dao_playback_init(&s->play, opts, s->count);
	dao_ros_uri_free(&u);
	*state = s;
	return 0;
fail:
	dao_ros_uri_free(&u);
	dao_source_poses_free(s->poses);
	dao_frame_free(&s->depth);
	dao_frame_free(&s->color);
	dao_bag_close(s->bag);
	free(s);
	return r;
}

static int bag_open(const char *uri, const struct dao_source_options *opts, void **state,
		    struct dao_error *err)
{
	return dao_bag_source_open(uri, opts, DAO_DEFAULT_MAX_PIXELS, state, err);
}

static void bag_get_info(void *state, struct dao_source_info *in)
{
	struct bag_source *s = state;
	*in = s->info;
}

static int bag_start(void *state, struct dao_error *err)
{
	struct bag_source *s = state;
	(void)err;
	dao_playback_restart(&s->play);
	return 0;
}

/* Decodes message `i` into s->depth. */
static int decode(struct bag_source *s, uint32_t i, struct dao_error *err)
{
	const char *path = dao_bag_path(s->bag), *topic = dao_bag_topic(s->bag, s->topic)->name;
	const uint8_t *d;
	uint32_t n;
	uint64_t rec_ns;
	struct dao_ros_image img;
	int r = dao_bag_read_message(s->bag, s->topic, i, &d, &n, &rec_ns, err);
	if (r < 0)
		return r;
	if (dao_ros_image_parse(d, n, &img) < 0)
		return dao_error_set(err, -EINVAL, "%s: message %u of '%s' is not a sensor_msgs/Image",
				     path, i, topic);
	if (img.width != s->info.width || img.height != s->info.height ||
	    strcmp(img.encoding, s->encoding))
		return dao_error_set(err, -EINVAL,
				     "%s: message %u of '%s' is %ux%u %s, the topic began with %ux%u "
				     "%s", path, i, topic, img.width, img.height, img.encoding,
				     s->info.width, s->info.height, s->encoding);
	uint32_t bpp = s->is_float ? 4 : 2;
	if (img.step < (uint64_t)img.width * bpp ||
	    (uint64_t)img.step * img.height > img.data_len)
		return dao_error_set(err, -EINVAL,
				     "%s: message %u of '%s': %u bytes of data for %u rows of step %u "
				     "(%ux%u, %u bytes a pixel)", path, i, topic, img.data_len,
				     img.height, img.step, img.width, img.height, bpp);
	dao_ros_copy_depth(&s->depth, img.data, img.step, bpp,
			   !!img.is_bigendian != dao_ros_host_is_big_endian());
	s->depth.depth_unit = s->is_float ? 0.0f : s->unit;
	s->depth.timestamp_ns = img.header.stamp_ns ? img.header.stamp_ns : rec_ns;
	s->depth.sequence = (uint64_t)i + 1;
	s->depth_rec_ns = rec_ns;
	dao_ros_keep_frame_id(s->frame_id, &s->frame_id_len, img.header.frame_id,
			      img.header.frame_id_len);
	return 0;
}

/* Colour message i: parsed, checked against the topic's first; its time in *t_ns. */
static int color_message(struct bag_source *s, uint32_t i, struct dao_ros_image *img,
			 uint64_t *t_ns, struct dao_error *err)
{
	const char *path = dao_bag_path(s->bag);
	const char *topic = dao_bag_topic(s->bag, (uint32_t)s->color_topic)->name;
	const uint8_t *d;
	uint32_t n;
	uint64_t rec_ns;
	int r = dao_bag_read_message(s->bag, (uint32_t)s->color_topic, i, &d, &n, &rec_ns, err);
	if (r < 0)
		return r;
	if (dao_ros_image_parse(d, n, img) < 0)
		return dao_error_set(err, -EINVAL, "%s: message %u of '%s' is not a sensor_msgs/Image",
				     path, i, topic);
	uint32_t bpp = dao_ros_color_bytes(img->encoding);
	if (img->width != s->color.width || img->height != s->color.height ||
	    strcmp(img->encoding, s->color_encoding))
		return dao_error_set(err, -EINVAL,
				     "%s: message %u of '%s' is %ux%u %s, the topic began with %ux%u "
				     "%s", path, i, topic, img->width, img->height, img->encoding,
				     s->color.width, s->color.height, s->color_encoding);
	if (img->step < (uint64_t)img->width * bpp ||
	    (uint64_t)img->step * img->height > img->data_len)
		return dao_error_set(err, -EINVAL,
				     "%s: message %u of '%s': %u bytes of data for %u rows of step %u",
				     path, i, topic, img->data_len, img->height, img->step);
	*t_ns = img->header.stamp_ns ? img->header.stamp_ns : rec_ns;
	return 0;
}

/*
 * The colour frame for the depth frame just decoded: of the colour messages
 * recorded around it (two before, two after, by the index), the one whose
 * time is nearest to the depth's, converted into s->color.
 */
static int decode_color(struct bag_source *s, struct dao_error *err)
{
	const uint64_t t = s->depth.timestamp_ns;
	uint32_t lo = 0, hi = s->color_count;
	while (lo < hi) { /* the first colour message recorded at or after the depth */
		uint32_t mid = lo + (hi - lo) / 2;
		if (dao_bag_message_time(s->bag, (uint32_t)s->color_topic, mid) < s->depth_rec_ns)
			lo = mid + 1;
		else
			hi = mid;
	}
	uint32_t first = lo >= 2 ? lo - 2 : 0, last = lo + 2 < s->color_count ? lo + 2 : s->color_count;
	uint32_t best = first;
	uint64_t best_d = UINT64_MAX;
	struct dao_ros_image img;
	int r;
	for (uint32_t i = first; i < last || i == first; i++) {
		uint64_t ct;
		if ((r = color_message(s, i, &img, &ct, err)) < 0)
			return r;
		uint64_t d = ct > t ? ct - t : t - ct;
		if (d < best_d) {
			best_d = d;
			best = i;
		}
	}
	uint64_t ct;
	if ((r = color_message(s, best, &img, &ct, err)) < 0)
		return r;
	dao_ros_color_to_rgb(&s->color, img.data, img.step, img.encoding);
	s->color.timestamp_ns = ct;
	s->color.sequence = (uint64_t)best + 1;
	return 0;
}

static int bag_read(void *state, struct dao_source_frame *f, int timeout_ms, struct dao_error *err)
{
	struct bag_source *s = state;
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
		if ((r = decode_color(s, err)) < 0) /* skipped like a corrupt depth frame */
			return dao_playback_skip(&s->play, r, err);
		f->color = s->color;
	}
	f->depth = s->depth;
	f->index = dao_playback_advance(&s->play);
	return 0;
}

static int bag_seek(void *state, uint64_t index, struct dao_error *err)
{
	struct bag_source *s = state;
	if (index >= s->count)
		return dao_error_set(err, -EINVAL, "seek to frame %llu: the topic has %u frames",
				     (unsigned long long)index, s->count);
	dao_playback_seek(&s->play, index);
	return 0;
}

static int bag_frame_pose(void *state, const struct dao_source_frame *f,
			  struct dao_source_pose *pose, struct dao_error *err)
{
	struct bag_source *s = state;
	struct dao_pose_feed feed;
	dao_bag_pose_feed(s->bag, &feed);
	return dao_source_poses_get(s->poses, &feed, s->frame_id, s->frame_id_len,
				    f->depth.timestamp_ns, pose, err);
}

static void bag_close(void *state)
{
	struct bag_source *s = state;
	dao_source_poses_free(s->poses);
	dao_frame_free(&s->depth);
	dao_frame_free(&s->color);
	dao_bag_close(s->bag);
	free(s);
}

static const struct dao_source_ops bag_source_ops = {
	.version = DAO_SOURCE_OPS_VERSION,
	.probe = bag_probe,
	.open = bag_open,
	.get_info = bag_get_info,
	.start = bag_start,
	.read = bag_read,
	.seek = bag_seek,
	.close = bag_close,
	.frame_pose = bag_frame_pose,
};

const struct dao_plugin dao_builtin_bag_plugin = {
	DAO_PLUGIN_HEADER,
	.name = "bag",
	.description = "ROS 1 bags (format 2.0, chunks none/bz2/lz4) and RealSense .bag "
		       "recordings: depth images 16UC1, mono16, 32FC1, colour rgb8, bgr8, rgba8, "
		       "bgra8, mono8; camera poses from tf, odometry or an IMU; "
		       "FILE.bag[?topic=T][&unit=M][&color=C][&pose_frame=F][&pose_topic=O]",
	.source = &bag_source_ops,
};
