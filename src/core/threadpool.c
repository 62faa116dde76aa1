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
	int rows, band;
	atomic_int next_band;
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

/* Takes bands until none is left; `thread`: 0 the caller, 1 .. nworkers the workers. */
static void drain(struct dao_pool *p, int thread)
{
	for (;;) {
		int b = atomic_fetch_add_explicit(&p->next_band, 1, memory_order_relaxed);
		int y0 = b * p->band;
		if (y0 >= p->rows)
			return;
		int y1 = y0 + p->band < p->rows ? y0 + p->band : p->rows;
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
	/* about four bands per thread balances load without much overhead */
	int band = rows / (4 * (p->nworkers + 1));
	if (band < min_rows)
		band = min_rows;
	if (p->nworkers == 0 || band >= rows) {
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
	p->band = band;
	atomic_store_explicit(&p->next_band, 0, memory_order_relaxed);
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
