/* SPDX-License-Identifier: MIT */
#define _GNU_SOURCE /* pthread_timedjoin_np */
#include "daemon.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "frame_queue.h"
#include "log.h"
#include "notify.h"

#define DEG2RAD (3.14159265358979323846 / 180.0)
#define DEFAULT_HFOV_DEG 58.5
#define DEFAULT_VFOV_DEG 45.6
#define LATENCY_RING 512
#define READ_TIMEOUT_MS 200
/*
 * A signal stops the pipeline in one second (counted from the signal): the
 * processing thread may finish frames already queued for STOP_PROCESS_MS, then
 * the sink queues close whatever it is doing; each sink writes what it has
 * queued until STOP_DRAIN_MS, drops the rest (counted) and finalises its
 * output, which must be done by STOP_DEADLINE_MS.  The natural end of a run
 * (end of a recording, max_frames) has no deadline: every queue drains.
 */
#define STOP_PROCESS_MS 200
#define STOP_DRAIN_MS 350
#define STOP_DEADLINE_MS 850
/*
 * A sink that fails with a permanent error (permanent_error()) is stopped for
 * good; after any other error it is closed and reopened after a backoff
 * doubling from SINK_RETRY_INITIAL_MS to SINK_RETRY_MAX_MS.  Its warnings: at
 * most SINK_LOG_BURST per SINK_LOG_INTERVAL_MS, the rest counted.
 */
#define SINK_RETRY_INITIAL_MS 500
#define SINK_RETRY_MAX_MS 30000
#define SINK_LOG_BURST 3
#define SINK_LOG_INTERVAL_MS 60000
/* A sink that has written frames and then waited this long for the next one is
 * flushed (file sinks sync to disk), so a stalled source's last frames are
 * durable within about a second, as frames arriving are. */
#define SINK_IDLE_FLUSH_MS 1000

enum sink_state {
	SINK_WAITING = 0,             /* not opened yet (no frame so far) */
	SINK_RUNNING,
	SINK_RETRYING,                /* failed; reopened after a backoff */
	SINK_STOPPED,                 /* for good: see stop_reason */
};

static const char *const sink_state_names[] = {"waiting", "running", "retrying", "stopped"};

struct sink_runner {
	struct daemon *d;
	const struct sink_config *cfg;
	struct frame_queue *q;
	pthread_t thread;
	int running;
	atomic_int done;              /* the thread has finished (its output is final) */
	struct dao_sink *sink;
	enum dao_pixfmt fmt;          /* what the open sink was negotiated for */
	uint32_t fmt_w, fmt_h;
	uint64_t next_open_ns;
	unsigned backoff_ms;
	uint64_t last_failure_ns;
	int unflushed;                /* frames written since the last flush */
	unsigned long long failures;  /* in a row, since the last good write */
	struct log_limit warn_limit;
	char reopen_uri[DAOD_MAX_URI + 8]; /* the URI with overwrite=true turned off ("" = same) */
	int reopen_noted;             /* the log said so */
	atomic_int state;             /* enum sink_state */
	char stop_reason[320];        /* written before state becomes SINK_STOPPED */
	const char *stop_code;        /* ... and the error's name: "ENOSPC", "ECANCELED", ... */
	/* counters (atomics: read by the stats thread) */
	atomic_ullong written, dropped, errors, opens;
	pthread_mutex_t lat_lock;
	uint32_t lat_us[LATENCY_RING];
	unsigned lat_n, lat_pos;
};

enum { SNAP_NONE = 0, SNAP_REQUESTED, SNAP_WRITING, SNAP_DONE };

struct daemon {
	struct daemon_config cfg;
	const struct dao_plugins *plugins;
	struct frame_queue *input;
	struct sink_runner sinks[DAOD_MAX_SINKS];
	unsigned nsinks;
	int wants[STREAM_COUNT];
	int lossless;                 /* manual playback: wait, never drop */

	pthread_t capture, process;
	int capture_running, process_running;
	atomic_int capture_done, process_done;
	pthread_mutex_t lock;         /* params, pause, snapshot, source info */
	pthread_cond_t wake;
	atomic_int stop;              /* a signal: stop within the deadlines */
	atomic_int end_capture;       /* the capture thread stops reading */
	atomic_int failed;            /* a fatal error ended the pipeline */
	atomic_int paused;
	atomic_ullong process_deadline_ns, drain_deadline_ns; /* of a signal stop */
	int stragglers;               /* threads that missed the stop deadline */
	int sinks_unfinished;         /* ... of them sinks (their output may be incomplete) */

	struct dao_params params;
	int params_pending;
	struct dao_sink_host host;    /* what sinks may ask (window controls) */
	struct dao_source_info src_info;
	int have_src_info;
	double cam_hfov, cam_vfov;    /* of the camera the pipeline uses (recorders store it) */
	int have_cam;

	pthread_t snapshot_writer;    /* writes snapshots: a slow or stuck file holds up only it */
	int snapshot_writer_running;
	pthread_cond_t snapshot_cond; /* (lock) a frame to write, or snapshot_quit */
	int snapshot_quit;
	struct dao_frame snapshot_frame; /* the frame being written (SNAP_WRITING) */
	char snapshot_path[512];
	int snapshot_state;           /* SNAP_* or -errno (failed) */
	int snapshot_abandoned;       /* cancelled while being written */
	int snapshot_notify_fd;       /* told (one byte) when it is done, -1 = nobody */
	char snapshot_msg[768];

	atomic_ullong captured, input_dropped, processed, process_errors, source_opens,
		source_failures, source_bad_frames;
	struct log_limit source_log;  /* the capture thread's repeated warnings */
	atomic_ullong source_call_ns; /* when the capture thread entered a source call, 0 = none */
	int watchdog_withheld;        /* (processing thread) pings stopped for a hung source */
	atomic_ullong cpu_ns_total;
	uint64_t start_ns;
	uint64_t interval_start_ns, interval_processed;
};

static uint64_t now_ns(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return (uint64_t)t.tv_sec * 1000000000u + (uint64_t)t.tv_nsec;
}

static uint64_t thread_cpu_ns(void)
{
	struct timespec t;
	clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
	return (uint64_t)t.tv_sec * 1000000000u + (uint64_t)t.tv_nsec;
}

/* Sleeps up to ms, returning early when the daemon stops. */
static void nap(struct daemon *d, unsigned ms)
{
	struct timespec until;
	clock_gettime(CLOCK_MONOTONIC, &until);
	until.tv_sec += ms / 1000;
	until.tv_nsec += (long)(ms % 1000) * 1000000;
	if (until.tv_nsec >= 1000000000) {
		until.tv_sec++;
		until.tv_nsec -= 1000000000;
	}
	pthread_mutex_lock(&d->lock);
	while (!atomic_load(&d->stop) &&
	       pthread_cond_timedwait(&d->wake, &d->lock, &until) != ETIMEDOUT)
		;
	pthread_mutex_unlock(&d->lock);
}

/* ---- capture ------------------------------------------------------------ */

/*
 * 1 if the source URI names something on disk (a recording, a depth PNG, a
 * directory of them) rather than a device: "oni:", "bag:" and "images:" URIs, any
 * URI whose path ends in .oni, .bag or .png, and paths outside /dev without a plugin
 * prefix.  Such a source must open at start; a device may be plugged in later.
 */
static int source_names_file(const char *uri)
{
	size_t p = 0;
	while ((uri[p] >= 'a' && uri[p] <= 'z') || (uri[p] >= '0' && uri[p] <= '9') ||
	       uri[p] == '-' || uri[p] == '_')
		p++;
	int prefixed = p > 1 && uri[p] == ':'; /* as the plugin registry reads a prefix */
	if (prefixed && ((p == 3 && (!strncmp(uri, "oni", 3) || !strncmp(uri, "bag", 3))) ||
			 (p == 6 && !strncmp(uri, "images", 6))))
		return 1;
	const char *rest = prefixed ? uri + p + 1 : uri;
	size_t n = strcspn(rest, "?");
	if (n > 4 && (!strncasecmp(rest + n - 4, ".oni", 4) || !strncasecmp(rest + n - 4, ".bag", 4) ||
		      !strncasecmp(rest + n - 4, ".png", 4)))
		return 1;
	return !prefixed && memchr(rest, '/', n) && strncmp(rest, "/dev/", 5) != 0;
}

/* The source opened and started; NULL after a failure (waited out, or fatal: d->failed). */
static struct dao_source *open_source(struct daemon *d, unsigned *backoff, int first)
{
	struct dao_source_options so = {
		.playback = d->cfg.playback,
		.loop = d->cfg.loop,
		.start_frame = d->cfg.start,
		.want_color = d->wants[STREAM_OVERLAY],
		.depth_unit = d->cfg.depth_unit,
	};
	struct dao_source *src = NULL;
	struct dao_error err = {0};
	atomic_store(&d->source_call_ns, now_ns());
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

static void *capture_main(void *arg)
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
		atomic_store(&d->source_call_ns, now_ns());
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
			atomic_store(&d->source_call_ns, now_ns());
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
		it->t_capture_ns = now_ns();
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

/* ---- processing ---------------------------------------------------------- */

static int make_camera(struct daemon *d, uint32_t w, uint32_t h, struct dao_camera *cam)
{
	struct dao_error err;
	const struct daemon_config *c = &d->cfg;
	if (c->has_intrinsics)
		return dao_camera_from_intrinsics(cam, w, h, c->intrinsics[0], c->intrinsics[1],
						  c->intrinsics[2], c->intrinsics[3], &err);
	if (c->has_fov)
		return dao_camera_from_fov(cam, w, h, c->fov_deg[0] * DEG2RAD, c->fov_deg[1] * DEG2RAD,
					   &err);
	pthread_mutex_lock(&d->lock);
	struct dao_source_info in = d->src_info;
	pthread_mutex_unlock(&d->lock);
	if (in.has_intrinsics)
		return dao_camera_from_intrinsics(cam, w, h, in.fx, in.fy, in.cx, in.cy, &err);
	if (in.has_fov)
		return dao_camera_from_fov(cam, w, h, in.hfov, in.vfov, &err);
	log_warn("no intrinsics: the source has no field of view and the config gives none; "
		 "assuming %.1f x %.1f degrees ([source] intrinsics or fov)",
		 DEFAULT_HFOV_DEG, DEFAULT_VFOV_DEG);
	return dao_camera_from_fov(cam, w, h, DEFAULT_HFOV_DEG * DEG2RAD, DEFAULT_VFOV_DEG * DEG2RAD,
				   &err);
}

struct outputs {
	struct dao_frame ao16, ao8, rgb, overlay;
};

static void free_outputs(struct outputs *o)
{
	dao_frame_free(&o->ao16);
	dao_frame_free(&o->ao8);
	dao_frame_free(&o->rgb);
	dao_frame_free(&o->overlay);
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

/* The source's colour darkened by the AO (same size only). */
static int overlay(const struct dao_frame *color, const struct dao_frame *ao, struct dao_frame *out)
{
	if (color->format != DAO_PIXFMT_RGB24 || color->width != ao->width ||
	    color->height != ao->height)
		return -1;
	for (uint32_t y = 0; y < ao->height; y++) {
		const uint8_t *c = (const uint8_t *)color->data + (size_t)y * (size_t)color->stride;
		const uint16_t *a = (const uint16_t *)((const uint8_t *)ao->data + (size_t)y * (size_t)ao->stride);
		uint8_t *o = (uint8_t *)out->data + (size_t)y * (size_t)out->stride;
		for (uint32_t x = 0; x < 3 * ao->width; x++)
			o[x] = (uint8_t)(((uint32_t)c[x] * a[x / 3] + 32767u) / 65535u);
	}
	return 0;
}

static void fan_out(struct daemon *d, const struct fq_item *in, struct outputs *o, int have_overlay)
{
	for (unsigned i = 0; i < d->nsinks; i++) {
		struct sink_runner *s = &d->sinks[i];
		const struct dao_frame *f;
		switch (s->cfg->stream) {
		case STREAM_SHADED: f = &o->rgb; break;
		case STREAM_AO: f = &o->ao16; break;
		case STREAM_AO8: f = &o->ao8; break;
		case STREAM_DEPTH: f = &in->frame; break;
		case STREAM_OVERLAY: f = have_overlay ? &o->overlay : NULL; break;
		default: f = NULL;
		}
		if (!f || atomic_load(&s->state) == SINK_STOPPED)
			continue;
		uint64_t dropped = 0;
		struct fq_item *it = fq_begin_push(s->q, !d->lossless, &dropped);
		atomic_fetch_add(&s->dropped, dropped);
		if (!it) { /* its queue closed at the stop deadline: this frame never reaches it */
			atomic_fetch_add(&s->dropped, 1);
			continue;
		}
		if (fq_frame_copy(&it->frame, f) < 0) {
			fq_cancel_push(s->q, it);
			continue;
		}
		it->frame.sequence = in->index;
		it->frame.timestamp_ns = in->frame.timestamp_ns;
		it->frame.depth_unit = in->frame.depth_unit;
		it->index = in->index;
		it->t_capture_ns = in->t_capture_ns;
		fq_end_push(s->q, it);
	}
}

/* The snapshot's result (a frame written, or not): told to whoever waits for it. */
static void snapshot_done(struct daemon *d, int r, const char *msg)
{
	if (d->snapshot_abandoned) {
		d->snapshot_state = SNAP_NONE;
		d->snapshot_abandoned = 0;
		return;
	}
	d->snapshot_state = r < 0 ? r : SNAP_DONE;
	snprintf(d->snapshot_msg, sizeof d->snapshot_msg, "%s", r < 0 ? msg : "");
	if (d->snapshot_notify_fd >= 0) {
		ssize_t w = write(d->snapshot_notify_fd, "s", 1); /* non-blocking pipe */
		(void)w;
	}
}

/*
 * A requested snapshot: the processing thread copies the frame and goes on;
 * the snapshot thread writes it.  Written here, a FIFO whose reader did not
 * read (or a hung network file system) stopped every sink.
 */
static void take_snapshot(struct daemon *d, const struct dao_frame *rgb)
{
	pthread_mutex_lock(&d->lock);
	if (d->snapshot_state == SNAP_REQUESTED) {
		if (fq_frame_copy(&d->snapshot_frame, rgb) < 0) {
			snapshot_done(d, -ENOMEM, "out of memory for the snapshot");
		} else {
			d->snapshot_state = SNAP_WRITING;
			pthread_cond_signal(&d->snapshot_cond);
		}
	}
	pthread_mutex_unlock(&d->lock);
}

/*
 * 0 if a snapshot may be written at `path`: a new name, a FIFO or device
 * (dao_png_write decides), an empty file or a PNG.  Any other regular file is
 * refused: `ctl snapshot` with the name of a recording (a typo, or a member of
 * the socket group, who writes as depthaod's user) replaced the running
 * recording with a picture while the recorder went on into the unlinked file.
 */
static int snapshot_may_replace(const char *path, char *msg, size_t len)
{
	static const unsigned char png_sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
	struct stat st;
	if (stat(path, &st) != 0 || !S_ISREG(st.st_mode) || st.st_size == 0)
		return 0;
	unsigned char b[sizeof png_sig];
	int fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK);
	ssize_t n = fd >= 0 ? read(fd, b, sizeof b) : -1;
	if (fd >= 0)
		close(fd);
	if (n == (ssize_t)sizeof b && !memcmp(b, png_sig, sizeof b))
		return 0;
	snprintf(msg, len, "%s exists and is not a PNG; a snapshot replaces only PNG files "
		 "(remove it or pick another name)", path);
	return -EEXIST;
}

static void *snapshot_main(void *arg)
{
	struct daemon *d = arg;
	char path[sizeof d->snapshot_path];
	pthread_mutex_lock(&d->lock);
	for (;;) {
		while (d->snapshot_state != SNAP_WRITING && !d->snapshot_quit)
			pthread_cond_wait(&d->snapshot_cond, &d->lock);
		if (d->snapshot_state != SNAP_WRITING)
			break;
		memcpy(path, d->snapshot_path, sizeof path);
		pthread_mutex_unlock(&d->lock);
		/* the frame is this thread's while the state is SNAP_WRITING */
		struct dao_error err = {0};
		int r = snapshot_may_replace(path, err.message, sizeof err.message);
		if (r == 0)
			r = dao_png_write(path, &d->snapshot_frame, &err);
		pthread_mutex_lock(&d->lock);
		snapshot_done(d, r, err.message);
	}
	pthread_mutex_unlock(&d->lock);
	return NULL;
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
	uint64_t since = atomic_load(&d->source_call_ns), t = now_ns();
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

static void *process_main(void *arg)
{
	struct daemon *d = arg;
	struct dao_context *ctx = NULL;
	struct outputs o = {0};
	struct fq_item *in;
	struct log_limit error_log = LOG_LIMIT_INIT(60000, 5);
	for (;;) {
		watchdog_ping(d); /* each round: per frame, or every 100 ms while idle */
		if (atomic_load(&d->paused) && !atomic_load(&d->stop)) {
			nap(d, 20); /* paused: nothing new is processed (live input queues up and drops) */
			continue;
		}
		if (!(in = fq_pop(d->input, 100))) {
			if (fq_closed_and_empty(d->input))
				break;
			continue;
		}
		if (atomic_load(&d->stop) && now_ns() >= atomic_load(&d->process_deadline_ns)) {
			/* a signal, and no time left for queued input (or drain_on_stop = false) */
			fq_done(d->input, in);
			atomic_fetch_add(&d->input_dropped, fq_clear(d->input) + 1);
			break;
		}
		struct dao_error err = {0};
		const uint32_t w = in->frame.width, h = in->frame.height;
		if (!ctx || dao_context_camera(ctx)->width != w || dao_context_camera(ctx)->height != h) {
			struct dao_camera cam;
			dao_context_destroy(ctx);
			ctx = NULL;
			pthread_mutex_lock(&d->lock);
			struct dao_params p = d->params;
			d->params_pending = 0;
			pthread_mutex_unlock(&d->lock);
			if (make_camera(d, w, h, &cam) < 0 || dao_context_create(&ctx, &cam, &p, &err) < 0 ||
			    fq_frame_reserve(&o.ao16, DAO_PIXFMT_GRAY16, w, h) < 0 ||
			    fq_frame_reserve(&o.ao8, DAO_PIXFMT_GRAY8, w, h) < 0 ||
			    fq_frame_reserve(&o.rgb, DAO_PIXFMT_RGB24, w, h) < 0 ||
			    fq_frame_reserve(&o.overlay, DAO_PIXFMT_RGB24, w, h) < 0) {
				log_error("cannot set up the pipeline for %ux%u frames: %s", w, h,
					  err.message[0] ? err.message : "bad camera or out of memory");
				dao_context_destroy(ctx);
				ctx = NULL;
				atomic_fetch_add(&d->process_errors, 1);
				fq_done(d->input, in);
				continue;
			}
			log_info("pipeline: %ux%u, fx %.1f, fy %.1f, %s kernels", w, h, cam.fx, cam.fy,
				 dao_simd_name(dao_context_simd(ctx)));
			pthread_mutex_lock(&d->lock);
			dao_camera_fov(&cam, &d->cam_hfov, &d->cam_vfov);
			d->have_cam = 1;
			pthread_mutex_unlock(&d->lock);
		}
		pthread_mutex_lock(&d->lock);
		if (d->params_pending) {
			if (dao_context_set_params(ctx, &d->params, &err) < 0)
				log_error("new AO parameters refused: %s", err.message);
			d->params_pending = 0;
		}
		int want_rgb = d->wants[STREAM_SHADED] || d->snapshot_state == SNAP_REQUESTED;
		pthread_mutex_unlock(&d->lock);

		uint64_t c0 = thread_cpu_ns();
		int r = dao_context_process(ctx, &in->frame, NULL, in->index, &o.ao16, &err);
		if (r == 0 && want_rgb)
			r = dao_context_shade(ctx, &o.rgb, &err);
		int have_overlay = 0;
		if (r == 0) {
			if (d->wants[STREAM_AO8])
				ao_to_8bit(&o.ao16, &o.ao8);
			if (d->wants[STREAM_OVERLAY] && in->color.format == DAO_PIXFMT_RGB24)
				have_overlay = overlay(&in->color, &o.ao16, &o.overlay) == 0;
		}
		atomic_fetch_add(&d->cpu_ns_total, thread_cpu_ns() - c0);
		if (r < 0) {
			atomic_fetch_add(&d->process_errors, 1);
			log_limited(&error_log, LOG_ERROR, "frame %llu: %s", (unsigned long long)in->index,
				    err.message);
			fq_done(d->input, in);
			continue;
		}
		if (want_rgb)
			take_snapshot(d, &o.rgb);
		fan_out(d, in, &o, have_overlay);
		fq_done(d->input, in);
		unsigned long long n = atomic_fetch_add(&d->processed, 1) + 1;
		if (d->cfg.max_frames && n >= d->cfg.max_frames) {
			log_info("processed %llu frames (max_frames); stopping", n);
			atomic_store(&d->end_capture, 1);
			break;
		}
	}
	if (atomic_load(&d->stop) && !d->cfg.drain_on_stop)
		for (unsigned i = 0; i < d->nsinks; i++)
			atomic_fetch_add(&d->sinks[i].dropped, fq_clear(d->sinks[i].q));
	for (unsigned i = 0; i < d->nsinks; i++)
		fq_close(d->sinks[i].q);
	dao_context_destroy(ctx);
	free_outputs(&o);
	log_limit_flush(&error_log, LOG_ERROR, "frame errors");
	/* the capture thread may be blocked on a full input queue: unblock it */
	atomic_store(&d->end_capture, 1);
	fq_close(d->input);
	atomic_store(&d->process_done, 1);
	return NULL;
}

/* ---- sinks ------------------------------------------------------------ */

static void record_latency(struct sink_runner *s, uint64_t t_capture)
{
	uint64_t us = (now_ns() - t_capture) / 1000u;
	pthread_mutex_lock(&s->lat_lock);
	s->lat_us[s->lat_pos] = us > UINT32_MAX ? UINT32_MAX : (uint32_t)us;
	s->lat_pos = (s->lat_pos + 1) % LATENCY_RING;
	if (s->lat_n < LATENCY_RING)
		s->lat_n++;
	pthread_mutex_unlock(&s->lat_lock);
}

static int host_get_param(void *user, const char *name, char *value, size_t len)
{
	struct dao_params p;
	daemon_get_params(user, &p);
	return dao_params_get(&p, name, value, len, NULL);
}

static int host_set_param(void *user, const char *name, const char *value)
{
	struct daemon *d = user;
	struct dao_params p;
	struct dao_error err = {0};
	daemon_get_params(d, &p);
	int r = dao_params_set(&p, name, value, &err);
	if (r == 0)
		r = dao_params_validate(&p, &err);
	if (r == 0) {
		daemon_set_params(d, &p);
		log_info("sink control: %s = %s", name, value);
	}
	return r;
}

/* A sink's log line (e.g. the file a recorder chose) at its level. */
static void host_log(void *user, int level, const char *message)
{
	(void)user;
	log_msg(level == DAO_LOG_ERROR ? LOG_ERROR : level == DAO_LOG_WARN ? LOG_WARN : LOG_INFO,
		"%s", message);
}

/* Errors after which a sink cannot go on: retrying would not help, and reopening a
 * file could truncate what it already holds. */
static int permanent_error(int r)
{
	return r == -ENOSPC || r == -EDQUOT || r == -EFBIG || r == -EROFS || r == -EPIPE;
}

static const char *error_name(int r)
{
	switch (r) {
	case -ENOSPC: return "ENOSPC";
	case -EDQUOT: return "EDQUOT";
	case -EFBIG: return "EFBIG";
	case -EROFS: return "EROFS";
	case -EPIPE: return "EPIPE";
	case -ENOTSUP: return "ENOTSUP";
	case -ECANCELED: return "ECANCELED";
	default: return "error";
	}
}

static const char *remedy(int r)
{
	switch (r) {
	case -ENOSPC:
		return "free space on that filesystem or point the sink at another one, then restart "
		       "depthaod";
	case -EDQUOT:
		return "raise the disk quota of depthaod's user or point the sink elsewhere, then "
		       "restart depthaod";
	case -EFBIG:
		return "the file reached the largest size the filesystem allows; point the sink at "
		       "another filesystem, then restart depthaod";
	case -EROFS:
		return "the filesystem is read-only; remount it read-write or point the sink "
		       "elsewhere, then restart depthaod";
	case -EPIPE:
		return "its reader went away (a closed pipe or stdout); restart depthaod to write "
		       "there again";
	default:
		return "see the message; restart depthaod once it is fixed";
	}
}

static void close_sink(struct sink_runner *s)
{
	struct dao_error err = {0};
	if (s->sink && dao_sink_close(s->sink, &err) < 0)
		log_error("sink %s: closing %s: %s", s->cfg->name, s->cfg->uri, err.message);
	s->sink = NULL;
}

/* Stops the sink for good: what it wrote is finalised, it is never reopened. */
static void stop_sink(struct sink_runner *s, int r, enum log_level level, const char *why,
		      const char *advice)
{
	close_sink(s);
	snprintf(s->stop_reason, sizeof s->stop_reason, "%s", why);
	s->stop_code = error_name(r);
	atomic_store(&s->state, SINK_STOPPED);
	log_msg(level, "sink %s (%s) stopped: %s%s%s; the daemon and the other sinks keep running",
		s->cfg->name, s->cfg->uri, why, advice ? ": " : "", advice ? advice : "");
}

/* An open, negotiate or write failed with r: stop the sink, or retry after a backoff. */
static void sink_failed(struct sink_runner *s, int r, const char *msg)
{
	atomic_fetch_add(&s->errors, 1);
	if (r == -ENOTSUP) { /* this sink cannot work here */
		close_sink(s);
		snprintf(s->stop_reason, sizeof s->stop_reason, "%s", msg);
		s->stop_code = error_name(r);
		atomic_store(&s->state, SINK_STOPPED);
		log_warn("sink %s (%s): %s; it stays off", s->cfg->name, s->cfg->uri, msg);
		return;
	}
	if (permanent_error(r)) {
		stop_sink(s, r, LOG_ERROR, msg, remedy(r));
		return;
	}
	close_sink(s);
	s->failures++;
	s->last_failure_ns = now_ns();
	s->next_open_ns = s->last_failure_ns + (uint64_t)s->backoff_ms * 1000000u;
	log_limited(&s->warn_limit, LOG_WARN, "sink %s (%s): %s; retrying in %.1f s (failure %llu)",
		    s->cfg->name, s->cfg->uri, msg, s->backoff_ms / 1000.0, s->failures);
	s->backoff_ms = s->backoff_ms * 2 > SINK_RETRY_MAX_MS ? SINK_RETRY_MAX_MS : s->backoff_ms * 2;
	atomic_store(&s->state, SINK_RETRYING);
}

/*
 * The URI for opening the sink again, after it wrote frames in this run: an
 * "overwrite=true" (or =1) among the options after the last '?' becomes
 * "overwrite=false", so that a reopen (after an error, or for a new frame size)
 * never replaces what this run recorded; "" when there is none.  overwrite
 * replaces a file that is there when the sink first opens, nothing after.
 */
static void make_reopen_uri(const char *uri, char *out, size_t cap)
{
	const char *q = strrchr(uri, '?');
	out[0] = '\0';
	if (!q || !strchr(q, '='))
		return;
	size_t n = (size_t)(q - uri) + 1, len = 0;
	int changed = 0;
	if (n >= cap)
		return;
	memcpy(out, uri, n);
	len = n;
	for (const char *kv = q + 1; *kv;) {
		size_t k = strcspn(kv, "&");
		const char *opt = kv;
		size_t optlen = k;
		if ((k == 14 && !strncmp(kv, "overwrite=true", 14)) ||
		    (k == 11 && !strncmp(kv, "overwrite=1", 11))) {
			opt = "overwrite=false";
			optlen = 15;
			changed = 1;
		}
		if (len + optlen + 2 > cap) {
			out[0] = '\0';
			return;
		}
		memcpy(out + len, opt, optlen);
		len += optlen;
		kv += k;
		if (*kv == '&')
			out[len++] = *kv++;
	}
	out[changed ? len : 0] = '\0';
}

/* Opens and negotiates the sink for the frames of `it`; 0, or the failure handled. */
static int open_sink(struct sink_runner *s, const struct fq_item *it)
{
	struct daemon *d = s->d;
	struct dao_error err = {0};
	const char *uri = s->cfg->uri;
	unsigned long long wrote = atomic_load(&s->written);
	if (wrote && s->reopen_uri[0]) {
		uri = s->reopen_uri;
		if (!s->reopen_noted++)
			log_info("sink %s: opened again after %llu frame%s: overwrite applies to its first "
				 "open only, what this run wrote is kept", s->cfg->name, wrote,
				 wrote == 1 ? "" : "s");
	}
	int r = dao_sink_open(d->plugins, uri, &s->sink, &err);
	if (r == 0) {
		dao_sink_attach_host(s->sink, &d->host);
		pthread_mutex_lock(&d->lock);
		struct dao_source_info in = d->src_info;
		if (d->have_cam) { /* the camera in use: configured intrinsics win over the source's */
			in.has_fov = 1;
			in.hfov = d->cam_hfov;
			in.vfov = d->cam_vfov;
		}
		pthread_mutex_unlock(&d->lock);
		struct dao_sink_format fmt = {
			.format = it->frame.format, .width = it->frame.width, .height = it->frame.height,
			.fps = in.fps, .depth_unit = it->frame.depth_unit, .has_fov = in.has_fov,
			.hfov = in.hfov, .vfov = in.vfov, .mirrored = in.mirrored,
		};
		r = dao_sink_negotiate(s->sink, &fmt, &err);
		if (r == 0 && fmt.format != it->frame.format) {
			r = -ENOTSUP;
			snprintf(err.message, sizeof err.message,
				 "it takes %s, not the %s stream (set [sink.%s] stream)",
				 dao_pixfmt_name(fmt.format), stream_name(s->cfg->stream), s->cfg->name);
		}
	}
	if (r < 0) {
		sink_failed(s, r, err.message[0] ? err.message : strerror(-r));
		return r;
	}
	s->fmt = it->frame.format;
	s->fmt_w = it->frame.width;
	s->fmt_h = it->frame.height;
	if (atomic_fetch_add(&s->opens, 1) == 0)
		log_info("sink %s: %s (%s stream)", s->cfg->name, s->cfg->uri,
			 stream_name(s->cfg->stream));
	atomic_store(&s->state, SINK_RUNNING);
	return 0;
}

static void write_frame(struct sink_runner *s, const struct fq_item *it)
{
	struct dao_error err = {0};
	int r = dao_sink_write(s->sink, &it->frame, &err);
	if (r == -ECANCELED) { /* finished by the user (a closed window) */
		char why[300];
		snprintf(why, sizeof why, "%s", err.message);
		stop_sink(s, r, LOG_INFO, why, NULL);
	} else if (r < 0) {
		atomic_fetch_add(&s->dropped, 1);
		sink_failed(s, r, err.message[0] ? err.message : strerror(-r));
	} else {
		atomic_fetch_add(&s->written, 1);
		record_latency(s, it->t_capture_ns);
		if (s->failures)
			log_limited(&s->warn_limit, LOG_INFO, "sink %s: writing again after %llu "
				    "failure%s", s->cfg->name, s->failures, s->failures == 1 ? "" : "s");
		s->failures = 0;
		/* the backoff starts afresh once the sink has worked for a while: one that
		 * fails after every few frames keeps backing off */
		if (now_ns() - s->last_failure_ns >= (uint64_t)SINK_RETRY_MAX_MS * 1000000u)
			s->backoff_ms = SINK_RETRY_INITIAL_MS;
	}
}

/* The sink has been idle with unflushed frames: flush them (a failure is handled
 * like a failed write). */
static void flush_idle_sink(struct sink_runner *s)
{
	struct dao_error err = {0};
	s->unflushed = 0;
	int r = dao_sink_flush(s->sink, &err);
	if (r < 0)
		sink_failed(s, r, err.message[0] ? err.message : strerror(-r));
}

static void *sink_main(void *arg)
{
	struct sink_runner *s = arg;
	struct fq_item *it;
	for (;;) {
		it = fq_pop(s->q, s->unflushed ? SINK_IDLE_FLUSH_MS : -1);
		if (!it) {
			if (fq_closed_and_empty(s->q))
				break;
			if (s->sink && s->unflushed)
				flush_idle_sink(s);
			continue;
		}
		if (atomic_load(&s->d->stop) && now_ns() >= atomic_load(&s->d->drain_deadline_ns)) {
			/* a signal, and the time for queued frames is over: finalise now */
			unsigned left = fq_clear(s->q) + 1;
			fq_done(s->q, it);
			atomic_fetch_add(&s->dropped, left);
			log_warn("sink %s: %u queued frame%s dropped at the stop deadline",
				 s->cfg->name, left, left == 1 ? "" : "s");
			break;
		}
		if (atomic_load(&s->state) == SINK_STOPPED) {
			fq_done(s->q, it);
			continue;
		}
		if (s->sink && (it->frame.format != s->fmt || it->frame.width != s->fmt_w ||
				it->frame.height != s->fmt_h)) {
			log_info("sink %s: the stream is now %ux%u; reopening", s->cfg->name,
				 it->frame.width, it->frame.height);
			close_sink(s);
		}
		if (!s->sink && (now_ns() < s->next_open_ns || open_sink(s, it) < 0)) {
			if (atomic_load(&s->state) != SINK_STOPPED)
				atomic_fetch_add(&s->dropped, 1); /* waiting out the backoff */
			fq_done(s->q, it);
			continue;
		}
		write_frame(s, it);
		s->unflushed = s->sink != NULL;
		fq_done(s->q, it);
	}
	if (s->sink) {
		struct dao_error err = {0};
		int r = dao_sink_flush(s->sink, &err);
		if (r < 0)
			log_error("sink %s (%s): flushing at the end: %s", s->cfg->name, s->cfg->uri,
				  err.message[0] ? err.message : strerror(-r));
	}
	close_sink(s);
	char what[96];
	snprintf(what, sizeof what, "sink %s", s->cfg->name);
	log_limit_flush(&s->warn_limit, LOG_WARN, what);
	atomic_store(&s->done, 1);
	return NULL;
}

/* ---- life cycle -------------------------------------------------------- */

int daemon_create(struct daemon **out, const struct daemon_config *cfg,
		  const struct dao_plugins *plugins, char *msg, size_t len)
{
	struct daemon *d = calloc(1, sizeof(*d));
	if (!d) {
		snprintf(msg, len, "out of memory");
		return -ENOMEM;
	}
	d->cfg = *cfg;
	d->plugins = plugins;
	d->lossless = cfg->playback == DAO_PLAYBACK_MANUAL;
	d->snapshot_notify_fd = -1;
	d->source_log = (struct log_limit)LOG_LIMIT_INIT(60000, 5);
	d->host = (struct dao_sink_host){d, host_get_param, host_set_param, host_log};
	pthread_mutex_init(&d->lock, NULL);
	pthread_condattr_t ca;
	pthread_condattr_init(&ca);
	pthread_condattr_setclock(&ca, CLOCK_MONOTONIC);
	pthread_cond_init(&d->wake, &ca);
	pthread_condattr_destroy(&ca);
	pthread_cond_init(&d->snapshot_cond, NULL);
	if (config_params(cfg, &d->params, msg, len) < 0 || fq_create(&d->input, cfg->input_queue) < 0) {
		daemon_destroy(d);
		return -EINVAL;
	}
	for (unsigned i = 0; i < cfg->nsinks; i++) {
		struct sink_runner *s = &d->sinks[i];
		s->d = d;
		s->cfg = &d->cfg.sinks[i];
		s->backoff_ms = SINK_RETRY_INITIAL_MS;
		s->warn_limit = (struct log_limit)LOG_LIMIT_INIT(SINK_LOG_INTERVAL_MS, SINK_LOG_BURST);
		make_reopen_uri(s->cfg->uri, s->reopen_uri, sizeof s->reopen_uri);
		pthread_mutex_init(&s->lat_lock, NULL);
		if (fq_create(&s->q, s->cfg->queue) < 0) {
			snprintf(msg, len, "out of memory");
			daemon_destroy(d);
			return -ENOMEM;
		}
		d->nsinks++;
		d->wants[s->cfg->stream] = 1;
	}
	*out = d;
	return 0;
}

int daemon_start(struct daemon *d, char *msg, size_t len)
{
	d->start_ns = d->interval_start_ns = now_ns();
	for (unsigned i = 0; i < d->nsinks; i++) {
		if (pthread_create(&d->sinks[i].thread, NULL, sink_main, &d->sinks[i]) != 0) {
			snprintf(msg, len, "cannot start a thread");
			return -EAGAIN;
		}
		d->sinks[i].running = 1;
	}
	if (pthread_create(&d->snapshot_writer, NULL, snapshot_main, d) != 0) {
		snprintf(msg, len, "cannot start a thread");
		return -EAGAIN;
	}
	d->snapshot_writer_running = 1;
	if (pthread_create(&d->process, NULL, process_main, d) != 0) {
		snprintf(msg, len, "cannot start a thread");
		return -EAGAIN;
	}
	d->process_running = 1;
	if (pthread_create(&d->capture, NULL, capture_main, d) != 0) {
		snprintf(msg, len, "cannot start a thread");
		return -EAGAIN;
	}
	d->capture_running = 1;
	return 0;
}

int daemon_finished(struct daemon *d)
{
	if (!atomic_load(&d->capture_done) || !atomic_load(&d->process_done))
		return 0;
	for (unsigned i = 0; i < d->nsinks; i++)
		if (!atomic_load(&d->sinks[i].done))
			return 0;
	return 1;
}

int daemon_failed(struct daemon *d)
{
	return atomic_load(&d->failed);
}

/* Joins a thread by the deadline; 0 if it is still running then (logged if `what`). */
static int join_by(pthread_t t, int *running, uint64_t deadline, const char *what)
{
	if (!*running)
		return 1;
	uint64_t n = now_ns();
	uint64_t left = deadline > n ? deadline - n : 0;
	struct timespec abs;
	clock_gettime(CLOCK_REALTIME, &abs); /* pthread_timedjoin_np uses CLOCK_REALTIME */
	abs.tv_sec += (time_t)(left / 1000000000u);
	abs.tv_nsec += (long)(left % 1000000000u);
	if (abs.tv_nsec >= 1000000000) {
		abs.tv_sec++;
		abs.tv_nsec -= 1000000000;
	}
	if (pthread_timedjoin_np(t, NULL, &abs) != 0) {
		if (what)
			log_error("%s did not finish within the stop deadline; its output may be "
				  "incomplete", what);
		return 0; /* still running: it keeps its memory (*running stays set) */
	}
	*running = 0;
	return 1;
}

static void join(pthread_t t, int *running)
{
	if (*running)
		pthread_join(t, NULL);
	*running = 0;
}

/* Ends the snapshot thread by the deadline; 0 if it is still writing then (a stuck file). */
static int stop_snapshot_writer(struct daemon *d, uint64_t deadline)
{
	pthread_mutex_lock(&d->lock);
	d->snapshot_quit = 1;
	pthread_cond_broadcast(&d->snapshot_cond);
	pthread_mutex_unlock(&d->lock);
	if (join_by(d->snapshot_writer, &d->snapshot_writer_running, deadline, NULL))
		return 1;
	log_warn("a snapshot was still being written at the stop deadline (a FIFO nobody "
		 "reads?); it is abandoned");
	return 0;
}

void daemon_stop(struct daemon *d)
{
	if (daemon_finished(d)) { /* the natural end: everything has drained already */
		join(d->capture, &d->capture_running);
		join(d->process, &d->process_running);
		for (unsigned i = 0; i < d->nsinks; i++)
			join(d->sinks[i].thread, &d->sinks[i].running);
		if (!stop_snapshot_writer(d, now_ns() + (uint64_t)STOP_DEADLINE_MS * 1000000u))
			d->stragglers = 1;
		return;
	}
	uint64_t t0 = now_ns();
	int drain = d->cfg.drain_on_stop;
	atomic_store(&d->process_deadline_ns, drain ? t0 + (uint64_t)STOP_PROCESS_MS * 1000000u : t0);
	atomic_store(&d->drain_deadline_ns, drain ? t0 + (uint64_t)STOP_DRAIN_MS * 1000000u : t0);
	atomic_store(&d->stop, 1);
	atomic_store(&d->end_capture, 1);
	pthread_mutex_lock(&d->lock);
	pthread_cond_broadcast(&d->wake);
	pthread_mutex_unlock(&d->lock);
	fq_close(d->input); /* capture stops pushing */
	if (!drain) {
		atomic_fetch_add(&d->input_dropped, fq_clear(d->input));
		for (unsigned i = 0; i < d->nsinks; i++)
			atomic_fetch_add(&d->sinks[i].dropped, fq_clear(d->sinks[i].q));
	}
	/* the processing thread's time for queued input; then the sinks get theirs, whatever
	 * it is doing (a frame may take longer than the whole second) */
	join_by(d->process, &d->process_running, t0 + (uint64_t)STOP_PROCESS_MS * 1000000u, NULL);
	for (unsigned i = 0; i < d->nsinks; i++)
		fq_close(d->sinks[i].q);
	uint64_t deadline = t0 + (uint64_t)STOP_DEADLINE_MS * 1000000u;
	for (unsigned i = 0; i < d->nsinks; i++) {
		char what[96];
		snprintf(what, sizeof what, "sink %s", d->sinks[i].cfg->name);
		if (!join_by(d->sinks[i].thread, &d->sinks[i].running, deadline, what))
			d->sinks_unfinished++;
	}
	/* a frame or a read still going on now is not worth more waiting: nothing of it
	 * would reach a sink */
	int all = d->sinks_unfinished == 0;
	deadline = t0 + (uint64_t)STOP_DRAIN_MS * 1000000u;
	if (!join_by(d->process, &d->process_running, deadline, NULL)) {
		log_warn("the processing thread was still inside a frame at the stop deadline; "
			 "that frame is dropped (the sinks have finalised what they had)");
		all = 0;
	}
	if (!join_by(d->capture, &d->capture_running, deadline, NULL)) {
		log_warn("the source did not return from a read by the stop deadline; it is "
			 "abandoned");
		all = 0;
	}
	if (!stop_snapshot_writer(d, deadline))
		all = 0;
	d->stragglers = !all;
}

int daemon_stragglers(struct daemon *d)
{
	return d->stragglers;
}

int daemon_sinks_unfinished(struct daemon *d)
{
	return d->sinks_unfinished;
}

void daemon_destroy(struct daemon *d)
{
	if (!d)
		return;
	int running = d->capture_running || d->process_running || d->snapshot_writer_running;
	for (unsigned i = 0; i < d->nsinks; i++)
		running |= d->sinks[i].running;
	if (running)
		daemon_stop(d);
	if (d->stragglers)
		return; /* a thread still uses the daemon's memory: the process exit frees it */
	for (unsigned i = 0; i < d->nsinks; i++) {
		fq_destroy(d->sinks[i].q);
		pthread_mutex_destroy(&d->sinks[i].lat_lock);
	}
	fq_destroy(d->input);
	dao_frame_free(&d->snapshot_frame);
	pthread_mutex_destroy(&d->lock);
	pthread_cond_destroy(&d->wake);
	pthread_cond_destroy(&d->snapshot_cond);
	free(d);
}

void daemon_set_params(struct daemon *d, const struct dao_params *p)
{
	pthread_mutex_lock(&d->lock);
	d->params = *p;
	d->params_pending = 1;
	pthread_mutex_unlock(&d->lock);
}

void daemon_get_params(struct daemon *d, struct dao_params *p)
{
	pthread_mutex_lock(&d->lock);
	*p = d->params;
	pthread_mutex_unlock(&d->lock);
}

void daemon_set_paused(struct daemon *d, int paused)
{
	atomic_store(&d->paused, paused);
}

int daemon_snapshot_request(struct daemon *d, const char *path, int notify_fd, char *msg,
			    size_t len)
{
	if (atomic_load(&d->paused)) {
		snprintf(msg, len, "the pipeline is paused: resume it, then take the snapshot");
		return -EAGAIN;
	}
	if (strlen(path) >= sizeof d->snapshot_path) {
		snprintf(msg, len, "the path is longer than %zu bytes", sizeof d->snapshot_path - 1);
		return -ENAMETOOLONG;
	}
	pthread_mutex_lock(&d->lock);
	if (d->snapshot_state == SNAP_REQUESTED || d->snapshot_state == SNAP_WRITING) {
		pthread_mutex_unlock(&d->lock);
		snprintf(msg, len, "another snapshot is in progress");
		return -EBUSY;
	}
	snprintf(d->snapshot_path, sizeof d->snapshot_path, "%s", path);
	d->snapshot_state = SNAP_REQUESTED;
	d->snapshot_abandoned = 0;
	d->snapshot_notify_fd = notify_fd;
	pthread_mutex_unlock(&d->lock);
	return 0;
}

int daemon_snapshot_result(struct daemon *d, char *msg, size_t len)
{
	pthread_mutex_lock(&d->lock);
	int r = d->snapshot_state;
	if (r == SNAP_REQUESTED || r == SNAP_WRITING) {
		pthread_mutex_unlock(&d->lock);
		return 1;
	}
	if (r < 0)
		snprintf(msg, len, "%s", d->snapshot_msg);
	d->snapshot_state = SNAP_NONE;
	pthread_mutex_unlock(&d->lock);
	return r < 0 ? r : 0;
}

int daemon_snapshot_cancel(struct daemon *d)
{
	pthread_mutex_lock(&d->lock);
	int writing = d->snapshot_state == SNAP_WRITING;
	if (writing)
		d->snapshot_abandoned = 1;
	else
		d->snapshot_state = SNAP_NONE;
	d->snapshot_notify_fd = -1;
	pthread_mutex_unlock(&d->lock);
	return writing;
}

static int cmp_u32(const void *a, const void *b)
{
	uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
	return x < y ? -1 : x > y;
}

struct json_object *daemon_stats(struct daemon *d, int reset_interval)
{
	uint64_t t = now_ns();
	unsigned long long processed = atomic_load(&d->processed);
	pthread_mutex_lock(&d->lock);
	double secs = (double)(t - d->interval_start_ns) / 1e9;
	double fps = secs > 0 ? (double)(processed - d->interval_processed) / secs : 0;
	if (reset_interval) {
		d->interval_start_ns = t;
		d->interval_processed = processed;
	}
	pthread_mutex_unlock(&d->lock);
	struct json_object *j = json_object_new_object();
	json_object_object_add(j, "uptime_s", json_object_new_double((double)(t - d->start_ns) / 1e9));
	json_object_object_add(j, "paused", json_object_new_boolean(atomic_load(&d->paused)));
	json_object_object_add(j, "source_opens", json_object_new_int64((int64_t)atomic_load(&d->source_opens)));
	json_object_object_add(j, "source_failures", json_object_new_int64((int64_t)atomic_load(&d->source_failures)));
	json_object_object_add(j, "source_bad_frames", json_object_new_int64((int64_t)atomic_load(&d->source_bad_frames)));
	json_object_object_add(j, "frames_in", json_object_new_int64((int64_t)atomic_load(&d->captured)));
	json_object_object_add(j, "frames_dropped_in", json_object_new_int64((int64_t)atomic_load(&d->input_dropped)));
	json_object_object_add(j, "frames_processed", json_object_new_int64((int64_t)processed));
	json_object_object_add(j, "process_errors", json_object_new_int64((int64_t)atomic_load(&d->process_errors)));
	json_object_object_add(j, "fps", json_object_new_double(fps));
	json_object_object_add(j, "cpu_ms_per_frame",
			       json_object_new_double(processed ? (double)atomic_load(&d->cpu_ns_total) / 1e6 / (double)processed : 0));
	struct json_object *sinks = json_object_new_array();
	for (unsigned i = 0; i < d->nsinks; i++) {
		struct sink_runner *s = &d->sinks[i];
		struct json_object *o = json_object_new_object();
		uint32_t lat[LATENCY_RING];
		pthread_mutex_lock(&s->lat_lock);
		unsigned n = s->lat_n;
		memcpy(lat, s->lat_us, n * sizeof(uint32_t));
		pthread_mutex_unlock(&s->lat_lock);
		qsort(lat, n, sizeof(uint32_t), cmp_u32);
		json_object_object_add(o, "name", json_object_new_string(s->cfg->name));
		json_object_object_add(o, "uri", json_object_new_string(s->cfg->uri));
		json_object_object_add(o, "stream", json_object_new_string(stream_name(s->cfg->stream)));
		json_object_object_add(o, "frames_out", json_object_new_int64((int64_t)atomic_load(&s->written)));
		json_object_object_add(o, "frames_dropped", json_object_new_int64((int64_t)atomic_load(&s->dropped)));
		json_object_object_add(o, "errors", json_object_new_int64((int64_t)atomic_load(&s->errors)));
		int state = atomic_load(&s->state);
		json_object_object_add(o, "state", json_object_new_string(sink_state_names[state]));
		if (state == SINK_STOPPED) {
			json_object_object_add(o, "stop_reason", json_object_new_string(s->stop_reason));
			json_object_object_add(o, "stop_code", json_object_new_string(s->stop_code));
		}
		json_object_object_add(o, "disabled", json_object_new_boolean(state == SINK_STOPPED));
		json_object_object_add(o, "opens", json_object_new_int64((int64_t)atomic_load(&s->opens)));
		json_object_object_add(o, "queued", json_object_new_int((int)fq_length(s->q)));
		json_object_object_add(o, "latency_ms_median",
				       json_object_new_double(n ? lat[n / 2] / 1000.0 : 0));
		json_object_object_add(o, "latency_ms_p99",
				       json_object_new_double(n ? lat[((size_t)n * 99 + 99) / 100 - 1] / 1000.0 : 0));
		json_object_array_add(sinks, o);
	}
	json_object_object_add(j, "sinks", sinks);
	return j;
}
