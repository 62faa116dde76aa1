/* SPDX-License-Identifier: MIT */
/*
 * The evaluation suite: every synthetic scene, clean and with sensor noise,
 * as the depth PNG a sensor would deliver (millimetres), with its ground
 * truth.  Runs the library on each case and measures it (`depthao eval`,
 * the accuracy tests).
 */
#ifndef DAO_SYNTH_SUITE_H
#define DAO_SYNTH_SUITE_H

#include <stdint.h>

#include <depthao/depthao.h>

#include "synth/synth.h"

#define SYNTH_SUITE_MAX 32

/* Kinect v1-like noise of the noisy variants (issue #2): sigma = 0.0012 z^2, mm steps, 2 % holes. */
#define SYNTH_NOISE_K 0.0012
#define SYNTH_NOISE_QUANTUM 0.001
#define SYNTH_NOISE_DROP 0.02

struct synth_case {
	const char *scene;
	int noisy;
	uint16_t *depth_mm;   /* what the sensor delivers */
	float *depth_m;       /* the same in metres (0 = no data) */
	float *gt;            /* ground-truth visibility (shared by clean and noisy) */
};

struct synth_suite {
	struct dao_camera cam;
	double radius;
	int count;
	struct synth_case cases[SYNTH_SUITE_MAX];
	struct synth_image images[SYNTH_SUITE_MAX / 2];
};

/*
 * Renders the scenes named in `scenes` (NULL = all) with rays_sqrt^2 rays per
 * pixel, each clean and (if with_noise) noisy with seed `seed`.
 */
int synth_suite_load(struct synth_suite *s, const char *const *scenes, double radius,
		     int rays_sqrt, int with_noise, uint64_t seed, int threads,
		     struct dao_error *err);

void synth_suite_free(struct synth_suite *s);

/*
 * Fills a case from a rendered depth plane (metres): noise (if noisy, with
 * `seed`) and millimetre quantisation, as a sensor would deliver it.  `gt` is
 * borrowed.  Free with synth_case_free().
 */
int synth_case_make(struct synth_case *c, const char *scene, int noisy, const float *depth,
		    float *gt, int width, int height, uint64_t seed, struct dao_error *err);
void synth_case_free(struct synth_case *c);

/* Runs the library with `params` on one case; fills metrics and the time in ms. */
int synth_suite_run_case(const struct synth_suite *s, int index, struct dao_context *ctx,
			 float *ao, struct synth_metrics *m, double *ms, struct dao_error *err);

/* Scenes that count towards the "clean scenes" mean (all but the plane). */
int synth_scene_is_structured(const char *scene);

/* The original six scenes, which the accuracy bars (eval --check) are about; the
 * thickness scenes (thin-poles, chair, floating-plate) are reported beside them. */
int synth_scene_is_foundation(const char *scene);

#endif
