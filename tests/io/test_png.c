/* SPDX-License-Identifier: MIT */
#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "common/cmocka_all.h"
#include "common/test_common.h"

static char dir[512];

static const char *path(const char *name)
{
	static char buf[600];
	snprintf(buf, sizeof buf, "%s/%s", dir, name);
	return buf;
}

static void fill(struct dao_frame *f)
{
	size_t bpp = dao_pixfmt_bytes_per_pixel(f->format);
	for (uint32_t y = 0; y < f->height; y++) {
		unsigned char *row = (unsigned char *)f->data + (size_t)y * f->stride;
		for (size_t i = 0; i < f->width * bpp; i++)
			row[i] = (unsigned char)(i * 7 + y * 13 + (i >> 3));
	}
}

static void assert_same_pixels(const struct dao_frame *a, const struct dao_frame *b)
{
	assert_int_equal(a->width, b->width);
	assert_int_equal(a->height, b->height);
	size_t bpp = dao_pixfmt_bytes_per_pixel(a->format);
	for (uint32_t y = 0; y < a->height; y++)
		assert_memory_equal((const char *)a->data + (size_t)y * a->stride,
				    (const char *)b->data + (size_t)y * b->stride, a->width * bpp);
}

static void test_round_trips(void **state)
{
	(void)state;
	static const enum dao_pixfmt fmts[] = { DAO_PIXFMT_GRAY8, DAO_PIXFMT_GRAY16, DAO_PIXFMT_RGB24 };
	for (int k = 0; k < 3; k++) {
		/* a strided source frame */
		size_t bpp = dao_pixfmt_bytes_per_pixel(fmts[k]);
		int stride = (int)(37 * bpp + 6);
		unsigned char *buf = calloc((size_t)stride, 23);
		struct dao_frame f = { .format = fmts[k], .width = 37, .height = 23,
				.stride = stride, .data = buf};
		fill(&f);
		if (fmts[k] == DAO_PIXFMT_GRAY16) {
			uint16_t *p = (uint16_t *)(void *)buf;
			p[0] = 0, p[1] = 65535, p[2] = 0x0102, p[3] = 0x0201; /* byte order matters */
		}
		struct dao_error err;
		assert_int_equal(dao_png_write(path("rt.png"), &f, &err), 0);
		struct dao_frame g;
		assert_int_equal(dao_png_read(path("rt.png"), &g, &err), 0);
		assert_int_equal(g.format, fmts[k]);
		assert_same_pixels(&f, &g);
		dao_frame_free(&g);
		free(buf);
	}
	/* 16-bit samples are big-endian on disk: the first sample 0x1234 starts with 0x12 */
	uint16_t px[2] = { 0x1234, 0x5678 };
	struct dao_frame d = { .format = DAO_PIXFMT_DEPTH16, .width = 2, .height = 1, .stride = 4,
			.data = px, .depth_unit = 0.001f};
	assert_int_equal(dao_png_write(path("d.png"), &d, NULL), 0);
	struct dao_frame g;
	assert_int_equal(dao_png_read_depth(path("d.png"), 0.0002f, &g, NULL), 0);
	assert_int_equal(g.format, DAO_PIXFMT_DEPTH16);
	assert_true(g.depth_unit == 0.0002f);
	assert_int_equal(((uint16_t *)g.data)[0], 0x1234);
	assert_int_equal(((uint16_t *)g.data)[1], 0x5678);
	dao_frame_free(&g);
}

/* The file a path holds, malloc'ed; its length in *len. */
static unsigned char *slurp(const char *file, size_t *len)
{
	FILE *fp = fopen(file, "rb");
	assert_non_null(fp);
	fseek(fp, 0, SEEK_END);
	long n = ftell(fp);
	rewind(fp);
	unsigned char *b = malloc((size_t)n + 1);
	assert_non_null(b);
	assert_int_equal(fread(b, 1, (size_t)n, fp), (size_t)n);
	fclose(fp);
	*len = (size_t)n;
	return b;
}

/* dao_png_encode() gives the bytes dao_png_write_compressed() stores, at every level,
 * and they decode to the frame's pixels (strided source, every format). */
static void test_encode_in_memory(void **state)
{
	(void)state;
	static const enum dao_pixfmt fmts[] = { DAO_PIXFMT_GRAY8, DAO_PIXFMT_GRAY16,
						DAO_PIXFMT_DEPTH16, DAO_PIXFMT_RGB24 };
	for (int k = 0; k < 4; k++)
		for (int level = 0; level <= 9; level += 3) {
			size_t bpp = dao_pixfmt_bytes_per_pixel(fmts[k]);
			int stride = (int)(41 * bpp + 5);
			unsigned char *buf = calloc((size_t)stride, 19);
			struct dao_frame f = { .format = fmts[k], .width = 41, .height = 19, .stride = stride,
						 .data = buf, .depth_unit = 0.001f };
			fill(&f);
			void *png = NULL;
			size_t n = 0;
			struct dao_error err;
			assert_int_equal(dao_png_encode(&f, level, &png, &n, &err), 0);
			assert_non_null(png);
			assert_true(n > 8 && !memcmp(png, "\x89PNG\r\n\x1a\n", 8));
			assert_int_equal(dao_png_write_compressed(path("m.png"), &f, level, &err), 0);
			size_t flen;
			unsigned char *file = slurp(path("m.png"), &flen);
			assert_int_equal(flen, n);
			assert_memory_equal(file, png, n);
			free(file);
			/* and the bytes decode to the pixels */
			FILE *fp = fopen(path("m2.png"), "wb");
			assert_non_null(fp);
			assert_int_equal(fwrite(png, 1, n, fp), n);
			fclose(fp);
			struct dao_frame g;
			assert_int_equal(dao_png_read(path("m2.png"), &g, &err), 0);
			assert_same_pixels(&f, &g);
			dao_frame_free(&g);
			free(png);
			free(buf);
		}
	/* errors leave nothing allocated and say what is wrong */
	uint8_t px[16] = { 0 };
	struct dao_frame f = { .format = DAO_PIXFMT_GRAY8, .width = 4, .height = 4, .stride = 4,
				.data = px };
	void *png = (void *)px;
	size_t n = 99;
	struct dao_error err;
	assert_int_equal(dao_png_encode(&f, 10, &png, &n, &err), -EINVAL);
	assert_null(png);
	assert_int_equal(n, 0);
	assert_non_null(strstr(err.message, "0..9"));
	f.format = DAO_PIXFMT_GRAY_F32;
	f.stride = 16;
	assert_int_equal(dao_png_encode(&f, 1, &png, &n, &err), -EINVAL);
	assert_non_null(strstr(err.message, "gray-f32"));
	f.format = DAO_PIXFMT_GRAY8;
	f.stride = 2;
	assert_int_equal(dao_png_encode(&f, 1, &png, &n, &err), -EINVAL);
	assert_int_equal(dao_png_encode(&f, 1, NULL, &n, &err), -EINVAL);
}

static void expect_read_error(const char *file, int code, const char *needle, int depth)
{
	struct dao_frame f;
	struct dao_error err = { 0 };
	int r = depth ? dao_png_read_depth(file, 0.001f, &f, &err) : dao_png_read(file, &f, &err);
	assert_int_equal(r, code);
	assert_null(f.data);
	if (!strstr(err.message, needle))
		fail_msg("'%s': message '%s' lacks '%s'", file, err.message, needle);
}

static void test_read_errors(void **state)
{
	(void)state;
	expect_read_error(path("missing.png"), -ENOENT, "missing.png", 0);
	FILE *fp = fopen(path("text.png"), "w");
	fputs("hello, not a png", fp);
	fclose(fp);
	expect_read_error(path("text.png"), -EINVAL, "not a PNG", 0);
	/* truncate a valid PNG to half */
	uint8_t px[64 * 64];
	for (int i = 0; i < 64 * 64; i++)
		px[i] = (uint8_t)(i * 31 % 251);
	struct dao_frame f = { .format = DAO_PIXFMT_GRAY8, .width = 64, .height = 64, .stride = 64,
			.data = px};
	assert_int_equal(dao_png_write(path("g8.png"), &f, NULL), 0);
	FILE *in = fopen(path("g8.png"), "rb");
	unsigned char data[65536];
	size_t n = fread(data, 1, sizeof data, in);
	fclose(in);
	FILE *out = fopen(path("trunc.png"), "wb");
	fwrite(data, 1, n / 2, out);
	fclose(out);
	expect_read_error(path("trunc.png"), -EINVAL, "corrupt or truncated", 0);
	/* flip bytes inside the image data: CRC mismatch */
	data[n / 2] ^= 0xff;
	out = fopen(path("crc.png"), "wb");
	fwrite(data, 1, n, out);
	fclose(out);
	expect_read_error(path("crc.png"), -EINVAL, "corrupt", 0);
	/* an 8-bit image is not a depth image */
	expect_read_error(path("g8.png"), -EINVAL, "16-bit", 1);
	struct dao_frame g;
	struct dao_error err;
	assert_int_equal(dao_png_read_depth(path("g8.png"), 0.0f, &g, &err), -EINVAL);
	assert_non_null(strstr(err.message, "unit"));
}

static int count_temp_files(void)
{
	int n = 0;
	DIR *d = opendir(dir);
	struct dirent *e;
	while ((e = readdir(d)))
		n += strstr(e->d_name, ".tmp-") != NULL;
	closedir(d);
	return n;
}

static void test_write_errors(void **state)
{
	(void)state;
	uint8_t px[16] = { 0 };
	struct dao_frame f = { .format = DAO_PIXFMT_GRAY8, .width = 4, .height = 4, .stride = 4,
			.data = px};
	struct dao_error err;
	int r = dao_png_write(path("no/such/dir/x.png"), &f, &err);
	assert_int_equal(r, -ENOENT);
	assert_non_null(strstr(err.message, "x.png"));
	assert_int_equal(access(path("no/such/dir/x.png"), F_OK), -1);
	/* unsupported formats and broken frames */
	struct dao_frame bad = f;
	bad.format = DAO_PIXFMT_GRAY_F32;
	bad.stride = 16;
	assert_int_equal(dao_png_write(path("f.png"), &bad, &err), -EINVAL);
	assert_non_null(strstr(err.message, "gray-f32"));
	bad = f;
	bad.stride = 2;
	assert_int_equal(dao_png_write(path("f.png"), &bad, &err), -EINVAL);
	assert_int_equal(dao_png_write("", &f, &err), -EINVAL);
	assert_int_equal(access(path("f.png"), F_OK), -1);
	/* writing over a directory fails at the rename and leaves nothing behind */
	char sub[600];
	snprintf(sub, sizeof sub, "%s/adir", dir);
	assert_int_equal(mkdir(sub, 0755), 0);
	r = dao_png_write(sub, &f, &err);
	assert_true(r < 0);
	assert_int_equal(count_temp_files(), 0);
	rmdir(sub);
}

int main(void)
{
	snprintf(dir, sizeof dir, "%s", dao_test_tmpdir("png"));
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_round_trips),
		cmocka_unit_test(test_read_errors),
		cmocka_unit_test(test_write_errors),
		cmocka_unit_test(test_encode_in_memory),
	};
	int r = cmocka_run_group_tests(tests, NULL, NULL);
	char cmd[700];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
	if (system(cmd) != 0)
		fprintf(stderr, "could not remove %s\n", dir);
	return r;
}
