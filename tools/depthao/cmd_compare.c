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

struct compare_options {
	const char *scene, *input, *out, *intr, *intr_file;
	char algos[128];
	int noise, rays_sqrt;
	double unit;
};

/* The options into o: -1 to go on, else the exit status (0 after --help). */
static int parse_args(int argc, char **argv, struct compare_options *o)
{
	*o = (struct compare_options){ .algos = "gtao,vbao,hbao,ssao,edl", .rays_sqrt = 16,
				       .unit = 0.001 };
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
		if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
			usage(stdout);
			return 0;
		}
		if (!strcmp(a, "--noise")) {
			o->noise = 1;
			continue;
		}
		if (!v)
			return usage_error("compare", "%s needs a value", a);
		if (!strcmp(a, "--scene"))
			o->scene = v;
		else if (!strcmp(a, "--input"))
			o->input = v;
		else if (!strcmp(a, "--out"))
			o->out = v;
		else if (!strcmp(a, "--intrinsics"))
			o->intr = v;
		else if (!strcmp(a, "--intrinsics-file"))
			o->intr_file = v;
		else if (!strcmp(a, "--depth-unit"))
			o->unit = atof(v);
		else if (!strcmp(a, "--algorithms"))
			snprintf(o->algos, sizeof o->algos, "%s", v);
		else if (!strcmp(a, "--rays")) {
			long n = strtol(v, NULL, 10), r = lrint(sqrt((double)(n > 0 ? n : 0)));
			if (n < 1 || n > 65536 || r * r != n)
				return usage_error("compare", "--rays %s must be a perfect square in 1..65536", v);
			o->rays_sqrt = (int)r;
		} else
			return usage_error("compare", "unknown option '%s'", a);
		i++;
	}
	if (!o->out || (!o->scene == !o->input))
		return usage_error("compare", "give --out and one of --scene or --input");
	if (!(o->unit > 0 && o->unit <= 1))
		return usage_error("compare", "--depth-unit must be in (0, 1]");
	return -1;
}

/* The synthetic scene's ground truth and depth (noisy if asked): 0 or the exit status. */
static int render_scene(const struct compare_options *o, struct dao_camera *cam,
			struct synth_image *img, struct synth_case *c)
{
	struct synth_scene sc;
	struct dao_error err;
	synth_default_camera(cam);
	if (synth_scene_build(o->scene, 0.0, &sc, &err))
		return usage_error("compare", "%s", err.message);
	fprintf(stderr, "depthao: rendering %s (%d rays per pixel)...\n", o->scene,
		o->rays_sqrt * o->rays_sqrt);
	if (synth_render(&sc, cam, 0.5, o->rays_sqrt, 2, img, &err) ||
	    synth_case_make(c, o->scene, o->noise, img->depth, img->gt, (int)cam->width,
			    (int)cam->height, 1, &err)) {
		fprintf(stderr, "depthao: %s\n", err.message);
		return 1;
	}
	return 0;
}

/* The depth PNG in metres (*depth, the caller frees it) and its camera: 0 or the exit status. */
static int read_input(const struct compare_options *o, struct dao_camera *cam, float **depth)
{
	struct dao_frame f;
	struct dao_error err;
	char msg[512];
	if (dao_png_read_depth(o->input, (float)o->unit, &f, &err)) {
		fprintf(stderr, "depthao: %s\n", err.message);
		return 1;
	}
	double k[4];
	int r = -1;
	if (o->intr && sscanf(o->intr, "%lf,%lf,%lf,%lf", &k[0], &k[1], &k[2], &k[3]) == 4)
		r = dao_camera_from_intrinsics(cam, f.width, f.height, k[0], k[1], k[2], k[3], &err);
	else if (o->intr_file && camera_file_read(o->intr_file, cam, msg, sizeof msg) == 0)
		r = cam->width == f.width && cam->height == f.height ? 0 : -1;
	if (r) {
		dao_frame_free(&f);
		return usage_error("compare", "--input needs its camera: --intrinsics FX,FY,CX,CY "
				   "or --intrinsics-file of the same size");
	}
	float *d = *depth = malloc((size_t)f.width * f.height * sizeof(float));
	for (uint32_t y = 0; y < f.height; y++)
		for (uint32_t x = 0; x < f.width; x++) {
			uint16_t v;
			memcpy(&v, (uint8_t *)f.data + (size_t)y * (size_t)f.stride + 2 * x, 2);
			d[(size_t)y * f.width + x] = (float)(v * o->unit);
		}
	dao_frame_free(&f);
	return 0;
}

/* The depth tile's plane: near bright, far dark, holes black. */
static void depth_shade(const float *depth, size_t np, float *plane)
{
	float lo = INFINITY, hi = 0;
	for (size_t i = 0; i < np; i++)
		if (depth[i] > 0)
			lo = fminf(lo, depth[i]), hi = fmaxf(hi, depth[i]);
	for (size_t i = 0; i < np; i++)
		plane[i] = depth[i] > 0 ? 1.0f - 0.8f * (depth[i] - lo) / fmaxf(hi - lo, 1e-6f) : 0.0f;
}

/*
 * One tile per entry of the algorithm list, after the *tiles already in m
 * (plane: w x h of scratch): 0 or the exit status.
 */
static int algorithm_tiles(const char *list, const struct dao_camera *cam, float *depth,
			   float *plane, struct dao_frame *m, int *tiles)
{
	const uint32_t w = cam->width, h = cam->height;
	char algos[128], *save = NULL;
	struct dao_error err;
	snprintf(algos, sizeof algos, "%s", list);
	for (char *name = strtok_r(algos, ",", &save); name && *tiles < MAX_TILES;
	     name = strtok_r(NULL, ",", &save)) {
		struct dao_params p;
		struct dao_context *ctx;
		dao_params_init(&p, DAO_QUALITY_DEFAULT);
		const char *alg = name;
		if (algorithm_entry(name, &p, &err)) /* checked before the rendering */
			return usage_error("compare", "%s", err.message);
		struct dao_frame in = {.format = DAO_PIXFMT_DEPTH_F32, .width = w, .height = h,
				.stride = (int32_t)(w * 4), .data = depth};
		struct dao_frame ao = {.format = DAO_PIXFMT_GRAY_F32, .width = w, .height = h,
				.stride = (int32_t)(w * 4), .data = plane};
		if (dao_context_create(&ctx, cam, &p, &err) ||
		    dao_context_process(ctx, &in, NULL, 0, &ao, &err)) {
			fprintf(stderr, "depthao: %s: %s\n", alg, err.message);
			return 1;
		}
		dao_context_destroy(ctx);
		put_tile(m, (*tiles)++, plane, w, h);
		fprintf(stderr, "depthao: tile %d: %s\n", *tiles, alg);
	}
	return 0;
}

/* The montage of the depth, the ground truth (if any) and the algorithms: the exit status. */
static int write_montage(const struct compare_options *o, const struct dao_camera *cam,
			 float *depth, const float *gt)
{
	const uint32_t w = cam->width, h = cam->height;
	const size_t np = (size_t)w * h;
	float *plane = malloc(np * sizeof(float));
	struct dao_frame m = {0};
	struct dao_error err;
	int tiles = 0, status = 1;
	if (!plane || dao_frame_alloc(&m, DAO_PIXFMT_RGB24, (w / 2) * COLUMNS, (h / 2) * 2, &err))
		goto out;
	memset(m.data, 255, (size_t)m.stride * m.height); /* unused tiles stay white */
	depth_shade(depth, np, plane);
	put_tile(&m, tiles++, plane, w, h);
	if (gt)
		put_tile(&m, tiles++, gt, w, h);
	if ((status = algorithm_tiles(o->algos, cam, depth, plane, &m, &tiles)))
		goto out;
	status = 1;
	if (dao_png_write(o->out, &m, &err)) {
		fprintf(stderr, "depthao: %s\n", err.message);
		goto out;
	}
	printf("%s: %d tiles (depth%s, then the algorithms)\n", o->out, tiles,
	       gt ? ", ground truth" : "");
	status = 0;
out:
	free(plane);
	dao_frame_free(&m);
	return status;
}

int cmd_compare(int argc, char **argv)
{
	struct compare_options o;
	int status = parse_args(argc, argv, &o);
	if (status >= 0)
		return status;
	struct dao_error err;
	if (check_algorithms(o.algos, &err))
		return usage_error("compare", "%s", err.message);
	struct dao_camera cam;
	float *depth = NULL;
	struct synth_image img = {0};
	struct synth_case c = {0};
	if (o.scene)
		status = render_scene(&o, &cam, &img, &c);
	else
		status = read_input(&o, &cam, &depth);
	if (!status)
		status = write_montage(&o, &cam, o.scene ? c.depth_m : depth, o.scene ? img.gt : NULL);
	free(depth);
	synth_case_free(&c);
	synth_image_free(&img);
	return status;
}
