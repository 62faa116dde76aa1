/* SPDX-License-Identifier: MIT */
/*
 * dao_ply_write() on float depth: NaN, inf, 0 and negative depth are no data,
 * every other pixel is one vertex at its back-projection, in row order; the
 * file is parsed here byte by byte (little-endian, whatever the host); the
 * AO as GRAY_F32 is clamped to [0, 1]; bad inputs are -EINVAL with a message.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/cmocka_all.h"
#include "common/test_common.h"

#define W 5
#define H 3

static float get_f32(const unsigned char *p)
{
	uint32_t u = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 |
		     (uint32_t)p[3] << 24;
	float v;
	memcpy(&v, &u, 4);
	return v;
}

static unsigned char *slurp(const char *path, size_t *len)
{
	FILE *f = fopen(path, "rb");
	assert_non_null(f);
	static unsigned char buf[1 << 16];
	*len = fread(buf, 1, sizeof buf, f);
	fclose(f);
	return buf;
}

static void test_float_depth(void **state)
{
	(void)state;
	struct dao_camera cam;
	struct dao_error err;
	assert_int_equal(dao_camera_from_intrinsics(&cam, W, H, 4.0, 5.0, 2.0, 1.0, &err), 0);
	float depth[H][W + 1] = { /* one pixel of padding per row: a stride */
		{ 1.0f, NAN, 2.0f, 0.0f, 3.0f },
		{ INFINITY, -1.0f, 0.5f, 1.5f, -INFINITY },
		{ 4.0f, 0.0f, 0.25f, NAN, 2.5f },
	};
	float vis[H][W] = {
		{ 1.0f, 0.5f, 0.25f, 0.0f, 1.5f },
		{ 0.1f, 0.2f, -0.5f, 0.75f, NAN },
		{ 0.0f, 1.0f, 0.5f, 0.3f, 0.6f },
	};
	struct dao_frame d = { .format = DAO_PIXFMT_DEPTH_F32, .width = W, .height = H,
			       .stride = (W + 1) * 4, .data = depth };
	struct dao_frame a = { .format = DAO_PIXFMT_GRAY_F32, .width = W, .height = H,
			       .stride = W * 4, .data = vis };
	char path[512];
	snprintf(path, sizeof path, "%s/f.ply", dao_test_tmpdir("ply"));
	uint64_t n = 0;
	assert_int_equal(dao_ply_write(path, &cam, &d, &a, &n, &err), 0);
	assert_int_equal(n, 8);

	size_t len;
	unsigned char *buf = slurp(path, &len);
	const char *end = strstr((const char *)buf, "end_header\n");
	assert_non_null(end);
	assert_non_null(strstr((const char *)buf, "format binary_little_endian 1.0\n"));
	assert_non_null(strstr((const char *)buf, "element vertex 8\n"));
	assert_non_null(strstr((const char *)buf, "property float scalar_ao\nend_header\n"));
	size_t off = (size_t)(end - (const char *)buf) + strlen("end_header\n");
	assert_int_equal(len - off, 8 * 19);
	const unsigned char *p = buf + off;
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			float z = depth[y][x];
			if (!(isfinite(z) && z > 0))
				continue;
			assert_float_equal(get_f32(p), (float)((x - 2.0) / 4.0 * z), 1e-7);
			assert_float_equal(get_f32(p + 4), (float)((y - 1.0) / 5.0 * z), 1e-7);
			assert_float_equal(get_f32(p + 8), z, 0);
			float v = vis[y][x] > 1 ? 1 : vis[y][x] > 0 ? vis[y][x] : 0;
			assert_int_equal(p[12], (int)lrintf(v * 255));
			assert_int_equal(p[13], p[12]);
			assert_int_equal(p[14], p[12]);
			assert_float_equal(get_f32(p + 15), v, 0);
			p += 19;
		}

	/* without AO: x, y, z only */
	assert_int_equal(dao_ply_write(path, &cam, &d, NULL, NULL, &err), 0);
	buf = slurp(path, &len);
	end = strstr((const char *)buf, "end_header\n");
	assert_null(strstr((const char *)buf, "red"));
	assert_int_equal(len - ((size_t)(end - (const char *)buf) + 11), 8 * 12);
}

static void test_bad_inputs(void **state)
{
	(void)state;
	struct dao_camera cam;
	struct dao_error err;
	uint16_t mm[H][W] = { { 0 } };
	assert_int_equal(dao_camera_from_intrinsics(&cam, W, H, 4.0, 5.0, 2.0, 1.0, &err), 0);
	struct dao_frame d = { .format = DAO_PIXFMT_DEPTH16, .width = W, .height = H,
			       .stride = W * 2, .data = mm, .depth_unit = 0.001f };
	char path[512];
	snprintf(path, sizeof path, "%s/bad.ply", dao_test_tmpdir("ply"));
	struct dao_frame small = d;
	small.width = W - 1;
	assert_int_equal(dao_ply_write(path, &cam, &small, NULL, NULL, &err), -EINVAL);
	struct dao_frame nounit = d;
	nounit.depth_unit = 0;
	assert_int_equal(dao_ply_write(path, &cam, &nounit, NULL, NULL, &err), -EINVAL);
	assert_non_null(strstr(err.message, "depth_unit"));
	struct dao_frame rgb = d;
	rgb.format = DAO_PIXFMT_GRAY16;
	assert_int_equal(dao_ply_write(path, &cam, &rgb, NULL, NULL, &err), -EINVAL);
	assert_non_null(strstr(err.message, "depth16 or depth_f32"));
	assert_int_equal(dao_ply_write(path, &cam, &d, &d, NULL, &err), -EINVAL);
	assert_non_null(strstr(err.message, "gray_f32, gray16 or gray8"));
	FILE *f = fopen(path, "rb");
	assert_null(f); /* nothing written */
	/* no pixel with depth: a valid file of no vertices */
	uint64_t n = 7;
	assert_int_equal(dao_ply_write(path, &cam, &d, NULL, &n, &err), 0);
	assert_int_equal(n, 0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_float_depth),
		cmocka_unit_test(test_bad_inputs),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
