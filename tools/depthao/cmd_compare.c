/* SPDX-License-Identifier: MIT */
/*
 * depthao compare: one picture of the algorithms side by side on a synthetic
 * scene (with its ray-traced ground truth) or on a real depth frame.  Tiles,
 * left to right, top to bottom: depth, ground truth (synthetic scenes), then
 * each algorithm's visibility, at half size.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

#include "cli_params.h"
#include "common/camera_file.h"
#include "commands.h"
#include "synth/suite.h"
#include "synth/synth.h"

#define MAX_TILES 8
#define COLUMNS 4

static void usage(FILE *out)
{
	fprintf(out,
		"usage: depthao compare (--scene NAME | --input DEPTH.png --intrinsics FX,FY,CX,CY)\n"
		"                       --out MONTAGE.png [--algorithms LIST] [--noise] [--rays N]\n"
		"\n"
		"Writes one PNG with the algorithms side by side at half size, %d per row: the\n"
		"depth (near = bright), the ray-traced ground truth (synthetic scenes only), then\n"
		"the visibility of each algorithm in LIST (default gtao,vbao,hbao,ssao,edl) with\n"
		"the medium preset; an entry NAME:PARAM=VALUE[:PARAM=VALUE] sets parameters of\n"
		"its own (e.g. vbao:vbao-thickness-mode=constant).\n"
		"\n"
		"  --scene NAME          a synthetic scene (see 'depthao synth --help')\n"
		"  --noise               the scene with Kinect-like sensor noise\n"
		"  --rays N              ground-truth rays per pixel, a square (default 256)\n"
		"  --input DEPTH.png     a 16-bit depth PNG in millimetres (--depth-unit M otherwise)\n"
		"  --intrinsics F,F,C,C  its camera (or --intrinsics-file FILE: Open3D JSON or ROS\n"
		"                        CameraInfo YAML)\n",
		COLUMNS);
}

/* Writes `plane` (values in [0, 1], w x h) into tile t of the montage, halved. */
static void put_tile(struct dao_frame *m, int t, const float *plane, uint32_t w, uint32_t h)
{
	const uint32_t tw = w / 2, th = h / 2;
	const uint32_t ox = (uint32_t)(t % COLUMNS) * tw, oy = (uint32_t)(t / COLUMNS) * th;
	for (uint32_t y = 0; y < th; y++) {
		uint8_t *row = (uint8_t *)m->data + (size_t)(oy + y) * (size_t)m->stride + 3 * ox;
		for (uint32_t x = 0; x < tw; x++) {
			const float *p = plane + (size_t)(2 * y) * w + 2 * x;
			float v = 0.25f * (p[0] + p[1] + p[w] + p[w + 1]);
			uint8_t g = (uint8_t)lrintf(255.0f * (v < 0 ? 0 : v > 1 ? 1 : v));
			row[3 * x] = row[3 * x + 1] = row[3 * x + 2] = g;
		}
	}
}

/*
 * Sets p from one entry of --algorithms, NAME[:PARAM=VALUE]... (an algorithm
 * with parameters of its own); the entry is cut to NAME.  0, or -1 with a
 * message in err.
 */
static int algorithm_entry(char *entry, struct dao_params *p, struct dao_error *err)
{
	char *colon = strchr(entry, ':');
	if (colon)
		*colon = '\0';
	if (dao_params_set(p, "algorithm", entry, err))
		return -1;
	return colon ? cli_apply_param_list(colon + 1, p, err) : 0;
}

/* Every entry of the --algorithms list valid?  0, or -1 with a message in err. */
static int check_algorithms(const char *list, struct dao_error *err)
{
	char buf[128], *save = NULL;
	snprintf(buf, sizeof buf, "%s", list);
	for (char *e = strtok_r(buf, ",", &save); e; e = strtok_r(NULL, ",", &save)) {
		struct dao_params p;
		dao_params_init(&p, DAO_QUALITY_DEFAULT);
		if (algorithm_entry(e, &p, err))
			return -1;
	}
	return 0;
}

int cmd_compare(int argc, char **argv)
{
	const char *scene = NULL, *input = NULL, *out = NULL, *intr = NULL, *intr_file = NULL;
	char algos_buf[128] = "gtao,vbao,hbao,ssao,edl";
	int noise = 0, rays_sqrt = 16;
	double unit = 0.001;
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
		if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
			usage(stdout);
			return 0;
		}
		if (!strcmp(a, "--noise")) {
			noise = 1;
			continue;
		}
		if (!v)
			return usage_error("compare", "%s needs a value", a);
		if (!strcmp(a, "--scene"))
			scene = v;
		else if (!strcmp(a, "--input"))
			input = v;
		else if (!strcmp(a, "--out"))
			out = v;
		else if (!strcmp(a, "--intrinsics"))
			intr = v;
		else if (!strcmp(a, "--intrinsics-file"))
			intr_file = v;
		else if (!strcmp(a, "--depth-unit"))
			unit = atof(v);
		else if (!strcmp(a, "--algorithms"))
			snprintf(algos_buf, sizeof algos_buf, "%s", v);
		else if (!strcmp(a, "--rays")) {
			long n = strtol(v, NULL, 10), r = lrint(sqrt((double)(n > 0 ? n : 0)));
			if (n < 1 || n > 65536 || r * r != n)
				return usage_error("compare", "--rays %s must be a perfect square in 1..65536", v);
			rays_sqrt = (int)r;
		} else
			return usage_error("compare", "unknown option '%s'", a);
		i++;
	}
	if (!out || (!scene == !input))
		return usage_error("compare", "give --out and one of --scene or --input");
	if (!(unit > 0 && unit <= 1))
		return usage_error("compare", "--depth-unit must be in (0, 1]");

	struct dao_error err;
	if (check_algorithms(algos_buf, &err))
		return usage_error("compare", "%s", err.message);
	struct dao_camera cam;
	float *depth = NULL, *gt = NULL;
	struct synth_image img = {0};
	struct synth_case c = {0};
	int status = 1;
	if (scene) {
		struct synth_scene sc;
		synth_default_camera(&cam);
		if (synth_scene_build(scene, 0.0, &sc, &err))
			return usage_error("compare", "%s", err.message);
		fprintf(stderr, "depthao: rendering %s (%d rays per pixel)...\n", scene,
			rays_sqrt * rays_sqrt);
		if (synth_render(&sc, &cam, 0.5, rays_sqrt, 2, &img, &err) ||
		    synth_case_make(&c, scene, noise, img.depth, img.gt, (int)cam.width,
				    (int)cam.height, 1, &err)) {
			fprintf(stderr, "depthao: %s\n", err.message);
			goto out;
		}
		depth = c.depth_m;
		gt = img.gt;
	} else {
		struct dao_frame f;
		char msg[512];
		if (dao_png_read_depth(input, (float)unit, &f, &err)) {
			fprintf(stderr, "depthao: %s\n", err.message);
			return 1;
		}
		double k[4];
		int r = -1;
		if (intr && sscanf(intr, "%lf,%lf,%lf,%lf", &k[0], &k[1], &k[2], &k[3]) == 4)
			r = dao_camera_from_intrinsics(&cam, f.width, f.height, k[0], k[1], k[2], k[3], &err);
		else if (intr_file && camera_file_read(intr_file, &cam, msg, sizeof msg) == 0)
			r = cam.width == f.width && cam.height == f.height ? 0 : -1;
		if (r) {
			dao_frame_free(&f);
			return usage_error("compare", "--input needs its camera: --intrinsics FX,FY,CX,CY "
					   "or --intrinsics-file of the same size");
		}
		depth = malloc((size_t)f.width * f.height * sizeof(float));
		for (uint32_t y = 0; y < f.height; y++)
			for (uint32_t x = 0; x < f.width; x++) {
				uint16_t v;
				memcpy(&v, (uint8_t *)f.data + (size_t)y * (size_t)f.stride + 2 * x, 2);
				depth[(size_t)y * f.width + x] = (float)(v * unit);
			}
		dao_frame_free(&f);
	}
	const uint32_t w = cam.width, h = cam.height;
	const size_t np = (size_t)w * h;
	float *plane = malloc(np * sizeof(float));
	struct dao_frame m = {0};
	char *save = NULL;
	int tiles = 0;
	if (!plane || dao_frame_alloc(&m, DAO_PIXFMT_RGB24, (w / 2) * COLUMNS, (h / 2) * 2, &err))
		goto out2;
	memset(m.data, 255, (size_t)m.stride * m.height); /* unused tiles stay white */
	/* the depth tile: near bright, far dark, holes black */
	float lo = INFINITY, hi = 0;
	for (size_t i = 0; i < np; i++)
		if (depth[i] > 0)
			lo = fminf(lo, depth[i]), hi = fmaxf(hi, depth[i]);
	for (size_t i = 0; i < np; i++)
		plane[i] = depth[i] > 0 ? 1.0f - 0.8f * (depth[i] - lo) / fmaxf(hi - lo, 1e-6f) : 0.0f;
	put_tile(&m, tiles++, plane, w, h);
	if (gt)
		put_tile(&m, tiles++, gt, w, h);
	for (char *name = strtok_r(algos_buf, ",", &save); name && tiles < MAX_TILES;
	     name = strtok_r(NULL, ",", &save)) {
		struct dao_params p;
		struct dao_context *ctx;
		dao_params_init(&p, DAO_QUALITY_DEFAULT);
		const char *alg = name;
		if (algorithm_entry(name, &p, &err)) { /* checked before the rendering */
			status = usage_error("compare", "%s", err.message);
			goto out2;
		}
		struct dao_frame in = {DAO_PIXFMT_DEPTH_F32, w, h, (int32_t)(w * 4), depth, 0, 0, 0};
		struct dao_frame ao = {DAO_PIXFMT_GRAY_F32, w, h, (int32_t)(w * 4), plane, 0, 0, 0};
		if (dao_context_create(&ctx, &cam, &p, &err) ||
		    dao_context_process(ctx, &in, NULL, 0, &ao, &err)) {
			fprintf(stderr, "depthao: %s: %s\n", alg, err.message);
			goto out2;
		}
		dao_context_destroy(ctx);
		put_tile(&m, tiles++, plane, w, h);
		fprintf(stderr, "depthao: tile %d: %s\n", tiles, alg);
	}
	if (dao_png_write(out, &m, &err)) {
		fprintf(stderr, "depthao: %s\n", err.message);
		goto out2;
	}
	printf("%s: %d tiles (depth%s, then the algorithms)\n", out, tiles, gt ? ", ground truth" : "");
	status = 0;
out2:
	free(plane);
	dao_frame_free(&m);
out:
	if (!scene)
		free(depth);
	synth_case_free(&c);
	synth_image_free(&img);
	return status;
}
