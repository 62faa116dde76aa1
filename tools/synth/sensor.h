/* SPDX-License-Identifier: MIT */
/*
 * Simulated depth sensors (tools and tests only): what a Kinect-class
 * structured-light camera, a RealSense-class active-stereo camera or a
 * time-of-flight camera would deliver for a synthetic scene, next to the
 * clean render and the i.i.d. Gaussian model of sensor_noise.c.  Each model
 * works from the scene itself (ray tracing: projector and second-camera
 * visibility, pixel footprints, indirect light), not only from the clean
 * depth; each is deterministic for a seed.  The physics and the constants of
 * each model, and how they were checked against real frames, are in the
 * source files (sensor_structured.c, sensor_stereo.c, sensor_tof.c) and in
 * docs/sensor-models.md.
 */
#ifndef DAO_SYNTH_SENSOR_H
#define DAO_SYNTH_SENSOR_H

#include <stdint.h>

#include <depthao/camera.h>
#include <depthao/error.h>

#include "synth/synth.h"

enum synth_sensor {
	SYNTH_SENSOR_CLEAN,            /* the exact render, in millimetres */
	SYNTH_SENSOR_GAUSSIAN,         /* sigma = 0.0012 z^2, mm steps, 2 % holes (issue #2) */
	SYNTH_SENSOR_STRUCTURED_LIGHT, /* Kinect v1 / PrimeSense: dot pattern, block matching */
	SYNTH_SENSOR_ACTIVE_STEREO,    /* RealSense D4xx: two IR cameras, semi-global matching */
	SYNTH_SENSOR_TOF,              /* continuous-wave time of flight */
	SYNTH_SENSOR_COUNT
};

/* "clean", "gaussian", "structured-light", "active-stereo", "tof". */
const char *synth_sensor_name(enum synth_sensor s);

/* Parses a name (also "noisy" for gaussian, "sl", "stereo"); -EINVAL with a message. */
int synth_sensor_parse(const char *name, enum synth_sensor *out, struct dao_error *err);

/*
 * What `sensor` delivers for `scene` seen through `cam`, given the clean
 * render `img` of that scene and camera (depth and normals; its ground truth
 * is not used): depth in metres in `out` (w x h, 0 = no data), before the
 * millimetre rounding of synth_case_make().  Deterministic for `seed`; uses
 * up to `threads` threads for the ray tracing.  0 or -ENOMEM / -EINVAL.
 * A frame on its own: synth_sensor_simulate_frame() with both seeds `seed`.
 */
int synth_sensor_simulate(enum synth_sensor sensor, const struct synth_scene *scene,
			  const struct dao_camera *cam, const struct synth_image *img,
			  uint64_t seed, int threads, float *out, struct dao_error *err);

/*
 * One frame of a sequence from one device: `device_seed` draws what belongs to
 * the device and repeats from frame to frame (the structured-light pattern's
 * slow deviation from its stored reference, sensor_structured.c), `frame_seed`
 * the noise of this exposure (speckle, read noise, drop-outs).  The same
 * contract as synth_sensor_simulate otherwise.
 */
int synth_sensor_simulate_frame(enum synth_sensor sensor, const struct synth_scene *scene,
				const struct dao_camera *cam, const struct synth_image *img,
				uint64_t device_seed, uint64_t frame_seed, int threads, float *out,
				struct dao_error *err);

/* The models, called by synth_sensor_simulate_frame (same contract; `seed`
 * is the frame's). */
int synth_sensor_structured_light(const struct synth_scene *scene, const struct dao_camera *cam,
				  const struct synth_image *img, uint64_t device_seed,
				  uint64_t seed, int threads, float *out, struct dao_error *err);
int synth_sensor_active_stereo(const struct synth_scene *scene, const struct dao_camera *cam,
			       const struct synth_image *img, uint64_t seed, int threads,
			       float *out, struct dao_error *err);
int synth_sensor_tof(const struct synth_scene *scene, const struct dao_camera *cam,
		     const struct synth_image *img, uint64_t seed, int threads, float *out,
		     struct dao_error *err);

#endif
