/* SPDX-License-Identifier: MIT */
/*
 * Synthetic depth scenes with exact, ray-traced ground-truth AO.  Internal
 * to the depthao tools and tests (not part of libdepthao's API).
 */
#ifndef DAO_SYNTH_SYNTH_H
#define DAO_SYNTH_SYNTH_H

#include <stdint.h>

#include <depthao/camera.h>
#include <depthao/error.h>

#include "synth/geometry.h"

#define SYNTH_MAX_PRIMS 48

struct synth_scene {
	const char *name;
	const char *description;
	int count;
	struct synth_prim prims[SYNTH_MAX_PRIMS]; /* in the camera's optical frame */
};

/* Names of the scenes, NULL-terminated. */
const char *const *synth_scene_names(void);

/*
 * Builds scene `name`, posed for a camera looking at it.  An optional
 * `time` in [0, 1] moves the scene's animated object (0 = rest pose).
 */
int synth_scene_build(const char *name, double time, struct synth_scene *out,
		      struct dao_error *err);

/*
 * A variant of scene `name`: 0 is the scene itself; every other number a
 * deterministic perturbation of it (camera pose, object positions and sizes,
 * wall distances), for held-out evaluation (suite.h).
 */
int synth_scene_build_variant(const char *name, double time, int variant,
			      struct synth_scene *out, struct dao_error *err);

/* The camera of all synthetic scenes: 640x480, fx = fy = 525, cx = 319.5, cy = 239.5. */
void synth_default_camera(struct dao_camera *cam);

struct synth_image {
	int width, height;
	float *depth;   /* z along the optical axis, m; 0 where the ray hits nothing */
	float *normal;  /* 3 per pixel, true geometric normal facing the camera */
	float *gt;      /* visibility in [0, 1], 1 where there is no surface */
};

/*
 * Ray-traces depth and normals, and, if rays_sqrt > 0, ground-truth AO:
 * cosine-weighted hemisphere visibility around the true normal with
 * rays_sqrt^2 stratified rays per pixel, a ray counting as blocked when it
 * hits geometry closer than `radius`.  Deterministic; uses `threads` threads.
 */
int synth_render(const struct synth_scene *scene, const struct dao_camera *cam, double radius,
		 int rays_sqrt, int threads, struct synth_image *out, struct dao_error *err);

void synth_image_free(struct synth_image *img);

/*
 * Nearest hit of the ray o + t d with t in (tmin, tmax): the primitive's
 * index (-1 if none), *t and the outward unit normal *n (n may be NULL).
 */
int synth_trace(const struct synth_scene *s, vec3 o, vec3 d, double tmin, double tmax, double *t,
		vec3 *n);

/* 1 if the point x lies in the primitive's solid (its surface included). */
int synth_prim_inside(const struct synth_prim *p, vec3 x);

/*
 * The length of the ray o + t d inside solid matter from its hit at t on
 * primitive `prim` (synth_trace's): to where it leaves the union of the
 * primitives it passes through without leaving solid matter, in metres (d
 * need not be unit); INFINITY inside a half-space it never leaves.
 */
double synth_ray_inside(const struct synth_scene *s, vec3 o, vec3 d, double t, int prim);

/* synth_ray_inside of every pixel's camera ray (cam's pixel centres), w x h
 * floats; 0 where the ray hits nothing, INFINITY in half-spaces. */
void synth_inside_plane(const struct synth_scene *s, const struct dao_camera *cam, float *out);

/* 1 if anything lies on the ray o + t d for t in (tmin, tmax). */
int synth_occluded(const struct synth_scene *s, vec3 o, vec3 d, double tmin, double tmax);

/*
 * Kinect-like sensor noise on a depth plane (m): Gaussian with
 * sigma = k z^2, quantised to `quantum` metres, and about `drop_fraction`
 * of the pixels lost in small clumps (set to 0).  Deterministic for a seed.
 */
void synth_sensor_noise(float *depth, int width, int height, double k, double quantum,
			double drop_fraction, uint64_t seed);

/* Statistics of |ao - gt| over pixels where `valid` (depth > 0) holds. */
struct synth_metrics {
	double mae, bias, p99, mean_occlusion;
	long count;
	long nan_count;           /* NaN or out-of-range values anywhere */
	long invalid_not_one;     /* pixels without depth whose value is not exactly 1 */
};

int synth_metrics(const float *ao, const float *gt, const float *depth, int width, int height,
		  struct synth_metrics *m);

#endif
