/* SPDX-License-Identifier: MIT */
#define _GNU_SOURCE /* sched_getaffinity, CPU_COUNT */
#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <unistd.h>

#include "pipeline/threadpool.h"

struct dao_pool {
	int nworkers;
	pthread_t *workers;
	pthread_mutex_t lock;
	pthread_cond_t wake;     /* workers wait for a new generation */
	pthread_cond_t done;     /* the caller waits for the workers to finish */
	unsigned generation;     /* bumped for every job */
	int busy;                /* workers still inside the current job */
	int quit;
	/* the current job */
	dao_pool_fn fn;
	void *arg;
	int rows, band;
	atomic_int next_band;
};

/* Takes bands until none is left. */
static void drain(struct dao_pool *p)
{
	for (;;) {
		int b = atomic_fetch_add_explicit(&p->next_band, 1, memory_order_relaxed);
		int y0 = b * p->band;
		if (y0 >= p->rows)
			return;
		int y1 = y0 + p->band < p->rows ? y0 + p->band : p->rows;
		p->fn(p->arg, y0, y1);
	}
}

static void *worker_main(void *arg)
{
	struct dao_pool *p = arg;
	unsigned seen = 0;
	pthread_mutex_lock(&p->lock);
	for (;;) {
		while (!p->quit && p->generation == seen)
			pthread_cond_wait(&p->wake, &p->lock);
		if (p->quit)
			break;
		seen = p->generation;
		pthread_mutex_unlock(&p->lock);
		drain(p);
		pthread_mutex_lock(&p->lock);
		if (--p->busy == 0)
			pthread_cond_signal(&p->done);
	}
	pthread_mutex_unlock(&p->lock);
	return NULL;
}

int dao_pool_online_cpus(void)
{
	cpu_set_t set;
	if (sched_getaffinity(0, sizeof set, &set) == 0) {
		int n = CPU_COUNT(&set);
		if (n > 0)
			return n;
	}
	long n = sysconf(_SC_NPROCESSORS_ONLN);
	return n > 0 ? (int)n : 1;
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
	p->quit = 1;
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

void dao_pool_run(struct dao_pool *p, int rows, int min_rows, dao_pool_fn fn, void *arg)
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
		fn(arg, 0, rows);
		return;
	}
	pthread_mutex_lock(&p->lock);
	p->fn = fn;
	p->arg = arg;
	p->rows = rows;
	p->band = band;
	atomic_store_explicit(&p->next_band, 0, memory_order_relaxed);
	p->busy = p->nworkers;
	p->generation++;
	pthread_cond_broadcast(&p->wake);
	pthread_mutex_unlock(&p->lock);

	drain(p);

	pthread_mutex_lock(&p->lock);
	while (p->busy > 0)
		pthread_cond_wait(&p->done, &p->lock);
	pthread_mutex_unlock(&p->lock);
}
