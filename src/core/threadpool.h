/* SPDX-License-Identifier: MIT */
/*
 * A persistent pool of worker threads owned by one context.  Work is a
 * function over row bands: dao_pool_run() splits [0, rows) into bands, runs
 * them on the workers and the calling thread, and returns when all are done.
 * Threads are created once (dao_pool_create) and never per frame.
 */
#ifndef DAO_PIPELINE_THREADPOOL_H
#define DAO_PIPELINE_THREADPOOL_H

struct dao_pool;

/* fn processes rows [y0, y1) with the caller's argument. */
typedef void (*dao_pool_fn)(void *arg, int y0, int y1);

/* Creates a pool running `threads` bands in parallel (>= 1; 1 = no workers). */
int dao_pool_create(struct dao_pool **out, int threads);

void dao_pool_destroy(struct dao_pool *pool);

/* Number of threads work is spread over (workers + the caller). */
int dao_pool_threads(const struct dao_pool *pool);

/*
 * Runs fn over [0, rows) in bands of at least `min_rows` rows and waits for
 * completion.  Bands are handed out dynamically, large first and shrinking
 * to min_rows (guided self-scheduling), so a slow core does not hold up the
 * others and the threads finish together.  Bands start at multiples of
 * min_rows.  Not re-entrant: one dao_pool_run at a time per pool.
 */
void dao_pool_run(struct dao_pool *pool, int rows, int min_rows, dao_pool_fn fn, void *arg);

/* fn processes rows [y0, y1) on thread `thread`, 0 .. dao_pool_threads() - 1
 * (0: the caller), which no other band runs on at the same time: an index
 * into per-thread scratch allocated once (never on a worker's stack). */
typedef void (*dao_pool_thread_fn)(void *arg, int thread, int y0, int y1);

/* dao_pool_run for a function that is told its thread. */
void dao_pool_run_threads(struct dao_pool *pool, int rows, int min_rows, dao_pool_thread_fn fn,
			  void *arg);

#endif
