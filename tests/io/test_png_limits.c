/* SPDX-License-Identifier: MIT */
/*
 * The pixel limit of the PNG readers: a file that declares more than the
 * limit is refused with -EFBIG before anything of the image's size is
 * allocated (the test interposes glibc's allocator and records the largest
 * request), the default limit is DAO_DEFAULT_MAX_PIXELS (4096 x 4096, the
 * boundary included), and an explicit limit moves the boundary both ways.
 */
#define _GNU_SOURCE
#include <errno.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <png.h>
#include <zlib.h>

#include "common/cmocka_all.h"
#include "common/test_common.h"

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define DAO_TEST_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define DAO_TEST_ASAN 1
#endif

/* glibc's allocator, interposed; not under AddressSanitizer, which brings its own */
#if defined(__GLIBC__) && !defined(DAO_TEST_ASAN)
void *__libc_malloc(size_t n);
void *__libc_calloc(size_t n, size_t m);
void *__libc_realloc(void *p, size_t n);
void *__libc_memalign(size_t a, size_t n);
void __libc_free(void *p);

static atomic_size_t largest; /* the largest single request since the last reset */

static void seen(size_t n)
{
	size_t cur = atomic_load(&largest);
	while (n > cur && !atomic_compare_exchange_weak(&largest, &cur, n))
		;
}

void *malloc(size_t n)
{
	seen(n);
	return __libc_malloc(n);
}

void *calloc(size_t n, size_t m)
{
	seen(n * m);
	return __libc_calloc(n, m);
}

void *realloc(void *p, size_t n)
{
	seen(n);
	return __libc_realloc(p, n);
}

void *aligned_alloc(size_t a, size_t n)
{
	seen(n);
	return __libc_memalign(a, n);
}

int posix_memalign(void **out, size_t a, size_t n)
{
	seen(n);
	*out = __libc_memalign(a, n);
	return *out ? 0 : ENOMEM;
}

void free(void *p)
{
	__libc_free(p);
}
#define HAVE_ALLOC_COUNTER 1
#else
static atomic_size_t largest; /* stays 0: nothing records allocations */
#define HAVE_ALLOC_COUNTER 0
#endif

static char dir[512];

/* dir/name in one of four buffers, so a test can hold a few paths at once */
static const char *path(const char *name)
{
	static char buf[4][600];
	static unsigned next;
	char *b = buf[next++ % 4];
	snprintf(b, sizeof buf[0], "%s/%s", dir, name);
	return b;
}

/* Writes a 16-bit gray PNG of width x height zeros, row by row (no buffer of the image's size). */
static void write_zero_png(const char *file, uint32_t width, uint32_t height)
{
	FILE *fp = fopen(file, "wb");
	assert_non_null(fp);
	png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
	png_infop info = png_create_info_struct(png);
	assert_non_null(png);
	assert_non_null(info);
	png_bytep row = calloc((size_t)width, 2);
	assert_non_null(row);
	if (setjmp(png_jmpbuf(png)))
		fail_msg("libpng failed writing %s", file);
	png_init_io(png, fp);
	png_set_IHDR(png, info, width, height, 16, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE,
		     PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
	png_set_compression_level(png, 9);
	png_write_info(png, info);
	for (uint32_t y = 0; y < height; y++)
		png_write_row(png, row);
	png_write_end(png, NULL);
	png_destroy_write_struct(&png, &info);
	free(row);
	assert_int_equal(fclose(fp), 0);
}

static void put32(FILE *fp, uint32_t v)
{
	const unsigned char b[4] = {v >> 24, v >> 16, v >> 8, v};
	assert_int_equal(fwrite(b, 1, 4, fp), 4);
}

static void put_chunk(FILE *fp, const char *type, const unsigned char *data, uint32_t n)
{
	put32(fp, n);
	assert_int_equal(fwrite(type, 1, 4, fp), 4);
	if (n)
		assert_int_equal(fwrite(data, 1, n, fp), n);
	uLong crc = crc32(crc32(0, (const Bytef *)type, 4), data, n);
	put32(fp, (uint32_t)crc);
}

/*
 * A file whose header declares a 16-bit gray width x height image, followed
 * by the first `rows` rows of zeros and nothing else: a header that lies.
 */
static void write_truncated_png(const char *file, uint32_t width, uint32_t height, uint32_t rows)
{
	FILE *fp = fopen(file, "wb");
	assert_non_null(fp);
	assert_int_equal(fwrite("\x89PNG\r\n\x1a\n", 1, 8, fp), 8);
	unsigned char ihdr[13] = {width >> 24, width >> 16, width >> 8, width,
				  height >> 24, height >> 16, height >> 8, height, 16, 0, 0, 0, 0};
	put_chunk(fp, "IHDR", ihdr, sizeof ihdr);
	size_t row_bytes = 1 + (size_t)width * 2; /* filter byte + samples */
	unsigned char *row = calloc(row_bytes, 1), out[65536];
	z_stream z = {0};
	assert_non_null(row);
	assert_int_equal(deflateInit(&z, 9), Z_OK);
	for (uint32_t y = 0; y < rows; y++) {
		z.next_in = row;
		z.avail_in = (uInt)row_bytes;
		do {
			z.next_out = out;
			z.avail_out = sizeof out;
			assert_true(deflate(&z, y + 1 == rows ? Z_SYNC_FLUSH : Z_NO_FLUSH) != Z_STREAM_ERROR);
			uint32_t n = (uint32_t)(sizeof out - z.avail_out);
			if (n)
				put_chunk(fp, "IDAT", out, n);
		} while (z.avail_out == 0);
	}
	deflateEnd(&z);
	free(row);
	assert_int_equal(fclose(fp), 0);
}

/* The 0.5 MB file of issue #16 that declared 16384 x 16384 (here cut after 64 rows). */
static void test_huge_header_refused_before_allocating(void **state)
{
	(void)state;
	const char *f = path("huge.png");
	write_truncated_png(f, 16384, 16384, 64);
	struct dao_frame out;
	struct dao_error err;
	atomic_store(&largest, 0);
	int r = dao_png_read_depth(f, 0.001f, &out, &err);
	size_t biggest = atomic_load(&largest);
	if (r != -EFBIG)
		fail_msg("expected -EFBIG, got %d: %s", r, err.message);
	assert_non_null(strstr(err.message, "16384x16384"));
	assert_non_null(strstr(err.message, "268435456 pixels"));
	assert_non_null(strstr(err.message, "16777216")); /* the limit */
	assert_null(out.data);
	if (HAVE_ALLOC_COUNTER) {
		printf("largest allocation while refusing it: %zu bytes\n", biggest);
		/* libpng's own state is some kilobytes; one row alone would be 32 KB */
		assert_true(biggest < 32768);
	}
	/* an explicit limit above it gets as far as the missing data */
	r = dao_png_read_limited(f, 16384ull * 16384ull, &out, &err);
	assert_int_equal(r, -EINVAL);
	assert_non_null(strstr(err.message, "corrupt or truncated"));
}

/* 16384 x 1024 is exactly 4096 x 4096: in; one row more is out. */
static void test_default_limit_boundary(void **state)
{
	(void)state;
	const char *at = path("at.png"), *over = path("over.png");
	write_zero_png(at, 16384, 1024);
	write_zero_png(over, 16384, 1025);
	struct dao_frame out;
	struct dao_error err;
	assert_int_equal(dao_png_read(at, &out, &err), 0);
	assert_int_equal(out.width, 16384);
	assert_int_equal(out.height, 1024);
	dao_frame_free(&out);
	assert_int_equal(dao_png_read_depth(over, 0.001f, &out, &err), -EFBIG);
	assert_non_null(strstr(err.message, "16384x1025"));
	assert_int_equal(dao_png_read(over, &out, &err), -EFBIG);
	/* 0 is the default */
	assert_int_equal(dao_png_read_limited(over, 0, &out, &err), -EFBIG);
	assert_int_equal(dao_png_read_depth_limited(at, 0.001f, 0, &out, &err), 0);
	dao_frame_free(&out);
	/* a raised limit lets it in, with its pixels */
	assert_int_equal(dao_png_read_depth_limited(over, 0.002f, 16384ull * 1025, &out, &err), 0);
	assert_int_equal(out.format, DAO_PIXFMT_DEPTH16);
	assert_int_equal(out.height, 1025);
	assert_true(out.depth_unit == 0.002f);
	const uint16_t *last = (const uint16_t *)((const char *)out.data + (size_t)1024 * out.stride);
	assert_int_equal(last[16383], 0);
	dao_frame_free(&out);
}

/* A lower limit: exactly the image passes, one pixel less refuses it. */
static void test_explicit_limit(void **state)
{
	(void)state;
	const char *f = path("small.png");
	write_zero_png(f, 64, 48);
	struct dao_frame out;
	struct dao_error err;
	assert_int_equal(dao_png_read_depth_limited(f, 0.001f, 64 * 48 - 1, &out, &err), -EFBIG);
	assert_non_null(strstr(err.message, "64x48 (3072 pixels)"));
	assert_non_null(strstr(err.message, "limit of 3071 pixels"));
	assert_int_equal(dao_png_read_limited(f, 64 * 48, &out, &err), 0);
	assert_int_equal(out.format, DAO_PIXFMT_GRAY16);
	dao_frame_free(&out);
}

static int setup(void **state)
{
	(void)state;
	snprintf(dir, sizeof dir, "%s/dao-png-limits-XXXXXX", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
	return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state)
{
	(void)state;
	const char *names[] = {"huge.png", "at.png", "over.png", "small.png"};
	for (size_t i = 0; i < sizeof names / sizeof *names; i++)
		unlink(path(names[i]));
	return rmdir(dir);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_huge_header_refused_before_allocating),
		cmocka_unit_test(test_default_limit_boundary),
		cmocka_unit_test(test_explicit_limit),
	};
	return cmocka_run_group_tests(tests, setup, teardown);
}
