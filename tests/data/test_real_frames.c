/* SPDX-License-Identifier: MIT */
/*
 * Real sensor frames from ../shared/data through the default pipeline:
 * decoding matches the documented ranges, outputs are sane and deterministic,
 * and large flat regions (found automatically) come out open, not banded.
 * With the defaults (noise-model=auto: the noise measured in the frame) the
 * same flat regions must come out at least as open as with the fixed noise
 * model the defaults had before, and the noise must have been measured.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/test_common.h"

struct real_frame {
	const char *file;
	float unit;
	double fx, fy, cx, cy;
	double zmin_mm, zmax_mm; /* from ../shared/data/README.md */
	double radius;           /* AO radius for the scene's scale, m */
};

static const struct real_frame frames[] = {
	{ "redwood_open3d/depth_00000.png", 0.001f, 525, 525, 319.5, 239.5, 955, 2702, 0.5 },
	{ "redwood_open3d/depth_00001.png", 0.001f, 525, 525, 319.5, 239.5, 955, 2702, 0.5 },
	{ "tum_open3d/TUM_depth.png", 0.0002f, 525, 525, 319.5, 239.5, 1460, 9330, 0.5 },
	{ "realsense_6dpose/depth.png", 0.001f, 622.439, 622.439, 315.746, 250.804, 361, 1581, 0.15 }, /* table top */
};

/*
 * "Open flat" blocks: 16x16 blocks on a plane (1/z, which is affine in the
 * pixel on any plane, fits within the sensor noise) with nothing on the
 * camera's side of that plane within the AO radius R in 3D: every valid pixel
 * whose point lies within R of the block centre is at or behind the plane.
 * Their true AO is 1 (up to what the camera cannot see), so sensor noise and
 * disparity banding are the only things that could darken them.
 */
#define BLOCK 16

static int fit_inverse_plane(const float *z, int w, int x0, int y0, double *abc, double *rms_m)
{
	double s[3][3] = { { 0 } }, t[3] = { 0 };
	for (int y = y0; y < y0 + BLOCK; y++)
		for (int x = x0; x < x0 + BLOCK; x++) {
			if (z[y * w + x] <= 0)
				return -1;
			double v = 1.0 / z[y * w + x], r[3] = { 1, x - x0, y - y0 };
			for (int i = 0; i < 3; i++) {
				t[i] += r[i] * v;
				for (int j = 0; j < 3; j++)
					s[i][j] += r[i] * r[j];
			}
		}
	/* Cramer's rule on the 3x3 normal equations */
	double det = s[0][0] * (s[1][1] * s[2][2] - s[1][2] * s[2][1]) -
		     s[0][1] * (s[1][0] * s[2][2] - s[1][2] * s[2][0]) +
		     s[0][2] * (s[1][0] * s[2][1] - s[1][1] * s[2][0]);
	if (fabs(det) < 1e-12)
		return -1;
	for (int k = 0; k < 3; k++) {
		double m[3][3];
		memcpy(m, s, sizeof m);
		for (int i = 0; i < 3; i++)
			m[i][k] = t[i];
		abc[k] = (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
			  m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
			  m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])) / det;
	}
	double e2 = 0;
	for (int y = y0; y < y0 + BLOCK; y++)
		for (int x = x0; x < x0 + BLOCK; x++) {
			double zp = 1.0 / (abc[0] + abc[1] * (x - x0) + abc[2] * (y - y0));
			e2 += (z[y * w + x] - zp) * (z[y * w + x] - zp);
		}
	*rms_m = sqrt(e2 / (BLOCK * BLOCK));
	return 0;
}

/* 1 if nothing within RADIUS of the block centre is on the camera side of its plane. */
static int nothing_above(const float *z, int w, int h, const struct dao_camera *cam, int x0,
			 int y0, const double *abc, double radius)
{
	const int cx = x0 + BLOCK / 2, cy = y0 + BLOCK / 2;
	double C[3];
	dao_camera_pixel_to_view(cam, cx, cy, z[cy * w + cx], C);
	const int r = (int)ceil(radius * cam->fx / C[2] * 1.5) + 1;
	for (int y = cy - r; y <= cy + r; y++)
		for (int x = cx - r; x <= cx + r; x++) {
			if (x < 0 || y < 0 || x >= w || y >= h || z[y * w + x] <= 0)
				continue;
			double P[3];
			dao_camera_pixel_to_view(cam, x, y, z[y * w + x], P);
			double d2 = (P[0] - C[0]) * (P[0] - C[0]) + (P[1] - C[1]) * (P[1] - C[1]) +
				    (P[2] - C[2]) * (P[2] - C[2]);
			if (d2 > radius * radius)
				continue;
			double wp = abc[0] + abc[1] * (x - x0) + abc[2] * (y - y0);
			if (wp <= 0)
				return 0; /* the plane turns away: be conservative */
			double zp = 1.0 / wp, sigma = 0.0012 * zp * zp;
			if (z[y * w + x] < zp - 4.0 * sigma - 0.004)
				return 0;
		}
	return 1;
}

/* mean and RMS about it of v where mask is set (1 and 0 without any) */
static void masked_stats(const float *v, const unsigned char *mask, size_t n, double *mean,
			 double *rms)
{
	double s = 0, s2 = 0;
	long k = 0;
	for (size_t i = 0; i < n; i++)
		if (mask[i])
			s += v[i], s2 += (double)v[i] * v[i], k++;
	*mean = k ? s / k : 1.0;
	*rms = k ? sqrt(fmax(s2 / k - *mean * *mean, 0.0)) : 0.0;
}

static int check_frame(const struct real_frame *rf)
{
	char path[512];
	if (dao_test_data_path(rf->file, path, sizeof path)) {
		printf("SKIP: %s not found (../shared/data is not beside the project)\n", path);
		return DAO_TEST_SKIP;
	}
	struct dao_error err;
	struct dao_frame depth;
	if (dao_png_read_depth(path, rf->unit, &depth, &err)) {
		printf("FAIL: %s\n", err.message);
		return 1;
	}
	const int w = (int)depth.width, h = (int)depth.height;
	/* decoding: the documented range */
	double lo = 1e9, hi = 0;
	for (int i = 0; i < w * h; i++) {
		uint16_t c = ((uint16_t *)depth.data)[i];
		if (c) {
			double mm = c * rf->unit * 1000.0;
			lo = fmin(lo, mm), hi = fmax(hi, mm);
		}
	}
	int status = 0;
	if (fabs(lo - rf->zmin_mm) > 0.06 * rf->zmin_mm || fabs(hi - rf->zmax_mm) > 0.06 * rf->zmax_mm) {
		printf("FAIL: %s: depth range %.0f..%.0f mm, documented %.0f..%.0f\n", rf->file, lo, hi,
		       rf->zmin_mm, rf->zmax_mm);
		status = 1;
	}
	struct dao_camera cam;
	dao_camera_from_intrinsics(&cam, depth.width, depth.height, rf->fx, rf->fy, rf->cx, rf->cy, NULL);
	struct dao_context *ctx;
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.radius = (float)rf->radius;
	dao_context_create(&ctx, &cam, &p, NULL);
	float *a = malloc((size_t)w * h * sizeof(float)), *b = malloc((size_t)w * h * sizeof(float));
	float *z = malloc((size_t)w * h * sizeof(float));
	struct dao_frame ao = { .format = DAO_PIXFMT_GRAY_F32, .width = depth.width,
			.height = depth.height, .stride = 4 * w, .data = a};
	struct dao_frame ao2 = ao, zf = ao;
	ao2.data = b;
	zf.format = DAO_PIXFMT_DEPTH_F32;
	zf.data = z;
	if (dao_context_process(ctx, &depth, NULL, 0, &ao, &err) ||
	    dao_context_get_depth(ctx, &zf, &err) ||
	    dao_context_process(ctx, &depth, NULL, 0, &ao2, &err)) {
		printf("FAIL: %s\n", err.message);
		return 1;
	}
	struct dao_noise_info ni;
	dao_context_noise(ctx, &ni);
	if (memcmp(a, b, (size_t)w * h * sizeof(float)) != 0) {
		printf("FAIL: %s: two runs differ\n", rf->file);
		status = 1;
	}
	double mean = 0;
	long nan = 0, invalid_bad = 0, valid = 0;
	for (int i = 0; i < w * h; i++) {
		if (!(a[i] >= 0.0f && a[i] <= 1.0f)) {
			nan++;
			continue;
		}
		if (((uint16_t *)depth.data)[i] == 0) {
			invalid_bad += a[i] != 1.0f;
			continue;
		}
		mean += a[i];
		valid++;
	}
	mean /= valid;
	/* open flat regions: 1 in `flat` for their pixels */
	unsigned char *flat = calloc((size_t)w * h, 1);
	int blocks = 0, rejected_rough = 0, rejected_occluded = 0;
	for (int by = 0; by + BLOCK <= h; by += BLOCK)
		for (int bx = 0; bx + BLOCK <= w; bx += BLOCK) {
			double abc[3], rms;
			if (fit_inverse_plane(z, w, bx, by, abc, &rms))
				continue;
			double zc = 1.0 / abc[0], sigma = 0.0012 * zc * zc;
			if (rms > 2.0 * sigma + 0.001) {
				rejected_rough++;
				continue;
			}
			if (!nothing_above(z, w, h, &cam, bx, by, abc, rf->radius)) {
				rejected_occluded++;
				continue;
			}
			for (int y = by; y < by + BLOCK; y++)
				memset(flat + (size_t)y * w + bx, 1, BLOCK);
			blocks++;
		}
	double flat_mean, flat_rms;
	masked_stats(a, flat, (size_t)w * h, &flat_mean, &flat_rms);
	printf("%-32s depth %4.0f..%4.0f mm  mean visibility %.3f  open flat blocks %d (%d rough, "
	       "%d with occluders): mean %.4f  NaN %ld  no-data not 1: %ld\n", rf->file, lo, hi, mean,
	       blocks, rejected_rough, rejected_occluded, flat_mean, nan, invalid_bad);
	if (nan || invalid_bad) {
		printf("FAIL: %s: %ld NaN/out-of-range, %ld no-data pixels not exactly 1\n", rf->file, nan,
		       invalid_bad);
		status = 1;
	}
	if (mean < 0.75) {
		printf("FAIL: %s: mean visibility %.3f is implausibly dark\n", rf->file, mean);
		status = 1;
	}
	if (blocks == 0 || flat_mean < 0.95) {
		printf("FAIL: %s: flat regions (%d blocks) average %.4f, expected >= 0.95\n", rf->file,
		       blocks, flat_mean);
		status = 1;
	}
	/* the same blocks with the fixed noise model (the defaults before
	 * noise-model=auto): the defaults must do at least as well */
	p.prefilter = DAO_PREFILTER_BILATERAL;
	p.noise_model = DAO_NOISE_MODEL_FIXED;
	if (dao_context_set_params(ctx, &p, &err) || dao_context_process(ctx, &depth, NULL, 0, &ao2, &err)) {
		printf("FAIL: %s\n", err.message);
		return 1;
	}
	double fixed_mean, fixed_rms;
	masked_stats(b, flat, (size_t)w * h, &fixed_mean, &fixed_rms);
	printf("%-32s defaults: noise %.2e (link %.2e, slope %.2e) 1/m, scale %.1f px, normal "
	       "radius %d: flat blocks mean %.4f (fixed model %.4f), AO RMS about it %.4f (fixed "
	       "model %.4f)\n", rf->file, (double)ni.sigma_area, (double)ni.sigma_link,
	       (double)ni.sigma_slope, (double)ni.prefilter_scale, ni.normal_radius, flat_mean,
	       fixed_mean, flat_rms, fixed_rms);
	if (!ni.measured || flat_mean < fixed_mean || flat_mean < 0.99) {
		printf("FAIL: %s: with the defaults the flat regions average %.4f (fixed model %.4f), "
		       "expected >= both 0.99 and the fixed model\n", rf->file, flat_mean, fixed_mean);
		status = 1;
	}
	free(flat);
	free(a);
	free(b);
	free(z);
	dao_context_destroy(ctx);
	dao_frame_free(&depth);
	return status;
}

int main(void)
{
	int status = 0, skipped = 0;
	for (size_t k = 0; k < sizeof frames / sizeof frames[0]; k++) {
		int r = check_frame(&frames[k]);
		if (r == DAO_TEST_SKIP)
			skipped++;
		else if (r)
			status = 1;
	}
	if (skipped == (int)(sizeof frames / sizeof frames[0]))
		return DAO_TEST_SKIP;
	return status;
}
