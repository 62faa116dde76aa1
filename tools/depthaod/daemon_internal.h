/* SPDX-License-Identifier: MIT */
/*
 * What the daemon's files share (daemon.c, daemon_capture.c, daemon_process.c,
 * daemon_sinks.c, daemon_snapshot.c, daemon_stats.c): the state of the
 * pipeline and its threads.  Not an interface: daemon.h is.
 */
#ifndef DAOD_DAEMON_INTERNAL_H
#define DAOD_DAEMON_INTERNAL_H

#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>
#include <time.h>

#include "common/tool_clock.h"
#include "daemon.h"
#include "frame_queue.h"
#include "log.h"

#define DEG2RAD (3.14159265358979323846 / 180.0)
#define DEFAULT_HFOV_DEG 58.5
#define DEFAULT_VFOV_DEG 45.6
#define LATENCY_RING 512
#define RECENT_SECONDS 5 /* fps_recent: the rate over this many whole seconds */
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
	struct dao_sink_host host;    /* what the sink may ask (user: this runner) */
	atomic_uint extra_streams;    /* streams asked for besides cfg->stream (1u << stream) */
	pthread_mutex_t control_lock; /* the sink's parameter changes, one at a time; control_log */
	struct log_limit control_log;
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
	int wants[STREAM_COUNT];       /* the sinks' configured streams */
	int wants_color;              /* a sink may ask for the overlay at run time */
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
	/* (capture thread) the source's camera poses, for depth-temporal-motion source and
	   source+icp: given up (the source has none, said once), frames without one */
	int poses_off;
	uint64_t pose_gaps;
	atomic_ullong source_call_ns; /* when the capture thread entered a source call, 0 = none */
	int watchdog_withheld;        /* (processing thread) pings stopped for a hung source */
	atomic_ullong cpu_ns_total;
	uint64_t start_ns;
	/* the process's memory as the stats last measured it (daemon_stats.c):
	 * measured at most once a second, whoever asks (/api/stats is the network's) */
	atomic_ullong mem_ns;
	atomic_llong mem_rss, mem_heap;
	uint64_t interval_start_ns, interval_processed;
	/* (lock) frames processed per whole second of the monotonic clock, the last
	   RECENT_SECONDS + 1 of them: fps_recent, the rate of the last RECENT_SECONDS
	   complete seconds (fps is the mean over the interval) */
	uint64_t recent_sec[RECENT_SECONDS + 1];
	unsigned recent_count[RECENT_SECONDS + 1];
	/* (lock) the camera's pose track (dao_context_pose_track) and the last frame's
	 * motion estimate (stats "motion") */
	struct dao_pose_track pose;
	int motion_state, motion_reason;
	int motion_followed; /* the last frame followed the motion (its track ran) */
	/* (lock) the motion was switched off by new parameters: the track ends at the
	 * next frame, though the parameters that reach it follow the motion again */
	int pose_restart;
};

/* daemon_stats.c: counts one processed frame for fps_recent */
void daemon_count_recent(struct daemon *d, uint64_t now_ns);

/* daemon.c: sleeps up to ms, returning early when the daemon stops */
void nap(struct daemon *d, unsigned ms);
/* daemon.c: joins a thread by the deadline; 0 if it is still running then (logged if `what`) */
int join_by(pthread_t t, int *running, uint64_t deadline, const char *what);

/* the threads (arg: the daemon; a sink's: its struct sink_runner) */
void *capture_main(void *arg);  /* daemon_capture.c */
void *process_main(void *arg);  /* daemon_process.c */
void *snapshot_main(void *arg); /* daemon_snapshot.c */
void *sink_main(void *arg);     /* daemon_sinks.c */

/* daemon_snapshot.c: hands a shaded frame to the snapshot thread (the processing thread) */
void take_snapshot(struct daemon *d, const struct dao_frame *rgb);
/* daemon_snapshot.c: ends the snapshot thread by the deadline; 0 if it is still writing */
int stop_snapshot_writer(struct daemon *d, uint64_t deadline);

/* daemon_sinks.c: what a sink may ask of the daemon (struct dao_sink_host, user: its runner) */
void sink_host_init(struct sink_runner *s);
/* daemon_sinks.c: the streams some sink wants this frame (1u << enum stream_kind) */
unsigned sinks_wanted_streams(struct daemon *d);
/* daemon_sinks.c: a sink that may ask for any stream at run time (the http viewer) */
int sink_may_want_any_stream(const struct sink_config *cfg);
/* daemon_sinks.c: the URI a sink is reopened with (overwrite=true turned off), "" if the same */
void make_reopen_uri(const char *uri, char *out, size_t cap);

#endif
