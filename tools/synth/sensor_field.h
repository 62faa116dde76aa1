/* SPDX-License-Identifier: MIT */
/* Building blocks shared by the sensor models (tools and tests only). */
#ifndef DAO_SYNTH_SENSOR_FIELD_H
#define DAO_SYNTH_SENSOR_FIELD_H

#include <stdint.h>

#include "synth/rng.h"

/* A standard normal deviate (Box-Muller). */
double synth_gaussian(uint64_t *state);

/* A generator state for pixel i of a frame with `seed`, for a given purpose (stream). */
static inline uint64_t synth_pixel_rng(uint64_t seed, uint64_t stream, uint64_t i)
{
	uint64_t s = seed * 0x9e3779b97f4a7c15ull ^ (stream << 48) ^ i;
	synth_rng_next(&s);
	return s;
}

/*
 * A smooth random field of unit standard deviation over w x h pixels: normal
 * deviates on a grid of `scale` px, interpolated bilinearly, then smoothed
 * with a box of `scale` / 2 px (twice), and scaled to unit sigma.  Its
 * autocorrelation falls to about 1/e at 0.6 `scale`.  Deterministic for seed.
 * Returns 0 or -ENOMEM.
 */
int synth_smooth_field(float *out, int w, int h, double scale, uint64_t seed);

/*
 * Takes out 4-connected segments of fewer than `min_area` pixels whose
 * neighbours differ by at most `max_diff` (sets them to NAN), like the speckle
 * filters of depth sensors.  Returns 0 or -ENOMEM.
 */
int synth_remove_speckles(float *disp, int w, int h, float max_diff, int min_area);

/*
 * A projected dot pattern, tabulated per image row (projector and cameras
 * are rectified: a projector pixel lights the camera row of the same
 * number) at SYNTH_PATTERN_OVERSAMPLE samples per pixel along the row.
 */
#define SYNTH_PATTERN_OVERSAMPLE 16

struct synth_pattern {
	int u0;          /* projector column of table index 0 */
	int width;       /* samples per row */
	int h;
	float *v;        /* h rows x width samples */
};

/*
 * Dots on a jittered grid of `pitch` px (one per cell), Gaussian spots of
 * `sigma` px integrated over a pixel (sigma^2 + 1/12 per axis), each with a
 * brightness in [0.5, 1], over projector columns [u0, u1) and rows [0, h).
 * Free p->v.  0 or -ENOMEM.
 */
int synth_pattern_make(struct synth_pattern *p, int u0, int u1, int h, double pitch,
		       double sigma, uint64_t seed);

/* The pattern at projector column u (fractional) of row y; 0 outside. */
static inline float synth_pattern_at(const struct synth_pattern *p, double u, int y)
{
	double s = (u - p->u0) * SYNTH_PATTERN_OVERSAMPLE;
	if (!(s >= 0.0 && s < p->width - 1) || y < 0 || y >= p->h)
		return 0.0f;
	int i = (int)s;
	float t = (float)(s - i);
	const float *row = p->v + (size_t)y * p->width;
	return row[i] + t * (row[i + 1] - row[i]);
}

#endif
