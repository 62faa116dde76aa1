/* SPDX-License-Identifier: MIT */
/*
 * The processing thread: AO and shading of each captured frame, fanned out to
 * every sink's queue; it pings the systemd watchdog.
 */

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include <depthao/uri.h>

#include "common/camera_file.h"

#include "notify.h"
#include "daemon_internal.h"

/* err's message with what it is about before it ("[source] intrinsics: ..."). */
static int camera_error(struct dao_error *err, int r, const char *what)
{
	char m[sizeof err->message + 64];
	snprintf(m, sizeof m, "%s: %s", what, err->message);
	const size_t n = strnlen(m, sizeof err->message - 1);
	memcpy(err->message, m, n);
	err->message[n] = '\0';
	err->code = r;
	return r;
}

/* The camera file beside a PNG source (camera_file_beside, as depthao process
 * finds it).  1 and *cam; 0: none there; < 0 with err: one there that cannot
 * be used. */
static int camera_beside(const char *uri, uint32_t w, uint32_t h, struct dao_camera *cam,
			 struct dao_error *err)
{
	const size_t pre = dao_uri_prefix_len(uri);
	char file[4096 + 16], msg[512];
	const int found = camera_file_beside(uri + (pre ? pre + 1 : 0), file, sizeof file);
	if (found < 0)
		return dao_error_set(err, -errno, "the camera file beside the source, %s, cannot be "
				     "read: %s (make it readable, or give [source] intrinsics_file or "
				     "intrinsics)", file, strerror(errno));
	if (!found)
		return 0;
	if (camera_file_read(file, cam, msg, sizeof msg) != 0)
		return dao_error_set(err, -EINVAL, "%s ([source] intrinsics_file or intrinsics "
				     "overrides it)", msg);
	if (cam->width != w || cam->height != h)
		return dao_error_set(err, -EINVAL,
				     "the camera file beside the source, %s, is for %ux%u images, "
				     "the source delivers %ux%u ([source] intrinsics_file or "
				     "intrinsics overrides it)",
				     file, cam->width, cam->height, w, h);
	log_info("intrinsics from %s: fx %.2f fy %.2f cx %.2f cy %.2f", file, cam->fx, cam->fy,
		 cam->cx, cam->cy);
	return 1;
}

/* The camera of w x h frames from the config or the source: 0, or negative with err set. */
static int make_camera(struct daemon *d, uint32_t w, uint32_t h, struct dao_camera *cam,
		       struct dao_error *err)
{
	const struct daemon_config *c = &d->cfg;
	int r;
	if (c->has_intrinsics_file) {
		if (w != c->file_width || h != c->file_height)
			return dao_error_set(err, -EINVAL,
					     "[source] intrinsics_file is for %ux%u images, the "
					     "source delivers %ux%u: give the camera file of this "
					     "stream (not '%s')",
					     c->file_width, c->file_height, w, h, c->intrinsics_file);
		return dao_camera_from_intrinsics(cam, w, h, c->file_intrinsics[0],
						  c->file_intrinsics[1], c->file_intrinsics[2],
						  c->file_intrinsics[3], err);
	}
	if (c->has_intrinsics) {
		r = dao_camera_from_intrinsics(cam, w, h, c->intrinsics[0], c->intrinsics[1],
					       c->intrinsics[2], c->intrinsics[3], err);
		return r ? camera_error(err, r, "[source] intrinsics") : 0;
	}
	if (c->has_fov)
		return dao_camera_from_fov(cam, w, h, c->fov_deg[0] * DEG2RAD, c->fov_deg[1] * DEG2RAD,
					   err);
	pthread_mutex_lock(&d->lock);
	struct dao_source_info in = d->src_info;
	pthread_mutex_unlock(&d->lock);
	if (in.has_intrinsics) {
		r = dao_camera_from_intrinsics(cam, w, h, in.fx, in.fy, in.cx, in.cy, err);
		return r ? camera_error(err, r, "the source's intrinsics ([source] intrinsics "
					"overrides them)") : 0;
	}
	if (in.has_fov)
		return dao_camera_from_fov(cam, w, h, in.hfov, in.vfov, err);
	if ((r = camera_beside(c->source_uri, w, h, cam, err)) != 0)
		return r < 0 ? r : 0;
	log_warn("no intrinsics: the source has no field of view and the config gives none; "
		 "assuming %.1f x %.1f degrees ([source] intrinsics or fov)",
		 DEFAULT_HFOV_DEG, DEFAULT_VFOV_DEG);
	return dao_camera_from_fov(cam, w, h, DEFAULT_HFOV_DEG * DEG2RAD, DEFAULT_VFOV_DEG * DEG2RAD,
				   err);
}

struct outputs {
	struct dao_frame ao16, ao8, rgb, overlay;
	struct dao_frame fdepth; /* the filtered depth (DEPTH16), made when a sink wants it */
	int have_fdepth;         /* ... for this frame */
	int have_rgb;            /* the shaded image of this frame (none with algorithm=none) */
	int said_no_shading;     /* algorithm=none with a sink that wants shading: logged */
	/* the camera's pose after this frame (the stats' "motion"), for the sinks: where
	 * it is this frame's (dao_pose_track.current: the pipeline follows the camera,
	 * and the frame is the track's origin or its motion was accepted) */
	int has_pose;
	double pose_q[4], pose_t[3];
};

static void free_outputs(struct outputs *o)
{
	dao_frame_free(&o->ao16);
	dao_frame_free(&o->ao8);
	dao_frame_free(&o->rgb);
	dao_frame_free(&o->overlay);
	dao_frame_free(&o->fdepth);
}

static void ao_to_8bit(const struct dao_frame *a, struct dao_frame *b)
{
	for (uint32_t y = 0; y < a->height; y++) {
		const uint16_t *s = (const uint16_t *)((const uint8_t *)a->data + (size_t)y * (size_t)a->stride);
		uint8_t *t = (uint8_t *)b->data + (size_t)y * (size_t)b->stride;
		for (uint32_t x = 0; x < a->width; x++)
			t[x] = (uint8_t)(((uint32_t)s[x] * 255u + 32767u) / 65535u);
	}
}

static const struct dao_frame *stream_frame(int stream, const struct fq_item *in,
					    const struct outputs *o, int have_overlay)
{
	switch (stream) {
	case STREAM_SHADED: return o->have_rgb ? &o->rgb : NULL;
	case STREAM_AO: return &o->ao16;
	case STREAM_AO8: return &o->ao8;
	case STREAM_DEPTH: return &in->frame;
	case STREAM_OVERLAY: return have_overlay ? &o->overlay : NULL;
	case STREAM_FILTERED_DEPTH: return o->have_fdepth ? &o->fdepth : NULL;
	default: return NULL;
	}
}

/* Queues one stream's frame for a sink. */
static void push_frame(struct daemon *d, struct sink_runner *s, int stream,
		       const struct dao_frame *f, const struct fq_item *in, const struct outputs *o)
{
	uint64_t dropped = 0;
	struct fq_item *it = fq_begin_push(s->q, !d->lossless, &dropped);
	atomic_fetch_add(&s->dropped, dropped);
	if (!it) { /* its queue closed at the stop deadline: this frame never reaches it */
		atomic_fetch_add(&s->dropped, 1);
		return;
	}
	if (fq_item_copy_frame(it, f) < 0) {
		fq_cancel_push(s->q, it);
		return;
	}
	it->frame.sequence = in->index;
	it->frame.timestamp_ns = in->frame.timestamp_ns;
	/* the filtered depth has its own unit (float-metre input: millimetres) */
	it->frame.depth_unit = stream == STREAM_FILTERED_DEPTH ? f->depth_unit
							       : in->frame.depth_unit;
	it->index = in->index;
	it->t_capture_ns = in->t_capture_ns;
	it->stream = stream;
	/* in a sink's queue: the pose the sinks get (outputs), not the source's */
	it->has_pose = o->has_pose;
	memcpy(it->pose_q, o->pose_q, sizeof it->pose_q);
	memcpy(it->pose_t, o->pose_t, sizeof it->pose_t);
	fq_end_push(s->q, it);
}

/* Every sink gets its configured stream, then those it asked for besides. */
static void fan_out(struct daemon *d, const struct fq_item *in, struct outputs *o, int have_overlay)
{
	for (unsigned i = 0; i < d->nsinks; i++) {
		struct sink_runner *s = &d->sinks[i];
		if (atomic_load(&s->state) == SINK_STOPPED)
			continue;
		const int primary = (int)s->cfg->stream;
		const struct dao_frame *f = stream_frame(primary, in, o, have_overlay);
		if (f)
			push_frame(d, s, primary, f, in, o);
		unsigned extra = atomic_load(&s->extra_streams) & ~(1u << primary);
		for (int k = 0; k < STREAM_COUNT; k++)
			if ((extra & (1u << k)) && (f = stream_frame(k, in, o, have_overlay)))
				push_frame(d, s, k, f, in, o);
	}
}

/*
 * The systemd watchdog ping, from the processing loop: it comes round at
 * least every 100 ms unless a frame is stuck.  The capture thread must be
 * alive too: a source call (read, open, close) that has not returned for half
 * the watchdog interval is a hung driver, and the pings stop so that systemd
 * restarts the service (the processing loop alone would idle and ping on).
 */
static void watchdog_ping(struct daemon *d)
{
	uint64_t usec = notify_watchdog_usec();
	if (!usec)
		return;
	uint64_t since = atomic_load(&d->source_call_ns), t = tool_mono_ns();
	if (since && t > since && t - since > usec * 1000u / 2) {
		if (!d->watchdog_withheld)
			log_error("source %s: a call into the source has not returned for %.1f s (a "
				  "hung driver?); watchdog pings stop so that systemd restarts depthaod",
				  d->cfg.source_uri, (double)(t - since) / 1e9);
		d->watchdog_withheld = 1;
		return;
	}
	if (d->watchdog_withheld)
		log_info("source %s: it returned; watchdog pings go on", d->cfg.source_uri);
	d->watchdog_withheld = 0;
	notify_watchdog();
}

/*
 * The next input frame into *in: 1, or 0 when there is none yet (or
 * processing is paused), or -1 when processing ends (input closed, or a
 * signal and no time left for queued input).
 */
static int next_input(struct daemon *d, struct fq_item **in)
{
	watchdog_ping(d); /* each round: per frame, or every 100 ms while idle */
	if (atomic_load(&d->paused) && !atomic_load(&d->stop)) {
		nap(d, 20); /* paused: nothing new is processed (a recording waits, a live source's frames are released) */
		return 0;
	}
	if (!(*in = fq_pop(d->input, 100)))
		return fq_closed_and_empty(d->input) ? -1 : 0;
	if (atomic_load(&d->stop) && tool_mono_ns() >= atomic_load(&d->process_deadline_ns)) {
		/* a signal, and no time left for queued input (or drain_on_stop = false) */
		fq_done(d->input, *in);
		atomic_fetch_add(&d->input_dropped, fq_clear(d->input) + 1);
		return -1;
	}
	return 1;
}

/*
 * A context and output frames for w x h frames, with the current parameters
 * (made again when the size changes): 0, or -1 (logged and counted).
 */
static int setup_pipeline(struct daemon *d, struct dao_context **ctx, struct outputs *o,
			  uint32_t w, uint32_t h)
{
	struct dao_error err = {0};
	struct dao_camera cam;
	if (*ctx && dao_context_camera(*ctx)->width == w && dao_context_camera(*ctx)->height == h)
		return 0;
	dao_context_destroy(*ctx);
	*ctx = NULL;
	pthread_mutex_lock(&d->lock);
	struct dao_params p = d->params;
	d->params_pending = 0;
	pthread_mutex_unlock(&d->lock);
	if (make_camera(d, w, h, &cam, &err) < 0 || dao_context_create(ctx, &cam, &p, &err) < 0 ||
	    fq_frame_reserve(&o->ao16, DAO_PIXFMT_GRAY16, w, h) < 0 ||
	    fq_frame_reserve(&o->ao8, DAO_PIXFMT_GRAY8, w, h) < 0 ||
	    fq_frame_reserve(&o->rgb, DAO_PIXFMT_RGB24, w, h) < 0 ||
	    fq_frame_reserve(&o->overlay, DAO_PIXFMT_RGB24, w, h) < 0) {
		log_error("cannot set up the pipeline for %ux%u frames: %s", w, h,
			  err.message[0] ? err.message : "bad camera or out of memory");
		dao_context_destroy(*ctx);
		*ctx = NULL;
		atomic_fetch_add(&d->process_errors, 1);
		return -1;
	}
	log_info("pipeline: %ux%u, fx %.1f, fy %.1f, %s kernels", w, h, cam.fx, cam.fy,
		 dao_simd_name(dao_context_simd(*ctx)));
	pthread_mutex_lock(&d->lock);
	d->pose_restart = 0; /* a new camera, a new context: its pose track starts at its first frame */
	dao_camera_fov(&cam, &d->cam_hfov, &d->cam_vfov);
	d->have_cam = 1;
	pthread_mutex_unlock(&d->lock);
	return 0;
}

/*
 * New AO parameters into the context, and what this frame must produce:
 * the streams sinks ask for beyond the configured ones (*extra), and
 * whether the shaded image is wanted (the return value).
 */
static int take_settings(struct daemon *d, struct dao_context *ctx, unsigned *extra)
{
	struct dao_error err = {0};
	pthread_mutex_lock(&d->lock);
	if (d->params_pending) {
		if (dao_context_set_params(ctx, &d->params, &err) < 0) {
			log_error("new AO parameters refused: %s", err.message);
		} else if (d->pose_restart) {
			/* switched off, then on again: the context sees the off (its pose track
			 * ends), then the settings it has just taken, which cannot fail now */
			struct dao_params off = d->params;
			off.depth_temporal_motion = DAO_DEPTH_MOTION_OFF;
			(void)dao_context_set_params(ctx, &off, NULL);
			(void)dao_context_set_params(ctx, &d->params, NULL);
		}
		d->pose_restart = 0;
		d->params_pending = 0;
	}
	*extra = sinks_wanted_streams(d);
	int want_rgb = d->wants[STREAM_SHADED] || (*extra & (1u << STREAM_SHADED)) ||
		       d->snapshot_state == SNAP_REQUESTED;
	pthread_mutex_unlock(&d->lock);
	return want_rgb;
}

/*
 * The filtered depth of the frame just processed into `out` (DEPTH16, allocated at the
 * first frame that wants it, again only for a new size): counts of the input's unit,
 * millimetres for float-metre input.  Only when a sink wants it: a copy and a rounding
 * per pixel.
 */
static int get_filtered_depth(struct dao_context *ctx, const struct dao_frame *in,
			      struct dao_frame *out, struct dao_error *err)
{
	if (fq_frame_reserve(out, DAO_PIXFMT_DEPTH16, in->width, in->height) < 0)
		return dao_error_set(err, -ENOMEM, "out of memory for the filtered depth");
	out->depth_unit = in->format == DAO_PIXFMT_DEPTH16 ? in->depth_unit : 0.001f;
	return dao_context_get_depth(ctx, out, err);
}

/*
 * The AO of the frame and the images derived from it into o (*have_overlay:
 * the overlay was made); the CPU time counted.  0, or -1 (logged, counted).
 */
static int process_frame(struct daemon *d, struct dao_context *ctx, const struct fq_item *in,
			 struct outputs *o, int want_rgb, unsigned extra, int *have_overlay,
			 struct log_limit *error_log)
{
	struct dao_error err = {0};
	uint64_t c0 = tool_thread_cpu_ns();
	/* the source's camera pose (depth-temporal-motion source, source+icp; the other modes
	 * ignore it), or none */
	int r = dao_context_set_pose(ctx, in->has_pose ? in->pose_q : NULL, in->pose_t, &err);
	if (r < 0)
		log_limited(error_log, LOG_WARN, "frame %llu: its camera pose: %s",
			    (unsigned long long)in->index, err.message);
	/* the AO and the shaded image in one pass over the rows */
	r = dao_context_process_shaded(ctx, &in->frame, NULL, in->index, &o->ao16,
					   want_rgb ? &o->rgb : NULL, &err);
	o->have_rgb = r == 0 && want_rgb;
	/* algorithm=none: the depth streams go on, nothing to shade */
	if (want_rgb && r == -ENODATA) {
		if (!o->said_no_shading++)
			log_warn("algorithm none computes no AO: the sinks of the shaded "
				 "stream get no frames while it is set (%s)", err.message);
		r = 0;
	}
	*have_overlay = 0;
	if (r == 0) {
		/* the camera's pose, handed on where it is this frame's (the track's origin,
		 * or its motion accepted) */
		struct dao_motion_info mi = DAO_MOTION_INFO_INIT;
		struct dao_pose_track pt = DAO_POSE_TRACK_INIT;
		dao_context_motion(ctx, &mi);
		dao_context_pose_track(ctx, &pt);
		pthread_mutex_lock(&d->lock);
		if (pt.frames == 1 && d->pose.frames > 1)
			log_info("frame %llu: the camera's motion is followed again: its pose "
				 "starts over from this frame", (unsigned long long)in->index);
		if (pt.frames) /* while the motion is off the stats keep the last pose */
			d->pose = pt;
		d->motion_followed = pt.frames > 0;
		d->motion_state = mi.state;
		d->motion_reason = mi.reason;
		o->has_pose = pt.current;
		dao_pose_matrix_to_quat(pt.rotation, o->pose_q);
		memcpy(o->pose_t, pt.translation, sizeof o->pose_t);
		pthread_mutex_unlock(&d->lock);
		if (d->wants[STREAM_AO8] || (extra & (1u << STREAM_AO8)))
			ao_to_8bit(&o->ao16, &o->ao8);
		if ((d->wants[STREAM_OVERLAY] || (extra & (1u << STREAM_OVERLAY))) &&
		    in->color.format == DAO_PIXFMT_RGB24)
			*have_overlay = dao_overlay(&in->color, &o->ao16, &o->overlay, &err) == 0;
		o->have_fdepth = 0;
		if (d->wants[STREAM_FILTERED_DEPTH] || (extra & (1u << STREAM_FILTERED_DEPTH))) {
			r = get_filtered_depth(ctx, &in->frame, &o->fdepth, &err);
			o->have_fdepth = r == 0;
		}
	}
	atomic_fetch_add(&d->cpu_ns_total, tool_thread_cpu_ns() - c0);
	if (r < 0) {
		atomic_fetch_add(&d->process_errors, 1);
		log_limited(error_log, LOG_ERROR, "frame %llu: %s", (unsigned long long)in->index,
			    err.message);
		return -1;
	}
	return 0;
}

/* Processing ended: the sinks' queues closed (emptied on a signal without drain_on_stop). */
static void close_sinks(struct daemon *d)
{
	if (atomic_load(&d->stop) && !d->cfg.drain_on_stop)
		for (unsigned i = 0; i < d->nsinks; i++)
			atomic_fetch_add(&d->sinks[i].dropped, fq_clear(d->sinks[i].q));
	for (unsigned i = 0; i < d->nsinks; i++)
		fq_close(d->sinks[i].q);
}

void *process_main(void *arg)
{
	struct daemon *d = arg;
	struct dao_context *ctx = NULL;
	struct outputs o = {0};
	struct fq_item *in;
	struct log_limit error_log = LOG_LIMIT_INIT(60000, 5);
	for (;;) {
		int got = next_input(d, &in);
		if (got < 0)
			break;
		if (!got)
			continue;
		unsigned extra;
		int have_overlay;
		if (setup_pipeline(d, &ctx, &o, in->frame.width, in->frame.height) < 0) {
			fq_done(d->input, in);
			continue;
		}
		const int want_rgb = take_settings(d, ctx, &extra);
		if (process_frame(d, ctx, in, &o, want_rgb, extra, &have_overlay, &error_log) < 0) {
			fq_done(d->input, in);
			continue;
		}
		if (o.have_rgb)
			take_snapshot(d, &o.rgb);
		/* counted before a sink can have it: the stats never show a sink ahead */
		unsigned long long n = atomic_fetch_add(&d->processed, 1) + 1;
		daemon_count_recent(d, tool_mono_ns());
		fan_out(d, in, &o, have_overlay);
		fq_done(d->input, in);
		if (d->cfg.max_frames && n >= d->cfg.max_frames) {
			log_info("processed %llu frames (max_frames); stopping", n);
			atomic_store(&d->end_capture, 1);
			break;
		}
	}
	close_sinks(d);
	dao_context_destroy(ctx);
	free_outputs(&o);
	log_limit_flush(&error_log, LOG_ERROR, "frame errors");
	/* the capture thread may be blocked on a full input queue: unblock it */
	atomic_store(&d->end_capture, 1);
	fq_close(d->input);
	atomic_store(&d->process_done, 1);
	return NULL;
}
