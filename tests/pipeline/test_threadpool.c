/* SPDX-License-Identifier: MIT */
/*
 * dao_pool_run_threads: every row is processed exactly once, and the thread
 * index a band is told is in range and never held by two bands at once (the
 * tile kernels index their per-thread scratch with it); bands start at
 * multiples of min_rows, hold at least min_rows rows (but the last), and
 * shrink from the first to the last (guided self-scheduling).
 */
#include <stdatomic.h>
#include <stdlib.h>
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

#define MAX_BANDS 1024

struct bands {
	atomic_int count;
	int y0[MAX_BANDS], y1[MAX_BANDS];
};

static void record(void *arg, int y0, int y1)
{
	struct bands *b = arg;
	const int i = atomic_fetch_add(&b->count, 1);
	if (i < MAX_BANDS)
		b->y0[i] = y0, b->y1[i] = y1;
}

static int by_start(const void *a, const void *b)
{
	return *(const int *)a - *(const int *)b;
}

static void test_band_sizes(void **state)
{
	(void)state;
	static const int rows[] = { 1, 7, 15, 480, 961, 4000 };
	static const int mins[] = { 1, 2, 4, 8, 16 };
	for (int threads = 1; threads <= 4; threads++) {
		struct dao_pool *pool;
		assert_int_equal(dao_pool_create(&pool, threads), 0);
		for (size_t r = 0; r < sizeof rows / sizeof rows[0]; r++) {
			for (size_t m = 0; m < sizeof mins / sizeof mins[0]; m++) {
				static struct bands b;
				memset(&b, 0, sizeof b);
				dao_pool_run(pool, rows[r], mins[m], record, &b);
				const int n = atomic_load(&b.count);
				assert_in_range(n, 1, MAX_BANDS - 1);
				/* (y0, y1) pairs in order of their start */
				int pairs[2 * MAX_BANDS];
				for (int i = 0; i < n; i++)
					pairs[2 * i] = b.y0[i], pairs[2 * i + 1] = b.y1[i];
				qsort(pairs, (size_t)n, 2 * sizeof(int), by_start);
				int at = 0, last = rows[r];
				for (int i = 0; i < n; i++) {
					const int y0 = pairs[2 * i], y1 = pairs[2 * i + 1];
					assert_int_equal(y0, at);
					assert_true(y1 > y0);
					assert_int_equal(y0 % mins[m], 0);
					if (y1 < rows[r])
						assert_true(y1 - y0 >= mins[m]);
					/* guided: never larger than the band before, but
					 * the last one may be cut short and the rest not */
					if (y1 < rows[r])
						assert_true(y1 - y0 <= last);
					last = y1 - y0;
					at = y1;
				}
				assert_int_equal(at, rows[r]);
				if (threads == 1)
					assert_int_equal(n, 1);
				/* the first band is at most the rows / (2 threads)
				 * rounded up to min_rows: the others get work from
				 * the start */
				if (threads > 1 && rows[r] > mins[m]) {
					const int div = 2 * threads;
					int first = (rows[r] + div - 1) / div;
					first = (first + mins[m] - 1) / mins[m] * mins[m];
					assert_true(pairs[1] - pairs[0] <= first);
				}
			}
		}
		dao_pool_destroy(pool);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_thread_index),
		cmocka_unit_test(test_band_sizes),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
