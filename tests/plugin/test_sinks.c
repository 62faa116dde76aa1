/* SPDX-License-Identifier: MIT */
/*
 * The sink wrapper and the built-in sinks: "images" (PNG files), "y4m"
 * (YUV4MPEG2 to a file or FIFO, checked byte by byte: ffprobe is not
 * assumed) and "oni" (the recorder, read back with depthao's own reader).
 * What they do with files that exist and with a full disk; run as
 * `test-sinks enospc` under LD_PRELOAD=dao-enospc-preload.so (meson test
 * sinks-enospc), the full-disk tests also fill a regular file.
 */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <dirent.h>
#include <dlfcn.h>

#include <cmocka.h>

#include "common/test_common.h"
#include "source_test_util.h"

#define PI 3.14159265358979323846

static struct dao_plugins *g_plugins;

static int setup(void **state)
{
	(void)state;
	struct dao_error err;
	signal(SIGPIPE, SIG_IGN); /* as the daemon does: a gone reader is -EPIPE */
	return dao_plugins_load(&g_plugins, "", &err); /* built-ins only */
}

static int teardown(void **state)
{
	(void)state;
	dao_plugins_free(g_plugins);
	return 0;
}

/* A fresh temporary directory (copied: dao_test_tmpdir's buffer is static). */
static void tmpdir(const char *tag, char *buf, size_t len)
{
	snprintf(buf, len, "%s", dao_test_tmpdir(tag));
}

static struct dao_sink *open_sink(const char *uri)
{
	struct dao_sink *s = NULL;
	struct dao_error err;
	int r = dao_sink_open(g_plugins, uri, &s, &err);
	if (r)
		fprintf(stderr, "open %s: %s\n", uri, err.message);
	assert_int_equal(r, 0);
	assert_non_null(s);
	return s;
}

static int negotiate(struct dao_sink *s, enum dao_pixfmt f, uint32_t w, uint32_t h, double fps,
		     struct dao_error *err)
{
	struct dao_sink_format fmt = {
		.size = sizeof(struct dao_sink_format),
		.format = f, .width = w, .height = h, .fps = fps,
				      .depth_unit = 0.001f};
	return dao_sink_negotiate(s, &fmt, err);
}

static void close_ok(struct dao_sink *s)
{
	struct dao_error err;
	int r = dao_sink_close(s, &err);
	if (r)
		fprintf(stderr, "close: %s\n", err.message);
	assert_int_equal(r, 0);
}

/* Whole file into a malloc'ed buffer. */
static uint8_t *slurp(const char *path, size_t *len)
{
	FILE *f = fopen(path, "rb");
	assert_non_null(f);
	uint8_t *buf = NULL;
	size_t n = 0, cap = 0;
	for (;;) {
		if (n == cap) {
			cap = cap ? 2 * cap : 65536;
			buf = realloc(buf, cap);
			assert_non_null(buf);
		}
		size_t k = fread(buf + n, 1, cap - n, f);
		n += k;
		if (k == 0)
			break;
	}
	fclose(f);
	*len = n;
	return buf;
}

static int exists(const char *path)
{
	struct stat st;
	return stat(path, &st) == 0;
}

/* Number of entries (not . and ..) in a directory. */
static int count_entries(const char *dir)
{
	DIR *d = opendir(dir);
	assert_non_null(d);
	int n = 0;
	struct dirent *e;
	while ((e = readdir(d)))
		n += strcmp(e->d_name, ".") && strcmp(e->d_name, "..");
	closedir(d);
	return n;
}

/* A frame whose pixel bytes are a function of (x, y, k); rows padded by 3 bytes. */
static void make_frame(struct dao_frame *f, enum dao_pixfmt fmt, uint32_t w, uint32_t h,
		       uint32_t k)
{
	size_t bpp = dao_pixfmt_bytes_per_pixel(fmt);
	memset(f, 0, sizeof(*f));
	f->format = fmt;
	f->width = w;
	f->height = h;
	f->stride = (int32_t)(w * bpp + 3);
	f->data = calloc(h, (size_t)f->stride);
	assert_non_null(f->data);
	f->depth_unit = 0.001f;
	for (uint32_t y = 0; y < h; y++) {
		uint8_t *row = (uint8_t *)f->data + (size_t)y * (size_t)f->stride;
		for (uint32_t x = 0; x < w; x++) {
			uint32_t v = x * 31 + y * 17 + k * 7;
			if (bpp == 2) {
				uint16_t s = (uint16_t)(v * 257 + 1);
				memcpy(row + 2 * x, &s, 2);
			} else {
				for (size_t c = 0; c < bpp; c++)
					row[bpp * x + c] = (uint8_t)(v + 85 * c);
			}
		}
	}
}

static const uint8_t *pixel(const struct dao_frame *f, uint32_t x, uint32_t y)
{
	return (const uint8_t *)f->data + (size_t)y * (size_t)f->stride +
	       x * dao_pixfmt_bytes_per_pixel(f->format);
}

/* --- the wrapper -------------------------------------------------------- */

static void test_wrapper_open_errors(void **state)
{
	(void)state;
	struct dao_sink *s = NULL;
	struct dao_error err;
	assert_int_equal(dao_sink_open(g_plugins, "nosuch:thing", &s, &err), -ENOENT);
	assert_null(s);
	assert_non_null(strstr(err.message, "no sink plugin 'nosuch'"));
	assert_non_null(strstr(err.message, "available: ")); /* lists the sinks */
	assert_non_null(strstr(err.message, "y4m"));
	assert_non_null(strstr(err.message, "images"));
	assert_non_null(strstr(err.message, "oni"));
	assert_int_equal(dao_sink_open(g_plugins, "/tmp/whatever.xyz", &s, &err), -ENOENT);
	assert_non_null(strstr(err.message, "no sink recognises '/tmp/whatever.xyz'"));
	assert_int_equal(dao_sink_close(NULL, &err), 0);
	/* no place for the registry: an error, and nothing allocated (the registry
	 * leaked here before: 32 bytes definitely lost under valgrind; the sanitised
	 * suites' LeakSanitizer checks it) */
	assert_int_equal(dao_plugins_load(NULL, "", &err), -EINVAL);
	assert_non_null(strstr(err.message, "out is required"));
}

static void test_wrapper_auto_pick(void **state)
{
	(void)state;
	char dir[512], path[600];
	tmpdir("sink-pick", dir, sizeof dir);
	snprintf(path, sizeof path, "%s/x.oni", dir);
	struct dao_sink *s = open_sink(path);
	assert_string_equal(dao_sink_plugin(s)->name, "oni");
	close_ok(s); /* never negotiated: nothing written */
	assert_false(exists(path));
	snprintf(path, sizeof path, "%s/X.ONI?codec=none", dir);
	s = open_sink(path);
	assert_string_equal(dao_sink_plugin(s)->name, "oni");
	close_ok(s);
	snprintf(path, sizeof path, "%s/x.y4m", dir);
	s = open_sink(path);
	assert_string_equal(dao_sink_plugin(s)->name, "y4m");
	close_ok(s);
	s = open_sink(dir); /* an existing directory */
	assert_string_equal(dao_sink_plugin(s)->name, "images");
	close_ok(s);
}

static void test_wrapper_call_order(void **state)
{
	(void)state;
	char dir[512], uri[600];
	struct dao_error err;
	struct dao_frame f, other;
	tmpdir("sink-order", dir, sizeof dir);
	snprintf(uri, sizeof uri, "images:%s", dir);
	struct dao_sink *s = open_sink(uri);
	make_frame(&f, DAO_PIXFMT_GRAY8, 8, 6, 0);

	assert_int_equal(dao_sink_write(s, &f, &err), -EINVAL);
	assert_non_null(strstr(err.message, "negotiate"));

	assert_int_equal(negotiate(s, DAO_PIXFMT_GRAY8, 0, 6, 30, &err), -EINVAL);
	assert_non_null(strstr(err.message, "size"));
	assert_int_equal(negotiate(s, DAO_PIXFMT_GRAY8, 8, 6, NAN, &err), -EINVAL);
	assert_int_equal(negotiate(s, (enum dao_pixfmt)99, 8, 6, 30, &err), -EINVAL);
	assert_int_equal(dao_sink_write(s, &f, &err), -EINVAL); /* still not negotiated */

	assert_int_equal(negotiate(s, DAO_PIXFMT_GRAY8, 8, 6, 30, &err), 0);
	make_frame(&other, DAO_PIXFMT_GRAY8, 8, 5, 0);
	assert_int_equal(dao_sink_write(s, &other, &err), -EINVAL);
	assert_non_null(strstr(err.message, "8x6 gray8"));
	assert_non_null(strstr(err.message, "8x5 gray8"));
	free(other.data);
	make_frame(&other, DAO_PIXFMT_GRAY16, 8, 6, 0);
	assert_int_equal(dao_sink_write(s, &other, &err), -EINVAL);
	assert_non_null(strstr(err.message, "gray16"));
	free(other.data);
	other = f;
	other.data = NULL;
	assert_int_equal(dao_sink_write(s, &other, &err), -EINVAL);
	assert_int_equal(count_entries(dir), 0); /* none of those was written */

	/* negotiating again is fine until the first write */
	assert_int_equal(negotiate(s, DAO_PIXFMT_GRAY8, 8, 6, 25, &err), 0);
	f.sequence = 1;
	assert_int_equal(dao_sink_write(s, &f, &err), 0);
	assert_int_equal(dao_sink_flush(s, &err), 0);
	assert_int_equal(negotiate(s, DAO_PIXFMT_GRAY8, 8, 6, 30, &err), -EINVAL);
	assert_non_null(strstr(err.message, "after the first write"));
	close_ok(s);
	assert_int_equal(count_entries(dir), 1);
	free(f.data);
}

/* dao_sink_write_stream on a sink without write_stream: the checks of dao_sink_write
 * (a frame of another format is refused), a bad stream is refused, and a good frame is
 * written as by dao_sink_write. */
static void test_wrapper_write_stream_fallback(void **state)
{
	(void)state;
	char dir[512], uri[600];
	struct dao_error err;
	struct dao_frame f, other;
	tmpdir("sink-streams", dir, sizeof dir);
	snprintf(uri, sizeof uri, "images:%s", dir);
	struct dao_sink *s = open_sink(uri);
	assert_int_equal(dao_sink_takes_streams(s), 0);
	make_frame(&f, DAO_PIXFMT_GRAY8, 8, 6, 0);
	struct dao_sink_frame_info info = {.size = sizeof(struct dao_sink_frame_info),
					   .stream = DAO_STREAM_AO8, .capture_ns = 1};
	assert_int_equal(dao_sink_write_stream(s, &info, &f, &err), -EINVAL); /* not negotiated */
	assert_int_equal(negotiate(s, DAO_PIXFMT_GRAY8, 8, 6, 30, &err), 0);
	info.stream = DAO_STREAM_COUNT;
	assert_int_equal(dao_sink_write_stream(s, &info, &f, &err), -EINVAL);
	assert_non_null(strstr(err.message, "stream"));
	assert_int_equal(dao_sink_write_stream(s, NULL, &f, &err), -EINVAL);
	info.stream = DAO_STREAM_SHADED;
	make_frame(&other, DAO_PIXFMT_RGB24, 8, 6, 0);
	assert_int_equal(dao_sink_write_stream(s, &info, &other, &err), -EINVAL);
	assert_non_null(strstr(err.message, "rgb24"));
	free(other.data);
	assert_int_equal(count_entries(dir), 0);
	info.stream = DAO_STREAM_AO8;
	assert_int_equal(dao_sink_write_stream(s, &info, &f, &err), 0);
	close_ok(s);
	assert_int_equal(count_entries(dir), 1);
	assert_int_equal(dao_sink_takes_streams(NULL), 0);
	free(f.data);
}

static void test_wrapper_fake_plugins(void **state)
{
	(void)state;
	const char *dir = getenv("DAO_FAKE_PLUGIN_DIR");
	if (!dir)
		skip();
	struct dao_plugins *p;
	struct dao_sink *s = NULL;
	struct dao_error err;
	assert_int_equal(dao_plugins_load(&p, dir, &err), 0);
	/* a sink without write is not loaded (it would be called unchecked): opening it
	 * says why, no crash */
	assert_null(dao_plugins_find(p, "nowrite"));
	assert_int_equal(dao_sink_open(p, "nowrite:x", &s, &err), -ENOENT);
	assert_non_null(strstr(err.message, "sink 'nowrite' has no write()"));
	assert_null(s);
	/* the fake sink has no flush, attach_host or write_stream (optional): it takes frames */
	assert_int_equal(dao_sink_open(p, "fakesink:x", &s, &err), 0);
	struct dao_sink_host host = DAO_SINK_HOST_INIT;
	dao_sink_attach_host(s, &host);
	struct dao_sink_format fmt = DAO_SINK_FORMAT_INIT;
	fmt.format = DAO_PIXFMT_GRAY8;
	fmt.width = 8;
	fmt.height = 6;
	assert_int_equal(dao_sink_negotiate(s, &fmt, &err), 0);
	struct dao_frame f;
	make_frame(&f, DAO_PIXFMT_GRAY8, 8, 6, 0);
	assert_int_equal(dao_sink_write(s, &f, &err), 0);
	struct dao_sink_frame_info info = {.size = sizeof info, .stream = DAO_STREAM_AO8};
	assert_int_equal(dao_sink_write_stream(s, &info, &f, &err), 0);
	assert_int_equal(dao_sink_flush(s, &err), 0);
	assert_int_equal(dao_sink_takes_streams(s), 0);
	free(f.data);
	close_ok(s);
	/* a source-only plugin is not a sink */
	assert_int_equal(dao_sink_open(p, "fakebig:x", &s, &err), -ENOENT);
	dao_plugins_free(p);
}

/* --- images ------------------------------------------------------------- */

static void check_png(const char *dir, const char *name, const struct dao_frame *want,
		      enum dao_pixfmt read_as)
{
	char path[700];
	struct dao_frame got;
	struct dao_error err;
	snprintf(path, sizeof path, "%s/%s", dir, name);
	int r = dao_png_read(path, &got, &err);
	if (r)
		fprintf(stderr, "%s: %s\n", path, err.message);
	assert_int_equal(r, 0);
	assert_int_equal(got.format, read_as);
	assert_int_equal(got.width, want->width);
	assert_int_equal(got.height, want->height);
	size_t bpp = dao_pixfmt_bytes_per_pixel(want->format);
	for (uint32_t y = 0; y < want->height; y++)
		for (uint32_t x = 0; x < want->width; x++)
			assert_memory_equal(pixel(&got, x, y), pixel(want, x, y), bpp);
	dao_frame_free(&got);
}

static void test_images_sink(void **state)
{
	(void)state;
	char base[512], dir[600], uri[800];
	struct dao_error err;
	tmpdir("sink-images", base, sizeof base);
	snprintf(dir, sizeof dir, "%s/new/sub/out", base); /* missing parents */
	snprintf(uri, sizeof uri, "images:%s/", dir);
	static const struct {
		enum dao_pixfmt fmt, read_as;
		uint64_t seq;
		const char *name;
	} cases[] = {
		{DAO_PIXFMT_GRAY8, DAO_PIXFMT_GRAY8, 7, "000007.png"},
		{DAO_PIXFMT_GRAY16, DAO_PIXFMT_GRAY16, 123456, "123456.png"},
		{DAO_PIXFMT_RGB24, DAO_PIXFMT_RGB24, 0, "000000.png"},
		{DAO_PIXFMT_DEPTH16, DAO_PIXFMT_GRAY16, 1234567, "1234567.png"},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		struct dao_sink *s = open_sink(uri);
		assert_string_equal(dao_sink_plugin(s)->name, "images");
		assert_int_equal(negotiate(s, cases[i].fmt, 13, 9, 0, &err), 0);
		struct dao_frame f;
		make_frame(&f, cases[i].fmt, 13, 9, (uint32_t)i);
		f.sequence = cases[i].seq;
		assert_int_equal(dao_sink_write(s, &f, &err), 0);
		close_ok(s);
		check_png(dir, cases[i].name, &f, cases[i].read_as);
		free(f.data);
	}
	assert_int_equal(count_entries(dir), 4); /* no temporary files left */

	/* float formats: the sink names the nearest one it takes */
	struct dao_sink *s = open_sink(uri);
	struct dao_sink_format fmt = {.size = sizeof(struct dao_sink_format), .format = DAO_PIXFMT_GRAY_F32, .width = 4, .height = 4};
	assert_int_equal(dao_sink_negotiate(s, &fmt, &err), 0);
	assert_int_equal(fmt.format, DAO_PIXFMT_GRAY16);
	close_ok(s);

	/* a file where the directory should be */
	char file[700];
	snprintf(file, sizeof file, "%s/a-file", base);
	FILE *fp = fopen(file, "w");
	assert_non_null(fp);
	fclose(fp);
	snprintf(uri, sizeof uri, "images:%s", file);
	s = NULL;
	assert_int_equal(dao_sink_open(g_plugins, uri, &s, &err), -ENOTDIR);
	assert_null(s);
	assert_non_null(strstr(err.message, "a-file exists and is not a directory"));
	snprintf(uri, sizeof uri, "images:%s/below", file);
	assert_true(dao_sink_open(g_plugins, uri, &s, &err) < 0);
	assert_non_null(strstr(err.message, "cannot create directory"));
	assert_int_equal(dao_sink_open(g_plugins, "images:", &s, &err), -EINVAL);
}

/* --- y4m ---------------------------------------------------------------- */

struct y4m {
	char header[128];
	uint32_t w, h;
	const uint8_t *frames[64];
	size_t nframes;
};

/* Parses a YUV4MPEG2 stream of frames of frame_bytes each; 0 if well-formed. */
static int parse_y4m(const uint8_t *buf, size_t len, size_t frame_bytes, struct y4m *y)
{
	memset(y, 0, sizeof(*y));
	const uint8_t *nl = memchr(buf, '\n', len < 128 ? len : 128);
	if (!nl)
		return -1;
	size_t hl = (size_t)(nl - buf);
	memcpy(y->header, buf, hl);
	if (sscanf(y->header, "YUV4MPEG2 W%u H%u ", &y->w, &y->h) != 2)
		return -1;
	size_t pos = hl + 1;
	while (pos < len) {
		if (len - pos < 6 + frame_bytes || memcmp(buf + pos, "FRAME\n", 6) != 0 ||
		    y->nframes == 64)
			return -1;
		y->frames[y->nframes++] = buf + pos + 6;
		pos += 6 + frame_bytes;
	}
	return 0;
}

static void test_y4m_gray8(void **state)
{
	(void)state;
	char dir[512], path[600];
	struct dao_error err;
	tmpdir("sink-y4m", dir, sizeof dir);
	snprintf(path, sizeof path, "%s/out.y4m", dir);
	struct dao_sink *s = open_sink(path);
	assert_int_equal(negotiate(s, DAO_PIXFMT_GRAY8, 5, 3, 25, &err), 0);
	struct dao_frame f[3];
	for (uint32_t k = 0; k < 3; k++) {
		make_frame(&f[k], DAO_PIXFMT_GRAY8, 5, 3, k);
		assert_int_equal(dao_sink_write(s, &f[k], &err), 0);
	}
	assert_int_equal(dao_sink_flush(s, &err), 0);
	close_ok(s);
	size_t len;
	uint8_t *buf = slurp(path, &len);
	struct y4m y;
	assert_int_equal(parse_y4m(buf, len, 15, &y), 0);
	assert_string_equal(y.header, "YUV4MPEG2 W5 H3 F25:1 Ip A1:1 Cmono");
	assert_int_equal(y.nframes, 3);
	for (uint32_t k = 0; k < 3; k++)
		for (uint32_t r = 0; r < 3; r++)
			assert_memory_equal(y.frames[k] + 5 * r, pixel(&f[k], 0, r), 5);
	free(buf);
	for (uint32_t k = 0; k < 3; k++)
		free(f[k].data);

	/* an existing file is left alone (test_y4m_keeps_existing); with overwrite it is
	 * replaced, and no frame -> not even a header */
	char uri[700];
	snprintf(uri, sizeof uri, "y4m:%s?overwrite=true", path);
	s = open_sink(uri);
	close_ok(s);
	buf = slurp(path, &len);
	assert_int_equal(len, 0);
	free(buf);
}

static void test_y4m_gray16(void **state)
{
	(void)state;
	char dir[512], path[600];
	struct dao_error err;
	tmpdir("sink-y4m16", dir, sizeof dir);
	snprintf(path, sizeof path, "y4m:%s/out", dir); /* any name with the prefix */
	struct dao_sink *s = open_sink(path);
	assert_int_equal(negotiate(s, DAO_PIXFMT_GRAY16, 4, 2, 0, &err), 0); /* fps unknown */
	struct dao_frame f;
	make_frame(&f, DAO_PIXFMT_GRAY16, 4, 2, 1);
	uint16_t v = 0x1234;
	memcpy((uint8_t *)f.data, &v, 2); /* pixel (0, 0) */
	assert_int_equal(dao_sink_write(s, &f, &err), 0);
	close_ok(s);
	size_t len;
	uint8_t *buf = slurp(path + 4, &len);
	struct y4m y;
	assert_int_equal(parse_y4m(buf, len, 16, &y), 0);
	assert_string_equal(y.header, "YUV4MPEG2 W4 H2 F30:1 Ip A1:1 Cmono16");
	assert_int_equal(y.nframes, 1);
	assert_int_equal(y.frames[0][0], 0x34); /* little-endian samples */
	assert_int_equal(y.frames[0][1], 0x12);
	for (uint32_t r = 0; r < 2; r++)
		for (uint32_t x = 0; x < 4; x++) {
			uint16_t want;
			memcpy(&want, pixel(&f, x, r), 2);
			const uint8_t *got = y.frames[0] + 2 * (r * 4 + x);
			assert_int_equal(got[0] | got[1] << 8, want);
		}
	free(buf);
	free(f.data);
}

static void test_y4m_rgb_colours(void **state)
{
	(void)state;
	char dir[512], path[600];
	struct dao_error err;
	tmpdir("sink-y4m-rgb", dir, sizeof dir);
	snprintf(path, sizeof path, "%s/c.y4m", dir);
	static const uint8_t rgb[][3] = {
		{255, 255, 255}, {0, 0, 0}, {255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {128, 128, 128},
	};
	/* BT.601 limited range: Y' = 16 + 219 Y, Cb/Cr = 128 + 224 * ... */
	static const int ycc[][3] = {
		{235, 128, 128}, {16, 128, 128}, {81, 90, 240}, {145, 54, 34}, {41, 240, 110},
		{126, 128, 128},
	};
	const uint32_t W = 6, H = 2;
	struct dao_sink *s = open_sink(path);
	assert_int_equal(negotiate(s, DAO_PIXFMT_RGB24, W, H, 29.97, &err), 0);
	struct dao_frame f;
	make_frame(&f, DAO_PIXFMT_RGB24, W, H, 0);
	for (uint32_t y = 0; y < H; y++)
		for (uint32_t x = 0; x < W; x++)
			memcpy((uint8_t *)pixel(&f, x, y), rgb[(x + y) % W], 3);
	assert_int_equal(dao_sink_write(s, &f, &err), 0);
	assert_int_equal(dao_sink_write(s, &f, &err), 0);
	close_ok(s);
	size_t len;
	uint8_t *buf = slurp(path, &len);
	struct y4m y;
	assert_int_equal(parse_y4m(buf, len, 3 * W * H, &y), 0);
	assert_string_equal(y.header, "YUV4MPEG2 W6 H2 F30000:1001 Ip A1:1 C444");
	assert_int_equal(y.nframes, 2);
	for (uint32_t r = 0; r < H; r++)
		for (uint32_t x = 0; x < W; x++) {
			const int *want = ycc[(x + r) % W];
			size_t i = r * W + x;
			for (int c = 0; c < 3; c++) {
				int got = y.frames[1][c * W * H + i];
				if (abs(got - want[c]) > 1)
					fail_msg("colour %u,%u,%u plane %d: %d, want %d", rgb[(x + r) % W][0],
						 rgb[(x + r) % W][1], rgb[(x + r) % W][2], c, got, want[c]);
			}
		}
	/* white, black and pure red exactly as the standard's rounding gives them */
	assert_int_equal(y.frames[0][0], 235);
	assert_int_equal(y.frames[0][W * H + 0], 128);
	assert_int_equal(y.frames[0][2 * W * H + 0], 128);
	assert_int_equal(y.frames[0][1], 16);
	assert_int_equal(y.frames[0][2], 81);
	assert_int_equal(y.frames[0][W * H + 2], 90);
	assert_int_equal(y.frames[0][2 * W * H + 2], 240);
	free(buf);
	free(f.data);
}

/* The F field of the header for a given fps. */
static void check_fps(const char *dir, double fps, const char *want)
{
	char path[600];
	struct dao_error err;
	snprintf(path, sizeof path, "%s/fps.y4m", dir);
	unlink(path); /* an existing file is not replaced */
	struct dao_sink *s = open_sink(path);
	assert_int_equal(negotiate(s, DAO_PIXFMT_GRAY8, 2, 2, fps, &err), 0);
	struct dao_frame f;
	make_frame(&f, DAO_PIXFMT_GRAY8, 2, 2, 0);
	assert_int_equal(dao_sink_write(s, &f, &err), 0);
	close_ok(s);
	free(f.data);
	size_t len;
	uint8_t *buf = slurp(path, &len);
	struct y4m y;
	assert_int_equal(parse_y4m(buf, len, 4, &y), 0);
	if (!strstr(y.header, want))
		fail_msg("fps %g: header '%s', want '%s'", fps, y.header, want);
	free(buf);
}

static void test_y4m_fps_and_refusals(void **state)
{
	(void)state;
	char dir[512], path[600];
	struct dao_error err;
	tmpdir("sink-y4m-fps", dir, sizeof dir);
	check_fps(dir, 30, " F30:1 ");
	check_fps(dir, 15.0, " F15:1 ");
	check_fps(dir, 30000.0 / 1001, " F30000:1001 ");
	check_fps(dir, 59.94, " F60000:1001 ");
	check_fps(dir, 23.976, " F24000:1001 ");
	check_fps(dir, 12.5, " F25:2 ");
	check_fps(dir, 0, " F30:1 ");

	snprintf(path, sizeof path, "%s/d.y4m", dir);
	struct dao_sink *s = open_sink(path);
	assert_int_equal(negotiate(s, DAO_PIXFMT_DEPTH16, 4, 4, 30, &err), -ENOTSUP);
	assert_non_null(strstr(err.message, "depth16"));
	assert_non_null(strstr(err.message, "ao"));
	assert_non_null(strstr(err.message, "shaded"));
	struct dao_sink_format fmt = {.size = sizeof(struct dao_sink_format), .format = DAO_PIXFMT_GRAY_F32, .width = 4, .height = 4};
	assert_int_equal(dao_sink_negotiate(s, &fmt, &err), 0);
	assert_int_equal(fmt.format, DAO_PIXFMT_GRAY16);
	close_ok(s);

	assert_int_equal(dao_sink_open(g_plugins, "y4m:", &s, &err), -EINVAL);
	assert_int_equal(dao_sink_open(g_plugins, "y4m:/nonexistent-dir/x.y4m", &s, &err), -ENOENT);
	assert_non_null(strstr(err.message, "/nonexistent-dir/x.y4m"));
	assert_true(dao_sink_open(g_plugins, "y4m:/", &s, &err) < 0); /* a directory */
}

/* "-" is stdout, and closing the sink leaves stdout open (in a child process). */
static void test_y4m_stdout(void **state)
{
	(void)state;
	char dir[512], path[600];
	tmpdir("sink-y4m-stdout", dir, sizeof dir);
	snprintf(path, sizeof path, "%s/stdout", dir);
	fflush(stdout);
	pid_t pid = fork();
	assert_true(pid >= 0);
	if (pid == 0) {
		struct dao_error err;
		struct dao_sink *s = NULL;
		struct dao_frame f;
		int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
		if (fd < 0 || dup2(fd, STDOUT_FILENO) < 0)
			_exit(2);
		close(fd);
		make_frame(&f, DAO_PIXFMT_GRAY8, 3, 2, 0);
		if (dao_sink_open(g_plugins, "y4m:-", &s, &err) ||
		    negotiate(s, DAO_PIXFMT_GRAY8, 3, 2, 30, &err) || dao_sink_write(s, &f, &err) ||
		    dao_sink_close(s, &err))
			_exit(3);
		if (write(STDOUT_FILENO, "X", 1) != 1) /* still open */
			_exit(4);
		_exit(0);
	}
	int st;
	assert_int_equal(waitpid(pid, &st, 0), pid);
	assert_true(WIFEXITED(st));
	assert_int_equal(WEXITSTATUS(st), 0);
	size_t len;
	uint8_t *buf = slurp(path, &len);
	const char *hdr = "YUV4MPEG2 W3 H2 F30:1 Ip A1:1 Cmono\nFRAME\n";
	assert_int_equal(len, strlen(hdr) + 6 + 1);
	assert_memory_equal(buf, hdr, strlen(hdr));
	assert_int_equal(buf[len - 1], 'X');
	free(buf);
}

static double now_s(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return (double)t.tv_sec + t.tv_nsec * 1e-9;
}

static void test_y4m_fifo_without_reader(void **state)
{
	(void)state;
	char dir[512], fifo[600], uri[700];
	struct dao_error err;
	struct dao_sink *s = NULL;
	tmpdir("sink-fifo0", dir, sizeof dir);
	snprintf(fifo, sizeof fifo, "%s/pipe", dir);
	assert_int_equal(mkfifo(fifo, 0600), 0);
	snprintf(uri, sizeof uri, "y4m:%s", fifo);
	double t0 = now_s();
	assert_int_equal(dao_sink_open(g_plugins, uri, &s, &err), -ENXIO);
	assert_true(now_s() - t0 < 1.0);
	assert_null(s);
	assert_non_null(strstr(err.message, "no reader on FIFO"));
	assert_non_null(strstr(err.message, fifo));
}

/*
 * A reader process for a FIFO: opens it (non-blocking, so the writer's open
 * finds a reader), says so on `ready`, waits for `go` (the writer has it
 * open: reading before would see EOF), then copies what it reads to
 * `copy_to`, stopping after `limit` bytes (0 = until EOF).
 */
static pid_t start_reader(const char *fifo, const char *copy_to, size_t limit, int *go_fd)
{
	int ready[2], go[2];
	assert_int_equal(pipe(ready), 0);
	assert_int_equal(pipe(go), 0);
	pid_t pid = fork();
	assert_true(pid >= 0);
	if (pid == 0) {
		close(ready[0]);
		close(go[1]);
		int fd = open(fifo, O_RDONLY | O_NONBLOCK);
		char c = 'r';
		if (fd < 0 || write(ready[1], &c, 1) != 1 || read(go[0], &c, 1) != 1)
			_exit(2);
		int fl = fcntl(fd, F_GETFL);
		if (fl < 0 || fcntl(fd, F_SETFL, fl & ~O_NONBLOCK) < 0)
			_exit(3);
		FILE *out = fopen(copy_to, "wb");
		if (!out)
			_exit(4);
		char buf[4096];
		size_t total = 0;
		for (;;) {
			size_t want = sizeof buf;
			if (limit && limit - total < want)
				want = limit - total;
			if (want == 0)
				break;
			ssize_t k = read(fd, buf, want);
			if (k < 0 && errno == EINTR)
				continue;
			if (k <= 0)
				break;
			fwrite(buf, 1, (size_t)k, out);
			total += (size_t)k;
		}
		fclose(out);
		close(fd);
		_exit(0);
	}
	close(ready[1]);
	close(go[0]);
	char c;
	assert_int_equal(read(ready[0], &c, 1), 1);
	close(ready[0]);
	*go_fd = go[1];
	return pid;
}

static void wait_reader(pid_t pid)
{
	int st;
	assert_int_equal(waitpid(pid, &st, 0), pid);
	assert_true(WIFEXITED(st));
	assert_int_equal(WEXITSTATUS(st), 0);
}

static void let_reader_go(int fd)
{
	char c = 'g';
	assert_int_equal(write(fd, &c, 1), 1);
	close(fd);
}

static void test_y4m_fifo_with_reader(void **state)
{
	(void)state;
	char dir[512], fifo[600], copy[600], ref[600], uri[700];
	struct dao_error err;
	enum { W = 64, H = 48, N = 20 }; /* 20 x 9 KiB: more than a pipe holds */
	tmpdir("sink-fifo", dir, sizeof dir);
	snprintf(fifo, sizeof fifo, "%s/pipe", dir);
	snprintf(copy, sizeof copy, "%s/received", dir);
	snprintf(ref, sizeof ref, "%s/ref.y4m", dir);
	assert_int_equal(mkfifo(fifo, 0600), 0);

	int go_fd;
	pid_t pid = start_reader(fifo, copy, 0, &go_fd);
	struct dao_sink *s = open_sink(fifo); /* a FIFO picks y4m without a prefix */
	assert_string_equal(dao_sink_plugin(s)->name, "y4m");
	let_reader_go(go_fd);
	snprintf(uri, sizeof uri, "y4m:%s", ref);
	struct dao_sink *r = open_sink(uri); /* the same stream into a file */
	assert_int_equal(negotiate(s, DAO_PIXFMT_RGB24, W, H, 30, &err), 0);
	assert_int_equal(negotiate(r, DAO_PIXFMT_RGB24, W, H, 30, &err), 0);
	for (uint32_t k = 0; k < N; k++) {
		struct dao_frame f;
		make_frame(&f, DAO_PIXFMT_RGB24, W, H, k);
		assert_int_equal(dao_sink_write(s, &f, &err), 0);
		assert_int_equal(dao_sink_write(r, &f, &err), 0);
		free(f.data);
	}
	assert_int_equal(dao_sink_flush(s, &err), 0);
	close_ok(s);
	close_ok(r);
	wait_reader(pid);

	size_t len, ref_len;
	uint8_t *got = slurp(copy, &len), *want = slurp(ref, &ref_len);
	const char *hdr = "YUV4MPEG2 W64 H48 F30:1 Ip A1:1 C444\n";
	assert_int_equal(len, strlen(hdr) + N * (6 + 3 * W * H));
	assert_int_equal(len, ref_len);
	assert_memory_equal(got, want, len);
	struct y4m y;
	assert_int_equal(parse_y4m(got, len, 3 * W * H, &y), 0);
	assert_int_equal(y.nframes, N);
	free(got);
	free(want);
}

static void test_y4m_reader_goes_away(void **state)
{
	(void)state;
	char dir[512], fifo[600], copy[600];
	struct dao_error err;
	tmpdir("sink-fifo-epipe", dir, sizeof dir);
	snprintf(fifo, sizeof fifo, "%s/pipe", dir);
	snprintf(copy, sizeof copy, "%s/received", dir);
	assert_int_equal(mkfifo(fifo, 0600), 0);
	int go_fd;
	pid_t pid = start_reader(fifo, copy, 10, &go_fd); /* reads 10 bytes, then leaves */
	struct dao_sink *s = open_sink(fifo);
	let_reader_go(go_fd);
	assert_int_equal(negotiate(s, DAO_PIXFMT_GRAY8, 64, 64, 30, &err), 0);
	struct dao_frame f;
	make_frame(&f, DAO_PIXFMT_GRAY8, 64, 64, 0);
	int r = 0, n = 0;
	while (r == 0 && n++ < 1000) /* 4 MB at most; a pipe holds 64 KiB */
		r = dao_sink_write(s, &f, &err);
	assert_int_equal(r, -EPIPE);
	assert_non_null(strstr(err.message, "went away"));
	assert_int_equal(dao_sink_write(s, &f, &err), -EPIPE); /* and stays so */
	close_ok(s);
	wait_reader(pid);
	free(f.data);
}

/* --- oni ---------------------------------------------------------------- */

static void fill_depth(struct dao_frame *d, uint32_t f)
{
	for (uint32_t y = 0; y < TEST_H; y++)
		for (uint32_t x = 0; x < TEST_W; x++) {
			uint16_t v = test_depth(f, x, y);
			memcpy((uint8_t *)d->data + (size_t)y * (size_t)d->stride + 2 * x, &v, 2);
		}
}

/* Records `n` test frames through the sink; timestamps per `ts_mode`. */
enum ts_mode { TS_REAL, TS_ZERO, TS_BACKWARDS };

static void record(const char *uri, uint32_t n, float unit, int has_fov, enum ts_mode mode)
{
	struct dao_error err;
	struct dao_sink *s = open_sink(uri);
	assert_string_equal(dao_sink_plugin(s)->name, "oni");
	struct dao_sink_format fmt = {
		.size = sizeof(struct dao_sink_format),
		.format = DAO_PIXFMT_DEPTH16, .width = TEST_W,
				      .height = TEST_H, .fps = 29.97, .depth_unit = unit,
				      .has_fov = has_fov, .hfov = 1.0, .vfov = 0.75};
	int r = dao_sink_negotiate(s, &fmt, &err);
	if (r)
		fprintf(stderr, "negotiate: %s\n", err.message);
	assert_int_equal(r, 0);
	struct dao_frame d;
	make_frame(&d, DAO_PIXFMT_DEPTH16, TEST_W, TEST_H, 0); /* padded rows */
	d.depth_unit = unit;
	for (uint32_t f = 0; f < n; f++) {
		fill_depth(&d, f);
		d.sequence = f + 1;
		d.timestamp_ns = mode == TS_ZERO ? 0 : (1000 + (uint64_t)f * 33333) * 1000;
		if (mode == TS_BACKWARDS && f == 2)
			d.timestamp_ns = 5000; /* before frame 1 */
		r = dao_sink_write(s, &d, &err);
		if (r)
			fprintf(stderr, "write: %s\n", err.message);
		assert_int_equal(r, 0);
	}
	free(d.data);
	close_ok(s);
}

static struct dao_oni_reader *open_reader(const char *path, const struct dao_oni_stream_info **in)
{
	struct dao_oni_reader *rd;
	struct dao_error err;
	int r = dao_oni_reader_open(path, &rd, &err);
	if (r)
		fprintf(stderr, "%s: %s\n", path, err.message);
	assert_int_equal(r, 0);
	int st = dao_oni_reader_depth_stream(rd, &err);
	assert_true(st >= 0);
	*in = dao_oni_reader_stream(rd, (uint32_t)st);
	return rd;
}

static void test_oni_record_and_read_back(void **state)
{
	(void)state;
	char dir[512], path[600];
	struct dao_error err;
	tmpdir("sink-oni", dir, sizeof dir);
	snprintf(path, sizeof path, "%s/rec.oni", dir);
	record(path, 5, 0.001f, 1, TS_REAL);
	assert_int_equal(count_entries(dir), 1); /* no temporary file left */

	const struct dao_oni_stream_info *in;
	struct dao_oni_reader *rd = open_reader(path, &in);
	assert_int_equal(in->frame_count, 5);
	assert_int_equal(in->width, TEST_W);
	assert_int_equal(in->height, TEST_H);
	assert_int_equal(in->fps, 30); /* 29.97 rounded */
	assert_string_equal(in->codec_fourcc, "16zT");
	assert_int_equal(in->pixel_format, DAO_ONI_PIXEL_DEPTH_1_MM);
	assert_float_equal(in->depth_unit, 0.001, 1e-9);
	assert_true(in->has_fov);
	assert_float_equal(in->hfov, 1.0, 1e-12);
	assert_float_equal(in->vfov, 0.75, 1e-12);
	assert_int_equal(in->mirrored, 0);
	struct dao_frame d;
	assert_int_equal(dao_frame_alloc(&d, DAO_PIXFMT_DEPTH16, TEST_W, TEST_H, &err), 0);
	for (uint32_t f = 0; f < 5; f++) {
		assert_int_equal(dao_oni_reader_read_depth(rd, 0, f, &d, &err), 0);
		assert_true(test_is_frame(&d, f));
		assert_int_equal(d.timestamp_ns, (1000 + (uint64_t)f * 33333) * 1000);
	}
	dao_frame_free(&d);
	dao_oni_reader_close(rd);
}

static void test_oni_codecs(void **state)
{
	(void)state;
	char dir[512], path[600], uri[700];
	struct dao_error err;
	tmpdir("sink-oni-codec", dir, sizeof dir);
	static const struct {
		const char *query, *fourcc;
	} cases[] = {{"?codec=none", "NONE"}, {"?codec=16z", "16zP"}, {"?codec=16ZT", "16zT"}};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		snprintf(path, sizeof path, "%s/c%zu.oni", dir, i);
		snprintf(uri, sizeof uri, "oni:%s%s", path, cases[i].query);
		record(uri, 2, 0.001f, 1, TS_REAL);
		const struct dao_oni_stream_info *in;
		struct dao_oni_reader *rd = open_reader(path, &in);
		assert_string_equal(in->codec_fourcc, cases[i].fourcc);
		assert_int_equal(in->frame_count, 2);
		struct dao_frame d;
		assert_int_equal(dao_frame_alloc(&d, DAO_PIXFMT_DEPTH16, TEST_W, TEST_H, &err), 0);
		assert_int_equal(dao_oni_reader_read_depth(rd, 0, 1, &d, &err), 0);
		assert_true(test_is_frame(&d, 1));
		dao_frame_free(&d);
		dao_oni_reader_close(rd);
	}
	struct dao_sink *s = NULL;
	snprintf(uri, sizeof uri, "oni:%s/x.oni?codec=jpeg", dir);
	assert_int_equal(dao_sink_open(g_plugins, uri, &s, &err), -EINVAL);
	assert_non_null(strstr(err.message, "'codec' must be one of none, 16z, 16zp, 16zt, got 'jpeg'"));
	snprintf(path, sizeof path, "%s/what?.oni", dir); /* a '?' without options is a name */
	record(path, 1, 0.001f, 1, TS_REAL);
	assert_true(exists(path));
	snprintf(uri, sizeof uri, "oni:%s/x.oni?fps=30", dir);
	assert_int_equal(dao_sink_open(g_plugins, uri, &s, &err), -EINVAL);
	assert_non_null(strstr(err.message, "unknown option 'fps'"));
	assert_non_null(strstr(err.message, "(known: codec, overwrite)"));
	assert_int_equal(dao_sink_open(g_plugins, "oni:/nonexistent-dir/x.oni", &s, &err),
			 -ENOENT);
	assert_non_null(strstr(err.message, "/nonexistent-dir"));
	snprintf(uri, sizeof uri, "oni:%s", dir);
	assert_int_equal(dao_sink_open(g_plugins, uri, &s, &err), -EISDIR);
	assert_null(s);
}

static void test_oni_timestamps_units_fov(void **state)
{
	(void)state;
	char dir[512], path[600];
	struct dao_error err;
	struct dao_frame d;
	const struct dao_oni_stream_info *in;
	struct dao_oni_reader *rd;
	tmpdir("sink-oni-ts", dir, sizeof dir);
	assert_int_equal(dao_frame_alloc(&d, DAO_PIXFMT_DEPTH16, TEST_W, TEST_H, &err), 0);

	/* no timestamps: sequence * 1e6 / fps (30 after rounding); no fov: the default */
	snprintf(path, sizeof path, "%s/zero.oni", dir);
	record(path, 3, 0.001f, 0, TS_ZERO);
	rd = open_reader(path, &in);
	assert_true(in->has_fov);
	assert_float_equal(in->hfov, 58.5 * PI / 180, 1e-9);
	assert_float_equal(in->vfov, 45.6 * PI / 180, 1e-9);
	for (uint32_t f = 0; f < 3; f++) {
		assert_int_equal(dao_oni_reader_read_depth(rd, 0, f, &d, &err), 0);
		assert_int_equal(d.timestamp_ns, (uint64_t)(f + 1) * 1000000 / 30 * 1000);
	}
	dao_oni_reader_close(rd);

	/* a timestamp going backwards is clamped to the previous one */
	snprintf(path, sizeof path, "%s/back.oni", dir);
	record(path, 4, 0.001f, 1, TS_BACKWARDS);
	rd = open_reader(path, &in);
	assert_int_equal(in->frame_count, 4);
	uint64_t want[] = {1000, 34333, 34333, 100999};
	for (uint32_t f = 0; f < 4; f++) {
		assert_int_equal(dao_oni_reader_read_depth(rd, 0, f, &d, &err), 0);
		assert_int_equal(d.timestamp_ns, want[f] * 1000);
		assert_true(test_is_frame(&d, f));
	}
	dao_oni_reader_close(rd);

	/* 100 um: the finer pixel format */
	snprintf(path, sizeof path, "%s/um.oni", dir);
	record(path, 2, 0.0001f, 1, TS_REAL);
	rd = open_reader(path, &in);
	assert_int_equal(in->pixel_format, DAO_ONI_PIXEL_DEPTH_100_UM);
	assert_float_equal(in->depth_unit, 0.0001, 1e-9);
	assert_int_equal(dao_oni_reader_read_depth(rd, 0, 1, &d, &err), 0);
	assert_true(test_is_frame(&d, 1));
	dao_oni_reader_close(rd);
	dao_frame_free(&d);
}

static void test_oni_nothing_to_save(void **state)
{
	(void)state;
	char dir[512], path[600];
	struct dao_error err;
	tmpdir("sink-oni-empty", dir, sizeof dir);
	snprintf(path, sizeof path, "%s/empty.oni", dir);

	/* negotiated (the writer was opened), no frame: no file, no temporary */
	struct dao_sink *s = open_sink(path);
	assert_int_equal(negotiate(s, DAO_PIXFMT_DEPTH16, TEST_W, TEST_H, 30, &err), 0);
	assert_int_equal(dao_sink_close(s, &err), 0);
	assert_int_equal(count_entries(dir), 0);

	/* non-depth streams are refused, and negotiating again restarts cleanly */
	s = open_sink(path);
	assert_int_equal(negotiate(s, DAO_PIXFMT_DEPTH16, TEST_W, TEST_H, 30, &err), 0);
	assert_int_equal(negotiate(s, DAO_PIXFMT_GRAY16, TEST_W, TEST_H, 30, &err), -ENOTSUP);
	assert_non_null(strstr(err.message, "records depth"));
	assert_non_null(strstr(err.message, "subscribe it to the depth stream"));
	assert_int_equal(negotiate(s, DAO_PIXFMT_RGB24, TEST_W, TEST_H, 30, &err), -ENOTSUP);
	assert_int_equal(count_entries(dir), 0);
	struct dao_frame f;
	make_frame(&f, DAO_PIXFMT_GRAY16, TEST_W, TEST_H, 0);
	assert_int_equal(dao_sink_write(s, &f, &err), -EINVAL); /* not negotiated any more */
	free(f.data);
	assert_int_equal(dao_sink_close(s, &err), 0);
	assert_int_equal(count_entries(dir), 0);
}

/* --- existing files, device targets, full disks ---------------------------- */

/* What sinks log through their host. */
struct log_capture {
	char text[2048];
};

static void capture_log(void *user, int level, const char *message)
{
	struct log_capture *c = user;
	size_t n = strlen(c->text);
	snprintf(c->text + n, sizeof c->text - n, "%d %s\n", level, message);
}

/* Opens `uri` with a host that captures the log, negotiates w x h of `f`. */
static struct dao_sink *open_logged(const char *uri, struct log_capture *cap,
				    struct dao_sink_host *host, enum dao_pixfmt f, uint32_t w,
				    uint32_t h)
{
	struct dao_error err;
	struct dao_sink *s = open_sink(uri);
	memset(cap, 0, sizeof *cap);
	*host = (struct dao_sink_host){.size = sizeof(struct dao_sink_host), .user = cap, .log = capture_log};
	dao_sink_attach_host(s, host);
	int r = negotiate(s, f, w, h, 30, &err);
	if (r)
		fprintf(stderr, "negotiate %s: %s\n", uri, err.message);
	assert_int_equal(r, 0);
	return s;
}

/* Writes frames k0..k1-1 of a w x h pattern; all must succeed. */
static void write_frames(struct dao_sink *s, enum dao_pixfmt f, uint32_t w, uint32_t h,
			 uint32_t k0, uint32_t k1)
{
	struct dao_error err;
	for (uint32_t k = k0; k < k1; k++) {
		struct dao_frame fr;
		make_frame(&fr, f, w, h, k);
		if (f == DAO_PIXFMT_DEPTH16)
			fill_depth(&fr, k);
		fr.timestamp_ns = (1000 + 33333 * (uint64_t)k) * 1000;
		int r = dao_sink_write(s, &fr, &err);
		if (r)
			fprintf(stderr, "write %u: %s\n", k, err.message);
		assert_int_equal(r, 0);
		free(fr.data);
	}
}

/* A second recording to the same name goes to NAME-1.EXT, then NAME-2.EXT; the first stays. */
static void test_y4m_keeps_existing(void **state)
{
	(void)state;
	char dir[512], path[600], uri[700], next[600];
	struct log_capture cap;
	struct dao_sink_host host;
	struct dao_error err;
	tmpdir("sink-y4m-keep", dir, sizeof dir);
	snprintf(path, sizeof path, "%s/out.y4m", dir);
	struct dao_sink *s = open_sink(path);
	assert_int_equal(negotiate(s, DAO_PIXFMT_GRAY8, 8, 4, 30, &err), 0);
	write_frames(s, DAO_PIXFMT_GRAY8, 8, 4, 0, 2);
	close_ok(s);
	size_t len0, len;
	uint8_t *first = slurp(path, &len0);

	for (int i = 1; i <= 2; i++) {
		s = open_logged(path, &cap, &host, DAO_PIXFMT_GRAY8, 8, 4);
		write_frames(s, DAO_PIXFMT_GRAY8, 8, 4, 5, 6);
		close_ok(s);
		uint8_t *now = slurp(path, &len);
		assert_int_equal(len, len0);
		assert_memory_equal(now, first, len0); /* untouched */
		free(now);
		snprintf(next, sizeof next, "%s/out-%d.y4m", dir, i);
		uint8_t *buf = slurp(next, &len);
		struct y4m y;
		assert_int_equal(parse_y4m(buf, len, 32, &y), 0);
		assert_int_equal(y.nframes, 1);
		free(buf);
		if (!strstr(cap.text, next) || !strstr(cap.text, "exists"))
			fail_msg("the log does not say where the stream went: '%s'", cap.text);
	}
	assert_int_equal(count_entries(dir), 3);
	/* overwrite=true replaces it */
	snprintf(uri, sizeof uri, "y4m:%s?overwrite=true", path);
	s = open_sink(uri);
	assert_int_equal(negotiate(s, DAO_PIXFMT_GRAY8, 8, 4, 30, &err), 0);
	write_frames(s, DAO_PIXFMT_GRAY8, 8, 4, 0, 1);
	close_ok(s);
	uint8_t *buf = slurp(path, &len);
	assert_true(len < len0);
	free(buf);
	free(first);
	/* unknown options are errors */
	snprintf(uri, sizeof uri, "y4m:%s?overwrite=maybe", path);
	s = NULL;
	assert_int_equal(dao_sink_open(g_plugins, uri, &s, &err), -EINVAL);
	assert_non_null(strstr(err.message, "overwrite"));
	snprintf(uri, sizeof uri, "y4m:%s?fps=3", path);
	assert_int_equal(dao_sink_open(g_plugins, uri, &s, &err), -EINVAL);
	assert_non_null(strstr(err.message, "unknown option"));
	assert_int_equal(count_entries(dir), 3);
}

/* Character devices are streams (never created, truncated or replaced); directories are refused. */
static void test_y4m_stream_targets(void **state)
{
	(void)state;
	char dir[512], uri[700];
	struct dao_error err;
	struct dao_sink *s = NULL;
	tmpdir("sink-y4m-dev", dir, sizeof dir);
	s = open_sink("y4m:/dev/null");
	assert_int_equal(negotiate(s, DAO_PIXFMT_GRAY8, 8, 4, 30, &err), 0);
	write_frames(s, DAO_PIXFMT_GRAY8, 8, 4, 0, 3);
	close_ok(s);
	struct stat st;
	assert_int_equal(stat("/dev/null", &st), 0);
	assert_true(S_ISCHR(st.st_mode));
	snprintf(uri, sizeof uri, "y4m:%s", dir);
	assert_int_equal(dao_sink_open(g_plugins, uri, &s, &err), -EISDIR);
	assert_non_null(strstr(err.message, "directory"));
	assert_non_null(strstr(err.message, dir));
	assert_int_equal(count_entries(dir), 0);
}

/* The recorder never replaces a recording: the next one goes to NAME-1.oni. */
static void test_oni_keeps_existing(void **state)
{
	(void)state;
	char dir[512], path[600], next[600], uri[700];
	struct log_capture cap;
	struct dao_sink_host host;
	struct dao_error err;
	tmpdir("sink-oni-keep", dir, sizeof dir);
	snprintf(path, sizeof path, "%s/rec.oni", dir);
	record(path, 3, 0.001f, 1, TS_REAL);
	size_t len0, len;
	uint8_t *first = slurp(path, &len0);
	struct dao_sink *s = open_logged(path, &cap, &host, DAO_PIXFMT_DEPTH16, TEST_W, TEST_H);
	write_frames(s, DAO_PIXFMT_DEPTH16, TEST_W, TEST_H, 0, 2);
	close_ok(s);
	uint8_t *now = slurp(path, &len);
	assert_int_equal(len, len0);
	assert_memory_equal(now, first, len0);
	free(now);
	free(first);
	snprintf(next, sizeof next, "%s/rec-1.oni", dir);
	if (!strstr(cap.text, next) || !strstr(cap.text, "exists"))
		fail_msg("the log does not say where the recording went: '%s'", cap.text);
	const struct dao_oni_stream_info *in;
	struct dao_oni_reader *rd = open_reader(next, &in);
	assert_int_equal(in->frame_count, 2);
	assert_null(dao_oni_reader_warning(rd));
	dao_oni_reader_close(rd);
	rd = open_reader(path, &in);
	assert_int_equal(in->frame_count, 3);
	dao_oni_reader_close(rd);
	/* overwrite=true: replaced */
	snprintf(uri, sizeof uri, "oni:%s?overwrite=true", path);
	record(uri, 1, 0.001f, 1, TS_REAL);
	rd = open_reader(path, &in);
	assert_int_equal(in->frame_count, 1);
	dao_oni_reader_close(rd);
	assert_int_equal(count_entries(dir), 2);
	/* not a file at all: refused at open */
	s = NULL;
	assert_int_equal(dao_sink_open(g_plugins, "oni:/dev/null", &s, &err), -EINVAL);
	assert_non_null(strstr(err.message, "not a regular file"));
	assert_null(s);
}

/* dao_enospc_set of the preloaded full-disk module, or NULL. */
typedef void (*enospc_set_fn)(const char *path_contains, long long bytes);
static enospc_set_fn enospc_set(void)
{
	void *self = dlopen(NULL, RTLD_NOW);
	enospc_set_fn fn = NULL;
	if (self) {
		void *sym = dlsym(self, "dao_enospc_set");
		memcpy(&fn, &sym, sizeof fn);
		dlclose(self);
	}
	return fn;
}

/*
 * A full disk: the write that does not fit is -ENOSPC (a short write too),
 * the frames before it stay whole (the partial frame is cut off), every
 * later write fails the same way, and closing keeps the file.
 */
static void test_y4m_full_disk(void **state)
{
	(void)state;
	char dir[512], path[600];
	struct dao_error err;
	struct dao_frame f;
	make_frame(&f, DAO_PIXFMT_GRAY8, 16, 8, 0);
	/* /dev/full: every write is ENOSPC; it stays a device */
	struct dao_sink *s = open_sink("y4m:/dev/full");
	assert_int_equal(negotiate(s, DAO_PIXFMT_GRAY8, 16, 8, 30, &err), 0);
	assert_int_equal(dao_sink_write(s, &f, &err), -ENOSPC);
	assert_non_null(strstr(err.message, "/dev/full"));
	assert_int_equal(dao_sink_write(s, &f, &err), -ENOSPC);
	close_ok(s);
	struct stat st;
	assert_int_equal(stat("/dev/full", &st), 0);
	assert_true(S_ISCHR(st.st_mode));

	enospc_set_fn set = enospc_set();
	if (!set) {
		fprintf(stderr, "note: not preloaded; the regular-file part runs in sinks-enospc\n");
		free(f.data);
		return;
	}
	tmpdir("sink-y4m-full", dir, sizeof dir);
	snprintf(path, sizeof path, "%s/full.y4m", dir);
	const size_t hdr = strlen("YUV4MPEG2 W16 H8 F30:1 Ip A1:1 Cmono\n"), fb = 6 + 16 * 8;
	set(path, (long long)(hdr + 2 * fb + fb / 2)); /* room for 2.5 frames */
	s = open_sink(path);
	assert_int_equal(negotiate(s, DAO_PIXFMT_GRAY8, 16, 8, 30, &err), 0);
	int r[4];
	for (int k = 0; k < 4; k++)
		r[k] = dao_sink_write(s, &f, &err);
	set("", 0);
	assert_int_equal(r[0], 0);
	assert_int_equal(r[1], 0);
	assert_int_equal(r[2], -ENOSPC);
	assert_int_equal(r[3], -ENOSPC);
	assert_non_null(strstr(err.message, path));
	close_ok(s);
	size_t len;
	uint8_t *buf = slurp(path, &len);
	assert_int_equal(len, hdr + 2 * fb); /* the half frame was cut off */
	struct y4m y;
	assert_int_equal(parse_y4m(buf, len, 16 * 8, &y), 0);
	assert_int_equal(y.nframes, 2);
	assert_memory_equal(y.frames[1], f.data, 16); /* first row (stride 19) */
	free(buf);
	free(f.data);
}

static void test_oni_full_disk(void **state)
{
	(void)state;
	enospc_set_fn set = enospc_set();
	if (!set) {
		fprintf(stderr, "note: not preloaded; the recorder's full disk runs in sinks-enospc\n");
		return;
	}
	char dir[512], path[600], uri[700];
	struct log_capture cap;
	struct dao_sink_host host;
	struct dao_error err;
	tmpdir("sink-oni-full", dir, sizeof dir);
	snprintf(path, sizeof path, "%s/full.oni", dir);
	snprintf(uri, sizeof uri, "oni:%s?codec=none", path);
	const long long frame = 40 + 2 * TEST_W * TEST_H;
	set(path, 2000 + 5 * frame / 2); /* the preamble (< 1 KB) and 2.5 frames */
	struct dao_sink *s = open_logged(uri, &cap, &host, DAO_PIXFMT_DEPTH16, TEST_W, TEST_H);
	int r = 0, written = 0;
	struct dao_frame d;
	make_frame(&d, DAO_PIXFMT_DEPTH16, TEST_W, TEST_H, 0);
	for (uint32_t k = 0; k < 8 && r == 0; k++) {
		fill_depth(&d, k);
		d.timestamp_ns = (1000 + 33333 * (uint64_t)k) * 1000;
		r = dao_sink_write(s, &d, &err);
		written += r == 0;
	}
	assert_int_equal(r, -ENOSPC);
	assert_non_null(strstr(err.message, path));
	assert_int_equal(dao_sink_write(s, &d, &err), -ENOSPC); /* and stays so */
	free(d.data);
	assert_true(written >= 2);
	close_ok(s); /* the frames that fit, finalised */
	set("", 0);
	const struct dao_oni_stream_info *in;
	struct dao_oni_reader *rd = open_reader(path, &in);
	assert_int_equal(in->frame_count, (uint32_t)written);
	assert_null(dao_oni_reader_warning(rd));
	struct dao_frame back;
	assert_int_equal(dao_frame_alloc(&back, DAO_PIXFMT_DEPTH16, TEST_W, TEST_H, &err), 0);
	for (int k = 0; k < written; k++) {
		assert_int_equal(dao_oni_reader_read_depth(rd, 0, (uint32_t)k, &back, &err), 0);
		assert_true(test_is_frame(&back, (uint32_t)k));
	}
	dao_frame_free(&back);
	dao_oni_reader_close(rd);
	assert_int_equal(count_entries(dir), 1);
}

/* dao_sync_fail_set of the preloaded module, or NULL. */
typedef void (*sync_fail_fn)(const char *path_contains, int errnum);
static sync_fail_fn sync_fail_set(void)
{
	void *self = dlopen(NULL, RTLD_NOW);
	sync_fail_fn fn = NULL;
	if (self) {
		void *sym = dlsym(self, "dao_sync_fail_set");
		memcpy(&fn, &sym, sizeof fn);
		dlclose(self);
	}
	return fn;
}

/*
 * The sync a write brings about fails (a disk reporting a write-back error):
 * the frame that write handed to the kernel is in the file, so the write says
 * so (0) and the failure comes with the next call; what the sinks reported
 * written is exactly what the file holds.  Before, that write returned the
 * error while its frame stayed in the file: one frame more than counted.
 */
static void test_sync_failure_counts(void **state)
{
	(void)state;
	sync_fail_fn fail_sync = sync_fail_set();
	if (!fail_sync) {
		fprintf(stderr, "note: not preloaded; failing syncs run in sinks-enospc\n");
		return;
	}
	char dir[512], oni[600], y4m[600], uri[700];
	struct dao_error err;
	struct log_capture cap;
	struct dao_sink_host host;
	tmpdir("sink-sync-fail", dir, sizeof dir);
	snprintf(oni, sizeof oni, "%s/rec.oni", dir);
	snprintf(y4m, sizeof y4m, "%s/vid.y4m", dir);
	snprintf(uri, sizeof uri, "oni:%s?codec=none", oni);
	struct dao_sink *rec = open_logged(uri, &cap, &host, DAO_PIXFMT_DEPTH16, TEST_W, TEST_H);
	struct dao_sink *vid = open_sink(y4m);
	assert_int_equal(negotiate(vid, DAO_PIXFMT_GRAY8, TEST_W, TEST_H, 30, &err), 0);
	struct dao_frame d, g;
	make_frame(&d, DAO_PIXFMT_DEPTH16, TEST_W, TEST_H, 0);
	make_frame(&g, DAO_PIXFMT_GRAY8, TEST_W, TEST_H, 0);
	int ok_rec = 0, ok_vid = 0, r_rec = 0, r_vid = 0;
	for (uint32_t k = 0; k < 6 && (r_rec == 0 || r_vid == 0); k++) {
		if (k == 2) { /* the next writes are due to sync, and the syncs fail */
			struct timespec pause = {1, 100000000};
			nanosleep(&pause, NULL);
			fail_sync(dir, EIO);
		}
		fill_depth(&d, k);
		d.timestamp_ns = (1000 + 33333 * (uint64_t)k) * 1000;
		if (r_rec == 0 && (r_rec = dao_sink_write(rec, &d, &err)) == 0)
			ok_rec++;
		if (r_vid == 0 && (r_vid = dao_sink_write(vid, &g, &err)) == 0)
			ok_vid++;
	}
	assert_int_equal(r_rec, -EIO);
	assert_int_equal(r_vid, -EIO);
	struct dao_error ignored;
	dao_sink_close(rec, &ignored);
	dao_sink_close(vid, &ignored);
	fail_sync("", 0);
	const struct dao_oni_stream_info *in;
	struct dao_oni_reader *rd = open_reader(oni, &in);
	if ((int)in->frame_count != ok_rec)
		fail_msg("the recording holds %u frames, %d writes said written", in->frame_count,
			 ok_rec);
	dao_oni_reader_close(rd);
	size_t len;
	uint8_t *buf = slurp(y4m, &len);
	struct y4m y;
	assert_int_equal(parse_y4m(buf, len, TEST_W * TEST_H, &y), 0);
	if ((int)y.nframes != ok_vid)
		fail_msg("the y4m file holds %d frames, %d writes said written", y.nframes, ok_vid);
	free(buf);
	free(d.data);
	free(g.data);
}

int main(int argc, char **argv)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_wrapper_open_errors),
		cmocka_unit_test(test_wrapper_auto_pick),
		cmocka_unit_test(test_wrapper_call_order),
		cmocka_unit_test(test_wrapper_write_stream_fallback),
		cmocka_unit_test(test_wrapper_fake_plugins),
		cmocka_unit_test(test_images_sink),
		cmocka_unit_test(test_y4m_gray8),
		cmocka_unit_test(test_y4m_gray16),
		cmocka_unit_test(test_y4m_rgb_colours),
		cmocka_unit_test(test_y4m_fps_and_refusals),
		cmocka_unit_test(test_y4m_stdout),
		cmocka_unit_test(test_y4m_fifo_without_reader),
		cmocka_unit_test(test_y4m_fifo_with_reader),
		cmocka_unit_test(test_y4m_reader_goes_away),
		cmocka_unit_test(test_oni_record_and_read_back),
		cmocka_unit_test(test_oni_codecs),
		cmocka_unit_test(test_oni_timestamps_units_fov),
		cmocka_unit_test(test_oni_nothing_to_save),
		cmocka_unit_test(test_y4m_keeps_existing),
		cmocka_unit_test(test_y4m_stream_targets),
		cmocka_unit_test(test_oni_keeps_existing),
		cmocka_unit_test(test_y4m_full_disk),
		cmocka_unit_test(test_oni_full_disk),
	};
	const struct CMUnitTest full_disk[] = {
		cmocka_unit_test(test_y4m_full_disk),
		cmocka_unit_test(test_oni_full_disk),
		cmocka_unit_test(test_sync_failure_counts),
	};
	if (argc > 1 && !strcmp(argv[1], "enospc")) {
		if (!enospc_set()) {
			fprintf(stderr, "SKIP: not run under LD_PRELOAD=dao-enospc-preload.so\n");
			return 77;
		}
		return cmocka_run_group_tests(full_disk, setup, teardown);
	}
	return cmocka_run_group_tests(tests, setup, teardown);
}
