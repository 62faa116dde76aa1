/* SPDX-License-Identifier: MIT */
/* The public context API: every error path, bounds, outputs, determinism. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/cmocka_all.h"
#include "common/test_common.h"

enum { W = 64, H = 48, PAD = 16 };

static struct dao_camera camera(void)
{
	struct dao_camera cam;
	dao_camera_from_intrinsics(&cam, W, H, 60, 60, 31.5, 23.5, NULL);
	return cam;
}

/* A box on a floor-like plane, in millimetres, with a hole. */
static void fill_depth(uint16_t *mm)
{
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			int box = x > 24 && x < 40 && y > 14 && y < 30;
			mm[y * W + x] = (uint16_t)(box ? 1600 : 2000);
		}
	mm[3 * W + 5] = 0;
}

static struct dao_frame depth_frame(uint16_t *mm)
{
	return (struct dao_frame){ .format = DAO_PIXFMT_DEPTH16, .width = W, .height = H,
				   .stride = 2 * W, .data = mm, .depth_unit = 0.001f };
}

static void expect_err(int r, int code, const struct dao_error *err, const char *needle)
{
	assert_int_equal(r, code);
	if (!strstr(err->message, needle))
		fail_msg("message '%s' lacks '%s'", err->message, needle);
}

static void test_create_errors(void **state)
{
	(void)state;
	struct dao_context *ctx = (struct dao_context *)1;
	struct dao_camera cam = camera();
	struct dao_error err;
	expect_err(dao_context_create(NULL, &cam, NULL, &err), -EINVAL, &err, "NULL");
	expect_err(dao_context_create(&ctx, NULL, NULL, &err), -EINVAL, &err, "camera");
	assert_null(ctx);
	struct dao_camera bad = cam;
	bad.fx = -1;
	expect_err(dao_context_create(&ctx, &bad, NULL, &err), -EINVAL, &err, "focal");
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.radius = NAN;
	expect_err(dao_context_create(&ctx, &cam, &p, &err), -EINVAL, &err, "radius");
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.slices = 0;
	expect_err(dao_context_create(&ctx, &cam, &p, &err), -EINVAL, &err, "slices");
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.radius = -1.0f;
	expect_err(dao_context_create(&ctx, &cam, &p, &err), -EINVAL, &err, "radius");
	assert_null(ctx);
	dao_context_destroy(NULL);
}

static void test_process_errors(void **state)
{
	(void)state;
	struct dao_camera cam = camera();
	struct dao_context *ctx;
	struct dao_error err;
	assert_int_equal(dao_context_create(&ctx, &cam, NULL, &err), 0);
	uint16_t mm[W * H];
	fill_depth(mm);
	float aof[W * H];
	struct dao_frame ao = { .format = DAO_PIXFMT_GRAY_F32, .width = W, .height = H,
			.stride = 4 * W, .data = aof};
	struct dao_frame d = depth_frame(mm);

	expect_err(dao_context_shade(ctx, &(struct dao_frame){ .format = DAO_PIXFMT_RGB24,
			.width = W, .height = H, .stride = 3 * W, .data = aof}, &err),
		   -EAGAIN, &err, "process");
	expect_err(dao_context_process(NULL, &d, NULL, 0, &ao, &err), -EINVAL, &err, "context");
	expect_err(dao_context_process(ctx, NULL, NULL, 0, &ao, &err), -EINVAL, &err, "depth input");
	struct dao_frame b = d;
	b.format = DAO_PIXFMT_GRAY16;
	expect_err(dao_context_process(ctx, &b, NULL, 0, &ao, &err), -EINVAL, &err, "depth16");
	b = d;
	b.width = W - 1;
	expect_err(dao_context_process(ctx, &b, NULL, 0, &ao, &err), -EINVAL, &err, "does not match");
	b = d;
	b.stride = W;
	expect_err(dao_context_process(ctx, &b, NULL, 0, &ao, &err), -EINVAL, &err, "stride");
	b = d;
	b.stride = 2 * W + 1;
	expect_err(dao_context_process(ctx, &b, NULL, 0, &ao, &err), -EINVAL, &err, "stride");
	float units[] = { 0.0f, NAN, -0.001f, 2.0f };
	for (int k = 0; k < 4; k++) {
		b = d;
		b.depth_unit = units[k];
		expect_err(dao_context_process(ctx, &b, NULL, 0, &ao, &err), -EINVAL, &err, "depth_unit");
	}
	b = d;
	b.data = NULL;
	expect_err(dao_context_process(ctx, &b, NULL, 0, &ao, &err), -EINVAL, &err, "NULL");
	struct dao_frame bad_ao = ao;
	bad_ao.format = DAO_PIXFMT_RGB24;
	expect_err(dao_context_process(ctx, &d, NULL, 0, &bad_ao, &err), -EINVAL, &err, "AO output");
	bad_ao = ao;
	bad_ao.height = H + 1;
	expect_err(dao_context_process(ctx, &d, NULL, 0, &bad_ao, &err), -EINVAL, &err, "AO output");
	/* caller normals: wrong format, and a non-finite normal where there is depth */
	float nrm[3 * W * H];
	for (int i = 0; i < W * H; i++)
		nrm[3 * i] = 0, nrm[3 * i + 1] = 0, nrm[3 * i + 2] = -1;
	struct dao_frame nf = { .format = DAO_PIXFMT_NORMAL_F32, .width = W, .height = H,
			.stride = 12 * W, .data = nrm};
	struct dao_frame wrong = nf;
	wrong.format = DAO_PIXFMT_GRAY_F32;
	wrong.stride = 4 * W;
	expect_err(dao_context_process(ctx, &d, &wrong, 0, &ao, &err), -EINVAL, &err, "normal-f32");
	nrm[3 * (10 * W + 10)] = NAN;
	expect_err(dao_context_process(ctx, &d, &nf, 0, &ao, &err), -EINVAL, &err, "(10, 10)");
	/* a NaN normal where there is no depth is fine */
	nrm[3 * (10 * W + 10)] = 0;
	nrm[3 * (3 * W + 5)] = NAN;
	assert_int_equal(dao_context_process(ctx, &d, &nf, 0, &ao, &err), 0);
	/* shade output errors */
	expect_err(dao_context_shade(ctx, &ao, &err), -EINVAL, &err, "rgb24");
	expect_err(dao_context_shade(NULL, &ao, &err), -EINVAL, &err, "context");
	float normals_out[3 * W * H];
	struct dao_frame no = { .format = DAO_PIXFMT_GRAY_F32, .width = W, .height = H,
			.stride = 4 * W, .data = normals_out};
	expect_err(dao_context_get_normals(ctx, &no, &err), -EINVAL, &err, "normal-f32");
	/* set_params rejects and keeps the old ones */
	struct dao_params p, before;
	dao_context_get_params(ctx, &before);
	p = before;
	p.steps = 0;
	expect_err(dao_context_set_params(ctx, &p, &err), -EINVAL, &err, "steps");
	dao_context_get_params(ctx, &p);
	assert_memory_equal(&p, &before, sizeof p);
	assert_ptr_not_equal(dao_context_camera(ctx), NULL);
	assert_int_equal(dao_context_camera(ctx)->width, W);
	dao_context_destroy(ctx);
}

/* Caller buffers with padded strides and guard bytes: nothing outside is touched. */
static void test_bounds_and_formats(void **state)
{
	(void)state;
	struct dao_camera cam = camera();
	struct dao_context *ctx;
	assert_int_equal(dao_context_create(&ctx, &cam, NULL, NULL), 0);
	uint16_t mm[W * H];
	fill_depth(mm);
	/* depth at an odd stride inside a larger buffer */
	const int dstride = 2 * W + 6;
	unsigned char *dbuf = malloc((size_t)dstride * H + 2 * PAD);
	memset(dbuf, 0x5a, (size_t)dstride * H + 2 * PAD);
	for (int y = 0; y < H; y++)
		memcpy(dbuf + PAD + (size_t)y * dstride, mm + y * W, 2 * W);
	struct dao_frame d = { .format = DAO_PIXFMT_DEPTH16, .width = W, .height = H,
			.stride = dstride, .data = dbuf + PAD, .depth_unit = 0.001f};

	static const enum dao_pixfmt fmts[] = { DAO_PIXFMT_GRAY_F32, DAO_PIXFMT_GRAY16, DAO_PIXFMT_GRAY8 };
	float ref[W * H];
	for (int k = 0; k < 3; k++) {
		size_t bpp = dao_pixfmt_bytes_per_pixel(fmts[k]);
		int stride = (int)(W * bpp + 8);
		size_t size = (size_t)stride * H + 2 * PAD;
		unsigned char *buf = malloc(size);
		memset(buf, 0xa5, size);
		struct dao_frame ao = { .format = fmts[k], .width = W, .height = H,
				.stride = stride, .data = buf + PAD};
		assert_int_equal(dao_context_process(ctx, &d, NULL, 0, &ao, NULL), 0);
		for (int i = 0; i < PAD; i++)
			assert_true(buf[i] == 0xa5 && buf[size - 1 - i] == 0xa5);
		for (int y = 0; y < H; y++)
			for (size_t i = W * bpp; i < (size_t)stride; i++)
				assert_int_equal(buf[PAD + (size_t)y * stride + i], 0xa5);
		for (int y = 0; y < H; y++)
			for (int x = 0; x < W; x++) {
				const unsigned char *px = buf + PAD + (size_t)y * stride + x * bpp;
				if (k == 0) {
					memcpy(&ref[y * W + x], px, 4);
					assert_true(ref[y * W + x] >= 0.0f && ref[y * W + x] <= 1.0f);
				} else if (k == 1) {
					uint16_t q;
					memcpy(&q, px, 2);
					assert_int_equal(q, lrintf(ref[y * W + x] * 65535.0f));
				} else {
					assert_int_equal(*px, lrintf(ref[y * W + x] * 255.0f));
				}
			}
		free(buf);
	}
	/* the no-data pixel is exactly 1; the box casts occlusion on the plane */
	assert_true(ref[3 * W + 5] == 1.0f);
	float lo = 1.0f;
	for (int i = 0; i < W * H; i++)
		lo = fminf(lo, ref[i]);
	assert_true(lo < 0.9f);
	/* the input was not written */
	for (int i = 0; i < PAD; i++)
		assert_int_equal(dbuf[i], 0x5a);
	/* shaded output with padding */
	int rs = 3 * W + 5;
	unsigned char *rgb = malloc((size_t)rs * H + PAD);
	memset(rgb, 0x33, (size_t)rs * H + PAD);
	struct dao_frame out = { .format = DAO_PIXFMT_RGB24, .width = W, .height = H, .stride = rs,
			.data = rgb};
	assert_int_equal(dao_context_shade(ctx, &out, NULL), 0);
	for (int y = 0; y < H; y++)
		for (int i = 3 * W; i < rs; i++)
			assert_int_equal(rgb[(size_t)y * rs + i], 0x33);
	for (int i = 0; i < PAD; i++)
		assert_int_equal(rgb[(size_t)rs * H + i], 0x33);
	free(rgb);
	free(dbuf);
	dao_context_destroy(ctx);
}

static void process_f32(struct dao_context *ctx, uint16_t *mm, uint64_t index, float *out)
{
	struct dao_frame d = depth_frame(mm);
	struct dao_frame ao = { .format = DAO_PIXFMT_GRAY_F32, .width = W, .height = H,
			.stride = 4 * W, .data = out};
	struct dao_error err;
	if (dao_context_process(ctx, &d, NULL, index, &ao, &err))
		fail_msg("%s", err.message);
}

static void test_determinism_and_params(void **state)
{
	(void)state;
	struct dao_camera cam = camera();
	struct dao_context *ctx, *ctx1;
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	/* 4 threads, whatever the CPU count (threads = 0, one per CPU, is 1 on a
	 * single-CPU runner, and the comparison would then be of 1 with 1) */
	p.threads = 4;
	assert_int_equal(dao_context_create(&ctx, &cam, &p, NULL), 0);
	p.threads = 1;
	assert_int_equal(dao_context_create(&ctx1, &cam, &p, NULL), 0);
	uint16_t mm[W * H];
	fill_depth(mm);
	float a[W * H], b[W * H], c[W * H];
	process_f32(ctx, mm, 5, a);
	process_f32(ctx, mm, 5, b);
	assert_memory_equal(a, b, sizeof a);
	/* thread count does not change the result */
	process_f32(ctx1, mm, 5, c);
	assert_memory_equal(a, c, sizeof a);
	/* another frame index: another noise pattern, about the same mean */
	process_f32(ctx, mm, 6, b);
	double ma = 0, mb = 0;
	int differ = 0;
	for (int i = 0; i < W * H; i++) {
		ma += a[i], mb += b[i];
		differ += a[i] != b[i];
	}
	assert_true(differ > 0);
	assert_true(fabs(ma - mb) / (W * H) < 0.01);
	/* invalid_value */
	dao_context_get_params(ctx, &p);
	p.invalid_value = 0.5f;
	assert_int_equal(dao_context_set_params(ctx, &p, NULL), 0);
	process_f32(ctx, mm, 5, b);
	assert_true(b[3 * W + 5] == 0.5f);
	/* a flat wall facing the camera is open everywhere */
	for (int i = 0; i < W * H; i++)
		mm[i] = 2000;
	process_f32(ctx, mm, 0, a);
	for (int i = 0; i < W * H; i++)
		assert_true(a[i] >= 0.99f);
	dao_context_destroy(ctx);
	dao_context_destroy(ctx1);
}

/*
 * Parameters changed on a running context give what a fresh context with the
 * scalar reference kernels gives: a larger max-screen-radius (the 1/z phase
 * plane is re-made with wider padding), a radius whose samples reach far
 * beyond the image, another noise (another GTAO kernel) and back.
 */
static void test_params_change_kernels(void **state)
{
	(void)state;
	struct dao_camera cam = camera();
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	struct dao_context *ctx;
	assert_int_equal(dao_context_create(&ctx, &cam, &p, NULL), 0);
	uint16_t mm[W * H];
	fill_depth(mm);
	float a[W * H], b[W * H], first[W * H];
	static const struct {
		float radius, max_r;
		int noise;
	} cases[] = {
		{ 0.5f, 160.0f, DAO_NOISE_TILE },
		{ 6.0f, 4096.0f, DAO_NOISE_TILE }, /* ~180 px: beyond the 64 x 48 image */
		{ 6.0f, 4096.0f, DAO_NOISE_IGN },
		{ 0.5f, 20.0f, DAO_NOISE_TILE },
	};
	for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
		p.radius = cases[k].radius;
		p.max_screen_radius = cases[k].max_r;
		p.noise = cases[k].noise;
		assert_int_equal(dao_context_set_params(ctx, &p, NULL), 0);
		process_f32(ctx, mm, 2, a);
		struct dao_params pr = p;
		pr.simd = DAO_SIMD_REFERENCE;
		struct dao_context *ref;
		assert_int_equal(dao_context_create(&ref, &cam, &pr, NULL), 0);
		process_f32(ref, mm, 2, b);
		dao_context_destroy(ref);
		double mae = 0, occ = 0;
		for (int i = 0; i < W * H; i++) {
			mae += fabs(a[i] - b[i]);
			occ += 1.0 - b[i];
		}
		mae /= W * H;
		print_message("radius %.1f max %4.0f noise %d: MAE %.2e against the reference, "
			      "mean occlusion %.3f\n", (double)cases[k].radius, (double)cases[k].max_r,
			      cases[k].noise, mae, occ / (W * H));
		assert_true(mae < 1e-4);
		assert_true(occ / (W * H) > 0.005); /* the box occludes the floor */
		if (k == 0)
			memcpy(first, a, sizeof a);
		if (k == 1)
			assert_memory_not_equal(first, a, sizeof a); /* the new radius took effect */
	}
	dao_context_destroy(ctx);
}

/*
 * Tiny and odd sizes (fewer columns than a tile or a vector, a last block cut
 * short): the optimised kernels agree with the reference, every preset.
 */
static void test_small_sizes(void **state)
{
	(void)state;
	static const int sizes[][2] = { { 1, 1 }, { 3, 2 }, { 5, 7 }, { 17, 3 }, { 70, 5 },
					{ 130, 9 } };
	for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
		const int w = sizes[k][0], h = sizes[k][1];
		struct dao_camera cam;
		assert_int_equal(dao_camera_from_intrinsics(&cam, (uint32_t)w, (uint32_t)h, 40, 40,
							     0.5 * (w - 1), 0.5 * (h - 1), NULL), 0);
		uint16_t mm[130 * 9];
		for (int i = 0; i < w * h; i++) /* a slope with a step and a hole */
			mm[i] = (uint16_t)(i % 11 == 7 ? 0 : 1500 + 20 * (i % w) + (i % w > w / 2) * 300);
		struct dao_frame d = { .format = DAO_PIXFMT_DEPTH16, .width = (uint32_t)w,
				.height = (uint32_t)h, .stride = 2 * w, .data = mm,
				       .depth_unit = 0.001f};
		for (int q = 0; q < DAO_QUALITY_COUNT; q++) {
			float a[130 * 9], b[130 * 9];
			for (int ref = 0; ref < 2; ref++) {
				struct dao_params p;
				dao_params_init(&p, (enum dao_quality)q);
				p.simd = ref ? DAO_SIMD_REFERENCE : DAO_SIMD_AUTO;
				struct dao_context *ctx;
				assert_int_equal(dao_context_create(&ctx, &cam, &p, NULL), 0);
				struct dao_frame ao = { .format = DAO_PIXFMT_GRAY_F32,
						.width = (uint32_t)w, .height = (uint32_t)h,
							.stride = 4 * w, .data = ref ? b : a};
				assert_int_equal(dao_context_process(ctx, &d, NULL, 1, &ao, NULL), 0);
				dao_context_destroy(ctx);
			}
			double mae = 0;
			for (int i = 0; i < w * h; i++) {
				assert_true(a[i] >= 0.0f && a[i] <= 1.0f);
				mae += fabs(a[i] - b[i]);
			}
			mae /= w * h;
			if (mae > 1e-4)
				fail_msg("%dx%d preset %d: MAE %.2e against the reference", w, h, q, mae);
		}
	}
}

/* Float depth and caller normals give the same kind of answer as mm depth. */
static void test_float_depth_and_normals(void **state)
{
	(void)state;
	struct dao_camera cam = camera();
	struct dao_context *ctx;
	assert_int_equal(dao_context_create(&ctx, &cam, NULL, NULL), 0);
	float z[W * H], nrm[3 * W * H], a[W * H], b[W * H];
	uint16_t mm[W * H];
	fill_depth(mm);
	for (int i = 0; i < W * H; i++) {
		z[i] = mm[i] ? mm[i] * 0.001f : NAN; /* NaN = no data */
		nrm[3 * i] = 0, nrm[3 * i + 1] = 0, nrm[3 * i + 2] = -2.0f; /* normalised by the library */
	}
	struct dao_frame df = { .format = DAO_PIXFMT_DEPTH_F32, .width = W, .height = H,
			.stride = 4 * W, .data = z};
	struct dao_frame nf = { .format = DAO_PIXFMT_NORMAL_F32, .width = W, .height = H,
			.stride = 12 * W, .data = nrm};
	struct dao_frame ao = { .format = DAO_PIXFMT_GRAY_F32, .width = W, .height = H,
			.stride = 4 * W, .data = a};
	assert_int_equal(dao_context_process(ctx, &df, NULL, 0, &ao, NULL), 0);
	process_f32(ctx, mm, 0, b);
	assert_memory_equal(a, b, sizeof a);
	assert_int_equal(dao_context_process(ctx, &df, &nf, 0, &ao, NULL), 0);
	assert_true(a[3 * W + 5] == 1.0f);
	float got[3 * W * H];
	struct dao_frame no = { .format = DAO_PIXFMT_NORMAL_F32, .width = W, .height = H,
			.stride = 12 * W, .data = got};
	assert_int_equal(dao_context_get_normals(ctx, &no, NULL), 0);
	assert_true(fabsf(got[3 * 100 + 2] + 1.0f) < 1e-6f);
	float zo[W * H];
	struct dao_frame zf = { .format = DAO_PIXFMT_DEPTH_F32, .width = W, .height = H,
			.stride = 4 * W, .data = zo};
	assert_int_equal(dao_context_get_depth(ctx, &zf, NULL), 0);
	assert_true(fabsf(zo[0] - 2.0f) < 1e-3f && zo[3 * W + 5] == 0.0f);
	dao_context_destroy(ctx);
}

/* The GRAY16 value of an AO image pixel of visibility v, one pixel at a time: v clamped
 * to [0, 1] (NaN 0), x 65535, the nearest count (ties to even, nearbyintf's default). */
static uint16_t gray16_of(float v)
{
	v = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;
	return (uint16_t)nearbyintf(v * 65535.0f);
}

/* A wide frame's AO image of `fmt` at `stride` into `buf` (stride x rows + guard, all
 * 0xa5 first) by a new context: frame 0 of `z` (metres). */
static void wide_ao(int w, int h, int algorithm, const float *z, enum dao_pixfmt fmt, int stride,
		    unsigned char *buf, size_t size)
{
	struct dao_camera cam;
	dao_camera_from_intrinsics(&cam, (uint32_t)w, (uint32_t)h, 200, 200, (w - 1) / 2.0,
				   (h - 1) / 2.0, NULL);
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.threads = 1;
	p.algorithm = algorithm;
	p.invalid_value = 0.3f; /* 19660.5 counts: a tie, to even */
	struct dao_context *ctx = NULL;
	struct dao_error err;
	if (dao_context_create(&ctx, &cam, &p, &err))
		fail_msg("create %dx%d: %s", w, h, err.message);
	const struct dao_frame in = { .format = DAO_PIXFMT_DEPTH_F32, .width = (uint32_t)w,
				      .height = (uint32_t)h, .stride = 4 * w, .data = (void *)z };
	struct dao_frame ao = { .format = fmt, .width = (uint32_t)w, .height = (uint32_t)h,
				.stride = stride, .data = buf };
	memset(buf, 0xa5, size);
	if (dao_context_process(ctx, &in, NULL, 0, &ao, &err))
		fail_msg("process %dx%d: %s", w, h, err.message);
	dao_context_destroy(ctx);
}

/* Nothing of `buf` written but the w x h pixels of `bpp` bytes: each row's padding and
 * the guard after the image still 0xa5. */
static void untouched_outside(const unsigned char *buf, int w, int h, int bpp, int stride,
			      size_t guard, const char *what)
{
	for (int y = 0; y < h; y++)
		for (int k = bpp * w; k < stride; k++)
			if (buf[(size_t)y * stride + k] != 0xa5)
				fail_msg("%s, %d px: row %d's padding byte %d written", what, w, y,
					 k - bpp * w);
	for (size_t k = 0; k < guard; k++)
		if (buf[(size_t)stride * h + k] != 0xa5)
			fail_msg("%s, %d px: byte %zu past the image written", what, w, k);
}

/*
 * GRAY16 AO images of rows wider than the output's chunk of 256 pixels, with a ragged
 * tail (300 = 256 + 44, 517 = 2 x 256 + 5), into strides of an odd number of bytes of
 * padding (rows unaligned), a guard after the image: every pixel of a real run (GTAO)
 * the rule above applied to the same run's GRAY_F32 image, and every pixel of
 * algorithm=none's constant image 65535 where there is depth and invalid_value's counts
 * where not; padding and guard untouched.
 */
static void test_ao_wide_rows(void **state)
{
	(void)state;
	enum { WH = 24, PADB = 5, GUARD = 1024 }; /* a guard past a whole chunk */
	static const int widths[] = { 300, 517 };
	for (size_t wi = 0; wi < sizeof widths / sizeof widths[0]; wi++) {
		const int w = widths[wi];
		/* bumps on a slanted wall (occlusion that differs from pixel to pixel: a shifted
		 * or dropped chunk shows), holes among them, some at the chunks' edges */
		float *z = malloc(sizeof(float) * (size_t)w * WH);
		assert_non_null(z);
		for (int y = 0; y < WH; y++)
			for (int x = 0; x < w; x++)
				z[y * w + x] = x % 13 == 0 || x == 255 || x == 256 || x == w - 1
						       ? 0.0f
						       : 1.5f + 0.001f * (float)x +
								 0.04f * sinf(0.7f * (float)x) *
									 cosf(0.5f * (float)y);
		const int s32 = 4 * w + PADB, s16 = 2 * w + PADB;
		const size_t size32 = (size_t)s32 * WH + GUARD, size16 = (size_t)s16 * WH + GUARD;
		unsigned char *f32 = malloc(size32), *g16 = malloc(size16);
		assert_non_null(f32);
		assert_non_null(g16);
		for (int alg = 0; alg < 2; alg++) {
			const int algorithm = alg ? DAO_ALGORITHM_NONE : DAO_ALGORITHM_GTAO;
			const char *what = alg ? "algorithm=none" : "GTAO";
			wide_ao(w, WH, algorithm, z, DAO_PIXFMT_GRAY16, s16, g16, size16);
			if (!alg)
				wide_ao(w, WH, algorithm, z, DAO_PIXFMT_GRAY_F32, s32, f32, size32);
			int varied = 0;
			for (int y = 0; y < WH; y++)
				for (int x = 0; x < w; x++) {
					uint16_t got, want;
					memcpy(&got, g16 + (size_t)y * s16 + 2 * (size_t)x, 2);
					if (alg) {
						want = z[y * w + x] > 0.0f ? 65535 : gray16_of(0.3f);
					} else {
						float v;
						memcpy(&v, f32 + (size_t)y * s32 + 4 * (size_t)x, 4);
						want = gray16_of(v);
						varied += x && z[y * w + x] > 0.0f && z[y * w + x - 1] > 0.0f &&
							  memcmp(&v, f32 + (size_t)y * s32 + 4 * (size_t)x - 4,
								 4) != 0;
					}
					if (got != want)
						fail_msg("%s, %d px: (%d, %d) is %u, not %u", what, w, x, y,
							 got, want);
				}
			/* the real run's occlusion differs between most neighbours */
			if (!alg && varied < w * WH / 2)
				fail_msg("GTAO, %d px: only %d pixels differ from their left neighbour",
					 w, varied);
			untouched_outside(g16, w, WH, 2, s16, GUARD, what);
		}
		assert_int_equal(gray16_of(0.3f), 19660);
		free(f32);
		free(g16);
		free(z);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_create_errors),
		cmocka_unit_test(test_process_errors),
		cmocka_unit_test(test_bounds_and_formats),
		cmocka_unit_test(test_determinism_and_params),
		cmocka_unit_test(test_float_depth_and_normals),
		cmocka_unit_test(test_params_change_kernels),
		cmocka_unit_test(test_small_sizes),
		cmocka_unit_test(test_ao_wide_rows),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
