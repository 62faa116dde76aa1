/* SPDX-License-Identifier: MIT */
/*
 * Every optimised kernel set against the scalar reference, in the manner of
 * FFmpeg's checkasm: the same inputs through simd=reference and through each
 * instruction set this CPU has, stage by stage and end to end, on synthetic
 * scenes (clean and with sensor noise) and on the real frames in
 * ../shared/data.  The bounds are stated in docs/performance.md.  The AO kernels'
 * cases beyond the first of each are compared on bands of rows (struct rows), and
 * the reference depth and normals of each input are made once (planes_of()): the
 * scalar references of GTAO and VBAO are most of the run's time.
 */
#include "common/cmocka_all.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/depthao.h>

#include "core/half.h"
#include "core/math_util.h"
#include "denoise/denoise.h"
#include "depth/domain.h"
#include "depth/prefilter.h"
#include "kernels/ao_variants.h"
#include "kernels/gtao.h"
#include "kernels/gtao_tile.h"
#include "pipeline/kernels.h"
#include "pipeline/temporal_depth.h"
#include "normals/normals.h"
#include "shade/shade.h"
#include "simd/fastmath_check.h"
#include "synth/synth.h"
#include "common/test_common.h"

/* bounds, optimised vs reference (measured on this project's machine in brackets) */
#define PREFILTER_MAX_REL 2e-6    /* prefiltered depth, relative [1.2e-6] */
/* prefilter=domain, filtered depth relative to the reference: float rounding
 * (the refined hardware reciprocal of sigma, fused or separate
 * multiply-adds, the link weight's among them), which a local linear fit from few, one-sided
 * samples amplifies where the depth is ragged (1/z in and out are divisions:
 * with the refined 12-bit estimate there, a jumble of edges in the RealSense
 * frame reached 2.2e-5); with side windows the blend of the one-sided fits
 * follows the residual variance T2 - a T0 - b T1, a difference of sums
 * whose rounding is relative to T2, not to the residual: where the residual
 * is near the side test's threshold the blend moves with it (clean stairs,
 * at a crease: 1.8e-5; since the side test's 1 / sigma^2 is the link's
 * refined reciprocal squared, not a division, 2.2e-5 there with AVX2 and
 * 2.4e-5 on the RealSense frame with AVX-512; 1.05e-5 since the reference
 * computes the link weight as the kernels do, not with libm's exp) */
#define DOMAIN_MAX_REL 1e-4       /* largest [1.05e-5] */
#define DOMAIN_MEAN_REL 2e-8      /* mean over the pixels [5.4e-9] */
#define DENOISE_MAX_ABS 1e-6      /* plane denoise output [2.4e-7] */
#define NORMALS_MAX_ABS 1e-5      /* normal components (FMA contraction differs) */
#define GTAO_MAE 2e-6             /* GTAO kernel on identical inputs [3.9e-7] */
#define GTAO_P999 1e-4            /* 99.9th percentile of |difference| [2.7e-5] */
#define GTAO_MAX 0.05             /* a sample snapping to the other pixel of a tie [0.012] */
/* the tile kernel uses the hardware estimates of 1/sqrt (horizon cosine, and
 * sqrt(x) = x / sqrt(x) for the sines) and 1/z (falloff distance), relative
 * error < 3.7e-4 each, and the 4-term acos (4.2e-4 absolute with them) */
#define GTAO_TILE_MAE 1e-4        /* [3.4e-5] */
#define GTAO_TILE_P999 3e-3       /* [6.7e-4] */
/* VBAO tile kernel (precise cosines and acos: a sector edge rounds other
 * than the reference's only where the two differ in the last bits; the same
 * kernel with 5 % thicker occluders measured MAE >= 1.9e-4) */
#define VBAO_MAE 5e-6             /* [1.1e-6] */
#define VBAO_P999 5e-5            /* [1.6e-5] */
#define VBAO_MAX 0.1              /* one sector rounded the other way [0.057] */
/* HBAO tile kernel: the reference's very taps; precise 1/sqrt and 1/z, depth
 * from the 1/z plane (within an ulp), fused multiply-adds.  Its result is
 * continuous in every rounded value (a horizon update that turns the other
 * way at a tie changes it by the tie's difference), so the largest error
 * stays small too.  The same kernel with a 5 % larger tangent bias measured
 * MAE >= 1.0e-3, p99.9 >= 8.9e-3. */
#define HBAO_MAE 2e-7             /* [4.2e-8] */
#define HBAO_P999 1e-5            /* [1.9e-6] */
#define HBAO_MAX 1e-4             /* [1.2e-5] */
#define PIPELINE_MAE 5e-5         /* whole dao_context_process, default (tile) [1.6e-5] */

/* the tile kernels' working memory (a thread's, as the context allocates it) */
static struct dao_tile_scratch *scratch;

struct input {
	char name[64];
	struct dao_camera cam;
	float *depth; /* metres */
};

static struct input inputs[16];
static int ninputs;

static void add_synth(const char *scene, int noisy)
{
	struct input *in = &inputs[ninputs];
	struct synth_scene sc;
	struct synth_image img;
	assert_int_equal(synth_scene_build(scene, 0.0, &sc, NULL), 0);
	synth_default_camera(&in->cam);
	assert_int_equal(synth_render(&sc, &in->cam, 0.5, 0, 2, &img, NULL), 0);
	if (noisy)
		synth_sensor_noise(img.depth, img.width, img.height, 0.0012, 0.001, 0.01, 7);
	in->depth = img.depth;
	img.depth = NULL;
	synth_image_free(&img);
	snprintf(in->name, sizeof in->name, "%s%s", scene, noisy ? " noisy" : "");
	ninputs++;
}

static void add_real(const char *rel, float unit, double fx, double fy, double cx, double cy)
{
	char path[512];
	if (dao_test_data_path(rel, path, sizeof path)) {
		print_message("skipping %s: ../shared/data not found\n", rel);
		return;
	}
	struct input *in = &inputs[ninputs];
	struct dao_frame f;
	struct dao_error err;
	if (dao_png_read_depth(path, unit, &f, &err))
		fail_msg("%s: %s", rel, err.message);
	assert_int_equal(dao_camera_from_intrinsics(&in->cam, f.width, f.height, fx, fy, cx, cy, NULL), 0);
	in->depth = malloc((size_t)f.width * f.height * sizeof(float));
	for (uint32_t y = 0; y < f.height; y++)
		for (uint32_t x = 0; x < f.width; x++) {
			uint16_t v;
			memcpy(&v, (const char *)f.data + y * f.stride + 2 * x, 2);
			in->depth[y * f.width + x] = (float)v * unit;
		}
	dao_frame_free(&f);
	snprintf(in->name, sizeof in->name, "%s", rel);
	ninputs++;
}

static int setup(void **state)
{
	(void)state;
	static const char *const scenes[] = { "room-corner", "stairs", "boxes", "thin-pole" };
	for (int i = 0; i < 4; i++) {
		add_synth(scenes[i], 0);
		add_synth(scenes[i], 1);
	}
	add_real("redwood_open3d/depth_00000.png", 0.001f, 525, 525, 319.5, 239.5);
	add_real("tum_open3d/TUM_depth.png", 0.0002f, 525, 525, 319.5, 239.5);
	add_real("realsense_6dpose/depth.png", 0.001f, 622.439, 622.439, 315.746, 250.804);
	scratch = malloc(sizeof *scratch);
	assert_non_null(scratch);
	return 0;
}

/* The optimised sets this CPU can run. */
static int optimised_sets(enum dao_simd *out)
{
	int n = 0;
	for (int s = DAO_SIMD_GENERIC; s < DAO_SIMD_COUNT; s++)
		if (dao_simd_supported((enum dao_simd)s))
			out[n++] = (enum dao_simd)s;
	return n;
}

struct diff {
	double mae, max, p999;
	long n;
};

/* The k-th smallest of e[0..n), reordering e (Wirth's selection: a sort's
 * value in linear time). */
static float kth_smallest(float *e, long n, long k)
{
	long l = 0, m = n - 1;
	while (l < m) {
		const float x = e[k];
		long i = l, j = m;
		do {
			while (e[i] < x)
				i++;
			while (x < e[j])
				j--;
			if (i <= j) {
				const float t = e[i];
				e[i++] = e[j];
				e[j--] = t;
			}
		} while (i <= j);
		if (j < k)
			l = i;
		if (k < i)
			m = j;
	}
	return e[k];
}

static struct diff compare(const float *a, const float *b, size_t n, int relative)
{
	struct diff d = { 0 };
	float *e = malloc(n * sizeof *e);
	assert_non_null(e);
	for (size_t i = 0; i < n; i++) {
		if (isnan(a[i]) != isnan(b[i]))
			fail_msg("NaN in one result only at %zu", i);
		double v = fabs((double)a[i] - b[i]);
		if (relative && a[i] != 0.0f)
			v /= fabs(a[i]);
		e[d.n++] = (float)v;
		d.mae += v;
		if (v > d.max)
			d.max = v;
	}
	d.p999 = kth_smallest(e, (long)n, (long)(0.999 * (double)(n - 1)));
	d.mae /= (double)n;
	free(e);
	return d;
}

/* Reference prefilter + normals of an input, as the pipeline feeds the kernels. */
struct planes {
	int w, h;
	float *z, *n;
	struct dao_gtao_planes gp; /* both the bordered and the phase plane */
};

static void make_planes(const struct input *in, struct planes *p)
{
	struct dao_params prm;
	dao_params_init(&prm, DAO_QUALITY_DEFAULT);
	prm.simd = DAO_SIMD_REFERENCE;
	prm.threads = 2;
	prm.slices = 1; /* only depth and normals are used */
	prm.steps = 1;
	p->w = (int)in->cam.width;
	p->h = (int)in->cam.height;
	size_t np = (size_t)p->w * p->h;
	p->z = malloc(np * 4);
	p->n = malloc(np * 12);
	assert_int_equal(dao_gtao_planes_init(&p->gp, p->w, p->h, 160.0f), 0);
	struct dao_context *ctx;
	assert_int_equal(dao_context_create(&ctx, &in->cam, &prm, NULL), 0);
	struct dao_frame d = { .format = DAO_PIXFMT_DEPTH_F32, .width = in->cam.width,
			       .height = in->cam.height, .stride = 4 * p->w, .data = in->depth };
	assert_int_equal(dao_context_process(ctx, &d, NULL, 0, NULL, NULL), 0);
	struct dao_frame zf = { .format = DAO_PIXFMT_DEPTH_F32, .width = d.width, .height = d.height,
				.stride = 4 * p->w, .data = p->z };
	struct dao_frame nf = { .format = DAO_PIXFMT_NORMAL_F32, .width = d.width, .height = d.height,
				.stride = 12 * p->w, .data = p->n };
	assert_int_equal(dao_context_get_depth(ctx, &zf, NULL), 0);
	assert_int_equal(dao_context_get_normals(ctx, &nf, NULL), 0);
	dao_context_destroy(ctx);
	dao_gtao_planes_fill(&p->gp, p->z, 0, 0, p->h);
	dao_gtao_planes_fill(&p->gp, p->z, 1, 0, p->h);
}

/* The planes of input i, made (with the scalar code) when a test first asks for them:
 * the same for every test of the run; freed by teardown(). */
static struct planes planes[16];

static const struct planes *planes_of(int i)
{
	if (!planes[i].z)
		make_planes(&inputs[i], &planes[i]);
	return &planes[i];
}

static int teardown(void **state)
{
	(void)state;
	for (int i = 0; i < ninputs; i++) {
		free(inputs[i].depth);
		if (planes[i].z)
			dao_gtao_planes_free(&planes[i].gp);
		free(planes[i].z);
		free(planes[i].n);
	}
	free(scratch);
	return 0;
}

static void test_prefilter(void **state)
{
	(void)state;
	enum dao_simd sets[DAO_SIMD_COUNT];
	int ns = optimised_sets(sets);
	for (int i = 0; i < ninputs; i++) {
		const struct input *in = &inputs[i];
		const int w = (int)in->cam.width, h = (int)in->cam.height;
		const size_t np = (size_t)w * h;
		struct dao_prefilter_setup s;
		dao_prefilter_setup_init(&s, w, h, 3, 0.0012f, 0.001f);
		float *tmp = malloc(np * 4), *ref = malloc(np * 4), *opt = malloc(np * 4);
		dao_prefilter_h_ref(&s, in->depth, tmp, 0, h);
		dao_prefilter_v_ref(&s, tmp, ref, 0, h);
		for (int k = 0; k < ns; k++) {
			struct dao_kernels kr;
			dao_kernels_select(&kr, sets[k]);
			kr.prefilter_h(&s, in->depth, tmp, 0, h);
			kr.prefilter_v(&s, tmp, opt, 0, h);
			struct diff d = compare(ref, opt, np, 1);
			print_message("prefilter %-8s %-34s max rel %.2e\n", dao_simd_name(sets[k]),
				      in->name, d.max);
			for (size_t p = 0; p < np; p++)
				if ((ref[p] == 0.0f) != (opt[p] == 0.0f))
					fail_msg("hole mismatch at %zu", p);
			assert_true(d.max <= PREFILTER_MAX_REL);
		}
		free(tmp);
		free(ref);
		free(opt);
	}
}

/*
 * prefilter=domain, every pass and the whole filter: fixed scales (2 and
 * 8 px) with the depth quantum of the input, and per-cell noise and scale
 * (cells of 32 px, values ramping over the frame with a jitter, bilinear
 * between the cells as the noise estimate's are), with side windows (as the
 * pipeline runs it) and at 8 px without.
 */
static void test_domain(void **state)
{
	(void)state;
	enum dao_simd sets[DAO_SIMD_COUNT];
	int ns = optimised_sets(sets);
	for (int i = 0; i < ninputs; i++) {
		const struct input *in = &inputs[i];
		const int w = (int)in->cam.width, h = (int)in->cam.height;
		const size_t np = (size_t)w * h;
		float *tmp = malloc(np * 4), *ref = malloc(np * 4), *opt = malloc(np * 4);
		const int span = 32, cx = (w + span - 1) / span, cy = (h + span - 1) / span;
		float *cells = malloc(2 * (size_t)cx * cy * sizeof(float));
		float *sc = malloc(dao_domain_scratch_floats(w, h) * sizeof(float));
		assert_non_null(cells);
		assert_non_null(sc);
		for (int y = 0; y < cy; y++)
			for (int x = 0; x < cx; x++) {
				const float jitter = (float)((x * 7 + y * 13) % 5) / 5.0f;
				cells[y * cx + x] = 0.0005f + 0.002f * (float)x / (float)cx +
						    0.0004f * jitter;
				cells[cx * cy + y * cx + x] =
					1.0f / (1.5f + 10.0f * (float)y / (float)cy + 2.0f * jitter);
			}
		for (int mode = 0; mode < 4; mode++) {
			struct dao_domain_setup s = {
				.width = w, .height = h, .iterations = 3,
				.inv_scale = mode == 0 ? 0.5f : 0.125f,
				.range_coef = dao_domain_range_coef(3.0f),
				.noise = 0.0012f, .unit = 0.001f,
				.sides = mode != 3,
			};
			if (mode == 2) {
				s.noise_cells = cells, s.inv_scale_cells = cells + cx * cy;
				s.cells_x = cx, s.cells_y = cy, s.cell_span = span;
			}
			dao_domain_filter(&s, dao_domain_pass_ref, in->depth, tmp, ref, sc);
			for (int k = 0; k < ns; k++) {
				struct dao_kernels kr;
				dao_kernels_select(&kr, sets[k]);
				dao_domain_filter(&s, kr.domain_pass, in->depth, tmp, opt, sc);
				struct diff d = compare(ref, opt, np, 1);
				print_message("domain %-3s %-8s %-34s max rel %.2e mean %.2e\n",
					      mode == 0 ? "2" : mode == 1 ? "8" : mode == 2 ? "map" : "8-1",
					      dao_simd_name(sets[k]), in->name, d.max, d.mae);
				for (size_t p = 0; p < np; p++)
					if ((ref[p] == 0.0f) != (opt[p] == 0.0f) ||
					    (ref[p] == 0.0f) != (in->depth[p] <= 0.0f))
						fail_msg("hole mismatch at %zu", p);
				assert_true(d.max <= DOMAIN_MAX_REL);
				assert_true(d.mae <= DOMAIN_MEAN_REL);
			}
		}
		free(tmp);
		free(ref);
		free(opt);
		free(cells);
		free(sc);
	}
}

static void test_normals(void **state)
{
	(void)state;
	enum dao_simd sets[DAO_SIMD_COUNT];
	int ns = optimised_sets(sets);
	for (int i = 0; i < ninputs; i++) {
		const struct planes *p = planes_of(i);
		const size_t np = (size_t)p->w * p->h;
		float *ref = malloc(np * 12), *opt = malloc(np * 12);
		for (int r = 1; r <= 4; r += 3) {
			dao_normals_from_depth(&inputs[i].cam, p->z, r, ref, 0, p->h);
			for (int k = 0; k < ns; k++) {
				struct dao_kernels kr;
				dao_kernels_select(&kr, sets[k]);
				memset(opt, 0xff, np * 12);
				kr.normals(&inputs[i].cam, p->z, r, opt, 0, p->h);
				struct diff d = compare(ref, opt, 3 * np, 0);
				print_message("normals r%d %-8s %-34s max %.2e\n", r, dao_simd_name(sets[k]),
					      inputs[i].name, d.max);
				assert_true(d.max <= NORMALS_MAX_ABS);
			}
		}
		free(ref);
		free(opt);
	}
}

/* The phase plane of every kernel set equals the scalar fill's, bit for bit
 * (make_planes filled p->gp with the scalar code). */
static void test_planes_fill(void **state)
{
	(void)state;
	enum dao_simd sets[DAO_SIMD_COUNT];
	int ns = optimised_sets(sets);
	for (int i = 0; i < ninputs; i++) {
		const struct planes *p = planes_of(i);
		const size_t n = ((size_t)p->h + 2) * 4 * (size_t)p->gp.stride4;
		const float *want = dao_gtao_phase_row(&p->gp, -1, 0) - p->gp.pad4;
		for (int k = 0; k < ns; k++) {
			struct dao_gtao_planes got;
			assert_int_equal(dao_gtao_planes_init(&got, p->w, p->h, 160.0f), 0);
			struct dao_kernels kr;
			dao_kernels_select(&kr, sets[k]);
			kr.planes_fill(&got, p->z, 1, 0, p->h);
			const float *g = dao_gtao_phase_row(&got, -1, 0) - got.pad4;
			print_message("planes %-8s %-34s %s\n", dao_simd_name(sets[k]), inputs[i].name,
				      memcmp(want, g, n * sizeof(float)) ? "DIFFERS" : "identical");
			assert_memory_equal(want, g, n * sizeof(float));
			dao_gtao_planes_free(&got);
		}
	}
}

static void test_shade(void **state)
{
	(void)state;
	enum dao_simd sets[DAO_SIMD_COUNT];
	int ns = optimised_sets(sets);
	for (int i = 0; i < ninputs; i++) {
		const struct planes *p = planes_of(i);
		const size_t np = (size_t)p->w * p->h;
		float *ao = malloc(np * 4);
		unsigned seed = 9;
		for (size_t k = 0; k < np; k++) {
			seed = seed * 1103515245u + 12345u;
			ao[k] = (float)((seed >> 8) & 0xffff) / 60000.0f - 0.02f; /* a little outside [0, 1] */
		}
		struct dao_frame ref, opt;
		assert_int_equal(dao_frame_alloc(&ref, DAO_PIXFMT_RGB24, (uint32_t)p->w, (uint32_t)p->h, NULL), 0);
		assert_int_equal(dao_frame_alloc(&opt, DAO_PIXFMT_RGB24, (uint32_t)p->w, (uint32_t)p->h, NULL), 0);
		const struct dao_camera *c = &inputs[i].cam;
		struct dao_shade_setup ss = {p->w, p->h, c->ax, c->ay, c->bx, c->by, DAO_SHADE_LAMBERT,
					     0.5f, 5.0f, 1.0f, {30, 20, 10}, NULL};
		dao_shade(&ss, p->z, p->n, ao, &ref, 0, p->h);
		for (int k = 0; k < ns; k++) {
			struct dao_kernels kr;
			dao_kernels_select(&kr, sets[k]);
			memset(opt.data, 0x55, np * 3);
			kr.shade(&ss, p->z, p->n, ao, &opt, 0, p->h);
			print_message("shade     %-8s %-34s %s\n", dao_simd_name(sets[k]), inputs[i].name,
				      memcmp(ref.data, opt.data, np * 3) ? "DIFFERS" : "identical");
			assert_memory_equal(ref.data, opt.data, np * 3);
		}
		dao_frame_free(&ref);
		dao_frame_free(&opt);
		free(ao);
	}
}

static void test_denoise(void **state)
{
	(void)state;
	enum dao_simd sets[DAO_SIMD_COUNT];
	int ns = optimised_sets(sets);
	for (int i = 0; i < ninputs; i++) {
		const struct planes *p = planes_of(i);
		const size_t np = (size_t)p->w * p->h;
		float *ao = malloc(np * 4), *ref = malloc(np * 4), *opt = malloc(np * 4);
		unsigned seed = 5;
		for (size_t k = 0; k < np; k++) { /* noisy AO to smooth */
			seed = seed * 1103515245u + 12345u;
			ao[k] = (float)((seed >> 8) & 0xffff) / 65535.0f;
		}
		struct dao_denoise_setup s = { .width = p->w, .height = p->h, .noise_k = 0.0012f,
					       .sharpness = 4.0f, .radius = 4, .invalid_value = 1.0f };
		dao_denoise_plane(&s, p->z, ao, ref, 0, p->h);
		for (int k = 0; k < ns; k++) {
			struct dao_kernels kr;
			dao_kernels_select(&kr, sets[k]);
			kr.denoise_plane(&s, p->z, ao, opt, 0, p->h);
			struct diff d = compare(ref, opt, np, 0);
			print_message("denoise   %-8s %-34s max %.2e\n", dao_simd_name(sets[k]),
				      inputs[i].name, d.max);
			assert_true(d.max <= DENOISE_MAX_ABS);
		}
		free(ao);
		free(ref);
		free(opt);
	}
}

/*
 * The rows an AO case is compared on.  The first cases of each kernel (two slices of
 * six steps, on every input) are compared on whole frames; the cases that take other
 * code paths (more slices and steps, the other noises, odd slice counts) on three
 * bands of rows, a quarter of the frame: the top and the bottom, where taps fall off
 * the image, and the middle.  A band is computed alone as the pipeline's threads
 * compute theirs, with the values of the whole frame's rows (simd-odd-sizes checks
 * that of every kernel), so a band costs its share of the frame, for the reference
 * too.  The strips (x_begin, x_end) are checked on the bands in every case.
 */
struct rows {
	int n, y0[3], y1[3];
};

static struct rows row_bands(int h, int banded)
{
	const int b = h / 12;
	if (!banded || b < 1)
		return (struct rows){ .n = 1, .y0 = { 0 }, .y1 = { h } };
	return (struct rows){ .n = 3, .y0 = { 0, (h - b) / 2, h - b }, .y1 = { b, (h + b) / 2, h } };
}

/* compare() over the rows `r` of two planes w floats wide */
static struct diff compare_rows(const float *a, const float *b, int w, const struct rows *r)
{
	size_t n = 0, at = 0;
	for (int k = 0; k < r->n; k++)
		n += (size_t)(r->y1[k] - r->y0[k]) * w;
	float *ga = malloc(n * 4), *gb = malloc(n * 4);
	assert_true(ga && gb);
	for (int k = 0; k < r->n; k++) {
		const size_t off = (size_t)r->y0[k] * w, len = (size_t)(r->y1[k] - r->y0[k]) * w;
		memcpy(ga + at, a + off, len * 4);
		memcpy(gb + at, b + off, len * 4);
		at += len;
	}
	struct diff d = compare(ga, gb, n, 0);
	free(ga);
	free(gb);
	return d;
}

/* The rows `r` of two planes w floats wide hold the same bits. */
static void assert_rows_equal(const float *a, const float *b, int w, const struct rows *r)
{
	for (int k = 0; k < r->n; k++)
		assert_memory_equal(a + (size_t)r->y0[k] * w, b + (size_t)r->y0[k] * w,
				    (size_t)(r->y1[k] - r->y0[k]) * w * 4);
}

static void gtao_case(const struct planes *p, const struct input *in, int slices, int steps,
		      float thickness, int noise, int banded)
{
	enum dao_simd sets[DAO_SIMD_COUNT];
	int ns = optimised_sets(sets);
	const size_t np = (size_t)p->w * p->h;
	const struct rows r = row_bands(p->h, banded), sr = row_bands(p->h, 1);
	struct dao_params prm;
	dao_params_init(&prm, DAO_QUALITY_DEFAULT);
	prm.slices = slices;
	prm.steps = steps;
	prm.thickness = thickness;
	prm.noise = noise;
	struct dao_gtao_setup s;
	dao_gtao_setup_init(&s, &in->cam, &prm, 3);
	static float tile[8192];
	dao_gtao_fill_r2_tile(tile, 3);
	s.r2_tile = tile;
	float *ref = malloc(np * 4), *opt = malloc(np * 4), *strips = malloc(np * 4);
	for (int b = 0; b < r.n; b++)
		dao_gtao_ref(&s, p->z, p->n, ref, r.y0[b], r.y1[b]);
	for (int k = 0; k < ns; k++) {
		struct dao_kernels kr;
		dao_kernels_select(&kr, sets[k]);
		for (int b = 0; b < r.n; b++)
			kr.gtao(&s, p->z, &p->gp, p->n, opt, r.y0[b], r.y1[b], scratch);
		struct diff d = compare_rows(ref, opt, p->w, &r);
		print_message("gtao %2dx%-2d th %.2f noise %d %-8s %-30s%s MAE %.2e p99.9 %.2e max %.3f\n",
			      slices, steps, (double)thickness, noise, dao_simd_name(sets[k]), in->name,
			      banded ? " bands" : "", d.mae, d.p999, d.max);
		const int tile_noise = noise == DAO_NOISE_TILE;
		assert_true(d.mae <= (tile_noise ? GTAO_TILE_MAE : GTAO_MAE));
		assert_true(d.p999 <= (tile_noise ? GTAO_TILE_P999 : GTAO_P999));
		assert_true(d.max <= GTAO_MAX);
		/* in vertical strips (as the pipeline runs wide images): the very same values */
		for (int x = 0; x < p->w; x += 64) {
			struct dao_gtao_setup g = s;
			g.x_begin = x;
			g.x_end = x + 64 < p->w ? x + 64 : p->w;
			for (int b = 0; b < sr.n; b++)
				kr.gtao(&g, p->z, &p->gp, p->n, strips, sr.y0[b], sr.y1[b], scratch);
		}
		assert_rows_equal(strips, opt, p->w, &sr);
	}
	free(strips);
	free(ref);
	free(opt);
}

static void test_gtao(void **state)
{
	(void)state;
	for (int i = 0; i < ninputs; i++) {
		const struct planes *p = planes_of(i);
		gtao_case(p, &inputs[i], 2, 6, 0.0f, DAO_NOISE_IGN, 0);
		gtao_case(p, &inputs[i], 2, 6, 0.0f, DAO_NOISE_TILE, 0);
		if (i % 3 == 0) { /* the other code paths on a few inputs */
			gtao_case(p, &inputs[i], 4, 8, 0.3f, DAO_NOISE_TILE, 1);
			/* more steps than the kernel's step tables hold: made per block */
			if (i == 0)
				gtao_case(p, &inputs[i], 12, 12, 0.0f, DAO_NOISE_TILE, 1);
			gtao_case(p, &inputs[i], 4, 8, 0.0f, DAO_NOISE_R2, 1);
			gtao_case(p, &inputs[i], 3, 5, 0.05f, DAO_NOISE_NONE, 1);
		}
	}
}

/*
 * VBAO with tile noise against dao_vbao_ref: the constant thickness, a
 * thickness plane (varying from pixel to pixel, so the interpolation between
 * the taps shows) and a plane holding the constant everywhere, which must
 * give the very values of the constant (reference and kernel alike).
 */
enum { VBAO_CONSTANT, VBAO_PLANE, VBAO_FLAT_PLANE };

/* The bounds catch a kernel that is off by little: the same kernel with the occluders
 * 5 % thicker than the reference's exceeds them (a property of the bounds, checked with
 * the first set; `out` is overwritten). */
static void vbao_thicker(const struct dao_variant_setup *v, const struct planes *p,
			 const struct dao_gtao_planes *gp, const struct rows *r, const float *ref,
			 float *out, const struct dao_kernels *kr, const char *name)
{
	struct dao_variant_setup vt = *v;
	vt.vbao_thickness *= 1.05f;
	for (int b = 0; b < r->n; b++)
		kr->vbao(&vt, p->z, gp, p->n, out, r->y0[b], r->y1[b], scratch);
	struct diff dt = compare_rows(ref, out, p->w, r);
	print_message("vbao %2dx%-2d 5%% thicker %-30s MAE %.2e p99.9 %.2e\n", v->g->slices,
		      v->g->steps, name, dt.mae, dt.p999);
	assert_true(dt.mae > VBAO_MAE || dt.p999 > VBAO_P999);
}

static void vbao_case(const struct planes *p, const struct input *in, int slices, int steps,
		      int mode, int banded)
{
	enum dao_simd sets[DAO_SIMD_COUNT];
	int ns = optimised_sets(sets);
	const size_t np = (size_t)p->w * p->h;
	const struct rows r = row_bands(p->h, banded), sr = row_bands(p->h, 1);
	struct dao_params prm;
	dao_params_init(&prm, DAO_QUALITY_DEFAULT);
	prm.algorithm = DAO_ALGORITHM_VBAO;
	prm.slices = slices;
	prm.steps = steps;
	prm.noise = DAO_NOISE_TILE;
	struct dao_gtao_setup s;
	dao_gtao_setup_init(&s, &in->cam, &prm, 3);
	struct dao_variant_setup v;
	dao_variant_setup_init(&v, &s, &prm);
	/* the plane holds halves: a flat plane equals the constant where that is one */
	if (mode == VBAO_FLAT_PLANE)
		v.vbao_thickness = dao_half_round(v.vbao_thickness);
	float *thick = malloc(np * 4), *ref = malloc(np * 4), *opt = malloc(np * 4),
	      *strips = malloc(np * 4);
	struct dao_gtao_planes gp = p->gp; /* the test's planes, with a thickness plane */
	gp.thick = NULL;
	assert_int_equal(dao_gtao_planes_init_thickness(&gp), 0);
	for (size_t k = 0; k < np; k++) {
		const unsigned h = (unsigned)(k * 2654435761u) >> 20;
		thick[k] = mode == VBAO_FLAT_PLANE ? v.vbao_thickness
						    : 0.01f + 0.5f * (float)(h & 255u) / 255.0f;
	}
	dao_gtao_planes_fill_thickness(&gp, thick, 0, p->h);
	v.thickness = mode == VBAO_CONSTANT ? NULL : thick;
	for (int b = 0; b < r.n; b++)
		dao_vbao_ref(&v, p->z, p->n, ref, r.y0[b], r.y1[b]);
	struct dao_variant_setup v0 = v; /* a flat plane's setup without the plane */
	v0.thickness = NULL;
	if (mode == VBAO_FLAT_PLANE) { /* the reference without a plane: the same values */
		for (int b = 0; b < r.n; b++)
			dao_vbao_ref(&v0, p->z, p->n, strips, r.y0[b], r.y1[b]);
		assert_rows_equal(strips, ref, p->w, &r);
	}
	static const char *const mode_name[] = { "constant", "plane", "flat plane" };
	for (int k = 0; k < ns; k++) {
		struct dao_kernels kr;
		dao_kernels_select(&kr, sets[k]);
		for (int b = 0; b < r.n; b++)
			kr.vbao(&v, p->z, &gp, p->n, opt, r.y0[b], r.y1[b], scratch);
		struct diff d = compare_rows(ref, opt, p->w, &r);
		print_message("vbao %2dx%-2d %-10s %-8s %-30s%s MAE %.2e p99.9 %.2e max %.3f\n", slices,
			      steps, mode_name[mode], dao_simd_name(sets[k]), in->name,
			      banded ? " bands" : "", d.mae, d.p999, d.max);
		assert_true(d.mae <= VBAO_MAE);
		assert_true(d.p999 <= VBAO_P999);
		assert_true(d.max <= VBAO_MAX);
		if (mode == VBAO_CONSTANT && k == 0)
			vbao_thicker(&v, p, &gp, &r, ref, strips, &kr, in->name);
		if (mode == VBAO_FLAT_PLANE) { /* the kernel without a plane: the same values */
			for (int b = 0; b < r.n; b++)
				kr.vbao(&v0, p->z, &gp, p->n, strips, r.y0[b], r.y1[b], scratch);
			assert_rows_equal(strips, opt, p->w, &r);
		}
		/* in vertical strips (as the pipeline runs wide images): the very same values */
		for (int x = 0; x < p->w; x += 64) {
			struct dao_gtao_setup g = s;
			g.x_begin = x;
			g.x_end = x + 64 < p->w ? x + 64 : p->w;
			struct dao_variant_setup vs = v;
			vs.g = &g;
			for (int b = 0; b < sr.n; b++)
				kr.vbao(&vs, p->z, &gp, p->n, strips, sr.y0[b], sr.y1[b], scratch);
		}
		assert_rows_equal(strips, opt, p->w, &sr);
	}
	free(strips);
	free(gp.thick);
	free(thick);
	free(ref);
	free(opt);
}

static void test_vbao(void **state)
{
	(void)state;
	for (int i = 0; i < ninputs; i++) {
		const struct planes *p = planes_of(i);
		vbao_case(p, &inputs[i], 2, 6, VBAO_CONSTANT, 0);
		vbao_case(p, &inputs[i], 2, 6, VBAO_PLANE, 0);
		if (i % 3 == 0) {
			vbao_case(p, &inputs[i], 4, 8, VBAO_FLAT_PLANE, 1);
			/* more steps than the kernel's step tables hold: made per block */
			if (i == 0)
				vbao_case(p, &inputs[i], 12, 12, VBAO_PLANE, 1);
		}
		/* an odd number of slices: the last one's second pass after the loop
		 * (vbao_pipe), as the low preset's single slice */
		if (i == 0) {
			vbao_case(p, &inputs[i], 1, 6, VBAO_PLANE, 1);
			vbao_case(p, &inputs[i], 3, 4, VBAO_CONSTANT, 1);
		}
	}
}

/* HBAO with tile noise against dao_hbao_ref; in strips the very same values. */
static void hbao_case(const struct planes *p, const struct input *in, int slices, int steps,
		      int banded)
{
	enum dao_simd sets[DAO_SIMD_COUNT];
	int ns = optimised_sets(sets);
	const size_t np = (size_t)p->w * p->h;
	const struct rows r = row_bands(p->h, banded), sr = row_bands(p->h, 1);
	struct dao_params prm;
	dao_params_init(&prm, DAO_QUALITY_DEFAULT);
	prm.algorithm = DAO_ALGORITHM_HBAO;
	prm.slices = slices;
	prm.steps = steps;
	prm.noise = DAO_NOISE_TILE;
	struct dao_gtao_setup s;
	dao_gtao_setup_init(&s, &in->cam, &prm, 3);
	struct dao_variant_setup v;
	dao_variant_setup_init(&v, &s, &prm);
	float *ref = malloc(np * 4), *opt = malloc(np * 4), *strips = malloc(np * 4);
	for (int b = 0; b < r.n; b++)
		dao_hbao_ref(&v, p->z, p->n, ref, r.y0[b], r.y1[b]);
	for (int k = 0; k < ns; k++) {
		struct dao_kernels kr;
		dao_kernels_select(&kr, sets[k]);
		for (int b = 0; b < r.n; b++)
			kr.hbao(&v, p->z, &p->gp, p->n, opt, r.y0[b], r.y1[b], scratch);
		struct diff d = compare_rows(ref, opt, p->w, &r);
		print_message("hbao %2dx%-2d %-8s %-30s%s MAE %.2e p99.9 %.2e max %.2e\n", slices, steps,
			      dao_simd_name(sets[k]), in->name, banded ? " bands" : "", d.mae, d.p999,
			      d.max);
		assert_true(d.mae <= HBAO_MAE);
		assert_true(d.p999 <= HBAO_P999);
		assert_true(d.max <= HBAO_MAX);
		if (k == 0) {
			/* the bounds catch a kernel that is off by little: the same kernel with a
			 * tangent bias 5 % larger than the reference's exceeds them (a property
			 * of the bounds, checked with the first set) */
			struct dao_variant_setup vt = v;
			vt.tan_bias *= 1.05f;
			for (int b = 0; b < r.n; b++)
				kr.hbao(&vt, p->z, &p->gp, p->n, strips, r.y0[b], r.y1[b], scratch);
			struct diff dt = compare_rows(ref, strips, p->w, &r);
			print_message("hbao %2dx%-2d 5%% bias %-8s %-30s MAE %.2e p99.9 %.2e\n", slices,
				      steps, dao_simd_name(sets[k]), in->name, dt.mae, dt.p999);
			assert_true(dt.mae > HBAO_MAE || dt.p999 > HBAO_P999);
		}
		/* in vertical strips (as the pipeline runs wide images): the very same values */
		for (int x = 0; x < p->w; x += 64) {
			struct dao_gtao_setup g = s;
			g.x_begin = x;
			g.x_end = x + 64 < p->w ? x + 64 : p->w;
			struct dao_variant_setup vs = v;
			vs.g = &g;
			for (int b = 0; b < sr.n; b++)
				kr.hbao(&vs, p->z, &p->gp, p->n, strips, sr.y0[b], sr.y1[b], scratch);
		}
		assert_rows_equal(strips, opt, p->w, &sr);
	}
	free(strips);
	free(ref);
	free(opt);
}

static void test_hbao(void **state)
{
	(void)state;
	for (int i = 0; i < ninputs; i++) {
		const struct planes *p = planes_of(i);
		hbao_case(p, &inputs[i], 2, 6, 0);
		if (i % 3 == 0) {
			hbao_case(p, &inputs[i], 4, 8, 1);
			/* more steps than the kernel's step tables hold: made per direction */
			if (i == 0)
				hbao_case(p, &inputs[i], 12, 12, 1);
		}
	}
}

static void test_pipeline(void **state)
{
	(void)state;
	enum dao_simd sets[DAO_SIMD_COUNT];
	int ns = optimised_sets(sets);
	for (int i = 0; i < ninputs; i++) {
		const struct input *in = &inputs[i];
		const size_t np = (size_t)in->cam.width * in->cam.height;
		float *ref = malloc(np * 4), *opt = malloc(np * 4);
		struct dao_frame d = { .format = DAO_PIXFMT_DEPTH_F32, .width = in->cam.width,
				       .height = in->cam.height, .stride = 4 * (int32_t)in->cam.width,
				       .data = in->depth };
		struct dao_frame o = { .format = DAO_PIXFMT_GRAY_F32, .width = d.width,
				       .height = d.height, .stride = d.stride };
		for (int k = -1; k < ns; k++) {
			struct dao_params prm;
			dao_params_init(&prm, DAO_QUALITY_DEFAULT);
			prm.simd = k < 0 ? DAO_SIMD_REFERENCE : sets[k];
			struct dao_context *ctx;
			assert_int_equal(dao_context_create(&ctx, &in->cam, &prm, NULL), 0);
			assert_int_equal(dao_context_simd(ctx), prm.simd);
			o.data = k < 0 ? ref : opt;
			assert_int_equal(dao_context_process(ctx, &d, NULL, 1, &o, NULL), 0);
			dao_context_destroy(ctx);
			if (k < 0)
				continue;
			struct diff df = compare(ref, opt, np, 0);
			print_message("pipeline  %-8s %-34s MAE %.2e max %.3f\n",
				      dao_simd_name(sets[k]), in->name, df.mae, df.max);
			assert_true(df.mae <= PIPELINE_MAE);
		}
		free(ref);
		free(opt);
	}
}

typedef void (*fm_fn)(enum dao_fastmath_fn, const float *, float *, int);

static void test_fastmath(void **state)
{
	(void)state;
	enum { N = 1 << 16 };
	static float in[N], out[N];
	static const struct {
		enum dao_simd simd;
		fm_fn fn;
	} impl[] = {
		{ DAO_SIMD_GENERIC, dao_fastmath_eval_generic },
#if DAO_HAVE_X86_KERNELS
		{ DAO_SIMD_SSE41, dao_fastmath_eval_sse41 },
		{ DAO_SIMD_AVX2, dao_fastmath_eval_avx2 },
		{ DAO_SIMD_AVX512, dao_fastmath_eval_avx512 },
#endif
	};
	/* function, domain, libm, absolute or relative bound */
	static const struct {
		enum dao_fastmath_fn fn;
		const char *name;
		double lo, hi, bound;
		int relative;
	} fns[] = {
		{ DAO_FM_ACOS, "acos", -1.0, 1.0, 1e-6, 0 },
		/* 6.8e-5 of the polynomial plus the 1/sqrt estimate (12 bits; 14 on avx512) */
		{ DAO_FM_ACOS_FAST, "acos4", -1.0, 1.0, 5e-4, 0 },
		{ DAO_FM_SIN, "sin", -7.0, 7.0, 5e-7, 0 },
		{ DAO_FM_COS, "cos", -7.0, 7.0, 5e-7, 0 },
		{ DAO_FM_EXP, "exp", -80.0, 0.0, 5e-7, 1 },
		{ DAO_FM_EXP2_FAST, "exp2_3", -115.0, 0.0, 8e-5, 1 },
		{ DAO_FM_RCP, "rcp", 0.01, 100.0, 5e-7, 1 },
		{ DAO_FM_RSQRT, "rsqrt", 1e-6, 1e4, 5e-7, 1 },
	};
	for (size_t k = 0; k < sizeof impl / sizeof impl[0]; k++) {
		if (!dao_simd_supported(impl[k].simd))
			continue;
		for (size_t f = 0; f < sizeof fns / sizeof fns[0]; f++) {
			for (int i = 0; i < N; i++)
				in[i] = (float)(fns[f].lo + (fns[f].hi - fns[f].lo) * i / (N - 1));
			impl[k].fn(fns[f].fn, in, out, N);
			double worst = 0;
			for (int i = 0; i < N; i++) {
				double x = in[i], want;
				switch (fns[f].fn) {
				case DAO_FM_ACOS:
				case DAO_FM_ACOS_FAST: want = acos(x); break;
				case DAO_FM_SIN: want = sin(x); break;
				case DAO_FM_COS: want = cos(x); break;
				case DAO_FM_EXP: want = exp(x); break;
				case DAO_FM_EXP2_FAST: want = exp2(x); break;
				case DAO_FM_RCP: want = 1.0 / x; break;
				default: want = 1.0 / sqrt(x); break;
				}
				double e = fabs(out[i] - want);
				if (fns[f].relative)
					e /= fabs(want);
				if (e > worst)
					worst = e;
			}
			print_message("%-8s %-6s max %s error %.2e\n", dao_simd_name(impl[k].simd),
				      fns[f].name, fns[f].relative ? "relative" : "absolute", worst);
			assert_true(worst <= fns[f].bound);
		}
	}
}

/* The temporal depth filter's state, one per kernel set. */
struct tdepth {
	float *z, *hist;
	uint8_t *count, *age;
};

static void tdepth_alloc(struct tdepth *t, size_t np)
{
	t->z = malloc(np * 4);
	t->hist = calloc(np, 4);
	t->count = calloc(np, 1);
	t->age = calloc(np, 1);
	assert_true(t->z && t->hist && t->count && t->age);
}

static void tdepth_free(struct tdepth *t)
{
	free(t->z);
	free(t->hist);
	free(t->count);
	free(t->age);
}

/*
 * Frame f of a sequence made from `depth`: noise of a few sigma redrawn per
 * pixel and frame, a square that moves by 3 px a frame 0.4 m in front, and
 * holes that come and go.
 */
static void tdepth_frame(const float *depth, int w, int h, int f, float *z)
{
	unsigned seed = 977u * (unsigned)f + 13u;
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			const size_t i = (size_t)y * w + x;
			seed = seed * 1103515245u + 12345u;
			const float u = (float)((seed >> 8) & 0xffff) / 65535.0f - 0.5f;
			float v = depth[i];
			if (v > 0.0f)
				v += 0.008f * u * v * v;
			if (x >= 3 * f + w / 4 && x < 3 * f + w / 4 + w / 5 && y > h / 3 && y < h / 2 && v > 0.5f)
				v -= 0.4f;
			if (((seed >> 4) & 63u) == 0u)
				v = 0.0f;
			z[i] = v;
		}
}

static void test_temporal_depth(void **state)
{
	(void)state;
	enum dao_simd sets[DAO_SIMD_COUNT];
	int ns = optimised_sets(sets);
	/* the inputs, and a narrow one whose rows end between vectors */
	float narrow[37 * 5];
	for (int k = 0; k < 37 * 5; k++)
		narrow[k] = 1.0f + 0.01f * (float)(k % 37);
	for (int i = 0; i <= ninputs; i++) {
		const int w = i < ninputs ? (int)inputs[i].cam.width : 37;
		const int h = i < ninputs ? (int)inputs[i].cam.height : 5;
		const float *depth = i < ninputs ? inputs[i].depth : narrow;
		const size_t np = (size_t)w * h;
		struct tdepth ref, opt[DAO_SIMD_COUNT];
		tdepth_alloc(&ref, np);
		for (int k = 0; k < ns; k++)
			tdepth_alloc(&opt[k], np);
		float *sigma = malloc(np * 4);
		for (size_t k = 0; k < np; k++)
			sigma[k] = 0.001f + 0.002f * (float)(k % 7);
		for (int f = 0; f < 8; f++) {
			struct dao_temporal_depth_setup s = {
				.width = w, .alpha = 0.8f, .reject = 3.0f, .noise_k = 0.0012f,
				.quantum = 0.001f, .persist = 2, .fresh = f == 0 || f == 5,
				.sigma = f >= 6 ? sigma : NULL,
			};
			tdepth_frame(depth, w, h, f, ref.z);
			dao_temporal_depth_ref(&s, ref.z, ref.hist, ref.count, ref.age, 0, h);
			for (int k = 0; k < ns; k++) {
				struct dao_kernels kr;
				dao_kernels_select(&kr, sets[k]);
				tdepth_frame(depth, w, h, f, opt[k].z);
				/* in two bands, the first ending mid-image */
				kr.temporal_depth(&s, opt[k].z, opt[k].hist, opt[k].count, opt[k].age, 0, h / 3);
				kr.temporal_depth(&s, opt[k].z, opt[k].hist, opt[k].count, opt[k].age, h / 3, h);
				assert_memory_equal(ref.z, opt[k].z, np * 4);
				assert_memory_equal(ref.hist, opt[k].hist, np * 4);
				assert_memory_equal(ref.count, opt[k].count, np);
				assert_memory_equal(ref.age, opt[k].age, np);
			}
		}
		print_message("temporal depth: %-34s identical in %d sets over 8 frames\n",
			      i < ninputs ? inputs[i].name : "37 x 5", ns);
		tdepth_free(&ref);
		for (int k = 0; k < ns; k++)
			tdepth_free(&opt[k]);
		free(sigma);
	}
}

/* test-simd-kernels [--only PATTERN | --skip PATTERN]: the tests whose names match (or
 * do not); meson runs VBAO's as a test of its own (its scalar reference takes minutes
 * on a loaded host) */
int main(int argc, char **argv)
{
	if (argc == 3 && !strcmp(argv[1], "--only")) {
		cmocka_set_test_filter(argv[2]);
	} else if (argc == 3 && !strcmp(argv[1], "--skip")) {
		cmocka_set_skip_filter(argv[2]);
	} else if (argc != 1) {
		fprintf(stderr, "usage: %s [--only PATTERN | --skip PATTERN]\n", argv[0]);
		return 2;
	}
	/* a set this CPU cannot run is not checked here: say so, so a green run on an
	 * older CPU is not read as the oracle having covered it */
	for (int s = DAO_SIMD_GENERIC; s < DAO_SIMD_COUNT; s++)
		if (!dao_simd_supported((enum dao_simd)s))
			printf("SKIP %s: this CPU cannot run it; its kernels are not checked against "
			       "the reference in this run\n",
			       dao_simd_name((enum dao_simd)s));
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_fastmath),
		cmocka_unit_test(test_prefilter),
		cmocka_unit_test(test_domain),
		cmocka_unit_test(test_denoise),
		cmocka_unit_test(test_temporal_depth),
		cmocka_unit_test(test_normals),
		cmocka_unit_test(test_planes_fill),
		cmocka_unit_test(test_shade),
		cmocka_unit_test(test_gtao),
		cmocka_unit_test(test_vbao),
		cmocka_unit_test(test_hbao),
		cmocka_unit_test(test_pipeline),
	};
	return cmocka_run_group_tests(tests, setup, teardown);
}
