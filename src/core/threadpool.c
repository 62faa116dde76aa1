/* SPDX-License-Identifier: MIT */
#include <errno.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>

#include "core/threadpool.h"

struct dao_pool {
	int nworkers;
	pthread_t *workers;
	pthread_mutex_t lock;
	pthread_cond_t wake;     /* sleeping workers wait for a new generation */
	pthread_cond_t done;     /* a sleeping caller waits for the workers to finish */
	atomic_uint generation;  /* bumped for every job (release: publishes the job) */
	atomic_int busy;         /* workers still inside the current job */
	atomic_int quit;
	int sleepers;            /* workers blocked on `wake` (under lock) */
	/* the current job */
	dao_pool_fn fn;
	dao_pool_thread_fn tfn; /* or this one, told which thread runs the band */
	void *arg;
	int rows, min_rows;      /* a band holds at least min_rows rows (but the last) */
	int divisor;             /* a band is the rows left / divisor (2 per thread) */
	atomic_int next_row;
	atomic_int started;      /* workers that took their index (1 .. nworkers) */
};

/*
 * Hand-offs spin this many rounds before sleeping.  The stages of a frame
 * follow each other within microseconds, and waking a sleeping thread costs
 * tens of microseconds (more in a VM) per stage; between frames the spin ends
 * after ~50 us and the threads sleep.
 */
#define SPIN_ROUNDS 4000

static inline void cpu_relax(void)
{
#if defined(__x86_64__) || defined(__i386__)
	__builtin_ia32_pause();
#elif defined(__aarch64__)
	__asm__ volatile("yield");
#endif
}

/*
 * Guided self-scheduling (Polychronopoulos & Kuck 1987): each band is the
 * rows left divided by twice the threads, rounded up to a multiple of
 * min_rows.  The first bands are large (few hand-offs, a kernel's per-band
 * set-up paid rarely), the last ones min_rows, so the threads finish within
 * a small band of each other.  Equal bands (four per thread) left one
 * thread idle for half a band on average at the end of every stage:
 * measured 4-6 % of two threads' time over a default VGA frame, most of it
 * after GTAO's 1 ms bands (docs/perf/sched.md).
 */
static int take_band(struct dao_pool *p, int *y0, int *y1)
{
	int at = atomic_load_explicit(&p->next_row, memory_order_relaxed);
	for (;;) {
		const int left = p->rows - at;
		if (left <= 0)
			return 0;
		int n = (left + p->divisor - 1) / p->divisor;
		n = (n + p->min_rows - 1) / p->min_rows * p->min_rows;
		if (n > left)
			n = left;
		if (atomic_compare_exchange_weak_explicit(&p->next_row, &at, at + n,
							  memory_order_relaxed,
							  memory_order_relaxed)) {
			*y0 = at, *y1 = at + n;
			return 1;
		}
	}
}

/* Takes bands until none is left; `thread`: 0 the caller, 1 .. nworkers the workers. */
static void drain(struct dao_pool *p, int thread)
{
	int y0, y1;
	while (take_band(p, &y0, &y1)) {
		if (p->tfn)
			p->tfn(p->arg, thread, y0, y1);
		else
			p->fn(p->arg, y0, y1);
	}
}

static void *worker_main(void *arg)
{
	struct dao_pool *p = arg;
	const int thread = atomic_fetch_add(&p->started, 1) + 1;
	unsigned seen = 0;
	for (;;) {
		/* wait for a new job: spin a little, then sleep */
		unsigned g = atomic_load_explicit(&p->generation, memory_order_acquire);
		for (int i = 0; i < SPIN_ROUNDS && g == seen &&
				!atomic_load_explicit(&p->quit, memory_order_relaxed); i++) {
			cpu_relax();
			g = atomic_load_explicit(&p->generation, memory_order_acquire);
		}
		if (g == seen) {
			pthread_mutex_lock(&p->lock);
			p->sleepers++;
			while (!atomic_load(&p->quit) &&
			       (g = atomic_load_explicit(&p->generation, memory_order_acquire)) == seen)
				pthread_cond_wait(&p->wake, &p->lock);
			p->sleepers--;
			pthread_mutex_unlock(&p->lock);
		}
		if (atomic_load(&p->quit))
			break;
		seen = g;
		drain(p, thread);
		if (atomic_fetch_sub_explicit(&p->busy, 1, memory_order_acq_rel) == 1) {
			/* the last one out: wake the caller if it went to sleep */
			pthread_mutex_lock(&p->lock);
			pthread_cond_signal(&p->done);
			pthread_mutex_unlock(&p->lock);
		}
	}
	return NULL;
}

int dao_pool_create(struct dao_pool **out, int threads)
{
	*out = NULL;
	if (threads < 1)
		threads = 1;
	struct dao_pool *p = calloc(1, sizeof *p);
	if (!p)
		return -ENOMEM;
	p->nworkers = threads - 1;
	if (p->nworkers > 0) {
		p->workers = calloc((size_t)p->nworkers, sizeof *p->workers);
		if (!p->workers) {
			free(p);
			return -ENOMEM;
		}
	}
	pthread_mutex_init(&p->lock, NULL);
	pthread_cond_init(&p->wake, NULL);
	pthread_cond_init(&p->done, NULL);
	for (int i = 0; i < p->nworkers; i++) {
		int r = pthread_create(&p->workers[i], NULL, worker_main, p);
		if (r) {
			p->nworkers = i; /* tear down the ones that started */
			dao_pool_destroy(p);
			return -r;
		}
	}
	*out = p;
	return 0;
}

void dao_pool_destroy(struct dao_pool *p)
{
	if (!p)
		return;
	pthread_mutex_lock(&p->lock);
	atomic_store(&p->quit, 1);
	pthread_cond_broadcast(&p->wake);
	pthread_mutex_unlock(&p->lock);
	for (int i = 0; i < p->nworkers; i++)
		pthread_join(p->workers[i], NULL);
	pthread_cond_destroy(&p->done);
	pthread_cond_destroy(&p->wake);
	pthread_mutex_destroy(&p->lock);
	free(p->workers);
	free(p);
}

int dao_pool_threads(const struct dao_pool *p)
{
	return p->nworkers + 1;
}

static void run(struct dao_pool *p, int rows, int min_rows, dao_pool_fn fn,
		dao_pool_thread_fn tfn, void *arg)
{
	if (rows <= 0)
		return;
	if (min_rows < 1)
		min_rows = 1;
	if (p->nworkers == 0 || min_rows >= rows) {
		if (tfn)
			tfn(arg, 0, 0, rows);
		else
			fn(arg, 0, rows);
		return;
	}
	p->fn = fn;
	p->tfn = tfn;
	p->arg = arg;
	p->rows = rows;
	p->min_rows = min_rows;
	p->divisor = 2 * (p->nworkers + 1);
	atomic_store_explicit(&p->next_row, 0, memory_order_relaxed);
	atomic_store_explicit(&p->busy, p->nworkers, memory_order_relaxed);
	/* publishes the job to spinning workers; sleeping ones need the signal */
	atomic_fetch_add_explicit(&p->generation, 1, memory_order_release);
	pthread_mutex_lock(&p->lock);
	if (p->sleepers)
		pthread_cond_broadcast(&p->wake);
	pthread_mutex_unlock(&p->lock);

	drain(p, 0);

	for (int i = 0; atomic_load_explicit(&p->busy, memory_order_acquire) > 0; i++) {
		if (i < SPIN_ROUNDS) {
			cpu_relax();
			continue;
		}
		pthread_mutex_lock(&p->lock);
		while (atomic_load_explicit(&p->busy, memory_order_acquire) > 0)
			pthread_cond_wait(&p->done, &p->lock);
		pthread_mutex_unlock(&p->lock);
		break;
	}
}

void dao_pool_run(struct dao_pool *p, int rows, int min_rows, dao_pool_fn fn, void *arg)
{
	run(p, rows, min_rows, fn, NULL, arg);
}

void dao_pool_run_threads(struct dao_pool *p, int rows, int min_rows, dao_pool_thread_fn fn,
			  void *arg)
{
	run(p, rows, min_rows, NULL, fn, arg);
}
