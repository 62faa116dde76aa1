/* SPDX-License-Identifier: MIT */
/*
 * .oni recordings: the real Kinect recording from ../shared/data (run as
 * `test-oni-file kinect`, SKIP when absent), writer/reader round trips for
 * every codec and pixel format, writer rules, and bad input of every kind
 * (missing, empty, wrong magic or version, truncated, oversized or corrupt
 * frames), plus the fuzzer reproducers in tests/oni/regress/ and the fuzz
 * corpus.  Temporary files live in a fresh mkdtemp directory under /tmp.
 */
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "common/cmocka_all.h"
#include "common/test_common.h"

#include <depthao/frame.h>
#include <depthao/oni.h>

#define PLEN 700

/* Record types and sizes of the NI10 format, spelled out here independently of src/io/oni. */
#define REC_NEW_DATA 0x0Au
#define REC_END 0x0Bu
#define REC_NODE_ADDED 0x0Du
#define FILE_HEADER 24
#define REC_HEADER 28

static char dir[PLEN];

static uint64_t rng_state = 0x243F6A8885A308D3ull;

static uint32_t rnd(void)
{
	rng_state ^= rng_state >> 12;
	rng_state ^= rng_state << 25;
	rng_state ^= rng_state >> 27;
	return (uint32_t)((rng_state * 0x2545F4914F6CDD1Dull) >> 32);
}

/* snprintf into a PLEN buffer that fails the test instead of truncating. */
static void fmt(char *buf, const char *f, ...) __attribute__((format(printf, 2, 3)));
static void fmt(char *buf, const char *f, ...)
{
	va_list ap;
	va_start(ap, f);
	int n = vsnprintf(buf, PLEN, f, ap);
	va_end(ap);
	if (n < 0 || n >= PLEN)
		fail_msg("path too long: %s", buf);
}

static void pathof(char *buf, const char *name)
{
	fmt(buf, "%s/%s", dir, name);
}

/* A fresh empty directory inside the test directory. */
static void fresh_subdir(char *buf, const char *tag)
{
	fmt(buf, "%s/%s-XXXXXX", dir, tag);
	assert_non_null(mkdtemp(buf));
}

static int count_entries(const char *d)
{
	DIR *dp = opendir(d);
	assert_non_null(dp);
	int n = 0;
	struct dirent *e;
	while ((e = readdir(dp)))
		if (strcmp(e->d_name, ".") && strcmp(e->d_name, ".."))
			n++;
	closedir(dp);
	return n;
}

static void expect_message(const struct dao_error *err, const char *needle, const char *ctx)
{
	if (!strstr(err->message, needle))
		fail_msg("%s: message '%s' lacks '%s'", ctx, err->message, needle);
}

/* --- file bytes -------------------------------------------------------- */

struct bytes {
	uint8_t *p;
	size_t n;
};

static struct bytes load(const char *path)
{
	struct bytes b = {NULL, 0};
	FILE *f = fopen(path, "rb");
	assert_non_null(f);
	assert_int_equal(fseek(f, 0, SEEK_END), 0);
	long n = ftell(f);
	assert_true(n >= 0);
	rewind(f);
	b.n = (size_t)n;
	b.p = malloc(b.n ? b.n : 1);
	assert_non_null(b.p);
	assert_int_equal(fread(b.p, 1, b.n, f), b.n);
	fclose(f);
	return b;
}

static void save(const char *path, const void *p, size_t n)
{
	FILE *f = fopen(path, "wb");
	assert_non_null(f);
	if (n)
		assert_int_equal(fwrite(p, 1, n, f), n);
	assert_int_equal(fclose(f), 0);
}

static uint32_t rd32(const uint8_t *p)
{
	return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) |
	       ((uint32_t)p[3] << 24);
}

static void wr32(uint8_t *p, uint32_t v)
{
	for (int i = 0; i < 4; i++)
		p[i] = (uint8_t)(v >> (8 * i));
}

/* Offset of the nth (0-based) record of `type` in a 1.0.1.0 file, or 0. */
static size_t find_record(const struct bytes *b, uint32_t type, int nth)
{
	size_t pos = FILE_HEADER;
	while (pos + REC_HEADER <= b->n) {
		uint32_t t = rd32(b->p + pos + 4);
		if (t == type && nth-- == 0)
			return pos;
		if (t == REC_END)
			break;
		pos += (size_t)rd32(b->p + pos + 12) + rd32(b->p + pos + 16);
	}
	return 0;
}

/* --- synthetic recordings ---------------------------------------------- */

#define SW 37
#define SH 23
#define NF 4

static struct dao_oni_writer_options default_options(enum dao_oni_codec codec, int pf)
{
	struct dao_oni_writer_options o = DAO_ONI_WRITER_OPTIONS_INIT;
	o.width = SW;
	o.height = SH;
	o.fps = 30;
	o.codec = codec;
	o.pixel_format = pf;
	o.max_depth = 0;
	o.hfov = 1.0123456789012345;
	o.vfov = 0.7654321098765432;
	o.mirrored = 1;
	o.overwrite = 1; /* the tests write the same names again */
	return o;
}

/* Largest count a recording with these options accepts. */
static uint16_t max_count(const struct dao_oni_writer_options *o)
{
	uint32_t m = o->max_depth ? o->max_depth
				  : o->pixel_format == DAO_ONI_PIXEL_DEPTH_1_MM ? 10000 : 65535;
	if (o->codec == DAO_ONI_CODEC_16Z && m > 32767)
		m = 32767;
	return (uint16_t)m;
}

/* Frame k: holes, ramps, random pixels, both extremes. */
static void gen_frame(uint16_t *px, uint32_t w, uint32_t h, int k, uint16_t maxv)
{
	for (uint32_t y = 0; y < h; y++) {
		for (uint32_t x = 0; x < w; x++) {
			uint32_t i = y * w + x, v;
			if ((x + 3 * y + (uint32_t)k) % 7 == 0)
				v = 0;
			else if (y % 5 == 4)
				v = rnd() % ((uint32_t)maxv + 1);
			else
				v = 600 + 13 * x + 29 * y + 101 * (uint32_t)k;
			if (v > maxv)
				v = maxv;
			px[i] = (uint16_t)v;
		}
	}
	px[0] = maxv;
	px[1] = (uint16_t)(maxv - 1);
	px[w * h - 1] = 1;
}

static const uint64_t frame_ts[NF] = {1000, 34333, 34333, 100000};

/* Writes `n` packed frames through a padded (strided) input frame. */
static void write_frames(const char *path, const struct dao_oni_writer_options *o,
			 uint16_t *const *frames, const uint64_t *ts, int n, float unit)
{
	struct dao_oni_writer *w = NULL;
	struct dao_error err = {0};
	int r = dao_oni_writer_open(path, o, &w, &err);
	if (r)
		fail_msg("writer_open %s: %d %s", path, r, err.message);
	/* an odd stride: rows are unaligned, which frames allow (the sanitizer run checks) */
	int32_t stride = (int32_t)((o->width + 3) * 2 + 1);
	uint8_t *buf = malloc((size_t)stride * o->height);
	assert_non_null(buf);
	memset(buf, 0xEE, (size_t)stride * o->height); /* padding a reader must not see */
	for (int k = 0; k < n; k++) {
		for (uint32_t y = 0; y < o->height; y++)
			memcpy(buf + (size_t)y * (size_t)stride, frames[k] + (size_t)y * o->width,
			       o->width * 2);
		struct dao_frame f = {.format = DAO_PIXFMT_DEPTH16, .width = o->width,
				.height = o->height, .stride = stride, .data = buf,
				.depth_unit = unit};
		r = dao_oni_writer_write_depth(w, &f, ts[k], &err);
		if (r)
			fail_msg("write_depth frame %d: %d %s", k, r, err.message);
	}
	free(buf);
	r = dao_oni_writer_finish(w, &err);
	if (r)
		fail_msg("writer_finish: %d %s", r, err.message);
}

static struct dao_frame new_depth(uint32_t w, uint32_t h)
{
	struct dao_frame f;
	assert_int_equal(dao_frame_alloc(&f, DAO_PIXFMT_DEPTH16, w, h, NULL), 0);
	return f;
}

static void assert_frame_equals(const struct dao_frame *f, const uint16_t *want, const char *ctx)
{
	for (uint32_t y = 0; y < f->height; y++) {
		const uint16_t *row = (const uint16_t *)((const uint8_t *)f->data +
							 (size_t)y * (size_t)f->stride);
		for (uint32_t x = 0; x < f->width; x++)
			if (row[x] != want[(size_t)y * f->width + x])
				fail_msg("%s: pixel (%u, %u) is %u, expected %u", ctx, x, y, row[x],
					 want[(size_t)y * f->width + x]);
	}
}

/* A small valid recording (SW x SH, NF frames, 1 mm) of the given codec; the frames go to `frames`. */
static void make_small(const char *path, enum dao_oni_codec codec, uint16_t **frames)
{
	struct dao_oni_writer_options o = default_options(codec, DAO_ONI_PIXEL_DEPTH_1_MM);
	for (int k = 0; k < NF; k++) {
		frames[k] = malloc(SW * SH * sizeof(uint16_t));
		assert_non_null(frames[k]);
		gen_frame(frames[k], SW, SH, k, max_count(&o));
	}
	write_frames(path, &o, frames, frame_ts, NF, 0.001f);
}

static void free_frames(uint16_t **frames)
{
	for (int k = 0; k < NF; k++)
		free(frames[k]);
}

static void expect_open_error(const char *path, int code, const char *needle, const char *ctx)
{
	static char dummy;
	struct dao_oni_reader *r = (struct dao_oni_reader *)(void *)&dummy; /* must be reset */
	struct dao_error err = {0};
	int ret = dao_oni_reader_open(path, &r, &err);
	if (ret != code)
		fail_msg("%s: open returned %d (%s), expected %d", ctx, ret, err.message, code);
	assert_null(r);
	assert_int_equal(err.code, code);
	expect_message(&err, needle, ctx);
}

/*
 * `path` opens with `n` frames equal to frames[0..n) and, when `needle` is
 * not NULL, a warning that names the file and contains `needle` (NULL: a
 * finished file, no warning).
 */
static void expect_recovered(const char *path, uint16_t *const *frames, uint32_t n,
			     const char *needle, const char *ctx)
{
	struct dao_oni_reader *r = NULL;
	struct dao_error err = {0};
	int ret = dao_oni_reader_open(path, &r, &err);
	if (ret != 0)
		fail_msg("%s: open returned %d (%s), expected %u recovered frames", ctx, ret,
			 err.message, n);
	const char *w = dao_oni_reader_warning(r);
	if (needle && (!w || !strstr(w, needle) || !strstr(w, path)))
		fail_msg("%s: warning '%s' lacks '%s' or the path", ctx, w ? w : "(none)", needle);
	if (!needle && w)
		fail_msg("%s: unexpected warning '%s'", ctx, w);
	const struct dao_oni_stream_info *in = dao_oni_reader_stream(r, 0);
	if (!in || in->frame_count != n)
		fail_msg("%s: %u frames, expected %u", ctx, in ? in->frame_count : 0, n);
	struct dao_frame f = new_depth(in->width, in->height);
	for (uint32_t k = 0; k < n; k++) {
		if (dao_oni_reader_read_depth(r, 0, k, &f, &err) != 0)
			fail_msg("%s: frame %u: %s", ctx, k, err.message);
		assert_frame_equals(&f, frames[k], ctx);
		assert_int_equal(f.sequence, k + 1);
	}
	dao_frame_free(&f);
	dao_oni_reader_close(r);
}

/* --- (b) writer and reader round trips ------------------------------------ */

static void test_round_trips(void **state)
{
	(void)state;
	static const enum dao_oni_codec codecs[] = {DAO_ONI_CODEC_NONE, DAO_ONI_CODEC_16Z,
						    DAO_ONI_CODEC_16ZT};
	static const char *fourcc[] = {"NONE", "16zP", "16zT"};
	static const int pfs[] = {DAO_ONI_PIXEL_DEPTH_1_MM, DAO_ONI_PIXEL_DEPTH_100_UM};
	for (int c = 0; c < 3; c++) {
		for (int p = 0; p < 2; p++) {
			char ctx[64], path[PLEN];
			snprintf(ctx, sizeof(ctx), "%s pixel format %d", fourcc[c], pfs[p]);
			pathof(path, "rt.oni");
			struct dao_oni_writer_options o = default_options(codecs[c], pfs[p]);
			o.mirrored = p; /* both ways */
			o.fps = p ? 15 : 30;
			if (c == 1 && p == 0)
				o.max_depth = 8000; /* an explicit maximum is recorded as given */
			const float unit = pfs[p] == DAO_ONI_PIXEL_DEPTH_1_MM ? 0.001f : 0.0001f;
			uint16_t *frames[NF];
			for (int k = 0; k < NF; k++) {
				frames[k] = malloc(SW * SH * sizeof(uint16_t));
				assert_non_null(frames[k]);
				gen_frame(frames[k], SW, SH, k, max_count(&o));
			}
			write_frames(path, &o, frames, frame_ts, NF, unit);

			struct dao_oni_reader *r = NULL;
			struct dao_error err = {0};
			if (dao_oni_reader_open(path, &r, &err))
				fail_msg("%s: open: %s", ctx, err.message);
			assert_int_equal(dao_oni_reader_stream_count(r), 1);
			assert_int_equal(dao_oni_reader_depth_stream(r, &err), 0);
			assert_null(dao_oni_reader_stream(r, 1));
			const struct dao_oni_stream_info *s = dao_oni_reader_stream(r, 0);
			assert_non_null(s);
			assert_string_equal(s->name, "Depth1");
			assert_int_equal(s->sensor, DAO_ONI_SENSOR_DEPTH);
			assert_int_equal(s->codec, codecs[c]);
			assert_string_equal(s->codec_fourcc, fourcc[c]);
			assert_int_equal(s->width, SW);
			assert_int_equal(s->height, SH);
			assert_int_equal(s->fps, o.fps);
			assert_int_equal(s->frame_count, NF);
			assert_int_equal(s->pixel_format, pfs[p]);
			assert_true(s->depth_unit == unit);
			assert_int_equal(s->max_depth, o.max_depth ? o.max_depth
						       : pfs[p] == DAO_ONI_PIXEL_DEPTH_1_MM ? 10000 : 65535);
			assert_int_equal(s->has_fov, 1);
			assert_true(s->hfov == o.hfov); /* stored as doubles: exact */
			assert_true(s->vfov == o.vfov);
			assert_int_equal(s->mirrored, o.mirrored);
			assert_int_equal(s->registered, 0);
			assert_int_equal(s->first_timestamp_us, frame_ts[0]);
			assert_int_equal(s->last_timestamp_us, frame_ts[NF - 1]);

			struct dao_frame f = new_depth(SW, SH);
			/* backwards, so reading does not rely on order */
			for (int k = NF - 1; k >= 0; k--) {
				f.depth_unit = 0;
				f.timestamp_ns = 0;
				f.sequence = 0;
				if (dao_oni_reader_read_depth(r, 0, (uint32_t)k, &f, &err))
					fail_msg("%s: frame %d: %s", ctx, k, err.message);
				assert_frame_equals(&f, frames[k], ctx);
				assert_int_equal(f.timestamp_ns, frame_ts[k] * 1000);
				assert_int_equal(f.sequence, (uint64_t)k + 1);
				assert_true(f.depth_unit == unit);
			}
			/* past the end */
			assert_int_equal(dao_oni_reader_read_depth(r, 0, NF, &f, &err), -EINVAL);
			expect_message(&err, "past the end", ctx);
			/* no such stream */
			assert_int_equal(dao_oni_reader_read_depth(r, 1, 0, &f, &err), -EINVAL);
			dao_frame_free(&f);
			/* a frame of the wrong size or format */
			struct dao_frame g = new_depth(SW + 1, SH);
			assert_int_equal(dao_oni_reader_read_depth(r, 0, 0, &g, &err), -EINVAL);
			dao_frame_free(&g);
			assert_int_equal(dao_frame_alloc(&g, DAO_PIXFMT_DEPTH_F32, SW, SH, NULL), 0);
			assert_int_equal(dao_oni_reader_read_depth(r, 0, 0, &g, &err), -EINVAL);
			expect_message(&err, "depth16", ctx);
			dao_frame_free(&g);
			dao_oni_reader_close(r);
			free_frames(frames);
			assert_int_equal(unlink(path), 0);
			assert_int_equal(count_entries(dir), 0); /* no temporary left behind */
		}
	}
}

/* Files written in the old 32-bit layout (before 1.0.1.0: 24-byte record headers) read the same. */
static void test_old_layout(void **state)
{
	(void)state;
	char path[PLEN], old[PLEN];
	pathof(path, "new.oni");
	pathof(old, "old.oni");
	uint16_t *frames[NF];
	make_small(path, DAO_ONI_CODEC_16Z, frames);
	struct bytes b = load(path);
	uint8_t *o = malloc(b.n);
	assert_non_null(o);
	memcpy(o, b.p, FILE_HEADER);
	o[4] = 1, o[5] = 0, o[6] = 0, o[7] = 0; /* version 1.0.0.5 */
	wr32(o + 8, 5);
	size_t in = FILE_HEADER, out = FILE_HEADER;
	int ended = 0;
	while (!ended) {
		assert_true(in + REC_HEADER <= b.n);
		uint32_t fs = rd32(b.p + in + 12), ps = rd32(b.p + in + 16);
		ended = rd32(b.p + in + 4) == REC_END;
		memcpy(o + out, b.p + in, 20);
		wr32(o + out + 12, fs - 4);
		memcpy(o + out + 20, b.p + in + 20, 4); /* low half of the undo position */
		memcpy(o + out + 24, b.p + in + REC_HEADER, fs - REC_HEADER + ps);
		in += fs + ps;
		out += fs - 4 + ps;
	}
	assert_int_equal(in, b.n);
	save(old, o, out);
	struct dao_oni_reader *r = NULL;
	struct dao_error err = {0};
	if (dao_oni_reader_open(old, &r, &err))
		fail_msg("old layout: %s", err.message);
	const struct dao_oni_stream_info *s = dao_oni_reader_stream(r, 0);
	assert_int_equal(s->frame_count, NF);
	assert_int_equal(s->width, SW);
	struct dao_frame f = new_depth(SW, SH);
	for (int k = 0; k < NF; k++) {
		assert_int_equal(dao_oni_reader_read_depth(r, 0, (uint32_t)k, &f, &err), 0);
		assert_frame_equals(&f, frames[k], "old layout");
		assert_int_equal(f.sequence, (uint64_t)k + 1);
	}
	dao_frame_free(&f);
	dao_oni_reader_close(r);
	free(o);
	free(b.p);
	free_frames(frames);
	unlink(path);
	unlink(old);
}

static void test_unit_conversion(void **state)
{
	(void)state;
	char path[PLEN];
	pathof(path, "units.oni");
	struct dao_error err = {0};
	struct dao_oni_reader *r;
	struct dao_frame out = new_depth(4, 1);

	/* 100 um counts into a 1 mm file */
	struct dao_oni_writer_options o = default_options(DAO_ONI_CODEC_16Z, DAO_ONI_PIXEL_DEPTH_1_MM);
	o.width = 4, o.height = 1;
	struct dao_oni_writer *w;
	assert_int_equal(dao_oni_writer_open(path, &o, &w, &err), 0);
	uint16_t um[4] = {12340, 0, 12346, 12344};
	struct dao_frame f = {.format = DAO_PIXFMT_DEPTH16, .width = 4, .height = 1, .stride = 8,
			.data = um, .depth_unit = 0.0001f};
	assert_int_equal(dao_oni_writer_write_depth(w, &f, 10, &err), 0);
	/* 2 mm counts */
	uint16_t mm2[4] = {100, 0, 4999, 5000};
	struct dao_frame g = {.format = DAO_PIXFMT_DEPTH16, .width = 4, .height = 1, .stride = 8,
			.data = mm2, .depth_unit = 0.002f};
	assert_int_equal(dao_oni_writer_write_depth(w, &g, 20, &err), 0);
	/* 5001 * 2 mm is above the default 10 m */
	mm2[3] = 5001;
	assert_int_equal(dao_oni_writer_write_depth(w, &g, 30, &err), -ERANGE);
	expect_message(&err, "max depth", "converted count above max_depth");
	/* a frame without a unit */
	g.depth_unit = 0;
	assert_int_equal(dao_oni_writer_write_depth(w, &g, 30, &err), -EINVAL);
	expect_message(&err, "unit", "frame without unit");
	assert_int_equal(dao_oni_writer_finish(w, &err), 0);

	assert_int_equal(dao_oni_reader_open(path, &r, &err), 0);
	assert_int_equal(dao_oni_reader_stream(r, 0)->frame_count, 2); /* failed writes left no frame */
	assert_int_equal(dao_oni_reader_read_depth(r, 0, 0, &out, &err), 0);
	const uint16_t *px = out.data;
	assert_int_equal(px[0], 1234);
	assert_int_equal(px[1], 0);
	assert_int_equal(px[2], 1235);
	assert_int_equal(px[3], 1234);
	assert_int_equal(dao_oni_reader_read_depth(r, 0, 1, &out, &err), 0);
	assert_int_equal(px[0], 200);
	assert_int_equal(px[1], 0);
	assert_int_equal(px[2], 9998);
	assert_int_equal(px[3], 10000);
	dao_oni_reader_close(r);

	/* 1 mm counts into a 100 um file */
	o = default_options(DAO_ONI_CODEC_NONE, DAO_ONI_PIXEL_DEPTH_100_UM);
	o.width = 4, o.height = 1;
	assert_int_equal(dao_oni_writer_open(path, &o, &w, &err), 0);
	uint16_t mm[4] = {1234, 0, 6553, 1};
	struct dao_frame h = {.format = DAO_PIXFMT_DEPTH16, .width = 4, .height = 1, .stride = 8,
			.data = mm, .depth_unit = 0.001f};
	assert_int_equal(dao_oni_writer_write_depth(w, &h, 0, &err), 0);
	mm[3] = 6554; /* 65540 counts of 100 um */
	assert_int_equal(dao_oni_writer_write_depth(w, &h, 1, &err), -ERANGE);
	assert_int_equal(dao_oni_writer_finish(w, &err), 0);
	assert_int_equal(dao_oni_reader_open(path, &r, &err), 0);
	assert_int_equal(dao_oni_reader_stream(r, 0)->frame_count, 1);
	assert_int_equal(dao_oni_reader_read_depth(r, 0, 0, &out, &err), 0);
	assert_int_equal(px[0], 12340);
	assert_int_equal(px[1], 0);
	assert_int_equal(px[2], 65530);
	assert_int_equal(px[3], 10);
	assert_true(out.depth_unit == 0.0001f);
	dao_oni_reader_close(r);
	dao_frame_free(&out);
	unlink(path);
}

static void test_writer_rules(void **state)
{
	(void)state;
	char sub[PLEN], path[PLEN];
	struct dao_error err = {0};
	struct dao_oni_writer *w;
	uint16_t px[SW * SH];
	struct dao_frame f = {.format = DAO_PIXFMT_DEPTH16, .width = SW, .height = SH,
			.stride = SW * 2, .data = px, .depth_unit = 0.001f};

	/* -ERANGE above max_depth; the limit itself is fine */
	fresh_subdir(sub, "range");
	fmt(path, "%s/r.oni", sub);
	struct dao_oni_writer_options o = default_options(DAO_ONI_CODEC_NONE, DAO_ONI_PIXEL_DEPTH_1_MM);
	o.max_depth = 5000;
	assert_int_equal(dao_oni_writer_open(path, &o, &w, &err), 0);
	for (size_t i = 0; i < SW * SH; i++)
		px[i] = (uint16_t)(i % 5001);
	assert_int_equal(dao_oni_writer_write_depth(w, &f, 0, &err), 0);
	px[SW * 3 + 5] = 5001;
	assert_int_equal(dao_oni_writer_write_depth(w, &f, 1, &err), -ERANGE);
	expect_message(&err, "max depth", "count above max_depth");
	px[SW * 3 + 5] = 0;
	/* timestamps must not go backwards (equal is fine) */
	assert_int_equal(dao_oni_writer_write_depth(w, &f, 0, &err), 0);
	assert_int_equal(dao_oni_writer_write_depth(w, &f, 500, &err), 0);
	err.message[0] = 0;
	assert_int_equal(dao_oni_writer_write_depth(w, &f, 499, &err), -EINVAL);
	expect_message(&err, "goes back", "timestamp backwards");
	/* wrong size and format */
	struct dao_frame bad = f;
	bad.width = SW - 1;
	assert_int_equal(dao_oni_writer_write_depth(w, &bad, 600, &err), -EINVAL);
	bad = f;
	bad.format = DAO_PIXFMT_GRAY16;
	assert_int_equal(dao_oni_writer_write_depth(w, &bad, 600, &err), -EINVAL);
	expect_message(&err, "depth16", "gray16 frame");
	assert_int_equal(dao_oni_writer_write_depth(w, NULL, 600, &err), -EINVAL);
	assert_int_equal(dao_oni_writer_finish(w, &err), 0);
	struct dao_oni_reader *r;
	assert_int_equal(dao_oni_reader_open(path, &r, &err), 0);
	assert_int_equal(dao_oni_reader_stream(r, 0)->frame_count, 3);
	assert_int_equal(dao_oni_reader_stream(r, 0)->max_depth, 5000);
	assert_int_equal(dao_oni_reader_stream(r, 0)->last_timestamp_us, 500);
	dao_oni_reader_close(r);
	unlink(path);
	assert_int_equal(count_entries(sub), 0);

	/* the codecs' own limits: 16z holds counts below 32768 */
	for (size_t i = 0; i < SW * SH; i++)
		px[i] = 32767;
	o = default_options(DAO_ONI_CODEC_16Z, DAO_ONI_PIXEL_DEPTH_100_UM);
	assert_int_equal(dao_oni_writer_open(path, &o, &w, &err), 0);
	f.depth_unit = 0.0001f;
	assert_int_equal(dao_oni_writer_write_depth(w, &f, 0, &err), 0);
	px[7] = 32768;
	assert_int_equal(dao_oni_writer_write_depth(w, &f, 1, &err), -ERANGE);
	expect_message(&err, "16z", "16z value >= 32768");
	dao_oni_writer_abort(w); /* the first frame stays, unfinished */
	assert_int_equal(count_entries(sub), 1);
	unlink(path);

	{
		/* 16zT: more than 32768 distinct values in one frame */
		enum { TW = 256, TH = 129 };
		uint16_t *t = malloc(TW * TH * sizeof(*t));
		assert_non_null(t);
		for (size_t i = 0; i < TW * TH; i++)
			t[i] = (uint16_t)i;
		struct dao_frame tf = {.format = DAO_PIXFMT_DEPTH16, .width = TW, .height = TH,
				.stride = TW * 2, .data = t, .depth_unit = 0.0001f};
		o = default_options(DAO_ONI_CODEC_16ZT, DAO_ONI_PIXEL_DEPTH_100_UM);
		o.width = TW, o.height = TH;
		assert_int_equal(dao_oni_writer_open(path, &o, &w, &err), 0);
		assert_int_equal(dao_oni_writer_write_depth(w, &tf, 0, &err), -ERANGE);
		expect_message(&err, "16zt", "16zT too many distinct values");
		for (size_t i = 32768; i < TW * TH; i++)
			t[i] = 0; /* now exactly 32768 */
		assert_int_equal(dao_oni_writer_write_depth(w, &tf, 0, &err), 0);
		assert_int_equal(dao_oni_writer_finish(w, &err), 0);
		assert_int_equal(dao_oni_reader_open(path, &r, &err), 0);
		struct dao_frame back = new_depth(TW, TH);
		assert_int_equal(dao_oni_reader_read_depth(r, 0, 0, &back, &err), 0);
		assert_memory_equal(back.data, t, TW * TH * sizeof(*t));
		dao_frame_free(&back);
		dao_oni_reader_close(r);
		unlink(path);
		free(t);
	}

	/* finishing without frames is an error and leaves nothing */
	o = default_options(DAO_ONI_CODEC_16ZT, DAO_ONI_PIXEL_DEPTH_1_MM);
	assert_int_equal(dao_oni_writer_open(path, &o, &w, &err), 0);
	assert_int_equal(count_entries(sub), 1); /* the file itself, from the start */
	err.message[0] = 0;
	assert_int_equal(dao_oni_writer_finish(w, &err), -EINVAL);
	expect_message(&err, "no frames", "finish without frames");
	assert_int_equal(count_entries(sub), 0);
	assert_int_equal(access(path, F_OK), -1);
	/* nor does an abort without frames */
	assert_int_equal(dao_oni_writer_open(path, &o, &w, &err), 0);
	dao_oni_writer_abort(w);
	assert_int_equal(count_entries(sub), 0);
	dao_oni_writer_abort(NULL);

	/* abort after some frames keeps them: an unfinished file, recovered */
	assert_int_equal(dao_oni_writer_open(path, &o, &w, &err), 0);
	f.depth_unit = 0.001f;
	for (size_t i = 0; i < SW * SH; i++)
		px[i] = (uint16_t)(1000 + i);
	assert_int_equal(dao_oni_writer_write_depth(w, &f, 0, &err), 0);
	assert_int_equal(dao_oni_writer_write_depth(w, &f, 33, &err), 0);
	dao_oni_writer_abort(w);
	{
		uint16_t *same[2] = {px, px};
		expect_recovered(path, same, 2, "not finalised", "aborted recording");
	}

	/* the file is at its name while it grows; an existing file is never replaced
	 * unless asked (overwrite), and nothing is touched when it is not */
	o.overwrite = 0;
	struct dao_oni_writer *w2 = NULL;
	struct stat st0, st1;
	assert_int_equal(stat(path, &st0), 0);
	err.message[0] = 0;
	assert_int_equal(dao_oni_writer_open(path, &o, &w2, &err), -EEXIST);
	assert_null(w2);
	expect_message(&err, path, "existing file");
	expect_message(&err, "exists", "existing file");
	assert_int_equal(stat(path, &st1), 0);
	assert_int_equal(st1.st_size, st0.st_size);
	o.overwrite = 1;
	assert_int_equal(dao_oni_writer_open(path, &o, &w, &err), 0);
	assert_int_equal(dao_oni_writer_write_depth(w, &f, 0, &err), 0);
	assert_int_equal(access(path, F_OK), 0);
	assert_int_equal(count_entries(sub), 1);
	assert_int_equal(dao_oni_writer_finish(w, &err), 0);
	assert_int_equal(access(path, F_OK), 0);
	/* only regular files: a directory, a FIFO */
	char other[PLEN];
	fmt(other, "%s/d.oni", sub);
	assert_int_equal(mkdir(other, 0700), 0);
	assert_int_equal(dao_oni_writer_open(other, &o, &w2, &err), -EISDIR);
	assert_null(w2);
	expect_message(&err, "directory", "a directory");
	rmdir(other);
	assert_int_equal(mkfifo(other, 0600), 0);
	assert_int_equal(dao_oni_writer_open(other, &o, &w2, &err), -EINVAL);
	assert_null(w2);
	expect_message(&err, "not a regular file", "a FIFO");
	unlink(other);
	assert_int_equal(count_entries(sub), 1);
	unlink(path);

	/* bad options */
	static const struct {
		int field;
		const char *word;
	} bads[] = {{0, "size"}, {1, "size"}, {2, "fps"},  {3, "fps"},       {4, "codec"},
		    {5, "codec"}, {6, "pixel format"}, {7, "field of view"}, {8, "field of view"},
		    {9, "max_depth"}};
	for (size_t i = 0; i < sizeof(bads) / sizeof(bads[0]); i++) {
		o = default_options(DAO_ONI_CODEC_16Z, DAO_ONI_PIXEL_DEPTH_1_MM);
		switch (bads[i].field) {
		case 0: o.width = 0; break;
		case 1: o.height = DAO_MAX_DIMENSION + 1; break;
		case 2: o.fps = 0; break;
		case 3: o.fps = 1001; break;
		case 4: o.codec = DAO_ONI_CODEC_JPEG; break;
		case 5: o.codec = DAO_ONI_CODEC_8Z; break;
		case 6: o.pixel_format = 102; break;
		case 7: o.hfov = 0; break;
		case 8: o.vfov = 3.2; break;
		default: o.max_depth = 70000; break;
		}
		static char dummy;
		w = (struct dao_oni_writer *)(void *)&dummy; /* must be reset to NULL */
		err.message[0] = 0;
		assert_int_equal(dao_oni_writer_open(path, &o, &w, &err), -EINVAL);
		assert_null(w);
		expect_message(&err, bads[i].word, "bad writer option");
	}
	assert_int_equal(count_entries(sub), 0);
	/* a directory that does not exist */
	fmt(path, "%s/no/such/dir/x.oni", sub);
	o = default_options(DAO_ONI_CODEC_16Z, DAO_ONI_PIXEL_DEPTH_1_MM);
	assert_int_equal(dao_oni_writer_open(path, &o, &w, &err), -ENOENT);
	expect_message(&err, "x.oni", "missing directory");
	assert_int_equal(count_entries(sub), 0);
	rmdir(sub);
}

/* Frame count of the node record and of the data-begin record, and the file's max timestamp. */
static void header_counts(const char *path, uint32_t *node, uint32_t *data_begin, uint64_t *max_ts)
{
	struct bytes b = load(path);
	size_t f = FILE_HEADER + REC_HEADER;
	assert_true(b.n > f + 4);
	size_t counts = f + 4 + rd32(b.p + f) + 8; /* name, then node type and codec */
	*node = rd32(b.p + counts);
	size_t db = find_record(&b, 0x08, 0); /* NODE_DATA_BEGIN: u32 frames, u64 max ts */
	assert_true(db > 0);
	*data_begin = rd32(b.p + db + REC_HEADER);
	*max_ts = (uint64_t)rd32(b.p + 12) | ((uint64_t)rd32(b.p + 16) << 32);
	free(b.p);
}

/*
 * A write that fails (the file size limit here, -EFBIG; a full disk is the
 * same path with -ENOSPC) ends the recording; the frames before it stay and
 * are finalised by finish, or, when not even the end record fits, stay in an
 * unfinished file whose header counts them all.
 */
static void test_write_failure(void **state)
{
	(void)state;
	char sub[PLEN], path[PLEN + 16];
	fresh_subdir(sub, "full");
	snprintf(path, sizeof path, "%s/x.oni", sub);
	struct dao_oni_writer_options o = DAO_ONI_WRITER_OPTIONS_INIT;
	o.width = o.height = 200;
	o.fps = 30;
	o.codec = DAO_ONI_CODEC_NONE;
	o.pixel_format = DAO_ONI_PIXEL_DEPTH_1_MM;
	o.hfov = 1.0;
	o.vfov = 0.8;
	uint16_t *want[1] = {malloc(200 * 200 * 2)};
	assert_non_null(want[0]);
	for (int i = 0; i < 200 * 200; i++)
		want[0][i] = (uint16_t)(500 + i % 3000);
	struct dao_frame f = {.format = DAO_PIXFMT_DEPTH16, .width = 200, .height = 200,
			.stride = 400, .data = want[0], .depth_unit = 0.001f};
	struct rlimit old, lim;
	assert_int_equal(getrlimit(RLIMIT_FSIZE, &old), 0);
	void (*prev)(int) = signal(SIGXFSZ, SIG_IGN);
	/* room after the first frame: none, less than an end record, enough for the tail */
	static const uint64_t room[] = {20, 60, 20000};
	for (int i = 0; i < 3; i++) {
		struct dao_oni_writer *w;
		struct dao_error err = {0};
		struct dao_oni_writer_status st;
		unlink(path);
		assert_int_equal(dao_oni_writer_open(path, &o, &w, &err), 0);
		int r0 = dao_oni_writer_write_depth(w, &f, 0, &err);
		dao_oni_writer_get_status(w, &st);
		lim.rlim_cur = st.bytes + room[i];
		lim.rlim_max = old.rlim_max;
		assert_int_equal(setrlimit(RLIMIT_FSIZE, &lim), 0);
		int r1 = dao_oni_writer_write_depth(w, &f, 1, &err);
		struct dao_error err1 = err;
		int r2 = dao_oni_writer_write_depth(w, &f, 2, &err);
		struct dao_error err2 = err;
		struct dao_oni_writer_status st2;
		dao_oni_writer_get_status(w, &st2);
		err.message[0] = 0;
		int r3 = dao_oni_writer_finish(w, &err);
		assert_int_equal(setrlimit(RLIMIT_FSIZE, &old), 0);
		assert_int_equal(r0, 0);
		assert_int_equal(r1, -EFBIG);
		expect_message(&err1, "cannot write", "failed write");
		expect_message(&err1, "keeps its first 1 frame", "failed write");
		assert_int_equal(r2, -EFBIG);
		expect_message(&err2, "earlier write", "write after a failure");
		assert_int_equal(st2.frames, 1);
		assert_int_equal(st2.error, -EFBIG);
		assert_int_equal(count_entries(sub), 1);
		uint32_t node, db;
		uint64_t max_ts;
		header_counts(path, &node, &db, &max_ts);
		assert_int_equal(node, 1);
		assert_int_equal(db, 1);
		if (i == 0) { /* the end record does not fit: kept unfinished, and said so */
			assert_int_equal(r3, -EFBIG);
			expect_message(&err, "1 frame", "finish without room");
			expect_message(&err, "not finalised", "finish without room");
			expect_recovered(path, want, 1, "not finalised", "no room for the end");
		} else { /* finalised (without a seek table when only the end record fits) */
			if (r3)
				fail_msg("room %llu: finish: %s", (unsigned long long)room[i], err.message);
			expect_recovered(path, want, 1, NULL, "finished after a failure");
		}
	}
	signal(SIGXFSZ, prev);
	free(want[0]);
}

static double now_s(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* A 37x23 frame for frame k through the writer (packed rows). */
static int write_one(struct dao_oni_writer *w, uint16_t *px, uint64_t ts)
{
	struct dao_frame f = {.format = DAO_PIXFMT_DEPTH16, .width = SW, .height = SH,
			.stride = SW * 2, .data = px, .depth_unit = 0.001f};
	struct dao_error err = {0};
	int r = dao_oni_writer_write_depth(w, &f, ts, &err);
	if (r)
		fprintf(stderr, "write: %s\n", err.message);
	return r;
}

/*
 * Syncs: none per frame, one when a frame comes a second or more after the
 * last one (or the start); the header then counts the synced frames.
 */
static void test_sync_interval(void **state)
{
	(void)state;
	enum { N = 40 };
	char path[PLEN];
	pathof(path, "sync.oni");
	unlink(path);
	struct dao_oni_writer_options o = default_options(DAO_ONI_CODEC_16ZT, DAO_ONI_PIXEL_DEPTH_1_MM);
	o.overwrite = 0;
	uint16_t *frames[N + 1];
	for (int k = 0; k <= N; k++) {
		frames[k] = malloc(SW * SH * sizeof(uint16_t));
		assert_non_null(frames[k]);
		gen_frame(frames[k], SW, SH, k, max_count(&o));
	}
	struct dao_oni_writer *w;
	struct dao_error err = {0};
	struct dao_oni_writer_status st;
	double t0 = now_s();
	assert_int_equal(dao_oni_writer_open(path, &o, &w, &err), 0);
	for (int k = 0; k < N; k++)
		assert_int_equal(write_one(w, frames[k], 1000 + 33333 * (uint64_t)k), 0);
	double elapsed = now_s() - t0;
	dao_oni_writer_get_status(w, &st);
	assert_int_equal(st.frames, N);
	assert_int_equal(st.error, 0);
	/* at most one sync per second since the start, not one per frame */
	if (st.syncs > (uint32_t)elapsed)
		fail_msg("%u syncs in %.2f s", st.syncs, elapsed);
	if (st.syncs == 0)
		assert_int_equal(st.synced_frames, 0);
	uint32_t node, db;
	uint64_t max_ts;
	header_counts(path, &node, &db, &max_ts);
	assert_int_equal(node, st.synced_frames);
	assert_int_equal(db, st.synced_frames);
	/* a frame a second later is synced with all before it, and counted in the header */
	struct timespec pause = {1, 50000000};
	nanosleep(&pause, NULL);
	assert_int_equal(write_one(w, frames[N], 1000 + 33333 * (uint64_t)N), 0);
	dao_oni_writer_get_status(w, &st);
	assert_int_equal(st.frames, N + 1);
	assert_int_equal(st.synced_frames, N + 1);
	assert_true(st.syncs >= 1);
	header_counts(path, &node, &db, &max_ts);
	assert_int_equal(node, N + 1);
	assert_int_equal(db, N + 1);
	assert_int_equal(max_ts, 1000 + 33333 * (uint64_t)N);
	/* unfinished, it reads back whole, with a warning */
	expect_recovered(path, frames, N + 1, "not finalised", "synced, not finished");
	assert_int_equal(dao_oni_writer_sync(w, &err), 0);
	assert_int_equal(dao_oni_writer_finish(w, &err), 0);
	expect_recovered(path, frames, N + 1, NULL, "finished");
	for (int k = 0; k <= N; k++)
		free(frames[k]);
	unlink(path);
}

/*
 * kill -9 while recording: the file is at its name with every frame written,
 * the header counts those synced (what OpenNI2 plays), and a write cut short
 * at the end (a power cut) is dropped.
 */
static void test_killed_writer(void **state)
{
	(void)state;
	enum { N = 8, SYNC_AT = 5 };
	char sub[PLEN], path[PLEN + 16];
	fresh_subdir(sub, "kill");
	snprintf(path, sizeof path, "%s/k.oni", sub);
	struct dao_oni_writer_options o = default_options(DAO_ONI_CODEC_16Z, DAO_ONI_PIXEL_DEPTH_1_MM);
	uint16_t *frames[N];
	for (int k = 0; k < N; k++) {
		frames[k] = malloc(SW * SH * sizeof(uint16_t));
		assert_non_null(frames[k]);
		gen_frame(frames[k], SW, SH, k, max_count(&o));
	}
	int fds[2];
	assert_int_equal(pipe(fds), 0);
	fflush(NULL);
	pid_t pid = fork();
	assert_true(pid >= 0);
	if (pid == 0) {
		struct dao_oni_writer *w;
		struct dao_error err;
		struct dao_oni_writer_status st;
		struct timespec pause = {1, 50000000};
		if (dao_oni_writer_open(path, &o, &w, &err))
			_exit(2);
		for (int k = 0; k < N; k++) {
			if (k == SYNC_AT)
				nanosleep(&pause, NULL); /* this frame is synced, with all before */
			if (write_one(w, frames[k], 1000 + 33333 * (uint64_t)k))
				_exit(3);
		}
		dao_oni_writer_get_status(w, &st);
		if (write(fds[1], &st.synced_frames, sizeof st.synced_frames) != sizeof st.synced_frames)
			_exit(4);
		raise(SIGKILL);
		_exit(5);
	}
	close(fds[1]);
	uint32_t synced = 0;
	assert_int_equal(read(fds[0], &synced, sizeof synced), sizeof synced);
	close(fds[0]);
	int ws;
	assert_int_equal(waitpid(pid, &ws, 0), pid);
	assert_true(WIFSIGNALED(ws) && WTERMSIG(ws) == SIGKILL);
	assert_true(synced >= SYNC_AT + 1);
	assert_int_equal(count_entries(sub), 1);
	expect_recovered(path, frames, N, "not finalised", "killed writer");
	uint32_t node, db;
	uint64_t max_ts;
	header_counts(path, &node, &db, &max_ts);
	assert_int_equal(node, synced);
	assert_int_equal(db, synced);
	assert_int_equal(max_ts, 1000 + 33333 * (uint64_t)(synced - 1));
	/* half a record more at the end: dropped */
	struct bytes b = load(path);
	size_t at = find_record(&b, REC_NEW_DATA, 1);
	FILE *f = fopen(path, "ab");
	assert_non_null(f);
	assert_int_equal(fwrite(b.p + at, 1, 60, f), 60);
	assert_int_equal(fclose(f), 0);
	expect_recovered(path, frames, N, "cut short", "killed writer, cut record");
	free(b.p);
	for (int k = 0; k < N; k++)
		free(frames[k]);
}

static void test_codec_names(void **state)
{
	(void)state;
	enum dao_oni_codec c = DAO_ONI_CODEC_OTHER;
	assert_int_equal(dao_oni_codec_from_name("16zT", &c), 0);
	assert_int_equal(c, DAO_ONI_CODEC_16ZT);
	assert_int_equal(dao_oni_codec_from_name("16ZP", &c), 0);
	assert_int_equal(c, DAO_ONI_CODEC_16Z);
	assert_int_equal(dao_oni_codec_from_name("16z", &c), 0);
	assert_int_equal(c, DAO_ONI_CODEC_16Z);
	assert_int_equal(dao_oni_codec_from_name("None", &c), 0);
	assert_int_equal(c, DAO_ONI_CODEC_NONE);
	assert_int_equal(dao_oni_codec_from_name("jpeg", &c), -EINVAL);
	assert_int_equal(dao_oni_codec_from_name("", &c), -EINVAL);
	assert_int_equal(dao_oni_codec_from_name(NULL, &c), -EINVAL);
	for (int k = DAO_ONI_CODEC_NONE; k <= DAO_ONI_CODEC_16ZT; k++) {
		assert_int_equal(dao_oni_codec_from_name(dao_oni_codec_name((enum dao_oni_codec)k), &c), 0);
		assert_int_equal(c, k);
	}
}

/* --- (c) bad input ------------------------------------------------------- */

static void test_bad_files(void **state)
{
	(void)state;
	char path[PLEN], good[PLEN];
	pathof(path, "bad.oni");

	pathof(good, "missing.oni");
	expect_open_error(good, -ENOENT, "missing.oni", "missing file");
	expect_open_error(good, -ENOENT, "cannot open", "missing file");
	expect_open_error(dir, -EINVAL, "not a regular file", "a directory");
	/* a FIFO is refused without opening it for reading (that would wait for a writer) */
	pathof(good, "fifo.oni");
	assert_int_equal(mkfifo(good, 0600), 0);
	expect_open_error(good, -EINVAL, "is a FIFO (named pipe), not a regular file", "a FIFO");
	unlink(good);
	save(path, "", 0);
	expect_open_error(path, -EINVAL, "not an .oni file", "empty file");
	save(path, "NI10", 4);
	expect_open_error(path, -EINVAL, "header", "4-byte file");

	pathof(good, "good.oni");
	uint16_t *frames[NF];
	make_small(good, DAO_ONI_CODEC_16Z, frames);
	struct bytes b = load(good);
	uint8_t *p = malloc(b.n + 64);
	assert_non_null(p);

	/* wrong magic */
	memcpy(p, b.p, b.n);
	memcpy(p, "NI11", 4);
	save(path, p, b.n);
	expect_open_error(path, -EINVAL, "NI10", "wrong magic");
	memcpy(p, "\x89PNG", 4);
	save(path, p, b.n);
	expect_open_error(path, -EINVAL, "not an .oni file", "PNG magic");

	/* unsupported versions: 2.0.0.0, 1.0.0.3, 1.0.1.1 */
	static const uint8_t versions[][8] = {{2, 0, 0, 0, 0, 0, 0, 0},
					      {1, 0, 0, 0, 3, 0, 0, 0},
					      {1, 0, 1, 0, 1, 0, 0, 0},
					      {1, 1, 0, 0, 0, 0, 0, 0}};
	for (size_t v = 0; v < sizeof(versions) / sizeof(versions[0]); v++) {
		memcpy(p, b.p, b.n);
		memcpy(p + 4, versions[v], 8);
		save(path, p, b.n);
		expect_open_error(path, -EINVAL, "not supported", "unsupported version");
	}

	/* truncated: inside the file header, inside a record header, inside a payload */
	size_t first_data = find_record(&b, REC_NEW_DATA, 0);
	size_t second_data = find_record(&b, REC_NEW_DATA, 1);
	size_t end = find_record(&b, REC_END, 0);
	assert_true(first_data > FILE_HEADER);
	assert_true(second_data > first_data);
	assert_int_equal(end + REC_HEADER, b.n); /* the end record is last */
	/* cut before the first complete frame: nothing to recover */
	save(path, b.p, 10);
	expect_open_error(path, -EINVAL, "header", "cut inside the file header");
	save(path, b.p, FILE_HEADER);
	expect_open_error(path, -EINVAL, "truncated", "cut after the file header");
	save(path, b.p, FILE_HEADER + 10);
	expect_open_error(path, -EINVAL, "before its first complete frame", "cut in a record header");
	size_t payload = first_data + REC_HEADER + 12;
	save(path, b.p, payload + 5);
	expect_open_error(path, -EINVAL, "before its first complete frame", "cut inside a payload");
	save(path, b.p, first_data);
	expect_open_error(path, -EINVAL, "nothing to recover", "cut before the first frame");
	/* cut after complete frames: an unfinished recording, recovered with a warning */
	save(path, b.p, second_data + 5);
	expect_recovered(path, frames, 1, "cut short", "cut in a frame header");
	save(path, b.p, second_data + REC_HEADER + 12 + 3);
	expect_recovered(path, frames, 1, "cut short", "cut in a frame's payload");
	save(path, b.p, second_data);
	expect_recovered(path, frames, 1, "without an end record", "cut between records");
	save(path, b.p, end);
	expect_recovered(path, frames, NF, "without an end record", "cut before the end record");
	/* every cut: the complete frames before it, pixel for pixel, or a clean error */
	size_t frame_end[NF];
	for (int k = 0; k < NF; k++) {
		size_t at = find_record(&b, REC_NEW_DATA, k);
		frame_end[k] = at + rd32(b.p + at + 12) + rd32(b.p + at + 16);
	}
	for (size_t cut = 0; cut < b.n; cut++) {
		uint32_t complete = 0;
		while (complete < NF && frame_end[complete] <= cut)
			complete++;
		save(path, b.p, cut);
		char ctx[64];
		snprintf(ctx, sizeof ctx, "cut at %zu of %zu", cut, b.n);
		if (complete)
			expect_recovered(path, frames, complete, "not finalised", ctx);
		else
			expect_open_error(path, -EINVAL, cut < FILE_HEADER ? "header" : "truncated", ctx);
	}
	/* zeros after the last record (space allocated, data lost in a power cut) */
	memcpy(p, b.p, second_data);
	memset(p + second_data, 0, b.n - second_data);
	save(path, p, b.n);
	expect_recovered(path, frames, 1, "zero", "zeros at the end");
	/* but not garbage: that is corruption */
	memset(p + second_data + 200, 0x5A, 1);
	save(path, p, b.n);
	expect_open_error(path, -EINVAL, "bad record magic", "zeros, then garbage");
	/* a frame count in the header that is too small does not matter (the reader counts) */
	memcpy(p, b.p, b.n);
	size_t counts = FILE_HEADER + REC_HEADER + 4 + rd32(b.p + FILE_HEADER + REC_HEADER) + 8;
	wr32(p + counts, 1);
	save(path, p, b.n);
	expect_recovered(path, frames, NF, NULL, "stale frame count");

	/* a NONE frame whose payload is larger than the frame: size patched, bytes inserted */
	{
		char none[PLEN];
		uint16_t *nf[NF];
		pathof(none, "none.oni");
		make_small(none, DAO_ONI_CODEC_NONE, nf);
		struct bytes c = load(none);
		size_t at = find_record(&c, REC_NEW_DATA, 1);
		assert_true(at > 0);
		uint32_t ps = rd32(c.p + at + 16);
		assert_int_equal(ps, SW * SH * 2);
		uint8_t *q = malloc(c.n + 2);
		assert_non_null(q);
		size_t split = at + rd32(c.p + at + 12) + ps;
		memcpy(q, c.p, split);
		q[split] = 0x12, q[split + 1] = 0x34;
		memcpy(q + split + 2, c.p + split, c.n - split);
		wr32(q + at + 16, ps + 2);
		save(path, q, c.n + 2);
		expect_open_error(path, -EINVAL, "more than", "NONE payload too large");
		expect_open_error(path, -EINVAL, "frame 1", "NONE payload too large");
		/* a payload one pixel short: also refused */
		memcpy(q, c.p, split - 2);
		memcpy(q + split - 2, c.p + split, c.n - split);
		wr32(q + at + 16, ps - 2);
		save(path, q, c.n - 2);
		expect_open_error(path, -EINVAL, "bytes of data", "NONE payload too small");
		free(q);
		free(c.p);
		free_frames(nf);
		unlink(none);
	}

	/* structural corruption */
	memcpy(p, b.p, b.n);
	wr32(p + FILE_HEADER, 0x12345678); /* first record's magic */
	save(path, p, b.n);
	expect_open_error(path, -EINVAL, "bad record magic", "bad record magic");
	memcpy(p, b.p, b.n);
	wr32(p + first_data + 4, 0x77); /* record type */
	save(path, p, b.n);
	expect_open_error(path, -EINVAL, "unknown record type", "unknown record type");
	memcpy(p, b.p, b.n);
	wr32(p + first_data + 8, 7); /* node id above the header's maximum */
	save(path, p, b.n);
	expect_open_error(path, -EINVAL, "maximum", "node id too large");
	memcpy(p, b.p, b.n);
	wr32(p + first_data + 8, 0); /* a node never added */
	save(path, p, b.n);
	expect_open_error(path, -EINVAL, "never added", "frame of an unknown node");
	memcpy(p, b.p, b.n);
	wr32(p + first_data + 12, 3); /* fields size below the header size */
	save(path, p, b.n);
	expect_open_error(path, -EINVAL, "fields size", "fields size 3");
	memcpy(p, b.p, b.n);
	wr32(p + first_data + 12, 0xFFFFFFF0u);
	save(path, p, b.n);
	expect_open_error(path, -EINVAL, "fields size", "huge fields size");
	memcpy(p, b.p, b.n);
	/* a payload size past the end of the file with records after it: damage, not
	 * an interrupted recording (issue 38: it was recovered as one) */
	wr32(p + first_data + 16, 0xFFFFFFF0u);
	save(path, p, b.n);
	expect_open_error(path, -EINVAL, "yet a record follows", "huge payload size");
	memcpy(p, b.p, b.n);
	wr32(p + second_data + 16, 0xFFFFFFFFu); /* after a complete frame: still damage */
	save(path, p, b.n);
	expect_open_error(path, -EINVAL, "damage, not an interrupted recording",
			  "huge payload size after a frame");
	{
		char cut[64];
		snprintf(cut, sizeof cut, "head -c %zu keeps the 1 frame before", second_data);
		expect_open_error(path, -EINVAL, cut, "the advice names the cut");
	}
	/* the same record cut short by the end of the file: recovered, as before */
	save(path, p, second_data + REC_HEADER + 40);
	expect_recovered(path, frames, 1, "not finalised", "huge payload size, file ends");
	memcpy(p, b.p, b.n);
	wr32(p + first_data + 12, REC_HEADER + 4); /* frame fields cut short */
	save(path, p, b.n);
	expect_open_error(path, -EINVAL, "corrupt", "short frame fields");
	memcpy(p, b.p, b.n);
	wr32(p + FILE_HEADER + REC_HEADER, 0x1000); /* node name length past the record */
	save(path, p, b.n);
	expect_open_error(path, -EINVAL, "cut short", "node name too long");

	/* zero frames: a depth node without NEW_DATA records, then the end record */
	memcpy(p, b.p, first_data);
	memcpy(p + first_data, b.p + end, REC_HEADER);
	save(path, p, first_data + REC_HEADER);
	{
		struct dao_oni_reader *r = NULL;
		struct dao_error err = {0};
		if (dao_oni_reader_open(path, &r, &err))
			fail_msg("zero frames: %s", err.message);
		assert_int_equal(dao_oni_reader_stream_count(r), 1);
		const struct dao_oni_stream_info *s = dao_oni_reader_stream(r, 0);
		assert_int_equal(s->frame_count, 0);
		assert_int_equal(s->width, SW);
		assert_int_equal(s->first_timestamp_us, 0);
		struct dao_frame f = new_depth(SW, SH);
		assert_int_equal(dao_oni_reader_read_depth(r, 0, 0, &f, &err), -EINVAL);
		expect_message(&err, "past the end", "zero frames");
		dao_frame_free(&f);
		dao_oni_reader_close(r);
	}

	free(p);
	free(b.p);
	free_frames(frames);
	unlink(good);
	unlink(path);
}

/* Corrupt 16zT payloads: read_depth fails with -EINVAL or returns, never crashes. */
static void test_corrupt_payload(void **state)
{
	(void)state;
	char good[PLEN], path[PLEN];
	pathof(good, "t.oni");
	pathof(path, "tbad.oni");
	uint16_t *frames[NF];
	make_small(good, DAO_ONI_CODEC_16ZT, frames);
	struct bytes b = load(good);
	size_t at = find_record(&b, REC_NEW_DATA, 2);
	assert_true(at > 0);
	size_t payload = at + rd32(b.p + at + 12);
	uint32_t ps = rd32(b.p + at + 16);
	assert_true(ps > 16);
	uint8_t *p = malloc(b.n);
	assert_non_null(p);
	struct dao_frame f = new_depth(SW, SH);
	struct dao_error err;

	/* a table larger than the payload */
	memcpy(p, b.p, b.n);
	p[payload] = 0xFF, p[payload + 1] = 0x7F;
	save(path, p, b.n);
	struct dao_oni_reader *r = NULL;
	assert_int_equal(dao_oni_reader_open(path, &r, &err), 0);
	assert_int_equal(dao_oni_reader_read_depth(r, 0, 2, &f, &err), -EINVAL);
	expect_message(&err, "corrupt", "16zT table too large");
	expect_message(&err, "frame 2", "16zT table too large");
	expect_message(&err, "table", "16zT table too large");
	/* the other frames still read */
	assert_int_equal(dao_oni_reader_read_depth(r, 0, 1, &f, &err), 0);
	assert_frame_equals(&f, frames[1], "frame next to a corrupt one");
	dao_oni_reader_close(r);

	/* the last byte dropped (payload size patched, the file stays consistent) */
	memcpy(p, b.p, b.n);
	memmove(p + payload + ps - 1, b.p + payload + ps, b.n - payload - ps);
	wr32(p + at + 16, ps - 1);
	save(path, p, b.n - 1);
	assert_int_equal(dao_oni_reader_open(path, &r, &err), 0);
	assert_int_equal(dao_oni_reader_read_depth(r, 0, 2, &f, &err), -EINVAL);
	expect_message(&err, "corrupt", "16zT stream cut short");
	dao_oni_reader_close(r);

	/* random garbage over the payload */
	int failed = 0, ok = 0;
	for (int iter = 0; iter < 300; iter++) {
		memcpy(p, b.p, b.n);
		int nbytes = 1 + (int)(rnd() % 8);
		for (int k = 0; k < nbytes; k++)
			p[payload + rnd() % ps] = (uint8_t)rnd();
		if (iter % 10 == 0) /* sometimes all of it */
			for (uint32_t k = 0; k < ps; k++)
				p[payload + k] = (uint8_t)rnd();
		save(path, p, b.n);
		assert_int_equal(dao_oni_reader_open(path, &r, &err), 0);
		int ret = dao_oni_reader_read_depth(r, 0, 2, &f, &err);
		if (ret == 0) {
			ok++;
		} else {
			if (ret != -EINVAL)
				fail_msg("garbage %d: read_depth returned %d (%s)", iter, ret, err.message);
			expect_message(&err, "corrupt", "garbage payload");
			failed++;
		}
		assert_int_equal(dao_oni_reader_read_depth(r, 0, 3, &f, &err), 0);
		assert_frame_equals(&f, frames[3], "frame after a garbage one");
		dao_oni_reader_close(r);
	}
	assert_true(failed > 0);
	dao_frame_free(&f);
	free(p);
	free(b.p);
	free_frames(frames);
	unlink(good);
	unlink(path);
}

/* The file shrinks after opening: reads fail with -EIO. */
static void test_file_shrinks(void **state)
{
	(void)state;
	char path[PLEN];
	pathof(path, "shrink.oni");
	uint16_t *frames[NF];
	make_small(path, DAO_ONI_CODEC_NONE, frames);
	struct dao_oni_reader *r = NULL;
	struct dao_error err = {0};
	assert_int_equal(dao_oni_reader_open(path, &r, &err), 0);
	assert_int_equal(truncate(path, 200), 0);
	struct dao_frame f = new_depth(SW, SH);
	assert_int_equal(dao_oni_reader_read_depth(r, 0, 3, &f, &err), -EIO);
	expect_message(&err, "shrunk", "file shrank");
	dao_frame_free(&f);
	dao_oni_reader_close(r);
	free_frames(frames);
	unlink(path);
}

/*
 * Opens a file and reads every frame of every depth stream.  Anything may
 * fail, but only with a negative code and a message.  Returns 0 if the file
 * opened and every frame read.
 */
static int read_everything(const char *path)
{
	struct dao_oni_reader *r = NULL;
	struct dao_error err = {0};
	int ret = dao_oni_reader_open(path, &r, &err);
	if (ret < 0) {
		if (!err.message[0] || r)
			fail_msg("%s: open failed (%d) without a message", path, ret);
		return ret;
	}
	assert_int_equal(ret, 0);
	int bad = 0;
	for (uint32_t s = 0; s < dao_oni_reader_stream_count(r); s++) {
		const struct dao_oni_stream_info *in = dao_oni_reader_stream(r, s);
		if (in->sensor != DAO_ONI_SENSOR_DEPTH || in->frame_count == 0 ||
		    (uint64_t)in->width * in->height > 4096u * 4096u)
			continue;
		struct dao_frame f = new_depth(in->width, in->height);
		for (uint32_t k = 0; k < in->frame_count; k++) {
			err.message[0] = 0;
			ret = dao_oni_reader_read_depth(r, s, k, &f, &err);
			if (ret < 0) {
				if (ret != -EINVAL && ret != -EIO)
					fail_msg("%s: frame %u: unexpected code %d", path, k, ret);
				if (!err.message[0])
					fail_msg("%s: frame %u failed without a message", path, k);
				bad = ret;
			}
		}
		dao_frame_free(&f);
	}
	dao_oni_reader_close(r);
	return bad;
}

/* Runs read_everything over every file of a directory; returns the number of files. */
static int read_directory(const char *d, int must_succeed)
{
	DIR *dp = opendir(d);
	if (!dp)
		return -1;
	struct dirent *e;
	int n = 0;
	char path[PLEN];
	while ((e = readdir(dp))) {
		if (e->d_name[0] == '.' || strstr(e->d_name, "README"))
			continue;
		fmt(path, "%s/%s", d, e->d_name);
		int ret = read_everything(path);
		if (must_succeed && ret != 0)
			fail_msg("%s: valid file failed to read (%d)", path, ret);
		n++;
	}
	closedir(dp);
	return n;
}

static void test_regressions(void **state)
{
	(void)state;
	const char *root = getenv("DAO_SOURCE_ROOT");
	if (!root) {
		fprintf(stderr, "DAO_SOURCE_ROOT is not set; skipping regress/ and the fuzz corpus\n");
		skip();
	}
	char d[PLEN];
	/* reproducers of fuzzer findings: must not crash, any clean outcome */
	fmt(d, "%s/tests/oni/regress", root);
	int n = read_directory(d, 0);
	fprintf(stderr, "%d file(s) in %s\n", n, d);
	/* the fuzz corpus is made of valid recordings: every frame must read */
	fmt(d, "%s/fuzz/corpus/oni", root);
	n = read_directory(d, 1);
	fprintf(stderr, "%d file(s) in %s\n", n, d);
	assert_true(n > 0);
}

/* --- (a) the real Kinect recording --------------------------------------- */

static char kinect_path[PLEN];

/* FNV-1a (64-bit) over the pixels as little-endian bytes, row after row. */
static uint64_t fnv1a(uint64_t h, const uint16_t *px, size_t n)
{
	for (size_t i = 0; i < n; i++) {
		h = (h ^ (px[i] & 0xFF)) * 0x100000001b3ull;
		h = (h ^ (px[i] >> 8)) * 0x100000001b3ull;
	}
	return h;
}

/*
 * FNV-1a over all 12 depth frames of 3DJ_test.oni as OpenNI2 2.2 decodes
 * them: written with OpenNI2's own file driver by a scratch tool
 * (oniDeviceOpen on the file, playback speed -1, oniStreamReadFrame for each
 * of the 12 frames, frame data appended to a raw file of 12 x 640 x 480
 * uint16), then hashed over that file's bytes.
 */
#define KINECT_OPENNI2_FNV1A 0xd4c179f8a79efb0aull

static void test_kinect(void **state)
{
	(void)state;
	enum { KW = 640, KH = 480, KN = 12 };
	struct dao_oni_reader *r = NULL;
	struct dao_error err = {0};
	if (dao_oni_reader_open(kinect_path, &r, &err))
		fail_msg("%s: %s", kinect_path, err.message);
	assert_int_equal(dao_oni_reader_stream_count(r), 2);
	assert_int_equal(dao_oni_reader_depth_stream(r, &err), 0);
	const struct dao_oni_stream_info *d = dao_oni_reader_stream(r, 0);
	assert_string_equal(d->name, "Depth1");
	assert_int_equal(d->sensor, DAO_ONI_SENSOR_DEPTH);
	assert_int_equal(d->codec, DAO_ONI_CODEC_16ZT);
	assert_string_equal(d->codec_fourcc, "16zT");
	assert_int_equal(d->width, KW);
	assert_int_equal(d->height, KH);
	assert_int_equal(d->fps, 30);
	assert_int_equal(d->frame_count, KN);
	assert_int_equal(d->pixel_format, DAO_ONI_PIXEL_DEPTH_1_MM);
	assert_true(d->depth_unit == 0.001f);
	assert_int_equal(d->mirrored, 1);
	assert_int_equal(d->registered, 1);
	assert_int_equal(d->has_fov, 1);
	assert_true(fabs(d->hfov - 1.01447) < 1e-4);
	assert_true(fabs(d->vfov - 0.78980) < 1e-4);
	assert_int_equal(d->first_timestamp_us, 11680);
	assert_int_equal(d->last_timestamp_us, 378742);
	const struct dao_oni_stream_info *c = dao_oni_reader_stream(r, 1);
	assert_string_equal(c->name, "Image1");
	assert_int_equal(c->sensor, DAO_ONI_SENSOR_COLOR);
	assert_int_equal(c->codec, DAO_ONI_CODEC_JPEG);
	assert_string_equal(c->codec_fourcc, "JPEG");
	assert_int_equal(c->frame_count, KN);
	assert_true(c->depth_unit == 0.0f);

	/* every frame, in order */
	uint16_t *all = malloc((size_t)KN * KW * KH * sizeof(*all));
	assert_non_null(all);
	struct dao_frame f = new_depth(KW, KH);
	uint64_t h = 0xcbf29ce484222325ull;
	for (uint32_t k = 0; k < KN; k++) {
		if (dao_oni_reader_read_depth(r, 0, k, &f, &err))
			fail_msg("frame %u: %s", k, err.message);
		memcpy(all + (size_t)k * KW * KH, f.data, (size_t)KW * KH * 2);
		h = fnv1a(h, f.data, (size_t)KW * KH);
		assert_int_equal(f.sequence, k + 1);
		assert_true(f.depth_unit == 0.001f);
		if (k == 0)
			assert_int_equal(f.timestamp_ns, 11680000ull);
		if (k == KN - 1)
			assert_int_equal(f.timestamp_ns, 378742000ull);
	}
	if (h != KINECT_OPENNI2_FNV1A)
		fail_msg("checksum of the decoded frames is 0x%016llx, OpenNI2's is 0x%016llx",
			 (unsigned long long)h, (unsigned long long)KINECT_OPENNI2_FNV1A);

	/* frame 0: a real scene between 627 and 4581 mm, with some holes */
	size_t holes = 0;
	uint16_t lo = UINT16_MAX, hi = 0;
	for (size_t i = 0; i < (size_t)KW * KH; i++) {
		uint16_t v = all[i];
		if (!v) {
			holes++;
			continue;
		}
		lo = v < lo ? v : lo;
		hi = v > hi ? v : hi;
	}
	assert_true(lo >= 627);
	assert_true(hi <= 4581);
	assert_true(hi - lo > 1000);
	assert_true(holes > 0);
	assert_true(holes < (size_t)KW * KH / 2);

	/* random order, and repeated reads, give the same pixels */
	uint32_t order[3 * KN];
	for (uint32_t i = 0; i < 3 * KN; i++)
		order[i] = i % KN;
	for (uint32_t i = 3 * KN - 1; i > 0; i--) {
		uint32_t j = rnd() % (i + 1), t = order[i];
		order[i] = order[j];
		order[j] = t;
	}
	for (uint32_t i = 0; i < 3 * KN; i++) {
		uint32_t k = order[i];
		assert_int_equal(dao_oni_reader_read_depth(r, 0, k, &f, &err), 0);
		assert_memory_equal(f.data, all + (size_t)k * KW * KH, (size_t)KW * KH * 2);
		assert_int_equal(f.sequence, k + 1);
	}
	dao_frame_free(&f);

	/* a larger stride: rows land at the stride, the padding is untouched */
	const int32_t stride = KW * 2 + 70;
	uint8_t *buf = malloc((size_t)stride * KH);
	assert_non_null(buf);
	memset(buf, 0xAB, (size_t)stride * KH);
	struct dao_frame s = {.format = DAO_PIXFMT_DEPTH16, .width = KW, .height = KH,
			.stride = stride, .data = buf};
	assert_int_equal(dao_oni_reader_read_depth(r, 0, 7, &s, &err), 0);
	for (uint32_t y = 0; y < KH; y++) {
		const uint8_t *row = buf + (size_t)y * (size_t)stride;
		assert_memory_equal(row, all + (size_t)7 * KW * KH + (size_t)y * KW, KW * 2);
		for (int i = KW * 2; i < stride; i++)
			if (row[i] != 0xAB)
				fail_msg("padding byte %d of row %u overwritten", i, y);
	}
	free(buf);

	/* the colour stream is listed, not decoded */
	struct dao_frame g = new_depth(KW, KH);
	assert_int_equal(dao_oni_reader_read_depth(r, 1, 0, &g, &err), -EINVAL);
	expect_message(&err, "not a depth stream", "colour stream");
	assert_int_equal(dao_oni_reader_read_depth(r, 0, KN, &g, &err), -EINVAL);
	dao_frame_free(&g);
	dao_oni_reader_close(r);
	free(all);
}

int main(int argc, char **argv)
{
	if (argc > 1 && !strcmp(argv[1], "kinect")) {
		if (dao_test_data_path("oni/3DJ_test.oni", kinect_path, sizeof(kinect_path)) < 0) {
			fprintf(stderr, "SKIP: %s not found (set DAO_SHARED_DATA to ../shared/data)\n",
				kinect_path);
			return DAO_TEST_SKIP;
		}
		const struct CMUnitTest kinect[] = {cmocka_unit_test(test_kinect)};
		return cmocka_run_group_tests(kinect, NULL, NULL);
	}
	snprintf(dir, sizeof(dir), "/tmp/dao-oni-test-XXXXXX");
	if (!mkdtemp(dir)) {
		perror("mkdtemp");
		return 1;
	}
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_round_trips),   cmocka_unit_test(test_old_layout),
		cmocka_unit_test(test_unit_conversion), cmocka_unit_test(test_writer_rules),
		cmocka_unit_test(test_write_failure), cmocka_unit_test(test_sync_interval),
		cmocka_unit_test(test_killed_writer),
		cmocka_unit_test(test_codec_names),   cmocka_unit_test(test_bad_files),
		cmocka_unit_test(test_corrupt_payload), cmocka_unit_test(test_file_shrinks),
		cmocka_unit_test(test_regressions),
	};
	int r = cmocka_run_group_tests(tests, NULL, NULL);
	char cmd[PLEN + 32];
	snprintf(cmd, sizeof(cmd), "rm -rf '%s'", dir);
	if (system(cmd) != 0)
		fprintf(stderr, "could not remove %s\n", dir);
	return r;
}
