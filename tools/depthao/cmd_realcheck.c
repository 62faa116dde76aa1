/* SPDX-License-Identifier: MIT */
/*
 * depthao realcheck: the real sensor frames of ../shared/data through the
 * AO pipeline, scored where the truth is known without a ground truth: on
 * open planar regions (open_planes.h) the true visibility is 1, so the mean
 * of 1 - visibility there is false occlusion, per frame.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

#include "cli_params.h"
#include "commands.h"
#include "file_list.h"
#include "process.h"
#include "synth/open_planes.h"
#include "synth/real_frames.h"
#include "synth/robust.h"

#define MAX_SELECTED 64

static void usage(FILE *out)
{
	struct dao_params defaults;
	dao_params_init(&defaults, DAO_QUALITY_DEFAULT);
	int n;
	const struct synth_real_frame *frames = synth_real_frames(&n);
	fprintf(out,
		"usage: depthao realcheck [--data DIR] [--frames LIST] [--quality Q] [--masks-out DIR]\n"
		"                         [AO parameter options]\n"
		"\n"
		"Runs the AO on the real sensor frames of the data directory and reports, per frame,\n"
		"the false occlusion on its open planar regions: pixels of planes found by RANSAC\n"
		"with nothing in front of the plane within the AO radius, whose true visibility is\n"
		"1 up to what the camera cannot see.  Mean false occlusion = mean of 1 - visibility\n"
		"there; also its 90th percentile and the share of those pixels darker than 0.9.\n"
		"\n"
		"  --data DIR        the data (default $DAO_SHARED_DATA, else ../shared/data)\n"
		"  --frames LIST     comma-separated frame names (default: all):");
	for (int i = 0; i < n; i++)
		fprintf(out, "%s%s", i % 6 ? " " : "\n                      ", frames[i].name);
	fprintf(out,
		"\n"
		"  --quality Q       preset (default medium); parameter options override it\n"
		"  --masks-out DIR   write NAME-mask.png (255 = open planar) and NAME-ao.png\n"
		"  --help            this text\n"
		"The AO radius (--radius, default 0.5 m) is also the radius of the open regions.\n"
		"\nAO parameters:\n");
	cli_print_param_help(out, &defaults);
}

struct frame_result {
	const struct synth_real_frame *f;
	long open_px;
	double mean, p90, dark;
};

static int write_outputs(const char *dir, const char *name, const uint8_t *mask, const float *ao,
			 uint32_t w, uint32_t h)
{
	char file[256];
	struct dao_frame m = { 0 }, a = { 0 };
	struct dao_error err;
	int r = dao_frame_alloc(&m, DAO_PIXFMT_GRAY8, w, h, &err) ||
		dao_frame_alloc(&a, DAO_PIXFMT_GRAY8, w, h, &err);
	if (!r) {
		for (size_t i = 0; i < (size_t)w * h; i++) {
			((uint8_t *)m.data)[i] = mask[i] ? 255 : 0;
			((uint8_t *)a.data)[i] = (uint8_t)lrintf(255.0f * ao[i]);
		}
		snprintf(file, sizeof file, "%s-mask.png", name);
		char *p = path_join(dir, file);
		r = !p || dao_png_write(p, &m, &err);
		free(p);
		snprintf(file, sizeof file, "%s-ao.png", name);
		p = r ? NULL : path_join(dir, file);
		r = r || !p || dao_png_write(p, &a, &err);
		free(p);
		if (r)
			fprintf(stderr, "depthao: %s\n", err.message);
	}
	dao_frame_free(&m);
	dao_frame_free(&a);
	return r;
}

static int check_frame(const struct synth_real_frame *f, const char *dir, const struct dao_params *p,
		       const char *masks_out, struct frame_result *res)
{
	float *z = NULL, *ao = NULL, *occ = NULL;
	uint8_t *mask = NULL;
	struct dao_context *ctx = NULL;
	struct dao_camera cam;
	struct dao_error err = { 0 };
	double unit;
	int status = 1;
	if (synth_real_frame_load(f, dir, &z, &cam, &unit, &err)) {
		fprintf(stderr, "depthao: %s\n", err.message);
		return 1;
	}
	const uint32_t w = cam.width, h = cam.height;
	const size_t np = (size_t)w * h;
	ao = malloc(np * sizeof(float));
	occ = malloc(np * sizeof(float));
	mask = malloc(np);
	if (!ao || !occ || !mask) {
		fprintf(stderr, "depthao: out of memory\n");
		goto out;
	}
	long open_px;
	struct dao_frame in = { .format = DAO_PIXFMT_DEPTH_F32, .width = w, .height = h,
			.stride = (int32_t)(w * 4), .data = z};
	struct dao_frame out = { .format = DAO_PIXFMT_GRAY_F32, .width = w, .height = h,
			.stride = (int32_t)(w * 4), .data = ao};
	if (synth_open_planes(z, &cam, unit, p->radius, mask, &open_px, &err) ||
	    dao_context_create(&ctx, &cam, p, &err) ||
	    dao_context_process(ctx, &in, NULL, 0, &out, &err)) {
		fprintf(stderr, "depthao: %s: %s\n", f->name, err.message);
		goto out;
	}
	size_t n = 0;
	double sum = 0;
	long dark = 0;
	for (size_t i = 0; i < np; i++)
		if (mask[i]) {
			occ[n++] = 1.0f - ao[i];
			sum += 1.0 - ao[i];
			dark += ao[i] < 0.9f;
		}
	res->f = f;
	res->open_px = open_px;
	res->mean = n ? sum / (double)n : 0.0;
	res->dark = n ? (double)dark / (double)n : 0.0;
	res->p90 = n ? synth_select(occ, n, (size_t)((double)(n - 1) * 0.9)) : 0.0;
	status = masks_out ? write_outputs(masks_out, f->name, mask, ao, w, h) : 0;
out:
	dao_context_destroy(ctx);
	free(z);
	free(ao);
	free(occ);
	free(mask);
	return status;
}

struct realcheck_options {
	const char *dir, *masks_out, *list;
	enum dao_quality q;
	char *overrides[128];   /* the parameter options, as given */
	int noverride;
};

/* The options into o: -1 to go on, else the exit status (0 after --help). */
static int parse_args(int argc, char **argv, struct realcheck_options *o)
{
	*o = (struct realcheck_options){ .q = DAO_QUALITY_DEFAULT };
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i];
		if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
			usage(stdout);
			return 0;
		}
		if (!strcmp(a, "--data") || !strcmp(a, "--frames") || !strcmp(a, "--masks-out") ||
		    !strcmp(a, "--quality")) {
			if (i + 1 >= argc)
				return usage_error("realcheck", "%s needs a value", a);
			const char *v = argv[++i];
			if (!strcmp(a, "--data")) {
				o->dir = v;
			} else if (!strcmp(a, "--frames")) {
				o->list = v;
			} else if (!strcmp(a, "--masks-out")) {
				o->masks_out = v;
			} else {
				struct dao_error err;
				if (dao_quality_parse(v, &o->q, &err))
					return usage_error("realcheck", "%s", err.message);
			}
			continue;
		}
		/* parameter options: checked now, applied over the preset later */
		struct dao_params scratch;
		dao_params_init(&scratch, DAO_QUALITY_DEFAULT);
		char msg[DAO_ERROR_MESSAGE_MAX];
		int j = i, r = cli_apply_param_option(&scratch, argc, argv, &j, msg, sizeof msg);
		if (r < 0)
			return usage_error("realcheck", "%s", msg);
		if (r == 0)
			return usage_error("realcheck", "unknown option '%s'", a);
		for (int k = i; k <= j && o->noverride < 128; k++)
			o->overrides[o->noverride++] = argv[k];
		i = j;
	}
	return -1;
}

/* The preset with the parameter options over it: 0 or the exit status. */
static int make_params(const struct realcheck_options *o, struct dao_params *p)
{
	dao_params_init(p, o->q);
	char *args[130];
	args[0] = "realcheck";
	for (int k = 0; k < o->noverride; k++)
		args[k + 1] = o->overrides[k];
	char msg[DAO_ERROR_MESSAGE_MAX];
	for (int k = 1; k <= o->noverride; k++)
		if (cli_apply_param_option(p, o->noverride + 1, args, &k, msg, sizeof msg) < 0)
			return usage_error("realcheck", "%s", msg);
	struct dao_error err;
	if (dao_params_validate(p, &err))
		return usage_error("realcheck", "%s", err.message);
	return 0;
}

/* The indices of the frames named in list (all if NULL) into selected: 0 or the exit status. */
static int select_frames(const char *list, const struct synth_real_frame *frames, int n,
			 int selected[MAX_SELECTED], int *ns)
{
	*ns = 0;
	if (!list) {
		for (int k = 0; k < n && k < MAX_SELECTED; k++)
			selected[(*ns)++] = k;
		return 0;
	}
	char buf[1024];
	snprintf(buf, sizeof buf, "%s", list);
	char *save = NULL;
	for (char *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
		int k;
		for (k = 0; k < n && strcmp(frames[k].name, tok); k++)
			;
		if (k == n)
			return usage_error("realcheck", "unknown frame '%s'", tok);
		if (*ns < MAX_SELECTED)
			selected[(*ns)++] = k;
	}
	return 0;
}

/* Checks the selected frames, a table row each, then the means: the exit status. */
static int report_frames(const struct synth_real_frame *frames, const int *selected, int ns,
			 const struct realcheck_options *o, const struct dao_params *p)
{
	struct frame_result res[MAX_SELECTED];
	printf("| frame | sensor | open planar px | mean false occlusion | p90 | share < 0.9 |\n");
	printf("|---|---|---:|---:|---:|---:|\n");
	double sum = 0, sum_sl = 0;
	int n_sl = 0, nm = 0;
	for (int k = 0; k < ns; k++) {
		if (check_frame(&frames[selected[k]], o->dir, p, o->masks_out, &res[k]))
			return 1;
		const struct frame_result *r = &res[k];
		if (!r->open_px) {
			printf("| %s | %s | 0 | no open planar region at R = %g m | | |\n", r->f->name,
			       r->f->sensor, p->radius);
			continue;
		}
		printf("| %s | %s | %ld | %.4f | %.3f | %.1f %% |\n", r->f->name, r->f->sensor,
		       r->open_px, r->mean, r->p90, 100.0 * r->dark);
		fflush(stdout);
		sum += r->mean;
		nm++;
		if (r->f->model == SYNTH_SENSOR_STRUCTURED_LIGHT)
			sum_sl += r->mean, n_sl++;
	}
	if (nm)
		printf("| **mean of the frames with open regions** | | | **%.4f** | | |\n", sum / nm);
	if (n_sl && n_sl < nm)
		printf("| **mean of those from structured light** | | | **%.4f** | | |\n", sum_sl / n_sl);
	return 0;
}

int cmd_realcheck(int argc, char **argv)
{
	struct realcheck_options o;
	struct dao_params p;
	int status = parse_args(argc, argv, &o);
	if (status >= 0)
		return status;
	if ((status = make_params(&o, &p)))
		return status;
	int n, selected[MAX_SELECTED], ns;
	const struct synth_real_frame *frames = synth_real_frames(&n);
	if ((status = select_frames(o.list, frames, n, selected, &ns)))
		return status;
	if (!o.dir)
		o.dir = synth_real_data_dir();
	if (o.masks_out && process_ensure_dir(o.masks_out))
		return 1;
	return report_frames(frames, selected, ns, &o, &p);
}
