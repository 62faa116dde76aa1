/* SPDX-License-Identifier: MIT */
/*
 * The thickness estimated from the image (kernels/thickness.h) on ray-traced
 * depth: poles of known width get their width, walls and floors the bound,
 * runs cut by holes, occluders and the border follow their rules; and VBAO
 * with the estimate is closer to the ray-traced truth behind thin poles
 * than GTAO and than VBAO with one thickness for everything.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "common/test_common.h"
#include "core/math_util.h"
#include "kernels/gtao_planes.h"
#include "kernels/thickness.h"
#include "synth/geometry.h"
#include "synth/real_frames.h"
#include "synth/suite.h"
#include "synth/synth.h"

#define W 640
#define H 480

static const double pole_d[4] = { 0.02, 0.05, 0.10, 0.20 };
static const double pole_x[4] = { -0.6, -0.2, 0.2, 0.6 };
#define POLE_Z 2.2  /* m, the poles' axes */
#define WALL_Z 2.6  /* m, the wall behind them */

static void camera(struct dao_camera *cam, int w, int h)
{
	const double f = 525.0 * w / 640.0;
	assert_int_equal(dao_camera_from_intrinsics(cam, (uint32_t)w, (uint32_t)h, f, f,
						    0.5 * (w - 1), 0.5 * (h - 1), NULL), 0);
}

/* Camera frame (x right, y down, z forward): a wall, four upright poles in front of
 * it (from y = -0.6 to 0.4 m), and a floor 0.4 m below the camera. */
static void poles_scene(struct synth_scene *s)
{
	*s = (struct synth_scene){ .name = "poles" };
	s->prims[s->count++] = (struct synth_prim){ .kind = SYNTH_HALFSPACE, .c = { 0, 0, WALL_Z },
						    .n = { 0, 0, -1 } };
	s->prims[s->count++] = (struct synth_prim){ .kind = SYNTH_HALFSPACE, .c = { 0, 0.4, 0 },
						    .n = { 0, -1, 0 } };
	for (int i = 0; i < 4; i++)
		s->prims[s->count++] = (struct synth_prim){
			.kind = SYNTH_CYLINDER, .c = { pole_x[i], -0.1, POLE_Z }, .n = { 0, 1, 0 },
			.r = 0.5 * pole_d[i], .h = 0.5 };
	for (int i = 0; i < s->count; i++)
		synth_prim_bound(&s->prims[i]);
}

/* The column pass of columns [x0, x1) with a scratch of its own (no plane split). */
static void cols(const struct dao_thickness_setup *ts, const float *z, float *t, int x0, int x1)
{
	float *scratch = malloc(dao_thickness_cols_scratch(ts->height) * sizeof(float));
	assert_non_null(scratch);
	dao_thickness_cols(ts, z, t, scratch, NULL, x0, x1);
	free(scratch);
}

/* The estimate with slabs at least their rays' length plus `spacing` (thickness.h). */
static void estimate_spaced(const struct dao_camera *cam, const float *z, float max,
			    float spacing, float *t)
{
	struct dao_thickness_setup ts;
	dao_thickness_setup_init(&ts, cam, max);
	ts.spacing = spacing;
	dao_thickness_rows(&ts, z, t, 0, (int)cam->height);
	cols(&ts, z, t, 0, (int)cam->width);
}

static void estimate(const struct dao_camera *cam, const float *z, float max, float *t)
{
	estimate_spaced(cam, z, max, 0.0f, t);
}

static int cmp_float(const void *a, const void *b)
{
	float x = *(const float *)a, y = *(const float *)b;
	return (x > y) - (x < y);
}

/* Median of the estimate over the pixels of pole i, rows 150..250 (the poles' middle). */
static double pole_median(const struct dao_camera *cam, const float *z, const float *t, int i)
{
	static float v[W * 101];
	int n = 0;
	for (int y = 150; y <= 250; y++)
		for (int x = 0; x < W; x++) {
			const size_t k = (size_t)y * W + x;
			const double X = (x * cam->ax + cam->bx) * z[k];
			if (z[k] < WALL_Z - 0.01 && fabs(X - pole_x[i]) < 0.5 * pole_d[i] + 0.01)
				v[n++] = t[k];
		}
	assert_true(n > 100);
	qsort(v, (size_t)n, sizeof v[0], cmp_float);
	return v[n / 2];
}

static void test_pole_widths(void **state)
{
	(void)state;
	struct synth_scene s;
	struct dao_camera cam;
	struct synth_image img;
	poles_scene(&s);
	camera(&cam, W, H);
	assert_int_equal(synth_render(&s, &cam, 0.5, 0, 1, &img, NULL), 0);
	float *t = malloc((size_t)W * H * sizeof(float));
	estimate(&cam, img.depth, 0.5f, t);
	for (int i = 0; i < 4; i++) {
		const double m = pole_median(&cam, img.depth, t, i);
		print_message("pole %.0f cm wide (%.1f px): thickness %.1f cm\n", pole_d[i] * 100,
			      pole_d[i] * 525.0 / POLE_Z, m * 100);
		/* within a pixel's footprint at the pole's depth, 0.42 cm, and 10 % */
		assert_true(fabs(m - pole_d[i]) <= 0.1 * pole_d[i] + 0.0042);
	}
	/* the wall between the poles goes on behind them, the floor runs into the border
	 * and under the poles: both at the bound */
	assert_float_equal(t[(size_t)200 * W + 320], 0.5f, 0.0f); /* wall between poles 2 and 3 */
	assert_float_equal(t[(size_t)20 * W + 320], 0.5f, 0.0f);  /* wall above them */
	assert_float_equal(t[(size_t)470 * W + 320], 0.5f, 0.0f); /* floor */
	/* the bound caps the 20 cm pole */
	estimate(&cam, img.depth, 0.15f, t);
	assert_float_equal(pole_median(&cam, img.depth, t, 3), 0.15f, 0.0f);
	free(t);
	synth_image_free(&img);
}

/*
 * A pole's chord plus half a spacing (thickness.h, DAO_CHORD_EXTRA): the poles stand
 * 0.4 m before the wall, within 3 spacings of 0.15 m (0.45 m) but not of 0.11 m
 * (0.33 m).  With 0.15 m the poles thinner than it get their width plus 7.5 cm, at
 * most 15 cm (2 cm: 9.5 cm, 5 cm: 12.5 cm, 10 cm: 15 cm; 20 cm: 20 cm), on noisy
 * depth (noise_k set) too where its dropouts are filled (fill_px); with 0.11 m, or
 * on noisy depth whose dropouts are not filled, their width alone.
 */
static void expect_blocked_same_k(const struct dao_camera *cam, const float *z, float max,
				  float spacing, float noise_k);
static void expect_blocked_same_kf(const struct dao_camera *cam, const float *z, float max,
				   float spacing, float noise_k, int fill_px);

static void test_pole_chord_extra(void **state)
{
	(void)state;
	struct synth_scene s;
	struct dao_camera cam;
	struct synth_image img;
	poles_scene(&s);
	camera(&cam, W, H);
	assert_int_equal(synth_render(&s, &cam, 0.5, 0, 1, &img, NULL), 0);
	float *t = malloc((size_t)W * H * sizeof(float));
	struct dao_thickness_setup ts;
	dao_thickness_setup_init(&ts, &cam, 0.5f);
	static const struct { float spacing, noise_k, extra; int fill_px; } cases[] = {
		{ 0.15f, 0.0f, 0.075f, 8 }, { 0.11f, 0.0f, 0.0f, 8 }, { 0.15f, 0.0012f, 0.075f, 8 },
		{ 0.15f, 0.0012f, 0.0f, 0 },
	};
	for (int c = 0; c < 4; c++) {
		ts.spacing = cases[c].spacing;
		ts.noise_k = cases[c].noise_k;
		ts.fill_px = cases[c].fill_px;
		dao_thickness_rows(&ts, img.depth, t, 0, H);
		cols(&ts, img.depth, t, 0, W);
		for (int i = 0; i < 4; i++) {
			const double m = pole_median(&cam, img.depth, t, i);
			double want = pole_d[i];
			if (cases[c].extra > 0.0f && want < ts.spacing)
				want = fmin(want + cases[c].extra, ts.spacing);
			print_message("pole %.0f cm, spacing %.2f m, noise_k %.4f: %.1f cm (want "
				      "%.1f)\n", pole_d[i] * 100, (double)ts.spacing,
				      (double)ts.noise_k, m * 100, want * 100);
			assert_true(fabs(m - want) <= 0.1 * pole_d[i] + 0.0042);
		}
		expect_blocked_same_k(&cam, img.depth, 0.5f, ts.spacing, ts.noise_k);
	}
	free(t);
	synth_image_free(&img);
}

/* A strip of 10 px at 2 m on a line: bounded by holes and farther surfaces it is
 * 10 px wide; cut by a nearer surface or the image border its extent is unknown. */
static void test_run_ends(void **state)
{
	(void)state;
	struct dao_camera cam;
	camera(&cam, 64, 4);
	const float px = 2.0f / (float)cam.fx; /* one pixel at 2 m */
	float z[64 * 4], t[64 * 4];
	for (int x = 0; x < 64; x++) {
		const int strip = x >= 20 && x < 30;
		z[0 * 64 + x] = strip ? 2.0f : 3.0f;                 /* farther both sides */
		z[1 * 64 + x] = strip ? 2.0f : 0.0f;                 /* holes both sides */
		z[2 * 64 + x] = strip ? 2.0f : x < 20 ? 3.0f : 1.0f; /* an occluder right */
		z[3 * 64 + x] = x < 10 ? 2.0f : 3.0f;                /* at the border */
	}
	struct dao_thickness_setup ts;
	dao_thickness_setup_init(&ts, &cam, 0.5f);
	dao_thickness_rows(&ts, z, t, 0, 4);
	assert_float_equal(t[0 * 64 + 25], 10 * px, 1e-5);
	assert_float_equal(t[1 * 64 + 25], 10 * px, 1e-5);
	assert_float_equal(t[2 * 64 + 25], 0.5f, 0.0f);
	assert_float_equal(t[3 * 64 + 5], 0.5f, 0.0f);
	/* the surfaces beside the strip: the far one is cut by the strip (unknown), the
	 * holes get the bound */
	assert_float_equal(t[0 * 64 + 40], 0.5f, 0.0f);
	assert_float_equal(t[1 * 64 + 40], 0.5f, 0.0f);
	/* columns of 4 px of one depth run into both borders: the rows' value stays */
	cols(&ts, z, t, 0, 64);
	assert_float_equal(t[0 * 64 + 25], 10 * px, 1e-5);
	/* a slope within the jump is one surface: 2 % deeper per pixel (an image of one
	 * row, with a camera of one row: the setup's height is the lines across a pass
	 * may read, face_bound's and carried_bound's) */
	struct dao_camera cam1;
	camera(&cam1, 64, 1);
	float zs[64], ts1[64];
	for (int x = 0; x < 64; x++)
		zs[x] = x >= 20 && x < 30 ? 2.0f * powf(1.02f, (float)(x - 20)) : 5.0f;
	dao_thickness_setup_init(&ts, &cam1, 2.0f);
	dao_thickness_rows(&ts, zs, ts1, 0, 1);
	/* the chord from the outer edge of its first pixel to that of its last */
	const float z0 = zs[20], z1 = zs[29];
	const float dx = (29.5f * cam1.ax + cam1.bx) * z1 - (19.5f * cam1.ax + cam1.bx) * z0;
	const float dy = cam1.by * (z1 - z0);
	const float chord = sqrtf(dx * dx + dy * dy + (z1 - z0) * (z1 - z0));
	print_message("a 10 px strip sloping 2 %%/px: %.3f m (chord %.3f m, flat %.3f m)\n",
		      ts1[25], chord, 10 * px);
	assert_float_equal(ts1[25], chord, 1e-4);
	assert_true(chord > 10 * px + 0.1f);
}

/* Holes end a run on its outline only when something farther lies beyond them (a
 * shadow beside an object) or nothing does up to the border: a dropout inside a
 * surface or a hole before a nearer one says nothing about where it ends. */
static void test_run_holes(void **state)
{
	(void)state;
	struct dao_camera cam;
	camera(&cam, 64, 4);
	const float px = 2.0f / (float)cam.fx;
	float z[64 * 4], t[64 * 4];
	for (int x = 0; x < 64; x++) {
		const int strip = x >= 20 && x < 30, gap = x >= 30 && x < 34;
		/* a surface 20..49 with a dropout at 35 */
		z[0 * 64 + x] = x == 35 ? 0.0f : x >= 20 && x < 50 ? 2.0f : 3.0f;
		z[1 * 64 + x] = strip ? 2.0f : gap ? 0.0f : 3.0f; /* a shadow, then farther */
		z[2 * 64 + x] = strip ? 2.0f : gap ? 0.0f : x < 20 ? 3.0f : 1.0f; /* then nearer */
		z[3 * 64 + x] = strip ? 2.0f : x < 20 ? 3.0f : 0.0f; /* holes up to the border */
	}
	struct dao_thickness_setup ts;
	dao_thickness_setup_init(&ts, &cam, 0.5f);
	dao_thickness_rows(&ts, z, t, 0, 4);
	assert_float_equal(t[0 * 64 + 25], 0.5f, 0.0f);
	assert_float_equal(t[0 * 64 + 40], 0.5f, 0.0f);
	assert_float_equal(t[1 * 64 + 25], 10 * px, 1e-5);
	assert_float_equal(t[2 * 64 + 25], 0.5f, 0.0f);
	assert_float_equal(t[3 * 64 + 25], 10 * px, 1e-5);
}

/*
 * A face hidden in a hole across the baseline (thickness_run.c, hidden_face): on
 * noisy depth whose dropouts are not filled, a run of 10 px at 2 m (3.8 cm,
 * under half the 0.11 m spacing) ended along a column by a hole of 2 px or
 * more with something farther beyond it gets the bound, as the lowest board of
 * shelves-below under structured light, whose underside lies in such a hole;
 * with a direct step or a hole of 1 px, along a row (the baseline, where such
 * holes are shadows beside poles too), on clean depth or with the dropouts
 * filled it keeps its chord, and so does a run of 4 px.  The same in the
 * blocked passes as in the references.
 */
static void test_hidden_face(void **state)
{
	(void)state;
	enum { HW = 640, HH = 40 };
	struct dao_camera cam;
	camera(&cam, HW, HH);
	const float px = 2.0f / (float)cam.fx;
	float *z = malloc(sizeof(float) * HW * HH), *zt = malloc(sizeof(float) * HW * HH);
	float *t = malloc(sizeof(float) * HW * HH);
	assert_non_null(z);
	assert_non_null(zt);
	assert_non_null(t);
	/* a board 10 rows high across the image (rows 10..19; 4 rows, 10..13, in columns
	 * 400..)  before a wall at 3 m; below it, by column, a hole of 3 px (columns
	 * 0..199), none (200..299), a hole of 1 px (300..399), a hole of 3 px (400..) */
	for (int y = 0; y < HH; y++)
		for (int x = 0; x < HW; x++) {
			const int bottom = x < 400 ? 20 : 14;
			const int hole = x < 200 || x >= 400 ? 3 : x < 300 ? 0 : 1;
			const int board = y >= 10 && y < bottom;
			z[(size_t)y * HW + x] = board ? 2.0f : y >= bottom && y < bottom + hole ? 0.0f
											       : 3.0f;
		}
	/* the same turned: a post 10 columns wide (300..309) with a hole of 3 px left of
	 * it, along the rows */
	for (int y = 0; y < HH; y++)
		for (int x = 0; x < HW; x++)
			zt[(size_t)y * HW + x] = x >= 300 && x < 310 ? 2.0f
						 : x >= 297 && x < 300 ? 0.0f : 3.0f;
	struct dao_thickness_setup ts;
	dao_thickness_setup_init(&ts, &cam, 0.5f);
	ts.spacing = 0.11f;
	/* structured light's: a prefilter's scale of 14 px, not filled */
	dao_thickness_setup_noise(&ts, 14.0f, 0.0012f);
	assert_true(ts.noise_k > 0.0f);
	assert_int_equal(ts.fill_px, 0);
	dao_thickness_rows(&ts, z, t, 0, HH);
	cols(&ts, z, t, 0, HW);
	const float hidden = t[15 * HW + 100], step = t[15 * HW + 250], one = t[15 * HW + 350];
	const float shortrun = t[12 * HW + 500];
	dao_thickness_rows(&ts, zt, t, 0, HH);
	cols(&ts, zt, t, 0, HW);
	const float along = t[20 * HW + 305];
	print_message("a 10 px board (%.1f cm), noisy: a hole of 3 px below %.3f m, a step %.3f, "
		      "1 px %.3f, 4 px board %.3f, a post with the hole along the row %.3f\n",
		      (double)(10 * px * 100), (double)hidden, (double)step, (double)one,
		      (double)shortrun, (double)along);
	assert_float_equal(hidden, 0.5f, 0.0f);
	assert_float_equal(step, 10 * px, 1e-4);
	assert_float_equal(one, 10 * px, 1e-4);
	assert_float_equal(shortrun, 4 * px, 1e-4);
	assert_float_equal(along, 10 * px, 1e-4);
	/* the same in the blocked passes as in the references */
	expect_blocked_same_kf(&cam, z, 0.5f, ts.spacing, ts.noise_k, 0);
	expect_blocked_same_kf(&cam, zt, 0.5f, ts.spacing, ts.noise_k, 0);
	/* clean, or the dropouts filled: the chord */
	for (int c = 0; c < 2; c++) {
		dao_thickness_setup_init(&ts, &cam, 0.5f);
		ts.spacing = 0.11f;
		if (c)
			dao_thickness_setup_noise(&ts, 5.0f, 0.0012f);
		assert_int_equal(ts.fill_px, DAO_THICKNESS_FILL_PX);
		dao_thickness_rows(&ts, z, t, 0, HH);
		cols(&ts, z, t, 0, HW);
		assert_float_equal(t[15 * HW + 100], 10 * px, 1e-4);
	}
	free(z);
	free(zt);
	free(t);
}

/*
 * Slabs 2, 3 and 5 cm thick (80 x 60 cm, turned by 20 degrees) floating 35 cm
 * above a floor, seen from above at about 35 degrees, as the floating-plate
 * scene sees its plate: the top faces are wide on screen in rows and
 * columns (their extents, over 0.5 m, say nothing), their thickness shows
 * only in their edge faces.
 */
static const double slab_t[3] = { 0.02, 0.03, 0.05 };

static vec3 rot(const vec3 R[3], vec3 p)
{
	return v3(v3_dot(R[0], p), v3_dot(R[1], p), v3_dot(R[2], p));
}

static void slabs_scene(struct synth_scene *s, vec3 *up)
{
	*s = (struct synth_scene){ .name = "slabs" };
	const vec3 eye = v3(0.3, -0.3, 1.7), target = v3(0.0, 1.8, 0.3);
	const vec3 f = v3_normalize(v3_sub(target, eye));
	const vec3 right = v3_normalize(v3_cross(f, v3(0, 0, 1)));
	const vec3 R[3] = { right, v3_cross(f, right), f };
	s->prims[s->count++] = (struct synth_prim){ .kind = SYNTH_HALFSPACE, .c = { 0, 0, 0 },
						    .n = { 0, 0, 1 } };
	s->prims[s->count++] = (struct synth_prim){ .kind = SYNTH_HALFSPACE, .c = { 0, 3.4, 0 },
						    .n = { 0, -1, 0 } };
	const double a = 20.0 * 3.14159265358979 / 180.0;
	for (int i = 0; i < 3; i++)
		s->prims[s->count++] = (struct synth_prim){
			.kind = SYNTH_BOX, .c = { -1.0 + 1.0 * i, 1.8 + 0.2 * i, 0.35 },
			.axis = { { cos(a), sin(a), 0 }, { -sin(a), cos(a), 0 }, { 0, 0, 1 } },
			.half = { 0.4, 0.3, 0.5 * slab_t[i] } };
	for (int i = 0; i < s->count; i++) {
		synth_prim_transform(&s->prims[i], R, eye);
		synth_prim_bound(&s->prims[i]);
	}
	*up = rot(R, v3(0, 0, 1));
}

/* The slabs, clean, one ray a pixel, on the test camera. */
static void render_slabs(struct synth_scene *s, vec3 *up, struct dao_camera *cam,
			 struct synth_image *img)
{
	slabs_scene(s, up);
	camera(cam, W, H);
	assert_int_equal(synth_render(s, cam, 0.5, 0, 1, img, NULL), 0);
}

/* What a slab's pixel should get (thickness.h): 3 times its ray's length `through` the
 * slab, at least that length plus `spacing`, at most that length plus the larger of
 * the spacing and DAO_SLAB_EXTRA_SEC spacings over the cosine `cosr` of the ray to the
 * slab's normal (with a spacing); at most the bound, 0.5 m. */
static double slab_want(double through, double cosr, double spacing)
{
	double extra = (DAO_THICKNESS_SLAB_SCALE - 1.0) * through;
	if (spacing > 0.0)
		extra = fmin(extra, fmax(spacing, DAO_SLAB_EXTRA_SEC * spacing / cosr));
	return fmin(0.5, through + fmax(extra, spacing));
}

/* The estimate on slab i's top face against slab_want of each pixel's ray through the
 * slab: the median ratio; *n the pixels. */
static double slab_ratio(const struct synth_scene *s, vec3 up, const struct dao_camera *cam,
			 const float *t, int i, double spacing, int *n)
{
	static float r[W * H];
	*n = 0;
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			const vec3 d = v3_normalize(v3(x * cam->ax + cam->bx, y * cam->ay + cam->by, 1));
			double tt;
			vec3 nn;
			if (synth_trace(s, v3(0, 0, 0), d, 0.0, 100.0, &tt, &nn) != 2 + i ||
			    v3_dot(nn, up) < 0.99)
				continue;
			const double through = slab_t[i] / fabs(v3_dot(d, up));
			r[(*n)++] = (float)(t[(size_t)y * W + x] /
					    slab_want(through, fabs(v3_dot(d, up)), spacing));
		}
	if (*n == 0)
		return 0;
	qsort(r, (size_t)*n, sizeof r[0], cmp_float);
	return r[*n / 2];
}

static void test_slabs(void **state)
{
	(void)state;
	struct synth_scene s;
	struct dao_camera cam;
	struct synth_image img;
	vec3 up;
	render_slabs(&s, &up, &cam, &img);
	float *t = malloc((size_t)W * H * sizeof(float));
	assert_non_null(t);
	estimate(&cam, img.depth, 0.5f, t);
	for (int i = 0; i < 3; i++) {
		int n;
		const double m = slab_ratio(&s, up, &cam, t, i, 0.0, &n);
		print_message("slab %.0f cm thick: top face (%d px) estimate / (%.0f x its rays' "
			      "length through it) %.2f\n", slab_t[i] * 100, n,
			      (double)DAO_THICKNESS_SLAB_SCALE, m);
		assert_true(n > 2000);
		assert_true(m > 0.8 && m < 1.25);
	}
	/* the floor around them runs into the border: the bound */
	assert_float_equal(t[(size_t)470 * W + 320], 0.5f, 0.0f);
	free(t);
	synth_image_free(&img);
}

/*
 * A scene as `sensor` delivers it (millimetres, seed 7: not one of eval's),
 * through the pipeline at the medium preset with VBAO and the thickness from
 * the image: its filtered depth in z (cam's size), the estimate in t, made
 * with the crease test the pipeline derives from the frame's measured noise.
 */
static void sensor_estimate(const struct synth_scene *s, const struct dao_camera *cam,
			    const struct synth_image *img, enum synth_sensor sensor, float *z, float *t)
{
	struct dao_error err;
	struct synth_case c;
	const int w = (int)cam->width, h = (int)cam->height;
	assert_int_equal(synth_case_simulate(&c, s, 0, cam, img, sensor, 7, 2, &err), 0);
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_MEDIUM);
	p.algorithm = DAO_ALGORITHM_VBAO;
	p.vbao_thickness_mode = DAO_VBAO_THICKNESS_IMAGE;
	struct dao_context *ctx;
	assert_int_equal(dao_context_create(&ctx, cam, &p, &err), 0);
	const struct dao_frame depth = {
		.format = DAO_PIXFMT_DEPTH16, .width = (uint32_t)w, .height = (uint32_t)h,
		.stride = w * (int)sizeof(uint16_t), .data = c.depth_mm, .depth_unit = 0.001f,
	};
	struct dao_frame out = {
		.format = DAO_PIXFMT_DEPTH_F32, .width = (uint32_t)w, .height = (uint32_t)h,
		.stride = w * (int)sizeof(float), .data = z,
	};
	assert_int_equal(dao_context_process(ctx, &depth, NULL, 0, NULL, &err), 0);
	assert_int_equal(dao_context_get_depth(ctx, &out, &err), 0);
	struct dao_noise_info ni;
	dao_context_noise(ctx, &ni);
	assert_true(ni.measured);
	dao_context_destroy(ctx);
	synth_case_free(&c);
	/* as the pipeline runs it (context_frame.c) */
	struct dao_thickness_setup ts;
	dao_thickness_setup_init(&ts, cam, 0.5f);
	dao_thickness_setup_rounding(&ts, ni.prefilter_scale);
	dao_thickness_setup_noise(&ts, ni.prefilter_scale, ni.sigma_area);
	float *zf = malloc((size_t)w * h * sizeof(float));
	assert_non_null(zf);
	dao_thickness_fill_rows(&ts, z, zf, 0, h);
	dao_thickness_rows(&ts, zf, t, 0, h);
	cols(&ts, zf, t, 0, w);
	free(zf);
}

/*
 * The share of the pixels with depth whose estimate is less than half of what
 * it should be: half the length of the pixel's ray through the object it
 * hits (ray-traced; walls and floors: infinite), at most the bound 0.5 m.
 */
static double too_thin_share(const struct synth_scene *s, const struct dao_camera *cam,
			     const float *z, const float *t)
{
	const int w = (int)cam->width, h = (int)cam->height;
	long n = 0, thin = 0;
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			const size_t k = (size_t)y * w + x;
			if (!(z[k] > 0.0f))
				continue;
			const vec3 d = v3_normalize(v3(x * cam->ax + cam->bx, y * cam->ay + cam->by, 1));
			double t0, t1 = 1e9;
			vec3 nn;
			const int i = synth_trace(s, v3(0, 0, 0), d, 0.0, 100.0, &t0, &nn);
			if (i < 0)
				continue;
			double through = 1e9;
			if (s->prims[i].kind != SYNTH_HALFSPACE &&
			    synth_prim_intersect(&s->prims[i], v3(0, 0, 0), d, t0 + 1e-5, 100.0, &t1, &nn))
				through = t1 - t0;
			n++;
			thin += t[k] < 0.5 * fmin(through, 0.5);
		}
	return (double)thin / (double)n;
}

/*
 * Boxes on a floor before a wall, as a Gaussian sensor (2 % holes) and a
 * structured-light sensor (holes in its shadows and where it loses the dots)
 * deliver them: walls, floor and boxes are thick.  A hole inside a surface
 * is no outline: the runs between a sensor's dropouts made walls, floor and
 * box faces as thin as the distance between two holes (before: 6.3 % of the
 * pixels too thin with Gaussian noise, 4.4 % with structured light, 0.04 %
 * clean), which let the light through where they meet (boxes +8 % MAE over
 * GTAO on both inputs).
 */
static void test_boxes_noisy(void **state)
{
	(void)state;
	static const enum synth_sensor sensors[] = { SYNTH_SENSOR_CLEAN, SYNTH_SENSOR_GAUSSIAN,
						     SYNTH_SENSOR_STRUCTURED_LIGHT };
	struct synth_scene s;
	struct dao_camera cam;
	struct synth_image img;
	struct dao_error err;
	assert_int_equal(synth_scene_build_variant("boxes", 0.0, 0, &s, &err), 0);
	synth_default_camera(&cam);
	assert_int_equal(synth_render(&s, &cam, 0.5, 0, 2, &img, &err), 0);
	const size_t n = (size_t)cam.width * cam.height;
	float *z = malloc(n * sizeof(float)), *t = malloc(n * sizeof(float));
	assert_non_null(z);
	assert_non_null(t);
	for (int k = 0; k < 3; k++) {
		sensor_estimate(&s, &cam, &img, sensors[k], z, t);
		const double share = too_thin_share(&s, &cam, z, t);
		print_message("boxes, %s: %.2f %% of the pixels too thin\n",
			      synth_sensor_name(sensors[k]), 100.0 * share);
		/* measured 0.04 %, 0.04 %, 4.4 %; with the dropouts filled (thickness.h,
		 * dao_thickness_fill_rows; Gaussian only, structured light's prefilter
		 * scale is over DAO_THICKNESS_FILL_PX) 0.04 %, 0.43 %, 4.4 %: runs that go
		 * on across holes reach more ends, some of them false slabs and face
		 * bounds (boxes' MAE with Gaussian noise +2 -> +3 % over GTAO, docs/design/thickness.md)
		 * (structured light: the edge faces of some
		 * boxes' narrow sides pass the rounded crease test, below; 3.6 % before
		 * the face bound across holes, which bounds some box sides lost in holes
		 * like a board's edge face: boxes' MAE 0.0359 -> 0.0360, docs/design/thickness.md) */
		assert_true(share < (sensors[k] == SYNTH_SENSOR_STRUCTURED_LIGHT ? 0.05 : 0.01));
	}
	free(t);
	free(z);
	synth_image_free(&img);
}

static void expect_blocked_same(const struct dao_camera *cam, const float *z, float max,
				float spacing);

/*
 * The same slabs with VBAO's sample spacing (the pipeline's 0.11 m at the medium
 * preset; 0.15 m here): the 2 and 3 cm slabs take their rays' length through the
 * slab plus the spacing, more than 3 times that length; so does the 5 cm slab, seen
 * within 60 degrees of its normal (3 times its length, 26 cm, would be more).
 */
static void test_slabs_spacing(void **state)
{
	(void)state;
	struct synth_scene s;
	struct dao_camera cam;
	struct synth_image img;
	vec3 up;
	render_slabs(&s, &up, &cam, &img);
	float *t = malloc((size_t)W * H * sizeof(float));
	assert_non_null(t);
	struct dao_thickness_setup ts;
	dao_thickness_setup_init(&ts, &cam, 0.5f);
	assert_float_equal(ts.spacing, 0.0f, 0.0f); /* none unless the pipeline sets it */
	ts.spacing = 0.15f;
	estimate_spaced(&cam, img.depth, 0.5f, ts.spacing, t);
	for (int i = 0; i < 3; i++) {
		int n;
		const double m = slab_ratio(&s, up, &cam, t, i, ts.spacing, &n);
		const double m3 = slab_ratio(&s, up, &cam, t, i, 0.0, &n);
		print_message("slab %.0f cm thick, spacing %.2f m: estimate / what it should get "
			      "%.2f (/ 3 x %.2f)\n", slab_t[i] * 100, (double)ts.spacing, m,
			      m3);
		assert_true(n > 2000);
		assert_true(m > 0.8 && m < 1.25);
		/* measured 0.97, 0.98 and 0.99; against 3 times the length 1.50 and 1.15 (the
		 * old rule: 0.88 and 0.93) */
		if (i < 2)
			assert_true(m3 > 1.1);
	}
	expect_blocked_same(&cam, img.depth, 0.5f, ts.spacing);
	free(t);
	synth_image_free(&img);
}

/*
 * The slabs with a small spacing, 4 cm (thickness.h, DAO_SLAB_EXTRA_SEC): seen from
 * above at about 35 degrees, within 60 of their normal, they get their rays' length
 * plus the spacing, not 3 times that length (the 5 cm slab: 12.7 cm, not 26 cm; the
 * factor alone gave 2.0 times the length plus the spacing).
 */
static void test_slabs_spacing_face_on(void **state)
{
	(void)state;
	struct synth_scene s;
	struct dao_camera cam;
	struct synth_image img;
	vec3 up;
	render_slabs(&s, &up, &cam, &img);
	float *t = malloc((size_t)W * H * sizeof(float));
	assert_non_null(t);
	const float spacing = 0.04f;
	estimate_spaced(&cam, img.depth, 0.5f, spacing, t);
	for (int i = 0; i < 3; i++) {
		int n;
		const double m = slab_ratio(&s, up, &cam, t, i, spacing, &n);
		const double m3 = slab_ratio(&s, up, &cam, t, i, 0.0, &n);
		print_message("slab %.0f cm thick, spacing %.2f m: estimate / its length plus the "
			      "spacing %.2f (/ 3 x %.2f)\n", slab_t[i] * 100, (double)spacing, m, m3);
		assert_true(n > 2000);
		assert_true(m > 0.8 && m < 1.25);
		if (i == 2)
			assert_true(m3 < 0.7);
	}
	expect_blocked_same(&cam, img.depth, 0.5f, spacing);
	free(t);
	synth_image_free(&img);
}

/*
 * Upright boards 1 and 3 cm thick (60 cm wide, 1 m tall, standing on a floor,
 * turned by 30 and 10 degrees) and a box 50 x 50 x 80 cm, seen from 1.4 m
 * high as the panels scene sees its boards: a board's rows span 60 cm (the
 * bound) and its columns run into the floor without a step, so without the
 * absence of a visible edge face every board pixel kept the bound, 0.5 m
 * (15 and 5 times 3 times its rays' length through the board).  The boards'
 * top faces show over less than a pixel or two in the columns: the bound
 * (thickness_bound.c, face_bound_at) gives the boards about their thickness, and
 * the box, whose top face shows, is not made thin.  The same in the blocked
 * passes as in the references.
 */
static void upright_boards_scene(struct synth_scene *s)
{
	*s = (struct synth_scene){ .name = "boards" };
	const vec3 eye = v3(0.2, -0.1, 1.4), target = v3(0.0, 3.0, 0.5);
	const vec3 f = v3_normalize(v3_sub(target, eye));
	const vec3 right = v3_normalize(v3_cross(f, v3(0, 0, 1)));
	const vec3 R[3] = { right, v3_cross(f, right), f };
	s->prims[s->count++] = (struct synth_prim){ .kind = SYNTH_HALFSPACE, .c = { 0, 0, 0 },
						    .n = { 0, 0, 1 } };
	s->prims[s->count++] = (struct synth_prim){ .kind = SYNTH_HALFSPACE, .c = { 0, 3.2, 0 },
						    .n = { 0, -1, 0 } };
	static const double yaw[3] = { 30.0, 10.0, -10.0 };
	static const vec3 half[3] = { { 0.3, 0.005, 0.5 }, { 0.3, 0.015, 0.5 },
				      { 0.25, 0.25, 0.4 } };
	for (int i = 0; i < 3; i++) {
		const double a = yaw[i] * 3.14159265358979 / 180.0;
		s->prims[s->count++] = (struct synth_prim){
			.kind = SYNTH_BOX, .c = { -0.8 + 0.8 * i, 2.2 + 0.2 * i, half[i].z },
			.axis = { { cos(a), sin(a), 0 }, { -sin(a), cos(a), 0 }, { 0, 0, 1 } },
			.half = half[i] };
	}
	for (int i = 0; i < s->count; i++) {
		synth_prim_transform(&s->prims[i], R, eye);
		synth_prim_bound(&s->prims[i]);
	}
}

/* Over the pixels that see prim p: the median of the estimate / 3 times the ray's length
 * through the prim (at most the bound), and the share where it is under half of that. */
static double prim_ratio(const struct synth_scene *s, const struct dao_camera *cam,
			 const float *t, const float *inside, int p, double *thin, double *at_max,
			 int *n)
{
	static float r[W * H];
	int nthin = 0, nmax = 0;
	*n = 0;
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			const vec3 d = v3_normalize(v3(x * cam->ax + cam->bx, y * cam->ay + cam->by, 1));
			double tt;
			vec3 nn;
			const size_t k = (size_t)y * W + x;
			if (synth_trace(s, v3(0, 0, 0), d, 0.0, 100.0, &tt, &nn) != p)
				continue;
			const double want = fmin(0.5, DAO_THICKNESS_SLAB_SCALE * inside[k]);
			r[(*n)++] = (float)(t[k] / want);
			nthin += t[k] < 0.5 * want;
			nmax += t[k] >= 0.5f;
		}
	assert_true(*n > 0);
	*thin = (double)nthin / *n;
	*at_max = (double)nmax / *n;
	qsort(r, (size_t)*n, sizeof r[0], cmp_float);
	return r[*n / 2];
}

/* The upright boards rendered clean, with planes for the estimate and for the
 * primitive each pixel shows (synth_inside_plane). */
struct upright_boards {
	struct synth_scene s;
	struct dao_camera cam;
	struct synth_image img;
	float *t, *inside;
};

static void upright_boards_render(struct upright_boards *b)
{
	upright_boards_scene(&b->s);
	camera(&b->cam, W, H);
	assert_int_equal(synth_render(&b->s, &b->cam, 0.5, 0, 1, &b->img, NULL), 0);
	b->t = malloc((size_t)W * H * sizeof(float));
	b->inside = malloc((size_t)W * H * sizeof(float));
	assert_non_null(b->t);
	assert_non_null(b->inside);
	synth_inside_plane(&b->s, &b->cam, b->inside);
}

static void upright_boards_free(struct upright_boards *b)
{
	free(b->inside);
	free(b->t);
	synth_image_free(&b->img);
}

/* The two boards' estimates near 3 x their rays' length through them, fewer
 * than at_most of their pixels at the bound; the box not made thin. */
static void expect_upright_boards(const struct synth_scene *s, const struct dao_camera *cam,
				  const float *t, const float *inside, const char *how,
				  double at_most)
{
	static const char *const what[3] = { "board 1 cm", "board 3 cm", "box 50 cm" };
	for (int i = 0; i < 3; i++) {
		int n;
		double thin, at_max;
		const double m = prim_ratio(s, cam, t, inside, 2 + i, &thin, &at_max, &n);
		print_message("%s%s (%d px): estimate / (3 x its rays' length through it) median "
			      "%.2f, under half %.1f %%, at the bound %.1f %%\n", what[i], how, n, m,
			      100.0 * thin, 100.0 * at_max);
		assert_true(n > 5000);
		if (i < 2)
			assert_true(m > 0.7 && m < 2.0 && at_max < at_most);
		else
			assert_true(m > 0.9 && thin < 0.01);
	}
}

static void test_boards_upright(void **state)
{
	(void)state;
	struct upright_boards b;
	upright_boards_render(&b);
	estimate(&b.cam, b.img.depth, 0.5f, b.t);
	/* medians 1.11 and 1.15 with the value made for the middle of the bound's
	 * interval (2.2 and 1.7 with the bound itself; 15.6 before it); at the
	 * bound 0.7 % and 0 (the 1 cm board's far end, whose side face looks away:
	 * 5.5 % before the bound carried across, thickness_bound_across.c) */
	expect_upright_boards(&b.s, &b.cam, b.t, b.inside, "", 0.01);
	expect_blocked_same(&b.cam, b.img.depth, 0.5f, 0.0f);
	expect_blocked_same(&b.cam, b.img.depth, 0.5f, 0.11f);
	upright_boards_free(&b);
}

/*
 * The upright boards of test_boards_upright as a Gaussian sensor delivers
 * them, through the pipeline (sensor_estimate, seed 7), as the panels scene's
 * boards (docs/design/thickness.md, "Boards seen face-on under Gaussian noise").  Two things
 * made the 3 cm board thick: its columns' face bounds held only over the first
 * pixels of the broad face, where the noise tilted a single segment by more
 * than the straightness test's 20 degrees (straight_face_end: now the chord
 * from DAO_BOUND_FACE_LONG pixels back may pass it), and the prefilter rounded
 * the crease to the top face into the edge face's pixels, so a bound made from
 * their count f was 2 - 3 times too thick (face_bound_at: now at most the end
 * pixel's depth behind the broad face plus a pixel's extent).  The 1 cm board
 * median 1.01, 5.3 % at the bound (1.05 and 19.5 % before; the chord alone
 * gives the same); the 3 cm board 1.86 and 16.4 % (4.25 and 42.3 % before;
 * 2.52 and 18.6 % with the chord alone, 3.16 and 40.1 % with the depth
 * alone); the box 1.00, 3.3 % under half either way.  The same in the blocked
 * passes as in the references on that depth.
 */
static void test_boards_gaussian(void **state)
{
	(void)state;
	struct upright_boards b;
	upright_boards_render(&b);
	float *z = malloc((size_t)W * H * sizeof(float));
	assert_non_null(z);
	sensor_estimate(&b.s, &b.cam, &b.img, SYNTH_SENSOR_GAUSSIAN, z, b.t);
	static const char *const what[3] = { "board 1 cm", "board 3 cm", "box 50 cm" };
	for (int i = 0; i < 3; i++) {
		int n;
		double thin, at_max;
		const double m =
			prim_ratio(&b.s, &b.cam, b.t, b.inside, 2 + i, &thin, &at_max, &n);
		print_message("%s, Gaussian sensor (%d px): estimate / (3 x its rays' length "
			      "through it) median %.2f, under half %.1f %%, "
			      "at the bound %.1f %%\n",
			      what[i], n, m, 100.0 * thin, 100.0 * at_max);
		assert_true(n > 5000);
		if (i == 0)
			assert_true(m > 0.7 && m < 2.0 && at_max < 0.1);
		else if (i == 1)
			assert_true(m > 0.7 && m < 2.2 && at_max < 0.25);
		else
			assert_true(m > 0.9 && thin < 0.05);
	}
	expect_blocked_same_k(&b.cam, z, 0.5f, 0.11f, 0.0026f);
	free(z);
	upright_boards_free(&b);
}

/* Mean |ao - truth| over the wall behind the poles (rows 60..170 of 240, z > 2.5 m). */
static double wall_mae(const float *ao, const struct synth_image *img)
{
	double sum = 0;
	int n = 0;
	for (int y = 60; y < 170; y++)
		for (int x = 0; x < img->width; x++) {
			const size_t k = (size_t)y * img->width + x;
			if (img->depth[k] > WALL_Z - 0.01) {
				sum += fabs(ao[k] - img->gt[k]);
				n++;
			}
		}
	return sum / n;
}

static double run_mae(const struct dao_camera *cam, const struct synth_image *img, int algorithm,
		      int mode, float thickness)
{
	float *ao = dao_test_ao_of_depth(cam, img->depth, algorithm, mode, thickness);
	assert_non_null(ao);
	const double m = wall_mae(ao, img);
	free(ao);
	return m;
}

/* The row pass (chunks of a row) and the column pass (blocks of columns, in
 * two sweeps), split anywhere, against the references that walk each line
 * pixel by pixel, bit for bit; and the thickness plane the column pass splits
 * by phase as it goes, against the split of the reference's result. */
static void expect_blocked_same_k(const struct dao_camera *cam, const float *z, float max,
				  float spacing, float noise_k)
{
	expect_blocked_same_kf(cam, z, max, spacing, noise_k, DAO_THICKNESS_FILL_PX);
}

/* ... with fill_px (0: structured light's setting, dao_thickness_setup_noise) */
static void expect_blocked_same_kf(const struct dao_camera *cam, const float *z, float max,
				   float spacing, float noise_k, int fill_px)
{
	const int w = (int)cam->width, h = (int)cam->height;
	const size_t n = (size_t)w * h;
	float *ref = malloc(n * sizeof(float)), *got = malloc(n * sizeof(float));
	assert_non_null(ref);
	assert_non_null(got);
	struct dao_thickness_setup ts;
	dao_thickness_setup_init(&ts, cam, max);
	ts.spacing = spacing;
	ts.noise_k = noise_k;
	ts.fill_px = fill_px;
	dao_thickness_rows_ref(&ts, z, ref, 0, h);
	dao_thickness_rows(&ts, z, got, 0, h / 3);
	dao_thickness_rows(&ts, z, got, h / 3, h);
	size_t diff = 0;
	for (size_t i = 0; i < n; i++)
		diff += memcmp(&ref[i], &got[i], sizeof(float)) != 0;
	assert_int_equal(diff, 0);
	dao_thickness_cols_ref(&ts, z, ref, 0, w);
	struct dao_gtao_planes pr, pg;
	assert_int_equal(dao_gtao_planes_init(&pr, w, h, 20.0f), 0);
	assert_int_equal(dao_gtao_planes_init(&pg, w, h, 20.0f), 0);
	assert_int_equal(dao_gtao_planes_init_thickness(&pr), 0);
	assert_int_equal(dao_gtao_planes_init_thickness(&pg), 0);
	dao_gtao_planes_fill_thickness(&pr, ref, 0, h);
	float *scratch = malloc(dao_thickness_cols_scratch(h) * sizeof(float));
	assert_non_null(scratch);
	/* splits that cut blocks: one column, a partial block, the rest */
	const int cuts[] = { 0, 1, 1 + DAO_THICKNESS_COL_BLOCK / 2, 3 * DAO_THICKNESS_COL_BLOCK + 5, w };
	for (size_t c = 0; c + 1 < sizeof(cuts) / sizeof(cuts[0]); c++)
		dao_thickness_cols(&ts, z, got, scratch, &pg, cuts[c], cuts[c + 1]);
	for (size_t i = 0; i < n; i++)
		diff += memcmp(&ref[i], &got[i], sizeof(float)) != 0;
	assert_int_equal(diff, 0);
	const size_t np = ((size_t)h + 2) * 4 * (size_t)pr.stride4;
	assert_memory_equal(pr.thick, pg.thick, np * sizeof(uint16_t));
	free(scratch);
	dao_gtao_planes_free(&pg);
	dao_gtao_planes_free(&pr);
	free(got);
	free(ref);
}

static void expect_blocked_same(const struct dao_camera *cam, const float *z, float max,
				float spacing)
{
	expect_blocked_same_k(cam, z, max, spacing, 0.0f);
}

static void test_same_as_reference(void **state)
{
	(void)state;
	struct synth_scene s;
	struct dao_camera cam;
	struct synth_image img;
	vec3 up;
	camera(&cam, W, H);
	poles_scene(&s);
	assert_int_equal(synth_render(&s, &cam, 0.5, 0, 1, &img, NULL), 0);
	expect_blocked_same(&cam, img.depth, 0.5f, 0.0f);
	expect_blocked_same(&cam, img.depth, 0.15f, 0.0f);
	synth_image_free(&img);
	slabs_scene(&s, &up);
	assert_int_equal(synth_render(&s, &cam, 0.5, 0, 1, &img, NULL), 0);
	expect_blocked_same(&cam, img.depth, 0.5f, 0.0f);
	synth_image_free(&img);
	/* a checkerboard of 8 px squares 1 and 1.2 m away with noise and holes, on a
	 * frame whose width is no multiple of the block */
	camera(&cam, 203, 97);
	float *z = malloc((size_t)203 * 97 * sizeof(float));
	assert_non_null(z);
	uint32_t r = 12345;
	for (int y = 0; y < 97; y++)
		for (int x = 0; x < 203; x++) {
			r = r * 1664525u + 1013904223u;
			const float noise = 0.004f * ((float)(r >> 8) / 16777216.0f - 0.5f);
			z[(size_t)y * 203 + x] = (r >> 28) == 0 ? 0.0f
				: (((x >> 3) + (y >> 3)) & 1 ? 1.2f : 1.0f) + noise;
		}
	expect_blocked_same(&cam, z, 0.5f, 0.0f);
	/* with the noise tolerance of a structured-light frame (dao_thickness_setup_noise) */
	expect_blocked_same_k(&cam, z, 0.5f, 0.11f, 2.0f * 0.0013f);
	free(z);
	/* boards and a chair with that tolerance: runs longer than face_bound looks at,
	 * whose broad face's direction comes from their length (the memo's length key) */
	static const char *const boards[] = { "chair", "panels" };
	synth_default_camera(&cam);
	for (size_t i = 0; i < sizeof(boards) / sizeof(boards[0]); i++) {
		struct dao_error err;
		assert_int_equal(synth_scene_build(boards[i], 0.0, &s, &err), 0);
		assert_int_equal(synth_render(&s, &cam, 0.5, 0, 1, &img, NULL), 0);
		expect_blocked_same_k(&cam, img.depth, 0.5f, 0.11f, 2.0f * 0.0013f);
		synth_image_free(&img);
	}
}

/* The same on the real sensor frames of ../shared/data, raw (their holes, noise and
 * projector shadows as recorded); the frames not there are skipped. */
static void test_same_as_reference_real(void **state)
{
	(void)state;
	int n, done = 0;
	const struct synth_real_frame *frames = synth_real_frames(&n);
	const char *dir = synth_real_data_dir();
	for (int k = 0; k < n; k++) {
		char path[1024];
		snprintf(path, sizeof path, "%s/%s", dir, frames[k].file);
		FILE *probe = fopen(path, "rb");
		if (!probe)
			continue;
		fclose(probe);
		float *z;
		struct dao_camera cam;
		double unit;
		struct dao_error err;
		assert_int_equal(synth_real_frame_load(&frames[k], dir, &z, &cam, &unit, &err), 0);
		expect_blocked_same(&cam, z, 0.5f, 0.05f);
		expect_blocked_same_k(&cam, z, 0.5f, 0.05f, 2.0f * 0.0013f);
		free(z);
		done++;
	}
	print_message("%d of %d real frames estimated as the references do\n", done, n);
}

static void test_vbao_behind_poles(void **state)
{
	(void)state;
	struct synth_scene s;
	struct dao_camera cam;
	struct synth_image img;
	poles_scene(&s);
	camera(&cam, 320, 240);
	assert_int_equal(synth_render(&s, &cam, 0.5, 8, 2, &img, NULL), 0);
	const double g = run_mae(&cam, &img, DAO_ALGORITHM_GTAO, 0, 0.2f);
	const double c2 = run_mae(&cam, &img, DAO_ALGORITHM_VBAO, DAO_VBAO_THICKNESS_CONSTANT, 0.2f);
	const double c5 = run_mae(&cam, &img, DAO_ALGORITHM_VBAO, DAO_VBAO_THICKNESS_CONSTANT, 0.5f);
	const double e = run_mae(&cam, &img, DAO_ALGORITHM_VBAO, DAO_VBAO_THICKNESS_IMAGE, 0.2f);
	print_message("wall behind the poles, MAE: gtao %.4f, vbao 0.2 m %.4f, 0.5 m %.4f, "
		      "image %.4f\n", g, c2, c5, e);
	/* measured 0.1138, 0.0737, 0.1226, 0.0487 (the same before and after the slab test) */
	assert_true(e < 0.5 * g);
	assert_true(e < 0.75 * c2);
	assert_true(e < 0.5 * c5);
	synth_image_free(&img);
}

/*
 * The slabs of test_slabs as a Gaussian sensor delivers them, through the
 * pipeline: the measured noise has the prefilter round each edge face's
 * crease (a turn of 34 - 43 degrees left of about 90), and the crease test
 * follows the prefilter's scale (dao_thickness_setup_rounding).  With the 50
 * degree test of clean depth the 5 cm slab's top face kept the bound over
 * most of its pixels.  The 2 and 3 cm slabs' edge faces are not found with
 * this noise (their rounded turn stays under 30 degrees), but the absence of a
 * visible edge face (face_bound) bounds them about right: 0.89 and 0.97 (3.9
 * and 2.7 before, the bound's share).  None is found with structured light,
 * whose disparity bands hold an edge face within one or two steps and whose
 * block matching loses the last pixels of a silhouette to holes (docs/design/thickness.md);
 * the face bound across those holes, with the noise's tolerance for the end's
 * pixels, gives the 2 and 3 cm slabs 0.49 and 0.30 (3.90 and 2.71 before).
 */
static void test_slabs_noisy(void **state)
{
	(void)state;
	struct synth_scene s;
	struct dao_camera cam;
	struct synth_image img;
	vec3 up;
	/* the crease test's turn: 50 degrees up to 2 px, 30 from 5 px */
	struct dao_thickness_setup ts;
	camera(&cam, W, H);
	dao_thickness_setup_init(&ts, &cam, 0.5f);
	assert_float_equal(ts.crease_cos, cosf(50.0f * DAO_PI_F / 180.0f), 1e-6);
	dao_thickness_setup_rounding(&ts, 1.5f);
	assert_float_equal(ts.crease_cos, cosf(50.0f * DAO_PI_F / 180.0f), 1e-6);
	dao_thickness_setup_rounding(&ts, 3.5f);
	assert_float_equal(ts.crease_cos, cosf(40.0f * DAO_PI_F / 180.0f), 1e-6);
	dao_thickness_setup_rounding(&ts, 16.0f);
	assert_float_equal(ts.crease_cos, cosf(30.0f * DAO_PI_F / 180.0f), 1e-6);
	slabs_scene(&s, &up);
	assert_int_equal(synth_render(&s, &cam, 0.5, 0, 2, &img, NULL), 0);
	const size_t n = (size_t)W * H;
	float *z = malloc(n * sizeof(float)), *t = malloc(n * sizeof(float));
	assert_non_null(z);
	assert_non_null(t);
	static const enum synth_sensor sensors[] = { SYNTH_SENSOR_GAUSSIAN,
						     SYNTH_SENSOR_STRUCTURED_LIGHT };
	for (int k = 0; k < 2; k++) {
		sensor_estimate(&s, &cam, &img, sensors[k], z, t);
		for (int i = 0; i < 3; i++) {
			int np;
			const double m = slab_ratio(&s, up, &cam, t, i, 0.0, &np);
			print_message("slab %.0f cm thick, %s: top face (%d px) estimate / (%.0f x its "
				      "rays' length through it) %.2f\n", slab_t[i] * 100,
				      synth_sensor_name(sensors[k]), np,
				      (double)DAO_THICKNESS_SLAB_SCALE, m);
			assert_true(np > 2000);
			/* the 5 cm slab with Gaussian noise: found (0.92; 1.40 with the clean
			 * depth's 50 degrees, the bound's share of the rest).  With the face
			 * bound's value made for the middle of its interval 0.76, 0.88 and 0.87
			 * (0.89, 0.97, 0.92 with the bound itself): at spacing 0, as here; in the
			 * pipeline the spacing's term governs the thin slabs (the floating plate
			 * with Gaussian noise 0.0126 -> 0.0125) */
			/* With the dropouts filled (dao_thickness_fill_rows), more runs reach
			 * their ends and their face bounds: 0.53, 0.86 and 0.68 at spacing 0
			 * (the floating plate with Gaussian noise in the pipeline 0.0116 ->
			 * 0.0113, 256 rays) */
			if (k == 0)
				assert_true(m > 0.45 && m < 1.25);
			else if (i < 2)
				assert_true(m > 0.2 && m < 2.0);
		}
	}
	free(t);
	free(z);
	synth_image_free(&img);
}

/*
 * The slabs of test_slabs with their edge faces lost in holes, as a
 * structured-light sensor loses them (the window of its block matching
 * straddles the silhouette; docs/design/thickness.md, "Noisy input"): each top face's runs
 * end at a hole with the floor beyond it.  The hole can hide an edge face of
 * as many pixels as it has, so the face bound holds across it (face_bound),
 * its value made for the middle of what the end allows, here about half the
 * edge face: medians 0.63, 0.53 and 1.19 of 3 times the rays' length (before:
 * 3.94 for the 2 cm slab, the bound's share; in the pipeline the spacing of
 * VBAO's samples governs the thin slabs' value).
 */
static void test_slabs_edge_holes(void **state)
{
	(void)state;
	struct synth_scene s;
	struct dao_camera cam;
	struct synth_image img;
	vec3 up;
	render_slabs(&s, &up, &cam, &img);
	int lost = 0;
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			const vec3 d = v3_normalize(v3(x * cam.ax + cam.bx, y * cam.ay + cam.by, 1));
			double tt;
			vec3 nn;
			const int p = synth_trace(&s, v3(0, 0, 0), d, 0.0, 100.0, &tt, &nn);
			if (p >= 2 && v3_dot(nn, up) < 0.99) {
				img.depth[(size_t)y * W + x] = 0.0f;
				lost++;
			}
		}
	float *t = malloc((size_t)W * H * sizeof(float));
	assert_non_null(t);
	estimate(&cam, img.depth, 0.5f, t);
	for (int i = 0; i < 3; i++) {
		int n;
		const double m = slab_ratio(&s, up, &cam, t, i, 0.0, &n);
		print_message("slab %.0f cm thick, edge faces lost (%d px): top face (%d px) "
			      "estimate / (%.0f x its rays' length through it) %.2f\n",
			      slab_t[i] * 100, lost, n, (double)DAO_THICKNESS_SLAB_SCALE, m);
		assert_true(n > 2000);
		assert_true(m > 0.5 && m < 1.5);
	}
	expect_blocked_same(&cam, img.depth, 0.5f, 0.11f);
	expect_blocked_same_k(&cam, img.depth, 0.5f, 0.11f, 0.0026f);
	free(t);
	synth_image_free(&img);
}

/*
 * Dropouts inside a surface (thickness.h, dao_thickness_fill_rows; docs/design/thickness.md,
 * "Noisy input"): a Gaussian sensor drops 2 % of its pixels, and the
 * prefilter leaves holes of 1, 3, 5 and 7 px (measured on the chair's
 * Gaussian frame) with the same surface on both sides.  A hole is no outline,
 * so every piece of the chair's backrest (a 4 cm board seen face-on, 48 cm
 * wide) between two of them kept the bound along its row and its column.
 * With the holes filled along the rows the runs go on across them and the
 * board gets what it gets on clean depth; through the pipeline, which fills
 * them the same way, VBAO with the estimate is about as close to the truth
 * with the dropouts as without (before: the floor behind and below the chair
 * darkened by its backrest and seat at the bound).
 */
static void punch_dropouts(float *z, int w, int h)
{
	uint32_t r = 4242;
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			r = r * 1664525u + 1013904223u;
			if ((r >> 8) % 200 != 0)
				continue; /* 0.5 % of the pixels start a hole of 1 - 7 px */
			const int len = 1 + 2 * (int)((r >> 4) & 3);
			for (int k = 0; k < len && x + k < w; k++)
				z[(size_t)y * w + x + k] = 0.0f;
		}
}

static void test_chair_dropouts(void **state)
{
	(void)state;
	struct synth_scene s;
	struct dao_camera cam;
	struct synth_image img;
	struct dao_error err;
	assert_int_equal(synth_scene_build_variant("chair", 0.0, 0, &s, &err), 0);
	synth_default_camera(&cam);
	assert_int_equal(synth_render(&s, &cam, 0.5, 8, 2, &img, &err), 0);
	const size_t n = (size_t)cam.width * cam.height;
	float *z = malloc(n * sizeof(float)), *zf = malloc(n * sizeof(float));
	float *tc = malloc(n * sizeof(float)), *tr = malloc(n * sizeof(float));
	float *tf = malloc(n * sizeof(float));
	assert_non_null(z);
	assert_non_null(zf);
	assert_non_null(tc);
	assert_non_null(tr);
	assert_non_null(tf);
	memcpy(z, img.depth, n * sizeof(float));
	punch_dropouts(z, W, H);
	struct dao_thickness_setup ts;
	dao_thickness_setup_init(&ts, &cam, 0.5f);
	ts.spacing = 0.11f;
	dao_thickness_fill_rows(&ts, z, zf, 0, H);
	size_t holes = 0, left = 0;
	for (size_t k = 0; k < n; k++) {
		holes += !(z[k] > 0.0f);
		left += !(zf[k] > 0.0f);
	}
	estimate_spaced(&cam, img.depth, 0.5f, 0.11f, tc);
	estimate_spaced(&cam, z, 0.5f, 0.11f, tr);
	estimate_spaced(&cam, zf, 0.5f, 0.11f, tf);
	/* the backrest (the scene's last primitive): pixels with depth over 1.5 times
	 * their clean estimate */
	const int back = s.count - 1;
	int nb = 0, thick_r = 0, thick_f = 0;
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			const size_t k = (size_t)y * W + x;
			const vec3 d = v3_normalize(v3(x * cam.ax + cam.bx, y * cam.ay + cam.by, 1));
			double tt;
			if (!(z[k] > 0.0f) || synth_trace(&s, v3(0, 0, 0), d, 0.0, 100.0, &tt, NULL) != back)
				continue;
			nb++;
			thick_r += tr[k] > 1.5f * tc[k];
			thick_f += tf[k] > 1.5f * tc[k];
		}
	print_message("chair with dropouts (%.1f %% holes, %.2f %% left after the fill): "
		      "backrest pixels over 1.5 times their clean estimate: %.1f %% with the "
		      "holes, %.1f %% filled (%d px)\n", 100.0 * holes / n, 100.0 * left / n,
		      100.0 * thick_r / nb, 100.0 * thick_f / nb, nb);
	assert_true(nb > 10000);
	/* measured 34.0 % and 2.1 % */
	assert_true(thick_f < 0.05 * nb);
	expect_blocked_same(&cam, zf, 0.5f, 0.11f);
	/* through the pipeline */
	float *ec = dao_test_ao_of_depth(&cam, img.depth, DAO_ALGORITHM_VBAO,
					 DAO_VBAO_THICKNESS_IMAGE, 0.2f);
	float *ed = dao_test_ao_of_depth(&cam, z, DAO_ALGORITHM_VBAO, DAO_VBAO_THICKNESS_IMAGE, 0.2f);
	assert_non_null(ec);
	assert_non_null(ed);
	double sc = 0, sd = 0;
	long m = 0;
	for (size_t k = 0; k < n; k++)
		if (z[k] > 0.0f) {
			sc += fabs(ec[k] - img.gt[k]);
			sd += fabs(ed[k] - img.gt[k]);
			m++;
		}
	print_message("chair, VBAO with the estimate, MAE over the pixels with depth: clean "
		      "%.4f, with dropouts %.4f\n", sc / m, sd / m);
	/* measured 0.0109 and 0.0112 (0.0135 without the fill) */
	assert_true(sd < 1.05 * sc);
	free(ed);
	free(ec);
	free(tf);
	free(tr);
	free(tc);
	free(zf);
	free(z);
	synth_image_free(&img);
}

/*
 * Small images and their borders (thickness_fill.c, dao_thickness_fill_rows and
 * the face bound on noisy depth): widths and heights of 1 to 13 pixels (the fill looks at four
 * pixels at a time, then at the row's tail), holes of 0, NaN and negative depth up
 * to the borders, boards with a lip at their ends, noise.  The fill is its rule
 * pixel by pixel (a hole of at most fill_px between two pixels on one surface
 * filled linearly, everything else copied), and the blocked passes give the
 * references' result, within (0, max]: on the filled depth, and on the depth
 * itself on noisy settings (noise_k, fill_px 0); and
 * with pixels 50 times finer and holes down the columns too, so that column
 * runs are thinner than half a spacing beside a hole (hidden_face).
 */
static uint32_t small_rand(uint32_t *r)
{
	*r = *r * 1664525u + 1013904223u;
	return *r >> 8;
}

static void small_depth(float *z, int w, int h, uint32_t *r)
{
	const float zb = 2.5f + 0.001f * (float)(small_rand(r) % 1000);
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++)
			z[(size_t)y * w + x] = zb + 0.004f * (float)x + 0.003f * (float)y;
	const int x0 = (int)(small_rand(r) % (unsigned)w), y0 = (int)(small_rand(r) % (unsigned)h);
	const int x1 = x0 + 1 + (int)(small_rand(r) % (unsigned)w);
	const int y1 = y0 + 1 + (int)(small_rand(r) % (unsigned)h);
	const float zn = 0.8f + 0.001f * (float)(small_rand(r) % 1000);
	for (int y = y0; y < y1 && y < h; y++)
		for (int x = x0; x < x1 && x < w; x++)
			z[(size_t)y * w + x] = zn + 0.01f * (float)(x - x0) +
					       (y == y0 || x == x0 ? 0.02f : 0.0f);
	for (size_t i = 0; i < (size_t)w * h; i++) {
		const uint32_t u = small_rand(r) % 1000;
		z[i] *= 1.0f + 0.000002f * (float)(small_rand(r) % 1000) - 0.001f;
		if (u < 50)
			z[i] = 0.0f;
		else if (u < 60)
			z[i] = NAN;
		else if (u < 65)
			z[i] = -1.0f;
	}
	for (int k = 0; k < w * h / 12; k++) {
		const int y = (int)(small_rand(r) % (unsigned)h), x = (int)(small_rand(r) % (unsigned)w);
		const int len = 1 + (int)(small_rand(r) % 10);
		for (int i = 0; i < len && x + i < w; i++)
			z[(size_t)y * w + x + i] = 0.0f;
	}
}

static void expect_small_same(const struct dao_thickness_setup *ts, const float *z)
{
	const int w = ts->width, h = ts->height;
	const size_t n = (size_t)w * h;
	float *ref = malloc(n * sizeof(float)), *got = malloc(n * sizeof(float));
	float *scratch = malloc(dao_thickness_cols_scratch(h) * sizeof(float));
	assert_non_null(ref);
	assert_non_null(got);
	assert_non_null(scratch);
	dao_thickness_rows_ref(ts, z, ref, 0, h);
	dao_thickness_rows(ts, z, got, 0, h / 2);
	dao_thickness_rows(ts, z, got, h / 2, h);
	assert_memory_equal(ref, got, n * sizeof(float));
	dao_thickness_cols_ref(ts, z, ref, 0, w);
	dao_thickness_cols(ts, z, got, scratch, NULL, 0, w / 3);
	dao_thickness_cols(ts, z, got, scratch, NULL, w / 3, w);
	assert_memory_equal(ref, got, n * sizeof(float));
	for (size_t i = 0; i < n; i++)
		assert_true(ref[i] > 0.0f && ref[i] <= ts->max);
	free(scratch);
	free(got);
	free(ref);
}

static void test_small_images(void **state)
{
	(void)state;
	uint32_t r = 2026;
	for (int h = 1; h <= 13; h++)
		for (int w = 1; w <= 13; w++)
			for (int v = 0; v < 4; v++) {
				struct dao_camera cam;
				const double f = 0.8 * (w > 8 ? w : 8);
				assert_int_equal(dao_camera_from_intrinsics(&cam, (uint32_t)w, (uint32_t)h,
									   f, f, 0.5 * (w - 1),
									   0.5 * (h - 1), NULL),
						 0);
				const size_t n = (size_t)w * h;
				float *z = malloc(n * sizeof(float)), *zf = malloc(n * sizeof(float));
				float *want = malloc(n * sizeof(float));
				assert_non_null(z);
				assert_non_null(zf);
				assert_non_null(want);
				small_depth(z, w, h, &r);
				struct dao_thickness_setup ts;
				dao_thickness_setup_init(&ts, &cam, 0.5f);
				ts.spacing = 0.11f;
				/* the fill, in two bands, against its rule */
				dao_thickness_fill_rows(&ts, z, zf, 0, h / 2);
				dao_thickness_fill_rows(&ts, z, zf, h / 2, h);
				memcpy(want, z, n * sizeof(float));
				for (int y = 0; y < h; y++) {
					const float *zr = z + (size_t)y * w;
					float *o = want + (size_t)y * w;
					for (int a = 1; a < w; a++) {
						if (zr[a] > 0.0f || !(zr[a - 1] > 0.0f))
							continue;
						int b = a;
						while (b < w && !(zr[b] > 0.0f))
							b++;
						const float za = zr[a - 1];
						if (b < w && b - a <= ts.fill_px && zr[b] > 0.0f &&
						    fabsf(zr[b] - za) <=
							    DAO_THICKNESS_JUMP * (za < zr[b] ? za : zr[b])) {
							const float dz = (zr[b] - za) / (float)(b - a + 1);
							for (int k = a; k < b; k++)
								o[k] = za + dz * (float)(k - a + 1);
						}
						a = b;
					}
				}
				assert_memory_equal(zf, want, n * sizeof(float));
				ts.noise_k = 0.0026f;
				expect_small_same(&ts, zf);
				ts.fill_px = 0;
				expect_small_same(&ts, z);
				ts.noise_k = 0.0f;
				expect_small_same(&ts, z);
				/* pixels 50 times finer, holes of 1 - 3 px down the columns too: column
				 * runs under half a spacing beside a hole (hidden_face), noisy, not
				 * filled (their own random numbers: the cases above stay the same) */
				struct dao_camera fine;
				assert_int_equal(dao_camera_from_intrinsics(&fine, (uint32_t)w, (uint32_t)h,
									   50.0 * f, 50.0 * f,
									   0.5 * (w - 1),
									   0.5 * (h - 1), NULL),
						 0);
				dao_thickness_setup_init(&ts, &fine, 0.5f);
				ts.spacing = 0.11f;
				ts.noise_k = 0.0026f;
				ts.fill_px = 0;
				uint32_t rc = r ^ 0x9e3779b9u;
				for (int k = 0; k < w * h / 12 + 1; k++) {
					const int x = (int)(small_rand(&rc) % (unsigned)w);
					const int y = (int)(small_rand(&rc) % (unsigned)h);
					const int len = 1 + (int)(small_rand(&rc) % 3);
					for (int i = 0; i < len && y + i < h; i++)
						z[(size_t)(y + i) * w + x] = 0.0f;
				}
				expect_small_same(&ts, z);
				free(want);
				free(zf);
				free(z);
			}
}

/* Mean |ao - truth| over every pixel with depth. */
static double image_mae(const float *ao, const struct synth_image *img)
{
	double sum = 0;
	long n = 0;
	for (size_t k = 0; k < (size_t)img->width * img->height; k++)
		if (img->depth[k] > 0.0f) {
			sum += fabs(ao[k] - img->gt[k]);
			n++;
		}
	return sum / (double)n;
}

/*
 * The slabs through the pipeline, which gives the estimate VBAO's sample spacing
 * (its search radius over its steps): the floor around the 2 and 3 cm slabs is
 * lit where their samples leave gaps at 3 times their rays' length.
 */
static void test_vbao_slabs(void **state)
{
	(void)state;
	struct synth_scene s;
	struct dao_camera cam;
	struct synth_image img;
	vec3 up;
	slabs_scene(&s, &up);
	camera(&cam, W, H);
	assert_int_equal(synth_render(&s, &cam, 0.5, 8, 2, &img, NULL), 0);
	float *g = dao_test_ao_of_depth(&cam, img.depth, DAO_ALGORITHM_GTAO, 0, 0.2f);
	float *e = dao_test_ao_of_depth(&cam, img.depth, DAO_ALGORITHM_VBAO,
					DAO_VBAO_THICKNESS_IMAGE, 0.2f);
	assert_non_null(g);
	assert_non_null(e);
	const double mg = image_mae(g, &img), me = image_mae(e, &img);
	print_message("slabs, MAE: gtao %.4f, vbao with the estimate %.4f\n", mg, me);
	/* measured 0.0485 and 0.0204 (0.0228 without the spacing; the samples are
	 * deterministic, the kernel sets agree within the oracle's bounds) */
	assert_true(me < 0.0216);
	assert_true(me < 0.5 * mg);
	free(g);
	free(e);
	synth_image_free(&img);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_pole_widths),
		cmocka_unit_test(test_pole_chord_extra),
		cmocka_unit_test(test_run_ends),
		cmocka_unit_test(test_run_holes),
		cmocka_unit_test(test_hidden_face),
		cmocka_unit_test(test_slabs),
		cmocka_unit_test(test_slabs_spacing),
		cmocka_unit_test(test_slabs_spacing_face_on),
		cmocka_unit_test(test_boards_upright),
		cmocka_unit_test(test_boards_gaussian),
		cmocka_unit_test(test_same_as_reference),
		cmocka_unit_test(test_same_as_reference_real),
		cmocka_unit_test(test_vbao_behind_poles),
		cmocka_unit_test(test_boxes_noisy),
		cmocka_unit_test(test_slabs_noisy),
		cmocka_unit_test(test_slabs_edge_holes),
		cmocka_unit_test(test_vbao_slabs),
		cmocka_unit_test(test_chair_dropouts),
		cmocka_unit_test(test_small_images),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
