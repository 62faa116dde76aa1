/* SPDX-License-Identifier: MIT */
/*
 * A reference depth post-processing chain in the manner of librealsense's
 * (tools and tests only, the anchor of `depthao eval --depth`; never a
 * default of depthao), written from Intel's published documentation of its
 * post-processing filters (docs/depth-accuracy.md says what was read and
 * which choices the documentation leaves open):
 *
 *   depth -> disparity -> spatial filter -> temporal filter -> depth -> hole filling
 *
 * with the documented defaults and decimation off:
 *  - spatial edge-preserving filter: 2 iterations of 1-D recursive passes
 *    (left-right, right-left, top-down, bottom-up), each an exponential
 *    moving average with alpha 0.5 that does not cross a step of more than
 *    delta 20 disparity levels; no hole filling of its own;
 *  - temporal filter: alpha 0.4, delta 20, persistence "valid in 2 of the
 *    last 4 frames" (a pixel without data takes the history's value if the
 *    pixel had data in at least 2 of the last 4 frames);
 *  - hole filling "farthest from around": an empty pixel takes, among its 4
 *    neighbours (up, down, left, right) that have depth, the farthest;
 *    raster order, in place (filled pixels feed the next).
 *
 * Disparity levels: d = fx * RS_REF_BASELINE / z * RS_REF_SUBPIXEL, the
 * units of a D4xx camera with a 50 mm baseline and 1/32 px subpixel steps.
 */
#ifndef DAO_SYNTH_RS_REFERENCE_H
#define DAO_SYNTH_RS_REFERENCE_H

#include <stdint.h>

#include <depthao/error.h>

#define RS_REF_BASELINE 0.050
#define RS_REF_SUBPIXEL 32.0

struct rs_ref_options {
	float spatial_alpha, spatial_delta;
	int spatial_iterations;
	float temporal_alpha, temporal_delta;
	int persist_valid, persist_of;   /* valid in persist_valid of the last persist_of */
	int hole_fill;                   /* 1: farthest from around, 0: off */
};

/* The documented defaults (above). */
void rs_ref_options_default(struct rs_ref_options *o);

struct rs_ref {
	struct rs_ref_options o;
	int w, h;
	double k;          /* disparity = k / z */
	float *disp;       /* working frame */
	float *hist;       /* the temporal filter's last output, 0 = none */
	uint8_t *valid;    /* validity of the last frames, bit 0 the newest */
	int frames;        /* frames since the start */
};

/* 0 or -ENOMEM / -EINVAL with a message. */
int rs_ref_init(struct rs_ref *r, const struct rs_ref_options *o, int w, int h, double fx,
		struct dao_error *err);
void rs_ref_free(struct rs_ref *r);

/* Starts the temporal history over (a new sequence). */
void rs_ref_reset(struct rs_ref *r);

/* One frame: depth in metres (0 = none) to the filtered depth `out` (may be `in`). */
void rs_ref_process(struct rs_ref *r, const float *in, float *out);

/* The stages alone, on disparity (0 = none), w x h; for tests. */
void rs_ref_spatial(float *d, int w, int h, float alpha, float delta, int iterations);
void rs_ref_hole_fill_farthest(float *z, int w, int h);

#endif
