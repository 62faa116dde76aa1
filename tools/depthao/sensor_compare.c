/* SPDX-License-Identifier: MIT */
/*
 * depthao sensorstats --compare: the real sensor frames of ../shared/data
 * next to the simulated sensors, measured the same way (sensor_stats.h), as
 * the tables of docs/sensor-models.md, and a picture of their
 * plane residuals.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

#include "sensor_compare.h"
#include "synth/real_frames.h"
#include "synth/sensor.h"
#include "synth/suite.h"

/* The synthetic scenes each model is measured on, and the seeds. */
static const char *const compare_scenes[] = { "room-corner", "boxes", "spheres", "stairs", NULL };
#define COMPARE_SEEDS 2

/* A residual crop of the picture. */
#define TILE_W 320
#define TILE_H 240
#define TILES 6
#define TILE_COLUMNS 3
#define TILE_RANGE_W 0.008  /* 1/m: the grey scale spans +-this residual of 1/z */

struct row {
	char name[96];
	struct synth_sensor_stats s;
	double f;
};

/* sigma_z / z^2 over the depth bins [lo, hi) m, weighted by their plane pixels; 0 if too few. */
static double k_over(const struct synth_sensor_stats *s, double lo, double hi)
{
	double sum = 0, n = 0;
	for (int b = 0; b < SYNTH_STATS_ZBINS; b++) {
		double zc = (b + 0.5) * SYNTH_STATS_ZBIN;
		if (zc < lo || zc >= hi || s->bin[b].pixels < 500)
			continue;
		sum += (double)s->bin[b].pixels * s->bin[b].sigma_z / (zc * zc);
		n += (double)s->bin[b].pixels;
	}
	return n >= 2000 ? sum / n : 0.0;
}

static void print_k(double k)
{
	if (k > 0)
		printf(" %.4f |", k);
	else
		printf(" - |");
}

static void print_tables(const struct row *rows, int n)
{
	printf("| source | plane px | sigma(1/z) 1/m | sigma_z/z^2 1-2 m | 2-3 m | 3-4.5 m |"
	       " ACF rows 1 px | 2 | 4 | 8 | 16 | 32 | ACF cols 1 px | 4 | 8 | 16 |\n");
	printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
	for (int i = 0; i < n; i++) {
		const struct synth_sensor_stats *s = &rows[i].s;
		printf("| %s | %ld | %.4f |", rows[i].name, s->plane_pixels, s->sigma_w);
		print_k(k_over(s, 1.0, 2.0));
		print_k(k_over(s, 2.0, 3.0));
		print_k(k_over(s, 3.0, 4.5));
		for (int k = 1; k <= 32; k *= 2)
			printf(" %.2f |", s->acf_row[k]);
		printf(" %.2f | %.2f | %.2f | %.2f |\n", s->acf_col[1], s->acf_col[4], s->acf_col[8],
		       s->acf_col[16]);
	}
	printf("\n| source | f b / q (m px) | holes | beside edges | shadow runs | left of the "
	       "foreground | median width px | implied baseline m | flying px (of edge px) |\n");
	printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
	for (int i = 0; i < n; i++) {
		const struct synth_sensor_stats *s = &rows[i].s;
		const long runs = s->shadow_left + s->shadow_right;
		printf("| %s |", rows[i].name);
		if (s->band_c > 0)
			printf(" %.0f |", s->band_c);
		else
			printf(" not banded |");
		printf(" %.1f %% | %.0f %% | %ld |", 100 * s->hole_fraction, 100 * s->edge_hole_fraction,
		       runs);
		if (runs)
			printf(" %.0f %% | %.1f | %.3f |", 100.0 * s->shadow_left / runs, s->shadow_width,
			       s->shadow_baseline);
		else
			printf(" - | - | - |");
		printf(" %.1f %% |\n", s->edge_pixels ? 100.0 * s->flying_pixels / s->edge_pixels : 0.0);
	}
}

/* The 320 x 240 window (on a 16-px grid) holding the most plane pixels. */
static void best_window(const float *res, int w, int h, int *bx, int *by)
{
	long best = -1;
	*bx = *by = 0;
	for (int y = 0; y + TILE_H <= h; y += 16)
		for (int x = 0; x + TILE_W <= w; x += 16) {
			long n = 0;
			for (int yy = y; yy < y + TILE_H; yy += 4)
				for (int xx = x; xx < x + TILE_W; xx += 4)
					n += !isnan(res[(size_t)yy * w + xx]);
			if (n > best)
				best = n, *bx = x, *by = y;
		}
}

/* Tile t of the picture: the residual map, grey +-TILE_RANGE_W; no plane dark blue, no depth black. */
static void put_tile(struct dao_frame *pic, int t, const float *res, const float *z, int w, int h)
{
	int bx, by;
	best_window(res, w, h, &bx, &by);
	const int ox = (t % TILE_COLUMNS) * TILE_W, oy = (t / TILE_COLUMNS) * TILE_H;
	for (int y = 0; y < TILE_H; y++) {
		uint8_t *row = (uint8_t *)pic->data + (size_t)(oy + y) * (size_t)pic->stride + 3 * ox;
		for (int x = 0; x < TILE_W; x++) {
			const size_t i = (size_t)(by + y) * w + (bx + x);
			uint8_t *p = row + 3 * x;
			if (!(z[i] > 0)) {
				p[0] = p[1] = p[2] = 0;
			} else if (isnan(res[i])) {
				p[0] = 20, p[1] = 30, p[2] = 70;
			} else {
				double v = 0.5 + 0.5 * res[i] / TILE_RANGE_W;
				uint8_t g = (uint8_t)lrint(255.0 * (v < 0 ? 0 : v > 1 ? 1 : v));
				p[0] = p[1] = p[2] = g;
			}
		}
	}
}

/* Measures one frame into the accumulator; with `pic`, also draws its residual as tile t. */
static int measure(const float *z, const struct dao_camera *cam, double unit,
		   struct synth_stats_acc *acc, struct dao_frame *pic, int t)
{
	const size_t np = (size_t)cam->width * cam->height;
	struct synth_plane planes[SYNTH_PLANES_MAX];
	struct synth_sensor_stats s;
	struct dao_error err = { 0 };
	int n = 0, r;
	int32_t *lab = malloc(np * sizeof(int32_t));
	float *res = pic ? malloc(np * sizeof(float)) : NULL;
	if (!lab || (pic && !res)) {
		snprintf(err.message, sizeof err.message, "out of memory");
		r = -ENOMEM;
	} else {
		r = sensorstats_measure(z, cam, unit, &s, planes, &n, lab, &err);
		if (!r && pic) {
			r = synth_plane_residual_map(z, cam, planes, lab, res);
			if (!r)
				put_tile(pic, t, res, z, (int)cam->width, (int)cam->height);
			else
				snprintf(err.message, sizeof err.message, "out of memory");
		}
	}
	if (!r)
		synth_stats_acc_add(acc, &s);
	else
		fprintf(stderr, "depthao: %s\n", err.message);
	free(lab);
	free(res);
	return r;
}

static int real_rows(const char *dir, struct row *rows, int *n, struct dao_frame *pic)
{
	int count;
	const struct synth_real_frame *frames = synth_real_frames(&count);
	for (int i = 0; i < count;) {
		int j = i;
		struct synth_stats_acc acc;
		synth_stats_acc_begin(&acc);
		struct dao_camera cam = { 0 };
		for (; j < count && !strcmp(frames[j].file, frames[i].file); j++) {
			float *z;
			double unit;
			struct dao_error err;
			if (synth_real_frame_load(&frames[j], dir, &z, &cam, &unit, &err)) {
				fprintf(stderr, "depthao: %s\n", err.message);
				return 1;
			}
			/* tiles 0 and 1: the first Kinect frame and TUM */
			int tile = j == 0 ? 0 : !strcmp(frames[j].name, "tum") ? 1 : -1;
			int r = measure(z, &cam, unit, &acc, tile >= 0 ? pic : NULL, tile);
			free(z);
			if (r)
				return 1;
		}
		struct row *rw = &rows[(*n)++];
		synth_stats_acc_end(&acc, &rw->s);
		rw->f = cam.fx;
		if (j - i > 1)
			snprintf(rw->name, sizeof rw->name, "real: %s, %d frames", frames[i].sensor, j - i);
		else
			snprintf(rw->name, sizeof rw->name, "real: %s, %s", frames[i].sensor, frames[i].name);
		fprintf(stderr, "depthao: measured %s\n", rw->name);
		i = j;
	}
	return 0;
}

static int simulated_rows(struct row *rows, int *n, struct dao_frame *pic)
{
	static const enum synth_sensor models[] = {
		SYNTH_SENSOR_STRUCTURED_LIGHT, SYNTH_SENSOR_GAUSSIAN, SYNTH_SENSOR_ACTIVE_STEREO,
		SYNTH_SENSOR_TOF,
	};
	struct dao_camera cam;
	synth_default_camera(&cam);
	for (size_t k = 0; k < sizeof models / sizeof models[0]; k++) {
		struct synth_stats_acc acc;
		synth_stats_acc_begin(&acc);
		for (int si = 0; compare_scenes[si]; si++) {
			struct synth_scene sc;
			struct synth_image img;
			struct dao_error err;
			if (synth_scene_build(compare_scenes[si], 0.0, &sc, &err) ||
			    synth_render(&sc, &cam, 0.5, 0, 2, &img, &err)) {
				fprintf(stderr, "depthao: %s\n", err.message);
				return 1;
			}
			for (int seed = 1; seed <= COMPARE_SEEDS; seed++) {
				struct synth_case c;
				/* tiles 2..5: each model's room corner */
				int tile = si == 0 && seed == 1 ? 2 + (int)k : -1;
				int r = synth_case_simulate(&c, &sc, 0, &cam, &img, models[k], (uint64_t)seed,
							    2, &err);
				if (r)
					fprintf(stderr, "depthao: %s\n", err.message);
				else
					r = measure(c.depth_m, &cam, 0.001, &acc, tile >= 0 ? pic : NULL, tile);
				synth_case_free(&c);
				if (r) {
					synth_image_free(&img);
					return 1;
				}
			}
			synth_image_free(&img);
		}
		struct row *rw = &rows[(*n)++];
		synth_stats_acc_end(&acc, &rw->s);
		rw->f = cam.fx;
		snprintf(rw->name, sizeof rw->name, "model: %s", synth_sensor_name(models[k]));
		fprintf(stderr, "depthao: measured %s\n", rw->name);
	}
	return 0;
}

int sensor_compare_run(const char *data_dir, const char *picture)
{
	struct row rows[16];
	int n = 0, status = 1;
	struct dao_frame pic = { 0 };
	struct dao_error err;
	if (picture) {
		if (dao_frame_alloc(&pic, DAO_PIXFMT_RGB24, TILE_COLUMNS * TILE_W,
				    (TILES / TILE_COLUMNS) * TILE_H, &err)) {
			fprintf(stderr, "depthao: %s\n", err.message);
			return 1;
		}
		memset(pic.data, 255, (size_t)pic.stride * pic.height);
	}
	struct dao_frame *pp = picture ? &pic : NULL;
	if (real_rows(data_dir, rows, &n, pp) || simulated_rows(rows, &n, pp))
		goto out;
	print_tables(rows, n);
	if (picture) {
		if (dao_png_write(picture, &pic, &err)) {
			fprintf(stderr, "depthao: %s\n", err.message);
			goto out;
		}
		fprintf(stderr, "depthao: wrote %s\n", picture);
	}
	status = 0;
out:
	dao_frame_free(&pic);
	return status;
}
