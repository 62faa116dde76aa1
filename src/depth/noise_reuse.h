/* SPDX-License-Identifier: MIT */
#ifndef DAO_DEPTH_NOISE_REUSE_H
#define DAO_DEPTH_NOISE_REUSE_H

/*
 * noise-interval: the noise measured when it changes, not in every frame
 * (noise-model=auto on streams).
 *
 * What a measurement (noise_estimate.h) gives, and what of it is the
 * sensor's and what the scene's:
 * - the frame's medians `area`, `link`, `slope`: the sensor's noise, the
 *   same from frame to frame while the camera sees about the same depths
 *   (a structured-light sensor's is constant in 1/z at any depth; a ToF
 *   sensor's grows in 1/z as the surfaces come nearer, about as w to w^2:
 *   sigma_z constant or growing with z), with what follows from them: the
 *   denoise's and the temporal depth filter's noise, the normals' radius;
 * - per cell (32 x 32 px) `link`, the domain filter's range unit there:
 *   the sensor's noise at the cell's depths (ToF: a function of them), and
 *   the cell's mean 1/z `w`, which sets the filter's spatial scale there
 *   (dao_auto_scale: the noise in units of the pixel's footprint): the
 *   scene's;
 * - the frame's median `w` (the normals' radius and the reported
 *   prefilter-scale, at exponents 1/4 and 3/4: a 5 % move changes them
 *   1 % and 4 %);
 * - with the temporal depth filter, the noise after it over the noise
 *   before it (the side windows' threshold, context_frame.c): it falls from 1 to
 *   about 1/3 in the first frames of a history and rises where the scene
 *   moves (the filter's histories restart there).
 *
 * So a measurement is kept, and every frame between two measurements
 * checks the scene cheaply: per cell the mean 1/z and the share of pixels
 * with depth on every DAO_NOISE_REUSE_STEP-th pixel of every
 * DAO_NOISE_REUSE_STEP-th row (64 samples of a full cell; 1/16 of a pass
 * over the frame).  A cell whose mean 1/z moved by more than
 * DAO_NOISE_REUSE_W of itself, or whose share with depth moved by more
 * than DAO_NOISE_REUSE_COVER, since its measurement is measured again on
 * its own (its blocks and medians: its `link` and `w` are then this
 * frame's, whatever the sensor's noise does with depth).  When more than
 * 1 / DAO_NOISE_REUSE_CUT of the cells with depth moved (a scene cut, the
 * camera turned), everything is measured again and the schedule restarts.
 * Below the thresholds the cell keeps what was measured: 5 % in 1/z moves
 * a ToF cell's noise by 5 - 10 % and its spatial scale by 4 %, no more
 * than the scatter of one cell's measurement (noise_estimate.h: 9 % RMS of
 * `link`).
 *
 * The schedule: after a restart (the first frame, a gap or a step back in
 * frame_index, dao_context_reset, new parameters, a scene cut) frames 0,
 * 1, 2, 4, 8, ... of it are measured, then every noise-interval frames:
 * the doubling follows the temporal depth filter while its history settles.
 * The result of a frame is then a function of the frames since the
 * restart, as with the temporal filters; noise-interval 1 (the library's
 * default) measures every frame and each frame's result is its own.
 */
#include <stdint.h>

#include "depth/noise_estimate.h"

#define DAO_NOISE_REUSE_STEP 4      /* px between the check's samples, both ways */
#define DAO_NOISE_REUSE_W 0.05f     /* a cell moved: its mean 1/z by more than this share */
#define DAO_NOISE_REUSE_COVER 0.25f /* ... or its share of pixels with depth by more than this */
#define DAO_NOISE_REUSE_CUT 4       /* a cut: more than 1/CUT of the cells with depth moved */

struct dao_noise_reuse {
	int cw, ch;             /* the grid's cells */
	int valid;              /* a measurement to reuse (one with usable cells) */
	float area, link, slope, w; /* its frame medians (noise_estimate.h) */
	float side_ratio;       /* noise after / before the temporal depth filter; NAN: none */
	float *cell;            /* per cell: link, then mean 1/z (2 planes) */
	float *sig_ref;         /* per cell: the check's mean 1/z and share with depth when
				 * the cell was measured (2 planes) */
	float *sig_now;         /* ... in this frame */
	int *changed;           /* the cells that moved in this frame */
	uint64_t since;         /* this frame's number since the schedule restarted */
	uint64_t next;          /* ... the next full measurement's */
	int age;                /* frames since the full measurement kept */
};

/* Allocates for the cells of g (the only allocation). */
int dao_noise_reuse_init(struct dao_noise_reuse *r, const struct dao_noise_grid *g);
void dao_noise_reuse_free(struct dao_noise_reuse *r);

/* Forget the measurement: the next frame is measured and the schedule starts over. */
static inline void dao_noise_reuse_restart(struct dao_noise_reuse *r)
{
	r->valid = 0;
	r->since = 0;
	r->next = 0;
}

/* This frame is due for a full measurement. */
static inline int dao_noise_reuse_due(const struct dao_noise_reuse *r)
{
	return !r->valid || r->since >= r->next;
}

/* Keeps the full measurement in g (after dao_noise_cells_finish), and with
 * z (the depth it was measured on) the check's reference; schedules the
 * next one at most `interval` frames on. */
void dao_noise_reuse_store(struct dao_noise_reuse *r, const struct dao_noise_grid *g,
			   const float *z, int interval);

/* The cells that moved since their measurement (into r->changed): their
 * count, or -1 for a cut (more than 1/DAO_NOISE_REUSE_CUT of the cells with
 * depth). */
int dao_noise_reuse_changes(struct dao_noise_reuse *r, const struct dao_noise_grid *g,
			    const float *z);

/* Cell changed[i] measured again in g from z (thread-safe across i). */
void dao_noise_reuse_measure_cell(struct dao_noise_reuse *r, struct dao_noise_grid *g,
				  const float *z, int i);

/* The end of a frame: one more frame since the restart and the measurement. */
static inline void dao_noise_reuse_advance(struct dao_noise_reuse *r)
{
	r->since++;
	r->age++;
}

#endif
