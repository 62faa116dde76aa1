/* SPDX-License-Identifier: MIT */
/*
 * The real-frame metric of issue #15: false occlusion on the open planar
 * regions of real sensor frames (tools/synth/open_planes.c, `depthao
 * realcheck`).
 *
 * 1. The finder itself, where the truth is known: on synthetic scenes, clean
 *    and as structured light delivers them, the pixels it calls open have a
 *    ray-traced visibility of 1 (mean >= 0.995, at most 1 % below 0.97), and
 *    it finds a fair share of the truly open pixels.
 * 2. The real frames of ../shared/data (a subset, for time: `depthao
 *    realcheck` reports every frame): each has open planar pixels, and the
 *    default AO's mean false occlusion on them is reported per frame and
 *    must meet issue #15's target of 0.010 (the defaults with the noise
 *    measured in the frame: 0.0030-0.0041 on the Kinect frames, 0.0015
 *    Redwood, 0.0054 TUM and 0.0033 RealSense at R = 0.25 m; the fixed
 *    noise model before them: 0.042-0.046, 0.0064, 0.054, 0.012).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/test_common.h"
#include "synth/open_planes.h"
#include "synth/real_frames.h"
#include "synth/suite.h"

#define ISSUE_TARGET 0.010

static int check_synthetic(const struct synth_scene *sc, const struct dao_camera *cam,
			   const struct synth_image *img, enum synth_sensor sensor)
{
	const char *name = sc->name;
	const size_t np = (size_t)cam->width * cam->height;
	struct synth_case c;
	struct dao_error err;
	if (synth_case_simulate(&c, sc, 0, cam, img, sensor, 1, 2, &err)) {
		printf("FAIL: %s: %s\n", name, err.message);
		return 1;
	}
	uint8_t *mask = malloc(np);
	long n = 0;
	int status = 0;
	if (synth_open_planes(c.depth_m, cam, 0.001, 0.5, mask, &n, &err)) {
		printf("FAIL: %s: %s\n", name, err.message);
		status = 1;
		goto out;
	}
	double sum = 0;
	long below = 0, open_truth = 0;
	for (size_t i = 0; i < np; i++) {
		open_truth += c.depth_m[i] > 0 && img->gt[i] >= 0.999f;
		if (mask[i]) {
			sum += img->gt[i];
			below += img->gt[i] < 0.97f;
		}
	}
	double mean = n ? sum / n : 0.0;
	printf("%-12s %-16s open planar px %6ld of %6ld truly open: ground truth there %.4f, "
	       "%ld px below 0.97\n", name, synth_sensor_name(sensor), n, open_truth, mean, below);
	if (n < open_truth / 4 || mean < 0.995 || below > n / 100) {
		printf("FAIL: %s, %s: the open planar pixels are not open or too few\n", name,
		       synth_sensor_name(sensor));
		status = 1;
	}
out:
	free(mask);
	synth_case_free(&c);
	return status;
}

struct real_case {
	const char *name;
	double radius;     /* TUM and the table top have no open region at 0.5 m */
	long min_open;     /* px, from the measurement with a margin */
	double bar;
	int twice;         /* run the finder twice: it must be deterministic */
};

static const struct real_case real_cases[] = {
	{ "kinect-oni-0", 0.5, 8000, ISSUE_TARGET, 1 },
	{ "kinect-oni-6", 0.5, 8000, ISSUE_TARGET, 0 },
	{ "redwood-0", 0.5, 2500, ISSUE_TARGET, 0 },
	{ "tum", 0.25, 10000, ISSUE_TARGET, 0 },
	{ "realsense", 0.25, 5000, ISSUE_TARGET, 0 },
};

static int check_real(const struct real_case *rc, const char *dir, int *skipped)
{
	int n;
	const struct synth_real_frame *frames = synth_real_frames(&n), *f = NULL;
	for (int k = 0; k < n; k++)
		if (!strcmp(frames[k].name, rc->name))
			f = &frames[k];
	if (!f) {
		printf("FAIL: no real frame '%s'\n", rc->name);
		return 1;
	}
	char path[1024];
	snprintf(path, sizeof path, "%s/%s", dir, f->file);
	FILE *probe = fopen(path, "rb");
	if (!probe) {
		printf("SKIP: %s not found (../shared/data is not beside the project)\n", path);
		(*skipped)++;
		return 0;
	}
	fclose(probe);
	float *z;
	struct dao_camera cam;
	struct dao_error err;
	double unit;
	if (synth_real_frame_load(f, dir, &z, &cam, &unit, &err)) {
		printf("FAIL: %s\n", err.message);
		return 1;
	}
	const size_t np = (size_t)cam.width * cam.height;
	uint8_t *mask = malloc(np), *again = rc->twice ? malloc(np) : NULL;
	float *ao = malloc(np * sizeof(float));
	long open_px = 0, open2 = 0;
	int status = 0;
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.radius = (float)rc->radius;
	struct dao_context *ctx = NULL;
	struct dao_frame in = { .format = DAO_PIXFMT_DEPTH_F32, .width = cam.width,
			.height = cam.height, .stride = (int32_t)(cam.width * 4), .data = z};
	struct dao_frame out = { .format = DAO_PIXFMT_GRAY_F32, .width = cam.width,
			.height = cam.height, .stride = (int32_t)(cam.width * 4), .data = ao};
	if (synth_open_planes(z, &cam, unit, rc->radius, mask, &open_px, &err) ||
	    (again && synth_open_planes(z, &cam, unit, rc->radius, again, &open2, &err)) ||
	    dao_context_create(&ctx, &cam, &p, &err) || dao_context_process(ctx, &in, NULL, 0, &out, &err)) {
		printf("FAIL: %s: %s\n", rc->name, err.message);
		status = 1;
		goto out;
	}
	if (again && (open_px != open2 || memcmp(mask, again, np) != 0)) {
		printf("FAIL: %s: two runs of the finder differ\n", rc->name);
		status = 1;
	}
	double sum = 0;
	for (size_t i = 0; i < np; i++)
		if (mask[i])
			sum += 1.0 - ao[i];
	double mean = open_px ? sum / open_px : 1.0;
	printf("%-14s R = %.2f m: open planar px %6ld, mean false occlusion %.4f (bar %.3f; issue "
	       "#15 target for the defaults %.3f)\n", rc->name, rc->radius, open_px, mean, rc->bar,
	       ISSUE_TARGET);
	if (open_px < rc->min_open) {
		printf("FAIL: %s: %ld open planar px, expected >= %ld\n", rc->name, open_px, rc->min_open);
		status = 1;
	}
	if (mean > rc->bar) {
		printf("FAIL: %s: mean false occlusion %.4f above %.3f\n", rc->name, mean, rc->bar);
		status = 1;
	}
out:
	dao_context_destroy(ctx);
	free(z);
	free(mask);
	free(again);
	free(ao);
	return status;
}

int main(void)
{
	int status = 0, skipped = 0;
	static const char *const scenes[] = { "spheres", "boxes", "room-corner" };
	struct dao_camera cam;
	synth_default_camera(&cam);
	for (int k = 0; k < 3; k++) {
		struct synth_scene sc;
		struct synth_image img;
		struct dao_error err;
		/* 64 rays: the ground truth to about 0.03, enough to tell open from occluded */
		if (synth_scene_build(scenes[k], 0.0, &sc, &err) ||
		    synth_render(&sc, &cam, 0.5, 8, 2, &img, &err)) {
			printf("FAIL: %s: %s\n", scenes[k], err.message);
			return 1;
		}
		status |= check_synthetic(&sc, &cam, &img, SYNTH_SENSOR_CLEAN);
		status |= check_synthetic(&sc, &cam, &img, SYNTH_SENSOR_STRUCTURED_LIGHT);
		synth_image_free(&img);
	}
	const char *dir = synth_real_data_dir();
	const int nreal = (int)(sizeof real_cases / sizeof real_cases[0]);
	for (int k = 0; k < nreal; k++)
		status |= check_real(&real_cases[k], dir, &skipped);
	if (!status && skipped == nreal) {
		printf("SKIP: no real frames; the synthetic checks passed\n");
		return DAO_TEST_SKIP;
	}
	return status;
}
