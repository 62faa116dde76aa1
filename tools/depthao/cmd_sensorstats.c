/* SPDX-License-Identifier: MIT */
/*
 * depthao sensorstats: what a depth sensor's errors look like.  Finds the
 * planes of depth frames (RANSAC in 1/z) and reports the statistics of
 * sensor_stats.h: residual amplitude per depth, its autocorrelation along
 * rows and columns, the spacing of the depth bands, holes and projector
 * shadows.  Runs on real frames (a PNG, an .oni recording, or the frames of
 * ../shared/data) and on the simulated sensors of `depthao synth`, so that
 * each model can be checked against the sensor it imitates.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

#include "common/camera_file.h"
#include "commands.h"
#include "sensor_compare.h"
#include "synth/open_planes.h"
#include "synth/planes.h"
#include "synth/real_frames.h"
#include "synth/sensor.h"
#include "synth/sensor_stats.h"
#include "synth/suite.h"

static void usage(FILE *out)
{
	fprintf(out,
		"usage: depthao sensorstats --input DEPTH [options]\n"
		"       depthao sensorstats --scene NAME --sensor MODEL [--seed N] [--frames N]\n"
		"       depthao sensorstats --real [--data DIR]\n"
		"       depthao sensorstats --compare [--data DIR] [--picture OUT.png]\n"
		"\n"
		"Finds the planes of depth frames (RANSAC in 1/z) and reports how the depth\n"
		"deviates from them and where it is missing: the residual's robust sigma per depth\n"
		"(in m and as sigma/z^2), its autocorrelation along rows and columns at lags of\n"
		"1..%d px, the spacing of the depth bands (for disparity quantised to q px,\n"
		"adjacent levels z1 < z2 give z1 z2 / (z2 - z1) = f b / q: 348 for a Kinect v1),\n"
		"holes, the side of the projector shadows beside foreground edges, flying pixels.\n"
		"\n"
		"  --input DEPTH      a 16-bit depth PNG or an .oni recording\n"
		"  --depth-unit M     PNG: metres per count (default 0.001; TUM: 0.0002)\n"
		"  --intrinsics F,F,C,C, --intrinsics-file FILE   PNG: the camera (a recording\n"
		"                     has its field of view; default 525,525,319.5,239.5)\n"
		"  --frame N          recording: only frame N (default: every frame, pooled)\n"
		"  --scene NAME       a synthetic scene (see 'depthao synth --help') ...\n"
		"  --sensor MODEL     ... seen by clean, gaussian, structured-light,\n"
		"                     active-stereo or tof\n"
		"  --seed N           first noise seed (default 1); --frames N seeds, pooled\n"
		"  --real             every frame of the data directory, grouped by sensor\n"
		"  --compare          the real frames and the simulated sensors side by side:\n"
		"                     the table of docs/sensor-models.md\n"
		"  --picture OUT.png  with --compare: real and simulated plane residuals\n"
		"  --data DIR         the real data (default $DAO_SHARED_DATA or ../shared/data)\n"
		"  --residual-out P   --input/--scene: the plane residual map as a PNG\n",
		SYNTH_STATS_LAGS);
}

void sensorstats_print(const char *title, const struct synth_sensor_stats *s, double f)
{
	printf("== %s\n", title);
	printf("planes %d, %ld px; residual 1/z robust sigma %.5f 1/m (x f = %.3f px m)\n", s->planes,
	       s->plane_pixels, s->sigma_w, s->sigma_w * f);
	printf("  depth m | plane px | sigma_z mm | sigma_z/z^2 | levels | step mm | f b/q\n");
	for (int b = 0; b < SYNTH_STATS_ZBINS; b++) {
		const struct synth_zbin_stats *zb = &s->bin[b];
		if (zb->pixels < 500 && zb->gap <= 0)
			continue;
		double zc = (b + 0.5) * SYNTH_STATS_ZBIN;
		printf("  %3.1f-%3.1f | %8ld | %10.2f | %11.5f | %6d | %7.1f | %5.0f\n",
		       b * SYNTH_STATS_ZBIN, (b + 1) * SYNTH_STATS_ZBIN, zb->pixels, 1e3 * zb->sigma_z,
		       zb->pixels >= 500 ? zb->sigma_z / (zc * zc) : 0.0, zb->levels, 1e3 * zb->gap,
		       zb->band_c);
	}
	printf("autocorrelation, rows:");
	for (int k = 1; k <= SYNTH_STATS_LAGS; k *= 2)
		printf(" %d px %.2f", k, s->acf_row[k]);
	printf(" (1/e at %.1f px)\n", s->corr_len_row);
	printf("autocorrelation, cols:");
	for (int k = 1; k <= SYNTH_STATS_LAGS; k *= 2)
		printf(" %d px %.2f", k, s->acf_col[k]);
	printf(" (1/e at %.1f px)\n", s->corr_len_col);
	printf("bands: f b / q = %.0f m px (%ld level pairs)\n", s->band_c, s->band_pairs);
	long runs = s->shadow_left + s->shadow_right;
	printf("holes %.1f %%, %.1f %% of them beside depth edges; shadow runs %ld, left of the "
	       "foreground %.0f %%, median width %.1f px, baseline %.3f m; flying pixels %.1f %% "
	       "of %ld edge px\n",
	       100 * s->hole_fraction, 100 * s->edge_hole_fraction, runs,
	       runs ? 100.0 * s->shadow_left / runs : 0.0, s->shadow_width, s->shadow_baseline,
	       s->edge_pixels ? 100.0 * s->flying_pixels / s->edge_pixels : 0.0, s->edge_pixels);
}

/* Planes and statistics of one frame; labels (w x h) may be NULL. */
int sensorstats_measure(const float *z, const struct dao_camera *cam, double unit,
			struct synth_sensor_stats *s, struct synth_plane *planes, int *nplanes,
			int32_t *labels, struct dao_error *err)
{
	struct synth_plane local[SYNTH_PLANES_MAX];
	int n = 0;
	int32_t *lab = labels ? labels : malloc((size_t)cam->width * cam->height * sizeof(int32_t));
	if (!lab) {
		snprintf(err->message, sizeof err->message, "out of memory");
		return err->code = -ENOMEM;
	}
	if (!planes)
		planes = local;
	int r = synth_planes_find_frame(z, cam, unit, planes, &n, lab, err);
	if (!r)
		r = synth_sensor_stats(z, cam, unit, planes, n, lab, s, err);
	if (nplanes)
		*nplanes = n;
	if (!labels)
		free(lab);
	return r;
}

/* Writes the residual map: 1/z residual scaled to +-4 robust sigma, grey; no plane black. */
static int write_residual(const char *path, const float *z, const struct dao_camera *cam,
			  double unit, struct dao_error *err)
{
	const size_t np = (size_t)cam->width * cam->height;
	struct synth_plane planes[SYNTH_PLANES_MAX];
	struct synth_sensor_stats s;
	int n = 0;
	int32_t *lab = malloc(np * sizeof(int32_t));
	float *res = malloc(np * sizeof(float));
	struct dao_frame img = { 0 };
	int r = -ENOMEM;
	if (lab && res)
		r = sensorstats_measure(z, cam, unit, &s, planes, &n, lab, err);
	if (!r)
		r = synth_plane_residual_map(z, cam, planes, lab, res);
	if (!r)
		r = dao_frame_alloc(&img, DAO_PIXFMT_GRAY8, cam->width, cam->height, err);
	if (!r) {
		for (size_t i = 0; i < np; i++) {
			float v = isnan(res[i]) ? 0.0f
				  : 127.5f + 127.0f * fmaxf(-1.0f, fminf(1.0f, res[i] / (4.0f * (float)s.sigma_w)));
			((uint8_t *)img.data)[i] = (uint8_t)lrintf(v);
		}
		r = dao_png_write(path, &img, err);
	}
	if (r == -ENOMEM && !err->message[0])
		snprintf(err->message, sizeof err->message, "out of memory");
	dao_frame_free(&img);
	free(lab);
	free(res);
	return r;
}

struct options {
	const char *input, *scene, *data, *picture, *residual_out, *intrinsics, *intrinsics_file;
	enum synth_sensor sensor;
	int have_sensor, real, compare, frame, frames;
	double unit;
	unsigned long long seed;
};

static int parse(int argc, char **argv, struct options *o)
{
	*o = (struct options){ .unit = 0.001, .frame = -1, .frames = 1, .seed = 1 };
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i];
		if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
			usage(stdout);
			exit(0);
		}
		if (!strcmp(a, "--real")) {
			o->real = 1;
			continue;
		}
		if (!strcmp(a, "--compare")) {
			o->compare = 1;
			continue;
		}
		if (i + 1 >= argc)
			return usage_error("sensorstats", "%s needs a value", a);
		const char *v = argv[++i];
		char *end;
		if (!strcmp(a, "--input")) {
			o->input = v;
		} else if (!strcmp(a, "--scene")) {
			o->scene = v;
		} else if (!strcmp(a, "--data")) {
			o->data = v;
		} else if (!strcmp(a, "--picture")) {
			o->picture = v;
		} else if (!strcmp(a, "--residual-out")) {
			o->residual_out = v;
		} else if (!strcmp(a, "--intrinsics")) {
			o->intrinsics = v;
		} else if (!strcmp(a, "--intrinsics-file")) {
			o->intrinsics_file = v;
		} else if (!strcmp(a, "--sensor")) {
			struct dao_error err;
			if (synth_sensor_parse(v, &o->sensor, &err))
				return usage_error("sensorstats", "%s", err.message);
			o->have_sensor = 1;
		} else if (!strcmp(a, "--depth-unit")) {
			o->unit = strtod(v, &end);
			if (*end || !(o->unit > 0 && o->unit <= 1))
				return usage_error("sensorstats", "--depth-unit '%s' must be in (0, 1] metres", v);
		} else if (!strcmp(a, "--frame") || !strcmp(a, "--frames")) {
			long n = strtol(v, &end, 10);
			if (*end || !*v || n < 0 || n > 100000 || (n == 0 && !strcmp(a, "--frames")))
				return usage_error("sensorstats", "%s '%s' must be a %s integer", a, v,
						   !strcmp(a, "--frame") ? "non-negative" : "positive");
			if (!strcmp(a, "--frame"))
				o->frame = (int)n;
			else
				o->frames = (int)n;
		} else if (!strcmp(a, "--seed")) {
			o->seed = strtoull(v, &end, 10);
			if (*end || !*v || v[0] == '-')
				return usage_error("sensorstats", "--seed '%s' is not a non-negative integer", v);
		} else {
			return usage_error("sensorstats", "unknown option '%s'", a);
		}
	}
	int modes = !!o->input + !!o->scene + o->real + o->compare;
	if (modes != 1)
		return usage_error("sensorstats", "give one of --input, --scene, --real or --compare");
	if (o->scene && !o->have_sensor)
		return usage_error("sensorstats", "--scene needs --sensor");
	if (o->picture && !o->compare)
		return usage_error("sensorstats", "--picture goes with --compare");
	if (o->residual_out && !o->input && !o->scene)
		return usage_error("sensorstats", "--residual-out goes with --input or --scene");
	if (o->scene) {
		struct synth_scene sc;
		struct dao_error err;
		if (synth_scene_build(o->scene, 0.0, &sc, &err))
			return usage_error("sensorstats", "%s", err.message);
	}
	return 0;
}

static int run_input(const struct options *o)
{
	struct dao_error err = { 0 };
	int count = synth_depth_frame_count(o->input, &err);
	if (count < 0) {
		fprintf(stderr, "depthao: %s\n", err.message);
		return 1;
	}
	if (o->frame >= count) {
		fprintf(stderr, "depthao: %s has %d frame%s, --frame %d does not exist\n", o->input,
			count, count == 1 ? "" : "s", o->frame);
		return 1;
	}
	struct synth_stats_acc acc;
	synth_stats_acc_begin(&acc);
	struct dao_camera cam;
	int first = o->frame >= 0 ? o->frame : 0, last = o->frame >= 0 ? o->frame : count - 1;
	for (int k = first; k <= last; k++) {
		float *z;
		uint32_t w, h;
		double unit;
		int has_cam;
		if (synth_depth_load(o->input, k, o->unit, &z, &w, &h, &unit, &cam, &has_cam, &err)) {
			fprintf(stderr, "depthao: %s\n", err.message);
			return 1;
		}
		if (!has_cam || o->intrinsics || o->intrinsics_file) {
			char msg[512];
			double kk[4] = { 525, 525, 319.5, 239.5 };
			int r = 0;
			if (o->intrinsics_file) {
				r = camera_file_read(o->intrinsics_file, &cam, msg, sizeof msg);
				if (!r && (cam.width != w || cam.height != h)) {
					snprintf(msg, sizeof msg, "%s is for %ux%u, the depth is %ux%u",
						 o->intrinsics_file, cam.width, cam.height, w, h);
					r = -1;
				}
			} else {
				if (o->intrinsics && sscanf(o->intrinsics, "%lf,%lf,%lf,%lf", &kk[0], &kk[1],
							    &kk[2], &kk[3]) != 4) {
					free(z);
					return usage_error("sensorstats", "--intrinsics needs FX,FY,CX,CY");
				}
				r = dao_camera_from_intrinsics(&cam, w, h, kk[0], kk[1], kk[2], kk[3], &err);
				snprintf(msg, sizeof msg, "%s", err.message);
			}
			if (r) {
				free(z);
				fprintf(stderr, "depthao: %s\n", msg);
				return 1;
			}
		}
		struct synth_sensor_stats s;
		int r = sensorstats_measure(z, &cam, unit, &s, NULL, NULL, NULL, &err);
		if (!r && o->residual_out && k == first)
			r = write_residual(o->residual_out, z, &cam, unit, &err);
		free(z);
		if (r) {
			fprintf(stderr, "depthao: %s\n", err.message);
			return 1;
		}
		synth_stats_acc_add(&acc, &s);
	}
	struct synth_sensor_stats total;
	synth_stats_acc_end(&acc, &total);
	char title[600];
	snprintf(title, sizeof title, "%s (%d frame%s)", o->input, last - first + 1,
		 last > first ? "s" : "");
	sensorstats_print(title, &total, cam.fx);
	return 0;
}

static int run_scene(const struct options *o)
{
	struct synth_stats_acc acc;
	synth_stats_acc_begin(&acc);
	struct dao_camera cam;
	synth_default_camera(&cam);
	struct synth_scene sc;
	struct synth_image img;
	struct dao_error err;
	if (synth_scene_build(o->scene, 0.0, &sc, &err) ||
	    synth_render(&sc, &cam, 0.5, 0, 2, &img, &err)) {
		fprintf(stderr, "depthao: %s\n", err.message);
		return 1;
	}
	int status = 0;
	for (int k = 0; k < o->frames && !status; k++) {
		struct synth_case c = { 0 };
		struct synth_sensor_stats s;
		int r = synth_case_simulate(&c, &sc, 0, &cam, &img, o->sensor, o->seed + (uint64_t)k, 2, &err);
		if (!r)
			r = sensorstats_measure(c.depth_m, &cam, 0.001, &s, NULL, NULL, NULL, &err);
		if (!r && o->residual_out && k == 0)
			r = write_residual(o->residual_out, c.depth_m, &cam, 0.001, &err);
		synth_case_free(&c);
		if (r) {
			fprintf(stderr, "depthao: %s\n", err.message);
			status = 1;
		} else {
			synth_stats_acc_add(&acc, &s);
		}
	}
	synth_image_free(&img);
	if (status)
		return status;
	struct synth_sensor_stats total;
	synth_stats_acc_end(&acc, &total);
	char title[256];
	snprintf(title, sizeof title, "%s, %s, seeds %llu..%llu", sc.name, synth_sensor_name(o->sensor),
		 o->seed, o->seed + (unsigned long long)o->frames - 1);
	sensorstats_print(title, &total, cam.fx);
	return 0;
}

static int run_real(const struct options *o)
{
	const char *dir = o->data ? o->data : synth_real_data_dir();
	int n;
	const struct synth_real_frame *frames = synth_real_frames(&n);
	for (int i = 0; i < n;) {
		/* frames of one file are pooled */
		int j = i;
		struct synth_stats_acc acc;
		synth_stats_acc_begin(&acc);
		struct dao_camera cam;
		for (; j < n && !strcmp(frames[j].file, frames[i].file); j++) {
			float *z;
			double unit;
			struct dao_error err;
			struct synth_sensor_stats s;
			if (synth_real_frame_load(&frames[j], dir, &z, &cam, &unit, &err) ||
			    sensorstats_measure(z, &cam, unit, &s, NULL, NULL, NULL, &err)) {
				fprintf(stderr, "depthao: %s\n", err.message);
				return 1;
			}
			free(z);
			synth_stats_acc_add(&acc, &s);
		}
		struct synth_sensor_stats total;
		synth_stats_acc_end(&acc, &total);
		char title[256];
		snprintf(title, sizeof title, "%s: %s (%d frame%s)", frames[i].file, frames[i].sensor,
			 j - i, j - i > 1 ? "s" : "");
		sensorstats_print(title, &total, cam.fx);
		i = j;
	}
	return 0;
}

int cmd_sensorstats(int argc, char **argv)
{
	struct options o;
	int r = parse(argc, argv, &o);
	if (r)
		return r;
	if (o.input)
		return run_input(&o);
	if (o.scene)
		return run_scene(&o);
	if (o.real)
		return run_real(&o);
	return sensor_compare_run(o.data ? o.data : synth_real_data_dir(), o.picture);
}
