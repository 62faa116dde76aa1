/* SPDX-License-Identifier: MIT */
/*
 * The plugin registry and the built-in "oni" source: URI dispatch, error
 * messages, modules that must be skipped, and every playback mode.
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <cmocka.h>

#include "common/test_common.h"
#include "source_test_util.h"

#define FRAMES 6

static char g_path[512];
static struct dao_plugins *g_plugins;

static int setup(void **state)
{
	(void)state;
	struct dao_error err;
	snprintf(g_path, sizeof g_path, "%s/six.oni", dao_test_tmpdir("source-oni"));
	if (test_write_oni(g_path, FRAMES, DAO_ONI_CODEC_16ZT) < 0)
		return -1;
	/* only built-ins: an empty search path */
	return dao_plugins_load(&g_plugins, "", &err);
}

static int teardown(void **state)
{
	(void)state;
	dao_plugins_free(g_plugins);
	return 0;
}

static struct dao_source *open_src(const char *uri, const struct dao_source_options *o)
{
	return test_open_started(g_plugins, uri, o);
}

/* Reads one frame and returns its index, or the read's status (EOS/error) as -1000 - code. */
static long long read_index(struct dao_source *s)
{
	struct dao_source_frame f;
	struct dao_error err;
	int r = dao_source_read(s, &f, 1000, &err);
	if (r != 0)
		return -1000 + r;
	assert_true(test_is_frame(&f.depth, (uint32_t)f.index));
	assert_int_equal(f.depth.sequence, f.index + 1);
	assert_int_equal(f.depth.timestamp_ns, (1000 + f.index * 33333) * 1000);
	assert_int_equal(f.color.format, DAO_PIXFMT_NONE);
	dao_source_release(s, &f);
	return (long long)f.index;
}

static void test_builtins_listed(void **state)
{
	(void)state;
	assert_true(dao_plugins_count(g_plugins) >= 1);
	const struct dao_plugin *p = dao_plugins_find(g_plugins, "oni");
	assert_non_null(p);
	assert_non_null(p->source);
	assert_string_equal(dao_plugins_origin(g_plugins, 0), "built-in");
	assert_null(dao_plugins_find(g_plugins, "nosuch"));
}

static void test_info_and_auto_pick(void **state)
{
	(void)state;
	struct dao_source *s = open_src(g_path, NULL); /* no prefix: probed by extension */
	assert_string_equal(dao_source_plugin(s)->name, "oni");
	struct dao_source_info in;
	dao_source_get_info(s, &in);
	assert_int_equal(in.width, TEST_W);
	assert_int_equal(in.height, TEST_H);
	assert_int_equal(in.format, DAO_PIXFMT_DEPTH16);
	assert_float_equal(in.depth_unit, 0.001, 1e-9);
	assert_int_equal(in.frame_count, FRAMES);
	assert_int_equal(in.live, 0);
	assert_true(in.has_fov);
	assert_float_equal(in.hfov, 1.0, 1e-12);
	assert_float_equal(in.vfov, 0.75, 1e-12);
	assert_float_equal(in.fps, TEST_FPS, 0);
	assert_non_null(strstr(in.description, "six.oni"));
	assert_string_equal(in.warning, ""); /* a finished recording */
	dao_source_close(s);
}

/* A recording whose writer died: every frame it wrote plays, with a warning. */
static void test_unfinished_recording(void **state)
{
	(void)state;
	char path[600];
	snprintf(path, sizeof path, "%s/cut.oni", dao_test_tmpdir("source-oni-cut"));
	struct bytes_of_file {
		char *p;
		long n;
	} b = {NULL, 0};
	FILE *f = fopen(g_path, "rb");
	assert_non_null(f);
	assert_int_equal(fseek(f, 0, SEEK_END), 0);
	b.n = ftell(f);
	rewind(f);
	b.p = malloc((size_t)b.n);
	assert_non_null(b.p);
	assert_int_equal(fread(b.p, 1, (size_t)b.n, f), (size_t)b.n);
	fclose(f);
	/* the end record, seek table and the last frame's second half are gone */
	long keep = b.n - 28 - 28 - 28 - (FRAMES + 1) * 20 - 40;
	f = fopen(path, "wb");
	assert_non_null(f);
	assert_int_equal(fwrite(b.p, 1, (size_t)keep, f), (size_t)keep);
	fclose(f);
	free(b.p);
	struct dao_source *s = open_src(path, NULL);
	struct dao_source_info in;
	dao_source_get_info(s, &in);
	assert_int_equal(in.frame_count, FRAMES - 1);
	assert_non_null(strstr(in.warning, "cut.oni"));
	assert_non_null(strstr(in.warning, "not finalised"));
	for (long long i = 0; i < FRAMES - 1; i++)
		assert_int_equal(read_index(s), i);
	assert_int_equal(read_index(s), -1000 + DAO_SOURCE_EOS);
	dao_source_close(s);
}

static void test_manual_every_frame_once(void **state)
{
	(void)state;
	char uri[600];
	snprintf(uri, sizeof uri, "oni:%s", g_path);
	struct dao_source *s = open_src(uri, NULL);
	for (long long i = 0; i < FRAMES; i++)
		assert_int_equal(read_index(s), i);
	assert_int_equal(read_index(s), -1000 + DAO_SOURCE_EOS);
	assert_int_equal(read_index(s), -1000 + DAO_SOURCE_EOS); /* stays at the end */
	dao_source_close(s);
}

static void test_loop_wraps(void **state)
{
	(void)state;
	struct dao_source_options o = {.size = sizeof(struct dao_source_options), .loop = 1, .start_frame = 4};
	struct dao_source *s = open_src(g_path, &o);
	long long expect[] = {4, 5, 4, 5, 4};
	for (size_t i = 0; i < sizeof expect / sizeof expect[0]; i++)
		assert_int_equal(read_index(s), expect[i]);
	dao_source_close(s);
}

static void test_start_step_seek(void **state)
{
	(void)state;
	struct dao_source_options o = {.size = sizeof(struct dao_source_options), .start_frame = 1, .step = 2};
	struct dao_source *s = open_src(g_path, &o);
	assert_int_equal(read_index(s), 1);
	assert_int_equal(read_index(s), 3);
	assert_int_equal(read_index(s), 5);
	assert_int_equal(read_index(s), -1000 + DAO_SOURCE_EOS);
	struct dao_error err;
	assert_int_equal(dao_source_seek(s, 2, &err), 0); /* back from the end */
	assert_int_equal(read_index(s), 2);
	assert_int_equal(dao_source_seek(s, FRAMES, &err), -EINVAL);
	assert_non_null(strstr(err.message, "6 frames"));
	dao_source_close(s);
}

static void test_realtime_delivers_all(void **state)
{
	(void)state;
	struct dao_source_options o = {.size = sizeof(struct dao_source_options), .playback = DAO_PLAYBACK_REALTIME};
	struct dao_source *s = open_src(g_path, &o);
	for (long long i = 0; i < FRAMES; i++)
		assert_int_equal(read_index(s), i); /* paced, but none skipped */
	assert_int_equal(read_index(s), -1000 + DAO_SOURCE_EOS);
	dao_source_close(s);
}

static void test_open_errors(void **state)
{
	(void)state;
	struct dao_source *s = NULL;
	struct dao_error err;
	assert_int_equal(dao_source_open(g_plugins, "nosuch:thing", NULL, &s, &err), -ENOENT);
	assert_non_null(strstr(err.message, "no source plugin 'nosuch'"));
	assert_non_null(strstr(err.message, "oni")); /* lists what there is */
	assert_int_equal(dao_source_open(g_plugins, "/tmp/whatever.xyz", NULL, &s, &err), -ENOENT);
	assert_non_null(strstr(err.message, "no source recognises"));
	assert_int_equal(dao_source_open(g_plugins, "oni:/nonexistent/x.oni", NULL, &s, &err),
			 -ENOENT);
	assert_non_null(strstr(err.message, "/nonexistent/x.oni"));
	struct dao_source_options o = {.size = sizeof(struct dao_source_options), .start_frame = FRAMES};
	assert_int_equal(dao_source_open(g_plugins, g_path, &o, &s, &err), -EINVAL);
	assert_non_null(strstr(err.message, "start frame"));
	assert_null(s);
}

/* A directory of depth PNGs: frame f of the test pattern as f.png, in name order. */
static const char *write_pngs(const char *tag, uint32_t n, uint32_t odd_one)
{
	const char *dir = dao_test_tmpdir(tag);
	struct dao_frame d;
	struct dao_error err;
	assert_int_equal(dao_frame_alloc(&d, DAO_PIXFMT_DEPTH16, TEST_W, TEST_H, &err), 0);
	d.depth_unit = 0.001f;
	for (uint32_t f = 0; f < n; f++) {
		char path[600];
		for (uint32_t y = 0; y < TEST_H; y++)
			for (uint32_t x = 0; x < TEST_W; x++)
				((uint16_t *)d.data)[y * TEST_W + x] = test_depth(f, x, y);
		struct dao_frame w = d;
		if (f == odd_one)
			w.width = TEST_W - 1; /* a frame of another size */
		snprintf(path, sizeof path, "%s/%02u.png", dir, f);
		assert_int_equal(dao_png_write(path, &w, &err), 0);
	}
	dao_frame_free(&d);
	return dir;
}

static void test_images_source(void **state)
{
	(void)state;
	char uri[600];
	snprintf(uri, sizeof uri, "images:%s", write_pngs("images", 4, 99));
	struct dao_source_options o = {.size = sizeof(struct dao_source_options), .start_frame = 1, .loop = 1, .depth_unit = 0.0002f};
	struct dao_source *s = open_src(uri, &o);
	struct dao_source_info in;
	dao_source_get_info(s, &in);
	assert_int_equal(in.frame_count, 4);
	assert_int_equal(in.width, TEST_W);
	assert_int_equal(in.has_fov, 0);
	assert_float_equal(in.depth_unit, 0.0002, 1e-9);
	struct dao_error err;
	long long expect[] = {1, 2, 3, 1};
	for (int i = 0; i < 4; i++) {
		struct dao_source_frame f;
		assert_int_equal(dao_source_read(s, &f, 1000, &err), 0);
		assert_int_equal(f.index, expect[i]);
		assert_true(test_is_frame(&f.depth, (uint32_t)f.index));
		assert_float_equal(f.depth.depth_unit, 0.0002, 1e-9);
		dao_source_release(s, &f);
	}
	dao_source_close(s);

	/* a directory is picked without a prefix too; a frame of another size is an error */
	const char *dir = write_pngs("images-odd", 3, 2);
	s = open_src(dir, NULL);
	assert_string_equal(dao_source_plugin(s)->name, "images");
	struct dao_source_frame f;
	assert_int_equal(dao_source_read(s, &f, 1000, &err), 0);
	assert_int_equal(dao_source_read(s, &f, 1000, &err), 0);
	assert_int_equal(dao_source_read(s, &f, 1000, &err), -EINVAL);
	assert_non_null(strstr(err.message, "02.png is 36x23, but the sequence is 37x23"));
	dao_source_close(s);

	/* an empty directory */
	snprintf(uri, sizeof uri, "images:%s", dao_test_tmpdir("images-empty"));
	assert_int_equal(dao_source_open(g_plugins, uri, NULL, &s, &err), -ENOENT);
	assert_non_null(strstr(err.message, "no *.png files"));
}

/*
 * Real-time playback of depth PNGs follows their timestamps (a recording at
 * 30 fps), as .oni and bag recordings do: with step 3, frames 0, 3 and 6 come
 * 100 ms apart, the recording's own time.  A sleep is never shorter than asked,
 * so this lower bound holds on a loaded host.
 */
static uint64_t mono_ms(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return (uint64_t)t.tv_sec * 1000 + (uint64_t)t.tv_nsec / 1000000;
}

static void test_images_realtime_step(void **state)
{
	(void)state;
	char uri[600];
	snprintf(uri, sizeof uri, "images:%s", write_pngs("images-realtime", 7, 99));
	struct dao_source_options o = {.size = sizeof(struct dao_source_options),
				       .playback = DAO_PLAYBACK_REALTIME, .step = 3};
	struct dao_source *s = open_src(uri, &o);
	struct dao_error err;
	struct dao_source_frame f;
	const uint64_t t0 = mono_ms();
	for (uint64_t i = 0; i <= 6; i += 3) {
		assert_int_equal(dao_source_read(s, &f, 1000, &err), 0);
		assert_int_equal(f.index, i);
		assert_int_equal(f.depth.timestamp_ns, i * 1000000000u / 30);
		dao_source_release(s, &f);
	}
	const uint64_t ms = mono_ms() - t0;
	if (ms < 199)
		fail_msg("frames 0, 3, 6 at 30 fps played in %llu ms, not 200", (unsigned long long)ms);
	assert_int_equal(dao_source_read(s, &f, 1000, &err), DAO_SOURCE_EOS);
	dao_source_close(s);
}

static uint32_t rd32(const uint8_t *p)
{
	return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}

/*
 * A copy of the six-frame 16zT recording whose frame `bad` has a corrupt
 * payload: its 16zT table claims more entries than the payload holds.  Records of
 * a 1.0.1.0 file: 24-byte file header, then records with the type at +4, the size
 * of the header fields at +12 and of the payload at +16; NEW_DATA = 0x0A.
 */
static void write_corrupt_oni(const char *path, int bad)
{
	FILE *f = fopen(g_path, "rb");
	assert_non_null(f);
	static uint8_t b[1 << 20];
	size_t n = fread(b, 1, sizeof b, f);
	fclose(f);
	assert_true(n > 24 && n < sizeof b);
	size_t pos = 24;
	int seen = 0;
	while (pos + 28 <= n) {
		if (rd32(b + pos + 4) == 0x0Au && seen++ == bad)
			break;
		pos += (size_t)rd32(b + pos + 12) + rd32(b + pos + 16);
	}
	assert_true(pos + 28 <= n);
	size_t payload = pos + rd32(b + pos + 12);
	b[payload] = 0xFF;
	b[payload + 1] = 0x7F;
	f = fopen(path, "wb");
	assert_non_null(f);
	assert_int_equal(fwrite(b, 1, n, f), n);
	fclose(f);
}

/*
 * A frame that cannot be decoded fails its read and is skipped: the next read
 * delivers the frame after it, so a looping recording plays every good frame
 * instead of starting over before the bad one forever.
 */
static void test_bad_frame_skipped(void **state)
{
	(void)state;
	char path[600];
	snprintf(path, sizeof path, "%s/corrupt.oni", dao_test_tmpdir("source-oni-corrupt"));
	write_corrupt_oni(path, 2);
	struct dao_source_options o = {.size = sizeof(struct dao_source_options), .loop = 1};
	struct dao_source *s = open_src(path, &o);
	long long expect[] = {0, 1, -1000 - EINVAL, 3, 4, 5, 0, 1, -1000 - EINVAL, 3};
	for (size_t i = 0; i < sizeof expect / sizeof expect[0]; i++)
		assert_int_equal(read_index(s), expect[i]);
	dao_source_close(s);

	/* a truncated PNG in a directory: the same */
	const char *dir = write_pngs("images-corrupt", 4, 99);
	char png[700];
	snprintf(png, sizeof png, "%s/01.png", dir);
	assert_int_equal(truncate(png, 40), 0);
	char uri[700];
	snprintf(uri, sizeof uri, "images:%s", dir);
	s = open_src(uri, &o);
	struct dao_error err;
	struct dao_source_frame f;
	long long want[] = {0, -1, 2, 3, 0, -1, 2, 3}; /* -1: an error naming the file */
	for (int i = 0; i < 8; i++) {
		int r = dao_source_read(s, &f, 1000, &err);
		if (want[i] < 0) {
			if (r >= 0)
				fail_msg("images read %d: %d, expected an error", i, r);
			assert_non_null(strstr(err.message, "01.png"));
			continue;
		}
		assert_int_equal(r, 0);
		assert_int_equal(f.index, want[i]);
		assert_true(test_is_frame(&f.depth, (uint32_t)f.index));
		dao_source_release(s, &f);
	}
	dao_source_close(s);
}

/*
 * A looping recording none of whose frames can be read: each fails once, then
 * the reads end in -EIO with a message, instead of failing forever.
 */
static void test_all_frames_bad(void **state)
{
	(void)state;
	char dir[600], png[700], uri[700];
	snprintf(dir, sizeof dir, "%s", write_pngs("images-all-bad", 3, 99));
	struct dao_source_options o = {.size = sizeof(struct dao_source_options), .loop = 1};
	snprintf(uri, sizeof uri, "images:%s", dir);
	struct dao_source *s = open_src(uri, &o); /* the first image sets the size */
	for (int i = 0; i < 3; i++) {
		snprintf(png, sizeof png, "%s/%02d.png", dir, i);
		assert_int_equal(truncate(png, 40), 0);
	}
	struct dao_source_frame f;
	struct dao_error err;
	for (int i = 0; i < 3; i++) {
		assert_int_equal(dao_source_read(s, &f, 1000, &err), -EINVAL);
		snprintf(png, sizeof png, "%02d.png", i);
		assert_non_null(strstr(err.message, png));
	}
	for (int i = 0; i < 3; i++) {
		int r = dao_source_read(s, &f, 1000, &err);
		if (r != -EIO)
			fail_msg("read %d after a pass of bad frames: %d (%s), expected -EIO", i, r,
				 err.message);
		assert_non_null(strstr(err.message, "no frame can be read: all 3 from frame 0"));
		assert_non_null(strstr(err.message, "02.png"));
	}
	dao_source_close(s);
}

/* AO of the whole Kinect recording: its camera from the recorded FOV, sane, deterministic. */
static void test_kinect_recording_ao(void **state)
{
	(void)state;
	char path[512];
	if (dao_test_data_path("oni/3DJ_test.oni", path, sizeof path)) {
		printf("../shared/data/oni/3DJ_test.oni is absent; skipped\n");
		skip();
	}
	struct dao_source *s = open_src(path, NULL);
	struct dao_source_info in;
	dao_source_get_info(s, &in);
	struct dao_camera cam;
	struct dao_error err;
	assert_true(in.has_fov);
	assert_int_equal(dao_camera_from_fov(&cam, in.width, in.height, in.hfov, in.vfov, &err), 0);
	assert_float_equal(cam.fx, 575.8, 0.1); /* the README of ../shared/data */
	assert_float_equal(cam.fy, 575.8, 0.1);
	assert_float_equal(cam.cx, 319.5, 1e-9);
	assert_float_equal(cam.cy, 239.5, 1e-9);
	struct dao_context *ctx[2];
	struct dao_frame ao[2];
	for (int k = 0; k < 2; k++) {
		assert_int_equal(dao_context_create(&ctx[k], &cam, NULL, &err), 0);
		assert_int_equal(dao_frame_alloc(&ao[k], DAO_PIXFMT_GRAY_F32, 640, 480, &err), 0);
	}
	int frames = 0;
	struct dao_source_frame f;
	while (dao_source_read(s, &f, 1000, &err) == 0) {
		double sum = 0;
		for (int k = 0; k < 2; k++)
			assert_int_equal(dao_context_process(ctx[k], &f.depth, NULL, f.index, &ao[k], &err), 0);
		const float *a = ao[0].data, *b = ao[1].data;
		for (size_t i = 0; i < 640 * 480; i++) {
			assert_true(a[i] >= 0.0f && a[i] <= 1.0f); /* also false for NaN */
			assert_true(a[i] == b[i]);                 /* deterministic */
			sum += a[i];
		}
		double mean = sum / (640 * 480);
		assert_true(mean > 0.5 && mean < 0.99); /* an indoor scene: mostly open, some occlusion */
		frames++;
	}
	assert_int_equal(frames, 12);
	for (int k = 0; k < 2; k++) {
		dao_frame_free(&ao[k]);
		dao_context_destroy(ctx[k]);
	}
	dao_source_close(s);
}

static void test_modules_skipped_with_reason(void **state)
{
	(void)state;
	const char *dir = getenv("DAO_FAKE_PLUGIN_DIR");
	if (!dir)
		skip();
	struct dao_plugins *p;
	struct dao_error err;
	assert_int_equal(dao_plugins_load(&p, dir, &err), 0);
	assert_non_null(dao_plugins_find(p, "fakesink"));
	assert_null(dao_plugins_find(p, "wrongabi"));
	assert_null(dao_plugins_find(p, "noversion"));
	assert_null(dao_plugins_find(p, "smalldesc"));
	assert_null(dao_plugins_find(p, "futuredesc"));
	assert_null(dao_plugins_find(p, "nostart"));
	assert_null(dao_plugins_find(p, "nowrite"));
	/* a source or sink with only the optional callbacks left out loads */
	assert_non_null(dao_plugins_find(p, "fakebig"));
	int abi = 0, nosym = 0, nover = 0, small = 0, future = 0, nostart = 0, nowrite = 0;
	for (size_t i = 0; i < dao_plugins_skipped_count(p); i++) {
		const char *m = dao_plugins_skipped(p, i);
		abi += strstr(m, "fake-wrongabi.so") && strstr(m, "ABI") ? 1 : 0;
		nosym += strstr(m, "fake-nosymbol.so") && strstr(m, "not a depthao plugin") ? 1 : 0;
		nover += strstr(m, "fake-noversion.so") && strstr(m, "DAO_SOURCE_OPS_VERSION") ? 1 : 0;
		/* the descriptor's size and version, each with what to do */
		small += strstr(m, "fake-smalldesc.so") && strstr(m, "8 bytes") &&
				 strstr(m, "DAO_PLUGIN_HEADER") ? 1 : 0;
		future += strstr(m, "fake-futuredesc.so") && strstr(m, "version 2") &&
				  strstr(m, "update depthao") ? 1 : 0;
		/* a callback the host would call unchecked: each one missing named, what a
		 * source or sink must have, what to do */
		nostart += strstr(m, "fake-nostart.so: source 'nostart' has no start(), read(); "
				     "a source plugin must implement open, get_info, start, read "
				     "and close: add them and rebuild it (docs/sources.md") ? 1 : 0;
		nowrite += strstr(m, "fake-nowrite.so: sink 'nowrite' has no write(); a sink "
				     "plugin must implement open, negotiate, write and close: add "
				     "it and rebuild it") ? 1 : 0;
	}
	assert_int_equal(abi, 1);
	assert_int_equal(nosym, 1);
	assert_int_equal(nover, 1);
	assert_int_equal(small, 1);
	assert_int_equal(future, 1);
	assert_int_equal(nostart, 1);
	assert_int_equal(nowrite, 1);
	assert_int_equal(dao_plugins_skipped_count(p), 7);
	/* a sink is not a source */
	struct dao_source *s = NULL;
	assert_int_equal(dao_source_open(p, "fakesink:x", NULL, &s, &err), -ENOENT);
	/* opening a refused plugin by name says why it is not there */
	assert_int_equal(dao_source_open(p, "nostart:64x48", NULL, &s, &err), -ENOENT);
	assert_null(s);
	assert_non_null(strstr(err.message, "no source plugin 'nostart': "));
	assert_non_null(strstr(err.message, "fake-nostart.so: source 'nostart' has no start(), "
					    "read()"));
	struct dao_sink *k = NULL;
	assert_int_equal(dao_sink_open(p, "nowrite:x", &k, &err), -ENOENT);
	assert_null(k);
	assert_non_null(strstr(err.message, "no sink plugin 'nowrite': "));
	assert_non_null(strstr(err.message, "sink 'nowrite' has no write()"));
	/* the source with only the required callbacks streams */
	assert_int_equal(dao_source_open(p, "fakebig:64x48", NULL, &s, &err), 0);
	assert_int_equal(dao_source_start(s, &err), 0);
	struct dao_source_frame f;
	assert_int_equal(dao_source_read(s, &f, 100, &err), 0);
	assert_true(f.depth.width == 64 && f.depth.height == 48);
	assert_int_equal(((const uint16_t *)f.depth.data)[64 * 48 - 1], 1000);
	dao_source_release(s, &f); /* no release callback: nothing to give back */
	assert_int_equal(dao_source_seek(s, 0, &err), -ENOTSUP);
	dao_source_close(s); /* no stop callback */
	/* a missing source is an error, not a crash */
	assert_int_equal(dao_source_start(NULL, &err), -EINVAL);
	assert_non_null(strstr(err.message, "dao_source_open"));
	assert_int_equal(dao_source_read(NULL, &f, 0, &err), -EINVAL);
	dao_plugins_free(p);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_builtins_listed),
		cmocka_unit_test(test_info_and_auto_pick),
		cmocka_unit_test(test_unfinished_recording),
		cmocka_unit_test(test_manual_every_frame_once),
		cmocka_unit_test(test_loop_wraps),
		cmocka_unit_test(test_start_step_seek),
		cmocka_unit_test(test_realtime_delivers_all),
		cmocka_unit_test(test_open_errors),
		cmocka_unit_test(test_images_source),
		cmocka_unit_test(test_images_realtime_step),
		cmocka_unit_test(test_bad_frame_skipped),
		cmocka_unit_test(test_all_frames_bad),
		cmocka_unit_test(test_kinect_recording_ao),
		cmocka_unit_test(test_modules_skipped_with_reason),
	};
	return cmocka_run_group_tests(tests, setup, teardown);
}
