/* SPDX-License-Identifier: MIT */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/cmocka_all.h"
#include "common/test_common.h"
#include "depth/decode.h"
#include "depth/prefilter.h"

static void test_decode_units(void **state)
{
	(void)state;
	/* rows padded to 11 bytes: odd stride, unaligned samples */
	unsigned char buf[3 * 11];
	memset(buf, 0xee, sizeof buf);
	const uint16_t counts[3][4] = { { 0, 1, 1000, 65535 }, { 5000, 2, 3, 4 }, { 7, 8, 9, 10 } };
	for (int y = 0; y < 3; y++)
		memcpy(buf + 11 * y + 1, counts[y], 8);
	struct dao_frame f = { .format = DAO_PIXFMT_DEPTH16, .width = 4, .height = 3, .stride = 11,
			       .data = buf + 1 };
	static const float units[] = { 0.001f, 0.0001f, 0.0002f };
	for (int k = 0; k < 3; k++) {
		float z[12];
		f.depth_unit = units[k];
		dao_decode_depth(&f, 0.0f, 1000.0f, z, 0, 3);
		for (int y = 0; y < 3; y++)
			for (int x = 0; x < 4; x++)
				assert_true(z[y * 4 + x] == (float)counts[y][x] * units[k]);
	}
	/* TUM: 5000 counts per metre */
	float z[12];
	f.depth_unit = 0.0002f;
	dao_decode_depth(&f, 0.0f, 1000.0f, z, 1, 2);
	assert_true(fabsf(z[4] - 1.0f) < 1e-6f);
	/* range limits: outside [min, max] is no data */
	f.depth_unit = 0.001f;
	dao_decode_depth(&f, 0.005f, 5.0f, z, 0, 3);
	assert_true(z[1] == 0.0f && z[2] == 1.0f && z[3] == 0.0f && z[4] == 5.0f && z[5] == 0.0f);
	assert_true(z[8] == 0.007f);
}

static void test_decode_float(void **state)
{
	(void)state;
	float in[8] = { 1.5f, 0.0f, NAN, INFINITY, -INFINITY, -2.0f, 30.0f, 0.2f };
	struct dao_frame f = { .format = DAO_PIXFMT_DEPTH_F32, .width = 8, .height = 1, .stride = 32,
			       .data = in };
	float z[8];
	dao_decode_depth(&f, 0.1f, 20.0f, z, 0, 1);
	const float want[8] = { 1.5f, 0, 0, 0, 0, 0, 0, 0.2f };
	for (int i = 0; i < 8; i++)
		assert_true(z[i] == want[i]);
}

enum { W = 80, H = 60 };

/* Depth of plane n.X = c at pixel (x, y) for a 70 px focal length. */
static float plane_at(int x, int y, const double n[3], double c)
{
	double rx = (x - 39.5) / 70.0, ry = (y - 29.5) / 70.0;
	return (float)(c / (n[0] * rx + n[1] * ry + n[2]));
}

/* both reference passes over the whole frame */
static void prefilter(const float *z, float *out, int radius, float k, float unit)
{
	struct dao_prefilter_setup s;
	dao_prefilter_setup_init(&s, W, H, radius, k, unit);
	float *tmp = malloc(W * H * sizeof(float));
	assert_non_null(tmp);
	dao_prefilter_h_ref(&s, z, tmp, 0, H);
	dao_prefilter_v_ref(&s, tmp, out, 0, H);
	free(tmp);
}

static void test_prefilter_keeps_planes(void **state)
{
	(void)state;
	static const double planes[][4] = { { 0, 0, -1, -2 }, { 0.4, -0.3, -0.866, -1.5 } };
	float *z = malloc(W * H * sizeof(float)), *out = malloc(W * H * sizeof(float));
	for (int p = 0; p < 2; p++) {
		for (int y = 0; y < H; y++)
			for (int x = 0; x < W; x++)
				z[y * W + x] = plane_at(x, y, planes[p], planes[p][3]);
		z[10 * W + 10] = 0.0f; /* a hole */
		prefilter(z, out, 3, 0.0012f, 0.0f);
		assert_true(out[10 * W + 10] == 0.0f); /* holes are not filled */
		for (int y = 4; y < H - 4; y++)
			for (int x = 4; x < W - 4; x++) {
				if (abs(x - 10) <= 3 && abs(y - 10) <= 3)
					continue; /* asymmetric window around the hole */
				float e = fabsf(out[y * W + x] - z[y * W + x]) / z[y * W + x];
				if (e > 1e-5f)
					fail_msg("plane %d moved by %g at (%d, %d)", p, e, x, y);
			}
	}
	free(z);
	free(out);
}

static void test_prefilter_noise_and_edges(void **state)
{
	(void)state;
	float *z = malloc(W * H * sizeof(float)), *out = malloc(W * H * sizeof(float));
	unsigned seed = 1;
	/* a step from 1.5 m (left) to 2.0 m (right) with sigma = 0.0012 z^2 noise */
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			float base = x < 40 ? 1.5f : 2.0f;
			float g = 0;
			for (int k = 0; k < 12; k++) { /* Irwin-Hall: approximately normal */
				seed = seed * 1103515245u + 12345u;
				g += (float)((seed >> 8) & 0xffff) / 65536.0f;
			}
			z[y * W + x] = base + (g - 6.0f) * 0.0012f * base * base;
		}
	prefilter(z, out, 3, 0.0012f, 0.001f);
	double s_in = 0, s_out = 0;
	int n = 0;
	for (int y = 5; y < H - 5; y++)
		for (int x = 45; x < 75; x++) {
			s_in += (z[y * W + x] - 2.0) * (z[y * W + x] - 2.0);
			s_out += (out[y * W + x] - 2.0) * (out[y * W + x] - 2.0);
			n++;
		}
	double sd_in = sqrt(s_in / n), sd_out = sqrt(s_out / n);
	print_message("prefilter: noise %.2f mm -> %.2f mm\n", sd_in * 1e3, sd_out * 1e3);
	assert_true(sd_out < sd_in / 2.0);
	/* the edge stays sharp: pixels 3+ px from it keep their side's depth */
	for (int y = 3; y < H - 3; y++) {
		assert_true(fabsf(out[y * W + 36] - 1.5f) < 0.01f);
		assert_true(fabsf(out[y * W + 43] - 2.0f) < 0.02f);
	}
	free(z);
	free(out);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_decode_units),
		cmocka_unit_test(test_decode_float),
		cmocka_unit_test(test_prefilter_keeps_planes),
		cmocka_unit_test(test_prefilter_noise_and_edges),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
