/* SPDX-License-Identifier: MIT */
/* depthao sensorstats: the measurement of one frame and the real-vs-simulated comparison. */
#ifndef DAO_TOOLS_SENSOR_COMPARE_H
#define DAO_TOOLS_SENSOR_COMPARE_H

#include <stdint.h>

#include <depthao/depthao.h>

#include "synth/planes.h"
#include "synth/sensor_stats.h"

/*
 * Planes (synth_planes_find, told the frame's band step) and statistics of
 * one frame in metres; planes (SYNTH_PLANES_MAX), nplanes and labels (w x h)
 * may be NULL.  0 or -errno with a message.
 */
int sensorstats_measure(const float *z, const struct dao_camera *cam, double unit,
			struct synth_sensor_stats *s, struct synth_plane *planes, int *nplanes,
			int32_t *labels, struct dao_error *err);

/* The human-readable report of sensorstats (f: the camera's focal length, px). */
void sensorstats_print(const char *title, const struct synth_sensor_stats *s, double f);

/*
 * The comparison of docs/sensor-models.md: the real frames of
 * `data_dir` and the simulated sensors on the synthetic scenes, as Markdown
 * tables on stdout, and if `picture` is not NULL a PNG of their plane
 * residuals.  Returns the exit status.
 */
int sensor_compare_run(const char *data_dir, const char *picture);

#endif
