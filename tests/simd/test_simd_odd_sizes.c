/* SPDX-License-Identifier: MIT */
/*
 * The SIMD oracle at odd sizes.  test_simd_kernels.c compares every kernel
 * set with the scalar reference at the sensors' sizes, where rows are whole
 * vectors; here every optimised kernel of every instruction set this CPU
 * runs is compared at every width 1..67 (every tail of a 4-, 8- and 16-lane
 * vector and of a 16-pixel block, several times over) and heights 1, 2, 3
 * and 7, within the same bounds, and
 *  - every output has canary bytes before and after it and in the padding
 *    of each row where it has a stride, which must come back untouched;
 *  - every input ends where an unreadable page begins, so a read past its
 *    end faults;
 *  - a band of rows (or lanes, or columns) is computed alone and must equal
 *    the same rows of the whole, with the rows outside it untouched.
 * The kernels selected by the CPU when the library loads (target_clones:
 * decode, the output conversion, the noise estimate) have no per-set entry;
 * they are checked through the pipeline run per set at the same sizes.
 */
#define _DEFAULT_SOURCE /* MAP_ANONYMOUS */
#include "common/cmocka_all.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

#include <depthao/depthao.h>

#include "depth/decode.h"
#include "depth/domain.h"
#include "depth/prefilter.h"
#include "denoise/denoise.h"
#include "kernels/ao_variants.h"
#include "kernels/gtao.h"
#include "kernels/gtao_planes.h"
#include "kernels/gtao_tile.h"
#include "normals/normals.h"
#include "pipeline/kernels.h"
#include "pipeline/temporal_depth.h"
#include "shade/shade.h"

/* the bounds of test_simd_kernels.c (where they are explained), optimised vs reference */
#define PREFILTER_MAX_REL 2e-6
#define DOMAIN_MAX_REL 1e-4
#define DOMAIN_MEAN_REL 2e-8
#define DENOISE_MAX_ABS 1e-6
#define NORMALS_MAX_ABS 1e-5
#define GTAO_MAE 2e-6
#define GTAO_MAX 0.05
#define GTAO_TILE_MAE 1e-4
#define GTAO_TILE_P999 3e-3
#define VBAO_MAE 5e-6
#define VBAO_MAX 0.1
#define HBAO_MAE 2e-7
#define HBAO_P999 1e-5
#define HBAO_MAX 1e-4
#define PIPELINE_MAE 5e-5
/* At these sizes nearly every pixel is within the search radius of the image's
 * border, where taps fall off the image and the kernels' rounding of the tap
 * positions matters most: the 99.9th percentiles are larger than at 640x480
 * (measured here in brackets; the error is the same at a given pixel whatever
 * the width, so it is not a tail's) */
#define GTAO_ODD_P999 5e-4        /* per-pixel kernel [1.8e-4], 1e-4 at 640x480 */
#define VBAO_ODD_P999 3e-4        /* [1.2e-4 with a thickness plane], 5e-5 at 640x480 */

#define MAX_W 67
static const int heights[] = { 1, 2, 3, 7 };
#define NHEIGHTS ((int)(sizeof heights / sizeof heights[0]))

/* ---- guarded memory ---------------------------------------------------- */

#define GUARD 64      /* canary bytes before and after an output */
#define CANARY 0xa5u  /* 0xa5a5a5a5 as a float: -2.9e-16, no value a kernel writes */
#define ROW_PAD 12    /* canary bytes after each row of a strided output */

/* An output: `rows` rows of `row` bytes, `stride` apart, canaries around them. */
struct gbuf {
	unsigned char *mem, *data;
	size_t row, stride, rows;
};

static void gb_alloc(struct gbuf *b, size_t row, size_t stride, size_t rows)
{
	b->row = row, b->stride = stride, b->rows = rows;
	b->mem = malloc(stride * rows + 2 * GUARD);
	assert_non_null(b->mem);
	b->data = b->mem + GUARD;
	memset(b->mem, CANARY, stride * rows + 2 * GUARD);
}

/* a dense plane of `per_row` bytes per row */
static void *gb_plane(struct gbuf *b, size_t per_row, size_t rows)
{
	gb_alloc(b, per_row, per_row, rows);
	return b->data;
}

static void gb_reset(struct gbuf *b)
{
	memset(b->mem, CANARY, b->stride * b->rows + 2 * GUARD);
}

static void gb_free(struct gbuf *b)
{
	free(b->mem);
	b->mem = b->data = NULL;
}

static int is_canary(const unsigned char *p, size_t n)
{
	for (size_t i = 0; i < n; i++)
		if (p[i] != CANARY)
			return 0;
	return 1;
}

/* Every byte outside rows [y0, y1) of the buffer (and outside each row's `row`
 * bytes) is still a canary. */
static void gb_check(const struct gbuf *b, int y0, int y1, const char *what, const char *set,
		     int w, int h)
{
	const unsigned char *end = b->data + b->stride * b->rows;
	if (!is_canary(b->mem, GUARD))
		fail_msg("%s %s %dx%d: wrote before its output", what, set, w, h);
	if (!is_canary(end, GUARD))
		fail_msg("%s %s %dx%d: wrote after its output", what, set, w, h);
	for (size_t y = 0; y < b->rows; y++) {
		const unsigned char *r = b->data + y * b->stride;
		if ((int)y < y0 || (int)y >= y1) {
			if (!is_canary(r, b->stride))
				fail_msg("%s %s %dx%d: wrote row %zu outside its rows [%d, %d)", what,
					 set, w, h, y, y0, y1);
		} else if (!is_canary(r + b->row, b->stride - b->row)) {
			fail_msg("%s %s %dx%d: wrote into the padding after row %zu", what, set, w, h,
				 y);
		}
	}
}

/* An input of n bytes that ends where an unreadable page begins. */
struct ginput {
	unsigned char *map;
	size_t len;
	void *data;
};

static void *gi_alloc(struct ginput *g, size_t n)
{
	const size_t page = (size_t)sysconf(_SC_PAGESIZE);
	const size_t body = (n + page - 1) / page * page;
	g->len = body + page;
	g->map = mmap(NULL, g->len, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
	assert_true(g->map != MAP_FAILED);
	assert_int_equal(mprotect(g->map + body, page, PROT_NONE), 0);
	g->data = g->map + body - n;
	return g->data;
}

static void gi_free(struct ginput *g)
{
	munmap(g->map, g->len);
}

/* ---- inputs -------------------------------------------------------------- */

static uint32_t hash3(uint32_t x, uint32_t y, uint32_t s)
{
	uint32_t h = x * 0x9e3779b1u ^ (y + 0x7f4a7c15u) * 0x85ebca77u ^ s * 0xc2b2ae3du;
	h ^= h >> 15;
	h *= 0x2c1b3c6du;
	h ^= h >> 12;
	return h;
}

/* A tilted plane with boxes in front of it (depth edges every few pixels),
 * sensor-like noise and holes: metres, 0 = no data. */
static void scene(float *z, int w, int h, uint32_t seed)
{
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			const uint32_t r = hash3((uint32_t)x, (uint32_t)y, seed);
			float v = 1.5f + 0.012f * (float)x + 0.02f * (float)y;
			if (x % 11 >= 3 && x % 11 < 8 && y % 9 >= 2 && y % 9 < 6)
				v -= 0.35f;
			v += 0.0012f * v * v * ((float)(r & 0xffff) / 65535.0f - 0.5f);
			z[(size_t)y * w + x] = (r >> 16) % 13 == 0 ? 0.0f : v;
		}
}

static void camera(struct dao_camera *cam, int w, int h)
{
	assert_int_equal(dao_camera_from_intrinsics(cam, (uint32_t)w, (uint32_t)h, 60, 60,
						    (w - 1) / 2.0, (h - 1) / 2.0, NULL),
			 0);
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

/* The kernels of every optimised set this CPU can run. */
static int kernel_sets(struct dao_kernels *out)
{
	enum dao_simd sets[DAO_SIMD_COUNT];
	const int n = optimised_sets(sets);
	for (int k = 0; k < n; k++)
		dao_kernels_select(&out[k], sets[k]);
	return n;
}

/* A band of rows in the middle (or the whole, for fewer than 3 rows). */
static void band(int h, int *y0, int *y1)
{
	*y0 = h >= 3 ? 1 : 0;
	*y1 = h >= 3 ? h - 1 : h;
}

/* Rows [y0, y1) of a band run equal those of the whole run. */
static void band_equal(const struct gbuf *b, const void *whole, int y0, int y1, const char *what,
		       const char *set, int w, int h)
{
	gb_check(b, y0, y1, what, set, w, h);
	for (int y = y0; y < y1; y++) {
		const unsigned char *a = b->data + (size_t)y * b->stride;
		const unsigned char *c = (const unsigned char *)whole + (size_t)y * b->row;
		for (size_t i = 0; i < b->row; i++)
			if (a[i] != c[i])
				fail_msg("%s %s %dx%d: row %d of a band differs from the whole's at "
					 "byte %zu (float %zu: %.9g, whole %.9g)",
					 what, set, w, h, y, i, i / 4, (double)((const float *)a)[i / 4],
					 (double)((const float *)c)[i / 4]);
	}
}

/* ---- error statistics over every size ------------------------------------- */

struct errs {
	float *e;
	size_t n, cap;
	double max;
	int max_w, max_h;
};

static void errs_add(struct errs *s, double v, int w, int h)
{
	if (s->n == s->cap) {
		s->cap = s->cap ? 2 * s->cap : 65536;
		s->e = realloc(s->e, s->cap * sizeof *s->e);
		assert_non_null(s->e);
	}
	s->e[s->n++] = (float)v;
	if (v > s->max)
		s->max = v, s->max_w = w, s->max_h = h;
}

/* Differences of n values; relative to |a| where `relative` and a != 0. */
static void errs_compare(struct errs *s, const float *a, const float *b, size_t n, int relative,
			 const char *what, const char *set, int w, int h)
{
	for (size_t i = 0; i < n; i++) {
		if (isnan(a[i]) || isnan(b[i]))
			fail_msg("%s %s %dx%d: NaN at %zu (reference %g, kernel %g)", what, set, w, h,
				 i, (double)a[i], (double)b[i]);
		double v = fabs((double)a[i] - b[i]);
		if (relative && a[i] != 0.0f)
			v /= fabs(a[i]);
		errs_add(s, v, w, h);
	}
}

static int cmp_f(const void *a, const void *b)
{
	float x = *(const float *)a, y = *(const float *)b;
	return (x > y) - (x < y);
}

/* Prints and checks the statistics; bounds <= 0 are not checked. */
static void errs_done(struct errs *s, const char *what, const char *set, double max_bound,
		      double mae_bound, double p999_bound)
{
	double sum = 0;
	for (size_t i = 0; i < s->n; i++)
		sum += s->e[i];
	qsort(s->e, s->n, sizeof *s->e, cmp_f);
	const double mae = s->n ? sum / (double)s->n : 0;
	const double p999 = s->n ? s->e[(size_t)(0.999 * (double)(s->n - 1))] : 0;
	print_message("%-22s %-8s %7zu px  max %.2e (%dx%d)  MAE %.2e  p99.9 %.2e\n", what, set,
		      s->n, s->max, s->max_w, s->max_h, mae, p999);
	if (max_bound > 0 && s->max > max_bound)
		fail_msg("%s %s: largest difference %.3e at %dx%d exceeds %.1e", what, set, s->max,
			 s->max_w, s->max_h, max_bound);
	if (mae_bound > 0 && mae > mae_bound)
		fail_msg("%s %s: MAE %.3e exceeds %.1e", what, set, mae, mae_bound);
	if (p999_bound > 0 && p999 > p999_bound)
		fail_msg("%s %s: p99.9 %.3e exceeds %.1e", what, set, p999, p999_bound);
	free(s->e);
	memset(s, 0, sizeof *s);
}

#define FOR_SIZES(w, h)                                  \
	for (int hi_ = 0; hi_ < NHEIGHTS; hi_++)         \
		for (int w = 1, h = heights[hi_]; w <= MAX_W; w++)

/* ---- the kernels ----------------------------------------------------------- */

/* the bilateral prefilter, both passes */
static void test_prefilter(void **state)
{
	(void)state;
	struct dao_kernels sets[DAO_SIMD_COUNT];
	const int ns = kernel_sets(sets);
	for (int k = 0; k < ns; k++) {
		const struct dao_kernels kr = sets[k];
		const char *set = dao_simd_name(kr.simd);
		struct errs e = { 0 };
		FOR_SIZES(w, h)
		{
			const size_t np = (size_t)w * h;
			struct ginput gz, gt;
			float *z = gi_alloc(&gz, np * 4), *tin = gi_alloc(&gt, np * 4);
			scene(z, w, h, 1);
			struct dao_prefilter_setup s;
			dao_prefilter_setup_init(&s, w, h, 3, 0.0012f, 0.001f);
			float *tmp = malloc(np * 4), *ref = malloc(np * 4);
			dao_prefilter_h_ref(&s, z, tmp, 0, h);
			dao_prefilter_v_ref(&s, tmp, ref, 0, h);
			struct gbuf bt, bo;
			float *t = gb_plane(&bt, 4 * (size_t)w, (size_t)h);
			float *o = gb_plane(&bo, 4 * (size_t)w, (size_t)h);
			kr.prefilter_h(&s, z, t, 0, h);
			gb_check(&bt, 0, h, "prefilter h", set, w, h);
			errs_compare(&e, tmp, t, np, 1, "prefilter h", set, w, h);
			memcpy(tin, t, np * 4); /* the vertical pass reads it, ending at the page */
			kr.prefilter_v(&s, tin, o, 0, h);
			gb_check(&bo, 0, h, "prefilter v", set, w, h);
			errs_compare(&e, ref, o, np, 1, "prefilter", set, w, h);
			for (size_t p = 0; p < np; p++)
				if ((ref[p] == 0.0f) != (o[p] == 0.0f))
					fail_msg("prefilter %s %dx%d: hole mismatch at %zu", set, w, h, p);
			int y0, y1;
			band(h, &y0, &y1);
			memcpy(tmp, t, np * 4);
			memcpy(ref, o, np * 4);
			gb_reset(&bt);
			kr.prefilter_h(&s, z, t, y0, y1);
			band_equal(&bt, tmp, y0, y1, "prefilter h band", set, w, h);
			gb_reset(&bo);
			kr.prefilter_v(&s, tin, o, y0, y1);
			band_equal(&bo, ref, y0, y1, "prefilter v band", set, w, h);
			gb_free(&bt);
			gb_free(&bo);
			free(tmp);
			free(ref);
			gi_free(&gz);
			gi_free(&gt);
		}
		errs_done(&e, "prefilter (relative)", set, PREFILTER_MAX_REL, 0, 0);
	}
}

/*
 * prefilter=domain, the whole filter (fixed scales of 2 and 8 px, per-cell
 * noise and scale in cells of 8 px, with and without side windows), with its
 * transposed intermediate and scratch guarded; and one pass over a band of
 * lanes.
 */
static void test_domain(void **state)
{
	(void)state;
	struct dao_kernels sets[DAO_SIMD_COUNT];
	const int ns = kernel_sets(sets);
	static const char *const mode_name[] = { "2 px", "8 px", "cells", "8 px one-sided" };
	for (int k = 0; k < ns; k++) {
		const struct dao_kernels kr = sets[k];
		const char *set = dao_simd_name(kr.simd);
		for (int mode = 0; mode < 4; mode++) {
			struct errs e = { 0 };
			double sum = 0;
			size_t cnt = 0;
			FOR_SIZES(w, h)
			{
				const size_t np = (size_t)w * h;
				struct ginput gz;
				float *z = gi_alloc(&gz, np * 4);
				scene(z, w, h, 2);
				const int span = 8, cx = (w + span - 1) / span, cy = (h + span - 1) / span;
				struct ginput gc;
				float *cells = gi_alloc(&gc, 2 * (size_t)cx * cy * sizeof(float));
				for (int y = 0; y < cy; y++)
					for (int x = 0; x < cx; x++) {
						const float j = (float)((x * 7 + y * 13) % 5) / 5.0f;
						cells[y * cx + x] = 0.0005f + 0.0003f * (float)x + 0.0004f * j;
						cells[cx * cy + y * cx + x] = 1.0f / (1.5f + (float)y + 2.0f * j);
					}
				struct dao_domain_setup s = {
					.width = w, .height = h, .iterations = 3,
					.inv_scale = mode == 0 ? 0.5f : 0.125f,
					.range_coef = dao_domain_range_coef(3.0f),
					.noise = 0.0012f, .unit = 0.001f, .sides = mode != 3,
				};
				if (mode == 2) {
					s.noise_cells = cells, s.inv_scale_cells = cells + cx * cy;
					s.cells_x = cx, s.cells_y = cy, s.cell_span = span;
				}
				const size_t nsc = dao_domain_scratch_floats(w, h);
				float *ref = malloc(np * 4), *rtmp = malloc(np * 4);
				float *rsc = malloc(nsc * 4);
				dao_domain_filter(&s, dao_domain_pass_ref, z, rtmp, ref, rsc);
				struct gbuf bt, bo, bs;
				float *t = gb_plane(&bt, 4 * (size_t)h, (size_t)w); /* transposed */
				float *o = gb_plane(&bo, 4 * (size_t)w, (size_t)h);
				float *sc = gb_plane(&bs, 4 * nsc, 1);
				dao_domain_filter(&s, kr.domain_pass, z, t, o, sc);
				gb_check(&bt, 0, w, "domain tmp", set, w, h);
				gb_check(&bo, 0, h, "domain", set, w, h);
				gb_check(&bs, 0, 1, "domain scratch", set, w, h);
				const size_t n0 = e.n;
				errs_compare(&e, ref, o, np, 1, "domain", set, w, h);
				for (size_t i = n0; i < e.n; i++)
					sum += e.e[i];
				cnt += np;
				for (size_t p = 0; p < np; p++)
					if ((ref[p] == 0.0f) != (o[p] == 0.0f) ||
					    (ref[p] == 0.0f) != (z[p] <= 0.0f))
						fail_msg("domain %s %s %dx%d: hole mismatch at %zu", mode_name[mode],
							 set, w, h, p);
				/* the first pass (down the columns, one lane per column) over a
				 * band of lanes: the rest of its transposed output untouched */
				struct dao_domain_pass p;
				dao_domain_pass_init(&p, &s, 0, z, rtmp);
				kr.domain_pass(&p, sc, 0, p.lanes);
				/* lanes as the pipeline hands them out: strips of DAO_DOMAIN_STRIP
				 * (a tail of fewer than a vector's lanes is the reference's) */
				const int l0 = p.lanes > DAO_DOMAIN_STRIP ? DAO_DOMAIN_STRIP : 0;
				const int l1 = p.lanes > 2 * DAO_DOMAIN_STRIP ? 2 * DAO_DOMAIN_STRIP : p.lanes;
				gb_reset(&bt);
				dao_domain_pass_init(&p, &s, 0, z, t);
				kr.domain_pass(&p, sc, l0, l1);
				band_equal(&bt, rtmp, l0, l1, "domain pass lanes", set, w, h);
				gb_check(&bs, 0, 1, "domain scratch", set, w, h);
				gb_free(&bt);
				gb_free(&bo);
				gb_free(&bs);
				free(ref);
				free(rtmp);
				free(rsc);
				gi_free(&gz);
				gi_free(&gc);
			}
			char what[64];
			snprintf(what, sizeof what, "domain %s", mode_name[mode]);
			const double mean = sum / (double)cnt;
			print_message("%-22s %-8s mean relative %.2e\n", what, set, mean);
			assert_true(mean <= DOMAIN_MEAN_REL);
			errs_done(&e, what, set, DOMAIN_MAX_REL, 0, 0);
		}
	}
}

static void random_ao(float *ao, size_t n, unsigned seed, float lo, float hi)
{
	for (size_t k = 0; k < n; k++) {
		seed = seed * 1103515245u + 12345u;
		ao[k] = lo + (hi - lo) * (float)((seed >> 8) & 0xffff) / 65535.0f;
	}
}

static void test_denoise(void **state)
{
	(void)state;
	struct dao_kernels sets[DAO_SIMD_COUNT];
	const int ns = kernel_sets(sets);
	for (int k = 0; k < ns; k++) {
		const struct dao_kernels kr = sets[k];
		const char *set = dao_simd_name(kr.simd);
		struct errs e = { 0 };
		FOR_SIZES(w, h)
		{
			const size_t np = (size_t)w * h;
			struct ginput gz, ga;
			float *z = gi_alloc(&gz, np * 4), *ao = gi_alloc(&ga, np * 4);
			scene(z, w, h, 3);
			random_ao(ao, np, 5, 0.0f, 1.0f);
			struct dao_denoise_setup s = { .width = w, .height = h, .noise_k = 0.0012f,
						       .sharpness = 4.0f, .radius = 4,
						       .invalid_value = 1.0f };
			float *ref = malloc(np * 4);
			dao_denoise_plane(&s, z, ao, ref, 0, h);
			struct gbuf b;
			float *o = gb_plane(&b, 4 * (size_t)w, (size_t)h);
			kr.denoise_plane(&s, z, ao, o, 0, h);
			gb_check(&b, 0, h, "denoise", set, w, h);
			errs_compare(&e, ref, o, np, 0, "denoise", set, w, h);
			/* the border columns (on lanes from VN + 4 columns on): the reference's bytes */
			for (int y = 0; y < h; y++)
				for (int x = 0; x < w; x++)
					if ((x < 2 || x >= w - 2) &&
					    memcmp(ref + (size_t)y * w + x, o + (size_t)y * w + x, 4))
						fail_msg("denoise %s %dx%d: border pixel (%d, %d) is %.9g, "
							 "the reference's %.9g", set, w, h, x, y,
							 o[(size_t)y * w + x], ref[(size_t)y * w + x]);
			memcpy(ref, o, np * 4);
			int y0, y1;
			band(h, &y0, &y1);
			gb_reset(&b);
			kr.denoise_plane(&s, z, ao, o, y0, y1);
			band_equal(&b, ref, y0, y1, "denoise band", set, w, h);
			gb_free(&b);
			free(ref);
			gi_free(&gz);
			gi_free(&ga);
		}
		errs_done(&e, "denoise", set, DENOISE_MAX_ABS, 0, 0);
	}
}

static void test_normals(void **state)
{
	(void)state;
	struct dao_kernels sets[DAO_SIMD_COUNT];
	const int ns = kernel_sets(sets);
	for (int k = 0; k < ns; k++) {
		const struct dao_kernels kr = sets[k];
		const char *set = dao_simd_name(kr.simd);
		struct errs e = { 0 };
		FOR_SIZES(w, h)
		{
			const size_t np = (size_t)w * h;
			struct dao_camera cam;
			camera(&cam, w, h);
			struct ginput gz;
			float *z = gi_alloc(&gz, np * 4);
			scene(z, w, h, 4);
			float *ref = malloc(np * 12);
			struct gbuf b;
			float *o = gb_plane(&b, 12 * (size_t)w, (size_t)h);
			for (int r = 1; r <= 4; r += 3) {
				dao_normals_from_depth(&cam, z, r, ref, 0, h);
				gb_reset(&b);
				kr.normals(&cam, z, r, o, 0, h);
				gb_check(&b, 0, h, "normals", set, w, h);
				errs_compare(&e, ref, o, 3 * np, 0, "normals", set, w, h);
				memcpy(ref, o, np * 12);
				int y0, y1;
				band(h, &y0, &y1);
				gb_reset(&b);
				kr.normals(&cam, z, r, o, y0, y1);
				band_equal(&b, ref, y0, y1, "normals band", set, w, h);
			}
			gb_free(&b);
			free(ref);
			gi_free(&gz);
		}
		errs_done(&e, "normals", set, NORMALS_MAX_ABS, 0, 0);
	}
}

/* Floats of a plane of gtao_planes.h, from its first entry (the border row included). */
static size_t phase_floats(const struct dao_gtao_planes *pl)
{
	return ((size_t)pl->height + 2) * 4 * (size_t)pl->stride4;
}

static const float *phase_base(const struct dao_gtao_planes *pl)
{
	return dao_gtao_phase_row(pl, -1, 0) - pl->pad4;
}

/* Both planes of every set equal the scalar fill's, bit for bit, borders and
 * padding (zeros) included; a band fills its rows only. */
static void test_planes_fill(void **state)
{
	(void)state;
	struct dao_kernels sets[DAO_SIMD_COUNT];
	const int ns = kernel_sets(sets);
	for (int k = 0; k < ns; k++) {
		const struct dao_kernels kr = sets[k];
		const char *set = dao_simd_name(kr.simd);
		FOR_SIZES(w, h)
		{
			struct ginput gz;
			float *z = gi_alloc(&gz, (size_t)w * h * 4);
			scene(z, w, h, 5);
			struct dao_gtao_planes want, got, part;
			assert_int_equal(dao_gtao_planes_init(&want, w, h, 160.0f), 0);
			assert_int_equal(dao_gtao_planes_init(&got, w, h, 160.0f), 0);
			assert_int_equal(dao_gtao_planes_init(&part, w, h, 160.0f), 0);
			const size_t nb = ((size_t)w + 2) * ((size_t)h + 2);
			const size_t nph = phase_floats(&want);
			int y0, y1;
			band(h, &y0, &y1);
			for (int phase = 0; phase < 2; phase++) {
				dao_gtao_planes_fill(&want, z, phase, 0, h);
				kr.planes_fill(&got, z, phase, 0, h);
				kr.planes_fill(&part, z, phase, y0, y1);
			}
			if (memcmp(want.izp, got.izp, nb * 4))
				fail_msg("planes %s %dx%d: the bordered plane differs", set, w, h);
			if (memcmp(phase_base(&want), phase_base(&got), nph * 4))
				fail_msg("planes %s %dx%d: the phase plane differs", set, w, h);
			/* the band: its rows as the whole's, every other entry still 0 */
			const size_t row_b = (size_t)w + 2, row_p = 4 * (size_t)want.stride4;
			for (int r = -1; r <= h; r++) {
				const int in = r >= y0 && r < y1;
				const float *a = want.izp + (size_t)(r + 1) * row_b;
				const float *b = part.izp + (size_t)(r + 1) * row_b;
				const float *pa = phase_base(&want) + (size_t)(r + 1) * row_p;
				const float *pb = phase_base(&part) + (size_t)(r + 1) * row_p;
				for (size_t i = 0; i < row_b; i++)
					if (b[i] != (in ? a[i] : 0.0f))
						fail_msg("planes band %s %dx%d: bordered row %d entry %zu", set,
							 w, h, r, i);
				for (size_t i = 0; i < row_p; i++)
					if (pb[i] != (in ? pa[i] : 0.0f))
						fail_msg("planes band %s %dx%d: phase row %d entry %zu", set, w,
							 h, r, i);
			}
			dao_gtao_planes_free(&want);
			dao_gtao_planes_free(&got);
			dao_gtao_planes_free(&part);
			gi_free(&gz);
		}
		print_message("planes %-8s identical at every size\n", set);
	}
}

/* The shaded image into a strided frame: the SIMD path (Lambert, AO^1, RGB24)
 * and the reference fallbacks (AO^0.5, GRAY8), bit for bit. */
static void test_shade(void **state)
{
	(void)state;
	struct dao_kernels sets[DAO_SIMD_COUNT];
	const int ns = kernel_sets(sets);
	for (int k = 0; k < ns; k++) {
		const struct dao_kernels kr = sets[k];
		const char *set = dao_simd_name(kr.simd);
		FOR_SIZES(w, h)
		{
			const size_t np = (size_t)w * h;
			struct dao_camera cam;
			camera(&cam, w, h);
			struct ginput gz, gn, ga;
			float *z = gi_alloc(&gz, np * 4), *n = gi_alloc(&gn, np * 12);
			float *ao = gi_alloc(&ga, np * 4);
			scene(z, w, h, 6);
			dao_normals_from_depth(&cam, z, 1, n, 0, h);
			random_ao(ao, np, 9, -0.02f, 1.02f); /* a little outside [0, 1] */
			for (int c = 0; c < 3; c++) {
				const enum dao_pixfmt fmt = c == 2 ? DAO_PIXFMT_GRAY8 : DAO_PIXFMT_RGB24;
				const size_t bpp = fmt == DAO_PIXFMT_RGB24 ? 3 : 1;
				const size_t row = bpp * (size_t)w, stride = row + ROW_PAD;
				struct dao_shade_setup ss = { w, h, cam.ax, cam.ay, cam.bx, cam.by,
							      DAO_SHADE_LAMBERT, 0.5f, 5.0f,
							      c == 1 ? 0.5f : 1.0f, { 30, 20, 10 }, NULL };
				unsigned char *ref = malloc(stride * (size_t)h);
				struct dao_frame fr = { .format = fmt, .width = (uint32_t)w,
							.height = (uint32_t)h, .stride = (int32_t)stride,
							.data = ref };
				dao_shade(&ss, z, n, ao, &fr, 0, h);
				struct gbuf b;
				gb_alloc(&b, row, stride, (size_t)h);
				fr.data = b.data;
				kr.shade(&ss, z, n, ao, &fr, 0, h);
				gb_check(&b, 0, h, "shade", set, w, h);
				for (int y = 0; y < h; y++)
					if (memcmp(ref + (size_t)y * stride, b.data + (size_t)y * stride, row))
						fail_msg("shade %s %dx%d (%s, AO^%g): row %d differs", set, w, h,
							 dao_pixfmt_name(fmt), (double)ss.power, y);
				int y0, y1;
				band(h, &y0, &y1);
				gb_reset(&b);
				kr.shade(&ss, z, n, ao, &fr, y0, y1);
				gb_check(&b, y0, y1, "shade band", set, w, h);
				for (int y = y0; y < y1; y++)
					if (memcmp(ref + (size_t)y * stride, b.data + (size_t)y * stride, row))
						fail_msg("shade band %s %dx%d: row %d differs", set, w, h, y);
				gb_free(&b);
				free(ref);
			}
			gi_free(&gz);
			gi_free(&gn);
			gi_free(&ga);
		}
		print_message("shade %-8s identical at every size\n", set);
	}
}

/* The temporal depth filter's state, every array guarded (they are read and written). */
struct tstate {
	struct gbuf z, hist, count, age;
};

static void ts_alloc(struct tstate *t, int w, int h)
{
	gb_plane(&t->z, 4 * (size_t)w, (size_t)h);
	gb_plane(&t->hist, 4 * (size_t)w, (size_t)h);
	gb_plane(&t->count, (size_t)w, (size_t)h);
	gb_plane(&t->age, (size_t)w, (size_t)h);
	memset(t->hist.data, 0, 4 * (size_t)w * h);
	memset(t->count.data, 0, (size_t)w * h);
	memset(t->age.data, 0, (size_t)w * h);
}

static void ts_free(struct tstate *t)
{
	gb_free(&t->z);
	gb_free(&t->hist);
	gb_free(&t->count);
	gb_free(&t->age);
}

/* Frame f: the scene with noise redrawn, a box moving 2 px a frame, holes coming and going. */
static void tframe(float *z, int w, int h, int f)
{
	scene(z, w, h, 7);
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			const uint32_t r = hash3((uint32_t)x, (uint32_t)y, 100u + (uint32_t)f);
			float *v = &z[(size_t)y * w + x];
			if (*v > 0.0f)
				*v += 0.004f * *v * *v * ((float)(r & 0xffff) / 65535.0f - 0.5f);
			if (x >= 2 * f && x < 2 * f + 9 && *v > 0.5f)
				*v -= 0.4f;
			if ((r >> 20) % 11 == 0)
				*v = 0.0f;
		}
}

static void test_temporal_depth(void **state)
{
	(void)state;
	struct dao_kernels sets[DAO_SIMD_COUNT];
	const int ns = kernel_sets(sets);
	for (int k = 0; k < ns; k++) {
		const struct dao_kernels kr = sets[k];
		const char *set = dao_simd_name(kr.simd);
		FOR_SIZES(w, h)
		{
			const size_t np = (size_t)w * h;
			struct ginput gs;
			float *sigma = gi_alloc(&gs, np * 4);
			for (size_t i = 0; i < np; i++)
				sigma[i] = 0.001f + 0.002f * (float)(i % 7);
			float *rz = malloc(np * 4), *rh = calloc(np, 4);
			uint8_t *rc = calloc(np, 1), *ra = calloc(np, 1);
			struct tstate t;
			ts_alloc(&t, w, h);
			for (int f = 0; f < 5; f++) {
				const struct dao_temporal_depth_setup s = {
					.width = w, .alpha = 0.8f, .reject = 3.0f, .noise_k = 0.0012f,
					.quantum = 0.001f, .persist = 2, .fresh = f == 0,
					.sigma = f >= 3 ? sigma : NULL,
				};
				tframe(rz, w, h, f);
				dao_temporal_depth_ref(&s, rz, rh, rc, ra, 0, h);
				tframe((float *)t.z.data, w, h, f);
				/* in two bands (frame 1: one band, then the other) */
				const int mid = f == 1 ? h : h / 3;
				kr.temporal_depth(&s, (float *)t.z.data, (float *)t.hist.data, t.count.data,
						  t.age.data, 0, mid);
				kr.temporal_depth(&s, (float *)t.z.data, (float *)t.hist.data, t.count.data,
						  t.age.data, mid, h);
				gb_check(&t.z, 0, h, "temporal depth z", set, w, h);
				gb_check(&t.hist, 0, h, "temporal depth history", set, w, h);
				gb_check(&t.count, 0, h, "temporal depth count", set, w, h);
				gb_check(&t.age, 0, h, "temporal depth age", set, w, h);
				if (memcmp(rz, t.z.data, np * 4) || memcmp(rh, t.hist.data, np * 4) ||
				    memcmp(rc, t.count.data, np) || memcmp(ra, t.age.data, np))
					fail_msg("temporal depth %s %dx%d frame %d: differs from the reference",
						 set, w, h, f);
			}
			ts_free(&t);
			free(rz);
			free(rh);
			free(rc);
			free(ra);
			gi_free(&gs);
		}
		print_message("temporal depth %-8s identical at every size over 5 frames\n", set);
	}
}

/* ---- the AO kernels ---------------------------------------------------------- */

enum ao_kind { AO_GTAO, AO_VBAO, AO_VBAO_PLANE, AO_HBAO };

/* One AO kernel case at one size: reference and optimised; the optimised one also
 * in a band of rows and in strips of whole blocks (as the pipeline runs wide images),
 * which must give the very same values. */
static void ao_size(const struct dao_kernels *kr, const char *set, enum ao_kind kind, int noise,
		    int w, int h, struct errs *e, struct dao_tile_scratch *scratch)
{
	static const char *const kind_name[] = { "gtao", "vbao", "vbao plane", "hbao" };
	const char *what = kind_name[kind];
	const size_t np = (size_t)w * h;
	struct dao_camera cam;
	camera(&cam, w, h);
	struct ginput gz, gn, gth;
	float *z = gi_alloc(&gz, np * 4), *n = gi_alloc(&gn, np * 12);
	float *thick = gi_alloc(&gth, np * 4);
	scene(z, w, h, 8);
	dao_normals_from_depth(&cam, z, 1, n, 0, h);
	struct dao_params prm;
	dao_params_init(&prm, DAO_QUALITY_DEFAULT);
	prm.algorithm = kind == AO_GTAO ? DAO_ALGORITHM_GTAO
			: kind == AO_HBAO ? DAO_ALGORITHM_HBAO : DAO_ALGORITHM_VBAO;
	prm.slices = 2;
	prm.steps = 6;
	prm.noise = noise;
	struct dao_gtao_setup s;
	dao_gtao_setup_init(&s, &cam, &prm, 3);
	static float tile[8192];
	dao_gtao_fill_r2_tile(tile, 3);
	s.r2_tile = tile;
	struct dao_variant_setup v;
	dao_variant_setup_init(&v, &s, &prm);
	struct dao_gtao_planes pl;
	assert_int_equal(dao_gtao_planes_init(&pl, w, h, s.max_r_px), 0);
	dao_gtao_planes_fill(&pl, z, 0, 0, h);
	dao_gtao_planes_fill(&pl, z, 1, 0, h);
	if (kind == AO_VBAO_PLANE) {
		for (size_t i = 0; i < np; i++)
			thick[i] = 0.01f + 0.5f * (float)(hash3((uint32_t)i, 0, 9) & 255u) / 255.0f;
		assert_int_equal(dao_gtao_planes_init_thickness(&pl), 0);
		dao_gtao_planes_fill_thickness(&pl, thick, 0, h);
		v.thickness = thick;
	}
	float *ref = malloc(np * 4), *whole = malloc(np * 4);
	struct gbuf b;
	float *o = gb_plane(&b, 4 * (size_t)w, (size_t)h);
#define RUN(setup, y0, y1)                                                     \
	do {                                                                   \
		if (kind == AO_GTAO)                                           \
			kr->gtao((setup).g, z, &pl, n, o, y0, y1, scratch);    \
		else if (kind == AO_HBAO)                                      \
			kr->hbao(&(setup), z, &pl, n, o, y0, y1, scratch);     \
		else                                                           \
			kr->vbao(&(setup), z, &pl, n, o, y0, y1, scratch);     \
	} while (0)
	if (kind == AO_GTAO)
		dao_gtao_ref(&s, z, n, ref, 0, h);
	else if (kind == AO_HBAO)
		dao_hbao_ref(&v, z, n, ref, 0, h);
	else
		dao_vbao_ref(&v, z, n, ref, 0, h);
	RUN(v, 0, h);
	gb_check(&b, 0, h, what, set, w, h);
	errs_compare(e, ref, o, np, 0, what, set, w, h);
	memcpy(whole, o, np * 4);
	int y0, y1;
	band(h, &y0, &y1);
	gb_reset(&b);
	RUN(v, y0, y1);
	char name[96];
	snprintf(name, sizeof name, "%s band", what);
	band_equal(&b, whole, y0, y1, name, set, w, h);
	if (w > DAO_GTAO_BLOCK_SPAN) { /* strips of whole blocks */
		gb_reset(&b);
		for (int x = 0; x < w; x += DAO_GTAO_BLOCK_SPAN) {
			struct dao_gtao_setup g = s;
			g.x_begin = x;
			g.x_end = x + DAO_GTAO_BLOCK_SPAN < w ? x + DAO_GTAO_BLOCK_SPAN : w;
			struct dao_variant_setup vs = v;
			vs.g = &g;
			RUN(vs, 0, h);
		}
		snprintf(name, sizeof name, "%s in strips of whole blocks", what);
		band_equal(&b, whole, 0, h, name, set, w, h);
	}
#undef RUN
	gb_free(&b);
	free(ref);
	free(whole);
	free(pl.thick);
	pl.thick = NULL;
	dao_gtao_planes_free(&pl);
	gi_free(&gz);
	gi_free(&gn);
	gi_free(&gth);
}

static void ao_all_sizes(enum ao_kind kind, int noise, double mx, double mae, double p999)
{
	static const char *const kind_name[] = { "gtao", "vbao", "vbao plane", "hbao" };
	static const char *const noise_name[] = { [DAO_NOISE_NONE] = "none", [DAO_NOISE_IGN] = "ign",
						  [DAO_NOISE_R2] = "r2", [DAO_NOISE_TILE] = "tile" };
	struct dao_kernels sets[DAO_SIMD_COUNT];
	const int ns = kernel_sets(sets);
	struct dao_tile_scratch *scratch = malloc(sizeof *scratch);
	assert_non_null(scratch);
	char what[64];
	snprintf(what, sizeof what, "%s noise %s", kind_name[kind], noise_name[noise]);
	for (int k = 0; k < ns; k++) {
		const char *set = dao_simd_name(sets[k].simd);
		struct errs e = { 0 };
		FOR_SIZES(w, h)
		{
			ao_size(&sets[k], set, kind, noise, w, h, &e, scratch);
		}
		errs_done(&e, what, set, mx, mae, p999);
	}
	free(scratch);
}

static void test_gtao(void **state)
{
	(void)state;
	ao_all_sizes(AO_GTAO, DAO_NOISE_IGN, GTAO_MAX, GTAO_MAE, GTAO_ODD_P999);
	ao_all_sizes(AO_GTAO, DAO_NOISE_TILE, GTAO_MAX, GTAO_TILE_MAE, GTAO_TILE_P999);
}

static void test_vbao(void **state)
{
	(void)state;
	ao_all_sizes(AO_VBAO, DAO_NOISE_TILE, VBAO_MAX, VBAO_MAE, VBAO_ODD_P999);
	ao_all_sizes(AO_VBAO_PLANE, DAO_NOISE_TILE, VBAO_MAX, VBAO_MAE, VBAO_ODD_P999);
}

static void test_hbao(void **state)
{
	(void)state;
	ao_all_sizes(AO_HBAO, DAO_NOISE_TILE, HBAO_MAX, HBAO_MAE, HBAO_P999);
}

/* ---- the decode (selected when the library loads) ------------------------------ */

static void test_decode(void **state)
{
	(void)state;
	FOR_SIZES(w, h)
	{
		for (int f32 = 0; f32 < 2; f32++) {
			const size_t bpp = f32 ? 4 : 2, stride = bpp * (size_t)w + 6;
			struct ginput gi;
			/* the last row ends at the unreadable page: no padding after it */
			unsigned char *in = gi_alloc(&gi, stride * (size_t)(h - 1) + bpp * (size_t)w);
			float *want = malloc((size_t)w * h * 4);
			for (int y = 0; y < h; y++)
				for (int x = 0; x < w; x++) {
					const uint32_t r = hash3((uint32_t)x, (uint32_t)y, 11);
					unsigned char *p = in + (size_t)y * stride + bpp * (size_t)x;
					float m;
					if (f32) {
						static const float odd[] = { 0.0f, -1.0f, NAN, INFINITY, 0.1f,
									     9.0f };
						m = r % 5 == 0 ? odd[(r >> 8) % 6]
							       : 0.3f + (float)(r & 0xfff) / 1000.0f;
						memcpy(p, &m, 4);
					} else {
						const uint16_t c = (uint16_t)(r % 7 == 0 ? 0 : r & 0x1fff);
						memcpy(p, &c, 2);
						m = (float)c * 0.001f;
					}
					const int ok = isfinite(m) && m > 0.0f && m >= 0.2f && m <= 6.0f;
					want[(size_t)y * w + x] = ok ? m : 0.0f;
				}
			const struct dao_frame fr = {
				.format = f32 ? DAO_PIXFMT_DEPTH_F32 : DAO_PIXFMT_DEPTH16,
				.width = (uint32_t)w, .height = (uint32_t)h, .stride = (int32_t)stride,
				.data = in, .depth_unit = 0.001f,
			};
			struct gbuf b;
			float *o = gb_plane(&b, 4 * (size_t)w, (size_t)h);
			dao_decode_depth(&fr, 0.2f, 6.0f, o, 0, h);
			gb_check(&b, 0, h, "decode", "auto", w, h);
			if (memcmp(want, o, (size_t)w * h * 4))
				fail_msg("decode %s %dx%d: differs", f32 ? "f32" : "depth16", w, h);
			int y0, y1;
			band(h, &y0, &y1);
			gb_reset(&b);
			dao_decode_depth(&fr, 0.2f, 6.0f, o, y0, y1);
			band_equal(&b, want, y0, y1, "decode band", "auto", w, h);
			gb_free(&b);
			free(want);
			gi_free(&gi);
		}
	}
}

/* ---- the pipeline per set: noise estimate, output conversion, shade, copies ---- */

/* A strided output frame with canaries. */
static void out_frame(struct dao_frame *f, struct gbuf *b, enum dao_pixfmt fmt, int w, int h)
{
	const size_t row = dao_pixfmt_bytes_per_pixel(fmt) * (size_t)w;
	gb_alloc(b, row, row + ROW_PAD, (size_t)h);
	*f = (struct dao_frame){ .format = fmt, .width = (uint32_t)w, .height = (uint32_t)h,
				 .stride = (int32_t)(row + ROW_PAD), .data = b->data };
}

static void test_pipeline(void **state)
{
	(void)state;
	enum dao_simd sets[DAO_SIMD_COUNT + 1];
	sets[0] = DAO_SIMD_REFERENCE;
	const int ns = 1 + optimised_sets(sets + 1);
	static const int ph[] = { 1, 2, 5 };
	struct errs e[DAO_SIMD_COUNT + 1] = { 0 };
	for (int hi = 0; hi < 3; hi++)
		for (int w = 1; w <= MAX_W; w++) {
			const int h = ph[hi];
			const size_t np = (size_t)w * h;
			struct dao_camera cam;
			camera(&cam, w, h);
			const size_t stride = 2 * (size_t)w + 4;
			struct ginput gi;
			unsigned char *in = gi_alloc(&gi, stride * (size_t)(h - 1) + 2 * (size_t)w);
			float *z = malloc(np * 4), *ref = malloc(np * 4);
			scene(z, w, h, 12);
			for (int y = 0; y < h; y++)
				for (int x = 0; x < w; x++) {
					const uint16_t c = (uint16_t)lrintf(z[(size_t)y * w + x] * 1000.0f);
					memcpy(in + (size_t)y * stride + 2 * (size_t)x, &c, 2);
				}
			const struct dao_frame d = { .format = DAO_PIXFMT_DEPTH16, .width = (uint32_t)w,
						     .height = (uint32_t)h, .stride = (int32_t)stride,
						     .data = in, .depth_unit = 0.001f };
			for (int k = 0; k < ns; k++) {
				const char *set = dao_simd_name(sets[k]);
				struct dao_params prm;
				dao_params_init(&prm, DAO_QUALITY_DEFAULT);
				prm.simd = sets[k];
				prm.threads = 1;
				struct dao_context *ctx;
				assert_int_equal(dao_context_create(&ctx, &cam, &prm, NULL), 0);
				struct dao_frame f[3];
				struct gbuf b[3];
				static const enum dao_pixfmt fmt[3] = { DAO_PIXFMT_GRAY_F32, DAO_PIXFMT_GRAY16,
									DAO_PIXFMT_GRAY8 };
				for (int c = 0; c < 3; c++) {
					out_frame(&f[c], &b[c], fmt[c], w, h);
					assert_int_equal(dao_context_process(ctx, &d, NULL, 1, &f[c], NULL), 0);
					gb_check(&b[c], 0, h, dao_pixfmt_name(fmt[c]), set, w, h);
				}
				/* GRAY16 and GRAY8 are the float output rounded to nearest-even */
				for (int y = 0; y < h; y++)
					for (int x = 0; x < w; x++) {
						float a;
						uint16_t g16;
						memcpy(&a, b[0].data + (size_t)y * b[0].stride + 4 * (size_t)x, 4);
						memcpy(&g16, b[1].data + (size_t)y * b[1].stride + 2 * (size_t)x, 2);
						const uint8_t g8 = b[2].data[(size_t)y * b[2].stride + (size_t)x];
						if (!(a >= 0.0f && a <= 1.0f) || g16 != (uint16_t)nearbyintf(a * 65535.0f) ||
						    g8 != (uint8_t)nearbyintf(a * 255.0f))
							fail_msg("output %s %dx%d (%d, %d): %g as %u and %u", set, w, h,
								 x, y, (double)a, g16, g8);
						if (k == 0)
							ref[(size_t)y * w + x] = a;
						else
							errs_add(&e[k], fabs((double)a - ref[(size_t)y * w + x]), w, h);
					}
				/* the shaded image and the copies of depth and normals */
				struct dao_frame fs, fd, fn;
				struct gbuf bs, bd, bn;
				out_frame(&fs, &bs, DAO_PIXFMT_RGB24, w, h);
				out_frame(&fd, &bd, DAO_PIXFMT_DEPTH_F32, w, h);
				out_frame(&fn, &bn, DAO_PIXFMT_NORMAL_F32, w, h);
				assert_int_equal(dao_context_shade(ctx, &fs, NULL), 0);
				assert_int_equal(dao_context_get_depth(ctx, &fd, NULL), 0);
				assert_int_equal(dao_context_get_normals(ctx, &fn, NULL), 0);
				gb_check(&bs, 0, h, "shaded", set, w, h);
				gb_check(&bd, 0, h, "depth copy", set, w, h);
				gb_check(&bn, 0, h, "normals copy", set, w, h);
				for (int c = 0; c < 3; c++)
					gb_free(&b[c]);
				gb_free(&bs);
				gb_free(&bd);
				gb_free(&bn);
				dao_context_destroy(ctx);
			}
			free(z);
			free(ref);
			gi_free(&gi);
		}
	for (int k = 1; k < ns; k++)
		errs_done(&e[k], "pipeline", dao_simd_name(sets[k]), 0, PIPELINE_MAE, 0);
}

int main(void)
{
	for (int s = DAO_SIMD_GENERIC; s < DAO_SIMD_COUNT; s++)
		if (!dao_simd_supported((enum dao_simd)s))
			printf("SKIP %s: this CPU cannot run it; its kernels are not checked against "
			       "the reference in this run\n",
			       dao_simd_name((enum dao_simd)s));
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_prefilter),
		cmocka_unit_test(test_domain),
		cmocka_unit_test(test_denoise),
		cmocka_unit_test(test_normals),
		cmocka_unit_test(test_planes_fill),
		cmocka_unit_test(test_shade),
		cmocka_unit_test(test_temporal_depth),
		cmocka_unit_test(test_gtao),
		cmocka_unit_test(test_vbao),
		cmocka_unit_test(test_hbao),
		cmocka_unit_test(test_decode),
		cmocka_unit_test(test_pipeline),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
