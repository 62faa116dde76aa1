/* SPDX-License-Identifier: MIT */
/*
 * The OpenNI2 source plugin against OpenNI2 itself: recordings written by
 * depthao play back frame-exactly (every codec), the real Kinect recording
 * reads the same through OpenNI2 and through depthao's reader, the playback
 * modes (manual, loop, start, step, seek back and forth, end of file), and
 * the Dummy device as a live source.  SKIP when the plugin was not built.
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include <cmocka.h>

#include "common/test_common.h"
#include "synth/suite.h"
#include "synth/synth.h"
#include "source_test_util.h"

#define FRAMES 6

static struct dao_plugins *g_plugins;
static char g_dir[400];

static struct dao_source *open_src(const char *uri, const struct dao_source_options *o)
{
	return test_open_started(g_plugins, uri, o);
}

static void recording(char *buf, size_t len, const char *codec_name)
{
	enum dao_oni_codec c;
	assert_int_equal(dao_oni_codec_from_name(codec_name, &c), 0);
	snprintf(buf, len, "openni2:%s/%s.oni", g_dir, codec_name);
	if (access(buf + 8, R_OK) != 0)
		assert_int_equal(test_write_oni(buf + 8, FRAMES, c), 0);
}

/* Next frame's index (checking its pixels), or -1000 + status. */
static long long next(struct dao_source *s)
{
	struct dao_source_frame f;
	struct dao_error err;
	int r = dao_source_read(s, &f, 3000, &err);
	if (r != 0) {
		if (r < 0)
			fprintf(stderr, "read: %s\n", err.message);
		return -1000 + r;
	}
	assert_true(test_is_frame(&f.depth, (uint32_t)f.index));
	assert_int_equal(f.depth.sequence, f.index + 1);
	assert_int_equal(f.depth.timestamp_ns, (1000 + f.index * 33333) * 1000);
	dao_source_release(s, &f);
	return (long long)f.index;
}

static void test_round_trip_every_codec(void **state)
{
	(void)state;
	const char *codecs[] = {"none", "16z", "16zt"};
	for (int c = 0; c < 3; c++) {
		char uri[512];
		recording(uri, sizeof uri, codecs[c]);
		struct dao_source *s = open_src(uri, NULL);
		assert_string_equal(dao_source_plugin(s)->name, "openni2");
		struct dao_source_info in;
		dao_source_get_info(s, &in);
		assert_int_equal(in.width, TEST_W);
		assert_int_equal(in.height, TEST_H);
		assert_int_equal(in.frame_count, FRAMES);
		assert_float_equal(in.depth_unit, 0.001, 1e-9);
		assert_true(in.has_fov);
		assert_float_equal(in.hfov, 1.0, 1e-6); /* OpenNI2 keeps it as float */
		assert_float_equal(in.vfov, 0.75, 1e-6);
		for (long long i = 0; i < FRAMES; i++)
			assert_int_equal(next(s), i);
		assert_int_equal(next(s), -1000 + DAO_SOURCE_EOS);
		dao_source_close(s);
	}
}

/* depthao synth's noisy spheres (the sphere rolling) -> .oni per codec -> OpenNI2 -> same depth. */
static void test_synth_scene_round_trip(void **state)
{
	(void)state;
	enum { N = 3 };
	struct dao_camera cam;
	struct synth_case cases[N];
	struct dao_error err;
	synth_default_camera(&cam);
	for (int i = 0; i < N; i++) {
		struct synth_scene sc;
		struct synth_image img;
		assert_int_equal(synth_scene_build("spheres", i / (double)(N - 1), &sc, &err), 0);
		assert_int_equal(synth_render(&sc, &cam, 0.5, 1, 2, &img, &err), 0);
		memset(&cases[i], 0, sizeof(cases[i]));
		assert_int_equal(synth_case_make(&cases[i], sc.name, 1, img.depth, img.gt, 640, 480,
						 7 + (uint64_t)i, &err), 0);
		synth_image_free(&img);
	}
	assert_true(memcmp(cases[0].depth_mm, cases[N - 1].depth_mm, 640 * 480 * 2) != 0);
	const enum dao_oni_codec codecs[] = {DAO_ONI_CODEC_NONE, DAO_ONI_CODEC_16Z, DAO_ONI_CODEC_16ZT};
	for (int c = 0; c < 3; c++) {
		char uri[600];
		snprintf(uri, sizeof uri, "openni2:%s/spheres-%s.oni", g_dir, dao_oni_codec_name(codecs[c]));
		struct dao_oni_writer_options o = DAO_ONI_WRITER_OPTIONS_INIT;
		o.width = 640;
		o.height = 480;
		o.fps = 30;
		o.codec = codecs[c];
		o.pixel_format = DAO_ONI_PIXEL_DEPTH_1_MM;
		dao_camera_fov(&cam, &o.hfov, &o.vfov);
		struct dao_oni_writer *w;
		assert_int_equal(dao_oni_writer_open(uri + 8, &o, &w, &err), 0);
		for (int i = 0; i < N; i++) {
			struct dao_frame d = {.format = DAO_PIXFMT_DEPTH16, .width = 640,
					.height = 480, .stride = 1280, .data = cases[i].depth_mm,
					      .depth_unit = 0.001f};
			assert_int_equal(dao_oni_writer_write_depth(w, &d, (uint64_t)i * 33333, &err), 0);
		}
		assert_int_equal(dao_oni_writer_finish(w, &err), 0);
		struct dao_source *s = open_src(uri, NULL);
		for (int i = 0; i < N; i++) {
			struct dao_source_frame f;
			assert_int_equal(dao_source_read(s, &f, 3000, &err), 0);
			assert_int_equal(f.index, (uint64_t)i);
			for (uint32_t y = 0; y < 480; y++)
				assert_memory_equal((uint8_t *)f.depth.data + (size_t)y * (size_t)f.depth.stride,
						    cases[i].depth_mm + (size_t)y * 640, 1280);
		}
		dao_source_close(s);
	}
	for (int i = 0; i < N; i++)
		synth_case_free(&cases[i]);
}

static void test_loop_and_stop_at_end(void **state)
{
	(void)state;
	char uri[512];
	recording(uri, sizeof uri, "16z");
	struct dao_source_options o = {.size = sizeof(struct dao_source_options), .loop = 1};
	struct dao_source *s = open_src(uri, &o);
	for (long long i = 0; i < 2 * FRAMES + 2; i++)
		assert_int_equal(next(s), i % FRAMES);
	dao_source_close(s);

	/* at the end the player is parked: with repeat off OpenNI2 would spin a core */
	s = open_src(uri, NULL);
	for (long long i = 0; i < FRAMES; i++)
		assert_int_equal(next(s), i);
	assert_int_equal(next(s), -1000 + DAO_SOURCE_EOS);
	struct rusage a, b;
	getrusage(RUSAGE_SELF, &a);
	struct timespec nap = {0, 400 * 1000 * 1000};
	nanosleep(&nap, NULL);
	getrusage(RUSAGE_SELF, &b);
	double cpu_ms = (double)(b.ru_utime.tv_sec - a.ru_utime.tv_sec) * 1e3 +
			(double)(b.ru_utime.tv_usec - a.ru_utime.tv_usec) / 1e3 +
			(double)(b.ru_stime.tv_sec - a.ru_stime.tv_sec) * 1e3 +
			(double)(b.ru_stime.tv_usec - a.ru_stime.tv_usec) / 1e3;
	printf("CPU time in 400 ms after the end of the recording: %.1f ms\n", cpu_ms);
	assert_true(cpu_ms < 200.0);
	assert_int_equal(next(s), -1000 + DAO_SOURCE_EOS);
	dao_source_close(s);
}

static void test_start_step_seek(void **state)
{
	(void)state;
	char uri[512];
	struct dao_error err;
	recording(uri, sizeof uri, "16zt");
	struct dao_source_options o = {.size = sizeof(struct dao_source_options), .start_frame = 3};
	struct dao_source *s = open_src(uri, &o);
	assert_int_equal(next(s), 3);
	assert_int_equal(next(s), 4);
	assert_int_equal(dao_source_seek(s, 1, &err), 0); /* backwards: reopens */
	assert_int_equal(next(s), 1);
	assert_int_equal(dao_source_seek(s, 4, &err), 0); /* forwards: reads ahead */
	assert_int_equal(next(s), 4);
	assert_int_equal(next(s), 5);
	assert_int_equal(next(s), -1000 + DAO_SOURCE_EOS);
	assert_int_equal(dao_source_seek(s, 0, &err), 0); /* after the end */
	assert_int_equal(next(s), 0);
	assert_int_equal(dao_source_seek(s, FRAMES, &err), -EINVAL);
	dao_source_close(s);

	struct dao_source_options st = {.size = sizeof(struct dao_source_options), .start_frame = 1, .step = 2};
	s = open_src(uri, &st);
	assert_int_equal(next(s), 1);
	assert_int_equal(next(s), 3);
	assert_int_equal(next(s), 5);
	assert_int_equal(next(s), -1000 + DAO_SOURCE_EOS);
	dao_source_close(s);
}

static void test_kinect_both_readers_agree(void **state)
{
	(void)state;
	char path[512], uri[600];
	if (dao_test_data_path("oni/3DJ_test.oni", path, sizeof path)) {
		printf("../shared/data/oni/3DJ_test.oni is absent; skipped\n");
		skip();
	}
	snprintf(uri, sizeof uri, "openni2:%s", path);
	struct dao_source *ni = open_src(uri, NULL);
	snprintf(uri, sizeof uri, "oni:%s", path);
	struct dao_source *own = open_src(uri, NULL);
	struct dao_source_info a, b;
	dao_source_get_info(ni, &a);
	dao_source_get_info(own, &b);
	assert_int_equal(a.frame_count, 12);
	assert_int_equal(b.frame_count, 12);
	assert_float_equal(a.hfov, b.hfov, 1e-6);
	assert_float_equal(a.vfov, b.vfov, 1e-6);
	assert_int_equal(a.mirrored, 1);
	assert_int_equal(b.mirrored, 1);
	assert_int_equal(b.registered, 1);
	struct dao_error err;
	for (int i = 0; i < 12; i++) {
		struct dao_source_frame fa, fb;
		assert_int_equal(dao_source_read(ni, &fa, 3000, &err), 0);
		assert_int_equal(dao_source_read(own, &fb, 3000, &err), 0);
		assert_int_equal(fa.index, (uint64_t)i);
		assert_int_equal(fb.index, (uint64_t)i);
		assert_int_equal(fa.depth.timestamp_ns, fb.depth.timestamp_ns);
		assert_int_equal(fa.depth.sequence, fb.depth.sequence);
		for (uint32_t y = 0; y < 480; y++)
			assert_memory_equal((uint8_t *)fa.depth.data + (size_t)y * (size_t)fa.depth.stride,
					    (uint8_t *)fb.depth.data + (size_t)y * (size_t)fb.depth.stride,
					    640 * 2);
	}
	struct dao_source_frame f;
	assert_int_equal(dao_source_read(ni, &f, 3000, &err), DAO_SOURCE_EOS);
	assert_int_equal(dao_source_read(own, &f, 3000, &err), DAO_SOURCE_EOS);
	dao_source_close(ni);
	dao_source_close(own);
}

static void test_kinect_colour(void **state)
{
	(void)state;
	char path[512], uri[600];
	if (dao_test_data_path("oni/3DJ_test.oni", path, sizeof path))
		skip();
	snprintf(uri, sizeof uri, "openni2:%s", path);
	struct dao_source_options o = {.size = sizeof(struct dao_source_options), .want_color = 1};
	struct dao_source *s = open_src(uri, &o);
	struct dao_source_info in;
	dao_source_get_info(s, &in);
	assert_int_equal(in.has_color, 1);
	assert_int_equal(in.color_width, 640);
	assert_int_equal(in.color_height, 480);
	struct dao_error err;
	int with_colour = 0, frames = 0;
	struct dao_source_frame f;
	while (dao_source_read(s, &f, 3000, &err) == 0) {
		frames++;
		if (f.color.format == DAO_PIXFMT_RGB24) {
			assert_int_equal(f.color.width, 640);
			/* a real picture: not all one value */
			const uint8_t *p = f.color.data;
			int varied = 0;
			for (size_t i = 3; i < 640 * 3 && !varied; i++)
				varied = p[i] != p[0];
			assert_true(varied);
			with_colour++;
		}
	}
	printf("%d depth frames, %d with colour\n", frames, with_colour);
	assert_int_equal(frames, 12);
	assert_true(with_colour >= 6);
	dao_source_close(s);
}

static void test_dummy_device_live(void **state)
{
	(void)state;
	struct dao_source *s = open_src("openni2:Dummy", NULL);
	struct dao_source_info in;
	dao_source_get_info(s, &in);
	assert_int_equal(in.live, 1);
	assert_int_equal(in.frame_count, -1);
	assert_int_equal(in.width, 320);
	assert_int_equal(in.height, 240);
	assert_true(in.depth_unit > 0);
	uint64_t last = 0;
	struct dao_error err;
	for (int i = 0; i < 5; i++) {
		struct dao_source_frame f;
		assert_int_equal(dao_source_read(s, &f, 3000, &err), 0);
		assert_int_equal(f.depth.width, 320);
		assert_true(f.depth.sequence > last);
		last = f.depth.sequence;
		assert_int_equal(f.index, (uint64_t)i);
		dao_source_release(s, &f);
	}
	assert_int_equal(dao_source_seek(s, 0, &err), -ENOTSUP);
	dao_source_close(s); /* and the process must exit cleanly after this */
}

static void test_open_errors(void **state)
{
	(void)state;
	struct dao_source *s = NULL;
	struct dao_error err;
	assert_int_equal(dao_source_open(g_plugins, "openni2:/nonexistent/a.oni", NULL, &s, &err),
			 -ENOENT);
	assert_non_null(strstr(err.message, "/nonexistent/a.oni"));
	assert_int_equal(dao_source_open(g_plugins, "openni2:no-such-device-uri", NULL, &s, &err),
			 -ENODEV);
	assert_non_null(strstr(err.message, "cannot open"));
	assert_null(s);
}

int main(void)
{
	const char *dir = getenv("DAO_OPENNI2_PLUGIN_DIR");
	struct dao_error err;
	if (!dir) {
		printf("the openni2 plugin was not built; skipped\n");
		return DAO_TEST_SKIP;
	}
	if (dao_plugins_load(&g_plugins, dir, &err) || !dao_plugins_find(g_plugins, "openni2")) {
		printf("the openni2 plugin did not load from %s\n", dir);
		for (size_t i = 0; i < dao_plugins_skipped_count(g_plugins); i++)
			printf("  %s\n", dao_plugins_skipped(g_plugins, i));
		return 1;
	}
	snprintf(g_dir, sizeof g_dir, "%s", dao_test_tmpdir("openni2"));
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_round_trip_every_codec),
		cmocka_unit_test(test_synth_scene_round_trip),
		cmocka_unit_test(test_loop_and_stop_at_end),
		cmocka_unit_test(test_start_step_seek),
		cmocka_unit_test(test_kinect_both_readers_agree),
		cmocka_unit_test(test_kinect_colour),
		cmocka_unit_test(test_dummy_device_live),
		cmocka_unit_test(test_open_errors),
	};
	int r = cmocka_run_group_tests(tests, NULL, NULL);
	dao_plugins_free(g_plugins);
	return r;
}
