/* SPDX-License-Identifier: MIT */
/*
 * Active stereo, RealSense D4xx class.
 *
 * Two IR cameras AS_BASELINE apart see the scene textured by a projected
 * dot pattern (the projector only adds texture: unlike structured light no
 * reference is stored); the depth camera is the left one, and each of its
 * pixels is matched along the row of the right image.  The Intel D400
 * documentation describes the rest: a disparity search of 0..126 px (at
 * 848 px wide), sub-pixel interpolation to 1/32 px, depth in 1 mm units, a
 * left-right check, and an invalid band at the left of the image, as wide as
 * the largest disparity: the right camera does not see what the leftmost
 * pixels of the left camera see.  Step by step:
 *
 *  1. Both IR images by ray tracing: the left camera is the scene's camera
 *     (its render gives the points), the right one sits AS_BASELINE along +x
 *     and gets rays of its own; a point is lit if the projector (between the
 *     cameras) sees it, and shows the pattern at its projector column (the
 *     same row: all three are rectified), with cos / distance^2, ambient
 *     light, and shot-like noise.
 *  2. Block matching (block_match.c): ZNCC over AS_WINDOW^2 windows of the
 *     left image against the right image at integer disparities, and the
 *     vertex of a parabola through the scores at d - 1, d, d + 1.  On a
 *     correlation peak that is not a parabola this vertex is biased toward
 *     the integer ("pixel locking", Shimizu & Okutomi 2005): the disparity
 *     of a slanted plane clusters around integers, a ripple of the depth
 *     with one period per pixel of disparity.  Quantised to 1/32 px.
 *  3. Invalidation: score below AS_MIN_SCORE, a second peak within
 *     AS_UNIQUENESS, the left-right check (the right image's best match
 *     must come back within 1 px), no texture, segments of fewer than
 *     AS_MIN_SEGMENT px; the left band where no window fits.
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

#define AS_BASELINE 0.05         /* m, right camera along +x */
#define AS_PROJECTOR_X 0.03      /* m, the projector between the cameras */
#define AS_WINDOW 7              /* px */
#define AS_ZMIN 0.3              /* m: the disparity search range (0 .. f b / ZMIN) */
#define AS_SUBPIXEL 32
#define AS_DOT_PITCH 3.6         /* px */
#define AS_DOT_SIGMA 0.7         /* px */
#define AS_PATTERN_SEED 0x4434303070726f6aull
#define AS_ALBEDO 0.8
#define AS_AMBIENT 0.01
#define AS_NOISE 0.05            /* relative (shot-like) noise of a pixel */
#define AS_READ_NOISE 0.002
#define AS_MIN_SCORE 0.5
#define AS_UNIQUENESS 0.03
#define AS_MIN_TEXTURE 0.004
#define AS_MIN_SEGMENT 60

struct stereo_job {
	const struct synth_scene *scene;
	const struct dao_camera *cam;
	const struct synth_image *img;
	const struct synth_pattern *pat;
	uint64_t seed;
	float *left, *right;
};

/* Brightness of the surface point X with normal n (facing the viewer), pattern row y. */
static double shade(const struct stereo_job *j, vec3 X, vec3 n, int y)
{
	const struct dao_camera *c = j->cam;
	const vec3 P = v3(AS_PROJECTOR_X, 0, 0);
	const vec3 L = v3_sub(X, P);
	const double d2 = v3_dot(L, L), cos_in = -v3_dot(n, L) / sqrt(d2);
	double signal = AS_AMBIENT * AS_ALBEDO;
	if (cos_in > 0.0 && !synth_occluded(j->scene, P, L, 1e-9, 1.0 - 1e-4)) {
		const double up = c->fx * L.x / L.z + c->cx;
		signal += AS_ALBEDO * cos_in / d2 * synth_pattern_at(j->pat, up, y);
	}
	return signal;
}

static void render_band(void *ctx, int band, int y0, int y1)
{
	(void)band;
	const struct stereo_job *j = ctx;
	const struct dao_camera *c = j->cam;
	const int w = (int)c->width;
	for (int y = y0; y < y1; y++)
		for (int x = 0; x < w; x++) {
			const size_t i = (size_t)y * w + x;
			uint64_t rng = synth_pixel_rng(j->seed, 3, i);
			/* left: the render's point */
			double s = 0.0;
			const double z = j->img->depth[i];
			if (z > 0.0) {
				const vec3 X = v3((x - c->cx) / c->fx * z, (y - c->cy) / c->fy * z, z);
				const vec3 n = v3(j->img->normal[3 * i], j->img->normal[3 * i + 1],
						  j->img->normal[3 * i + 2]);
				s = shade(j, X, n, y);
			}
			j->left[i] = (float)(s * (1.0 + AS_NOISE * synth_gaussian(&rng)) +
					     AS_READ_NOISE * synth_gaussian(&rng));
			/* right: a ray of its own */
			const vec3 O = v3(AS_BASELINE, 0, 0);
			const vec3 d = v3((x - c->cx) / c->fx, (y - c->cy) / c->fy, 1.0);
			double t;
			vec3 n;
			s = 0.0;
			if (synth_trace(j->scene, O, d, 1e-9, 1e9, &t, &n) >= 0) {
				if (v3_dot(n, d) > 0.0)
					n = v3_scale(n, -1.0);
				s = shade(j, v3_add(O, v3_scale(d, t)), n, y);
			}
			j->right[i] = (float)(s * (1.0 + AS_NOISE * synth_gaussian(&rng)) +
					      AS_READ_NOISE * synth_gaussian(&rng));
		}
}

int synth_sensor_active_stereo(const struct synth_scene *scene, const struct dao_camera *cam,
			       const struct synth_image *img, uint64_t seed, int threads,
			       float *out, struct dao_error *err)
{
	const int w = (int)cam->width, h = (int)cam->height;
	const size_t np = (size_t)w * h;
	const double fb = cam->fx * AS_BASELINE;
	const int dmax = (int)ceil(fb / AS_ZMIN);
	struct synth_pattern pat = { 0 };
	/* the projector's columns that either camera can see */
	const int pu0 = -(int)ceil(cam->fx * AS_BASELINE / AS_ZMIN) - 4;
	const int pu1 = w + (int)ceil(cam->fx * AS_PROJECTOR_X / AS_ZMIN) + 4;
	float *left = malloc(np * sizeof(float)), *right = malloc(np * sizeof(float));
	float *rdisp = malloc(np * sizeof(float));
	struct synth_match m = {
		.disparity = malloc(np * sizeof(float)), .score = malloc(np * sizeof(float)),
		.second = malloc(np * sizeof(float)), .texture = malloc(np * sizeof(float)),
		.right_disparity = rdisp,
	};
	int ret = -ENOMEM;
	if (!left || !right || !rdisp || !m.disparity || !m.score || !m.second || !m.texture ||
	    synth_pattern_make(&pat, pu0, pu1, h, AS_DOT_PITCH, AS_DOT_SIGMA, AS_PATTERN_SEED))
		goto out;
	struct stereo_job j = { scene, cam, img, &pat, seed, left, right };
	synth_parallel_rows(h, threads, 1, render_band, &j);
	const struct synth_match_options mo = {
		.window = AS_WINDOW, .dmin = 0, .dmax = dmax, .right_offset = 0, .right_width = w,
		.left_right = 1,
	};
	if ((ret = synth_block_match(left, right, w, h, &mo, threads, &m)))
		goto out;
	const double q = 1.0 / AS_SUBPIXEL;
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			const size_t i = (size_t)y * w + x;
			float d = m.disparity[i];
			int ok = !isnan(d) && m.score[i] >= AS_MIN_SCORE &&
				 m.second[i] <= m.score[i] - AS_UNIQUENESS &&
				 m.texture[i] >= AS_MIN_TEXTURE && d > 0.5f && d < dmax;
			if (ok) {
				/* left-right: the right pixel's own best match comes back */
				int xr = (int)lrintf((float)x - d);
				float dr = xr >= 0 && xr < w ? rdisp[(size_t)y * w + xr] : NAN;
				ok = !isnan(dr) && fabsf(dr - d) <= 1.0f;
			}
			m.disparity[i] = ok ? (float)(floor(d / q + 0.5) * q) : NAN;
		}
	if ((ret = synth_remove_speckles(m.disparity, w, h, 1.0f, AS_MIN_SEGMENT)))
		goto out;
	for (size_t i = 0; i < np; i++)
		out[i] = isnan(m.disparity[i]) ? 0.0f : (float)(fb / m.disparity[i]);
out:
	free(pat.v);
	free(left);
	free(right);
	free(rdisp);
	free(m.disparity);
	free(m.score);
	free(m.second);
	free(m.texture);
	return ret ? dao_error_set(err, ret, "active stereo: %s",
				   ret == -ENOMEM ? "out of memory" : "invalid matching options")
		   : 0;
}
