/* SPDX-License-Identifier: MIT */
/*
 * Metrics of an AO sequence against per-frame truth (depthao eval --sequence,
 * issue #37).  Internal to the tools and tests.
 *
 * - MAE: |ao - gt| over the pixels where the sensor delivered depth.
 * - Trail MAE: the same over the band that a depth discontinuity swept in the
 *   last SYNTH_TRAIL_FRAMES frames: pixels whose true depth changed by more
 *   than SYNTH_TRAIL_REL of itself from one frame to the next (or gained or
 *   lost a surface).  With a still camera that is behind (and ahead of) the
 *   moving object's silhouette; with a moving camera, behind every
 *   discontinuity's motion in the image.  A history kept where it should
 *   have been dropped shows there first.
 * - Flicker: per pixel, the temporal standard deviation of the AO over the
 *   sequence, averaged over static pixels: depth in every frame and a true
 *   depth that never moves more than SYNTH_STATIC_TOL_M from frame 0 (without
 *   truth: an input depth within SYNTH_STATIC_REL of its frame-0 value).  It
 *   is only meaningful where the camera stands still (the caller decides).
 * - Tracked flicker: with the true depth and pose of every frame, the same
 *   per surface point instead of per pixel: each pixel of frame 0 with a
 *   surface is a point in the world, projected into every frame and sampled
 *   there bilinearly where the four pixels around it (those of weight above
 *   SYNTH_TRACK_MIN_WEIGHT) have a true depth that agrees within
 *   SYNTH_TRACK_REL and depth from the sensor; the std over the frames of the
 *   AO there, averaged over the points seen in every frame.  With a still
 *   camera it is the per-pixel flicker; with a moving one it follows the
 *   surface, between pixels too.
 * - Change: the mean |ao_k - ao_k-1| over the pixels with depth in both
 *   frames, at the same pixel (what issue #37 quotes for the real recording).
 *
 * A column with `skip` > 0 leaves out the sequence's first `skip` frames from
 * its flicker and change (over the same static pixels; tracked, over the
 * points seen in every frame from `skip` on): what a temporal filter does
 * once its history has settled.
 * Frame 0 has no history to average with, so every filter's frame 0 is as
 * noisy as no filter's: over N frames, a filter with no noise at all after
 * frame 0 still shows 1/sqrt(N) of no filter's flicker.
 */
#ifndef DAO_SYNTH_SEQUENCE_METRICS_H
#define DAO_SYNTH_SEQUENCE_METRICS_H

#include <stdint.h>

#include "synth/trajectory.h"

#define SYNTH_TRAIL_FRAMES 4
#define SYNTH_TRAIL_REL 0.05
#define SYNTH_STATIC_TOL_M 0.001
#define SYNTH_STATIC_REL 0.03
#define SYNTH_TRACK_REL 0.01
#define SYNTH_TRACK_MIN_WEIGHT 1e-3

/* What the columns of a sequence share: the trail band and the static mask. */
struct synth_seq_masks {
	int width, height;
	long frame;             /* frames seen */
	int32_t *last_swept;    /* the last frame a discontinuity swept the pixel, or -1000 */
	float *ref;             /* frame 0's depth (true, or the input's without truth) */
	float *prev_true;       /* the previous frame's true depth */
	uint8_t *is_static;
	int with_truth;
};

/* One column's (filter setting's) accumulators. */
struct synth_seq_column {
	int width, height;
	long frames;
	double *sum, *sumsq;    /* per pixel, over the frames */
	float *prev;            /* the previous frame's AO */
	uint8_t *prev_valid;
	double change_sum;
	long change_n;
	double *tsum, *tsumsq;  /* per point of frame 0 (tracked flicker) */
	int32_t *tn;            /* frames the point was seen in */
	long skip;              /* the first frames left out (set after init; 0: none) */
	long offered;           /* frames given to synth_seq_column_add, skipped ones too */
};

/* The surface points of frame 0, in the world, for the tracked flicker. */
struct synth_seq_track {
	int width, height;
	double fx, fy, cx, cy;
	long frames;            /* frames seen */
	float *X;               /* 3 per pixel; NaN where frame 0 has no surface */
};

struct synth_seq_frame {
	double mae, trail_mae;
	long count, trail_count;
};

int synth_seq_masks_init(struct synth_seq_masks *m, int width, int height, int with_truth);
void synth_seq_masks_free(struct synth_seq_masks *m);

/*
 * Frame k of the sequence (call once per frame, before the columns' metrics):
 * `depth` the input (m, 0 = none), `true_depth` the truth (m) or NULL when
 * there is none (with_truth 0).  Updates the band and the static mask.
 */
void synth_seq_masks_add(struct synth_seq_masks *m, const float *depth, const float *true_depth);

/* 1 if pixel i lies in the trail band of the current frame. */
static inline int synth_seq_in_band(const struct synth_seq_masks *m, long i)
{
	return m->frame - 1 - m->last_swept[i] < SYNTH_TRAIL_FRAMES;
}

int synth_seq_column_init(struct synth_seq_column *c, int width, int height);
void synth_seq_column_free(struct synth_seq_column *c);

/*
 * One frame's AO of a column: adds it to the flicker and change
 * accumulators, and (with gt non-NULL) fills the frame's MAE and trail MAE
 * over the pixels with input depth.
 */
void synth_seq_column_add(struct synth_seq_column *c, const struct synth_seq_masks *m,
			  const float *ao, const float *gt, const float *depth,
			  struct synth_seq_frame *out);

/* Mean per-pixel temporal std over the static pixels (their number in *count). */
double synth_seq_flicker(const struct synth_seq_column *c, const struct synth_seq_masks *m,
			 long *count);

int synth_seq_track_init(struct synth_seq_track *t, int width, int height, double fx, double fy,
			 double cx, double cy);
void synth_seq_track_free(struct synth_seq_track *t);

/* Frame k's true depth (m) and pose: frame 0 sets the points; call before the columns'. */
void synth_seq_track_frame(struct synth_seq_track *t, const float *true_depth,
			   const struct synth_pose *pose);

/* One frame's AO of a column at the points of frame 0 (see above); after
 * synth_seq_column_add of the same frame, which tells it whether the frame is
 * one a `skip` column leaves out. */
void synth_seq_column_track(struct synth_seq_column *c, const struct synth_seq_track *t,
			    const float *ao, const float *depth, const float *true_depth,
			    const struct synth_pose *pose);

/* Mean temporal std of the AO over the points seen in every frame (their number in *count). */
double synth_seq_flicker_tracked(const struct synth_seq_column *c, const struct synth_seq_track *t,
				 long *count);

/* Mean frame-to-frame |change| of the AO (0 with fewer than two frames). */
double synth_seq_change(const struct synth_seq_column *c);

#endif
