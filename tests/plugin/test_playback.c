/* SPDX-License-Identifier: MIT */
/*
 * The playback cursor of the recording sources (src/io/plugin/playback.c): which
 * frames a read delivers (start, step, the end, loop), frames that fail and are
 * skipped, a recording none of whose frames can be read, and the real-time
 * pacing decisions against a fake clock.
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "plugin/playback.h"

/* The fake clock: now, what was slept, how often it was asked. */
static uint64_t g_now_ns;
static int64_t g_slept_us;
static int g_clock_calls;

static uint64_t fake_now(void)
{
	g_clock_calls++;
	return g_now_ns;
}

static void fake_sleep(int64_t us)
{
	g_clock_calls++;
	g_slept_us += us;
	g_now_ns += (uint64_t)us * 1000;
}

static void init(struct dao_playback_cursor *p, uint64_t count, uint32_t start, uint32_t step, int loop,
		 enum dao_playback mode)
{
	struct dao_source_options o = DAO_SOURCE_OPTIONS_INIT;
	o.start_frame = start;
	o.step = step;
	o.loop = loop;
	o.playback = mode;
	dao_playback_init(p, &o, count);
	p->now_ns = fake_now;
	p->sleep_us = fake_sleep;
	g_now_ns = 5000000000u;
	g_slept_us = 0;
	g_clock_calls = 0;
}

/*
 * One read of a recording whose frames in `bad` (a bit mask) fail: the index
 * delivered, or -1000 + the status.  err receives a failure's message.
 */
static long long read_one(struct dao_playback_cursor *p, uint64_t bad, struct dao_error *err)
{
	uint64_t i;
	int r = dao_playback_next(p, &i, err);
	if (r)
		return -1000 + r;
	if (bad >> i & 1) {
		dao_error_set(err, -EINVAL, "frame %llu is corrupt", (unsigned long long)i);
		return -1000 + dao_playback_skip(p, -EINVAL, err);
	}
	assert_int_equal(dao_playback_pace(p, i * 33333, 1000), 0);
	uint64_t got = dao_playback_advance(p);
	assert_int_equal(got, i);
	return (long long)got;
}

static void expect_reads(struct dao_playback_cursor *p, uint64_t bad, const long long *want, size_t n)
{
	struct dao_error err;
	for (size_t k = 0; k < n; k++) {
		long long got = read_one(p, bad, &err);
		if (got != want[k])
			fail_msg("read %zu: %lld, expected %lld", k, got, want[k]);
	}
}

#define EOS (-1000 + DAO_SOURCE_EOS)
#define BAD (-1000 - EINVAL)
#define DEAD (-1000 - EIO)

static void test_end_without_loop(void **state)
{
	(void)state;
	struct dao_playback_cursor p;
	init(&p, 4, 0, 0, 0, DAO_PLAYBACK_MANUAL); /* step 0: every frame */
	const long long want[] = {0, 1, 2, 3, EOS, EOS};
	expect_reads(&p, 0, want, 6);
}

static void test_loop_wraps_to_start(void **state)
{
	(void)state;
	struct dao_playback_cursor p;
	init(&p, 5, 1, 1, 1, DAO_PLAYBACK_MANUAL);
	const long long want[] = {1, 2, 3, 4, 1, 2, 3, 4, 1};
	expect_reads(&p, 0, want, 9);
}

static void test_start_and_step(void **state)
{
	(void)state;
	struct dao_playback_cursor p;
	init(&p, 10, 2, 3, 0, DAO_PLAYBACK_MANUAL);
	const long long want[] = {2, 5, 8, EOS};
	expect_reads(&p, 0, want, 4);
	init(&p, 10, 2, 3, 1, DAO_PLAYBACK_MANUAL);
	const long long looped[] = {2, 5, 8, 2, 5, 8, 2};
	expect_reads(&p, 0, looped, 7);
	/* a seek, then on by the step from there, the wrap back to start */
	dao_playback_seek(&p, 6);
	const long long sought[] = {6, 9, 2, 5};
	expect_reads(&p, 0, sought, 4);
}

/* Three bad frames in a row fail one read each; the good ones after them come. */
static void test_bad_frames_skipped(void **state)
{
	(void)state;
	struct dao_playback_cursor p;
	struct dao_error err;
	init(&p, 7, 0, 1, 1, DAO_PLAYBACK_MANUAL);
	const uint64_t bad = 1u << 2 | 1u << 3 | 1u << 4;
	const long long want[] = {0, 1, BAD, BAD, BAD, 5, 6, 0, 1, BAD, BAD, BAD, 5};
	expect_reads(&p, bad, want, 13);
	/* and the last ones, with no good frame after them before the wrap */
	init(&p, 4, 0, 1, 1, DAO_PLAYBACK_MANUAL);
	const long long tail[] = {0, BAD, BAD, BAD, 0, BAD};
	expect_reads(&p, 0xE, tail, 6);
	/* without loop: the bad ones, then the end */
	init(&p, 4, 1, 1, 0, DAO_PLAYBACK_MANUAL);
	const long long once[] = {1, BAD, BAD, EOS};
	expect_reads(&p, 0xC, once, 4);
	assert_int_equal(read_one(&p, 0xC, &err), EOS);
}

/*
 * Every frame bad: with loop, after one whole pass of failures the reads end
 * in -EIO, with a message that says so and gives the last failure; without
 * loop, the end of the recording.
 */
static void test_all_frames_bad(void **state)
{
	(void)state;
	struct dao_playback_cursor p;
	struct dao_error err;
	init(&p, 9, 1, 3, 1, DAO_PLAYBACK_MANUAL); /* frames 1, 4, 7 */
	const long long want[] = {BAD, BAD, BAD, DEAD, DEAD, DEAD};
	expect_reads(&p, ~0ull, want, 6);
	assert_int_equal(read_one(&p, ~0ull, &err), DEAD);
	assert_int_equal(err.code, -EIO);
	assert_non_null(strstr(err.message, "no frame can be read: all 3 from frame 1 (every 3)"));
	assert_non_null(strstr(err.message, "frame 7 is corrupt"));
	/* a seek tries again */
	dao_playback_seek(&p, 4);
	assert_int_equal(read_one(&p, 1u << 4, &err), BAD);
	assert_int_equal(read_one(&p, 1u << 4, &err), 7);
	assert_int_equal(read_one(&p, 1u << 4, &err), 1);

	init(&p, 3, 0, 1, 0, DAO_PLAYBACK_MANUAL);
	const long long once[] = {BAD, BAD, BAD, EOS, EOS};
	expect_reads(&p, ~0ull, once, 5);
}

/* A pass that began at a seek is not the whole recording: its failures do not end it. */
static void test_seek_pass_not_whole(void **state)
{
	(void)state;
	struct dao_playback_cursor p;
	init(&p, 4, 0, 1, 1, DAO_PLAYBACK_MANUAL);
	dao_playback_seek(&p, 2);
	const long long want[] = {BAD, BAD, 0, 1, BAD, BAD, 0};
	expect_reads(&p, 0xC, want, 7);
	/* one good frame in a pass keeps it going, however many fail */
	init(&p, 6, 0, 1, 1, DAO_PLAYBACK_MANUAL);
	const long long one[] = {BAD, BAD, BAD, BAD, BAD, 5, BAD, BAD, BAD, BAD, BAD, 5};
	expect_reads(&p, 0x1F, one, 12);
}

/* Manual playback never looks at the clock. */
static void test_manual_not_paced(void **state)
{
	(void)state;
	struct dao_playback_cursor p;
	init(&p, 3, 0, 1, 0, DAO_PLAYBACK_MANUAL);
	assert_int_equal(dao_playback_pace(&p, 0, 1000), 0);
	assert_int_equal(dao_playback_pace(&p, 10000000, 1000), 0);
	assert_int_equal(g_clock_calls, 0);
}

/*
 * Real time: the first frame is due at once and starts the clock; a later one
 * waits for its timestamp's distance from the first, less the time already
 * gone; a wait beyond the timeout waits the timeout and says -EAGAIN, the rest
 * is waited next time; a late frame does not wait.
 */
static void test_realtime_decisions(void **state)
{
	(void)state;
	struct dao_playback_cursor p;
	init(&p, 10, 0, 1, 1, DAO_PLAYBACK_REALTIME);
	assert_int_equal(dao_playback_pace(&p, 1000000, 1000), 0);
	assert_int_equal(g_slept_us, 0);
	g_now_ns += 10000000; /* 10 ms of processing */
	assert_int_equal(dao_playback_pace(&p, 1033333, 1000), 0);
	assert_int_equal(g_slept_us, 23333);
	/* 66.666 ms after the first, now 33.333 ms after it: 33.333 ms to wait */
	assert_int_equal(dao_playback_pace(&p, 1066666, 20), -EAGAIN);
	assert_int_equal(g_slept_us, 23333 + 20000);
	assert_int_equal(dao_playback_pace(&p, 1066666, 20), 0);
	assert_int_equal(g_slept_us, 23333 + 33333);
	/* a timeout of -1 waits as long as it takes, 0 not at all */
	assert_int_equal(dao_playback_pace(&p, 3000000, -1), 0);
	assert_int_equal(g_slept_us, 2000000 - 10000); /* all but the processing */
	assert_int_equal(dao_playback_pace(&p, 3100000, 0), -EAGAIN);
	assert_int_equal(g_slept_us, 1990000);
	/* late (the processing took 150 ms): at once */
	g_now_ns += 150000000;
	assert_int_equal(dao_playback_pace(&p, 3100000, 1000), 0);
	assert_int_equal(g_slept_us, 1990000);
	/* earlier than the first: the clock starts again from it */
	assert_int_equal(dao_playback_pace(&p, 500000, 1000), 0);
	assert_int_equal(dao_playback_pace(&p, 600000, 1000), 0);
	assert_int_equal(g_slept_us, 1990000 + 100000);
}

/* A start, a seek and a loop's wrap each start the clock again at the next frame. */
static void test_realtime_clock_restarts(void **state)
{
	(void)state;
	struct dao_playback_cursor p;
	struct dao_error err;
	uint64_t i;
	init(&p, 3, 0, 1, 1, DAO_PLAYBACK_REALTIME);
	assert_int_equal(dao_playback_pace(&p, 0, 1000), 0);
	dao_playback_restart(&p);
	assert_int_equal(dao_playback_pace(&p, 500000, 1000), 0);
	assert_int_equal(g_slept_us, 0);
	dao_playback_seek(&p, 2);
	assert_int_equal(dao_playback_pace(&p, 900000, 1000), 0);
	assert_int_equal(g_slept_us, 0);
	/* frame 2, then the wrap to 0: stamped 0 again, but also a later stamp would
	 * be due at once after a wrap */
	assert_int_equal(dao_playback_next(&p, &i, &err), 0);
	assert_int_equal(i, 2);
	assert_int_equal(dao_playback_advance(&p), 2);
	assert_int_equal(dao_playback_next(&p, &i, &err), 0);
	assert_int_equal(i, 0);
	assert_int_equal(dao_playback_pace(&p, 5000000, 1000), 0);
	assert_int_equal(g_slept_us, 0);
	assert_int_equal(dao_playback_pace(&p, 5033333, 1000), 0);
	assert_int_equal(g_slept_us, 33333);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_end_without_loop),
		cmocka_unit_test(test_loop_wraps_to_start),
		cmocka_unit_test(test_start_and_step),
		cmocka_unit_test(test_bad_frames_skipped),
		cmocka_unit_test(test_all_frames_bad),
		cmocka_unit_test(test_seek_pass_not_whole),
		cmocka_unit_test(test_manual_not_paced),
		cmocka_unit_test(test_realtime_decisions),
		cmocka_unit_test(test_realtime_clock_restarts),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
