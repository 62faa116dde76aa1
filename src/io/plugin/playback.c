/* SPDX-License-Identifier: MIT */
/* The playback cursor of the built-in recording sources (playback.h). */
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "core/clock.h"
#include "core/error_internal.h"
#include "plugin/playback.h"

static uint64_t mono_ns(void)
{
	return dao_mono_ns();
}

static void sleep_us(int64_t us)
{
	dao_sleep_us(us);
}

static void new_pass(struct dao_playback_cursor *p, int whole)
{
	p->pass_whole = whole;
	p->pass_delivered = 0;
	p->clock_started = 0; /* the timestamps start again */
}

void dao_playback_init(struct dao_playback_cursor *p, const struct dao_source_options *opts,
		       uint64_t count)
{
	memset(p, 0, sizeof(*p));
	p->count = count;
	p->start = opts->start_frame;
	p->step = opts->step ? opts->step : 1;
	p->loop = opts->loop;
	p->realtime = opts->playback == DAO_PLAYBACK_REALTIME;
	p->next = p->start;
	p->now_ns = mono_ns;
	p->sleep_us = sleep_us;
	new_pass(p, 1);
}

void dao_playback_restart(struct dao_playback_cursor *p)
{
	p->unreadable = 0;
	p->clock_started = 0;
}

void dao_playback_seek(struct dao_playback_cursor *p, uint64_t index)
{
	p->next = index;
	p->unreadable = 0;
	new_pass(p, index == p->start);
}

int dao_playback_next(struct dao_playback_cursor *p, uint64_t *index, struct dao_error *err)
{
	if (p->next >= p->count) {
		if (!p->loop)
			return DAO_SOURCE_EOS;
		/* with loop, a pass from the start that delivered nothing (each of its
		 * frames failed) would fail again forever */
		if (p->pass_whole && !p->pass_delivered)
			p->unreadable = 1;
		p->next = p->start;
		new_pass(p, 1);
	}
	if (p->unreadable)
		return dao_error_set(err, -EIO,
				     "no frame can be read: all %llu from frame %llu (every %llu) "
				     "failed; the last: %s",
				     (unsigned long long)((p->count - p->start + p->step - 1) / p->step),
				     (unsigned long long)p->start, (unsigned long long)p->step,
				     p->last_error);
	*index = p->next;
	return 0;
}

int dao_playback_skip(struct dao_playback_cursor *p, int r, const struct dao_error *err)
{
	snprintf(p->last_error, sizeof(p->last_error), "%s",
		 err && err->message[0] ? err->message : dao_strerror(r));
	p->next += p->step;
	return r;
}

int dao_playback_pace(struct dao_playback_cursor *p, uint64_t ts_us, int timeout_ms)
{
	if (!p->realtime)
		return 0;
	const uint64_t now = p->now_ns();
	if (!p->clock_started || ts_us < p->ts_start_us) {
		p->clock_start_ns = now;
		p->ts_start_us = ts_us;
		p->clock_started = 1;
		return 0;
	}
	const int64_t due = (int64_t)(ts_us - p->ts_start_us) -
			    ((int64_t)now - (int64_t)p->clock_start_ns) / 1000;
	if (due <= 0)
		return 0;
	int64_t wait = due;
	if (timeout_ms >= 0 && wait > (int64_t)timeout_ms * 1000)
		wait = (int64_t)timeout_ms * 1000;
	p->sleep_us(wait);
	return wait < due ? -EAGAIN : 0;
}

uint64_t dao_playback_advance(struct dao_playback_cursor *p)
{
	const uint64_t index = p->next;
	p->pass_delivered++;
	p->next += p->step;
	return index;
}
