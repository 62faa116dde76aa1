/* SPDX-License-Identifier: MIT */
/*
 * The daemon's statistics as JSON (`ctl stats`, stats_json).
 */

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#if DAOD_HAVE_MALLINFO2
#include <malloc.h>
#endif

#include <depthao/pose.h>

#include "daemon_internal.h"

static const char *const sink_state_names[] = {"waiting", "running", "retrying", "stopped"};

static int cmp_u32(const void *a, const void *b)
{
	uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
	return x < y ? -1 : x > y;
}

void daemon_count_recent(struct daemon *d, uint64_t now_ns)
{
	const uint64_t sec = now_ns / 1000000000u;
	const unsigned slot = (unsigned)(sec % (RECENT_SECONDS + 1));
	pthread_mutex_lock(&d->lock);
	if (d->recent_sec[slot] != sec) {
		d->recent_sec[slot] = sec;
		d->recent_count[slot] = 0;
	}
	d->recent_count[slot]++;
	pthread_mutex_unlock(&d->lock);
}

/* The frames of the RECENT_SECONDS whole seconds before the current one, per second
   (with d->lock held).  Younger than that, every frame over the time since start. */
static double fps_recent(const struct daemon *d, uint64_t now_ns)
{
	const uint64_t sec = now_ns / 1000000000u;
	const uint64_t young = d->start_ns / 1000000000u + RECENT_SECONDS >= sec;
	const uint64_t from = young ? 0 : sec - RECENT_SECONDS;
	unsigned long long n = 0;
	for (unsigned i = 0; i <= RECENT_SECONDS; i++)
		if ((young || d->recent_sec[i] < sec) && d->recent_sec[i] >= from)
			n += d->recent_count[i];
	const double secs = young ? (double)(now_ns - d->start_ns) / 1e9 : RECENT_SECONDS;
	return secs > 0 ? (double)n / secs : 0;
}

static const char *const motion_state_names[] = {"none", "refused", "still", "applied"};

/* "motion": the last frame's camera-motion estimate and the pose the context's track
   accumulated from them (dao_context_pose_track); the lock held */
static struct json_object *motion_stats(const struct daemon *d)
{
	const struct dao_pose_track *p = &d->pose;
	struct json_object *m = json_object_new_object();
	const int s = d->motion_state >= 0 && d->motion_state <= 3 ? d->motion_state : 0;
	double q[4];
	dao_pose_matrix_to_quat(p->rotation, q);
	json_object_object_add(m, "followed", json_object_new_boolean(d->motion_followed));
	json_object_object_add(m, "state", json_object_new_string(motion_state_names[s]));
	json_object_object_add(m, "reason", json_object_new_int(d->motion_reason));
	json_object_object_add(m, "frames_accepted", json_object_new_int64((int64_t)p->accepted));
	json_object_object_add(m, "frames_refused", json_object_new_int64((int64_t)p->refused));
	struct json_object *t = json_object_new_array(), *qa = json_object_new_array();
	for (int i = 0; i < 3; i++)
		json_object_array_add(t, json_object_new_double(p->translation[i]));
	for (int i = 0; i < 4; i++)
		json_object_array_add(qa, json_object_new_double(q[i]));
	json_object_object_add(m, "position_m", t);
	json_object_object_add(m, "orientation_xyzw", qa);
	return m;
}

/*
 * The process's memory: resident (/proc/self/statm) and, with glibc, what the
 * allocator has handed out and not had back (mallinfo2: every arena's chunks
 * in use, those in its per-thread caches included, plus the mmapped ones;
 * not thread stacks or other mmaps).  A leak of allocated memory grows
 * heap_in_use_bytes; the resident size also holds what the allocator keeps
 * for reuse (its per-thread arenas), which settles after the first busy
 * minutes.  -1 where not known (no /proc; not glibc, or an allocator such as
 * ASan's that leaves mallinfo2 empty).  mallinfo2 locks every arena in turn,
 * so it runs at most once a second whoever asks (the viewer's /api/stats
 * included); the others get the last figures.
 */
static struct json_object *memory_stats(struct daemon *d, uint64_t now_ns)
{
	unsigned long long last = atomic_load(&d->mem_ns);
	if (!last || now_ns - last >= 1000000000u) {
		if (atomic_compare_exchange_strong(&d->mem_ns, &last, now_ns ? now_ns : 1)) {
			long long rss = -1, heap = -1;
			FILE *f = fopen("/proc/self/statm", "re");
			if (f) {
				long long pages;
				const long page = sysconf(_SC_PAGESIZE);
				if (fscanf(f, "%*s %lld", &pages) == 1 && page > 0)
					rss = pages * page;
				fclose(f);
			}
#if DAOD_HAVE_MALLINFO2
			const struct mallinfo2 mi = mallinfo2();
			if (mi.arena || mi.hblkhd)
				heap = (long long)(mi.uordblks + mi.hblkhd);
#endif
			atomic_store(&d->mem_rss, rss);
			atomic_store(&d->mem_heap, heap);
		}
	}
	struct json_object *m = json_object_new_object();
	json_object_object_add(m, "rss_bytes", json_object_new_int64(atomic_load(&d->mem_rss)));
	json_object_object_add(m, "heap_in_use_bytes", json_object_new_int64(atomic_load(&d->mem_heap)));
	return m;
}

struct json_object *daemon_stats(struct daemon *d, int reset_interval)
{
	uint64_t t = tool_mono_ns();
	/* the counters downstream first (every frame is counted upstream before it
	 * goes on), so that one reply has sink frames_out <= frames_processed <=
	 * frames_in however the threads run meanwhile */
	unsigned long long written[DAOD_MAX_SINKS];
	for (unsigned i = 0; i < d->nsinks; i++)
		written[i] = atomic_load(&d->sinks[i].written);
	unsigned long long processed = atomic_load(&d->processed);
	const unsigned long long captured = atomic_load(&d->captured);
	pthread_mutex_lock(&d->lock);
	double secs = (double)(t - d->interval_start_ns) / 1e9;
	double fps = secs > 0 ? (double)(processed - d->interval_processed) / secs : 0;
	const double fps_last = fps_recent(d, t);
	struct json_object *motion = motion_stats(d);
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
	json_object_object_add(j, "frames_in", json_object_new_int64((int64_t)captured));
	json_object_object_add(j, "frames_dropped_in", json_object_new_int64((int64_t)atomic_load(&d->input_dropped)));
	json_object_object_add(j, "frames_processed", json_object_new_int64((int64_t)processed));
	json_object_object_add(j, "process_errors", json_object_new_int64((int64_t)atomic_load(&d->process_errors)));
	json_object_object_add(j, "fps", json_object_new_double(fps));
	json_object_object_add(j, "fps_recent", json_object_new_double(fps_last));
	json_object_object_add(j, "fps_recent_window_s", json_object_new_int(RECENT_SECONDS));
	json_object_object_add(j, "memory", memory_stats(d, t));
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
		json_object_object_add(o, "frames_out", json_object_new_int64((int64_t)written[i]));
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
	json_object_object_add(j, "motion", motion);
	return j;
}
