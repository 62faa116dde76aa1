/* SPDX-License-Identifier: MIT */
/*
 * One thread per sink: opens it for the frames it gets, writes them, and
 * handles its errors (stop for good, or reopen after a backoff).
 */

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/prctl.h>

#include "daemon_internal.h"

static void record_latency(struct sink_runner *s, uint64_t t_capture)
{
	uint64_t us = (tool_mono_ns() - t_capture) / 1000u;
	pthread_mutex_lock(&s->lat_lock);
	s->lat_us[s->lat_pos] = us > UINT32_MAX ? UINT32_MAX : (uint32_t)us;
	s->lat_pos = (s->lat_pos + 1) % LATENCY_RING;
	if (s->lat_n < LATENCY_RING)
		s->lat_n++;
	pthread_mutex_unlock(&s->lat_lock);
}

static int host_get_param(void *user, const char *name, char *value, size_t len)
{
	struct sink_runner *s = user;
	struct dao_params p;
	daemon_get_params(s->d, &p);
	return dao_params_get(&p, name, value, len, NULL);
}

/* Through the checks of `depthao ctl set` (control.c): dao_params_set, then
 * dao_params_validate of the whole set, then daemon_set_params. */
static int host_set_params(void *user, const char *const *names, const char *const *values,
			   size_t count, char *msg, size_t len)
{
	struct sink_runner *s = user;
	struct dao_params p;
	struct dao_error err = {0};
	int r = 0;
	/* a web page's requests come in parallel: one change applies after the other */
	pthread_mutex_lock(&s->control_lock);
	daemon_get_params(s->d, &p);
	for (size_t i = 0; i < count && r == 0; i++)
		r = dao_params_set(&p, names[i], values[i], &err);
	if (r == 0)
		r = dao_params_validate(&p, &err);
	if (r < 0) {
		pthread_mutex_unlock(&s->control_lock);
		if (msg && len)
			snprintf(msg, len, "%s", err.message[0] ? err.message : strerror(-r));
		return r;
	}
	daemon_set_params(s->d, &p);
	for (size_t i = 0; i < count; i++)
		log_limited(&s->control_log, LOG_INFO, "sink %s control: %s = %s", s->cfg->name,
			    names[i], values[i]);
	pthread_mutex_unlock(&s->control_lock);
	return 0;
}

static int host_set_param(void *user, const char *name, const char *value)
{
	return host_set_params(user, &name, &value, 1, NULL, 0);
}

/* A sink's log line (e.g. the file a recorder chose) at its level. */
static void host_log(void *user, int level, const char *message)
{
	(void)user;
	log_msg(level == DAO_LOG_ERROR ? LOG_ERROR : level == DAO_LOG_WARN ? LOG_WARN : LOG_INFO,
		"%s", message);
}

/* The same JSON as `depthao ctl stats`. */
static int host_stats_json(void *user, char *json, size_t len)
{
	struct sink_runner *s = user;
	struct json_object *j = daemon_stats(s->d, 0);
	const char *t = json_object_to_json_string_ext(j, JSON_C_TO_STRING_PLAIN);
	size_t n = strlen(t);
	int r = n < len ? (int)n : -ENOSPC;
	if (r >= 0)
		memcpy(json, t, n + 1);
	json_object_put(j);
	return r;
}

static int host_want_streams(void *user, unsigned mask)
{
	struct sink_runner *s = user;
	if (mask >> STREAM_COUNT)
		return -EINVAL;
	atomic_store(&s->extra_streams, mask);
	return 0;
}

void sink_host_init(struct sink_runner *s)
{
	_Static_assert((int)STREAM_SHADED == (int)DAO_STREAM_SHADED &&
			       (int)STREAM_AO == (int)DAO_STREAM_AO &&
			       (int)STREAM_AO8 == (int)DAO_STREAM_AO8 &&
			       (int)STREAM_DEPTH == (int)DAO_STREAM_DEPTH &&
			       (int)STREAM_OVERLAY == (int)DAO_STREAM_OVERLAY &&
			       (int)STREAM_FILTERED_DEPTH == (int)DAO_STREAM_FILTERED_DEPTH &&
			       (int)STREAM_COUNT == (int)DAO_STREAM_COUNT,
		       "depthaod's streams are numbered as enum dao_stream");
	s->control_log = (struct log_limit)LOG_LIMIT_INIT(10000, 10);
	s->host = (struct dao_sink_host){
		.size = sizeof(struct dao_sink_host),
		.user = s,
		.get_param = host_get_param,
		.set_param = host_set_param,
		.log = host_log,
		.set_params = host_set_params,
		.stats_json = host_stats_json,
		.want_streams = host_want_streams,
	};
}

unsigned sinks_wanted_streams(struct daemon *d)
{
	unsigned m = 0;
	for (unsigned i = 0; i < d->nsinks; i++)
		if (atomic_load(&d->sinks[i].state) != SINK_STOPPED)
			m |= atomic_load(&d->sinks[i].extra_streams);
	return m;
}

int sink_may_want_any_stream(const struct sink_config *cfg)
{
	return !strncmp(cfg->uri, "http:", 5);
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
	atomic_store(&s->extra_streams, 0); /* until it opens again and asks */
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
	s->last_failure_ns = tool_mono_ns();
	s->next_open_ns = s->last_failure_ns + (uint64_t)s->backoff_ms * 1000000u;
	log_limited(&s->warn_limit, LOG_WARN, "sink %s (%s): %s; retrying in %.1f s (failure %llu)",
		    s->cfg->name, s->cfg->uri, msg, s->backoff_ms / 1000.0, s->failures);
	s->backoff_ms = s->backoff_ms * 2 > SINK_RETRY_MAX_MS ? SINK_RETRY_MAX_MS : s->backoff_ms * 2;
	atomic_store(&s->state, SINK_RETRYING);
}

/*
 * The URI for opening the sink again, after it wrote frames in this run: an
 * "overwrite=true" (or =1) among the options (dao_uri_path_len()) becomes
 * "overwrite=false", so that a reopen (after an error, or for a new frame size)
 * never replaces what this run recorded; "" when there is none.  overwrite
 * replaces a file that is there when the sink first opens, nothing after.
 */
void make_reopen_uri(const char *uri, char *out, size_t cap)
{
	static const char *const overwrite_key[] = {"overwrite", NULL};
	const char *q = uri + dao_uri_path_len(uri, overwrite_key); /* as the sinks split it */
	out[0] = '\0';
	if (!*q)
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
		dao_sink_attach_host(s->sink, &s->host);
		pthread_mutex_lock(&d->lock);
		struct dao_source_info in = d->src_info;
		if (d->have_cam) { /* the camera in use: configured intrinsics win over the source's */
			in.has_fov = 1;
			in.hfov = d->cam_hfov;
			in.vfov = d->cam_vfov;
		}
		pthread_mutex_unlock(&d->lock);
		struct dao_sink_format fmt = {
			.size = sizeof(struct dao_sink_format),
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
	struct dao_sink_frame_info info = {.size = sizeof(struct dao_sink_frame_info),
					   .stream = (enum dao_stream)it->stream,
					   .capture_ns = it->t_capture_ns,
					   .has_pose = it->has_pose};
	memcpy(info.pose_rotation, it->pose_q, sizeof info.pose_rotation);
	memcpy(info.pose_translation, it->pose_t, sizeof info.pose_translation);
	int r = dao_sink_write_stream(s->sink, &info, &it->frame, &err);
	if (it->stream != (int)s->cfg->stream) {
		/* a stream asked for besides (want_streams): the sink's counters and its
		   errors are those of its configured stream */
		return;
	}
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
		if (tool_mono_ns() - s->last_failure_ns >= (uint64_t)SINK_RETRY_MAX_MS * 1000000u)
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

void *sink_main(void *arg)
{
	struct sink_runner *s = arg;
	struct fq_item *it;
	char name[16]; /* the thread's name in top -H and /proc: "sink:NAME" (15 bytes) */
	snprintf(name, sizeof name, "sink:%.10s", s->cfg->name);
	prctl(PR_SET_NAME, name, 0, 0, 0);
	for (;;) {
		it = fq_pop(s->q, s->unflushed ? SINK_IDLE_FLUSH_MS : -1);
		if (!it) {
			if (fq_closed_and_empty(s->q))
				break;
			if (s->sink && s->unflushed)
				flush_idle_sink(s);
			continue;
		}
		if (atomic_load(&s->d->stop) && tool_mono_ns() >= atomic_load(&s->d->drain_deadline_ns)) {
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
		if (it->stream != (int)s->cfg->stream) {
			/* another stream the sink asked for: only to an open sink that takes it */
			if (s->sink && dao_sink_takes_streams(s->sink))
				write_frame(s, it);
			fq_done(s->q, it);
			continue;
		}
		if (s->sink && (it->frame.format != s->fmt || it->frame.width != s->fmt_w ||
				it->frame.height != s->fmt_h)) {
			log_info("sink %s: the stream is now %ux%u; reopening", s->cfg->name,
				 it->frame.width, it->frame.height);
			close_sink(s);
		}
		if (!s->sink && (tool_mono_ns() < s->next_open_ns || open_sink(s, it) < 0)) {
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
	snprintf(what, sizeof what, "sink %s control", s->cfg->name);
	log_limit_flush(&s->control_log, LOG_INFO, what);
	atomic_store(&s->done, 1);
	return NULL;
}
