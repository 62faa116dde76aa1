/* SPDX-License-Identifier: MIT */
/*
 * dao_context_process_shaded, the shading fused into the pipeline's last
 * pass over the rows, against dao_context_process then dao_context_shade:
 * the same AO and the same shaded image, byte for byte, for every denoise,
 * the temporal AO, the shading modes and output formats, the optimised and
 * the reference kernels, and 1 to 4 threads (bands of 30, 15, 10 and 7
 * rows, chunks of 16 inside them: a row shaded from another row's AO, or
 * before its AO is final, shows at their boundaries).  Every thread count
 * gives the 1-thread bytes too.  Then the fused call's errors.
 */
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/cmocka_all.h"
#include "common/test_common.h"

enum { W = 160, H = 120, FRAMES = 3 };

/* A tilted floor, a box, a bump and holes, with a deterministic ripple and
 * noise in millimetres: every denoise and shading path has work. */
static void fill_depth(uint16_t *mm, int frame)
{
	uint32_t s = 12345u + (uint32_t)frame * 7919u;
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			double z = 1500.0 + 6.0 * y + 2.0 * x;
			if (x > 50 && x < 95 && y > 30 && y < 75)
				z -= 350.0;
			const double dx = x - 120.0, dy = y - 80.0;
			if (dx * dx + dy * dy < 400.0)
				z -= 0.5 * (400.0 - dx * dx - dy * dy);
			s = s * 1664525u + 1013904223u;
			z += (double)(s >> 28) - 7.5 + 3.0 * ((x + frame) % 5 == 0);
			mm[y * W + x] = (uint16_t)z;
		}
	for (int y = 10; y < 14; y++)
		for (int x = 20; x < 26; x++)
			mm[y * W + x] = 0;
	for (int y = 0; y < H; y += 9)
		mm[y * W + (y * 7) % W] = 0;
	for (int y = 0; y < H; y++)
		mm[y * W] = 0; /* a dropout column at the border */
}

struct outputs {
	uint8_t ao[W * H * 4];
	uint8_t shaded[W * H * 3];
};

struct config {
	int denoise, temporal, shade, simd;
	enum dao_pixfmt ao_fmt, shaded_fmt;
};

static int bpp(enum dao_pixfmt f)
{
	return f == DAO_PIXFMT_GRAY_F32 ? 4 : f == DAO_PIXFMT_GRAY16 ? 2 : f == DAO_PIXFMT_RGB24 ? 3 : 1;
}

/* FRAMES frames of a stream; `fused`: one call per frame, else process + shade.
 * The last frame's outputs. */
static void run(const struct config *c, int threads, int fused, struct outputs *o)
{
	struct dao_camera cam;
	assert_int_equal(dao_camera_from_intrinsics(&cam, W, H, 150, 150, 79.5, 59.5, NULL), 0);
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.threads = threads;
	p.denoise = c->denoise;
	p.temporal = c->temporal ? 0.6f : 0.0f;
	p.shade = c->shade;
	p.simd = c->simd;
	struct dao_context *ctx;
	struct dao_error err;
	assert_int_equal(dao_context_create(&ctx, &cam, &p, &err), 0);
	static uint16_t mm[W * H];
	memset(o, 0, sizeof *o);
	struct dao_frame in = { .format = DAO_PIXFMT_DEPTH16, .width = W, .height = H,
				.stride = 2 * W, .data = mm, .depth_unit = 0.001f };
	struct dao_frame ao = { .format = c->ao_fmt, .width = W, .height = H,
				.stride = bpp(c->ao_fmt) * W, .data = o->ao };
	struct dao_frame sh = { .format = c->shaded_fmt, .width = W, .height = H,
				.stride = bpp(c->shaded_fmt) * W, .data = o->shaded };
	for (int f = 0; f < FRAMES; f++) {
		fill_depth(mm, f);
		int r = fused ? dao_context_process_shaded(ctx, &in, NULL, (uint64_t)f, &ao, &sh, &err)
			      : dao_context_process(ctx, &in, NULL, (uint64_t)f, &ao, &err);
		if (!r && !fused)
			r = dao_context_shade(ctx, &sh, &err);
		if (r)
			fail_msg("frame %d: %d %s", f, r, err.message);
	}
	struct dao_timings tm = DAO_TIMINGS_INIT;
	dao_context_timings(ctx, &tm);
	assert_true(tm.shade_ms >= 0.0 && tm.denoise_ms >= 0.0 && tm.output_ms >= 0.0);
	dao_context_destroy(ctx);
}

/* the first differing byte, with its row, or nothing */
static void expect_same(const uint8_t *a, const uint8_t *b, size_t n, int row_bytes,
			const char *what, const struct config *c, int threads, const char *vs)
{
	for (size_t i = 0; i < n; i++)
		if (a[i] != b[i])
			fail_msg("%s differs at row %d byte %d (%s; denoise %d temporal %d shade %d "
				 "simd %d, %d threads)",
				 what, (int)(i / (size_t)row_bytes), (int)(i % (size_t)row_bytes), vs,
				 c->denoise, c->temporal, c->shade, c->simd, threads);
}

static void check_config(const struct config *c)
{
	static struct outputs one, sep, fus;
	const size_t ao_n = (size_t)bpp(c->ao_fmt) * W * H;
	const size_t sh_n = (size_t)bpp(c->shaded_fmt) * W * H;
	run(c, 1, 0, &one);
	/* the shaded image is not blank: the comparison has something to compare */
	int lit = 0;
	for (size_t i = 0; i < sh_n; i++)
		lit += one.shaded[i] > 0;
	assert_true(lit > (int)sh_n / 2);
	for (int t = 1; t <= 4; t++) {
		run(c, t, 0, &sep);
		run(c, t, 1, &fus);
		expect_same(sep.ao, fus.ao, ao_n, bpp(c->ao_fmt) * W, "AO", c, t, "fused vs not");
		expect_same(sep.shaded, fus.shaded, sh_n, bpp(c->shaded_fmt) * W, "shaded", c, t,
			    "fused vs not");
		expect_same(one.ao, fus.ao, ao_n, bpp(c->ao_fmt) * W, "AO", c, t, "vs 1 thread");
		expect_same(one.shaded, fus.shaded, sh_n, bpp(c->shaded_fmt) * W, "shaded", c, t,
			    "vs 1 thread");
	}
}

static void test_fused_equals_separate(void **state)
{
	(void)state;
	const struct config configs[] = {
		/* the defaults: plane denoise, Lambert into RGB24 (the SIMD shading) */
		{ DAO_DENOISE_PLANE, 0, DAO_SHADE_LAMBERT, DAO_SIMD_AUTO, DAO_PIXFMT_GRAY16,
		  DAO_PIXFMT_RGB24 },
		{ DAO_DENOISE_PLANE, 1, DAO_SHADE_LAMBERT, DAO_SIMD_AUTO, DAO_PIXFMT_GRAY_F32,
		  DAO_PIXFMT_GRAY8 },
		{ DAO_DENOISE_BILATERAL, 1, DAO_SHADE_TURBO, DAO_SIMD_AUTO, DAO_PIXFMT_GRAY8,
		  DAO_PIXFMT_RGB24 },
		{ DAO_DENOISE_NONE, 0, DAO_SHADE_GRAY, DAO_SIMD_AUTO, DAO_PIXFMT_GRAY16,
		  DAO_PIXFMT_RGB24 },
		{ DAO_DENOISE_PLANE, 0, DAO_SHADE_LAMBERT, DAO_SIMD_REFERENCE, DAO_PIXFMT_GRAY16,
		  DAO_PIXFMT_RGB24 },
	};
	for (size_t i = 0; i < sizeof configs / sizeof configs[0]; i++)
		check_config(&configs[i]);
}

static void test_fused_errors(void **state)
{
	(void)state;
	struct dao_camera cam;
	assert_int_equal(dao_camera_from_intrinsics(&cam, W, H, 150, 150, 79.5, 59.5, NULL), 0);
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.threads = 2;
	p.invalid_value = 0.25f;
	struct dao_context *ctx;
	struct dao_error err;
	assert_int_equal(dao_context_create(&ctx, &cam, &p, &err), 0);
	static uint16_t mm[W * H];
	static uint8_t rgb[W * H * 3], rgb2[W * H * 3];
	static uint16_t ao[W * H];
	fill_depth(mm, 0);
	struct dao_frame in = { .format = DAO_PIXFMT_DEPTH16, .width = W, .height = H,
				.stride = 2 * W, .data = mm, .depth_unit = 0.001f };
	struct dao_frame a = { .format = DAO_PIXFMT_GRAY16, .width = W, .height = H,
			       .stride = 2 * W, .data = ao };
	struct dao_frame sh = { .format = DAO_PIXFMT_GRAY16, .width = W, .height = H,
				.stride = 3 * W, .data = rgb };
	/* a wrong shaded frame: refused before the frame is processed */
	int r = dao_context_process_shaded(ctx, &in, NULL, 0, &a, &sh, &err);
	assert_int_equal(r, -EINVAL);
	assert_non_null(strstr(err.message, "rgb24 or gray8"));
	sh.format = DAO_PIXFMT_RGB24;
	assert_int_equal(dao_context_shade(ctx, &sh, &err), -EAGAIN);
	sh.width = W - 1;
	assert_int_equal(dao_context_process_shaded(ctx, &in, NULL, 0, &a, &sh, &err), -EINVAL);
	assert_non_null(strstr(err.message, "shaded output"));
	assert_int_equal(dao_context_shade(ctx, &sh, &err), -EINVAL);
	sh.width = W;
	assert_int_equal(dao_context_process_shaded(NULL, &in, NULL, 0, &a, &sh, &err), -EINVAL);
	/* no shaded frame: dao_context_process; then shading it gives the fused bytes */
	assert_int_equal(dao_context_process_shaded(ctx, &in, NULL, 0, &a, NULL, &err), 0);
	assert_int_equal(dao_context_shade(ctx, &sh, &err), 0);
	struct dao_frame sh2 = sh;
	sh2.data = rgb2;
	assert_int_equal(dao_context_process_shaded(ctx, &in, NULL, 0, NULL, &sh2, &err), 0);
	assert_memory_equal(rgb, rgb2, sizeof rgb);
	/* algorithm=none: the frame is processed (AO 1 where there is depth, as
	 * dao_context_process), nothing is shaded, -ENODATA as dao_context_shade */
	p.algorithm = DAO_ALGORITHM_NONE;
	assert_int_equal(dao_context_set_params(ctx, &p, &err), 0);
	memset(rgb2, 7, sizeof rgb2);
	r = dao_context_process_shaded(ctx, &in, NULL, 1, &a, &sh2, &err);
	assert_int_equal(r, -ENODATA);
	assert_non_null(strstr(err.message, "algorithm=none"));
	assert_int_equal(ao[5 * W + 5], 65535);
	assert_int_equal(ao[0], 16384); /* no depth: invalid_value 0.25 */
	assert_int_equal(rgb2[100], 7);
	assert_int_equal(dao_context_shade(ctx, &sh2, &err), -ENODATA);
	dao_context_destroy(ctx);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_fused_equals_separate),
		cmocka_unit_test(test_fused_errors),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
