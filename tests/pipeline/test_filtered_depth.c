/* SPDX-License-Identifier: MIT */
/*
 * The filtered depth as an output (dao_context_get_depth, algorithm=none):
 * its formats, units and errors, and what the filters may do to the depth:
 * no flying pixels at a step edge, no holes filled, the scale kept, a pixel
 * that lost its depth stays empty under the temporal filter.
 */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/cmocka_all.h"
#include "common/test_common.h"

enum { W = 128, H = 96, PAD = 6 };

static struct dao_camera camera(void)
{
	struct dao_camera cam;
	dao_camera_from_intrinsics(&cam, W, H, 110, 110, 63.5, 47.5, NULL);
	return cam;
}

static uint32_t lcg(uint32_t *s)
{
	*s = *s * 1664525u + 1013904223u;
	return *s >> 8;
}

/* uniform in [-1, 1] */
static float unit_noise(uint32_t *s)
{
	return (float)lcg(s) / (float)(1u << 24) * 2.0f - 1.0f; /* lcg: 24 bits */
}

/* Noise amplitude (bound, not sigma) of a surface at z: 2 mm at 1 m, z^2. */
static float amp(float z)
{
	return 0.002f * z * z;
}

/* A step: left of x = W/2 a plane at 1 m, right of it one at 2 m, each with
 * bounded noise; a 3 x 3 hole in each plane. Metres. */
static void make_step(float *z, uint32_t seed)
{
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			const float t = x < W / 2 ? 1.0f : 2.0f;
			z[y * W + x] = t + amp(t) * unit_noise(&seed);
		}
	for (int y = 40; y < 43; y++)
		for (int x = 20; x < 23; x++) {
			z[y * W + x] = 0.0f;
			z[y * W + x + 70] = 0.0f;
		}
}

static struct dao_frame f32_frame(float *z)
{
	return (struct dao_frame){ .format = DAO_PIXFMT_DEPTH_F32, .width = W, .height = H,
				   .stride = 4 * W, .data = z };
}

static struct dao_context *context(int algorithm, float depth_temporal)
{
	struct dao_camera cam = camera();
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.threads = 1;
	p.algorithm = algorithm;
	p.depth_temporal = depth_temporal;
	struct dao_context *ctx = NULL;
	struct dao_error err;
	if (dao_context_create(&ctx, &cam, &p, &err))
		fail_msg("create: %s", err.message);
	return ctx;
}

static void process(struct dao_context *ctx, float *z, uint64_t index, struct dao_frame *ao)
{
	struct dao_frame in = f32_frame(z);
	struct dao_error err;
	if (dao_context_process(ctx, &in, NULL, index, ao, &err))
		fail_msg("process: %s", err.message);
}

static void get_f32(struct dao_context *ctx, float *out)
{
	struct dao_frame f = f32_frame(out);
	struct dao_error err;
	if (dao_context_get_depth(ctx, &f, &err))
		fail_msg("get depth: %s", err.message);
}

/* Every filtered pixel with depth lies within the noise (twice its bound) of one of the two
 * surfaces (none in between: no flying pixels); the holes stay holes, and
 * the filtered depth has depth exactly where the input has. */
static void check_step(const float *in, const float *out)
{
	for (int i = 0; i < W * H; i++) {
		if (!(in[i] > 0.0f)) {
			assert_true(out[i] == 0.0f);
			continue;
		}
		assert_true(out[i] > 0.0f);
		/* twice the noise bound (measured: none beyond 1x), a margin for the
		 * local lines' overshoot; a pixel between the surfaces is 100x away */
		const int near = fabsf(out[i] - 1.0f) <= 2.0f * amp(1.0f);
		const int far = fabsf(out[i] - 2.0f) <= 2.0f * amp(2.0f);
		if (!near && !far)
			fail_msg("pixel (%d, %d): %.5f m is on neither surface", i % W, i / W,
				 (double)out[i]);
	}
}

/* Filtering happened: the filtered plane is smoother than the input. */
static double interior_mae(const float *z, float truth, int x0, int x1)
{
	double s = 0.0;
	int n = 0;
	for (int y = 8; y < H - 8; y++)
		for (int x = x0; x < x1; x++)
			if (z[y * W + x] > 0.0f) {
				s += fabs(z[y * W + x] - truth);
				n++;
			}
	return s / n;
}

static void test_step_edge(void **state)
{
	(void)state;
	float *in = malloc(sizeof(float) * W * H), *out = malloc(sizeof(float) * W * H);
	assert_non_null(in);
	assert_non_null(out);
	make_step(in, 7);
	struct dao_context *ctx = context(DAO_ALGORITHM_GTAO, 0.0f);
	process(ctx, in, 0, NULL);
	get_f32(ctx, out);
	check_step(in, out);
	/* the filter did something (else the test above could not fail for it) */
	assert_true(interior_mae(out, 1.0f, 8, W / 2 - 8) < 0.8 * interior_mae(in, 1.0f, 8, W / 2 - 8));
	assert_true(interior_mae(out, 2.0f, W / 2 + 8, W - 8) <
		    0.8 * interior_mae(in, 2.0f, W / 2 + 8, W - 8));
	dao_context_destroy(ctx);
	free(in);
	free(out);
}

/* algorithm=none: the same filtered depth as the AO pipeline's, bit for bit;
 * the AO is 1 where there is depth and invalid_value elsewhere; no normals,
 * no shading. */
static void test_depth_only(void **state)
{
	(void)state;
	float *in = malloc(sizeof(float) * W * H), *a = malloc(sizeof(float) * W * H),
	      *b = malloc(sizeof(float) * W * H), *ao = malloc(sizeof(float) * W * H);
	assert_non_null(in);
	assert_non_null(a);
	assert_non_null(b);
	assert_non_null(ao);
	make_step(in, 11);
	struct dao_context *full = context(DAO_ALGORITHM_GTAO, 0.0f);
	struct dao_context *none = context(DAO_ALGORITHM_NONE, 0.0f);
	process(full, in, 3, NULL);
	get_f32(full, a);
	struct dao_frame aof = { .format = DAO_PIXFMT_GRAY_F32, .width = W, .height = H,
				 .stride = 4 * W, .data = ao };
	for (int i = 0; i < W * H; i++)
		ao[i] = -5.0f;
	process(none, in, 3, &aof);
	get_f32(none, b);
	assert_memory_equal(a, b, sizeof(float) * W * H);
	struct dao_params p;
	dao_context_get_params(none, &p);
	for (int i = 0; i < W * H; i++)
		assert_true(ao[i] == (in[i] > 0.0f ? 1.0f : fminf(fmaxf(p.invalid_value, 0.0f), 1.0f)));
	struct dao_error err;
	float nbuf[3 * W * H];
	struct dao_frame nf = { .format = DAO_PIXFMT_NORMAL_F32, .width = W, .height = H,
				.stride = 12 * W, .data = nbuf };
	assert_int_equal(dao_context_get_normals(none, &nf, &err), -ENODATA);
	assert_non_null(strstr(err.message, "algorithm=none"));
	assert_int_equal(dao_context_get_bent_normals(none, &nf, &err), -ENODATA);
	uint8_t rgb[3 * W * H];
	struct dao_frame sf = { .format = DAO_PIXFMT_RGB24, .width = W, .height = H,
				.stride = 3 * W, .data = rgb };
	assert_int_equal(dao_context_shade(none, &sf, &err), -ENODATA);
	assert_non_null(strstr(err.message, "algorithm=none"));
	/* the AO pipeline's context still has them */
	assert_int_equal(dao_context_get_normals(full, &nf, &err), 0);
	dao_context_destroy(full);
	dao_context_destroy(none);
	free(in);
	free(a);
	free(b);
	free(ao);
}

/* Depth16 out: counts of the caller's unit into rows with padding; the
 * input's counts round-trip with the prefilter off; the saturation rule. */
static void test_counts(void **state)
{
	(void)state;
	static uint16_t mm[W * H];
	static uint16_t out[(W + PAD) * H];
	for (int i = 0; i < W * H; i++)
		mm[i] = (uint16_t)(i % 7 == 0 ? 0 : 500 + (i * 37) % 3000);
	struct dao_camera cam = camera();
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.threads = 1;
	p.algorithm = DAO_ALGORITHM_NONE;
	p.prefilter = DAO_PREFILTER_NONE;
	struct dao_context *ctx = NULL;
	struct dao_error err;
	assert_int_equal(dao_context_create(&ctx, &cam, &p, &err), 0);
	struct dao_frame d16 = { .format = DAO_PIXFMT_DEPTH16, .width = W, .height = H,
				 .stride = 2 * W, .data = mm, .depth_unit = 0.001f };
	struct dao_frame o = { .format = DAO_PIXFMT_DEPTH16, .width = W, .height = H,
			       .stride = 2 * (W + PAD), .data = out, .depth_unit = 0.001f };
	/* before a frame */
	assert_int_equal(dao_context_get_depth(ctx, &o, &err), -EAGAIN);
	assert_int_equal(dao_context_process(ctx, &d16, NULL, 0, NULL, &err), 0);
	for (int i = 0; i < (W + PAD) * H; i++)
		out[i] = 0xabcd;
	assert_int_equal(dao_context_get_depth(ctx, &o, &err), 0);
	for (int y = 0; y < H; y++) {
		assert_memory_equal(out + y * (W + PAD), mm + y * W, 2 * W);
		for (int x = W; x < W + PAD; x++)
			assert_int_equal(out[y * (W + PAD) + x], 0xabcd); /* padding untouched */
	}
	/* 0.1 mm counts: ten times the millimetres */
	o.depth_unit = 0.0001f;
	assert_int_equal(dao_context_get_depth(ctx, &o, &err), 0);
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++)
			assert_int_equal(out[y * (W + PAD) + x], 10 * mm[y * W + x]);
	/* 1 um: past 65535 counts saturates; 10 m: below half a count is 1 */
	o.depth_unit = 1e-6f;
	assert_int_equal(dao_context_get_depth(ctx, &o, &err), 0);
	for (int i = 0; i < W * H; i++)
		assert_int_equal(out[(i / W) * (W + PAD) + i % W], mm[i] ? 65535 : 0);
	o.depth_unit = 10.0f;
	assert_int_equal(dao_context_get_depth(ctx, &o, &err), 0);
	for (int i = 0; i < W * H; i++)
		assert_int_equal(out[(i / W) * (W + PAD) + i % W], mm[i] ? 1 : 0);
	/* errors */
	const float bad[] = { 0.0f, -0.001f, NAN, INFINITY };
	for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
		o.depth_unit = bad[k];
		assert_int_equal(dao_context_get_depth(ctx, &o, &err), -EINVAL);
		assert_non_null(strstr(err.message, "depth_unit"));
	}
	o.depth_unit = 0.001f;
	o.stride = 2 * W - 2;
	assert_int_equal(dao_context_get_depth(ctx, &o, &err), -EINVAL);
	o.stride = 2 * W;
	o.width = W - 1;
	assert_int_equal(dao_context_get_depth(ctx, &o, &err), -EINVAL);
	o.width = W;
	o.format = DAO_PIXFMT_GRAY16;
	assert_int_equal(dao_context_get_depth(ctx, &o, &err), -EINVAL);
	assert_int_equal(dao_context_get_depth(NULL, &o, &err), -EINVAL);
	dao_context_destroy(ctx);
}

/* A plane at a known depth stays within its noise and keeps its scale
 * (depth16 in, filtered counts back: the mean of the plane within a count). */
static void test_plane_scale(void **state)
{
	(void)state;
	static uint16_t mm[W * H], out[W * H];
	uint32_t s = 5;
	for (int i = 0; i < W * H; i++)
		mm[i] = (uint16_t)lrintf(1500.0f + 4.0f * unit_noise(&s));
	struct dao_camera cam = camera();
	struct dao_context *ctx = NULL;
	struct dao_error err;
	assert_int_equal(dao_context_create(&ctx, &cam, NULL, &err), 0);
	struct dao_frame d16 = { .format = DAO_PIXFMT_DEPTH16, .width = W, .height = H,
				 .stride = 2 * W, .data = mm, .depth_unit = 0.001f };
	assert_int_equal(dao_context_process(ctx, &d16, NULL, 0, NULL, &err), 0);
	struct dao_frame o = d16;
	o.data = out;
	assert_int_equal(dao_context_get_depth(ctx, &o, &err), 0);
	double sum_in = 0.0, sum_out = 0.0;
	for (int i = 0; i < W * H; i++) {
		assert_true(out[i] >= 1492 && out[i] <= 1508); /* the noise: +-4 */
		sum_in += mm[i];
		sum_out += out[i];
	}
	assert_true(fabs(sum_out - sum_in) / (W * H) < 1.0);
	dao_context_destroy(ctx);
}

/* With the temporal depth filter (persist 0, the default), a pixel that lost
 * its depth is empty in the filtered depth; it comes back with its depth. */
static void test_temporal_loss(void **state)
{
	(void)state;
	float *in = malloc(sizeof(float) * W * H), *out = malloc(sizeof(float) * W * H);
	assert_non_null(in);
	assert_non_null(out);
	struct dao_context *ctx = context(DAO_ALGORITHM_NONE, 0.8f);
	for (uint64_t f = 0; f < 6; f++) {
		make_step(in, 100 + (uint32_t)f);
		if (f >= 3)
			for (int y = 10; y < 20; y++)
				for (int x = 10; x < 20; x++)
					in[y * W + x] = 0.0f;
		process(ctx, in, f, NULL);
		get_f32(ctx, out);
		check_step(in, out);
	}
	for (int y = 10; y < 20; y++)
		for (int x = 10; x < 20; x++)
			assert_true(out[y * W + x] == 0.0f);
	make_step(in, 200);
	process(ctx, in, 6, NULL);
	get_f32(ctx, out);
	check_step(in, out);
	assert_true(out[15 * W + 15] > 0.0f);
	dao_context_destroy(ctx);
	free(in);
	free(out);
}

/* The AO image of algorithm=none in every format: visibility 1 where the
 * frame has depth, invalid-value elsewhere, rounded as the AO pipeline's
 * output rounds; on one and two threads, with the temporal depth filter in
 * the decode (noise-model fixed), after the noise measurement (auto) and off,
 * over frames whose holes move. */
static void test_depth_only_ao_formats(void **state)
{
	(void)state;
	static const enum dao_pixfmt fmts[3] = { DAO_PIXFMT_GRAY_F32, DAO_PIXFMT_GRAY16,
						 DAO_PIXFMT_GRAY8 };
	static const int bytes[3] = { 4, 2, 1 };
	/* 0.3: 19660.5 and 76.5 counts, rounded to even (19660, 76) */
	static const uint32_t open[3] = { 0x3f800000u, 65535u, 255u };
	static const uint32_t none[3] = { 0x3e99999au, 19660u, 76u };
	float *in = malloc(sizeof(float) * W * H);
	unsigned char *buf = malloc(4 * (W + PAD) * H);
	assert_non_null(in);
	assert_non_null(buf);
	const struct dao_camera cam = camera();
	for (int c = 0; c < 3 * 2 * 3; c++) {
		const int fmt = c % 3, threads = 1 + (c / 3) % 2, filter = c / 6;
		struct dao_params p;
		dao_params_init(&p, DAO_QUALITY_DEFAULT);
		p.algorithm = DAO_ALGORITHM_NONE;
		p.threads = threads;
		p.invalid_value = 0.3f;
		p.depth_temporal = filter ? 0.8f : 0.0f;
		p.noise_model = filter == 1 ? DAO_NOISE_MODEL_FIXED : DAO_NOISE_MODEL_AUTO;
		struct dao_context *ctx = NULL;
		struct dao_error err;
		if (dao_context_create(&ctx, &cam, &p, &err))
			fail_msg("create: %s", err.message);
		const int stride = bytes[fmt] * W + PAD;
		struct dao_frame ao = { .format = fmts[fmt], .width = W, .height = H,
					.stride = stride, .data = buf };
		for (uint64_t f = 0; f < 4; f++) {
			make_step(in, 300 + (uint32_t)f);
			for (int y = 5; y < 15; y++)
				for (int x = 3 * (int)f; x < 3 * (int)f + 9; x++)
					in[y * W + x] = 0.0f;
			memset(buf, 0xa5, 4 * (W + PAD) * H);
			process(ctx, in, f, &ao);
			for (int i = 0; i < W * H; i++) {
				const unsigned char *px =
					buf + (size_t)(i / W) * stride + (size_t)(i % W) * bytes[fmt];
				uint32_t v = px[0];
				if (bytes[fmt] == 2) {
					uint16_t v16;
					memcpy(&v16, px, 2);
					v = v16;
				} else if (bytes[fmt] == 4) {
					memcpy(&v, px, 4);
				}
				if (v != (in[i] > 0.0f ? open[fmt] : none[fmt]))
					fail_msg("case %d frame %d pixel (%d, %d): %#x", c, (int)f, i % W,
						 i / W, v);
			}
			/* nothing written past a row's pixels, into the stride's padding */
			for (int y = 0; y < H; y++)
				for (int k = 0; k < PAD; k++)
					if (buf[(size_t)y * stride + (size_t)bytes[fmt] * W + k] != 0xa5)
						fail_msg("case %d frame %d: row %d's padding byte %d "
							 "written", c, (int)f, y, k);
			/* the constant image is the output's time, no denoise ran */
			struct dao_timings tm = DAO_TIMINGS_INIT;
			dao_context_timings(ctx, &tm);
			assert_true(tm.denoise_ms == 0.0);
		}
		dao_context_destroy(ctx);
	}
	free(in);
	free(buf);
}

/* The metres-to-counts rule of dao_context_get_depth, one pixel at a time: 0 stays 0, a
 * depth below half a count is 1, past 65535 counts 65535, else the nearest count (ties
 * to even, the default rounding of nearbyintf). */
static uint16_t counts_of(float z, float unit)
{
	if (!(z > 0.0f))
		return 0;
	const float c = fminf(z * (1.0f / unit), 65535.0f);
	const uint16_t v = (uint16_t)nearbyintf(c);
	return v ? v : 1;
}

/*
 * Rows wider than the depth16 conversion's chunk of 256 pixels, with a ragged tail
 * (300 = 256 + 44, 517 = 2 x 256 + 5: neither a multiple of a vector's 4, 8 or 16
 * lanes), into a stride of an odd number of bytes of padding (the rows unaligned): in
 * metres every pixel the input's (the filters off, the filtered depth is the input),
 * in counts of three units every pixel the rule above (rounding, 1 below half a count,
 * saturation); the padding and a guard past the last row untouched.
 */
static void test_wide_rows(void **state)
{
	(void)state;
	enum { WH = 7, PADB = 5, GUARD = 64 };
	static const int widths[] = { 300, 517 };
	static const float units[] = { 0.0001f, 1e-5f, 10.0f };
	for (size_t wi = 0; wi < sizeof widths / sizeof widths[0]; wi++) {
		const int w = widths[wi];
		struct dao_camera cam;
		dao_camera_from_intrinsics(&cam, (uint32_t)w, WH, 300, 300, (w - 1) / 2.0, 3, NULL);
		struct dao_params p;
		dao_params_init(&p, DAO_QUALITY_DEFAULT);
		p.threads = 1;
		p.algorithm = DAO_ALGORITHM_NONE;
		p.prefilter = DAO_PREFILTER_NONE;
		p.depth_temporal = 0.0f;
		struct dao_context *ctx = NULL;
		struct dao_error err;
		if (dao_context_create(&ctx, &cam, &p, &err))
			fail_msg("create %dx%d: %s", w, WH, err.message);
		/* a depth that differs from pixel to pixel (a shifted or dropped chunk shows),
		 * holes among them, some at the chunks' edges */
		float *in = malloc(sizeof(float) * (size_t)w * WH);
		assert_non_null(in);
		uint32_t seed = 17;
		for (int y = 0; y < WH; y++)
			for (int x = 0; x < w; x++)
				in[y * w + x] = x % 13 == 0 || x == 255 || x == w - 1
							? 0.0f
							: 0.3f + 0.007f * (float)x + 0.09f * (float)y +
								  0.0004f * unit_noise(&seed);
		const struct dao_frame f32 = { .format = DAO_PIXFMT_DEPTH_F32, .width = (uint32_t)w,
					       .height = WH, .stride = 4 * w, .data = in };
		if (dao_context_process(ctx, &f32, NULL, 0, NULL, &err))
			fail_msg("process %dx%d: %s", w, WH, err.message);
		for (int fmt = 0; fmt < 1 + 3; fmt++) { /* metres, then counts of each unit */
			const int bpp = fmt ? 2 : 4;
			const int stride = bpp * w + PADB;
			const size_t size = (size_t)stride * WH;
			unsigned char *buf = malloc(size + GUARD);
			assert_non_null(buf);
			memset(buf, 0xa5, size + GUARD);
			struct dao_frame o = { .format = fmt ? DAO_PIXFMT_DEPTH16 : DAO_PIXFMT_DEPTH_F32,
					       .width = (uint32_t)w, .height = WH, .stride = stride,
					       .data = buf, .depth_unit = fmt ? units[fmt - 1] : 0.0f };
			if (dao_context_get_depth(ctx, &o, &err))
				fail_msg("get depth %dx%d format %d: %s", w, WH, fmt, err.message);
			for (int y = 0; y < WH; y++) {
				const unsigned char *row = buf + (size_t)y * stride;
				for (int x = 0; x < w; x++) {
					const float z = in[y * w + x];
					if (fmt) {
						uint16_t got;
						memcpy(&got, row + 2 * x, 2);
						if (got != counts_of(z, units[fmt - 1]))
							fail_msg("%d px, unit %g: (%d, %d) is %u counts, "
								 "not %u (%.6f m)", w, (double)units[fmt - 1],
								 x, y, got, counts_of(z, units[fmt - 1]),
								 (double)z);
					} else {
						float got;
						memcpy(&got, row + 4 * x, 4);
						if (memcmp(&got, &z, 4))
							fail_msg("%d px: (%d, %d) is %.6f m, not %.6f", w,
								 x, y, (double)got, (double)z);
					}
				}
				for (int k = bpp * w; k < stride; k++)
					if (row[k] != 0xa5)
						fail_msg("%d px format %d: row %d's padding byte %d written",
							 w, fmt, y, k - bpp * w);
			}
			for (size_t k = size; k < size + GUARD; k++)
				if (buf[k] != 0xa5)
					fail_msg("%d px format %d: byte %zu past the image written", w,
						 fmt, k - size);
			free(buf);
		}
		free(in);
		dao_context_destroy(ctx);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_step_edge),   cmocka_unit_test(test_depth_only),
		cmocka_unit_test(test_counts),      cmocka_unit_test(test_plane_scale),
		cmocka_unit_test(test_temporal_loss), cmocka_unit_test(test_depth_only_ao_formats),
		cmocka_unit_test(test_wide_rows),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
