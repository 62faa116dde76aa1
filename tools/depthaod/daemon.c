/* SPDX-License-Identifier: MIT */
/*
 * The daemon's life cycle: creating, starting and stopping the threads, and
 * what the control socket changes (parameters, pause).
 */
#define _GNU_SOURCE /* pthread_timedjoin_np */

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>

#include "daemon_internal.h"

/* Sleeps up to ms, returning early when the daemon stops. */
void nap(struct daemon *d, unsigned ms)
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

int daemon_create(struct daemon **out, const struct daemon_config *cfg,
		  const struct dao_plugins *plugins, char *msg, size_t len)
{
	struct daemon *d = calloc(1, sizeof(*d));
	if (!d) {
		snprintf(msg, len, "out of memory");
		return -ENOMEM;
	}
	atomic_init(&d->mem_rss, -1); /* not measured yet */
	atomic_init(&d->mem_heap, -1);
	d->cfg = *cfg;
	d->plugins = plugins;
	d->lossless = cfg->playback == DAO_PLAYBACK_MANUAL;
	d->snapshot_notify_fd = -1;
	d->source_log = (struct log_limit)LOG_LIMIT_INIT(60000, 5);
	pthread_mutex_init(&d->lock, NULL);
	d->pose = (struct dao_pose_track)DAO_POSE_TRACK_INIT;
	d->pose.rotation[0] = d->pose.rotation[4] = d->pose.rotation[8] = 1.0;
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
		sink_host_init(s);
		make_reopen_uri(s->cfg->uri, s->reopen_uri, sizeof s->reopen_uri);
		pthread_mutex_init(&s->lat_lock, NULL);
		pthread_mutex_init(&s->control_lock, NULL);
		if (fq_create(&s->q, s->cfg->queue) < 0) {
			snprintf(msg, len, "out of memory");
			daemon_destroy(d);
			return -ENOMEM;
		}
		d->nsinks++;
		d->wants[s->cfg->stream] = 1;
		if (sink_may_want_any_stream(s->cfg))
			d->wants_color = 1;
	}
	*out = d;
	return 0;
}

int daemon_start(struct daemon *d, char *msg, size_t len)
{
	d->start_ns = d->interval_start_ns = tool_mono_ns();
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
int join_by(pthread_t t, int *running, uint64_t deadline, const char *what)
{
	if (!*running)
		return 1;
	uint64_t n = tool_mono_ns();
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

void daemon_stop(struct daemon *d)
{
	if (daemon_finished(d)) { /* the natural end: everything has drained already */
		join(d->capture, &d->capture_running);
		join(d->process, &d->process_running);
		for (unsigned i = 0; i < d->nsinks; i++)
			join(d->sinks[i].thread, &d->sinks[i].running);
		if (!stop_snapshot_writer(d, tool_mono_ns() + (uint64_t)STOP_DEADLINE_MS * 1000000u))
			d->stragglers = 1;
		return;
	}
	uint64_t t0 = tool_mono_ns();
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
		pthread_mutex_destroy(&d->sinks[i].control_lock);
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
	/* the motion switched off (the library's rule, src/motion/pose_track.c, which
	 * is not public): switched on again, even before the next frame, the pose
	 * starts over (take_settings), as the library's track does when it sees the
	 * motion off */
	if (p->depth_temporal <= 0.0f || p->depth_temporal_motion == DAO_DEPTH_MOTION_OFF)
		d->pose_restart = 1;
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
