/* SPDX-License-Identifier: MIT */
/*
 * How good VBAO can be with the thickness right (issue #17): scenes of
 * `depthao eval`, clean, through the whole pipeline at the medium preset,
 * with VBAO's thickness plane replaced by the ray-traced truth -- the length
 * of each pixel's camera ray inside the solid it hits (synth_inside_plane),
 * scaled or with a margin added, capped -- against GTAO, the estimate from
 * the image and VBAO's constant; and, to find where the estimate loses, the
 * truth only where the estimate is 1.5 times too thick or too thin.  A
 * measuring program (docs/design/thickness.md, "Thickness from the image", the ceiling);
 * the test suite runs it once, small, to keep it working.
 *
 * The truth reaches the kernel the way the estimate does: this program is
 * linked with --wrap=dao_thickness_cols, so the pipeline's own call of the
 * column pass (the estimate's last step) lands in __wrap_dao_thickness_cols,
 * which runs the pass and then overwrites its columns of the plane with the
 * truth and splits them by phase again (the pass splits them as it goes); the
 * kernel that follows is the pipeline's.  The library is not changed for it.
 *
 *   thickness-ceiling [--set tune|heldout] [--rays N] [--variants N]
 *                     [--sensor clean|gaussian|structured-light|...] [--dump DIR] SCENE...
 *
 * --sensor feeds the pipeline that sensor's depth (clean by default); the
 * truth is still each pixel's camera ray through the scene.  --dump writes
 * each scene's planes as raw little-endian floats (640 x 480): depth (the
 * input), prefiltered (the depth the estimate saw), gt, truth, estimate, and
 * the AO of every column, for error maps.
 */
#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/depthao.h>

#include "kernels/gtao_planes.h"
#include "kernels/thickness.h"
#include "synth/suite.h"

/* what the wrapped column pass does after the real one */
static struct {
	const float *truth; /* NULL: leave the estimate */
	float scale, cap;
	float add;          /* added to the scaled truth, m */
	float add_tan;      /* added times tan(ray, surface normal), m */
	float add_sec;      /* added times 1 / cos(ray, surface normal), m */
	float extra_max;    /* > 0: v = truth + (scale - 1) truth, within add .. extra_max */
	const float *cosr;  /* |cos(ray, surface normal)| of each pixel */
	int where;          /* 0: everywhere, 1: only where the estimate is over 1.5 times
			     * the scaled truth, -1: only where under 1 / 1.5 times */
	float *estimate;    /* the estimate is copied here (if not NULL) */
	float *depth;       /* the depth the pass saw is copied here (if not NULL) */
} sub;

static atomic_long column_passes; /* the wrapper was called (pool threads run it) */

void __real_dao_thickness_cols(const struct dao_thickness_setup *t, const float *z, float *thick,
			       float *scratch, struct dao_gtao_planes *pl, int x0, int x1);
void __wrap_dao_thickness_cols(const struct dao_thickness_setup *t, const float *z, float *thick,
			       float *scratch, struct dao_gtao_planes *pl, int x0, int x1);

void __wrap_dao_thickness_cols(const struct dao_thickness_setup *t, const float *z, float *thick,
			       float *scratch, struct dao_gtao_planes *pl, int x0, int x1)
{
	__real_dao_thickness_cols(t, z, thick, scratch, pl, x0, x1);
	atomic_fetch_add_explicit(&column_passes, 1, memory_order_relaxed);
	for (int y = 0; y < t->height; y++)
		for (int x = x0; x < x1; x++) {
			const size_t i = (size_t)y * t->width + x;
			if (sub.estimate)
				sub.estimate[i] = thick[i];
			if (sub.depth)
				sub.depth[i] = z[i];
			if (sub.truth) {
				float v = sub.scale * sub.truth[i] + sub.add;
				if (sub.extra_max > 0.0f) {
					float xa = (sub.scale - 1.0f) * sub.truth[i];
					float em = sub.extra_max;
					if (sub.add_sec < 0.0f) {
						const float cr = sub.cosr[i] > 1e-3f ? sub.cosr[i] : 1e-3f;
						em = -sub.add_sec / cr;
					}
					xa = xa > em ? em : xa;
					xa = xa < sub.add ? sub.add : xa;
					v = sub.truth[i] + xa;
				}
				if (sub.add_tan != 0.0f || sub.add_sec > 0.0f) {
					const float cr = sub.cosr[i] > 1e-3f ? sub.cosr[i] : 1e-3f;
					v += sub.add_sec / cr +
					     sub.add_tan * sqrtf(fmaxf(0.0f, 1.0f - cr * cr)) / cr;
				}
				v = v < sub.cap ? v : sub.cap;
				if (!sub.where || (sub.where > 0 && thick[i] > 1.5f * v) ||
				    (sub.where < 0 && 1.5f * thick[i] < v))
					thick[i] = v;
			}
		}
	if (pl && sub.truth)
		dao_gtao_planes_fill_thickness_cols(pl, thick, 0, t->height, x0, x1);
}

/* The columns: GTAO, VBAO with the estimate, VBAO with the truth scaled and capped. */
struct column {
	const char *name;
	int algorithm;
	int truth;
	float scale, cap;
	int constant; /* VBAO with its constant 0.2 m instead */
	int where;    /* sub.where */
	float add;    /* sub.add */
	float add_tan, add_sec;
	float extra_max;
};

#define TRUTH(k, c, w, a) .algorithm = DAO_ALGORITHM_VBAO, .truth = 1, .scale = k, .cap = c, \
			  .where = w, .add = a
static const struct column columns[] = {
	{ "gtao", .algorithm = DAO_ALGORITHM_GTAO },
	{ "vbao estimate", .algorithm = DAO_ALGORITHM_VBAO },
	{ "truth x1", TRUTH(1.0f, 0.5f, 0, 0.0f) },
	{ "truth x2", TRUTH(2.0f, 0.5f, 0, 0.0f) },
	{ "truth x3", TRUTH(3.0f, 0.5f, 0, 0.0f) },
	{ "truth x4", TRUTH(4.0f, 0.5f, 0, 0.0f) },
	{ "truth x6", TRUTH(6.0f, 0.5f, 0, 0.0f) },
	{ "truth x3, cap 10 m", TRUTH(3.0f, 10.0f, 0, 0.0f) },
	{ "truth + 4 cm", TRUTH(1.0f, 0.5f, 0, 0.04f) },
	{ "truth + 8 cm", TRUTH(1.0f, 0.5f, 0, 0.08f) },
	{ "truth + 12 cm", TRUTH(1.0f, 0.5f, 0, 0.12f) },
	{ "truth + 11 cm tan", TRUTH(1.0f, 0.5f, 0, 0.0f), .add_tan = 0.11f },
	{ "truth + 5.5 cm tan", TRUTH(1.0f, 0.5f, 0, 0.0f), .add_tan = 0.055f },
	{ "truth + 8 cm + 11 cm tan", TRUTH(1.0f, 0.5f, 0, 0.08f), .add_tan = 0.11f },
	{ "truth + 8 cm + 5.5 cm tan", TRUTH(1.0f, 0.5f, 0, 0.08f), .add_tan = 0.055f },
	{ "max(x3, +11 cm)", TRUTH(3.0f, 0.5f, 0, 0.11f), .extra_max = 10.0f },
	{ "max(x3, +8 cm)", TRUTH(3.0f, 0.5f, 0, 0.08f), .extra_max = 10.0f },
	{ "x3 within +8..15 cm", TRUTH(3.0f, 0.5f, 0, 0.08f), .extra_max = 0.15f },
	{ "x3 within +8..20 cm", TRUTH(3.0f, 0.5f, 0, 0.08f), .extra_max = 0.20f },
	{ "x3 within +8..30 cm", TRUTH(3.0f, 0.5f, 0, 0.08f), .extra_max = 0.30f },
	{ "x3 within +11..20 cm", TRUTH(3.0f, 0.5f, 0, 0.11f), .extra_max = 0.20f },
	{ "x3 within +11..5.5 sec", TRUTH(3.0f, 0.5f, 0, 0.11f), .extra_max = 1.0f, .add_sec = -0.055f },
	{ "x3 within +8..4 sec", TRUTH(3.0f, 0.5f, 0, 0.08f), .extra_max = 1.0f, .add_sec = -0.04f },
	{ "x3 within +8..8 sec", TRUTH(3.0f, 0.5f, 0, 0.08f), .extra_max = 1.0f, .add_sec = -0.08f },
	{ "truth + 8 cm sec", TRUTH(1.0f, 0.5f, 0, 0.0f), .add_sec = 0.08f },
	{ "truth + 11 cm sec", TRUTH(1.0f, 0.5f, 0, 0.0f), .add_sec = 0.11f },
	{ "x3 where est too thick", TRUTH(3.0f, 0.5f, 1, 0.0f) },
	{ "x3 where est too thin", TRUTH(3.0f, 0.5f, -1, 0.0f) },
	{ "vbao 0.2 m", .algorithm = DAO_ALGORITHM_VBAO, .constant = 1 },
};
#undef TRUTH
#define NCOL (int)(sizeof columns / sizeof columns[0])

static int dump(const char *dir, const char *scene, int variant, const char *what, const float *p,
		size_t n)
{
	char path[1024];
	snprintf(path, sizeof path, "%s/%s-%d-%s.f32", dir, scene, variant, what);
	for (char *c = path + strlen(dir) + 1; *c; c++)
		if (*c == ' ' || *c == ',')
			*c = '_';
	FILE *f = fopen(path, "wb");
	if (!f || fwrite(p, sizeof(float), n, f) != n) {
		fprintf(stderr, "thickness-ceiling: cannot write %s\n", path);
		if (f)
			fclose(f);
		return -1;
	}
	return fclose(f);
}

int main(int argc, char **argv)
{
	enum synth_set set = SYNTH_SET_TUNE;
	int rays_sqrt = 8, variants = 1;
	enum synth_sensor sensor = SYNTH_SENSOR_CLEAN;
	const char *dir = NULL;
	const char *scenes[SYNTH_SUITE_MAX_IMAGES + 1];
	int ns = 0;
	for (int i = 1; i < argc; i++) {
		struct dao_error err;
		if (strcmp(argv[i], "--set") == 0 && i + 1 < argc) {
			if (synth_set_parse(argv[++i], &set, &err)) {
				fprintf(stderr, "thickness-ceiling: %s\n", err.message);
				return 2;
			}
		} else if (strcmp(argv[i], "--rays") == 0 && i + 1 < argc) {
			const long n = strtol(argv[++i], NULL, 10), r = lrint(sqrt((double)n));
			if (n < 1 || n > 65536 || r * r != n) {
				fprintf(stderr, "thickness-ceiling: --rays %s must be a perfect square "
					"in 1..65536\n", argv[i]);
				return 2;
			}
			rays_sqrt = (int)r;
		} else if (strcmp(argv[i], "--variants") == 0 && i + 1 < argc) {
			variants = atoi(argv[++i]);
			if (variants < 1 || variants > 16) {
				fprintf(stderr, "thickness-ceiling: --variants %s must be in 1..16\n",
					argv[i]);
				return 2;
			}
		} else if (strcmp(argv[i], "--sensor") == 0 && i + 1 < argc) {
			if (synth_sensor_parse(argv[++i], &sensor, &err)) {
				fprintf(stderr, "thickness-ceiling: %s\n", err.message);
				return 2;
			}
		} else if (strcmp(argv[i], "--dump") == 0 && i + 1 < argc) {
			dir = argv[++i];
		} else if (argv[i][0] != '-' && ns < SYNTH_SUITE_MAX_IMAGES) {
			scenes[ns++] = argv[i];
		} else {
			fprintf(stderr, "usage: thickness-ceiling [--set tune|heldout] [--rays N] "
				"[--variants N] [--sensor NAME] [--dump DIR] SCENE...\n");
			return 2;
		}
	}
	if (ns == 0) {
		fprintf(stderr, "thickness-ceiling: name the scenes (e.g. panels shelves-below)\n");
		return 2;
	}
	scenes[ns] = NULL;
	struct synth_suite_spec spec = { .scenes = scenes, .radius = 0.5, .rays_sqrt = rays_sqrt,
					 .sensors = &sensor, .nsensors = 1, .seed = 1, .threads = 2 };
	synth_suite_spec_set(&spec, set, variants);
	static struct synth_suite suite;
	struct dao_error err;
	if (synth_suite_load_spec(&suite, &spec, &err)) {
		fprintf(stderr, "thickness-ceiling: %s\n", err.message);
		return 1;
	}
	const size_t np = (size_t)suite.cam.width * suite.cam.height;
	float *ao = malloc(np * sizeof(float)), *truth = malloc(np * sizeof(float));
	float *est = malloc(np * sizeof(float)), *cosr = malloc(np * sizeof(float));
	float *pre = malloc(np * sizeof(float));
	if (!ao || !truth || !est || !cosr || !pre) {
		fprintf(stderr, "thickness-ceiling: out of memory\n");
		return 1;
	}
	printf("| scene | %s", columns[0].name);
	for (int k = 1; k < NCOL; k++)
		printf(" | %s", columns[k].name);
	printf(" |\n|---|");
	for (int k = 0; k < NCOL; k++)
		printf("---:|");
	printf("\n");
	double sum[NCOL] = { 0 };
	for (int c = 0; c < suite.count; c++) {
		const struct synth_case *sc = &suite.cases[c];
		struct synth_scene scene;
		if (synth_scene_build_variant(sc->scene, 0.0, sc->variant, &scene, &err)) {
			fprintf(stderr, "thickness-ceiling: %s\n", err.message);
			return 1;
		}
		synth_inside_plane(&scene, &suite.cam, truth);
		for (int y = 0; y < (int)suite.cam.height; y++)
			for (int x = 0; x < (int)suite.cam.width; x++) {
				const struct dao_camera *cm = &suite.cam;
				const vec3 d = v3_normalize(v3((x - cm->cx) / cm->fx,
							       (y - cm->cy) / cm->fy, 1.0));
				double t;
				vec3 nn;
				const int prim = synth_trace(&scene, v3(0, 0, 0), d, 0.0, 1e9, &t, &nn);
				cosr[(size_t)y * cm->width + x] =
					prim < 0 ? 1.0f : (float)fabs(v3_dot(d, nn));
			}
		sub.cosr = cosr;
		if (sc->variant)
			printf("| %s #%d |", sc->scene, sc->variant);
		else
			printf("| %s |", sc->scene);
		for (int k = 0; k < NCOL; k++) {
			struct dao_params p;
			dao_params_init(&p, DAO_QUALITY_MEDIUM);
			p.algorithm = columns[k].algorithm;
			p.vbao_thickness_mode = columns[k].constant ? DAO_VBAO_THICKNESS_CONSTANT
							       : DAO_VBAO_THICKNESS_IMAGE;
			p.threads = 2;
			struct dao_context *ctx;
			if (dao_context_create(&ctx, &suite.cam, &p, &err)) {
				fprintf(stderr, "thickness-ceiling: %s\n", err.message);
				return 1;
			}
			sub.truth = columns[k].truth ? truth : NULL;
			sub.scale = columns[k].scale;
			sub.cap = columns[k].cap;
			sub.where = columns[k].where;
			sub.add = columns[k].add;
			sub.add_tan = columns[k].add_tan;
			sub.add_sec = columns[k].add_sec;
			sub.extra_max = columns[k].extra_max;
			sub.estimate = est;
			sub.depth = pre;
			struct synth_metrics m;
			double ms;
			if (synth_suite_run_case(&suite, c, ctx, ao, &m, &ms, &err)) {
				fprintf(stderr, "thickness-ceiling: %s\n", err.message);
				return 1;
			}
			dao_context_destroy(ctx);
			if (columns[k].algorithm == DAO_ALGORITHM_VBAO && !columns[k].constant &&
			    atomic_exchange(&column_passes, 0) == 0) {
				/* the pipeline no longer calls the column pass: nothing was measured */
				fprintf(stderr, "thickness-ceiling: the pipeline did not call "
					"dao_thickness_cols, so the truth never reached VBAO; wrap the "
					"function that now fills the thickness plane\n");
				return 1;
			}
			sum[k] += m.mae;
			printf(" %.4f |", m.mae);
			if (dir && dump(dir, sc->scene, sc->variant, columns[k].name, ao, np))
				return 1;
			fflush(stdout);
		}
		printf("\n");
		if (dir && (dump(dir, sc->scene, sc->variant, "depth", sc->depth_m, np) ||
			    dump(dir, sc->scene, sc->variant, "gt", sc->gt, np) ||
			    dump(dir, sc->scene, sc->variant, "truth", truth, np) ||
			    dump(dir, sc->scene, sc->variant, "prefiltered", pre, np) ||
			    dump(dir, sc->scene, sc->variant, "estimate", est, np)))
			return 1;
	}
	printf("| **mean** |");
	for (int k = 0; k < NCOL; k++)
		printf(" **%.4f** |", sum[k] / suite.count);
	printf("\n");
	free(pre);
	free(cosr);
	free(est);
	free(truth);
	free(ao);
	synth_suite_free(&suite);
	return 0;
}
