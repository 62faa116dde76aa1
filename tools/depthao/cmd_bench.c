/* SPDX-License-Identifier: MIT */
/*
 * depthao bench: time the whole per-frame pipeline (process + shade) and each
 * stage on synthetic frames, for sizes x quality presets x thread counts, and
 * compare with the scalar reference kernels at the same settings.
 */
#include <errno.h>
#include <json-c/json.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <depthao/depthao.h>

#include "cli_params.h"
#include "commands.h"
#include "core/error_internal.h"
#include "synth/synth.h"

#define MAX_SIZES 8
#define MAX_QUALITIES 8
#define MAX_THREADS 4

struct size {
	int w, h;
};

struct config {
	struct size size;
	const char *quality;  /* preset name, or "custom" */
	struct dao_params params;
	int threads;
};

struct stats {
	double median, p95;
	double stage[8]; /* medians: decode noise prefilter normals gtao denoise output shade */
	int iterations;
};

static const char *const stage_names[] = { "decode", "noise", "prefilter", "normals", "gtao",
					    "denoise", "output", "shade" };
#define NSTAGES 8

static void usage(FILE *out)
{
	fprintf(out,
		"usage: depthao bench [options]\n"
		"\n"
		"Times the per-frame pipeline (dao_context_process with 16-bit AO output, then\n"
		"dao_context_shade to RGB) and each of its stages on a synthetic 16-bit depth\n"
		"frame (the \"boxes\" scene with Kinect-like noise), for every size x quality x\n"
		"thread count, after a warm-up.  Prints the median and 95th percentile per frame,\n"
		"megapixels per second, and the speedup over the scalar reference kernels\n"
		"(simd=reference) at the same settings.\n"
		"\n"
		"  --size WxH          one frame size (default: 320x240, 640x480, 1280x720)\n"
		"  --quality Q         low, medium, high, ultra, default (= what `depthao process`\n"
		"                      uses), or all (default: all presets)\n"
		"  --slices N          override the preset's slices\n"
		"  --steps N           override the preset's steps per side\n"
		"  --threads N         one thread count (default: 1 and every CPU)\n"
		"  --simd S            kernels to time: auto (default), generic, sse4.1, avx2,\n"
		"                      avx512\n"
		"  --min-time S        time each configuration for at least S seconds (default 0.5)\n"
		"  --min-iterations N  and at least N frames (default 30)\n"
		"  --no-reference      skip the (slow) reference runs and the speedup column\n"
		"  --json              one JSON object per configuration and line, no table\n"
		"  --help              this text\n"
		"\n"
		"Any other algorithm parameter can be set as in `depthao process` (--radius ...).\n");
}

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
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
static int run(const struct config *c, const struct dao_camera *cam, const uint16_t *depth,
	       int simd, int min_iter, double min_time, int max_iter, struct stats *st,
	       struct dao_error *err)
{
	struct dao_params p = c->params;
	p.threads = c->threads;
	p.simd = simd;
	struct dao_context *ctx;
	int r = dao_context_create(&ctx, cam, &p, err);
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
	struct dao_frame in = { .format = DAO_PIXFMT_DEPTH16, .width = (uint32_t)c->size.w,
				.height = (uint32_t)c->size.h, .stride = 2 * c->size.w,
				.data = (void *)depth, .depth_unit = 0.001f };
	struct dao_frame ao = { .format = DAO_PIXFMT_GRAY16, .width = in.width, .height = in.height,
				.stride = 2 * c->size.w, .data = ao16 };
	struct dao_frame sh = { .format = DAO_PIXFMT_RGB24, .width = in.width, .height = in.height,
				.stride = 3 * c->size.w, .data = rgb };
	/* warm-up: caches, page faults, the pool's threads */
	const int warm = simd == DAO_SIMD_REFERENCE ? 1 : 3;
	int n = 0;
	const double start = now_s();
	for (int i = -warm; i < max_iter; i++) {
		double t0 = now_s();
		r = dao_context_process(ctx, &in, NULL, (uint64_t)(i + warm), &ao, err);
		if (!r)
			r = dao_context_shade(ctx, &sh, err);
		if (r)
			goto out;
		double t1 = now_s();
		if (i < 0)
			continue;
		struct dao_timings tm;
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
	json_object_object_add(o, "slices", json_object_new_int(c->params.slices));
	json_object_object_add(o, "steps", json_object_new_int(c->params.steps));
	json_object_object_add(o, "threads", json_object_new_int(c->threads));
	json_object_object_add(o, "simd", json_object_new_string(dao_simd_name(simd)));
	json_object_object_add(o, "iterations", json_object_new_int(st->iterations));
	json_object_object_add(o, "median_ms", json_object_new_double(st->median));
	json_object_object_add(o, "p95_ms", json_object_new_double(st->p95));
	json_object_object_add(o, "mpix_per_s",
			       json_object_new_double((double)c->size.w * c->size.h / st->median / 1e3));
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
	char size[24], q[32], sp[16] = "-", rm[16] = "-";
	snprintf(size, sizeof size, "%dx%d", c->size.w, c->size.h);
	snprintf(q, sizeof q, "%s %dx%d", c->quality, c->params.slices, c->params.steps);
	if (ref) {
		snprintf(rm, sizeof rm, "%.0f", ref->median);
		snprintf(sp, sizeof sp, "%.0fx", ref->median / st->median);
	}
	printf("%-10s %-15s %2d %8.2f %8.2f %8.1f %8s %7s |", size, q, c->threads, st->median,
	       st->p95, (double)c->size.w * c->size.h / st->median / 1e3, rm, sp);
	for (int k = 0; k < NSTAGES; k++)
		printf(" %6.2f", st->stage[k]);
	putchar('\n');
	fflush(stdout);
}

int cmd_bench(int argc, char **argv)
{
	struct size sizes[MAX_SIZES] = { { 320, 240 }, { 640, 480 }, { 1280, 720 } };
	int nsizes = 3, size_given = 0;
	const char *qnames[MAX_QUALITIES];
	int nq = 0;
	int threads[MAX_THREADS], nthreads = 0;
	int json = 0, no_ref = 0, min_iter = 30;
	double min_time = 0.5;
	struct dao_params over; /* parameter options are recorded against a sentinel */
	dao_params_init(&over, DAO_QUALITY_DEFAULT);
	const char *param_args[64];
	int nparam = 0;
	int slices = 0, steps = 0, simd = DAO_SIMD_AUTO;
	struct dao_error err = { 0 };

	for (int i = 1; i < argc; i++) {
		const char *a = argv[i];
		const char *v = i + 1 < argc ? argv[i + 1] : NULL;
		if (!strcmp(a, "--help")) {
			usage(stdout);
			return 0;
		} else if (!strcmp(a, "--json")) {
			json = 1;
		} else if (!strcmp(a, "--no-reference")) {
			no_ref = 1;
		} else if (!strcmp(a, "--size")) {
			if (!v || parse_size(v, &sizes[0]))
				return usage_error("bench", "--size needs WxH, e.g. 640x480 (16..16384)");
			if (!size_given)
				nsizes = 0;
			if (nsizes == MAX_SIZES)
				return usage_error("bench", "at most %d --size options", MAX_SIZES);
			parse_size(v, &sizes[nsizes++]);
			size_given = 1;
			i++;
		} else if (!strcmp(a, "--quality")) {
			enum dao_quality q;
			if (!v)
				return usage_error("bench", "--quality needs a value");
			if (strcmp(v, "all") && dao_quality_parse(v, &q, &err))
				return usage_error("bench", "%s", err.message);
			if (nq == MAX_QUALITIES)
				return usage_error("bench", "too many --quality options");
			qnames[nq++] = v;
			i++;
		} else if (!strcmp(a, "--threads")) {
			char *end;
			long n = v ? strtol(v, &end, 10) : -1;
			if (!v || *end || n < 1 || n > 256)
				return usage_error("bench", "--threads needs a count from 1 to 256");
			if (nthreads == MAX_THREADS)
				return usage_error("bench", "at most %d --threads options", MAX_THREADS);
			threads[nthreads++] = (int)n;
			i++;
		} else if (!strcmp(a, "--min-time") || !strcmp(a, "--min-iterations")) {
			char *end;
			double n = v ? strtod(v, &end) : -1;
			if (!v || *end || n < 0 || n > 3600)
				return usage_error("bench", "%s needs a number from 0 to 3600", a);
			if (a[6] == 't')
				min_time = n;
			else
				min_iter = n < 1 ? 1 : (int)n;
			i++;
		} else {
			char msg[256];
			int j = i;
			int r = cli_apply_param_option(&over, argc, argv, &j, msg, sizeof msg);
			if (r < 0)
				return usage_error("bench", "%s", msg);
			if (r == 0)
				return usage_error("bench", "unknown option '%s'", a);
			if (nparam + (j - i + 1) > 64)
				return usage_error("bench", "too many parameter options");
			for (int k = i; k <= j; k++)
				param_args[nparam++] = argv[k];
			i = j;
		}
	}
	/* --slices, --steps, --threads and --simd given as parameter options */
	struct dao_params def;
	dao_params_init(&def, DAO_QUALITY_DEFAULT);
	if (over.slices != def.slices)
		slices = over.slices;
	if (over.steps != def.steps)
		steps = over.steps;
	if (over.threads != def.threads && nthreads < MAX_THREADS)
		threads[nthreads++] = over.threads;
	simd = over.simd;
	if (simd == DAO_SIMD_REFERENCE)
		return usage_error("bench", "--simd reference is what the speedup compares with; "
				   "pick auto, generic, sse4.1 or avx2");
	if (!dao_simd_supported((enum dao_simd)simd))
		return usage_error("bench", "--simd %s: this CPU or build cannot run it",
				   dao_simd_name((enum dao_simd)simd));
	int resolved = simd == DAO_SIMD_AUTO ? (int)dao_simd_best() : simd;
	if (nq == 0 || (nq == 1 && !strcmp(qnames[0], "all"))) {
		nq = 0;
		for (int q = 0; q < DAO_QUALITY_COUNT; q++)
			qnames[nq++] = dao_quality_name((enum dao_quality)q);
	}
	const int ncpu = dao_cpu_count();
	if (nthreads == 0) {
		threads[nthreads++] = 1;
		if (ncpu > 1)
			threads[nthreads++] = ncpu;
	}

	char model[128];
	dao_cpu_model(model, sizeof model);
	if (!json) {
		printf("depthao %s bench: %s, %d CPUs, kernels %s%s\n", dao_version(), model, ncpu,
		       dao_simd_name((enum dao_simd)resolved), simd == DAO_SIMD_AUTO ? " (auto)" : "");
		printf("frame = dao_context_process (depth16 in, gray16 AO out) + dao_context_shade "
		       "(RGB); synthetic \"boxes\" scene with sensor noise\n");
		printf("times in ms per frame; ref = scalar reference kernels (simd=reference), same "
		       "settings\n\n");
		printf("%-10s %-15s %2s %8s %8s %8s %8s %7s |", "size", "quality", "th", "median",
		       "p95", "Mpix/s", "ref", "speedup");
		for (int k = 0; k < NSTAGES; k++)
			printf(" %6.6s", stage_names[k]);
		putchar('\n');
	}

	for (int si = 0; si < nsizes; si++) {
		struct dao_camera cam;
		uint16_t *depth = NULL;
		int r = make_frame(sizes[si], &cam, &depth, &err);
		if (r) {
			fprintf(stderr, "depthao bench: %s\n", err.message);
			return 1;
		}
		for (int qi = 0; qi < nq; qi++) {
			struct config c = { .size = sizes[si] };
			enum dao_quality q;
			dao_quality_parse(qnames[qi], &q, NULL);
			dao_params_init(&c.params, q);
			c.quality = dao_quality_name(q);
			if (!strcmp(qnames[qi], "default"))
				c.quality = "default";
			/* the user's parameter options on top of the preset */
			for (int k = 0; k < nparam;) {
				char msg[256];
				int j = k;
				cli_apply_param_option(&c.params, nparam, (char **)param_args, &j, msg,
						       sizeof msg);
				k = j + 1;
			}
			if (slices || steps)
				c.quality = "custom";
			r = dao_params_validate(&c.params, &err);
			for (int ti = 0; !r && ti < nthreads; ti++) {
				c.threads = threads[ti];
				struct stats st, ref;
				r = run(&c, &cam, depth, simd, min_iter, min_time, 100000, &st, &err);
				if (!r && !no_ref)
					r = run(&c, &cam, depth, DAO_SIMD_REFERENCE, 3, 0.0, 3, &ref, &err);
				if (r)
					break;
				if (json)
					print_json(&c, resolved, &st, no_ref ? NULL : &ref);
				else
					print_row(&c, &st, no_ref ? NULL : &ref);
			}
			if (r) {
				free(depth);
				fprintf(stderr, "depthao bench: %s\n", err.message);
				return 1;
			}
		}
		free(depth);
	}
	return 0;
}
