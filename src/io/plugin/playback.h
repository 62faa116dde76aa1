/* SPDX-License-Identifier: MIT */
/*
 * The playback cursor of the built-in recording sources (oni, bag, images):
 * which frame a read delivers (start_frame, every step-th, the end or a wrap
 * to start_frame with `loop`), the skipping of frames that cannot be read,
 * and real-time pacing by the frames' timestamps.  A source's read is
 *
 *	if ((r = dao_playback_next(&p, &i, err)))
 *		return r;                              EOS, or no frame can be read
 *	if ((r = load frame i) < 0)
 *		return dao_playback_skip(&p, r, err);  the next read goes on after it
 *	if ((r = dao_playback_pace(&p, ts_us, timeout_ms)) < 0)
 *		return r;                              -EAGAIN: frame i again next time
 *	f->index = dao_playback_advance(&p);
 */
#ifndef DAO_PLUGIN_PLAYBACK_H
#define DAO_PLUGIN_PLAYBACK_H

#include <stdint.h>

#include <depthao/error.h>
#include <depthao/plugin.h>

struct dao_playback_cursor {
	uint64_t count;             /* frames in the recording */
	uint64_t start, step;       /* the options' start_frame, step (0 taken as 1) */
	int loop, realtime;
	uint64_t next;              /* the frame the next read delivers */
	/* this pass over the recording: it began at start (not at a seek), and
	 * how many of its frames were delivered */
	int pass_whole;
	uint64_t pass_delivered;
	int unreadable;             /* a whole pass failed: every read is -EIO */
	char last_error[DAO_ERROR_MESSAGE_MAX]; /* the last failure's message */
	/* real-time pacing: the clock starts at the first frame (again after a
	 * start, a seek or a wrap) */
	int clock_started;
	uint64_t clock_start_ns;
	uint64_t ts_start_us;       /* the timestamp delivered at clock_start_ns */
	/* the clock, dao_mono_ns() and dao_sleep_us() (a test's fake one) */
	uint64_t (*now_ns)(void);
	void (*sleep_us)(int64_t us);
};

/* A cursor at opts->start_frame of a recording of `count` frames (start_frame < count). */
void dao_playback_init(struct dao_playback_cursor *p, const struct dao_source_options *opts,
		       uint64_t count);

/* The source's start: the next frame starts the real-time clock again. */
void dao_playback_restart(struct dao_playback_cursor *p);

/* The next read delivers frame `index` (< count, checked by the source). */
void dao_playback_seek(struct dao_playback_cursor *p, uint64_t index);

/*
 * The frame to read, in *index.  DAO_SOURCE_EOS at the end without loop; with
 * loop, once every frame of a whole pass has failed in a row, -EIO with a
 * message (again on every read until a seek or start): a recording none of
 * whose frames can be read ends instead of failing forever.
 */
int dao_playback_next(struct dao_playback_cursor *p, uint64_t *index, struct dao_error *err);

/* Frame *index could not be read (error r, described in err): it is skipped. Returns r. */
int dao_playback_skip(struct dao_playback_cursor *p, int r, const struct dao_error *err);

/*
 * Real-time playback: waits until the frame stamped ts_us is due (the first
 * frame, and one stamped earlier than the clock's start, are due at once and
 * start the clock); -EAGAIN if that is beyond timeout_ms (>= 0), after
 * waiting that long (the frame is read again next time).  Manual: 0 at once.
 */
int dao_playback_pace(struct dao_playback_cursor *p, uint64_t ts_us, int timeout_ms);

/* The frame was delivered: returns its index; the cursor moves on. */
uint64_t dao_playback_advance(struct dao_playback_cursor *p);

#endif
