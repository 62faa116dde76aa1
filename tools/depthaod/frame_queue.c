/* SPDX-License-Identifier: MIT */
#include "frame_queue.h"

#include <errno.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum slot_state { SLOT_FREE = 0, SLOT_FILLING, SLOT_QUEUED, SLOT_BUSY };

struct frame_queue {
	pthread_mutex_t lock;
	pthread_cond_t changed;
	unsigned cap;
	struct fq_item *items;
	enum slot_state *state;
	unsigned *ring; /* queued slot indices, oldest first */
	unsigned head, count;
	int closed;
};

int fq_create(struct frame_queue **out, unsigned capacity)
{
	struct frame_queue *q = calloc(1, sizeof(*q));
	if (!q)
		return -ENOMEM;
	q->cap = capacity;
	q->items = calloc(capacity, sizeof(*q->items));
	q->state = calloc(capacity, sizeof(*q->state));
	q->ring = calloc(capacity, sizeof(*q->ring));
	if (!q->items || !q->state || !q->ring) {
		fq_destroy(q);
		return -ENOMEM;
	}
	pthread_mutex_init(&q->lock, NULL);
	pthread_condattr_t ca;
	pthread_condattr_init(&ca);
	pthread_condattr_setclock(&ca, CLOCK_MONOTONIC);
	pthread_cond_init(&q->changed, &ca);
	pthread_condattr_destroy(&ca);
	*out = q;
	return 0;
}

void fq_destroy(struct frame_queue *q)
{
	if (!q)
		return;
	if (q->items) {
		for (unsigned i = 0; i < q->cap; i++) {
			dao_frame_free(&q->items[i].frame);
			dao_frame_free(&q->items[i].color);
		}
		pthread_mutex_destroy(&q->lock);
		pthread_cond_destroy(&q->changed);
	}
	free(q->items);
	free(q->state);
	free(q->ring);
	free(q);
}

static unsigned slot_of(struct frame_queue *q, struct fq_item *it)
{
	return (unsigned)(it - q->items);
}

struct fq_item *fq_begin_push(struct frame_queue *q, int drop_oldest, uint64_t *dropped)
{
	pthread_mutex_lock(&q->lock);
	for (;;) {
		if (q->closed) {
			pthread_mutex_unlock(&q->lock);
			return NULL;
		}
		for (unsigned i = 0; i < q->cap; i++) {
			if (q->state[i] == SLOT_FREE) {
				q->state[i] = SLOT_FILLING;
				pthread_mutex_unlock(&q->lock);
				return &q->items[i];
			}
		}
		if (drop_oldest && q->count) {
			unsigned i = q->ring[q->head];
			q->head = (q->head + 1) % q->cap;
			q->count--;
			q->state[i] = SLOT_FILLING;
			if (dropped)
				(*dropped)++;
			pthread_mutex_unlock(&q->lock);
			return &q->items[i];
		}
		pthread_cond_wait(&q->changed, &q->lock);
	}
}

void fq_end_push(struct frame_queue *q, struct fq_item *it)
{
	pthread_mutex_lock(&q->lock);
	unsigned i = slot_of(q, it);
	q->state[i] = SLOT_QUEUED;
	q->ring[(q->head + q->count) % q->cap] = i;
	q->count++;
	pthread_cond_broadcast(&q->changed);
	pthread_mutex_unlock(&q->lock);
}

void fq_cancel_push(struct frame_queue *q, struct fq_item *it)
{
	pthread_mutex_lock(&q->lock);
	q->state[slot_of(q, it)] = SLOT_FREE;
	pthread_cond_broadcast(&q->changed);
	pthread_mutex_unlock(&q->lock);
}

struct fq_item *fq_pop(struct frame_queue *q, int timeout_ms)
{
	struct timespec until;
	clock_gettime(CLOCK_MONOTONIC, &until);
	if (timeout_ms > 0) {
		until.tv_sec += timeout_ms / 1000;
		until.tv_nsec += (long)(timeout_ms % 1000) * 1000000;
		if (until.tv_nsec >= 1000000000) {
			until.tv_sec++;
			until.tv_nsec -= 1000000000;
		}
	}
	pthread_mutex_lock(&q->lock);
	while (q->count == 0 && !q->closed) {
		if (timeout_ms == 0)
			break;
		if (timeout_ms < 0)
			pthread_cond_wait(&q->changed, &q->lock);
		else if (pthread_cond_timedwait(&q->changed, &q->lock, &until) == ETIMEDOUT)
			break;
	}
	struct fq_item *it = NULL;
	if (q->count) {
		unsigned i = q->ring[q->head];
		q->head = (q->head + 1) % q->cap;
		q->count--;
		q->state[i] = SLOT_BUSY;
		it = &q->items[i];
		pthread_cond_broadcast(&q->changed);
	}
	pthread_mutex_unlock(&q->lock);
	return it;
}

void fq_done(struct frame_queue *q, struct fq_item *it)
{
	pthread_mutex_lock(&q->lock);
	q->state[slot_of(q, it)] = SLOT_FREE;
	pthread_cond_broadcast(&q->changed);
	pthread_mutex_unlock(&q->lock);
}

void fq_close(struct frame_queue *q)
{
	pthread_mutex_lock(&q->lock);
	q->closed = 1;
	pthread_cond_broadcast(&q->changed);
	pthread_mutex_unlock(&q->lock);
}

unsigned fq_clear(struct frame_queue *q)
{
	pthread_mutex_lock(&q->lock);
	unsigned n = q->count;
	while (q->count) {
		q->state[q->ring[q->head]] = SLOT_FREE;
		q->head = (q->head + 1) % q->cap;
		q->count--;
	}
	pthread_cond_broadcast(&q->changed);
	pthread_mutex_unlock(&q->lock);
	return n;
}

unsigned fq_length(struct frame_queue *q)
{
	pthread_mutex_lock(&q->lock);
	unsigned n = q->count;
	pthread_mutex_unlock(&q->lock);
	return n;
}

int fq_closed_and_empty(struct frame_queue *q)
{
	pthread_mutex_lock(&q->lock);
	int r = q->closed && q->count == 0;
	pthread_mutex_unlock(&q->lock);
	return r;
}

int fq_frame_reserve(struct dao_frame *f, enum dao_pixfmt format, uint32_t w, uint32_t h)
{
	if (f->data && f->format == format && f->width == w && f->height == h)
		return 0;
	dao_frame_free(f);
	return dao_frame_alloc(f, format, w, h, NULL);
}

int fq_item_copy_frame(struct fq_item *it, const struct dao_frame *src)
{
	struct dao_frame *dst = &it->frame;
	const size_t row = (size_t)src->width * dao_pixfmt_bytes_per_pixel(src->format);
	const size_t bytes = row * src->height;
	if (!row || !src->height)
		return -EINVAL;
	if (!dst->data || it->frame_cap < bytes) {
		void *p = realloc(dst->data, bytes);
		if (!p)
			return -ENOMEM;
		dst->data = p;
		it->frame_cap = bytes;
	}
	dst->format = src->format;
	dst->width = src->width;
	dst->height = src->height;
	dst->stride = (int32_t)row;
	for (uint32_t y = 0; y < src->height; y++)
		memcpy((uint8_t *)dst->data + (size_t)y * row,
		       (const uint8_t *)src->data + (size_t)y * (size_t)src->stride, row);
	dst->depth_unit = src->depth_unit;
	dst->timestamp_ns = src->timestamp_ns;
	dst->sequence = src->sequence;
	return 0;
}

int fq_frame_copy(struct dao_frame *dst, const struct dao_frame *src)
{
	int r = fq_frame_reserve(dst, src->format, src->width, src->height);
	if (r < 0)
		return r;
	size_t row = (size_t)src->width * dao_pixfmt_bytes_per_pixel(src->format);
	for (uint32_t y = 0; y < src->height; y++)
		memcpy((uint8_t *)dst->data + (size_t)y * (size_t)dst->stride,
		       (const uint8_t *)src->data + (size_t)y * (size_t)src->stride, row);
	dst->depth_unit = src->depth_unit;
	dst->timestamp_ns = src->timestamp_ns;
	dst->sequence = src->sequence;
	return 0;
}
