/* SPDX-License-Identifier: MIT */
/*
 * The built-in "bag" source on bags written by rosbag's own Python writer
 * (make_bags.py, run at test time into a temporary directory): the three
 * chunk compressions, 16UC1 and big-endian 32FC1, the choice among two depth
 * topics, the RealSense layout with 0.1 mm units, seeking, real-time pacing,
 * the pixel limit, and truncated or corrupt files.  Exits 77 without
 * python3-rosbag.
 */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <dirent.h>

#include <cmocka.h>

#include "common/test_common.h"

#define W 64
#define H 48
#define FRAMES 5

static char g_dir[512];
static struct dao_plugins *g_plugins;

/* make_bags.py's depth_count */
static uint16_t depth_count(uint32_t x, uint32_t y, uint32_t i)
{
	return x == y ? 0 : (uint16_t)(500 + 7 * x + 13 * y + 100 * i);
}

static const char *bag(const char *name)
{
	static char path[700];
	snprintf(path, sizeof path, "%s/%s", g_dir, name);
	return path;
}

static struct dao_source *open_bag(const char *uri, const struct dao_source_options *o)
{
	struct dao_source *s = NULL;
	struct dao_error err;
	int r = dao_source_open(g_plugins, uri, o, &s, &err);
	if (r)
		fprintf(stderr, "open %s: %s\n", uri, err.message);
	assert_int_equal(r, 0);
	assert_string_equal(dao_source_plugin(s)->name, "bag");
	assert_int_equal(dao_source_start(s, &err), 0);
	return s;
}

/* Opening `uri` fails with `code` and a message holding every string of the NULL-ended list. */
static void expect_open_error(const char *uri, int code, ...)
{
	struct dao_source *s = NULL;
	struct dao_error err;
	memset(&err, 0, sizeof err);
	int r = dao_source_open(g_plugins, uri, NULL, &s, &err);
	fprintf(stderr, "expected error: %s\n", err.message);
	assert_int_equal(r, code);
	assert_null(s);
	va_list ap;
	va_start(ap, code);
	for (const char *want; (want = va_arg(ap, const char *));)
		assert_non_null(strstr(err.message, want));
	va_end(ap);
}

static void check_d16(const struct dao_frame *d, uint32_t i)
{
	assert_int_equal(d->format, DAO_PIXFMT_DEPTH16);
	assert_int_equal(d->width, W);
	assert_int_equal(d->height, H);
	for (uint32_t y = 0; y < H; y++) {
		const uint16_t *row = (const uint16_t *)((const uint8_t *)d->data +
							 (size_t)y * (size_t)d->stride);
		for (uint32_t x = 0; x < W; x++)
			if (row[x] != depth_count(x, y, i)) {
				fprintf(stderr, "frame %u (%u, %u): %u, want %u\n", i, x, y, row[x],
					depth_count(x, y, i));
				fail();
			}
	}
}

static void check_camera(const struct dao_source_info *in)
{
	assert_true(in->has_intrinsics);
	assert_true(in->fx == 60.0 && in->fy == 61.0 && in->cx == 31.5 && in->cy == 23.25);
	assert_true(in->has_fov);
	assert_true(fabs(in->hfov - 2 * atan(W / 120.0)) < 1e-12);
}

static void read_d16_bag(const char *name)
{
	struct dao_source *s = open_bag(bag(name), NULL);
	struct dao_source_info in;
	struct dao_source_frame f;
	struct dao_error err;
	dao_source_get_info(s, &in);
	assert_int_equal(in.width, W);
	assert_int_equal(in.height, H);
	assert_int_equal(in.format, DAO_PIXFMT_DEPTH16);
	assert_true(in.depth_unit == 0.001f);
	assert_int_equal(in.frame_count, FRAMES);
	assert_int_equal(in.live, 0);
	assert_non_null(strstr(in.description, "/camera/depth/image_raw"));
	check_camera(&in);
	for (uint32_t i = 0; i < FRAMES; i++) {
		assert_int_equal(dao_source_read(s, &f, 1000, &err), 0);
		assert_int_equal(f.index, i);
		check_d16(&f.depth, i);
		assert_true(f.depth.depth_unit == 0.001f);
		/* the header stamp (100 + i s, i ms), not the record time 3 ms later */
		assert_int_equal(f.depth.timestamp_ns, (100 + (uint64_t)i) * 1000000000u + i * 1000000u);
		assert_int_equal(f.color.format, DAO_PIXFMT_NONE);
		dao_source_release(s, &f);
	}
	assert_int_equal(dao_source_read(s, &f, 1000, &err), DAO_SOURCE_EOS);
	/* seeking by frame, backwards across chunks */
	assert_int_equal(dao_source_seek(s, 3, &err), 0);
	assert_int_equal(dao_source_read(s, &f, 1000, &err), 0);
	assert_int_equal(f.index, 3);
	check_d16(&f.depth, 3);
	assert_int_equal(dao_source_seek(s, 0, &err), 0);
	assert_int_equal(dao_source_read(s, &f, 1000, &err), 0);
	check_d16(&f.depth, 0);
	assert_int_equal(dao_source_seek(s, FRAMES, &err), -EINVAL);
	dao_source_close(s);
}

static void test_uncompressed(void **state)
{
	(void)state;
	read_d16_bag("d16_none.bag");
}

static void test_bz2(void **state)
{
	(void)state;
	read_d16_bag("d16_bz2.bag");
}

static void test_lz4(void **state)
{
	(void)state;
	read_d16_bag("d16_lz4.bag");
}

static void test_prefix_and_options(void **state)
{
	(void)state;
	char uri[800];
	struct dao_source_info in;
	/* the plugin named, and a unit given; start and step */
	snprintf(uri, sizeof uri, "bag:%s?unit=0.0005", bag("d16_lz4.bag"));
	struct dao_source_options o = {.size = sizeof(struct dao_source_options), .start_frame = 1, .step = 2};
	struct dao_source *s = open_bag(uri, &o);
	dao_source_get_info(s, &in);
	assert_true(in.depth_unit == 0.0005f);
	struct dao_source_frame f;
	struct dao_error err;
	for (uint32_t want = 1; want < FRAMES; want += 2) {
		assert_int_equal(dao_source_read(s, &f, 1000, &err), 0);
		assert_int_equal(f.index, want);
		check_d16(&f.depth, want);
		assert_true(f.depth.depth_unit == 0.0005f);
	}
	assert_int_equal(dao_source_read(s, &f, 1000, &err), DAO_SOURCE_EOS);
	dao_source_close(s);
	snprintf(uri, sizeof uri, "%s?unit=2", bag("d16_lz4.bag"));
	expect_open_error(uri, -EINVAL, "bag: 'unit' must be a number in (0, 1], got '2'", NULL);
	snprintf(uri, sizeof uri, "%s?topic=/x&colour=1", bag("d16_lz4.bag"));
	expect_open_error(uri, -EINVAL, "bag: unknown option 'colour' (known: topic, unit, color, "
			  "pose_frame, pose_topic, pose_gap)", NULL);
	/* a misspelt key is an error, not part of the file's name */
	snprintf(uri, sizeof uri, "%s?tpoic=/x", bag("d16_lz4.bag"));
	expect_open_error(uri, -EINVAL, "bag: unknown option 'tpoic'", NULL);
	snprintf(uri, sizeof uri, "%s?topic=/x&topic=/y", bag("d16_lz4.bag"));
	expect_open_error(uri, -EINVAL, "bag: option 'topic' is given twice", NULL);
	struct dao_source_options past = {.size = sizeof(struct dao_source_options), .start_frame = FRAMES};
	struct dao_source *none = NULL;
	assert_int_equal(dao_source_open(g_plugins, bag("d16_lz4.bag"), &past, &none, &err),
			 -EINVAL);
	assert_non_null(strstr(err.message, "past the end"));
}

static void test_float_big_endian(void **state)
{
	(void)state;
	struct dao_source *s = open_bag(bag("f32_be.bag"), NULL);
	struct dao_source_info in;
	struct dao_source_frame f;
	struct dao_error err;
	dao_source_get_info(s, &in);
	assert_int_equal(in.format, DAO_PIXFMT_DEPTH_F32);
	assert_int_equal(in.frame_count, FRAMES);
	check_camera(&in);
	for (uint32_t i = 0; i < FRAMES; i++) {
		assert_int_equal(dao_source_read(s, &f, 1000, &err), 0);
		assert_int_equal(f.depth.format, DAO_PIXFMT_DEPTH_F32);
		for (uint32_t y = 0; y < H; y++) {
			const float *row = (const float *)((const uint8_t *)f.depth.data +
							   (size_t)y * (size_t)f.depth.stride);
			for (uint32_t x = 0; x < W; x++) {
				uint16_t c = depth_count(x, y, i);
				if (c == 0)
					assert_true(isnan(row[x]));
				else
					assert_true(row[x] == (float)(c / 1000.0));
			}
		}
		/* header stamp 0: the record time, 50 s + 250 ms i */
		assert_int_equal(f.depth.timestamp_ns, 50000000000u + 250000000u * (uint64_t)i);
	}
	dao_source_close(s);
}

static double now_s(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return (double)t.tv_sec + t.tv_nsec * 1e-9;
}

/* Real time: frames 250 ms apart take at least 4 x 250 ms; an impatient read is -EAGAIN. */
static void test_realtime(void **state)
{
	(void)state;
	struct dao_source_options o = {.size = sizeof(struct dao_source_options), .playback = DAO_PLAYBACK_REALTIME};
	struct dao_source *s = open_bag(bag("f32_be.bag"), &o);
	struct dao_source_frame f;
	struct dao_error err;
	double t0 = now_s();
	assert_int_equal(dao_source_read(s, &f, 1000, &err), 0);
	assert_int_equal(dao_source_read(s, &f, 0, &err), -EAGAIN);
	for (uint32_t i = 1; i < FRAMES; i++) {
		assert_int_equal(dao_source_read(s, &f, 1000, &err), 0);
		assert_int_equal(f.index, i);
	}
	assert_true(now_s() - t0 >= 0.99);
	dao_source_close(s);
}

static void test_two_topics(void **state)
{
	(void)state;
	char uri[800];
	expect_open_error(bag("two.bag"), -EINVAL, "2 depth topics", "?topic=",
			  "/cam1/depth/image_raw (16UC1)", "/cam2/depth/image_raw (16UC1)", NULL);
	snprintf(uri, sizeof uri, "%s?topic=/cam3/depth", bag("two.bag"));
	expect_open_error(uri, -ENOENT, "no image topic '/cam3/depth'", "/cam1/depth/image_raw",
			  "/cam2/depth/image_raw", NULL);
	snprintf(uri, sizeof uri, "%s?topic=/cam2/depth/image_raw", bag("two.bag"));
	struct dao_source *s = open_bag(uri, NULL);
	struct dao_source_info in;
	struct dao_source_frame f;
	struct dao_error err;
	dao_source_get_info(s, &in);
	check_camera(&in); /* /cam2/depth/camera_info */
	for (uint32_t i = 0; i < FRAMES; i++) {
		assert_int_equal(dao_source_read(s, &f, 1000, &err), 0);
		check_d16(&f.depth, i + 1);
	}
	dao_source_close(s);
	snprintf(uri, sizeof uri, "%s?topic=/cam1/depth/image_raw", bag("two.bag"));
	s = open_bag(uri, NULL);
	dao_source_get_info(s, &in);
	assert_false(in.has_intrinsics); /* cam1 has no camera_info */
	assert_false(in.has_fov);
	assert_int_equal(dao_source_read(s, &f, 1000, &err), 0);
	check_d16(&f.depth, 0);
	dao_source_close(s);
	/* a topic that is not depth */
	snprintf(uri, sizeof uri, "%s?topic=/camera/color/image_raw", bag("d16_none.bag"));
	expect_open_error(uri, -EINVAL, "encoding 'rgb8', not depth", NULL);
}

static void test_realsense(void **state)
{
	(void)state;
	struct dao_source *s = open_bag(bag("realsense.bag"), NULL);
	struct dao_source_info in;
	struct dao_source_frame f;
	struct dao_error err;
	dao_source_get_info(s, &in);
	assert_true(in.depth_unit == 0.0001f);
	check_camera(&in);
	assert_non_null(strstr(in.description, "/device_0/sensor_0/Depth_0/image/data"));
	for (uint32_t i = 0; i < FRAMES; i++) {
		assert_int_equal(dao_source_read(s, &f, 1000, &err), 0);
		check_d16(&f.depth, i);
		assert_true(f.depth.depth_unit == 0.0001f);
	}
	dao_source_close(s);
	/* ?unit= wins over the recording's option */
	char uri[800];
	snprintf(uri, sizeof uri, "%s?unit=0.001", bag("realsense.bag"));
	s = open_bag(uri, NULL);
	dao_source_get_info(s, &in);
	assert_true(in.depth_unit == 0.001f);
	dao_source_close(s);
}

/*
 * A CameraInfo with distortion and a P other than K: P's intrinsics (the
 * rectified image's, as ROS's image_geometry and depthao's CameraInfo YAML
 * reader take them) and a warning that the depth must be rectified.
 */
/* A CameraInfo with impossible numbers (fx = 1e308) is an error naming the value
 * (issue 38: it was taken as the camera). */
static void test_implausible_camera_info(void **state)
{
	(void)state;
	expect_open_error(bag("implausible.bag"), -EINVAL, "implausible.bag",
			  "/camera/depth/camera_info is damaged", "fx=1e+308 is implausible",
			  "from 0.32 to 64000", NULL);
}

static void test_distorted(void **state)
{
	(void)state;
	struct dao_source *s = open_bag(bag("distorted.bag"), NULL);
	struct dao_source_info in;
	struct dao_source_frame f;
	struct dao_error err;
	dao_source_get_info(s, &in);
	fprintf(stderr, "distorted: %s\n", in.warning);
	assert_true(in.has_intrinsics);
	assert_true(in.fx == 45.0 && in.fy == 46.5 && in.cx == 30.0 && in.cy == 22.0);
	assert_true(in.has_fov);
	assert_true(fabs(in.hfov - 2 * atan(W / 90.0)) < 1e-12);
	assert_true(fabs(in.vfov - 2 * atan(H / 93.0)) < 1e-12);
	assert_non_null(strstr(in.warning, "/camera/depth/camera_info has lens distortion"));
	assert_non_null(strstr(in.warning, "must be rectified"));
	assert_non_null(strstr(in.warning, "from P"));
	assert_int_equal(dao_source_read(s, &f, 1000, &err), 0);
	check_d16(&f.depth, 0);
	dao_source_release(s, &f);
	dao_source_close(s);
}

static void test_pixel_limit(void **state)
{
	(void)state;
	struct dao_source *s = NULL;
	struct dao_error err;
	assert_int_equal(dao_source_open_limited(g_plugins, bag("d16_bz2.bag"), NULL, W * H - 1, &s,
						 &err), -EFBIG);
	assert_null(s);
	assert_non_null(strstr(err.message, "64x48"));
	assert_int_equal(dao_source_open_limited(g_plugins, bag("d16_bz2.bag"), NULL, W * H, &s,
						 &err), 0);
	dao_source_close(s);
}

static long file_size(const char *path)
{
	struct stat st;
	assert_int_equal(stat(path, &st), 0);
	return (long)st.st_size;
}

static unsigned char *slurp(const char *path, long *n)
{
	*n = file_size(path);
	unsigned char *b = malloc((size_t)*n);
	FILE *f = fopen(path, "rb");
	assert_non_null(b);
	assert_non_null(f);
	assert_int_equal(fread(b, 1, (size_t)*n, f), (size_t)*n);
	fclose(f);
	return b;
}

static void spill(const char *path, const unsigned char *b, long n)
{
	FILE *f = fopen(path, "wb");
	assert_non_null(f);
	assert_int_equal(fwrite(b, 1, (size_t)n, f), (size_t)n);
	assert_int_equal(fclose(f), 0);
}

/* Truncated anywhere, a bag is an error naming the file (and the byte, for a record). */
static void test_truncated(void **state)
{
	(void)state;
	long n;
	unsigned char *b = slurp(bag("d16_lz4.bag"), &n);
	char cut[700];
	snprintf(cut, sizeof cut, "%s/cut.bag", g_dir);
	const long lens[] = {0, 5, 13, 20, 4000, n / 2, n - 100, n - 1};
	for (size_t i = 0; i < sizeof lens / sizeof lens[0]; i++) {
		spill(cut, b, lens[i]);
		struct dao_source *s = NULL;
		struct dao_error err;
		int r = dao_source_open(g_plugins, cut, NULL, &s, &err);
		fprintf(stderr, "cut at %ld: %s\n", lens[i], err.message);
		assert_int_equal(r, -EINVAL);
		assert_null(s);
		assert_non_null(strstr(err.message, cut));
		if (lens[i] >= 4000)
			assert_non_null(strstr(err.message, "byte "));
	}
	free(b);
}

static long find(const unsigned char *b, long n, const char *what, long from)
{
	size_t k = strlen(what);
	for (long i = from; i + (long)k <= n; i++)
		if (!memcmp(b + i, what, k))
			return i;
	return -1;
}

/*
 * A damaged chunk: its frames are read errors naming the file and the chunk's
 * byte; the frames of other chunks still read.
 */
static void test_corrupt_chunk(void **state)
{
	(void)state;
	long n;
	unsigned char *b = slurp(bag("d16_bz2.bag"), &n);
	long z = find(b, n, "BZh9", 0); /* the first chunk's bzip2 stream */
	assert_true(z > 0);
	for (long i = z + 40; i < z + 60; i++)
		b[i] ^= 0x5a;
	char bad[700];
	snprintf(bad, sizeof bad, "%s/bad-chunk.bag", g_dir);
	spill(bad, b, n);
	free(b);
	struct dao_source *s = NULL;
	struct dao_error err;
	/* the first depth message is in the damaged chunk: opening reads it */
	int r = dao_source_open(g_plugins, bad, NULL, &s, &err);
	fprintf(stderr, "damaged chunk: %s\n", err.message);
	assert_int_equal(r, -EINVAL);
	assert_non_null(strstr(err.message, bad));
	assert_non_null(strstr(err.message, "byte "));
	assert_non_null(strstr(err.message, "bz2"));

	/* a damaged lz4 frame (its magic number) */
	b = slurp(bag("d16_lz4.bag"), &n);
	z = find(b, n, "\x04\x22\x4d\x18", 0);
	assert_true(z > 0);
	b[z] ^= 0xff;
	spill(bad, b, n);
	free(b);
	r = dao_source_open(g_plugins, bad, NULL, &s, &err);
	fprintf(stderr, "damaged lz4 chunk: %s\n", err.message);
	assert_int_equal(r, -EINVAL);
	assert_non_null(strstr(err.message, "byte "));
	assert_non_null(strstr(err.message, "the lz4 chunk does not decompress"));

	/*
	 * two chunk infos naming the same chunk: its index entries would be read
	 * twice (a file of N such infos makes N x M entries of M)
	 */
	b = slurp(bag("d16_none.bag"), &n);
	long c1 = find(b, n, "chunk_pos=", 0), c2 = c1 < 0 ? -1 : find(b, n, "chunk_pos=", c1 + 1);
	assert_true(c1 > 0 && c2 > c1);
	memcpy(b + c2 + 10, b + c1 + 10, 8);
	spill(bad, b, n);
	free(b);
	r = dao_source_open(g_plugins, bad, NULL, &s, &err);
	fprintf(stderr, "chunk named twice: %s\n", err.message);
	assert_int_equal(r, -EINVAL);
	assert_non_null(strstr(err.message, "overlaps another one"));

	/* an index entry pointing outside its chunk */
	b = slurp(bag("d16_none.bag"), &n);
	long ix = find(b, n, "op=\x04", 0);
	assert_true(ix > 0);
	/* the index record's data: after its header and data_len, entries of (time, offset) */
	assert_int_equal(b[ix - 4], 4); /* "op" is the header's first field: its length */
	long hdr = ix - 8;              /* the header_len before it */
	uint32_t hlen = (uint32_t)b[hdr] | (uint32_t)b[hdr + 1] << 8;
	long data = hdr + 4 + (long)hlen + 4;
	b[data + 8] = 0xff, b[data + 9] = 0xff, b[data + 10] = 0xff, b[data + 11] = 0x7f;
	spill(bad, b, n);
	free(b);
	r = dao_source_open(g_plugins, bad, NULL, &s, &err);
	fprintf(stderr, "bad index: %s\n", err.message);
	assert_int_equal(r, -EINVAL);
	assert_non_null(strstr(err.message, "points to offset"));
	assert_non_null(strstr(err.message, "byte "));
}

/*
 * A recording that was not finished (no index): its complete chunks are read,
 * with a warning; cut inside a chunk, the chunks before it.
 */
static void test_unindexed(void **state)
{
	(void)state;
	struct dao_source *s = open_bag(bag("unindexed.bag"), NULL);
	struct dao_source_info in;
	struct dao_source_frame f;
	struct dao_error err;
	dao_source_get_info(s, &in);
	fprintf(stderr, "unindexed: %s\n", in.warning);
	assert_non_null(strstr(in.warning, "unindexed.bag is not indexed"));
	assert_int_equal(in.frame_count, 3);
	check_camera(&in);
	for (uint32_t i = 0; i < 3; i++) {
		assert_int_equal(dao_source_read(s, &f, 1000, &err), 0);
		check_d16(&f.depth, i);
		assert_int_equal(f.depth.timestamp_ns, (100 + (uint64_t)i) * 1000000000u + i * 1000000u);
	}
	assert_int_equal(dao_source_read(s, &f, 1000, &err), DAO_SOURCE_EOS);
	assert_int_equal(dao_source_seek(s, 1, &err), 0);
	assert_int_equal(dao_source_read(s, &f, 1000, &err), 0);
	check_d16(&f.depth, 1);
	dao_source_close(s);

	/* cut 100 bytes before its end: inside the last chunk (or its index data) */
	long n;
	unsigned char *b = slurp(bag("unindexed.bag"), &n);
	char cut[700];
	snprintf(cut, sizeof cut, "%s/unindexed-cut.bag", g_dir);
	spill(cut, b, n - 100);
	s = open_bag(cut, NULL);
	dao_source_get_info(s, &in);
	fprintf(stderr, "unindexed, cut: %s\n", in.warning);
	assert_non_null(strstr(in.warning, "up to byte "));
	assert_true(in.frame_count >= 1 && in.frame_count <= 3);
	for (uint32_t i = 0; i < in.frame_count; i++) {
		assert_int_equal(dao_source_read(s, &f, 1000, &err), 0);
		check_d16(&f.depth, i);
	}
	dao_source_close(s);
	/* cut inside the first chunk: nothing to read */
	spill(cut, b, 4200);
	expect_open_error(cut, -EINVAL, "not indexed", "no complete chunk", "byte ", NULL);
	free(b);
	/* the indexed bags say nothing */
	s = open_bag(bag("d16_lz4.bag"), NULL);
	dao_source_get_info(s, &in);
	assert_string_equal(in.warning, "");
	dao_source_close(s);
}

static void test_not_a_bag(void **state)
{
	(void)state;
	char p[700];
	snprintf(p, sizeof p, "%s/text.bag", g_dir);
	spill(p, (const unsigned char *)"#ROSBAG V1.2\nhello", 18);
	expect_open_error(p, -EINVAL, "format 1.2", NULL);
	spill(p, (const unsigned char *)"a shopping bag, not a ROS one", 29);
	expect_open_error(p, -EINVAL, "not a ROS bag", NULL);
	expect_open_error("/nonexistent/x.bag", -ENOENT, "/nonexistent/x.bag", NULL);
}

/* The fuzzer's seed corpus (fuzz/corpus/bag, make_bags.py --seeds) reads without an error. */
static void test_fuzz_corpus(void **state)
{
	(void)state;
	const char *dir = getenv("DAO_BAG_CORPUS");
	assert_non_null(dir);
	DIR *d = opendir(dir);
	assert_non_null(d);
	int files = 0;
	for (struct dirent *e; (e = readdir(d));) {
		size_t n = strlen(e->d_name);
		if (n < 5 || strcmp(e->d_name + n - 4, ".bag"))
			continue;
		char p[1024];
		snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
		struct dao_source *s = open_bag(p, NULL);
		struct dao_source_info in;
		struct dao_source_frame f;
		struct dao_error err;
		dao_source_get_info(s, &in);
		assert_int_equal(in.width, 8);
		assert_int_equal(in.height, 6);
		assert_true(in.has_intrinsics);
		int64_t k = 0;
		for (int r; (r = dao_source_read(s, &f, 1000, &err)) != DAO_SOURCE_EOS; k++) {
			if (r)
				fprintf(stderr, "%s: %s\n", p, err.message);
			assert_int_equal(r, 0);
		}
		assert_int_equal(k, in.frame_count);
		dao_source_close(s);
		files++;
	}
	closedir(d);
	assert_true(files >= 5);
}

/*
 * Files the fuzzer found (tests/bag/regress): each opens or fails with a
 * message, and every frame reads or fails with one (the sanitizer builds
 * catch what a plain build lets pass).
 */
static void test_fuzz_regressions(void **state)
{
	(void)state;
	const char *dir = getenv("DAO_BAG_REGRESS");
	assert_non_null(dir);
	DIR *d = opendir(dir);
	assert_non_null(d);
	int files = 0;
	for (struct dirent *e; (e = readdir(d));) {
		if (e->d_name[0] == '.')
			continue;
		char p[1024];
		snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
		struct dao_source *s = NULL;
		struct dao_error err;
		memset(&err, 0, sizeof err);
		files++;
		if (dao_source_open(g_plugins, p, NULL, &s, &err) < 0) {
			fprintf(stderr, "%s: %s\n", e->d_name, err.message);
			assert_true(err.message[0]);
			continue;
		}
		assert_int_equal(dao_source_start(s, &err), 0);
		struct dao_source_frame f;
		for (int r; (r = dao_source_read(s, &f, 1000, &err)) != DAO_SOURCE_EOS;)
			if (r < 0)
				assert_true(err.message[0]);
		dao_source_close(s);
	}
	closedir(d);
	assert_true(files >= 1);
}

int main(void)
{
	const char *script = getenv("DAO_MAKE_BAGS");
	struct dao_error err;
	char cmd[1200];
	if (!script) {
		fprintf(stderr, "DAO_MAKE_BAGS (make_bags.py) is not set\n");
		return 1;
	}
	snprintf(g_dir, sizeof g_dir, "%s", dao_test_tmpdir("source-bag"));
	snprintf(cmd, sizeof cmd, "/usr/bin/python3 '%s' '%s'", script, g_dir);
	int st = system(cmd);
	if (st == -1 || !WIFEXITED(st))
		return 1;
	if (WEXITSTATUS(st) == 77)
		return 77; /* python3-rosbag is not installed: the script said so */
	if (WEXITSTATUS(st) != 0)
		return 1;
	/* the bags' directory as the module path: no modules there, the built-ins only */
	if (dao_plugins_load(&g_plugins, g_dir, &err) < 0)
		return 1;
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_uncompressed),
		cmocka_unit_test(test_bz2),
		cmocka_unit_test(test_lz4),
		cmocka_unit_test(test_prefix_and_options),
		cmocka_unit_test(test_float_big_endian),
		cmocka_unit_test(test_realtime),
		cmocka_unit_test(test_two_topics),
		cmocka_unit_test(test_realsense),
		cmocka_unit_test(test_distorted),
		cmocka_unit_test(test_pixel_limit),
		cmocka_unit_test(test_truncated),
		cmocka_unit_test(test_corrupt_chunk),
		cmocka_unit_test(test_unindexed),
		cmocka_unit_test(test_not_a_bag),
		cmocka_unit_test(test_implausible_camera_info),
		cmocka_unit_test(test_fuzz_corpus),
		cmocka_unit_test(test_fuzz_regressions),
	};
	int r = cmocka_run_group_tests(tests, NULL, NULL);
	dao_plugins_free(g_plugins);
	return r;
}
