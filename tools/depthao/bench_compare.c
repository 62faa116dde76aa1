/* SPDX-License-Identifier: MIT */
#define _XOPEN_SOURCE 700 /* realpath */
/*
 * depthao bench --compare / --compare-params: this build and other builds (or
 * this build with other parameters) timed side by side.  Every run is a child
 * process `depthao bench ... --json`; the runs are interleaved, round after
 * round, the first build of a round in turn, so that a change of the host's
 * load or clock hits all of them alike.  What is compared is each round's
 * ratio of this build's median to the other's: their median over the rounds,
 * and their min-max as the spread.
 */
#include <errno.h>
#include <json-c/json.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <depthao/depthao.h>

#include "bench.h"
#include "bench_input.h"
#include "commands.h"

/* One configuration (size x preset x threads) of one run, from its JSON line. */
struct result {
	int w, h, threads, slices, steps;
	char quality[24], algorithm[16];
	double median, p95, stage[BENCH_NSTAGES];
	unsigned stages; /* bit k: the run reported stage k */
};

/* A build (or this build with a parameter set) and its runs. */
struct variant {
	char label;    /* A (this build), B, C ... */
	char path[4096];
	char version[128];
	const char *what; /* "this build", "other build", or the --compare-params */
	char **argv;      /* path bench <options> [params] --json NULL */
	int argc;
	int is_params;    /* this build with the parameter set `what` */
	char *words;      /* `what` split into words, for argv */
	int runs;
	struct result *res; /* [round][configuration] */
	char *acc;          /* a round's output: its runs' for each size */
	size_t acc_len;
};

/* A child's exit status and output. */
struct child {
	char *out;
	size_t len;
	char err[4096]; /* the start of its stderr */
	int status;     /* exit status, or 128 + signal */
};

static int read_loadavg(double load[3])
{
	FILE *f = fopen("/proc/loadavg", "r");
	if (!f)
		return -1;
	int n = fscanf(f, "%lf %lf %lf", &load[0], &load[1], &load[2]);
	fclose(f);
	return n == 3 ? 0 : -1;
}

static void print_loadavg(const char *when)
{
	double l[3];
	if (read_loadavg(l))
		printf("load average %s: unknown\n", when);
	else
		printf("load average %s: %.2f %.2f %.2f\n", when, l[0], l[1], l[2]);
}

/* Runs argv[0] with argv, its stdout and stderr captured; 0, or -errno if it could not. */
static int run_child(char *const argv[], struct child *c)
{
	*c = (struct child){ 0 };
	FILE *err = tmpfile();
	int fd[2];
	if (!err)
		return -errno;
	if (pipe(fd)) {
		int e = errno;
		fclose(err);
		return -e;
	}
	fflush(stdout);
	fflush(stderr);
	pid_t pid = fork();
	if (pid < 0) {
		int e = errno;
		close(fd[0]);
		close(fd[1]);
		fclose(err);
		return -e;
	}
	if (pid == 0) {
		dup2(fd[1], 1);
		dup2(fileno(err), 2);
		close(fd[0]);
		close(fd[1]);
		execv(argv[0], argv);
		fprintf(stderr, "cannot run %s: %s\n", argv[0], strerror(errno));
		_exit(127);
	}
	close(fd[1]);
	size_t cap = 0;
	int r = 0;
	for (;;) {
		if (c->len + 4096 + 1 > cap) {
			char *p = realloc(c->out, cap = 2 * cap + 8192);
			if (!p) {
				r = -ENOMEM;
				break;
			}
			c->out = p;
		}
		ssize_t n = read(fd[0], c->out + c->len, 4096);
		if (n < 0 && errno == EINTR)
			continue;
		if (n <= 0)
			break;
		c->len += (size_t)n;
	}
	if (c->out)
		c->out[c->len] = 0;
	close(fd[0]);
	int st;
	while (waitpid(pid, &st, 0) < 0 && errno == EINTR)
		;
	c->status = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + (WIFSIGNALED(st) ? WTERMSIG(st) : 0);
	rewind(err);
	size_t n = fread(c->err, 1, sizeof c->err - 1, err);
	c->err[n] = 0;
	fclose(err);
	return r;
}

static void child_free(struct child *c)
{
	free(c->out);
	c->out = NULL;
}

/*
 * The line of a child's stderr that says why it failed: its first line that
 * starts with "depthao: " (a usage error), else its last line, without
 * "depthao: " and " (see ...)".
 */
static const char *child_reason(struct child *c)
{
	char *s = c->err, *pick = NULL;
	for (char *line = s; *line;) {
		char *nl = strchr(line, '\n');
		if (nl)
			*nl = 0;
		if (*line && (!pick || strncmp(pick, "depthao: ", 9)))
			pick = line;
		if (!nl)
			break;
		line = nl + 1;
	}
	if (!pick)
		return "(nothing on stderr)";
	if (!strncmp(pick, "depthao: ", 9))
		pick += 9;
	char *see = strstr(pick, " (see '");
	if (see)
		*see = 0;
	return pick;
}

/* OTHER (a build directory or a binary) to the path of its depthao; 0 or a usage error. */
static int resolve_other(const char *other, char *path, size_t n)
{
	struct stat st;
	if (stat(other, &st))
		return usage_error("bench", "--compare %s: %s", other, strerror(errno));
	const char *bin = other;
	char buf[4096];
	if (S_ISDIR(st.st_mode)) {
		static const char *const tries[] = { "tools/depthao/depthao", "depthao" };
		bin = NULL;
		for (size_t i = 0; i < sizeof tries / sizeof tries[0] && !bin; i++) {
			snprintf(buf, sizeof buf, "%s/%s", other, tries[i]);
			if (!stat(buf, &st) && S_ISREG(st.st_mode))
				bin = buf;
		}
		if (!bin)
			return usage_error("bench", "--compare %s: no depthao in this directory (it "
					   "has no tools/depthao/depthao: not a build directory?)", other);
	}
	if (access(bin, X_OK))
		return usage_error("bench", "--compare %s: not executable", bin);
	char *real = realpath(bin, NULL);
	if (!real || strlen(real) >= n) {
		free(real);
		return usage_error("bench", "--compare %s: path too long", other);
	}
	strcpy(path, real);
	free(real);
	return 0;
}

/* `PATH --version` into v->version; 0, or a usage error if it is not depthao. */
static int read_version(struct variant *v, const char *given)
{
	char *argv[] = { v->path, "--version", NULL };
	struct child c;
	int r = run_child(argv, &c);
	if (r) {
		child_free(&c);
		fprintf(stderr, "depthao bench: cannot run %s: %s\n", v->path, strerror(-r));
		return 1;
	}
	char *nl = c.out ? strchr(c.out, '\n') : NULL;
	if (nl)
		*nl = 0;
	if (c.status || !c.out || strncmp(c.out, "depthao ", 8)) {
		char said[64];
		snprintf(said, sizeof said, "%s", c.out && *c.out ? c.out : child_reason(&c));
		child_free(&c);
		return usage_error("bench", "--compare %s: not a depthao binary ('%s --version' "
				   "exits %d and prints '%s')", given, v->path, c.status, said);
	}
	snprintf(v->version, sizeof v->version, "%s", c.out);
	child_free(&c);
	return 0;
}

/* "--" + name; NULL if out of memory. */
static char *dashed(const char *name)
{
	char *s = malloc(strlen(name) + 3);
	if (s)
		sprintf(s, "--%s", name);
	return s;
}

/*
 * v->argv: PATH bench, the user's options, --size `size` (none if NULL), the options in
 * `extra` (or NULL), the words of the parameter set, --json.  `opt` holds the
 * options' "--name" strings.
 */
static int build_argv(struct variant *v, const struct bench_compare_spec *s, char **opt,
		      const char *size, char *const *extra)
{
	int n = 0, max = 2 * s->nargs + 16 + (v->is_params ? (int)strlen(v->what) : 0);
	free(v->argv);
	v->argv = malloc((size_t)max * sizeof *v->argv);
	if (!v->argv)
		return -ENOMEM;
	v->argv[n++] = v->path;
	v->argv[n++] = "bench";
	for (int i = 0; i < s->nargs; i++) {
		v->argv[n++] = opt[i];
		if (s->args[i].value)
			v->argv[n++] = (char *)s->args[i].value;
	}
	if (size) {
		v->argv[n++] = "--size";
		v->argv[n++] = (char *)size;
	}
	while (extra && *extra)
		v->argv[n++] = *extra++;
	/* the parameter set: its words, split at white space */
	if (v->is_params) {
		char *save;
		free(v->words);
		if (!(v->words = strdup(v->what)))
			return -ENOMEM;
		for (char *w = strtok_r(v->words, " \t\n", &save); w;
		     w = strtok_r(NULL, " \t\n", &save))
			v->argv[n++] = w;
	}
	v->argv[n++] = "--json";
	v->argv[n] = NULL;
	v->argc = n;
	return 0;
}

static int get_int(json_object *o, const char *key, int *out)
{
	json_object *x;
	if (!json_object_object_get_ex(o, key, &x) || !json_object_is_type(x, json_type_int))
		return -1;
	*out = json_object_get_int(x);
	return 0;
}

static int get_double(json_object *o, const char *key, double *out)
{
	json_object *x;
	if (!json_object_object_get_ex(o, key, &x) ||
	    !(json_object_is_type(x, json_type_double) || json_object_is_type(x, json_type_int)))
		return -1;
	*out = json_object_get_double(x);
	return 0;
}

static void get_string(json_object *o, const char *key, char *out, size_t n)
{
	json_object *x;
	if (json_object_object_get_ex(o, key, &x) && json_object_is_type(x, json_type_string))
		snprintf(out, n, "%s", json_object_get_string(x));
}

/* One JSON line of bench into `r`; 0, or -1 if it is not one. */
static int parse_line(const char *line, struct result *r)
{
	json_object *o = json_tokener_parse(line);
	*r = (struct result){ .quality = "?" };
	int bad = !o || !json_object_is_type(o, json_type_object) || get_int(o, "width", &r->w) ||
		  get_int(o, "height", &r->h) || get_int(o, "threads", &r->threads) ||
		  get_double(o, "median_ms", &r->median) || get_double(o, "p95_ms", &r->p95) ||
		  !(r->median > 0);
	if (!bad) {
		get_int(o, "slices", &r->slices);
		get_int(o, "steps", &r->steps);
		get_string(o, "quality", r->quality, sizeof r->quality);
		get_string(o, "algorithm", r->algorithm, sizeof r->algorithm);
		json_object *stg;
		if (json_object_object_get_ex(o, "stage_median_ms", &stg))
			for (int k = 0; k < BENCH_NSTAGES; k++)
				if (!get_double(stg, bench_stage_names[k], &r->stage[k]))
					r->stages |= 1u << k;
	}
	json_object_put(o);
	return bad ? -1 : 0;
}

/*
 * A run's output into its results for round `round`.  The first run sets the
 * configurations (*nconf, ref); the others must time the same sizes and
 * thread counts in the same order.  0, or 1 after printing why not.
 */
static int take_output(struct variant *v, int round, int rounds, int *nconf,
		       struct result **ref, const struct variant *first)
{
	int n = 0, cap = 16;
	struct result *got = malloc((size_t)cap * sizeof *got);
	char *save;
	if (!got)
		goto oom;
	for (char *line = v->acc ? strtok_r(v->acc, "\n", &save) : NULL; line;
	     line = strtok_r(NULL, "\n", &save)) {
		if (n == cap) {
			struct result *p = realloc(got, (size_t)(cap *= 2) * sizeof *got);
			if (!p)
				goto oom;
			got = p;
		}
		if (parse_line(line, &got[n])) {
			fprintf(stderr, "depthao bench: %c (%s) printed a line that is not bench's "
				"JSON: '%.100s'\n", v->label, v->path, line);
			free(got);
			return 1;
		}
		n++;
	}
	if (n == 0) {
		fprintf(stderr, "depthao bench: %c (%s) printed no configuration\n", v->label, v->path);
		free(got);
		return 1;
	}
	if (!*ref) {
		*nconf = n;
		*ref = got;
	} else {
		const struct result *e = *ref;
		int same = n == *nconf;
		for (int i = 0; same && i < n; i++)
			same = got[i].w == e[i].w && got[i].h == e[i].h &&
			       got[i].threads == e[i].threads;
		if (!same) {
			fprintf(stderr, "depthao bench: %c (%s) timed %d configurations and %c %d, "
				"not the same sizes and thread counts in the same order; give "
				"--quality and --threads\n", v->label, v->path, n, first->label,
				*nconf);
			free(got);
			return 1;
		}
	}
	if (!v->res && !(v->res = calloc((size_t)rounds * (size_t)*nconf, sizeof *v->res)))
		goto oom;
	memcpy(v->res + (size_t)round * (size_t)*nconf, got, (size_t)*nconf * sizeof *got);
	if (got != *ref)
		free(got);
	v->runs++;
	return 0;
oom:
	if (got != *ref)
		free(got);
	fprintf(stderr, "depthao bench: out of memory\n");
	return 1;
}

/* What to call variant v in messages. */
static void describe(const struct variant *v, char *out, size_t n)
{
	if (v->is_params)
		snprintf(out, n, "this build with --compare-params '%s'", v->what);
	else
		snprintf(out, n, "%c (%s)", v->label, v->path);
}

/* A child's usage error names an option of --input's ("... unknown option '--fov'"):
 * a build from before bench --input. */
static int rejects_input(const char *reason)
{
	static const char lead[] = "option '--";
	const char *q = strstr(reason, lead);
	if (!q)
		return 0;
	q += sizeof lead - 1;
	for (int k = 0; k < BENCH_INPUT_NOPTIONS; k++) {
		size_t n = strlen(bench_input_names[k]);
		if (!strncmp(q, bench_input_names[k], n) && q[n] == '\'')
			return 1;
	}
	return 0;
}

/* A failed run: 2 if it rejected an option, else 1; the message printed. */
static int report_failure(struct variant *v, struct child *c, int round)
{
	char who[4200];
	describe(v, who, sizeof who);
	const char *why = child_reason(c); /* once: it cuts c->err into lines */
	if (c->status == 2 && v->is_params)
		return usage_error("bench", "%s: %s", who, why);
	if (c->status == 2 && rejects_input(why))
		return usage_error("bench", "%s is older than bench --input (it says: %s): it "
				   "times the synthetic frame only; compare the two without --input "
				   "and its options, or against a build that has it", who,
				   why);
	if (c->status == 2)
		return usage_error("bench", "%s rejects an option that this build accepts (it says: "
				   "%s); leave that option out to compare the two", who,
				   why);
	if (c->status > 128)
		fprintf(stderr, "depthao bench: %s was killed by signal %d in round %d\n", who,
			c->status - 128, round + 1);
	else
		fprintf(stderr, "depthao bench: %s failed (exit %d) in round %d: %s\n", who,
			c->status, round + 1, why);
	return 1;
}

static int cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

/* The median of n values (the mean of the middle two for even n); sorts v. */
static double median(double *v, int n)
{
	qsort(v, (size_t)n, sizeof *v, cmp_double);
	return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* Over the rounds, for one configuration of one variant. */
struct summary {
	double median, p95, stage[BENCH_NSTAGES];
	unsigned stages;
};

/* Ratios of A's times to another variant's over the rounds. */
struct ratio {
	double median, min, max;
	double stage[BENCH_NSTAGES];
	unsigned stages;      /* the other reported stage k */
	unsigned stage_valid; /* and its time was > 0 in every round */
};

static void summarize(const struct variant *v, int c, int nconf, int rounds, double *tmp,
		      struct summary *s)
{
	const struct result *r0 = v->res + c;
	*s = (struct summary){ .stages = r0->stages };
	for (int r = 0; r < rounds; r++)
		tmp[r] = r0[(size_t)r * nconf].median;
	s->median = median(tmp, rounds);
	for (int r = 0; r < rounds; r++)
		tmp[r] = r0[(size_t)r * nconf].p95;
	s->p95 = median(tmp, rounds);
	for (int k = 0; k < BENCH_NSTAGES; k++) {
		if (!(s->stages >> k & 1))
			continue;
		for (int r = 0; r < rounds; r++)
			tmp[r] = r0[(size_t)r * nconf].stage[k];
		s->stage[k] = median(tmp, rounds);
	}
}

static void compute_ratio(const struct variant *a, const struct variant *b, int c, int nconf,
			  int rounds, double *tmp, struct ratio *q)
{
	const struct result *ra = a->res + c, *rb = b->res + c;
	*q = (struct ratio){ .stages = rb->stages & ra->stages };
	for (int r = 0; r < rounds; r++)
		tmp[r] = ra[(size_t)r * nconf].median / rb[(size_t)r * nconf].median;
	q->min = q->max = tmp[0];
	for (int r = 1; r < rounds; r++) {
		q->min = tmp[r] < q->min ? tmp[r] : q->min;
		q->max = tmp[r] > q->max ? tmp[r] : q->max;
	}
	q->median = median(tmp, rounds);
	for (int k = 0; k < BENCH_NSTAGES; k++) {
		if (!(q->stages >> k & 1))
			continue;
		int ok = 1;
		for (int r = 0; r < rounds && ok; r++) {
			double den = rb[(size_t)r * nconf].stage[k];
			ok = den > 0;
			tmp[r] = ok ? ra[(size_t)r * nconf].stage[k] / den : 0;
		}
		if (ok) {
			q->stage[k] = median(tmp, rounds);
			q->stage_valid |= 1u << k;
		}
	}
}

static void config_title(const struct result *r, char *out, size_t n)
{
	char algo[24] = "";
	if (r->algorithm[0] && strcmp(r->algorithm, "gtao"))
		snprintf(algo, sizeof algo, "%s ", r->algorithm);
	snprintf(out, n, "%dx%d %s%s %dx%d, %d thread%s", r->w, r->h, algo, r->quality, r->slices,
		 r->steps, r->threads, r->threads == 1 ? "" : "s");
}

static void print_table(struct variant *v, int nv, int nconf, int rounds, double *tmp)
{
	for (int c = 0; c < nconf; c++) {
		char title[128];
		config_title(&v[0].res[c], title, sizeof title);
		printf("\n%s", title);
		for (int i = 1; i < nv; i++) {
			char other[128];
			config_title(&v[i].res[c], other, sizeof other);
			if (strcmp(title, other))
				printf("  (%c: %s)", v[i].label, other);
		}
		printf("\n  %-6s %8s %8s %8s |", "", "median", "p95", "fps");
		for (int k = 0; k < BENCH_NSTAGES; k++)
			printf(" %9s", bench_stage_names[k]);
		putchar('\n');
		for (int i = 0; i < nv; i++) {
			struct summary s;
			summarize(&v[i], c, nconf, rounds, tmp, &s);
			printf("  %-6c %8.2f %8.2f %8.1f |", v[i].label, s.median, s.p95,
			       1e3 / s.median);
			for (int k = 0; k < BENCH_NSTAGES; k++)
				if (s.stages >> k & 1)
					printf(" %9.2f", s.stage[k]);
				else
					printf(" %9s", "-");
			putchar('\n');
		}
		for (int i = 1; i < nv; i++) {
			struct ratio q;
			compute_ratio(&v[0], &v[i], c, nconf, rounds, tmp, &q);
			char name[8], spread[40];
			snprintf(name, sizeof name, "%c/%c", v[0].label, v[i].label);
			snprintf(spread, sizeof spread, "(%.3f-%.3f)", q.min, q.max);
			printf("  %-6s %8.3f %-17s |", name, q.median, spread);
			for (int k = 0; k < BENCH_NSTAGES; k++)
				if (q.stage_valid >> k & 1)
					printf(" %9.2f", q.stage[k]);
				else
					printf(" %9s", q.stages >> k & 1 ? "n/a" : "-");
			putchar('\n');
		}
	}
}

static json_object *json_doubles(const double *x, int n)
{
	json_object *a = json_object_new_array();
	for (int i = 0; i < n; i++)
		json_object_array_add(a, json_object_new_double(x[i]));
	return a;
}

static json_object *json_config(struct variant *v, int nv, int c, int nconf, int rounds,
				double *tmp)
{
	const struct result *r = &v[0].res[c];
	json_object *o = json_object_new_object();
	json_object_object_add(o, "width", json_object_new_int(r->w));
	json_object_object_add(o, "height", json_object_new_int(r->h));
	json_object_object_add(o, "quality", json_object_new_string(r->quality));
	if (r->algorithm[0])
		json_object_object_add(o, "algorithm", json_object_new_string(r->algorithm));
	json_object_object_add(o, "slices", json_object_new_int(r->slices));
	json_object_object_add(o, "steps", json_object_new_int(r->steps));
	json_object_object_add(o, "threads", json_object_new_int(r->threads));
	json_object *builds = json_object_new_array();
	for (int i = 0; i < nv; i++) {
		struct summary s;
		summarize(&v[i], c, nconf, rounds, tmp, &s);
		const struct result *ri = &v[i].res[c];
		json_object *b = json_object_new_object();
		json_object_object_add(b, "build", json_object_new_string_len(&v[i].label, 1));
		json_object_object_add(b, "quality", json_object_new_string(ri->quality));
		json_object_object_add(b, "slices", json_object_new_int(ri->slices));
		json_object_object_add(b, "steps", json_object_new_int(ri->steps));
		json_object_object_add(b, "median_ms", json_object_new_double(s.median));
		json_object_object_add(b, "p95_ms", json_object_new_double(s.p95));
		json_object_object_add(b, "fps", json_object_new_double(1e3 / s.median));
		for (int k = 0; k < rounds; k++)
			tmp[k] = ri[(size_t)k * nconf].median;
		json_object_object_add(b, "round_median_ms", json_doubles(tmp, rounds));
		for (int k = 0; k < rounds; k++)
			tmp[k] = ri[(size_t)k * nconf].p95;
		json_object_object_add(b, "round_p95_ms", json_doubles(tmp, rounds));
		json_object *stg = json_object_new_object();
		for (int k = 0; k < BENCH_NSTAGES; k++)
			if (s.stages >> k & 1)
				json_object_object_add(stg, bench_stage_names[k],
						       json_object_new_double(s.stage[k]));
		json_object_object_add(b, "stage_median_ms", stg);
		json_object_array_add(builds, b);
	}
	json_object_object_add(o, "builds", builds);
	json_object *ratios = json_object_new_array();
	for (int i = 1; i < nv; i++) {
		struct ratio q;
		compute_ratio(&v[0], &v[i], c, nconf, rounds, tmp, &q);
		json_object *x = json_object_new_object();
		char name[4] = { v[0].label, '/', v[i].label, 0 };
		json_object_object_add(x, "ratio", json_object_new_string(name));
		json_object_object_add(x, "median", json_object_new_double(q.median));
		json_object_object_add(x, "min", json_object_new_double(q.min));
		json_object_object_add(x, "max", json_object_new_double(q.max));
		for (int k = 0; k < rounds; k++)
			tmp[k] = v[0].res[(size_t)k * nconf + c].median /
				 v[i].res[(size_t)k * nconf + c].median;
		json_object_object_add(x, "rounds", json_doubles(tmp, rounds));
		json_object *stg = json_object_new_object();
		for (int k = 0; k < BENCH_NSTAGES; k++)
			json_object_object_add(stg, bench_stage_names[k],
					       q.stage_valid >> k & 1 ?
						       json_object_new_double(q.stage[k]) : NULL);
		json_object_object_add(x, "stage", stg);
		json_object_array_add(ratios, x);
	}
	json_object_object_add(o, "ratios", ratios);
	return o;
}

static json_object *json_load(void)
{
	double l[3];
	return read_loadavg(l) ? NULL : json_doubles(l, 3);
}

static void print_json(const struct bench_compare_spec *spec, struct variant *v, int nv,
		       int nconf, int rounds, double *tmp, json_object *load_before)
{
	json_object *o = json_object_new_object();
	char model[128];
	dao_cpu_model(model, sizeof model);
	json_object_object_add(o, "cpu", json_object_new_string(model));
	json_object_object_add(o, "cpus", json_object_new_int(dao_cpu_count()));
	json_object_object_add(o, "rounds", json_object_new_int(rounds));
	json_object *sizes = json_object_new_array();
	for (int i = 0; !spec->input && i < spec->nsizes; i++)
		json_object_array_add(sizes, json_object_new_string(spec->sizes[i]));
	json_object_object_add(o, "sizes", sizes); /* none with --input: its own */
	if (spec->input)
		json_object_object_add(o, "input", json_object_new_string(spec->input));
	json_object_object_add(o, "load_before", load_before);
	json_object_object_add(o, "load_after", json_load());
	json_object *builds = json_object_new_array();
	for (int i = 0; i < nv; i++) {
		json_object *b = json_object_new_object();
		json_object_object_add(b, "build", json_object_new_string_len(&v[i].label, 1));
		json_object_object_add(b, "path", json_object_new_string(v[i].path));
		json_object_object_add(b, "version", json_object_new_string(v[i].version));
		json_object_object_add(b, "what", json_object_new_string(v[i].what));
		json_object *args = json_object_new_array();
		for (int k = 1; k < v[i].argc; k++)
			json_object_array_add(args, json_object_new_string(v[i].argv[k]));
		json_object_object_add(b, "args", args);
		json_object_object_add(b, "runs", json_object_new_int(v[i].runs));
		json_object_array_add(builds, b);
	}
	json_object_object_add(o, "builds", builds);
	json_object *configs = json_object_new_array();
	for (int c = 0; c < nconf; c++)
		json_object_array_add(configs, json_config(v, nv, c, nconf, rounds, tmp));
	json_object_object_add(o, "configurations", configs);
	puts(json_object_to_json_string_ext(o, JSON_C_TO_STRING_PLAIN));
	json_object_put(o);
}

static void print_header(const struct bench_compare_spec *s, const struct variant *v, int nv)
{
	char model[128];
	dao_cpu_model(model, sizeof model);
	printf("depthao bench, side by side: %d builds, %d rounds, interleaved (each round "
	       "starts with the next build); %s, %d CPUs\n", nv, s->rounds, model, dao_cpu_count());
	for (int i = 0; i < nv; i++) {
		if (v[i].is_params)
			printf("  %c  A with %s\n", v[i].label, v[i].what);
		else
			printf("  %c  %-11s %s   %s\n", v[i].label, v[i].what, v[i].path, v[i].version);
	}
	printf("each run: depthao bench");
	for (int k = 2; k < v[0].argc; k++)
		printf(" %s", v[0].argv[k]);
	if (s->input)
		printf("\n  one run on the frames of --input %s", s->input);
	else
		printf("\n  one run per size WxH:");
	for (int i = 0; !s->input && i < s->nsizes; i++)
		printf(" %s", s->sizes[i]);
	printf("\ntimes in ms per frame: the median over the rounds of each run's median and p95; "
	       "fps = 1000 / median\nA/X = A's time / X's (> 1: A is slower), the median of the "
	       "rounds' ratios (min-max); '-': a stage X does not time, n/a: X's is 0\n");
	print_loadavg("before");
}

/* The variants: this build, the others, this build with each parameter set. */
static int setup_variants(const struct bench_compare_spec *s, struct variant *v, int *nv)
{
	int n = 0, r;
	v[n] = (struct variant){ .label = 'A', .what = "this build" };
	ssize_t len = readlink("/proc/self/exe", v[0].path, sizeof v[0].path - 1);
	if (len <= 0) {
		fprintf(stderr, "depthao bench: cannot find this program (/proc/self/exe): %s\n",
			strerror(errno));
		return 1;
	}
	v[0].path[len] = 0;
	if ((r = read_version(&v[0], v[0].path)))
		return r;
	n++;
	for (int i = 0; i < s->nothers; i++, n++) {
		v[n] = (struct variant){ .label = (char)('A' + n), .what = "other build" };
		if ((r = resolve_other(s->others[i], v[n].path, sizeof v[n].path)) ||
		    (r = read_version(&v[n], s->others[i]))) {
			*nv = n + 1;
			return r;
		}
	}
	for (int i = 0; i < s->nparams; i++, n++) {
		v[n] = (struct variant){ .label = (char)('A' + n), .what = s->params[i],
					 .is_params = 1 };
		strcpy(v[n].path, v[0].path);
		strcpy(v[n].version, v[0].version);
	}
	*nv = n;
	return 0;
}

/* A small run of each variant: an option it rejects fails here, not after minutes. */
static int preflight(const struct bench_compare_spec *s, struct variant *v, int nv, char **opt)
{
	/* with --input: its first frame alone */
	static char *const quick[] = { "--min-time", "0", "--min-iterations", "1",
				       "--no-reference", NULL };
	static char *const quick_input[] = { "--min-time", "0", "--min-iterations", "1",
					     "--no-reference", "--input-frames", "1", NULL };
	char *const *extra = s->input ? quick_input : quick;
	for (int i = 0; i < nv; i++) {
		struct child c;
		int r = build_argv(&v[i], s, opt, s->input ? NULL : "64x48", extra);
		if (!r)
			r = run_child(v[i].argv, &c);
		if (r) {
			fprintf(stderr, "depthao bench: cannot run %s: %s\n", v[i].path, strerror(-r));
			return 1;
		}
		/* only a rejected option counts: other failures show in the real runs */
		r = c.status == 2 ? report_failure(&v[i], &c, 0) : 0;
		child_free(&c);
		if (r)
			return r;
	}
	return 0;
}

/* Appends a run's output to v->acc; 0 or -ENOMEM. */
static int accumulate(struct variant *v, const struct child *c)
{
	char *p = realloc(v->acc, v->acc_len + c->len + 1);
	if (!p)
		return -ENOMEM;
	v->acc = p;
	memcpy(v->acc + v->acc_len, c->out ? c->out : "", c->len);
	v->acc_len += c->len;
	v->acc[v->acc_len] = 0;
	return 0;
}

/* Each variant's argv with "--size WxH": what the header and the JSON show. */
static int display_argv(const struct bench_compare_spec *s, struct variant *v, int nv, char **opt)
{
	for (int i = 0; i < nv; i++)
		if (build_argv(&v[i], s, opt, s->input ? NULL : "WxH", NULL)) {
			fprintf(stderr, "depthao bench: out of memory\n");
			return 1;
		}
	return 0;
}

/*
 * The rounds: in each, for each size, every variant once, the first in turn
 * (A B C, B C A, ...).  One run per size: the last release times only the last
 * --size given.
 */
static int run_rounds(const struct bench_compare_spec *s, struct variant *v, int nv,
		      char **opt, int *nconf, struct result **ref)
{
	const int tty = isatty(2);
	for (int round = 0; round < s->rounds; round++) {
		for (int si = 0; si < s->nsizes; si++) {
			for (int k = 0; k < nv; k++) {
				struct variant *x = &v[(round + k) % nv];
				if (tty)
					fprintf(stderr, "\rround %d/%d: %s %c ", round + 1, s->rounds,
						s->sizes[si] ? s->sizes[si] : "--input",
						x->label);
				struct child c = { 0 };
				int r = build_argv(x, s, opt, s->sizes[si], NULL);
				if (!r)
					r = run_child(x->argv, &c);
				if (r) {
					child_free(&c);
					fprintf(stderr, "depthao bench: cannot run %s: %s\n", x->path,
						strerror(-r));
					return 1;
				}
				r = c.status ? report_failure(x, &c, round) : accumulate(x, &c);
				child_free(&c);
				if (r < 0)
					fprintf(stderr, "depthao bench: out of memory\n");
				if (r)
					return r < 0 ? 1 : r;
			}
		}
		for (int k = 0; k < nv; k++) {
			int r = take_output(&v[k], round, s->rounds, nconf, ref, &v[0]);
			v[k].acc_len = 0;
			if (r)
				return r;
		}
	}
	if (tty)
		fputs("\r                    \r", stderr);
	return 0;
}

int bench_compare(const struct bench_compare_spec *s)
{
	struct variant v[BENCH_MAX_VARIANTS];
	int nv = 0, nconf = 0, r;
	struct result *ref = NULL;
	char **opt = calloc((size_t)s->nargs + 1, sizeof *opt);
	double *tmp = malloc((size_t)s->rounds * sizeof *tmp);
	json_object *load_before = NULL;
	if (!opt || !tmp) {
		r = 1;
		goto out;
	}
	for (int i = 0; i < s->nargs; i++)
		if (!(opt[i] = dashed(s->args[i].name))) {
			r = 1;
			goto out;
		}
	if ((r = setup_variants(s, v, &nv)) || (r = preflight(s, v, nv, opt)))
		goto out;
	if ((r = display_argv(s, v, nv, opt)))
		goto out;
	if (s->json)
		load_before = json_load();
	else
		print_header(s, v, nv);
	if ((r = run_rounds(s, v, nv, opt, &nconf, &ref)) || (r = display_argv(s, v, nv, opt)))
		goto out;
	if (s->json) {
		print_json(s, v, nv, nconf, s->rounds, tmp, load_before);
		load_before = NULL;
	} else {
		print_table(v, nv, nconf, s->rounds, tmp);
		putchar('\n');
		print_loadavg("after");
	}
out:
	json_object_put(load_before);
	for (int i = 0; i < nv; i++) {
		free(v[i].argv);
		free(v[i].words);
		free(v[i].acc);
		free(v[i].res);
	}
	for (int i = 0; opt && i < s->nargs; i++)
		free(opt[i]);
	free(opt);
	free(tmp);
	free(ref);
	return r;
}
