/* SPDX-License-Identifier: MIT */
/* depthao bench: what the timing part (cmd_bench.c) and --compare (bench_compare.c) share. */
#ifndef DAO_TOOLS_BENCH_H
#define DAO_TOOLS_BENCH_H

#define BENCH_NSTAGES 8
/* the stages of dao_timings in bench's order: the keys of "stage_median_ms" */
extern const char *const bench_stage_names[BENCH_NSTAGES];

#define BENCH_MAX_VARIANTS 6 /* this build and up to 5 others or parameter sets */

/* An option by its long name without "--", and its value or NULL. */
struct bench_arg {
	const char *name, *value;
};

/* What `depthao bench --compare/--compare-params` runs. */
struct bench_compare_spec {
	/* bench's options for every child as the user gave them, each --threads
	 * value an option of its own; not --json, nor --size */
	const struct bench_arg *args;
	int nargs;
	/* the sizes, given or the default: one child per size, as the last release
	 * times the last --size only; with --input one NULL: no --size */
	const char *sizes[16];
	int nsizes;
	const char *input; /* --input (among the args), or NULL */
	const char *others[BENCH_MAX_VARIANTS]; /* --compare: build directories or binaries */
	int nothers;
	const char *params[BENCH_MAX_VARIANTS]; /* --compare-params: options for this build */
	int nparams;
	int rounds;
	int json;
};

/* Runs the comparison and prints it; the exit status (0, 1, or 2 for a usage error). */
int bench_compare(const struct bench_compare_spec *spec);

#endif
