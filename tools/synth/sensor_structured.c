/* SPDX-License-Identifier: MIT */
/*
 * Structured light, Kinect v1 / PrimeSense class.
 *
 * The device projects a fixed pseudo-random pattern of infrared dots from a
 * projector beside the IR camera, and finds each camera pixel's disparity
 * by correlating a window of the IR image with a stored image of the pattern
 * along the epipolar line (the rows: projector and camera are rectified).
 * Depth follows from triangulation, z = f b / d, with d quantised to 1/8
 * pixel of the IR camera (Khoshelham & Elberink 2012: f = 580 px, b =
 * 7.5 cm; disparity stored in 1/8 px).  What this simulation does, step by
 * step, and which property of real frames each step produces:
 *
 *  1. The pattern: dots on a jittered grid (about 0.1 per pixel, Gaussian
 *     spots of 0.6 px) in the projector's image, which has the camera's
 *     intrinsics and sits SL_BASELINE to the camera's +x side.  The stored
 *     reference is the pattern as the camera sees it at infinity.
 *  2. The IR image, by ray tracing: a camera pixel sees the surface point X
 *     (the render's depth); the projector lights X if nothing lies between
 *     them (a shadow ray: projector shadows, on the side of foreground
 *     objects away from the projector, i.e. left of them); X shows the
 *     pattern at the projector column x - f b / z (the same row), weighted by
 *     cos(incidence) / distance^2, plus ambient light, laser speckle
 *     (multiplicative: the disparity noise then stays constant over depth,
 *     as measured on real frames) and read noise.
 *     The projected pattern is displaced from the stored one by a smooth
 *     random field (SL_WAVE_SIGMA px, correlated over SL_WAVE_SCALE px): the
 *     slow "wavy" deviation of real Kinect walls (reference and projection
 *     drift apart with temperature and lens distortion; Smisek et al. 2011
 *     and Herrera et al. 2012 model it as a per-pixel disparity distortion).
 *     It belongs to the device: drawn from the device's seed, the same in
 *     every frame of a sequence (on the real Kinect recording the depth
 *     error repeats from frame to frame: docs/sensor-models.md), while the
 *     speckle and read noise are drawn anew for each frame.
 *  3. Block matching (block_match.c): ZNCC over SL_WINDOW^2 windows against
 *     the reference at every integer disparity of the range.  Overlapping
 *     windows make the errors of neighbouring pixels correlated over about
 *     the window size (the blobs on real walls), and a window across a
 *     depth edge takes one side's disparity: edges are displaced and ragged,
 *     not blended.
 *  4. Sub-pixel refinement on the grid of the output: the ZNCC of the window
 *     against the reference shifted by each 1/8 px of the IR camera
 *     (SL_FOCAL_IR) near the integer match, and the best of them.  So the
 *     disparity is quantised to 1/8 px without the pixel-locking bias of a
 *     parabola fit: the depth bands of z^2 / (8 f b), 1.1 cm at 2 m, 4.6 cm
 *     at 4 m.
 *  5. Invalidation: no match (score below SL_MIN_SCORE), ambiguous (a second
 *     peak within SL_UNIQUENESS), no pattern around the pixel itself (its
 *     5x5 neighbourhood without texture: shadows keep their full width
 *     instead of being filled from the lit side of the window; dark or far
 *     surfaces), outside the range, and segments of fewer than
 *     SL_MIN_SEGMENT px (the device's speckle filter).
 *
 * The constants were set by comparing `depthao sensorstats` on the real
 * Kinect frames of ../shared/data with this model (README, Sensor models).
 */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/error.h>
#include "synth/block_match.h"
#include "synth/parallel.h"
#include "synth/sensor.h"
#include "synth/sensor_field.h"

#define SL_BASELINE 0.075        /* m, projector on the camera's +x side */
#define SL_FOCAL_IR 580.0        /* px of the IR camera, whose 1/8 px is the disparity unit */
#define SL_SUBPIXEL 8
#define SL_WINDOW 9              /* px */
#define SL_ZMIN 0.5              /* m: the disparity search range */
#define SL_ZMAX 8.0
#define SL_DOT_PITCH 3.2         /* px between the dots' grid cells (~0.1 dots per px) */
#define SL_DOT_SIGMA 0.6         /* px */
#define SL_PATTERN_SEED 0x4b696e6563747631ull /* fixed: the pattern belongs to the device */
#define SL_ALBEDO 0.8
#define SL_AMBIENT 0.01          /* of the dot peak at 1 m */
#define SL_SPECKLE 0.30          /* multiplicative laser speckle, standard deviation */
#define SL_READ_NOISE 0.002      /* of the dot peak at 1 m */
#define SL_WAVE_SCALE 80.0       /* px */
#define SL_WAVE_SIGMA 0.08       /* px of the IR camera */
#define SL_MIN_SCORE 0.4
#define SL_UNIQUENESS 0.02
#define SL_MIN_TEXTURE 0.004     /* standard deviation of the window and of the 5x5 around the
				    pixel (above read noise and speckled ambient light) */
#define SL_MIN_SEGMENT 60        /* px */
#define SL_REFINE 2              /* sub-pixel levels tried on each side of the integer match */

struct render_job {
	const struct synth_scene *scene;
	const struct dao_camera *cam;
	const struct synth_image *img;
	const struct synth_pattern *pat;
	uint64_t seed;
	const float *wave;   /* pattern displacement, px */
	float *ir;
};

/* The IR image: the pattern on the scene as the camera sees it (step 2). */
static void render_band(void *ctx, int band, int y0, int y1)
{
	(void)band;
	const struct render_job *j = ctx;
	const struct dao_camera *c = j->cam;
	const int w = (int)c->width;
	const vec3 P = v3(SL_BASELINE, 0, 0);
	for (int y = y0; y < y1; y++)
		for (int x = 0; x < w; x++) {
			const size_t i = (size_t)y * w + x;
			uint64_t rng = synth_pixel_rng(j->seed, 1, i);
			const double z = j->img->depth[i];
			double signal = 0.0;
			if (z > 0.0) {
				const vec3 X = v3((x - c->cx) / c->fx * z, (y - c->cy) / c->fy * z, z);
				const vec3 L = v3_sub(X, P);
				const double d2 = v3_dot(L, L);
				const vec3 n = v3(j->img->normal[3 * i], j->img->normal[3 * i + 1],
						  j->img->normal[3 * i + 2]);
				const double cos_in = -v3_dot(n, L) / sqrt(d2);
				if (cos_in > 0.0 && !synth_occluded(j->scene, P, L, 1e-9, 1.0 - 1e-4)) {
					const double up = x - c->fx * SL_BASELINE / z + j->wave[i];
					signal = SL_ALBEDO * cos_in / d2 * synth_pattern_at(j->pat, up, y);
				}
				signal += SL_AMBIENT * SL_ALBEDO;
				signal *= 1.0 + SL_SPECKLE * synth_gaussian(&rng);
			}
			j->ir[i] = (float)(signal + SL_READ_NOISE * synth_gaussian(&rng));
		}
}

/*
 * ZNCC of the window of `ir` at (x, y) against the pattern shifted by
 * disparity d (camera px): the window's samples of the pattern lie 1 px =
 * SYNTH_PATTERN_OVERSAMPLE table entries apart, so one interpolation weight serves all.
 */
static float zncc_at(const float *ir, int w, const struct synth_pattern *pat, int x, int y, double d,
		     float mean_i, float inv_i)
{
	const int r = SL_WINDOW / 2;
	const double n = SL_WINDOW * SL_WINDOW;
	const double s0 = (x - r - d - pat->u0) * SYNTH_PATTERN_OVERSAMPLE;
	if (!(s0 >= 0.0 && s0 + (SL_WINDOW - 1) * SYNTH_PATTERN_OVERSAMPLE < pat->width - 1))
		return -1.0f;
	const int i0 = (int)s0;
	const float t = (float)(s0 - i0), t1 = 1.0f - t;
	float sp = 0, spp = 0, sip = 0;
	for (int yy = y - r; yy <= y + r; yy++) {
		const float *row = ir + (size_t)yy * w + (x - r);
		const float *pr = pat->v + (size_t)yy * pat->width + i0;
		for (int k = 0; k < SL_WINDOW; k++) {
			const float p = t1 * pr[k * SYNTH_PATTERN_OVERSAMPLE] + t * pr[k * SYNTH_PATTERN_OVERSAMPLE + 1];
			sp += p;
			spp += p * p;
			sip += row[k] * p;
		}
	}
	double var = spp / n - (sp / n) * (sp / n);
	if (!(var > 1e-12) || !(inv_i > 0))
		return -1.0f;
	return (float)((sip - sp * mean_i) * inv_i / sqrt(n * var));
}

struct refine_job {
	const float *ir;
	const struct synth_pattern *pat;
	const float *mean, *inv;
	float *disp;
	int w;
	double q;
};

/* Step 4: the best level k q within SL_REFINE levels of the integer stage's estimate. */
static void refine_band(void *ctx, int band, int y0, int y1)
{
	(void)band;
	const struct refine_job *j = ctx;
	for (int y = y0; y < y1; y++)
		for (int x = 0; x < j->w; x++) {
			const size_t i = (size_t)y * j->w + x;
			if (isnan(j->disp[i]))
				continue;
			const long m0 = lround(j->disp[i] / j->q);
			float best = -2.0f;
			long mb = m0;
			for (long m = m0 - SL_REFINE; m <= m0 + SL_REFINE; m++) {
				float c = zncc_at(j->ir, j->w, j->pat, x, y, m * j->q, j->mean[i], j->inv[i]);
				if (c > best)
					best = c, mb = m;
			}
			j->disp[i] = (float)(mb * j->q);
		}
}

int synth_sensor_structured_light(const struct synth_scene *scene, const struct dao_camera *cam,
				  const struct synth_image *img, uint64_t device_seed,
				  uint64_t seed, int threads, float *out, struct dao_error *err)
{
	const int w = (int)cam->width, h = (int)cam->height, r = SL_WINDOW / 2;
	const size_t np = (size_t)w * h;
	const double fb = cam->fx * SL_BASELINE;
	const int dmin = (int)floor(fb / SL_ZMAX), dmax = (int)ceil(fb / SL_ZMIN);
	/* the reference covers every projector column a window can reach */
	const int u0 = -dmax - r - 2, wr = w - u0;
	struct synth_pattern pat = { 0 };
	float *ir = malloc(np * sizeof(float)), *ref = malloc((size_t)wr * h * sizeof(float));
	float *wave = malloc(np * sizeof(float)), *mean = malloc(np * sizeof(float));
	float *inv = malloc(np * sizeof(float)), *tex3 = malloc(np * sizeof(float));
	struct synth_match m = {
		.disparity = malloc(np * sizeof(float)), .score = malloc(np * sizeof(float)),
		.second = malloc(np * sizeof(float)), .texture = malloc(np * sizeof(float)),
	};
	int ret = -ENOMEM;
	if (!ir || !ref || !wave || !mean || !inv || !tex3 || !m.disparity || !m.score || !m.second ||
	    !m.texture || synth_pattern_make(&pat, u0 - 2, w + 4, h, SL_DOT_PITCH, SL_DOT_SIGMA, SL_PATTERN_SEED) ||
	    synth_smooth_field(wave, w, h, SL_WAVE_SCALE, device_seed))
		goto out;
	/* step 1: the stored reference, the pattern at infinity */
	for (int y = 0; y < h; y++)
		for (int u = 0; u < wr; u++)
			ref[(size_t)y * wr + u] = synth_pattern_at(&pat, u + u0, y);
	/* step 2 */
	const double wave_px = SL_WAVE_SIGMA * cam->fx / SL_FOCAL_IR;
	for (size_t i = 0; i < np; i++)
		wave[i] = (float)(wave_px * wave[i]);
	struct render_job rj = { scene, cam, img, &pat, seed, wave, ir };
	synth_parallel_rows(h, threads, 1, render_band, &rj);
	/* step 3 */
	const struct synth_match_options mo = {
		.window = SL_WINDOW, .dmin = dmin, .dmax = dmax,
		.right_offset = -u0, .right_width = wr,
	};
	if ((ret = synth_block_match(ir, ref, w, h, &mo, threads, &m)) ||
	    (ret = synth_window_stats(ir, w, h, SL_WINDOW, mean, inv, NULL)) ||
	    (ret = synth_window_stats(ir, w, h, 5, wave, ref, tex3)))
		goto out;
	/* step 5, the rules on the integer match */
	for (size_t i = 0; i < np; i++) {
		float d = m.disparity[i];
		if (isnan(d) || m.score[i] < SL_MIN_SCORE || m.second[i] > m.score[i] - SL_UNIQUENESS ||
		    m.texture[i] < SL_MIN_TEXTURE || tex3[i] < SL_MIN_TEXTURE || d <= dmin || d >= dmax)
			m.disparity[i] = NAN;
	}
	/* step 4: 1/8 px of the IR camera, in camera px */
	struct refine_job fj = { ir, &pat, mean, inv, m.disparity, w,
				 cam->fx / (SL_FOCAL_IR * SL_SUBPIXEL) };
	synth_parallel_rows(h, threads, 1, refine_band, &fj);
	if ((ret = synth_remove_speckles(m.disparity, w, h, 1.0f, SL_MIN_SEGMENT)))
		goto out;
	for (size_t i = 0; i < np; i++)
		out[i] = isnan(m.disparity[i]) ? 0.0f : (float)(fb / m.disparity[i]);
out:
	free(pat.v);
	free(ir);
	free(ref);
	free(wave);
	free(mean);
	free(inv);
	free(tex3);
	free(m.disparity);
	free(m.score);
	free(m.second);
	free(m.texture);
	return ret ? dao_error_set(err, ret, "structured light: %s",
				   ret == -ENOMEM ? "out of memory" : "invalid matching options")
		   : 0;
}
