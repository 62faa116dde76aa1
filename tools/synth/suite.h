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

#include "synth/sensor.h"
#include "synth/synth.h"

#define SYNTH_SUITE_MAX 128        /* cases */
#define SYNTH_SUITE_MAX_IMAGES 48  /* rendered scenes (scene x variant) */

/* Kinect v1-like noise of the noisy variants (issue #2): sigma = 0.0012 z^2, mm steps, 2 % holes. */
#define SYNTH_NOISE_K 0.0012
#define SYNTH_NOISE_QUANTUM 0.001
#define SYNTH_NOISE_DROP 0.02

struct synth_case {
	const char *scene;
	int variant;          /* 0: the scene itself; see synth_scene_build_variant() */
	enum synth_sensor sensor;
	int noisy;            /* sensor != SYNTH_SENSOR_CLEAN */
	uint16_t *depth_mm;   /* what the sensor delivers */
	float *depth_m;       /* the same in metres (0 = no data) */
	float *gt;            /* ground-truth visibility (shared by clean and noisy) */
};

struct synth_suite {
	struct dao_camera cam;
	double radius;
	int count;
	struct synth_case cases[SYNTH_SUITE_MAX];
	struct synth_image images[SYNTH_SUITE_MAX_IMAGES];
};

/*
 * Two disjoint families of scenes, so that defaults tuned on one can be
 * reported on the other: `tune` holds the scenes as written (variant 0) and
 * the even variants, `heldout` the odd variants (perturbed camera, objects
 * and walls), with noise seeds of their own.
 */
enum synth_set {
	SYNTH_SET_TUNE,
	SYNTH_SET_HELDOUT,
};

/* "tune" / "heldout"; -EINVAL with a message. */
int synth_set_parse(const char *name, enum synth_set *out, struct dao_error *err);
const char *synth_set_name(enum synth_set set);

/* Variant k (0-based) of a family: tune 0, 2, 4, ...; heldout 1, 3, 5, ... */
static inline int synth_set_variant(enum synth_set set, int k)
{
	return 2 * k + (set == SYNTH_SET_HELDOUT);
}

/* Noise seed of a case: distinct per scene, variant and sensor, fixed per family. */
uint64_t synth_case_seed(uint64_t base, int scene_index, int variant, enum synth_sensor sensor);

struct synth_suite_spec {
	const char *const *scenes;          /* NULL-terminated; NULL = all */
	double radius;
	int rays_sqrt;
	const enum synth_sensor *sensors;   /* the inputs of every scene */
	int nsensors;
	int variant_first, variant_step;    /* variants first, first + step, ... */
	int variants;                       /* per scene, >= 1 */
	uint64_t seed;                      /* base of the noise seeds */
	int threads;
};

/* The variants of a family: synth_set_variant(set, 0), step 2. */
static inline void synth_suite_spec_set(struct synth_suite_spec *spec, enum synth_set set,
					int variants)
{
	spec->variant_first = synth_set_variant(set, 0);
	spec->variant_step = 2;
	spec->variants = variants;
}

/* Renders and simulates every (scene, variant) x sensor of `spec`. */
int synth_suite_load_spec(struct synth_suite *s, const struct synth_suite_spec *spec,
			  struct dao_error *err);

/*
 * Renders the scenes named in `scenes` (NULL = all) with rays_sqrt^2 rays per
 * pixel, each clean and (if with_noise) with Gaussian noise, seed `seed`
 * (the tune family's variant 0, as synth_suite_load_spec).
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

/*
 * Fills a case with what `sensor` delivers for `scene` (rendered as `img`,
 * whose ground truth the case borrows), in millimetres.  The scene and img
 * must outlive nothing: the case copies what it needs.
 */
int synth_case_simulate(struct synth_case *c, const struct synth_scene *scene, int variant,
			const struct dao_camera *cam, const struct synth_image *img,
			enum synth_sensor sensor, uint64_t seed, int threads, struct dao_error *err);

/* The same for one frame of a sequence from one device (the seeds of
 * synth_sensor_simulate_frame). */
int synth_case_simulate_frame(struct synth_case *c, const struct synth_scene *scene, int variant,
			      const struct dao_camera *cam, const struct synth_image *img,
			      enum synth_sensor sensor, uint64_t device_seed, uint64_t frame_seed,
			      int threads, struct dao_error *err);

/* Runs the library with `params` on one case; fills metrics and the time in ms. */
int synth_suite_run_case(const struct synth_suite *s, int index, struct dao_context *ctx,
			 float *ao, struct synth_metrics *m, double *ms, struct dao_error *err);

/* Scenes that count towards the "clean scenes" mean (all but the plane). */
int synth_scene_is_structured(const char *scene);

/* The original six scenes, which the accuracy bars (eval --check) are about; the
 * thickness scenes (thin-poles, chair, floating-plate, pole-gaps, table-above,
 * pole-widths, shelves-below, panels, chair-corner) are reported beside them. */
int synth_scene_is_foundation(const char *scene);

#endif
