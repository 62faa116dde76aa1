/* SPDX-License-Identifier: MIT */
/*
 * Statistics of a depth frame that characterise its sensor (tools and tests
 * only): the residual of its planes (amplitude per depth, spatial
 * autocorrelation), the quantisation of its depth values (band spacing), and
 * where data is missing (holes, projector shadows beside foreground edges,
 * flying pixels).  The same measurement runs on real frames and on the
 * simulated sensors (`depthao sensorstats`), so the two can be compared.
 */
#ifndef DAO_SYNTH_SENSOR_STATS_H
#define DAO_SYNTH_SENSOR_STATS_H

#include <stdint.h>

#include <depthao/camera.h>
#include <depthao/error.h>

#include "synth/planes.h"

#define SYNTH_STATS_LAGS 32
#define SYNTH_STATS_ZBINS 20
#define SYNTH_STATS_ZBIN 0.5        /* m per depth bin: [0, 0.5), [0.5, 1), ... */
#define SYNTH_STATS_ERODE 2         /* px taken off the plane regions' borders */

struct synth_zbin_stats {
	long pixels;                /* plane pixels in the bin */
	double sigma_z;             /* robust sigma of their depth residual, m */
	double sigma_w;             /* ... of their 1/z residual, 1/m */
	int levels;                 /* distinct depth values of the bin (every pixel) */
	double gap;                 /* median step between adjacent levels, m (0: too few) */
	double band_c;              /* median of z1 z2 / (z2 - z1) over adjacent levels, m px */
};

struct synth_sensor_stats {
	int planes;
	long plane_pixels;          /* after erosion */
	double sigma_w;             /* robust sigma of the 1/z residual over all planes, 1/m */
	struct synth_zbin_stats bin[SYNTH_STATS_ZBINS];
	/* autocorrelation of the 1/z residual at lags 0..LAGS px, within one plane */
	double acf_row[SYNTH_STATS_LAGS + 1], acf_col[SYNTH_STATS_LAGS + 1];
	double corr_len_row, corr_len_col; /* lag where it first falls below 1/e, px */
	/*
	 * Depth quantisation: for a disparity quantised to q px, adjacent levels
	 * z1 < z2 satisfy 1/z1 - 1/z2 = q/(f b), so z1 z2/(z2 - z1) = f b / q
	 * (Kinect v1: 580 x 0.075 x 8 = 348).  Median over level pairs more than
	 * 8 units apart (finer steps are distorted by the source's rounding);
	 * 0 where the values are not banded.
	 */
	double band_c;
	long band_pairs;
	double hole_fraction;       /* pixels without depth */
	double edge_hole_fraction;  /* share of them in row runs between a near and a far side */
	/*
	 * Shadows: such runs of >= 4 px whose length matches f b (1/z_near -
	 * 1/z_far) for a baseline b of 2-15 cm; a projector on the camera's right (+x) hides
	 * background on the left of foreground edges (near side on the run's right).
	 */
	long shadow_left;           /* shadow runs with the near side on their right */
	long shadow_right;          /* ... on their left */
	double shadow_width;        /* median length of the shadow runs, px */
	double shadow_baseline;     /* median baseline they imply, m */
	long edge_pixels;           /* row triples spanning a depth step of > 10 % between sides
				       flat for another pixel (not a slanted surface's ramp) */
	long flying_pixels;         /* ... whose middle pixel lies between the two sides */
};

/*
 * Measures `z` (metres, 0 = no data, w x h as in `cam`; `depth_unit` m per
 * count of the source, for the levels) with the planes found by
 * synth_planes_find (`labels` is eroded by SYNTH_STATS_ERODE px here, in a
 * copy).  Returns 0 or -ENOMEM with a message.
 */
int synth_sensor_stats(const float *z, const struct dao_camera *cam, double depth_unit,
		       const struct synth_plane *planes, int nplanes, const int32_t *labels,
		       struct synth_sensor_stats *s, struct dao_error *err);

/*
 * Accumulates several frames' statistics into one: call _begin, then
 * _add for each frame's result, then _end (pixel-weighted means of the
 * per-frame values; sums of counts).
 */
struct synth_stats_acc {
	struct synth_sensor_stats sum;
	double w_sigma, w_bin[SYNTH_STATS_ZBINS], w_band, w_acf, w_shadow;
	double w_gap[SYNTH_STATS_ZBINS];
	int frames;
};
void synth_stats_acc_begin(struct synth_stats_acc *a);
void synth_stats_acc_add(struct synth_stats_acc *a, const struct synth_sensor_stats *s);
void synth_stats_acc_end(struct synth_stats_acc *a, struct synth_sensor_stats *out);

/*
 * Only the band constant of sensor_stats (f b / q, 0 if the depth is not
 * banded), e.g. to give the plane finder the band step 1/band_c.
 */
int synth_band_constant(const float *z, int w, int h, double depth_unit, double *band_c);

/* The plane residual 1/z - plane (1/m) per pixel of the eroded regions, NAN elsewhere. */
int synth_plane_residual_map(const float *z, const struct dao_camera *cam,
			     const struct synth_plane *planes, const int32_t *labels, float *out);

#endif
