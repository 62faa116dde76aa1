/* SPDX-License-Identifier: MIT */
/* Real-time playback of a recording: each frame waits for its timestamp's moment. */
#ifndef DAO_PLUGIN_PACER_H
#define DAO_PLUGIN_PACER_H

#include <errno.h>
#include <stdint.h>

#include "core/clock.h"

struct dao_pacer {
	int started;            /* clock_start_ns / ts_start_us are set */
	uint64_t clock_start_ns;
	uint64_t ts_start_us;   /* the timestamp played at clock_start_ns */
};

/* The next frame starts the clock again (a seek, a loop, a new start). */
static inline void dao_pacer_reset(struct dao_pacer *p)
{
	p->started = 0;
}

/*
 * Waits until the frame stamped ts_us is due (the first frame, and one
 * stamped earlier than the first, are due at once and start the clock);
 * -EAGAIN if that is beyond timeout_ms (>= 0), after waiting that long.
 */
static inline int dao_pacer_wait(struct dao_pacer *p, uint64_t ts_us, int timeout_ms)
{
	if (!p->started || ts_us < p->ts_start_us) {
		p->clock_start_ns = dao_mono_ns();
		p->ts_start_us = ts_us;
		p->started = 1;
		return 0;
	}
	const int64_t due = (int64_t)(ts_us - p->ts_start_us) - dao_mono_us_since(p->clock_start_ns);
	if (due <= 0)
		return 0;
	int64_t wait = due;
	if (timeout_ms >= 0 && wait > (int64_t)timeout_ms * 1000)
		wait = (int64_t)timeout_ms * 1000;
	dao_sleep_us(wait);
	return wait < due ? -EAGAIN : 0;
}

#endif
