/* SPDX-License-Identifier: MIT */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/error_internal.h"
#include "synth/suite.h"

int synth_scene_is_structured(const char *scene)
{
	return strcmp(scene, "plane") != 0;
}

int synth_scene_is_foundation(const char *scene)
{
	return strcmp(scene, "thin-poles") != 0 && strcmp(scene, "chair") != 0 &&
	       strcmp(scene, "floating-plate") != 0;
}

int synth_case_make(struct synth_case *c, const char *scene, int noisy, const float *depth,
		    float *gt, int width, int height, uint64_t seed, struct dao_error *err)
{
	const size_t np = (size_t)width * height;
	c->scene = scene;
	c->noisy = noisy;
	c->gt = gt;
	c->depth_mm = malloc(np * sizeof(uint16_t));
	c->depth_m = malloc(np * sizeof(float));
	if (!c->depth_mm || !c->depth_m) {
		synth_case_free(c);
		return dao_error_set(err, -ENOMEM, "out of memory for scene '%s'", scene);
	}
	memcpy(c->depth_m, depth, np * sizeof(float));
	if (noisy)
		synth_sensor_noise(c->depth_m, width, height, SYNTH_NOISE_K, SYNTH_NOISE_QUANTUM,
				   SYNTH_NOISE_DROP, seed);
	for (size_t i = 0; i < np; i++) {
		double mm = floor((double)c->depth_m[i] * 1000.0 + 0.5);
		c->depth_mm[i] = (mm > 0.0 && mm <= 65535.0) ? (uint16_t)mm : 0;
		c->depth_m[i] = (float)c->depth_mm[i] * 0.001f;
	}
	return 0;
}

void synth_case_free(struct synth_case *c)
{
	free(c->depth_mm);
	free(c->depth_m);
	c->depth_mm = NULL;
	c->depth_m = NULL;
}

static int add_case(struct synth_suite *s, const char *name, int noisy, const float *depth,
		    float *gt, uint64_t seed, struct dao_error *err)
{
	int r = synth_case_make(&s->cases[s->count], name, noisy, depth, gt, (int)s->cam.width,
				(int)s->cam.height, seed, err);
	if (!r)
		s->count++;
	return r;
}

int synth_suite_load(struct synth_suite *s, const char *const *scenes, double radius,
		     int rays_sqrt, int with_noise, uint64_t seed, int threads,
		     struct dao_error *err)
{
	memset(s, 0, sizeof *s);
	synth_default_camera(&s->cam);
	s->radius = radius;
	if (!scenes)
		scenes = synth_scene_names();
	int n = 0;
	for (const char *const *name = scenes; *name; name++, n++) {
		if (n >= SYNTH_SUITE_MAX / 2) {
			synth_suite_free(s);
			return dao_error_set(err, -EINVAL, "too many scenes (at most %d)",
					     SYNTH_SUITE_MAX / 2);
		}
		struct synth_scene scene;
		int r = synth_scene_build(*name, 0.0, &scene, err);
		if (!r)
			r = synth_render(&scene, &s->cam, radius, rays_sqrt, threads, &s->images[n], err);
		if (!r)
			r = add_case(s, scene.name, 0, s->images[n].depth, s->images[n].gt, 0, err);
		if (!r && with_noise)
			r = add_case(s, scene.name, 1, s->images[n].depth, s->images[n].gt,
				     seed + (uint64_t)n, err);
		if (r) {
			synth_suite_free(s);
			return r;
		}
	}
	return 0;
}

void synth_suite_free(struct synth_suite *s)
{
	for (int i = 0; i < s->count; i++)
		synth_case_free(&s->cases[i]);
	for (int i = 0; i < SYNTH_SUITE_MAX / 2; i++)
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
