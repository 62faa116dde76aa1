/* SPDX-License-Identifier: MIT */
/*
 * A bounded queue of reusable frame slots between two threads.  The
 * producer fills a slot in place and publishes it; the consumer takes the
 * oldest, uses it and gives it back.  When every slot is taken, a push
 * either waits (lossless) or reclaims the oldest queued slot (drop-oldest,
 * counted).  Slots keep their pixel buffers, so steady state allocates
 * nothing.
 */
#ifndef DAOD_FRAME_QUEUE_H
#define DAOD_FRAME_QUEUE_H

#include <stdint.h>

#include <depthao/depthao.h>

struct fq_item {
	struct dao_frame frame;   /* owned buffer, reused */
	struct dao_frame color;   /* owned buffer (RGB24) or format NONE */
	uint64_t index;           /* source frame index */
	uint64_t t_capture_ns;    /* CLOCK_MONOTONIC when the source delivered it */
	int stream;               /* sink queues: the stream of `frame` (enum stream_kind) */
	int has_pose;             /* the camera's pose for the frame (pose_q, pose_t): the
				     source's in the input queue, the tracked one (the sinks
				     get it) in a sink's */
	double pose_q[4], pose_t[3];
	size_t frame_cap;         /* bytes allocated for frame.data (fq_item_copy_frame) */
};

struct frame_queue;

int fq_create(struct frame_queue **out, unsigned capacity);
void fq_destroy(struct frame_queue *q);

/*
 * A slot to fill, or NULL once the queue is closed.  When full: with
 * drop_oldest the oldest queued item is reclaimed and *dropped incremented;
 * otherwise waits for the consumer.
 */
struct fq_item *fq_begin_push(struct frame_queue *q, int drop_oldest, uint64_t *dropped);
void fq_end_push(struct frame_queue *q, struct fq_item *item);
void fq_cancel_push(struct frame_queue *q, struct fq_item *item);

/* The oldest item, or NULL after timeout_ms (-1 = forever) or when closed and empty. */
struct fq_item *fq_pop(struct frame_queue *q, int timeout_ms);
void fq_done(struct frame_queue *q, struct fq_item *item);

/* No more pushes; pops drain what is queued, then return NULL. */
void fq_close(struct frame_queue *q);
/* Drops everything queued (returns how many). */
unsigned fq_clear(struct frame_queue *q);
unsigned fq_length(struct frame_queue *q);
/* 1 once closed with nothing left to pop. */
int fq_closed_and_empty(struct frame_queue *q);

/* Makes `f` a frame of this format and size, reallocating only on change. */
int fq_frame_reserve(struct dao_frame *f, enum dao_pixfmt format, uint32_t w, uint32_t h);
/*
 * Copies src into it->frame, row by row (tightly packed), keeping its buffer
 * while it is large enough: a queue that carries frames of several formats in
 * turn (a sink taking several streams) reallocates only when one is larger.
 */
int fq_item_copy_frame(struct fq_item *it, const struct dao_frame *src);
/* Copies src into dst (reserving dst), row by row. */
int fq_frame_copy(struct dao_frame *dst, const struct dao_frame *src);

#endif
