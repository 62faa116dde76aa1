/* SPDX-License-Identifier: MIT */
/*
 * dao_pool_run_threads: every row is processed exactly once, and the thread
 * index a band is told is in range and never held by two bands at once (the
 * tile kernels index their per-thread scratch with it).
 */
#include <stdatomic.h>
#include <string.h>

#include "common/cmocka_all.h"
#include "core/threadpool.h"

#define ROWS 4000

struct job {
	int threads;
	atomic_int seen[ROWS];
	atomic_int holder[64];   /* bands running on each index now */
	atomic_int overlaps, out_of_range;
	atomic_int used[64];     /* bands each index ran */
};

static void band(void *arg, int thread, int y0, int y1)
{
	struct job *j = arg;
	if (thread < 0 || thread >= j->threads) {
		atomic_fetch_add(&j->out_of_range, 1);
		return;
	}
	if (atomic_fetch_add(&j->holder[thread], 1) != 0)
		atomic_fetch_add(&j->overlaps, 1);
	atomic_fetch_add(&j->used[thread], 1);
	for (int y = y0; y < y1; y++) {
		atomic_fetch_add(&j->seen[y], 1);
		for (volatile int k = 0; k < 200; k++) /* long enough for bands to overlap */
			;
	}
	atomic_fetch_sub(&j->holder[thread], 1);
}

static void test_thread_index(void **state)
{
	(void)state;
	for (int threads = 1; threads <= 4; threads++) {
		struct dao_pool *pool;
		assert_int_equal(dao_pool_create(&pool, threads), 0);
		assert_int_equal(dao_pool_threads(pool), threads);
		static struct job j;
		for (int run = 0; run < 20; run++) {
			memset(&j, 0, sizeof j);
			j.threads = threads;
			dao_pool_run_threads(pool, ROWS, 1, band, &j);
			for (int y = 0; y < ROWS; y++)
				assert_int_equal(atomic_load(&j.seen[y]), 1);
			assert_int_equal(atomic_load(&j.out_of_range), 0);
			assert_int_equal(atomic_load(&j.overlaps), 0);
		}
		int used = 0;
		for (int t = 0; t < threads; t++)
			used += atomic_load(&j.used[t]) > 0;
		print_message("%d threads: indices used in the last run %d\n", threads, used);
		dao_pool_destroy(pool);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_thread_index),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
