/* SPDX-License-Identifier: MIT */
/*
 * The capture thread: opens the source (again after failures, with a backoff)
 * and queues its frames for the processing thread.
 */

#include <errno.h>
#include <string.h>
#include <strings.h>

#include "daemon_internal.h"

/*
 * 1 if the source URI names something on disk (a recording, a depth PNG, a
 * directory of them) rather than a device: "oni:", "bag:" and "images:" URIs, any
 * URI whose path ends in .oni, .bag or .png, and paths outside /dev without a plugin
 * prefix.  Such a source must open at start; a device may be plugged in later.
 */
static int source_names_file(const char *uri)
{
	size_t p = dao_uri_prefix_len(uri); /* as the plugin registry reads a prefix */
	int prefixed = p > 0;
	if (prefixed && ((p == 3 && (!strncmp(uri, "oni", 3) || !strncmp(uri, "bag", 3))) ||
			 (p == 6 && !strncmp(uri, "images", 6))))
		return 1;
	const char *rest = prefixed ? uri + p + 1 : uri;
	size_t n = dao_uri_path_len(rest, NULL);
	if (n > 4 && (!strncasecmp(rest + n - 4, ".oni", 4) || !strncasecmp(rest + n - 4, ".bag", 4) ||
		      !strncasecmp(rest + n - 4, ".png", 4)))
		return 1;
	return !prefixed && memchr(rest, '/', n) && strncmp(rest, "/dev/", 5) != 0;
}

/*
 * An overlay sink needs colour that can be laid over the depth: a depth-only
 * source, or colour of another aspect ratio, is an error at start (never an
 * overlay sink that silently gets nothing).
 */
static int overlay_refused(struct daemon *d, const struct dao_source_info *in)
{
	struct dao_error err = {0};
	if (!in->has_color) {
		log_error("source %s delivers depth only (%s), but a sink asks for the overlay "
			  "stream (AO over colour): use a source with colour (an .oni or bag "
			  "recording with a colour stream, openni2:any) or another stream for that "
			  "sink%s%s", d->cfg.source_uri, in->description, in->warning[0] ? "; " : "",
			  in->warning);
		return 1;
	}
	if (dao_overlay_check(in->color_width, in->color_height, in->width, in->height, &err) < 0) {
		log_error("source %s: %s", d->cfg.source_uri, err.message);
		return 1;
	}
	if (!in->registered)
		log_warn("source %s: the depth is not registered to the colour camera (or the "
			 "source cannot tell): the overlay is offset by the parallax between the "
			 "two cameras", d->cfg.source_uri);
	return 0;
}

/* The source opened and started; NULL after a failure (waited out, or fatal: d->failed). */
static struct dao_source *open_source(struct daemon *d, unsigned *backoff, int first)
{
	struct dao_source_options so = {
		.size = sizeof(struct dao_source_options),
		.playback = d->cfg.playback,
		.loop = d->cfg.loop,
		.start_frame = d->cfg.start,
		.want_color = d->wants[STREAM_OVERLAY] || d->wants_color,
		.depth_unit = d->cfg.depth_unit,
	};
	struct dao_source *src = NULL;
	struct dao_error err = {0};
	atomic_store(&d->source_call_ns, tool_mono_ns());
	int r = dao_source_open_limited(d->plugins, d->cfg.source_uri, &so, d->cfg.max_pixels, &src,
					&err);
	if (r == 0 && (r = dao_source_start(src, &err)) < 0) {
		dao_source_close(src);
		src = NULL;
	}
	atomic_store(&d->source_call_ns, 0);
	if (r < 0 && first && source_names_file(d->cfg.source_uri)) {
		log_error("source %s: %s; a recording or image path must be there when depthaod "
			  "starts and open (only devices are waited for and retried): check [source] "
			  "uri and start depthaod again", d->cfg.source_uri,
			  err.message[0] ? err.message : strerror(-r));
		atomic_store(&d->failed, 1);
		return NULL;
	}
	if (r < 0) {
		atomic_fetch_add(&d->source_failures, 1);
		log_limited(&d->source_log, LOG_WARN, "source %s: %s; retrying in %u ms",
			    d->cfg.source_uri, err.message[0] ? err.message : strerror(-r), *backoff);
		nap(d, *backoff);
		*backoff = *backoff * 2 > d->cfg.retry_max_ms ? d->cfg.retry_max_ms : *backoff * 2;
		return NULL;
	}
	*backoff = d->cfg.retry_initial_ms;
	struct dao_source_info in;
	dao_source_get_info(src, &in);
	if (d->wants[STREAM_OVERLAY] && overlay_refused(d, &in)) {
		dao_source_close(src);
		atomic_store(&d->failed, 1);
		return NULL;
	}
	pthread_mutex_lock(&d->lock);
	d->src_info = in;
	d->have_src_info = 1;
	pthread_mutex_unlock(&d->lock);
	atomic_fetch_add(&d->source_opens, 1);
	log_info("source: %s", in.description);
	if (in.warning[0])
		log_warn("source: %s", in.warning);
	return src;
}

/*
 * The source's camera pose for frame f into it, when depth-temporal-motion takes poses
 * (source, source+icp): 1 with a pose, else 0 (a gap counted and warned, rate-limited;
 * a source without poses said once, and not asked again until it is reopened).
 */
static int capture_pose(struct daemon *d, struct dao_source *src, const struct dao_source_frame *f,
			struct fq_item *it)
{
	pthread_mutex_lock(&d->lock);
	const enum dao_depth_motion m = d->params.depth_temporal_motion;
	pthread_mutex_unlock(&d->lock);
	if (d->poses_off || (m != DAO_DEPTH_MOTION_SOURCE && m != DAO_DEPTH_MOTION_SOURCE_ICP))
		return 0;
	struct dao_source_pose pose = DAO_SOURCE_POSE_INIT;
	struct dao_error err = {0};
	int r = dao_source_frame_pose(src, f, &pose, &err);
	if (r == -ENOENT) {
		log_limited(&d->source_log, LOG_WARN, "source %s: frame %llu has no camera pose "
			    "(%llu so far; filtered without motion): %s", d->cfg.source_uri,
			    (unsigned long long)f->index, (unsigned long long)++d->pose_gaps,
			    err.message);
		return 0;
	}
	if (r < 0) {
		log_warn("source %s: depth-temporal-motion %s takes the camera's poses from the "
			 "source, and it has none: %s; the motion falls back as without poses "
			 "(icp estimates it from the depth)", d->cfg.source_uri,
			 m == DAO_DEPTH_MOTION_SOURCE ? "source" : "source+icp", err.message);
		d->poses_off = 1;
		return 0;
	}
	if (pose.warning[0])
		log_warn("source %s: %s", d->cfg.source_uri, pose.warning);
	memcpy(it->pose_q, pose.rotation, sizeof it->pose_q);
	memcpy(it->pose_t, pose.translation, sizeof it->pose_t);
	return 1;
}

void *capture_main(void *arg)
{
	struct daemon *d = arg;
	struct dao_source *src = NULL;
	unsigned backoff = d->cfg.retry_initial_ms;
	int live = 0, opened = 0;
	int64_t frame_count = 0, bad_in_a_row = 0;
	while (!atomic_load(&d->stop) && !atomic_load(&d->end_capture)) {
		if (!src) {
			if (!(src = open_source(d, &backoff, !opened))) {
				if (atomic_load(&d->failed))
					break;
				continue;
			}
			opened = 1;
			d->poses_off = 0;
			live = d->src_info.live;
			frame_count = d->src_info.frame_count;
			bad_in_a_row = 0;
		}
		if (atomic_load(&d->paused) && !live) {
			nap(d, 50); /* a paused recording simply waits */
			continue;
		}
		struct dao_source_frame f;
		struct dao_error err = {0};
		atomic_store(&d->source_call_ns, tool_mono_ns());
		int r = dao_source_read(src, &f, READ_TIMEOUT_MS, &err);
		atomic_store(&d->source_call_ns, 0);
		if (r == -EAGAIN)
			continue;
		if (r == DAO_SOURCE_EOS) {
			log_info("source %s: end of the recording", d->cfg.source_uri);
			break;
		}
		const char *why = err.message[0] ? err.message : strerror(-r);
		if (r < 0 && !live && r != -ENODEV &&
		    ++bad_in_a_row <= (frame_count > 0 ? frame_count : 1)) {
			/* a recording's frame that cannot be decoded: the source skips it */
			atomic_fetch_add(&d->source_bad_frames, 1);
			log_limited(&d->source_log, LOG_WARN, "source %s: a frame cannot be read and is "
				    "skipped: %s", d->cfg.source_uri, why);
			continue;
		}
		if (r < 0) {
			if (!live && r != -ENODEV)
				log_limited(&d->source_log, LOG_WARN, "source %s: no frame can be read "
					    "(%lld failures in a row, the last: %s); reopening",
					    d->cfg.source_uri, (long long)bad_in_a_row, why);
			else
				log_limited(&d->source_log, LOG_WARN, "source %s lost: %s; reopening",
					    d->cfg.source_uri, why);
			atomic_store(&d->source_call_ns, tool_mono_ns());
			dao_source_close(src);
			atomic_store(&d->source_call_ns, 0);
			src = NULL;
			continue;
		}
		bad_in_a_row = 0;
		if (atomic_load(&d->paused)) { /* live: keep the device flowing, drop */
			dao_source_release(src, &f);
			continue;
		}
		atomic_fetch_add(&d->captured, 1);
		uint64_t dropped = 0;
		struct fq_item *it = fq_begin_push(d->input, !d->lossless, &dropped);
		atomic_fetch_add(&d->input_dropped, dropped);
		if (!it) {
			dao_source_release(src, &f);
			break;
		}
		int ok = fq_frame_copy(&it->frame, &f.depth) == 0;
		if (ok && f.color.format == DAO_PIXFMT_RGB24)
			ok = fq_frame_copy(&it->color, &f.color) == 0;
		else
			it->color.format = DAO_PIXFMT_NONE;
		it->index = f.index;
		it->has_pose = ok && capture_pose(d, src, &f, it);
		it->t_capture_ns = tool_mono_ns();
		dao_source_release(src, &f);
		if (ok)
			fq_end_push(d->input, it);
		else
			fq_cancel_push(d->input, it);
	}
	dao_source_close(src);
	log_limit_flush(&d->source_log, LOG_WARN, "source");
	fq_close(d->input);
	atomic_store(&d->capture_done, 1);
	return NULL;
}
