/* SPDX-License-Identifier: MIT */
/*
 * Planes in a depth frame (tools and tests only), found by RANSAC in inverse
 * depth.  On any plane 1/z is an affine function of the normalised image
 * coordinates x' = (u - cx)/fx, y' = (v - cy)/fy:
 *     w = 1/z = a + b x' + c y',
 * with the unit normal facing the camera n = -(b, c, a)/|(a, b, c)| and the
 * plane at distance 1/|(a, b, c)| from the camera.  Three pixels give a
 * hypothesis by a 3x3 solve, and residuals are measured in 1/z, the unit in
 * which triangulating sensors (structured light, stereo) have about
 * constant noise over depth (a disparity error of e px is e/(f b) in 1/z).
 */
#ifndef DAO_SYNTH_PLANES_H
#define DAO_SYNTH_PLANES_H

#include <stdint.h>

#include <depthao/camera.h>
#include <depthao/error.h>

#define SYNTH_PLANES_MAX 16

struct synth_plane {
	double a, b, c;          /* 1/z = a + b x' + c y' */
	double normal[3];        /* unit, towards the camera */
	double distance;         /* of the plane from the camera centre, m */
	long pixels;             /* in its region */
	double zmin, zmax, zmean;
	double sigma_w;          /* robust sigma of the 1/z residual in the region, 1/m */
	double tolerance_w;      /* the final inlier tolerance, 1/m */
};

struct synth_plane_options {
	int max_planes;          /* at most SYNTH_PLANES_MAX */
	int min_pixels;          /* smallest plane region kept */
	int iterations;          /* RANSAC hypotheses per plane */
	int neighbourhood;       /* the 2nd and 3rd sample lie within this many px of the 1st */
	double tolerance_w;      /* inlier tolerance of the hypotheses, 1/m (lower on frames
				    whose own noise is lower: 5 x the RMS of 9x9 block fits) */
	double sigmas;           /* refined tolerance: this many robust sigmas of the residual */
	double depth_unit;       /* m per count of the source (0: float depth); 1.5 units are
				    always tolerated, whatever the sigma */
	double step_w;           /* 1/z between adjacent depth levels of a banded source
				    (1 / synth_sensor_stats' band_c), 0 if not banded */
	int tight;               /* 1: the refinement keeps within the hypothesis tolerance
				    (fewer slow deviations in the regions, fewer planes
				    slanting across stairs); 0: up to tolerance_w */
	uint64_t seed;
};

/* Defaults for 640x480 sensor frames: 8 planes of >= 2500 px, 300 hypotheses each. */
void synth_plane_options_default(struct synth_plane_options *o);

/* 1/z of plane p at pixel (u, v); <= 0 where the plane is behind the camera. */
double synth_plane_w(const struct synth_plane *p, const struct dao_camera *cam, double u, double v);

/*
 * Finds up to o->max_planes planes in `z` (metres, 0 = no data; w x h as in
 * `cam`), largest first.  `labels` (w x h) gets the plane index of each pixel
 * of a plane's region (its 4-connected inlier components of at least
 * o->min_pixels / 4 px), -1 elsewhere.  Deterministic for o->seed.  Returns 0
 * or -ENOMEM / -EINVAL with a message.
 */
int synth_planes_find(const float *z, const struct dao_camera *cam,
		      const struct synth_plane_options *o, struct synth_plane *planes, int *count,
		      int32_t *labels, struct dao_error *err);

/* Least-squares plane in 1/z through the pixels labelled `label`; -1 if degenerate. */
int synth_plane_fit(const float *z, const struct dao_camera *cam, const int32_t *labels,
		    int32_t label, struct synth_plane *p);

/* Removes `px` pixels from the border of every region (4-neighbourhood erosion). */
int synth_labels_erode(int32_t *labels, int w, int h, int px);

#endif
