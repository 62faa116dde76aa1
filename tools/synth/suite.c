/* SPDX-License-Identifier: MIT */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <depthao/error.h>
#include "synth/suite.h"

int synth_scene_is_structured(const char *scene)
{
	return strcmp(scene, "plane") != 0;
}

int synth_scene_is_foundation(const char *scene)
{
	static const char *const foundation[] = { "plane", "room-corner", "spheres", "stairs",
						  "boxes", "thin-pole", NULL };
	for (const char *const *f = foundation; *f; f++)
		if (strcmp(scene, *f) == 0)
			return 1;
	return 0;
}

int synth_set_parse(const char *name, enum synth_set *out, struct dao_error *err)
{
	if (name && strcmp(name, "tune") == 0)
		*out = SYNTH_SET_TUNE;
	else if (name && strcmp(name, "heldout") == 0)
		*out = SYNTH_SET_HELDOUT;
	else
		return dao_error_set(err, -EINVAL, "unknown scene set '%s': use tune or heldout",
				     name ? name : "");
	return 0;
}

const char *synth_set_name(enum synth_set set)
{
	return set == SYNTH_SET_HELDOUT ? "heldout" : "tune";
}

uint64_t synth_case_seed(uint64_t base, int scene_index, int variant, enum synth_sensor sensor)
{
	/* variant 0, Gaussian noise: base + scene index, as the suite always had */
	if (variant == 0 && sensor <= SYNTH_SENSOR_GAUSSIAN)
		return base + (uint64_t)scene_index;
	return base + 1000u * (uint64_t)variant + 100u * (uint64_t)sensor + (uint64_t)scene_index;
}

/* Millimetre counts, as a sensor delivers them, and the same in metres. */
static int case_fill(struct synth_case *c, const float *depth, size_t np, struct dao_error *err)
{
	c->depth_mm = malloc(np * sizeof(uint16_t));
	c->depth_m = malloc(np * sizeof(float));
	if (!c->depth_mm || !c->depth_m) {
		synth_case_free(c);
		return dao_error_set(err, -ENOMEM, "out of memory for scene '%s'", c->scene);
	}
	for (size_t i = 0; i < np; i++) {
		double mm = floor((double)depth[i] * 1000.0 + 0.5);
		c->depth_mm[i] = (mm > 0.0 && mm <= 65535.0) ? (uint16_t)mm : 0;
		c->depth_m[i] = (float)c->depth_mm[i] * 0.001f;
	}
	return 0;
}

int synth_case_make(struct synth_case *c, const char *scene, int noisy, const float *depth,
		    float *gt, int width, int height, uint64_t seed, struct dao_error *err)
{
	const size_t np = (size_t)width * height;
	*c = (struct synth_case){ .scene = scene, .noisy = noisy, .gt = gt,
				  .sensor = noisy ? SYNTH_SENSOR_GAUSSIAN : SYNTH_SENSOR_CLEAN };
	float *tmp = malloc(np * sizeof(float));
	if (!tmp)
		return dao_error_set(err, -ENOMEM, "out of memory for scene '%s'", scene);
	memcpy(tmp, depth, np * sizeof(float));
	if (noisy)
		synth_sensor_noise(tmp, width, height, SYNTH_NOISE_K, SYNTH_NOISE_QUANTUM,
				   SYNTH_NOISE_DROP, seed);
	int r = case_fill(c, tmp, np, err);
	free(tmp);
	return r;
}

int synth_case_simulate(struct synth_case *c, const struct synth_scene *scene, int variant,
			const struct dao_camera *cam, const struct synth_image *img,
			enum synth_sensor sensor, uint64_t seed, int threads, struct dao_error *err)
{
	return synth_case_simulate_frame(c, scene, variant, cam, img, sensor, seed, seed, threads,
					 err);
}

int synth_case_simulate_frame(struct synth_case *c, const struct synth_scene *scene, int variant,
			      const struct dao_camera *cam, const struct synth_image *img,
			      enum synth_sensor sensor, uint64_t device_seed, uint64_t seed,
			      int threads, struct dao_error *err)
{
	const size_t np = (size_t)cam->width * cam->height;
	*c = (struct synth_case){ .scene = scene->name, .variant = variant, .sensor = sensor,
				  .noisy = sensor != SYNTH_SENSOR_CLEAN, .gt = img->gt };
	float *tmp = malloc(np * sizeof(float));
	if (!tmp)
		return dao_error_set(err, -ENOMEM, "out of memory for scene '%s'", scene->name);
	int r = synth_sensor_simulate_frame(sensor, scene, cam, img, device_seed, seed, threads, tmp,
					    err);
	if (!r)
		r = case_fill(c, tmp, np, err);
	free(tmp);
	return r;
}

void synth_case_free(struct synth_case *c)
{
	free(c->depth_mm);
	free(c->depth_m);
	c->depth_mm = NULL;
	c->depth_m = NULL;
}

int synth_suite_load_spec(struct synth_suite *s, const struct synth_suite_spec *spec,
			  struct dao_error *err)
{
	memset(s, 0, sizeof *s);
	synth_default_camera(&s->cam);
	s->radius = spec->radius;
	const char *const *scenes = spec->scenes ? spec->scenes : synth_scene_names();
	const int variants = spec->variants < 1 ? 1 : spec->variants;
	int n = 0, index = 0;
	for (const char *const *name = scenes; *name; name++, index++)
		for (int k = 0; k < variants; k++, n++) {
			const int variant = spec->variant_first + k * spec->variant_step;
			if (n >= SYNTH_SUITE_MAX_IMAGES ||
			    s->count + spec->nsensors > SYNTH_SUITE_MAX) {
				synth_suite_free(s);
				return dao_error_set(err, -EINVAL, "too many cases (at most %d scenes "
						     "x variants and %d cases)", SYNTH_SUITE_MAX_IMAGES,
						     SYNTH_SUITE_MAX);
			}
			struct synth_scene scene;
			int r = synth_scene_build_variant(*name, 0.0, variant, &scene, err);
			if (!r)
				r = synth_render(&scene, &s->cam, spec->radius, spec->rays_sqrt,
						 spec->threads, &s->images[n], err);
			for (int k2 = 0; !r && k2 < spec->nsensors; k2++) {
				const enum synth_sensor sensor = spec->sensors[k2];
				r = synth_case_simulate(&s->cases[s->count], &scene, variant, &s->cam,
							&s->images[n], sensor,
							synth_case_seed(spec->seed, index, variant, sensor),
							spec->threads, err);
				if (!r)
					s->count++;
			}
			if (r) {
				synth_suite_free(s);
				return r;
			}
		}
	return 0;
}

int synth_suite_load(struct synth_suite *s, const char *const *scenes, double radius,
		     int rays_sqrt, int with_noise, uint64_t seed, int threads,
		     struct dao_error *err)
{
	static const enum synth_sensor both[] = { SYNTH_SENSOR_CLEAN, SYNTH_SENSOR_GAUSSIAN };
	const struct synth_suite_spec spec = {
		.scenes = scenes, .radius = radius, .rays_sqrt = rays_sqrt, .sensors = both,
		.nsensors = with_noise ? 2 : 1, .variant_first = 0, .variant_step = 2, .variants = 1,
		.seed = seed,
		.threads = threads,
	};
	return synth_suite_load_spec(s, &spec, err);
}

void synth_suite_free(struct synth_suite *s)
{
	for (int i = 0; i < s->count; i++)
		synth_case_free(&s->cases[i]);
	for (int i = 0; i < SYNTH_SUITE_MAX_IMAGES; i++)
		synth_image_free(&s->images[i]);
	s->count = 0;
}

int synth_suite_run_case(const struct synth_suite *s, int index, struct dao_context *ctx,
			 float *ao, struct synth_metrics *m, double *ms, struct dao_error *err)
{
	const struct synth_case *c = &s->cases[index];
	const uint32_t w = s->cam.width, h = s->cam.height;
	struct dao_frame depth = {
		.format = DAO_PIXFMT_DEPTH16, .width = w, .height = h,
		.stride = (int32_t)(w * sizeof(uint16_t)), .data = c->depth_mm, .depth_unit = 0.001f,
	};
	struct dao_frame out = {
		.format = DAO_PIXFMT_GRAY_F32, .width = w, .height = h,
		.stride = (int32_t)(w * sizeof(float)), .data = ao,
	};
	struct timespec t0, t1;
	clock_gettime(CLOCK_MONOTONIC, &t0);
	int r = dao_context_process(ctx, &depth, NULL, 0, &out, err);
	clock_gettime(CLOCK_MONOTONIC, &t1);
	if (r)
		return r;
	*ms = (double)(t1.tv_sec - t0.tv_sec) * 1e3 + (double)(t1.tv_nsec - t0.tv_nsec) * 1e-6;
	r = synth_metrics(ao, c->gt, c->depth_m, (int)w, (int)h, m);
	return r ? dao_error_set(err, r, "out of memory measuring %s", c->scene) : 0;
}
