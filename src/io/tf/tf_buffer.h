/* SPDX-License-Identifier: MIT */
#ifndef DAO_TF_TF_BUFFER_H
#define DAO_TF_TF_BUFFER_H

/*
 * A tf buffer: the transforms of a recording's /tf and /tf_static (or an
 * odometry topic), by frame, looked up at a time as tf2 does.  Every frame
 * has at most one parent; the transform from a child to its parent is
 * static (one value, any time) or dynamic (samples by stamp, interpolated
 * between the two around the time asked: linear in the translation,
 * spherical in the rotation).  Frame names lose a leading '/' (ROS 1 bags
 * write "/base_link" where tf2 says "base_link").
 *
 * Fill it with dao_tf_buffer_add, then call dao_tf_buffer_finish once
 * (sorts the samples), then look up.  Memory is bounded: at most
 * max_frames frames and max_samples dynamic samples (about 72 bytes each).
 * One thread at a time.
 */
#include <stddef.h>
#include <stdint.h>

#include <depthao/error.h>

#include "tf/rigid.h"

/* Longest frame name kept (bytes, without the NUL); longer ones are refused. */
#define DAO_TF_NAME_MAX 255

struct dao_tf_buffer;

int dao_tf_buffer_create(struct dao_tf_buffer **out, uint32_t max_frames, uint64_t max_samples,
			 struct dao_error *err);
void dao_tf_buffer_free(struct dao_tf_buffer *b);

/* What a transform added is. */
enum dao_tf_time {
	DAO_TF_DYNAMIC = 0,         /* a sample at its stamp (ROS /tf) */
	DAO_TF_STATIC = 1,          /* one value at any time (ROS /tf_static) */
	/* a sample, unless it is (at finish) the only stamp of its frame, every sample
	 * of which came this way: then static (Foxglove applies a frame's one
	 * transform at every time) */
	DAO_TF_STATIC_IF_ALONE = 2,
};

/*
 * Adds the transform of `child` in `parent` (names of plen and clen bytes,
 * not NUL-terminated) at stamp_ns, as `time` says (enum dao_tf_time).  0
 * added; 1 skipped, with the reason in err (a bad quaternion or translation,
 * an empty name, a name too long, a frame its own parent); < 0 the buffer
 * cannot hold the recording's tf: -EINVAL for a frame given two parents,
 * -E2BIG past a limit.
 */
int dao_tf_buffer_add(struct dao_tf_buffer *b, const char *parent, size_t plen,
		      const char *child, size_t clen, uint64_t stamp_ns,
		      const struct dao_rigid *tr, int time, struct dao_error *err);
/*
 * Sorts every frame's samples by stamp (a later sample of an equal stamp
 * wins) and makes the lone DAO_TF_STATIC_IF_ALONE samples static; 0 or
 * -ENOMEM.
 */
int dao_tf_buffer_finish(struct dao_tf_buffer *b, struct dao_error *err);

uint32_t dao_tf_buffer_frame_count(const struct dao_tf_buffer *b);
/* NULL if i >= count. */
const char *dao_tf_buffer_frame_name(const struct dao_tf_buffer *b, uint32_t i);
/* The frame of that name (a leading '/' ignored), or -1. */
int dao_tf_buffer_find(const struct dao_tf_buffer *b, const char *name);
/* The dynamic samples held. */
uint64_t dao_tf_buffer_samples(const struct dao_tf_buffer *b);
/* Up to cap bytes of "name, name, ..." (every frame, in the order first seen). */
void dao_tf_buffer_list(const struct dao_tf_buffer *b, char *buf, size_t cap);

/* The root of frame's tree (its ancestor without a parent); 0 or -ELOOP (a cycle, in err). */
int dao_tf_buffer_root(const struct dao_tf_buffer *b, int frame, int *root, struct dao_error *err);
/* Are frames a and b in one tree?  1, 0, or -ELOOP. */
int dao_tf_buffer_connected(const struct dao_tf_buffer *b, int a, int c, struct dao_error *err);

/*
 * The pose of frame `source` in frame `target` at t_ns (maps source's points
 * into target), through their nearest common ancestor.  Each dynamic
 * transform on the way is its sample at t_ns (within 1 us) or the
 * interpolation of the samples on either side, which must be at most
 * max_gap_ns apart.  0; -ENOENT when a transform has no such samples (a
 * gap, or a time before the first or after the last: no extrapolation);
 * -ENOTCONN when the frames are in different trees; -ELOOP for a cycle.
 * Messages name the frames and times.
 */
int dao_tf_buffer_lookup(struct dao_tf_buffer *b, int target, int source, uint64_t t_ns,
			 uint64_t max_gap_ns, struct dao_rigid *out, struct dao_error *err);

#endif
