/* SPDX-License-Identifier: MIT */
/*
 * Open planar regions of a depth frame (tools and tests only): pixels on a
 * plane of the frame with nothing in front of that plane within the AO
 * radius, so that their true ambient occlusion is 1 up to what the camera
 * cannot see (occluders outside the image or hidden behind the visible
 * surface).  Whatever darkens them in an AO image is an artefact of the
 * sensor's noise: the real-frame metric of `depthao realcheck` and the tests.
 */
#ifndef DAO_SYNTH_OPEN_PLANES_H
#define DAO_SYNTH_OPEN_PLANES_H

#include <stdint.h>

#include <depthao/camera.h>
#include <depthao/error.h>

#include "synth/planes.h"

/*
 * Planes as sensorstats finds them: synth_planes_find with the default
 * options for a source of `depth_unit` m per count, told the band step of the
 * frame (synth_band_constant).  planes holds SYNTH_PLANES_MAX.
 */
int synth_planes_find_frame(const float *z, const struct dao_camera *cam, double depth_unit,
			    struct synth_plane *planes, int *count, int32_t *labels,
			    struct dao_error *err);

/*
 * Sets mask[i] = 1 for the open planar pixels of `z` (metres, 0 = no data):
 * pixels of the planes' regions (found as by synth_planes_find_frame, but
 * with tight regions; eroded by 2 px) no point of the frame lies
 * within `radius` of and more than a tolerance in front of their plane (the
 * larger of 2 cm and 3 robust sigmas of the plane's residual at that depth).
 * *count gets their number.  Deterministic.  0 or -ENOMEM with a message.
 */
int synth_open_planes(const float *z, const struct dao_camera *cam, double depth_unit,
		      double radius, uint8_t *mask, long *count, struct dao_error *err);

#endif
