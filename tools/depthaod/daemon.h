/* SPDX-License-Identifier: MIT */
/*
 * The running pipeline: a capture thread (source -> input queue), a
 * processing thread (AO, shading, fan-out to every sink's own queue) and
 * one thread per sink.  A slow sink fills only its own queue: live sources
 * and real-time playback drop the oldest frames there (counted); manual
 * playback of a file waits instead and loses nothing.
 */
#ifndef DAOD_DAEMON_H
#define DAOD_DAEMON_H

#include <stddef.h>

#include <json-c/json.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

#include "config.h"

struct daemon;

int daemon_create(struct daemon **out, const struct daemon_config *cfg,
		  const struct dao_plugins *plugins, char *msg, size_t len);
int daemon_start(struct daemon *d, char *msg, size_t len);
/*
 * 1 once every thread has finished: the pipeline ended by itself (end of a
 * recording, max_frames, a fatal error) and every queue has drained.
 */
int daemon_finished(struct daemon *d);
/* 1 if a fatal error ended the pipeline (the process should exit non-zero). */
int daemon_failed(struct daemon *d);
/*
 * After daemon_finished: joins the threads.  Before (a signal): stops within a
 * second; queued frames are written while the deadlines allow (drain_on_stop)
 * or dropped, counted either way, and every sink finalises its output.
 */
void daemon_stop(struct daemon *d);
/* 1 if a thread missed daemon_stop's deadline (the process should exit now). */
int daemon_stragglers(struct daemon *d);
/* How many of them are sinks (whose output may then be incomplete). */
int daemon_sinks_unfinished(struct daemon *d);
void daemon_destroy(struct daemon *d);

/* AO parameters, applied between frames. */
void daemon_set_params(struct daemon *d, const struct dao_params *p);
void daemon_get_params(struct daemon *d, struct dao_params *p);
void daemon_set_paused(struct daemon *d, int paused);
/*
 * Asks for the next shaded frame to be written to `path` (PNG) without
 * waiting: 0, -EAGAIN (paused), -EBUSY (one is in progress), with msg.  When
 * it is done, a byte is written to notify_fd (-1: none; make it non-blocking).
 */
int daemon_snapshot_request(struct daemon *d, const char *path, int notify_fd, char *msg,
			    size_t len);
/* 1 while pending, 0 once written, -errno with msg if writing failed. */
int daemon_snapshot_result(struct daemon *d, char *msg, size_t len);
/*
 * Gives the request up (a frame already being written is finished, by the
 * snapshot thread, unreported); 1 if it was being written, 0 if no frame came.
 */
int daemon_snapshot_cancel(struct daemon *d);

/* Counters since start and over the last interval (the interval restarts). */
struct json_object *daemon_stats(struct daemon *d, int reset_interval);

#endif
