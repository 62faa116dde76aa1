/* SPDX-License-Identifier: MIT */
/*
 * depthao bench: time the whole per-frame pipeline (process + shade) and each
 * stage on synthetic frames, for sizes x quality presets x thread counts, and
 * compare with the scalar reference kernels at the same settings.
 */
#include <errno.h>
#include <getopt.h>
#include <json-c/json.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <depthao/depthao.h>

#include "common/tool_clock.h"
#include "bench.h"
#include "bench_input.h"
#include "cli_params.h"
#include "commands.h"
#include <depthao/error.h>
#include "synth/synth.h"

#define MAX_SIZES 16 /* = bench_compare_spec.sizes */
#define MAX_QUALITIES 8
#define MAX_THREADS 4
#define MAX_PARAM_OPTIONS 32

struct size {
	int w, h;
};

/* The frames a configuration is timed on: the synthetic one, or --input's. */
struct frames {
	const struct dao_camera *cam;
	const struct dao_frame *f;
	uint32_t n;
	int stream;        /* a stream: cycled with the frame index increasing, stream defaults */
	const char *input; /* --input, NULL for the synthetic frame */
};

struct config {
	struct size size;
	const struct frames *fr;
	const char *quality;  /* preset name, or "custom" */
	struct dao_params params;
	int threads;
};

struct stats {
	double median, p95;
	double stage[8]; /* medians: decode noise prefilter normals gtao denoise output shade */
	int iterations;
};

const char *const bench_stage_names[BENCH_NSTAGES] = { "decode", "noise", "prefilter",
							"normals", "gtao", "denoise",
							"output", "shade" };
#define NSTAGES BENCH_NSTAGES
#define stage_names bench_stage_names

/* --size sensors: the frames of the depth cameras people use */
static const struct size sensor_sizes[] = {
	{ 640, 480 },   /* Kinect v1, Xtion, Orbbec Astra: VGA */
	{ 848, 480 },   /* Intel RealSense D4xx at up to 90 fps */
	{ 1280, 720 },  /* RealSense D4xx at its full resolution */
	{ 1024, 1024 }, /* Azure Kinect / Orbbec Femto wide field of view: ToF */
};

static void usage(FILE *out)
{
	fprintf(out,
		"usage: depthao bench [options]\n"
		"\n"
		"Times the per-frame pipeline (dao_context_process_shaded: 16-bit AO output and\n"
		"the shaded RGB image) and each of its stages on a synthetic 16-bit depth\n"
		"frame (the \"boxes\" scene with Kinect-like noise), for every size x quality x\n"
		"thread count, or on your own frames (--input), after a warm-up.  Prints the\n"
		"median and 95th percentile per frame, frames per second (1000 / median),\n"
		"megapixels per second, and the speedup over the scalar reference kernels\n"
		"(simd=reference) at the same settings.\n"
		"\n"
		"  --size WxH[,WxH...] frame sizes, or `sensors` for the cameras' frames: 640x480\n"
		"                      (Kinect), 848x480 (RealSense), 1280x720, 1024x1024 (Azure\n"
		"                      Kinect ToF); repeatable (default: 320x240, 640x480, 1280x720)\n"
		"  --quality Q         low, medium, high, ultra, default (= what `depthao process`\n"
		"                      uses), or all (default: all presets)\n"
		"  --slices N          override the preset's slices\n"
		"  --steps N           override the preset's steps per side\n"
		"  --threads N[,N...]  thread counts, repeatable (default: 1 and every CPU)\n"
		"  --simd S            kernels to time: auto (default), generic, sse4.1, avx2,\n"
		"                      avx512\n"
		"  --min-time S        time each configuration for at least S seconds (default 0.5)\n"
		"  --min-iterations N  and at least N frames (default 30)\n"
		"  --no-reference      skip the (slow) reference runs and the speedup column\n"
		"  --input PATH        time these frames instead of the synthetic one: what\n"
		"                      `depthao process --input` takes (a 16-bit depth PNG, a\n"
		"                      directory of them, .oni, .bag, .mcap, .db3, a source URI;\n"
		"                      float-metre depth too), at their own size (--size is an\n"
		"                      error).  A directory, recording or device is timed as a\n"
		"                      stream: its frames in order, again and again, the frame\n"
		"                      index one up each frame (the last frame to the first: a\n"
		"                      cut), with `process`'s stream defaults (--depth-temporal\n"
		"                      0.8, the noise schedule; --depth-temporal 0 turns it off)\n"
		"  --input-frames N    the frames read into memory before timing, each then\n"
		"                      timed at least once (default 30; at most 2 GiB of depth);\n"
		"                      the reference runs once on each (a second or so a VGA\n"
		"                      frame: --no-reference for quick runs); bench reads no\n"
		"                      poses: --depth-temporal-motion source is refused\n"
		"  --intrinsics FX,FY,CX,CY, --fov H,V, --intrinsics-file FILE, --depth-unit M,\n"
		"  --max-pixels N|WxH  the camera, PNG unit and pixel limit, as in `depthao\n"
		"                      process` (default: the recording's, camera.json beside PNGs)\n"
		"  --json              one JSON object per configuration and line, no table\n"
		"  --help              this text\n"
		"\n"
		"Any other algorithm parameter can be set as in `depthao process` (--radius ...),\n"
		"among them --algorithm (gtao, vbao, hbao, ssao, edl): the AO stage is its kernel;\n"
		"--algorithm none times the depth filtering alone (no normals, AO or shading).\n"
		"\n"
		"Side by side: builds, or parameter sets, timed in one run:\n"
		"  --compare OTHER     also time OTHER, a build directory (its\n"
		"                      tools/depthao/depthao) or a depthao binary; repeatable\n"
		"  --compare-params 'OPTIONS'  also time this build with OPTIONS (split at\n"
		"                      spaces) added, e.g. '--noise-model fixed'; repeatable\n"
		"  --rounds N          rounds (default 5)\n"
		"Each run is a child process `depthao bench OPTIONS --size WxH --json`, one per\n"
		"size (with --input one, without --size); a round runs every build once per\n"
		"size, the first build in turn.  OPTIONS\n"
		"are the ones given, passed on as given (an older build knows fewer: it is said\n"
		"which one it rejects).  Printed per configuration: each build's median and p95\n"
		"(medians over the rounds) and fps; the ratio A/X of this build's (A) time to\n"
		"the other's (> 1: A is slower), the median of the rounds' ratios with their\n"
		"min-max, of the frame and each stage ('-': a stage X does not time); the load\n"
		"average before and after.  With --json, one object.  For example:\n"
		"  depthao bench --compare ../rel --compare-params '--noise-model fixed' \\\n"
		"      --size 640x480 --quality default --threads 2 --no-reference\n");
}

static double now_s(void)
{
	return (double)tool_mono_ns() * 1e-9;
}

static int cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

/* q in [0, 1] of n sorted values, nearest rank */
static double quantile(double *v, int n, double q)
{
	qsort(v, (size_t)n, sizeof *v, cmp_double);
	int k = (int)(q * (double)(n - 1) + 0.5);
	return v[k];
}

/* A noisy 16-bit depth frame of the boxes scene for a camera of this size. */
static int make_frame(struct size sz, struct dao_camera *cam, uint16_t **out, struct dao_error *err)
{
	const double f = 525.0 * (double)sz.w / 640.0;
	int r = dao_camera_from_intrinsics(cam, (uint32_t)sz.w, (uint32_t)sz.h, f, f,
					   0.5 * (sz.w - 1), 0.5 * (sz.h - 1), err);
	if (r)
		return r;
	struct synth_scene scene;
	r = synth_scene_build("boxes", 0.0, &scene, err);
	if (r)
		return r;
	struct synth_image img;
	r = synth_render(&scene, cam, 0.5, 0, 2, &img, err);
	if (r)
		return r;
	synth_sensor_noise(img.depth, sz.w, sz.h, 0.0012, 0.001, 0.01, 1);
	uint16_t *d = malloc((size_t)sz.w * sz.h * sizeof *d);
	if (!d) {
		synth_image_free(&img);
		return dao_error_set(err, -ENOMEM, "out of memory for the benchmark frame");
	}
	for (size_t i = 0; i < (size_t)sz.w * sz.h; i++) {
		double mm = img.depth[i] * 1000.0 + 0.5;
		d[i] = (uint16_t)(mm < 65535.0 ? mm : 0.0);
	}
	synth_image_free(&img);
	*out = d;
	return 0;
}

/* Times one configuration; iterations >= min_iter and >= min_time seconds. */
static int run(const struct config *c, int simd, int min_iter, double min_time, int max_iter,
	       struct stats *st, struct dao_error *err)
{
	const struct frames *fr = c->fr;
	struct dao_params p = c->params;
	p.threads = c->threads;
	p.simd = simd;
	struct dao_context *ctx;
	int r = dao_context_create(&ctx, fr->cam, &p, err);
	if (r)
		return r;
	const size_t npix = (size_t)c->size.w * c->size.h;
	uint16_t *ao16 = malloc(npix * 2);
	uint8_t *rgb = malloc(npix * 3);
	double *t = malloc((size_t)max_iter * sizeof *t);
	double *stage = malloc((size_t)max_iter * NSTAGES * sizeof *stage);
	if (!ao16 || !rgb || !t || !stage) {
		r = dao_error_set(err, -ENOMEM, "out of memory for the benchmark buffers");
		goto out;
	}
	const uint32_t w = (uint32_t)c->size.w, h = (uint32_t)c->size.h;
	struct dao_frame ao = { .format = DAO_PIXFMT_GRAY16, .width = w, .height = h,
				.stride = 2 * c->size.w, .data = ao16 };
	struct dao_frame sh = { .format = DAO_PIXFMT_RGB24, .width = w, .height = h,
				.stride = 3 * c->size.w, .data = rgb };
	/* warm-up: caches, page faults, the pool's threads */
	const int warm = simd == DAO_SIMD_REFERENCE ? 1 : 3;
	int n = 0;
	const double start = now_s();
	for (int i = -warm; i < max_iter; i++) {
		/* the frames in turn, the index one up each frame: a stream to the temporal
		 * filters (the last frame to the first a cut in the scene, as a camera may see) */
		const struct dao_frame *in = &fr->f[(size_t)(i + warm) % fr->n];
		double t0 = now_s();
		/* the AO and the shaded image in one pass; none: nothing to shade */
		r = dao_context_process_shaded(ctx, in, NULL, (uint64_t)(i + warm), &ao,
					       c->params.algorithm != DAO_ALGORITHM_NONE ? &sh : NULL,
					       err);
		if (r)
			goto out;
		double t1 = now_s();
		if (i < 0)
			continue;
		struct dao_timings tm = DAO_TIMINGS_INIT;
		dao_context_timings(ctx, &tm);
		t[n] = (t1 - t0) * 1e3;
		double s[NSTAGES] = { tm.decode_ms, tm.noise_ms, tm.prefilter_ms, tm.normals_ms,
				      tm.gtao_ms, tm.denoise_ms, tm.output_ms, tm.shade_ms };
		memcpy(stage + (size_t)n * NSTAGES, s, sizeof s);
		n++;
		if (n >= min_iter && t1 - start >= min_time)
			break;
	}
	st->iterations = n;
	st->p95 = quantile(t, n, 0.95);
	st->median = quantile(t, n, 0.5);
	for (int k = 0; k < NSTAGES; k++) {
		for (int i = 0; i < n; i++)
			t[i] = stage[(size_t)i * NSTAGES + k];
		st->stage[k] = quantile(t, n, 0.5);
	}
out:
	free(stage);
	free(t);
	free(rgb);
	free(ao16);
	dao_context_destroy(ctx);
	return r;
}

static int parse_size(const char *s, struct size *out)
{
	char *end;
	long w = strtol(s, &end, 10);
	if (*end != 'x' && *end != 'X')
		return -1;
	long h = strtol(end + 1, &end, 10);
	if (*end || w < 16 || h < 16 || w > 16384 || h > 16384)
		return -1;
	out->w = (int)w;
	out->h = (int)h;
	return 0;
}

static void print_json(const struct config *c, int simd, const struct stats *st,
		       const struct stats *ref)
{
	json_object *o = json_object_new_object();
	json_object_object_add(o, "width", json_object_new_int(c->size.w));
	json_object_object_add(o, "height", json_object_new_int(c->size.h));
	json_object_object_add(o, "quality", json_object_new_string(c->quality));
	char algo[32];
	if (dao_params_get(&c->params, "algorithm", algo, sizeof algo, NULL) == 0)
		json_object_object_add(o, "algorithm", json_object_new_string(algo));
	json_object_object_add(o, "slices", json_object_new_int(c->params.slices));
	json_object_object_add(o, "steps", json_object_new_int(c->params.steps));
	json_object_object_add(o, "threads", json_object_new_int(c->threads));
	json_object_object_add(o, "simd", json_object_new_string(dao_simd_name(simd)));
	if (c->fr->input) {
		json_object_object_add(o, "input", json_object_new_string(c->fr->input));
		json_object_object_add(o, "input_frames", json_object_new_int((int)c->fr->n));
		json_object_object_add(o, "input_format",
				       json_object_new_string(dao_pixfmt_name(c->fr->f[0].format)));
		json_object_object_add(o, "stream", json_object_new_boolean(c->fr->stream));
		/* what a stream changes: its defaults */
		json_object_object_add(o, "depth_temporal",
				       json_object_new_double(c->params.depth_temporal));
		json_object_object_add(o, "noise_interval",
				       json_object_new_int(c->params.noise_interval));
	}
	json_object_object_add(o, "iterations", json_object_new_int(st->iterations));
	json_object_object_add(o, "median_ms", json_object_new_double(st->median));
	json_object_object_add(o, "p95_ms", json_object_new_double(st->p95));
	json_object_object_add(o, "mpix_per_s",
			       json_object_new_double((double)c->size.w * c->size.h / st->median / 1e3));
	json_object_object_add(o, "fps", json_object_new_double(1e3 / st->median));
	json_object *stg = json_object_new_object();
	for (int k = 0; k < NSTAGES; k++)
		json_object_object_add(stg, stage_names[k], json_object_new_double(st->stage[k]));
	json_object_object_add(o, "stage_median_ms", stg);
	if (ref) {
		json_object_object_add(o, "reference_median_ms", json_object_new_double(ref->median));
		json_object_object_add(o, "speedup", json_object_new_double(ref->median / st->median));
	}
	puts(json_object_to_json_string_ext(o, JSON_C_TO_STRING_PLAIN));
	fflush(stdout);
	json_object_put(o);
}

static void print_row(const struct config *c, const struct stats *st, const struct stats *ref)
{
	char size[24], q[64], sp[16] = "-", rm[16] = "-";
	snprintf(size, sizeof size, "%dx%d", c->size.w, c->size.h);
	snprintf(q, sizeof q, "%s %dx%d", c->quality, c->params.slices, c->params.steps);
	if (c->params.algorithm != DAO_ALGORITHM_GTAO) {
		char algo[32];
		if (dao_params_get(&c->params, "algorithm", algo, sizeof algo, NULL) == 0)
			snprintf(q, sizeof q, "%s %s %dx%d", algo, c->quality, c->params.slices,
				 c->params.steps);
	}
	if (ref) {
		snprintf(rm, sizeof rm, "%.0f", ref->median);
		snprintf(sp, sizeof sp, "%.0fx", ref->median / st->median);
	}
	printf("%-10s %-15s %2d %8.2f %8.2f %7.1f %8.1f %8s %7s |", size, q, c->threads, st->median,
	       st->p95, 1e3 / st->median, (double)c->size.w * c->size.h / st->median / 1e3, rm, sp);
	for (int k = 0; k < NSTAGES; k++)
		printf(" %6.2f", st->stage[k]);
	putchar('\n');
	fflush(stdout);
}

/* What the command line asked for. */
struct bench_options {
	struct size sizes[MAX_SIZES];
	int nsizes;
	const char *qnames[MAX_QUALITIES];
	int nq;
	int threads[MAX_THREADS], nthreads;
	int json, no_ref, min_iter;
	double min_time;
	int slices, steps, simd; /* 0 / AUTO: the preset's */
	/* the parameter options, replayed on top of each preset */
	const char *param_args[2 * MAX_PARAM_OPTIONS];
	int nparam;
	struct bench_input_options in; /* --input and the options that go with it */
	/* --compare, --compare-params, --rounds, and the options to pass on to each run */
	struct bench_compare_spec cmp;
	struct bench_arg pass[MAX_PARAM_OPTIONS + MAX_QUALITIES + MAX_THREADS + 8 +
			      BENCH_INPUT_NOPTIONS];
	char size_text[MAX_SIZES][16], thread_text[MAX_THREADS][8];
};

enum { OPT_SIZE = 1000, OPT_QUALITY, OPT_THREADS, OPT_MIN_TIME, OPT_MIN_ITER, OPT_NO_REF,
       OPT_JSON, OPT_HELP, OPT_COMPARE, OPT_COMPARE_PARAMS, OPT_ROUNDS,
       OPT_INPUT, /* + index in bench_input_names */
       OPT_PARAM = OPT_INPUT + BENCH_INPUT_NOPTIONS /* + index in the parameter table */ };

static const struct option bench_long_options[] = {
	{ "size", required_argument, NULL, OPT_SIZE },
	{ "quality", required_argument, NULL, OPT_QUALITY },
	{ "threads", required_argument, NULL, OPT_THREADS },
	{ "min-time", required_argument, NULL, OPT_MIN_TIME },
	{ "min-iterations", required_argument, NULL, OPT_MIN_ITER },
	{ "no-reference", no_argument, NULL, OPT_NO_REF },
	{ "json", no_argument, NULL, OPT_JSON },
	{ "help", no_argument, NULL, OPT_HELP },
	{ "compare", required_argument, NULL, OPT_COMPARE },
	{ "compare-params", required_argument, NULL, OPT_COMPARE_PARAMS },
	{ "rounds", required_argument, NULL, OPT_ROUNDS },
};
#define N_BENCH_OPTIONS (int)(sizeof bench_long_options / sizeof bench_long_options[0])

/*
 * bench's own options, then every AO parameter by its name and with
 * underscores (as the parameter table accepts both); `names` holds the
 * underscore spellings.  Returns the table (NULL-terminated) in `opts`.
 */
static void long_options(struct option *opts, char (*names)[64])
{
	size_t n;
	const struct dao_param_info *t = dao_param_table(&n);
	int k = 0;
	for (int i = 0; i < N_BENCH_OPTIONS; i++)
		opts[k++] = bench_long_options[i];
	for (int i = 0; i < BENCH_INPUT_NOPTIONS; i++)
		opts[k++] = (struct option){ bench_input_names[i], required_argument, NULL,
					     OPT_INPUT + i };
	for (size_t i = 0; i < n; i++) {
		/* --threads is bench's own (a list of counts to time) */
		if (!strcmp(t[i].name, "threads"))
			continue;
		opts[k++] = (struct option){ t[i].name, required_argument, NULL, OPT_PARAM + (int)i };
		snprintf(names[i], sizeof names[i], "%s", t[i].name);
		for (char *c = names[i]; *c; c++)
			if (*c == '-')
				*c = '_';
		if (strcmp(names[i], t[i].name))
			opts[k++] = (struct option){ names[i], required_argument, NULL,
						     OPT_PARAM + (int)i };
	}
	opts[k] = (struct option){ NULL, 0, NULL, 0 };
}

/* Appends an option (its long name) and its value (or NULL) to what --compare passes on. */
static int pass_on(struct bench_options *o, const char *name, const char *value)
{
	if (o->cmp.nargs == (int)(sizeof o->pass / sizeof o->pass[0]))
		return usage_error("bench", "too many options");
	o->pass[o->cmp.nargs++] = (struct bench_arg){ name, value };
	return 0;
}

/* The next comma-separated item of *p (an empty one too), NULL at the end. */
static char *next_item(char **p)
{
	char *item = *p;
	if (!item)
		return NULL;
	char *comma = strchr(item, ',');
	*p = comma ? comma + 1 : NULL;
	if (comma)
		*comma = 0;
	return item;
}

/* --size's value (split in place): WxH or `sensors`, comma-separated; appended to o->sizes. */
static int add_sizes(struct bench_options *o, char *list)
{
	for (char *rest = list, *tok; (tok = next_item(&rest));) {
		const int named = !strcmp(tok, "sensors");
		const int n = named ? (int)(sizeof sensor_sizes / sizeof sensor_sizes[0]) : 1;
		if (o->nsizes + n > MAX_SIZES)
			return usage_error("bench", "at most %d sizes", MAX_SIZES);
		if (named)
			memcpy(&o->sizes[o->nsizes], sensor_sizes, sizeof sensor_sizes);
		else if (parse_size(tok, &o->sizes[o->nsizes]))
			return usage_error("bench", "--size needs WxH, e.g. 640x480 (16..16384), a "
					   "comma-separated list of them, or sensors");
		o->nsizes += n;
	}
	return 0;
}

/* --threads's value (split in place): counts, comma-separated; each passed on as its own
 * --threads. */
static int add_threads(struct bench_options *o, char *list)
{
	for (char *rest = list, *tok; (tok = next_item(&rest));) {
		char *end;
		long n = strtol(tok, &end, 10);
		if (*end || end == tok || n < 1 || n > 256)
			return usage_error("bench", "--threads needs a count from 1 to 256");
		if (o->nthreads == MAX_THREADS)
			return usage_error("bench", "at most %d thread counts", MAX_THREADS);
		snprintf(o->thread_text[o->nthreads], sizeof o->thread_text[0], "%ld", n);
		int r = pass_on(o, "threads", o->thread_text[o->nthreads]);
		if (r)
			return r;
		o->threads[o->nthreads++] = (int)n;
	}
	return 0;
}

/* One of bench's own options with its value; 0, or a usage error's exit status. */
static int bench_option(struct bench_options *o, int opt, const char *v, int *size_given)
{
	struct dao_error err = { 0 };
	char list[256];
	if ((opt == OPT_SIZE || opt == OPT_THREADS) && strlen(v) >= sizeof list)
		return usage_error("bench", "--%s: list too long", opt == OPT_SIZE ? "size" : "threads");
	switch (opt) {
	case OPT_SIZE:
		if (!*size_given)
			o->nsizes = 0;
		*size_given = 1;
		return add_sizes(o, strcpy(list, v));
	case OPT_QUALITY: {
		enum dao_quality q;
		if (strcmp(v, "all") && dao_quality_parse(v, &q, &err))
			return usage_error("bench", "%s", err.message);
		if (o->nq == MAX_QUALITIES)
			return usage_error("bench", "too many --quality options");
		o->qnames[o->nq++] = v;
		return pass_on(o, "quality", v);
	}
	case OPT_THREADS:
		return add_threads(o, strcpy(list, v));
	case OPT_MIN_TIME:
	case OPT_MIN_ITER: {
		char *end;
		double n = strtod(v, &end);
		if (*end || end == v || !(n >= 0 && n <= 3600))
			return usage_error("bench", "--%s needs a number from 0 to 3600",
					   opt == OPT_MIN_TIME ? "min-time" : "min-iterations");
		if (opt == OPT_MIN_TIME)
			o->min_time = n;
		else
			o->min_iter = n < 1 ? 1 : (int)n;
		return pass_on(o, opt == OPT_MIN_TIME ? "min-time" : "min-iterations", v);
	}
	case OPT_NO_REF:
		o->no_ref = 1;
		return pass_on(o, "no-reference", NULL);
	case OPT_JSON:
		o->json = 1;
		return 0;
	case OPT_COMPARE:
	case OPT_COMPARE_PARAMS:
		if (o->cmp.nothers + o->cmp.nparams + 1 >= BENCH_MAX_VARIANTS)
			return usage_error("bench", "at most %d --compare and --compare-params",
					   BENCH_MAX_VARIANTS - 1);
		if (opt == OPT_COMPARE)
			o->cmp.others[o->cmp.nothers++] = v;
		else
			o->cmp.params[o->cmp.nparams++] = v;
		return 0;
	case OPT_ROUNDS: {
		char *end;
		long n = strtol(v, &end, 10);
		if (*end || end == v || n < 1 || n > 1000)
			return usage_error("bench", "--rounds needs a count from 1 to 1000");
		o->cmp.rounds = (int)n;
		return 0;
	}
	}
	return usage_error("bench", "internal: option %d", opt);
}

/* After the command line: the sizes spelled out for --compare, and its checks. */
static int finish_compare(struct bench_options *o, int rounds_given)
{
	if (!o->cmp.nothers && !o->cmp.nparams)
		return rounds_given ? usage_error("bench", "--rounds goes with --compare or "
						  "--compare-params") : 0;
	o->cmp.args = o->pass;
	o->cmp.json = o->json;
	if ((o->cmp.input = o->in.po.input)) {
		o->cmp.nsizes = 1; /* one run: the input's frames at their size */
		o->cmp.sizes[0] = NULL;
		return 0;
	}
	/* every size, given or the default, so that all builds time the same frames */
	for (int i = 0; i < o->nsizes; i++) {
		snprintf(o->size_text[i], sizeof o->size_text[i], "%dx%d", o->sizes[i].w,
			 o->sizes[i].h);
		o->cmp.sizes[i] = o->size_text[i];
	}
	o->cmp.nsizes = o->nsizes;
	return 0;
}

/*
 * The command line into `o`; 0, -1 after --help, or a usage error's exit
 * status.  AO parameters are checked against a copy of the defaults and kept
 * to be applied on top of each preset.
 */
static int parse_options(int argc, char **argv, struct bench_options *o)
{
	static char names[256][64];
	struct option opts[N_BENCH_OPTIONS + BENCH_INPUT_NOPTIONS + 2 * 256 + 1];
	size_t nparams;
	dao_param_table(&nparams);
	if (nparams > 256)
		return usage_error("bench", "internal: %zu parameters", nparams);
	long_options(opts, names);

	*o = (struct bench_options){ .sizes = { { 320, 240 }, { 640, 480 }, { 1280, 720 } },
				     .nsizes = 3, .min_iter = 30, .min_time = 0.5,
				     .simd = DAO_SIMD_AUTO, .cmp.rounds = 5 };
	bench_input_options_init(&o->in);
	struct dao_params over; /* the parameter options, to check them and read slices ... */
	dao_params_init(&over, DAO_QUALITY_DEFAULT);
	const struct dao_param_info *table = dao_param_table(&nparams);
	int size_given = 0, rounds_given = 0, opt, r;
	optind = 1;
	opterr = 0;
	while ((opt = getopt_long(argc, argv, ":", opts, NULL)) != -1) {
		const char *given = argv[optind - 1];
		if (opt == OPT_HELP) {
			usage(stdout);
			return -1;
		} else if (opt == '?') {
			return usage_error("bench", "unknown option '%s'", given);
		} else if (opt == ':') {
			return usage_error("bench", "%s needs a value", given);
		} else if (opt >= OPT_PARAM) {
			const struct dao_param_info *pi = &table[opt - OPT_PARAM];
			struct dao_error err;
			if (dao_params_set(&over, pi->name, optarg, &err))
				return usage_error("bench", "%s", err.message);
			if (o->nparam + 2 > 2 * MAX_PARAM_OPTIONS)
				return usage_error("bench", "too many parameter options");
			o->param_args[o->nparam++] = pi->name;
			o->param_args[o->nparam++] = optarg;
			if ((r = pass_on(o, pi->name, optarg)))
				return r;
		} else if (opt >= OPT_INPUT) {
			if ((r = bench_input_option(&o->in, opt - OPT_INPUT, optarg)) ||
			    (r = pass_on(o, bench_input_names[opt - OPT_INPUT], optarg)))
				return r;
		} else if ((r = bench_option(o, opt, optarg, &size_given))) {
			return r;
		}
		rounds_given |= opt == OPT_ROUNDS;
	}
	if (optind < argc)
		return usage_error("bench", "unexpected argument '%s'", argv[optind]);
	if ((r = bench_input_check(&o->in, size_given, &over)) ||
	    (r = finish_compare(o, rounds_given)))
		return r;

	/* --slices, --steps and --simd given as parameter options */
	struct dao_params def;
	dao_params_init(&def, DAO_QUALITY_DEFAULT);
	if (over.slices != def.slices)
		o->slices = over.slices;
	if (over.steps != def.steps)
		o->steps = over.steps;
	o->simd = over.simd;
	if (o->simd == DAO_SIMD_REFERENCE)
		return usage_error("bench", "--simd reference is what the speedup compares with; "
				   "pick auto, generic, sse4.1, avx2 or avx512");
	if (!dao_simd_supported((enum dao_simd)o->simd))
		return usage_error("bench", "--simd %s: this CPU or build cannot run it",
				   dao_simd_name((enum dao_simd)o->simd));
	if (o->nq == 0 || (o->nq == 1 && !strcmp(o->qnames[0], "all"))) {
		o->nq = 0;
		for (int q = 0; q < DAO_QUALITY_COUNT; q++)
			o->qnames[o->nq++] = dao_quality_name((enum dao_quality)q);
	}
	if (o->nthreads == 0) {
		o->threads[o->nthreads++] = 1;
		if (dao_cpu_count() > 1)
			o->threads[o->nthreads++] = dao_cpu_count();
	}
	return 0;
}

/* What was timed: the synthetic frame, or --input's frames. */
static void print_input(const struct bench_options *o, const struct bench_input *in)
{
	if (!o->in.po.input) {
		printf("frame = dao_context_process_shaded (depth16 in, gray16 AO and RGB out); "
		       "synthetic \"boxes\" scene with sensor noise\n");
		return;
	}
	const struct dao_frame *f = &in->frames[0];
	char unit[32] = "";
	if (f->format == DAO_PIXFMT_DEPTH16)
		snprintf(unit, sizeof unit, " (%g mm)", (double)f->depth_unit * 1e3);
	printf("frame = dao_context_process_shaded (%s in, gray16 AO and RGB out) on --input %s\n",
	       dao_pixfmt_name(f->format), o->in.po.input);
	printf("input: %s; %u frame%s of %ux%u %s%s in memory, %s\n", in->description, in->n,
	       in->n == 1 ? "" : "s", f->width, f->height, dao_pixfmt_name(f->format), unit,
	       in->stream ? "cycled in order as a stream (frame index increasing; the stream "
			    "defaults: temporal depth filter, noise schedule)"
			  : "timed again and again (one file: not a stream)");
}

static void print_header(const struct bench_options *o, const struct bench_input *in,
			 int resolved)
{
	char model[128];
	dao_cpu_model(model, sizeof model);
	printf("depthao %s bench: %s, %d CPUs, kernels %s%s\n", depthao_version_line(), model,
	       dao_cpu_count(), dao_simd_name((enum dao_simd)resolved),
	       o->simd == DAO_SIMD_AUTO ? " (auto)" : "");
	print_input(o, in);
	printf("times in ms per frame; fps = 1000 / median; ref = scalar reference kernels "
	       "(simd=reference), same settings\n\n");
	printf("%-10s %-15s %2s %8s %8s %7s %8s %8s %7s |", "size", "quality", "th", "median", "p95",
	       "fps", "Mpix/s", "ref", "speedup");
	for (int k = 0; k < NSTAGES; k++)
		printf(" %6.6s", stage_names[k]);
	putchar('\n');
}

/* The parameters of preset `qname` with the user's parameter options on top. */
static int preset_config(const struct bench_options *o, const char *qname, struct config *c,
			 struct dao_error *err)
{
	enum dao_quality q;
	dao_quality_parse(qname, &q, NULL);
	dao_params_init(&c->params, q);
	if (c->fr->stream) /* as `depthao process` runs a recording */
		dao_params_stream_defaults(&c->params);
	c->quality = !strcmp(qname, "default") ? "default" : dao_quality_name(q);
	for (int k = 0; k < o->nparam; k += 2)
		dao_params_set(&c->params, o->param_args[k], o->param_args[k + 1], NULL);
	if (o->slices || o->steps)
		c->quality = "custom";
	return dao_params_validate(&c->params, err);
}

/* Every preset x thread count on these frames: timed, then the reference at the same
 * settings. */
static int run_frames(const struct bench_options *o, struct size sz, const struct frames *fr,
		      int resolved, struct dao_error *err)
{
	/* every input frame timed at least once */
	const int min_iter = fr->input && (int)fr->n > o->min_iter ? (int)fr->n : o->min_iter;
	int r = 0;
	for (int qi = 0; !r && qi < o->nq; qi++) {
		struct config c = { .size = sz, .fr = fr };
		r = preset_config(o, o->qnames[qi], &c, err);
		for (int ti = 0; !r && ti < o->nthreads; ti++) {
			c.threads = o->threads[ti];
			struct stats st = { 0 }, ref = { 0 };
			r = run(&c, o->simd, min_iter, o->min_time, 100000, &st, err);
			/* the reference on the same frames: with --input all of them
			 * (the speedup compares like with like), else three */
			const int ref_iter = fr->input && (int)fr->n > 3 ? (int)fr->n : 3;
			if (!r && !o->no_ref)
				r = run(&c, DAO_SIMD_REFERENCE, ref_iter, 0.0, ref_iter, &ref, err);
			if (r)
				break;
			if (o->json)
				print_json(&c, resolved, &st, o->no_ref ? NULL : &ref);
			else
				print_row(&c, &st, o->no_ref ? NULL : &ref);
		}
	}
	return r;
}

/* --input's frames, or the synthetic frame of every size. */
static int run_all(const struct bench_options *o, const struct bench_input *in, int resolved,
		   struct dao_error *err)
{
	if (o->in.po.input) {
		const struct frames fr = { &in->cam, in->frames, in->n, in->stream, o->in.po.input };
		const struct size sz = { (int)in->cam.width, (int)in->cam.height };
		return run_frames(o, sz, &fr, resolved, err);
	}
	for (int si = 0; si < o->nsizes; si++) {
		struct dao_camera cam;
		uint16_t *depth = NULL;
		const struct size sz = o->sizes[si];
		int r = make_frame(sz, &cam, &depth, err);
		if (r)
			return r;
		const struct dao_frame f = { .format = DAO_PIXFMT_DEPTH16, .width = (uint32_t)sz.w,
					     .height = (uint32_t)sz.h, .stride = 2 * sz.w,
					     .data = depth, .depth_unit = 0.001f };
		const struct frames fr = { &cam, &f, 1, 0, NULL };
		r = run_frames(o, sz, &fr, resolved, err);
		free(depth);
		if (r)
			return r;
	}
	return 0;
}

int cmd_bench(int argc, char **argv)
{
	struct bench_options o;
	int r = parse_options(argc, argv, &o);
	if (r)
		return r < 0 ? 0 : r;
	if (o.cmp.nothers || o.cmp.nparams)
		return bench_compare(&o.cmp);
	const int resolved = o.simd == DAO_SIMD_AUTO ? (int)dao_simd_best() : o.simd;
	struct bench_input in = { 0 };
	if (o.in.po.input && (r = bench_input_load(&o.in, &in)))
		return r;
	if (!o.json)
		print_header(&o, &in, resolved);
	struct dao_error err = { 0 };
	r = run_all(&o, &in, resolved, &err);
	bench_input_free(&in);
	if (r) {
		fprintf(stderr, "depthao bench: %s\n", err.message);
		return 1;
	}
	return 0;
}
