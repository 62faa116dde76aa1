/* SPDX-License-Identifier: MIT */
/*
 * depthao eval: renders the synthetic suite with ray-traced ground truth,
 * feeds each scene to the library as each simulated sensor delivers it
 * (clean, Gaussian noise, structured light, ...), runs each quality preset,
 * and prints scene x preset (MAE, bias, p99) for the tune or the held-out
 * family of scenes.  With --check it also enforces the accuracy bars of the
 * default preset (used by the test suite).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/depthao.h>

#include "cli_params.h"
#include "commands.h"
#include "eval_depth.h"
#include "eval_sequence.h"
#include "synth/suite.h"

/* Accuracy bars for the default preset at R = 0.5 m (docs/accuracy.md, issue #2). */
#define BAR_PLANE_OCCLUSION 0.003
#define BAR_CLEAN_MEAN_MAE 0.035
#define BAR_CLEAN_MAX_MAE 0.075
#define BAR_NOISY_MAX_MAE 0.06
/* issue #15: the tilted plane as structured light delivers it (with structured-light in
 * --sensors; the defaults with the noise measured in the frame: 0.0043, before 0.0553) */
#define BAR_SL_PLANE_OCCLUSION 0.005

/* Targets of issue #15 (reported; --check enforces the plane's, BAR_SL_PLANE_OCCLUSION). */
#define TARGET_SL_MEAN_MAE 0.035
#define TARGET_SL_PLANE_OCCLUSION 0.005
#define TARGET_CLEAN_MEAN_MAE 0.0275

#define EVAL_MAX_ALGORITHMS 4
#define EVAL_MAX_COLUMNS (DAO_QUALITY_COUNT * EVAL_MAX_ALGORITHMS)

struct eval_options {
	enum dao_quality qualities[DAO_QUALITY_COUNT];
	int nq;
	int algorithms[EVAL_MAX_ALGORITHMS]; /* enum dao_algorithm */
	char *algorithm_params[EVAL_MAX_ALGORITHMS]; /* "PARAM=VALUE[:...]" of each, or NULL */
	int na;
	const char *scenes[SYNTH_SUITE_MAX_IMAGES + 1];
	int rays_sqrt;
	int check;
	enum synth_sensor sensors[SYNTH_SENSOR_COUNT];
	int nsensors;
	enum synth_set set;
	int variants;
	struct dao_params overrides_base;   /* the defaults, to detect overridden fields */
	char *override_args[64];
	int n_override;
};

static void usage(FILE *out)
{
	fprintf(out,
		"usage: depthao eval [options] [parameter options]\n"
		"\n"
		"Renders the synthetic scenes (640x480, ray-traced ground truth), feeds them to the\n"
		"library as each sensor delivers them, runs each quality preset, and prints MAE,\n"
		"bias and p99 of the visibility against the ground truth of the clean geometry,\n"
		"over the pixels where the sensor delivered depth.\n"
		"\n"
		"  --quality LIST    comma-separated presets (default: low,medium,high)\n"
		"  --algorithms LIST comma-separated algorithms: gtao (default), vbao, hbao, ssao, edl;\n"
		"                    every algorithm runs every preset; NAME:PARAM=VALUE[:...]\n"
		"                    gives one its own parameters (vbao:vbao-thickness-mode=constant)\n"
		"  --scenes LIST     comma-separated scenes (default: all; the clean mean and the\n"
		"                    bars count the first six; the thickness scenes thin-poles,\n"
		"                    chair, floating-plate, pole-gaps, table-above, pole-widths,\n"
		"                    shelves-below, panels and chair-corner get their own mean)\n"
		"  --rays N          ground-truth rays per pixel, a square (default 256)\n"
		"  --sensors LIST    comma-separated inputs: clean, gaussian (sigma = 0.0012 z^2,\n"
		"                    mm, 2%% holes), structured-light, active-stereo, tof\n"
		"                    (default: clean,gaussian,structured-light; see 'depthao synth')\n"
		"  --no-noise        only clean input (the same as --sensors clean)\n"
		"  --set tune|heldout  the scene family: tune (the scenes as written, default) or\n"
		"                    heldout (perturbed camera, objects and walls, other noise\n"
		"                    seeds) to report defaults tuned on the other\n"
		"  --variants N      scene variants per scene from the family (default 1)\n"
		"  --check           exit 1 unless the default preset meets the accuracy bars\n"
		"  --depth           measure the filtered depth instead (depthao eval --depth --help)\n"
		"  --sequence PATH   a depth sequence instead: temporal filters off and on against\n"
		"                    per-frame truth (see 'depthao eval --sequence X --help')\n"
		"  --help            this text\n"
		"Parameter options (e.g. --radius 0.5) override every preset.\n");
}

static int parse_list(char *arg, const char **out, int max)
{
	int n = 0;
	for (char *tok = strtok(arg, ","); tok; tok = strtok(NULL, ",")) {
		if (n >= max)
			return -1;
		out[n++] = tok;
	}
	return n;
}

static int parse_sensors(char *v, struct eval_options *o)
{
	const char *names[SYNTH_SENSOR_COUNT + 1];
	int n = parse_list(v, names, SYNTH_SENSOR_COUNT);
	if (n <= 0)
		return usage_error("eval", "--sensors needs one to %d of clean, gaussian, "
				   "structured-light, active-stereo, tof", SYNTH_SENSOR_COUNT);
	for (int k = 0; k < n; k++) {
		struct dao_error err;
		if (synth_sensor_parse(names[k], &o->sensors[k], &err))
			return usage_error("eval", "%s", err.message);
		for (int m = 0; m < k; m++)
			if (o->sensors[m] == o->sensors[k])
				return usage_error("eval", "--sensors names %s twice", names[k]);
	}
	o->nsensors = n;
	return 0;
}

static int parse_set(char *v, struct eval_options *o)
{
	struct dao_error err;
	if (synth_set_parse(v, &o->set, &err))
		return usage_error("eval", "%s", err.message);
	return 0;
}

static int parse_variants(char *v, struct eval_options *o)
{
	char *end;
	long n = strtol(v, &end, 10);
	if (*end || !*v || n < 1 || n > 16)
		return usage_error("eval", "--variants '%s' must be an integer in 1..16", v);
	o->variants = (int)n;
	return 0;
}

/* NAME[:PARAM=VALUE...] entries: each algorithm and the parameters of its own. */
static int parse_algorithms(char *v, struct eval_options *o)
{
	char *names[EVAL_MAX_ALGORITHMS + 1];
	int n = parse_list(v, (const char **)names, EVAL_MAX_ALGORITHMS);
	if (n <= 0)
		return usage_error("eval", "--algorithms needs one to four of gtao, vbao, hbao, ssao, edl");
	for (int k = 0; k < n; k++) {
		struct dao_params scratch;
		struct dao_error err;
		dao_params_init(&scratch, DAO_QUALITY_DEFAULT);
		char *extra = strchr(names[k], ':');
		if (extra)
			*extra++ = '\0';
		if (dao_params_set(&scratch, "algorithm", names[k], &err))
			return usage_error("eval", "%s", err.message);
		o->algorithms[k] = scratch.algorithm;
		o->algorithm_params[k] = extra;
		if (extra && cli_apply_param_list(extra, &scratch, &err))
			return usage_error("eval", "%s", err.message);
	}
	o->na = n;
	return 0;
}

static int parse_rays(char *v, struct eval_options *o)
{
	char *end;
	long n = strtol(v, &end, 10);
	long r = lrint(sqrt((double)n));
	if (*end || n < 1 || r * r != n || n > 65536)
		return usage_error("eval", "--rays %s must be a perfect square in 1..65536", v);
	o->rays_sqrt = (int)r;
	return 0;
}

static int parse_scenes(char *v, struct eval_options *o)
{
	int n = parse_list(v, o->scenes, SYNTH_SUITE_MAX_IMAGES);
	if (n < 0)
		return usage_error("eval", "too many scenes in --scenes");
	o->scenes[n] = NULL;
	return 0;
}

static int parse_qualities(char *v, struct eval_options *o)
{
	const char *names[DAO_QUALITY_COUNT + 1];
	int n = parse_list(v, names, DAO_QUALITY_COUNT);
	if (n <= 0)
		return usage_error("eval", "--quality needs one to four presets");
	for (int k = 0; k < n; k++) {
		struct dao_error err;
		if (dao_quality_parse(names[k], &o->qualities[k], &err))
			return usage_error("eval", "%s", err.message);
	}
	o->nq = n;
	return 0;
}

/* The options that take a value, each with its parser (0 or the exit status). */
static const struct value_option {
	const char *name;
	int (*parse)(char *v, struct eval_options *o);
} value_options[] = {
	{ "--sensors", parse_sensors },
	{ "--set", parse_set },
	{ "--variants", parse_variants },
	{ "--algorithms", parse_algorithms },
	{ "--quality", parse_qualities },
	{ "--scenes", parse_scenes },
	{ "--rays", parse_rays },
};

static const struct value_option *value_option(const char *name)
{
	for (size_t k = 0; k < sizeof value_options / sizeof value_options[0]; k++)
		if (strcmp(name, value_options[k].name) == 0)
			return &value_options[k];
	return NULL;
}

/* A parameter option at argv[*i], checked and remembered (they are applied per preset later). */
static int remember_override(int argc, char **argv, int *i, struct eval_options *o)
{
	struct dao_params scratch;
	dao_params_init(&scratch, DAO_QUALITY_DEFAULT);
	int j = *i;
	char msg[DAO_ERROR_MESSAGE_MAX];
	int r = cli_apply_param_option(&scratch, argc, argv, &j, msg, sizeof msg);
	if (r < 0)
		return usage_error("eval", "%s", msg);
	if (r == 0)
		return usage_error("eval", "unknown option '%s'", argv[*i]);
	for (int k = *i; k <= j && o->n_override < 64; k++)
		o->override_args[o->n_override++] = argv[k];
	*i = j;
	return 0;
}

static int parse_args(int argc, char **argv, struct eval_options *o)
{
	o->rays_sqrt = 16;
	o->sensors[0] = SYNTH_SENSOR_CLEAN;
	o->sensors[1] = SYNTH_SENSOR_GAUSSIAN;
	o->sensors[2] = SYNTH_SENSOR_STRUCTURED_LIGHT;
	o->nsensors = 3;
	o->set = SYNTH_SET_TUNE;
	o->variants = 1;
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i];
		const struct value_option *vo;
		int r;
		if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
			usage(stdout);
			exit(0);
		} else if (strcmp(a, "--check") == 0) {
			o->check = 1;
		} else if (strcmp(a, "--no-noise") == 0) {
			o->sensors[0] = SYNTH_SENSOR_CLEAN;
			o->nsensors = 1;
		} else if ((vo = value_option(a))) {
			if (i + 1 >= argc)
				return usage_error("eval", "%s needs a value", a);
			if ((r = vo->parse(argv[++i], o)))
				return r;
		} else if (strncmp(a, "--", 2) == 0) {
			if ((r = remember_override(argc, argv, &i, o)))
				return r;
		} else {
			return usage_error("eval", "unexpected argument '%s'", a);
		}
	}
	if (o->nq == 0) {
		o->qualities[0] = DAO_QUALITY_LOW;
		o->qualities[1] = DAO_QUALITY_MEDIUM;
		o->qualities[2] = DAO_QUALITY_HIGH;
		o->nq = 3;
	}
	if (o->na == 0) {
		o->algorithms[0] = -1; /* whatever the presets and --algorithm say (GTAO) */
		o->na = 1;
	}
	return 0;
}

/* Preset q with the command-line overrides applied. */
static int params_for(const struct eval_options *o, enum dao_quality q, struct dao_params *p)
{
	dao_params_init(p, q);
	char *args[66];
	args[0] = "eval";
	for (int k = 0; k < o->n_override; k++)
		args[k + 1] = o->override_args[k];
	char msg[DAO_ERROR_MESSAGE_MAX];
	for (int i = 1; i <= o->n_override; i++)
		if (cli_apply_param_option(p, o->n_override + 1, args, &i, msg, sizeof msg) < 0) {
			fprintf(stderr, "depthao: %s\n", msg);
			return -1;
		}
	struct dao_error err;
	if (dao_params_validate(p, &err)) {
		fprintf(stderr, "depthao: %s\n", err.message);
		return -1;
	}
	return 0;
}

struct preset_summary {
	/* per sensor: the structured scenes (all but the plane) of the foundation set */
	double mae_sum[SYNTH_SENSOR_COUNT], mae_max[SYNTH_SENSOR_COUNT];
	int mae_n[SYNTH_SENSOR_COUNT];
	double plane_occ[SYNTH_SENSOR_COUNT];
	int plane_n[SYNTH_SENSOR_COUNT];
	double ms, thick_sum;
	int frames, thick_n;
	long nan, invalid;
};

static double mean_or_zero(double sum, int n)
{
	return n ? sum / n : 0.0;
}

/* One column of the table: an algorithm (-1: the preset's) at a preset. */
struct eval_column {
	enum dao_quality q;
	int algorithm;
	const char *params;  /* the algorithm's own "PARAM=VALUE[:...]", or NULL */
};

/* A run of the suite: its columns, the results per case and column, their summaries. */
struct eval_run {
	const struct eval_options *o;
	struct eval_column cols[EVAL_MAX_COLUMNS];
	int ncols;
	int default_col;                  /* the default preset's GTAO column, -1: none */
	int have[SYNTH_SENSOR_COUNT];     /* sensors in --sensors */
	struct synth_suite suite;
	struct synth_metrics (*res)[EVAL_MAX_COLUMNS];
	struct preset_summary sum[EVAL_MAX_COLUMNS];
};

/* The columns (one per algorithm and preset) and what --check needs of them; 0 or a usage error. */
static int plan_columns(struct eval_run *run)
{
	const struct eval_options *o = run->o;
	for (int a = 0; a < o->na; a++)
		for (int q = 0; q < o->nq; q++)
			run->cols[run->ncols++] = (struct eval_column){ o->qualities[q], o->algorithms[a],
									o->algorithm_params[a] };
	run->default_col = -1;
	for (int k = 0; k < run->ncols; k++)
		if (run->cols[k].q == DAO_QUALITY_DEFAULT && run->cols[k].algorithm <= DAO_ALGORITHM_GTAO &&
		    !run->cols[k].params && run->default_col < 0)
			run->default_col = k;
	if (o->check && run->default_col < 0)
		return usage_error("eval", "--check needs the default preset in --quality");
	for (int k = 0; k < o->nsensors; k++)
		run->have[o->sensors[k]] = 1;
	/* the bars of --check are about clean and Gaussian input */
	if (o->check && !run->have[SYNTH_SENSOR_CLEAN])
		return usage_error("eval", "--check needs clean in --sensors");
	return 0;
}

/* Adds the metrics of case c to the summary of its column. */
static void summarise(struct preset_summary *s, const struct synth_case *c,
		      const struct synth_metrics *m, double ms)
{
	const enum synth_sensor sn = c->sensor;
	s->ms += ms;
	s->frames++;
	s->nan += m->nan_count;
	s->invalid += m->invalid_not_one;
	if (!synth_scene_is_foundation(c->scene)) {
		if (sn == SYNTH_SENSOR_CLEAN) {
			s->thick_sum += m->mae;
			s->thick_n++;
		}
	} else if (!synth_scene_is_structured(c->scene)) {
		s->plane_occ[sn] += m->mean_occlusion;
		s->plane_n[sn]++;
	} else {
		s->mae_sum[sn] += m->mae;
		s->mae_n[sn]++;
		s->mae_max[sn] = fmax(s->mae_max[sn], m->mae);
	}
}

/* Every case through every column; 0, or the exit status after a message. */
static int run_columns(struct eval_run *run, float *ao)
{
	struct dao_error err;
	for (int k = 0; k < run->ncols; k++) {
		struct dao_params p;
		struct dao_context *ctx;
		if (params_for(run->o, run->cols[k].q, &p))
			return 2;
		if (run->cols[k].algorithm >= 0)
			p.algorithm = run->cols[k].algorithm;
		if (run->cols[k].params &&
		    (cli_apply_param_list(run->cols[k].params, &p, &err) ||
		     dao_params_validate(&p, &err))) {
			fprintf(stderr, "depthao: %s\n", err.message);
			return 1;
		}
		if (dao_context_create(&ctx, &run->suite.cam, &p, &err)) {
			fprintf(stderr, "depthao: %s\n", err.message);
			return 1;
		}
		for (int i = 0; i < run->suite.count; i++) {
			double ms;
			if (synth_suite_run_case(&run->suite, i, ctx, ao, &run->res[i][k], &ms, &err)) {
				fprintf(stderr, "depthao: %s\n", err.message);
				dao_context_destroy(ctx);
				return 1;
			}
			summarise(&run->sum[k], &run->suite.cases[i], &run->res[i][k], ms);
		}
		dao_context_destroy(ctx);
	}
	return 0;
}

/* The table: a row per case, then the means per sensor, thickness scenes, plane, time. */
static void print_table(const struct eval_run *run)
{
	const struct eval_options *o = run->o;
	const int ncols = run->ncols;
	const struct preset_summary *sum = run->sum;
	printf("| scene | input |");
	for (int k = 0; k < ncols; k++) {
		char alg[300] = "";
		if (o->na > 1 || run->cols[k].algorithm > 0) {
			struct dao_params p;
			dao_params_init(&p, DAO_QUALITY_DEFAULT);
			p.algorithm = run->cols[k].algorithm < 0 ? 0 : run->cols[k].algorithm;
			dao_params_get(&p, "algorithm", alg, 32, NULL);
			size_t l = strlen(alg);
			snprintf(alg + l, sizeof alg - l, "%s%s ", run->cols[k].params ? ":" : "",
				 run->cols[k].params ? run->cols[k].params : "");
		}
		printf(" %s%s%s MAE | bias | p99 |", alg, dao_quality_name(run->cols[k].q),
		       k == run->default_col ? " (default)" : "");
	}
	printf("\n|---|---|");
	for (int k = 0; k < ncols; k++)
		printf("---:|---:|---:|");
	printf("\n");
	for (int i = 0; i < run->suite.count; i++) {
		const struct synth_case *c = &run->suite.cases[i];
		if (c->variant)
			printf("| %s #%d | %s |", c->scene, c->variant, synth_sensor_name(c->sensor));
		else
			printf("| %s | %s |", c->scene, synth_sensor_name(c->sensor));
		for (int k = 0; k < ncols; k++)
			printf(" %.4f | %+.4f | %.3f |", run->res[i][k].mae, run->res[i][k].bias,
			       run->res[i][k].p99);
		printf("\n");
	}
	for (int k2 = 0; k2 < o->nsensors; k2++) {
		const enum synth_sensor sn = o->sensors[k2];
		printf("| **%s scenes, mean MAE** | |", sn == SYNTH_SENSOR_CLEAN ? "clean" : synth_sensor_name(sn));
		for (int k = 0; k < ncols; k++)
			printf(" **%.4f** | | |", mean_or_zero(sum[k].mae_sum[sn], sum[k].mae_n[sn]));
		printf("\n");
		if (sn != SYNTH_SENSOR_CLEAN) {
			printf("| %s scenes, largest MAE | |", synth_sensor_name(sn));
			for (int k = 0; k < ncols; k++)
				printf(" %.4f | | |", sum[k].mae_max[sn]);
			printf("\n");
		}
	}
	int any_thick = 0;
	for (int k = 0; k < ncols; k++)
		any_thick |= sum[k].thick_n > 0;
	if (any_thick) {
		printf("| **thickness scenes, mean MAE** | clean |");
		for (int k = 0; k < ncols; k++)
			printf(" **%.4f** | | |", mean_or_zero(sum[k].thick_sum, sum[k].thick_n));
		printf("\n");
	}
	for (int k2 = 0; k2 < o->nsensors; k2++) {
		const enum synth_sensor sn = o->sensors[k2];
		if (!sum[0].plane_n[sn])
			continue;
		printf("| plane, mean occlusion | %s |", synth_sensor_name(sn));
		for (int k = 0; k < ncols; k++)
			printf(" %.4f | | |", mean_or_zero(sum[k].plane_occ[sn], sum[k].plane_n[sn]));
		printf("\n");
	}
	printf("| ms/frame (all threads) | |");
	for (int k = 0; k < ncols; k++)
		printf(" %.0f | | |", sum[k].frames ? sum[k].ms / sum[k].frames : 0.0);
	printf("\n");
}

/* Issue #15's targets for the default preset, as measured (only the plane's is enforced). */
static void print_targets(const struct eval_run *run)
{
	if (run->default_col < 0)
		return;
	const struct preset_summary *d = &run->sum[run->default_col];
	const enum synth_sensor sl = SYNTH_SENSOR_STRUCTURED_LIGHT;
	const char *sep = "";
	printf("\nTargets (issue #15, default preset, %s set):", synth_set_name(run->o->set));
	if (run->have[sl] && d->mae_n[sl]) {
		printf("%s structured-light mean MAE %.4f (target <= %.3f)", sep,
		       mean_or_zero(d->mae_sum[sl], d->mae_n[sl]), TARGET_SL_MEAN_MAE);
		sep = ";";
	}
	if (run->have[sl] && d->plane_n[sl]) {
		printf("%s tilted plane under structured light, mean occlusion %.4f (target <= %.3f)",
		       sep, mean_or_zero(d->plane_occ[sl], d->plane_n[sl]), TARGET_SL_PLANE_OCCLUSION);
		sep = ";";
	}
	if (run->have[SYNTH_SENSOR_CLEAN] && d->mae_n[SYNTH_SENSOR_CLEAN])
		printf("%s clean mean MAE %.4f (target <= %.4f)", sep,
		       mean_or_zero(d->mae_sum[SYNTH_SENSOR_CLEAN], d->mae_n[SYNTH_SENSOR_CLEAN]),
		       TARGET_CLEAN_MEAN_MAE);
	printf("\n");
}

/* NaN or out-of-range output, and with --check the accuracy bars; 0 if all hold, else 1. */
static int check_results(const struct eval_run *run)
{
	int status = 0;
	for (int k = 0; k < run->ncols; k++)
		if (run->sum[k].nan || run->sum[k].invalid) {
			fprintf(stderr, "depthao: %s: %ld NaN/out-of-range values, %ld no-data pixels not 1\n",
				dao_quality_name(run->cols[k].q), run->sum[k].nan, run->sum[k].invalid);
			status = 1;
		}
	if (!run->o->check)
		return status;
	const struct preset_summary *s = &run->sum[run->default_col];
	const enum synth_sensor c = SYNTH_SENSOR_CLEAN, g = SYNTH_SENSOR_GAUSSIAN;
	const enum synth_sensor sl = SYNTH_SENSOR_STRUCTURED_LIGHT;
	struct {
		const char *what;
		double value, bar;
		int present;
	} bars[] = {
		{ "tilted plane, mean occlusion", mean_or_zero(s->plane_occ[c], s->plane_n[c]),
		  BAR_PLANE_OCCLUSION, 1 },
		{ "clean scenes, mean MAE", mean_or_zero(s->mae_sum[c], s->mae_n[c]),
		  BAR_CLEAN_MEAN_MAE, 1 },
		{ "clean scenes, largest MAE", s->mae_max[c], BAR_CLEAN_MAX_MAE, 1 },
		{ "noisy scenes, largest MAE", s->mae_max[g], BAR_NOISY_MAX_MAE, run->have[g] },
		{ "structured-light plane, occl.", mean_or_zero(s->plane_occ[sl], s->plane_n[sl]),
		  BAR_SL_PLANE_OCCLUSION, run->have[sl] && s->plane_n[sl] },
	};
	for (size_t b = 0; b < sizeof bars / sizeof bars[0]; b++) {
		if (!bars[b].present)
			continue;
		int ok = bars[b].value <= bars[b].bar;
		fprintf(stderr, "depthao: %-30s %.4f (bar %.3f) %s\n", bars[b].what, bars[b].value,
			bars[b].bar, ok ? "ok" : "FAILED");
		if (!ok)
			status = 1;
	}
	return status;
}

int cmd_eval(int argc, char **argv)
{
	/* the other measures have their own options */
	for (int i = 1; i < argc; i++) {
		if (strcmp(argv[i], "--sequence") == 0)
			return cmd_eval_sequence(argc, argv);
		if (strcmp(argv[i], "--depth") == 0)
			return cmd_eval_depth(argc, argv);
	}
	struct eval_options o = { 0 };
	if (parse_args(argc, argv, &o))
		return 2;
	/* validate the scene names before the long render */
	for (int k = 0; o.scenes[k]; k++) {
		struct synth_scene sc;
		struct dao_error e;
		if (synth_scene_build(o.scenes[k], 0.0, &sc, &e))
			return usage_error("eval", "%s", e.message);
	}
	struct eval_run run = { .o = &o };
	int status = plan_columns(&run);
	if (status)
		return status;

	struct dao_error err;
	fprintf(stderr, "depthao: rendering ground truth (%d rays per pixel), %s set...\n",
		o.rays_sqrt * o.rays_sqrt, synth_set_name(o.set));
	struct synth_suite_spec spec = {
		.scenes = o.scenes[0] ? o.scenes : NULL, .radius = 0.5, .rays_sqrt = o.rays_sqrt,
		.sensors = o.sensors, .nsensors = o.nsensors, .seed = 1, .threads = 2,
	};
	synth_suite_spec_set(&spec, o.set, o.variants);
	if (synth_suite_load_spec(&run.suite, &spec, &err)) {
		fprintf(stderr, "depthao: %s\n", err.message);
		return 1;
	}
	const size_t np = (size_t)run.suite.cam.width * run.suite.cam.height;
	float *ao = malloc(np * sizeof(float));
	run.res = calloc((size_t)run.suite.count, sizeof *run.res);
	if (!ao || !run.res) {
		fprintf(stderr, "depthao: out of memory\n");
		status = 1;
	} else if (!(status = run_columns(&run, ao))) {
		print_table(&run);
		print_targets(&run);
		status = check_results(&run);
	}
	free(ao);
	free(run.res);
	synth_suite_free(&run.suite);
	return status;
}
