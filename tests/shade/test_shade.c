/* SPDX-License-Identifier: MIT */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/cmocka_all.h"
#include "common/test_common.h"
#include "shade/colormap.h"
#include "shade/shade.h"

enum { W = 16, H = 8 };

struct fixture {
	struct dao_colormap map;
	struct dao_shade_setup s;
	float z[W * H], n[3 * W * H], ao[W * H];
	uint8_t rgb[3 * W * H], gray[W * H];
	struct dao_frame out_rgb, out_gray;
};

static struct fixture *make(int mode)
{
	struct fixture *f = calloc(1, sizeof *f);
	struct dao_camera cam;
	dao_camera_from_intrinsics(&cam, W, H, 100, 100, 7.5, 3.5, NULL);
	dao_colormap_fill(&f->map, mode);
	f->s = (struct dao_shade_setup){ .width = W, .height = H, .ax = cam.ax, .ay = cam.ay,
					 .bx = cam.bx, .by = cam.by, .mode = mode, .near_m = 1.0f,
					 .far_m = 3.0f, .power = 1.0f, .occ = { 10, 20, 30 },
					 .map = &f->map };
	for (int i = 0; i < W * H; i++) {
		f->z[i] = 2.0f;
		f->n[3 * i + 2] = -1.0f;
		f->ao[i] = 1.0f;
	}
	f->out_rgb = (struct dao_frame){ .format = DAO_PIXFMT_RGB24, .width = W, .height = H,
			.stride = 3 * W, .data = f->rgb};
	f->out_gray = (struct dao_frame){ .format = DAO_PIXFMT_GRAY8, .width = W, .height = H,
			.stride = W, .data = f->gray};
	return f;
}

static void test_lambert(void **state)
{
	(void)state;
	struct fixture *f = make(DAO_SHADE_LAMBERT);
	/* pixel 0: open, facing the light; 1: fully occluded; 2: tilted 60 deg; 3: no depth */
	f->ao[1] = 0.0f;
	f->n[3 * 2 + 0] = 0.866f, f->n[3 * 2 + 2] = -0.5f;
	f->z[3] = 0.0f;
	dao_shade(&f->s, f->z, f->n, f->ao, &f->out_rgb, 0, H);
	dao_shade(&f->s, f->z, f->n, f->ao, &f->out_gray, 0, H);
	/* the centre column faces the head light almost exactly */
	int centre = 4 * W + 8;
	assert_true(f->rgb[3 * centre] >= 250);
	/* fully occluded = the occlusion colour exactly */
	assert_int_equal(f->rgb[3], 10);
	assert_int_equal(f->rgb[4], 20);
	assert_int_equal(f->rgb[5], 30);
	/* tilted: darker than facing */
	assert_true(f->rgb[6] < f->rgb[0]);
	/* no depth: black */
	assert_int_equal(f->rgb[9] + f->rgb[10] + f->rgb[11], 0);
	/* gray output is the luma of the RGB one */
	for (int i = 0; i < W * H; i++) {
		float luma = 0.299f * f->rgb[3 * i] + 0.587f * f->rgb[3 * i + 1] + 0.114f * f->rgb[3 * i + 2];
		assert_true(fabsf(f->gray[i] - luma) <= 1.0f);
	}
	free(f);
}

static void test_colormaps(void **state)
{
	(void)state;
	static const int modes[] = { DAO_SHADE_TURBO, DAO_SHADE_JET, DAO_SHADE_GRAY };
	for (int m = 0; m < 3; m++) {
		struct fixture *f = make(modes[m]);
		f->z[0] = 1.0f;  /* near */
		f->z[1] = 3.0f;  /* far */
		f->z[2] = 9.0f;  /* beyond: clamped to far */
		f->ao[3] = 0.5f; /* half AO: halfway to the occlusion colour */
		dao_shade(&f->s, f->z, f->n, f->ao, &f->out_rgb, 0, H);
		for (int c = 0; c < 3; c++) {
			assert_int_equal(f->rgb[c], f->map.rgb[0][c]);
			assert_int_equal(f->rgb[3 + c], f->map.rgb[255][c]);
			assert_int_equal(f->rgb[6 + c], f->map.rgb[255][c]);
			const uint8_t *mid = f->map.rgb[128];
			float want = 0.5f * f->s.occ[c] + 0.5f * mid[c];
			assert_true(fabsf(f->rgb[9 + c] - want) <= 1.0f);
		}
		free(f);
	}
	/* gray ramps from black to white; jet from blue to red; turbo from dark to dark red */
	struct dao_colormap g, j, t;
	dao_colormap_fill(&g, DAO_SHADE_GRAY);
	dao_colormap_fill(&j, DAO_SHADE_JET);
	dao_colormap_fill(&t, DAO_SHADE_TURBO);
	assert_true(g.rgb[0][0] == 0 && g.rgb[255][0] == 255 && g.rgb[100][1] == 100);
	assert_true(j.rgb[0][2] > 100 && j.rgb[0][0] == 0 && j.rgb[255][0] > 100 && j.rgb[255][2] == 0);
	/* Turbo: entries of the published 256-entry sRGB table (Mikhailov 2019) */
	static const struct { int i; uint8_t rgb[3]; } published[] = {
		{ 0, { 48, 18, 59 } },     { 20, { 66, 75, 181 } },   { 52, { 61, 158, 254 } },
		{ 81, { 24, 222, 192 } },  { 100, { 63, 246, 138 } }, { 128, { 164, 252, 60 } },
		{ 150, { 219, 226, 54 } }, { 181, { 254, 158, 47 } }, { 203, { 241, 93, 19 } },
		{ 230, { 195, 37, 3 } },   { 250, { 139, 9, 2 } },   { 255, { 122, 4, 3 } },
	};
	for (size_t k = 0; k < sizeof published / sizeof published[0]; k++)
		for (int c = 0; c < 3; c++)
			if (abs(t.rgb[published[k].i][c] - published[k].rgb[c]) > 3)
				fail_msg("turbo entry %d channel %d: %d, published %d", published[k].i, c,
					 t.rgb[published[k].i][c], published[k].rgb[c]);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_lambert),
		cmocka_unit_test(test_colormaps),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
