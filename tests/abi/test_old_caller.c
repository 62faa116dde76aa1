/* SPDX-License-Identifier: MIT */
/*
 * An old program against this library (docs/abi.md): callers whose structs
 * are laid out as before fields were appended (here: dao_timings without
 * noise_ms, dao_noise_info without age and cells_measured, the writer's
 * status without bytes), built only against the public headers and linked
 * with the shared library as a program is.  Each struct sits between guard
 * bytes: the library fills what the caller's size holds and writes nothing
 * past it.  Newer callers (longer structs) get this library's fields and
 * size back, and input structs of sizes it cannot take are refused before
 * anything is written.  The entry points whose structs changed at 1.0 are
 * not exported under their old names, so a program built before 1.0 fails
 * to load instead of being written over.
 */
#define _GNU_SOURCE /* RTLD_DEFAULT */
#include <dlfcn.h>
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

#define GUARD 0x5a
#define W 64
#define H 48

/* `n` bytes at `p` all still GUARD. */
static int untouched(const void *p, size_t n)
{
	const unsigned char *b = p;
	for (size_t i = 0; i < n; i++)
		if (b[i] != GUARD)
			return 0;
	return 1;
}

/* dao_timings as a program built before noise_ms was appended lays it out. */
struct old_timings {
	uint32_t size;
	double decode_ms, prefilter_ms, normals_ms, gtao_ms, denoise_ms, output_ms, process_ms,
		shade_ms;
};

/* dao_noise_info before age and cells_measured (noise-interval) were appended. */
struct old_noise_info {
	uint32_t size;
	int measured;
	float sigma_area, sigma_link, prefilter_scale;
	int normal_radius;
	float denoise_noise, sigma_slope;
};

/* A context that has processed one frame: a tilted plane 1.5 m away, with noise. */
static struct dao_context *processed_context(void)
{
	struct dao_camera cam;
	struct dao_error err;
	assert_int_equal(dao_camera_from_intrinsics(&cam, W, H, 60, 60, 31.5, 23.5, &err), 0);
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.threads = 1;
	struct dao_context *ctx = NULL;
	assert_int_equal(dao_context_create(&ctx, &cam, &p, &err), 0);
	static uint16_t depth[W * H];
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++)
			depth[y * W + x] = (uint16_t)(1500 + 4 * x + (x * 7 + y * 13) % 5);
	/* positional, as programs built before `size` was in struct dao_frame wrote it
	 * (-Wextra warns about the fields it leaves out; they are 0: the first layout) */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
	struct dao_frame d = {DAO_PIXFMT_DEPTH16, W, H, W * 2, depth, 0.001f, 0, 0};
#pragma GCC diagnostic pop
	static float ao[W * H];
	struct dao_frame a = DAO_FRAME_INIT;
	a.format = DAO_PIXFMT_GRAY_F32;
	a.width = W;
	a.height = H;
	a.stride = W * 4;
	a.data = ao;
	assert_int_equal(dao_context_process(ctx, &d, NULL, 0, &a, &err), 0);
	return ctx;
}

static void test_timings(void **state)
{
	(void)state;
	struct dao_context *ctx = processed_context();
	struct dao_timings now = DAO_TIMINGS_INIT;
	dao_context_timings(ctx, &now);
	assert_int_equal(now.size, sizeof now);
	assert_true(now.process_ms > 0);

	/* what an old program's dao_context_timings() compiles to */
	struct {
		struct old_timings t;
		unsigned char guard[64];
	} old;
	memset(&old, GUARD, sizeof old);
	assert_true(sizeof old.t < sizeof now); /* the library's struct is longer */
	assert_int_equal(dao_context_timings_sized(ctx, (struct dao_timings *)&old.t,
						   sizeof old.t), 0);
	assert_int_equal(old.t.size, sizeof old.t);
	assert_true(old.t.process_ms == now.process_ms && old.t.gtao_ms == now.gtao_ms &&
		    old.t.shade_ms == now.shade_ms);
	assert_true(untouched(old.guard, sizeof old.guard));

	/* a size that ends inside a field, or holds only `size` */
	memset(&old, GUARD, sizeof old);
	const size_t cut = offsetof(struct old_timings, prefilter_ms) + 3;
	assert_int_equal(dao_context_timings_sized(ctx, (struct dao_timings *)&old.t, cut), 0);
	assert_int_equal(old.t.size, cut);
	assert_true(old.t.decode_ms == now.decode_ms);
	assert_true(untouched((unsigned char *)&old + cut, sizeof old - cut));
	memset(&old, GUARD, sizeof old);
	assert_int_equal(dao_context_timings_sized(ctx, (struct dao_timings *)&old.t, 4), 0);
	assert_int_equal(old.t.size, 4);
	assert_true(untouched((unsigned char *)&old + 4, sizeof old - 4));
	/* too small for `size` itself, or no struct: refused, nothing written */
	memset(&old, GUARD, sizeof old);
	assert_int_equal(dao_context_timings_sized(ctx, (struct dao_timings *)&old.t, 3), -EINVAL);
	assert_true(untouched(&old, sizeof old));
	assert_int_equal(dao_context_timings_sized(ctx, NULL, sizeof now), -EINVAL);

	/* a newer program's longer struct: this library's fields and size, nothing past */
	struct {
		struct dao_timings t;
		double later[4];
		unsigned char guard[16];
	} newer;
	memset(&newer, GUARD, sizeof newer);
	assert_int_equal(dao_context_timings_sized(ctx, &newer.t, offsetof(__typeof__(newer), guard)),
			 0);
	assert_int_equal(newer.t.size, sizeof newer.t);
	assert_true(newer.t.noise_ms == now.noise_ms);
	assert_true(untouched(newer.later, sizeof newer.later + sizeof newer.guard));
	dao_context_destroy(ctx);
}

static void test_noise_info(void **state)
{
	(void)state;
	struct dao_context *ctx = processed_context();
	struct dao_noise_info now = DAO_NOISE_INFO_INIT;
	dao_context_noise(ctx, &now);
	assert_int_equal(now.size, sizeof now);
	assert_int_equal(now.measured, 1); /* the default noise model measures it */

	struct {
		struct old_noise_info n;
		unsigned char guard[32];
	} old;
	memset(&old, GUARD, sizeof old);
	assert_true(sizeof old.n < sizeof now);
	assert_int_equal(dao_context_noise_sized(ctx, (struct dao_noise_info *)&old.n,
						 sizeof old.n), 0);
	assert_int_equal(old.n.size, sizeof old.n);
	assert_int_equal(old.n.measured, now.measured);
	assert_true(old.n.sigma_area == now.sigma_area && old.n.sigma_slope == now.sigma_slope);
	assert_int_equal(old.n.normal_radius, now.normal_radius);
	assert_true(untouched(old.guard, sizeof old.guard));
	dao_context_destroy(ctx);
}

/* The camera's makers write no more than the caller's size and refuse less than
 * the first layout; a longer (newer) struct gets this library's size back. */
static void test_camera(void **state)
{
	(void)state;
	struct dao_error err;
	struct {
		struct dao_camera c;
		double later[2];
		unsigned char guard[16];
	} cam;
	memset(&cam, GUARD, sizeof cam);
	assert_int_equal(dao_camera_from_fov_sized(&cam.c, offsetof(__typeof__(cam), guard), 64,
						   48, 1.0, 0.8, &err), 0);
	assert_int_equal(cam.c.size, sizeof cam.c);
	assert_true(cam.c.width == 64 && cam.c.fx > 0);
	assert_true(untouched(cam.later, sizeof cam.later + sizeof cam.guard));

	memset(&cam, GUARD, sizeof cam);
	assert_int_equal(dao_camera_from_intrinsics_sized(&cam.c, sizeof cam.c - 4, 64, 48, 60, 60,
							  31.5, 23.5, &err), -EINVAL);
	assert_non_null(strstr(err.message, "sizeof(struct dao_camera)"));
	assert_true(untouched(&cam, sizeof cam));
}

/* The recorder's options are read by their size, its status written by the caller's. */
static void test_oni_writer(void **state)
{
	(void)state;
	char dir[] = "/tmp/dao-abi-XXXXXX";
	assert_non_null(mkdtemp(dir));
	char path[64];
	snprintf(path, sizeof path, "%s/x.oni", dir);
	struct dao_error err;
	struct dao_oni_writer *w = NULL;

	struct dao_oni_writer_options none;
	memset(&none, 0, sizeof none);
	none.width = W; /* options without their size: refused, saying what to do */
	assert_int_equal(dao_oni_writer_open(path, &none, &w, &err), -EINVAL);
	assert_non_null(strstr(err.message, "DAO_ONI_WRITER_OPTIONS_INIT"));
	assert_null(w);
	struct {
		struct dao_oni_writer_options o;
		int later[2];
	} newer;
	memset(&newer, 0, sizeof newer);
	newer.o = (struct dao_oni_writer_options)DAO_ONI_WRITER_OPTIONS_INIT;
	newer.o.size = sizeof newer; /* settings this library cannot honour */
	assert_int_equal(dao_oni_writer_open(path, &newer.o, &w, &err), -EINVAL);
	assert_null(w);
	assert_true(access(path, F_OK) != 0); /* nothing created */

	struct dao_oni_writer_options o = DAO_ONI_WRITER_OPTIONS_INIT;
	o.width = W;
	o.height = H;
	o.fps = 30;
	o.codec = DAO_ONI_CODEC_16Z;
	o.pixel_format = DAO_ONI_PIXEL_DEPTH_1_MM;
	o.hfov = 1.0;
	o.vfov = 0.8;
	assert_int_equal(dao_oni_writer_open(path, &o, &w, &err), 0);
	static uint16_t depth[W * H];
	for (int i = 0; i < W * H; i++)
		depth[i] = (uint16_t)(1000 + i % 50);
	struct dao_frame d = {.format = DAO_PIXFMT_DEPTH16, .width = W, .height = H,
			      .stride = W * 2, .data = depth, .depth_unit = 0.001f};
	assert_int_equal(dao_oni_writer_write_depth(w, &d, 0, &err), 0);
	assert_int_equal(dao_oni_writer_write_depth(w, &d, 33333, &err), 0);

	/* the status of a program built before `bytes` */
	struct {
		struct dao_oni_writer_status st;
		unsigned char guard[16];
	} old;
	memset(&old, GUARD, sizeof old);
	const size_t old_size = offsetof(struct dao_oni_writer_status, bytes);
	assert_int_equal(dao_oni_writer_get_status_sized(w, &old.st, old_size), 0);
	assert_int_equal(old.st.size, old_size);
	assert_int_equal(old.st.frames, 2);
	assert_int_equal(old.st.error, 0);
	assert_true(untouched((unsigned char *)&old + old_size, sizeof old - old_size));
	struct dao_oni_writer_status st = DAO_ONI_WRITER_STATUS_INIT;
	dao_oni_writer_get_status(w, &st);
	assert_int_equal(st.size, sizeof st);
	assert_true(st.frames == 2 && st.bytes > 0);
	assert_int_equal(dao_oni_writer_finish(w, &err), 0);
	unlink(path);
	rmdir(dir);
}

/* struct dao_frame keeps its size (it is embedded in struct dao_source_frame);
 * the library's own frames say which fields they hold. */
static void test_frame(void **state)
{
	(void)state;
	assert_int_equal(sizeof(struct dao_frame), 88);
	assert_int_equal(DAO_FRAME_SIZE, 52);
	assert_int_equal(offsetof(struct dao_frame, size), 48);
	struct dao_error err;
	struct dao_frame f;
	memset(&f, GUARD, sizeof f);
	assert_int_equal(dao_frame_alloc(&f, DAO_PIXFMT_GRAY8, 8, 4, &err), 0);
	assert_int_equal(f.size, DAO_FRAME_SIZE);
	assert_int_equal(f.reserved0, 0);
	for (int i = 0; i < 4; i++)
		assert_true(f.reserved[i] == 0);
	dao_frame_free(&f);
}

/* The plugin descriptor: its ABI, size and version, as DAO_PLUGIN_HEADER sets them. */
static void test_plugin_descriptor(void **state)
{
	(void)state;
	static const struct dao_sink_ops ops = {.version = DAO_SINK_OPS_VERSION};
	static const struct dao_plugin pl = {DAO_PLUGIN_HEADER, .name = "x", .sink = &ops};
	assert_int_equal(offsetof(struct dao_plugin, abi_version), 0);
	assert_int_equal(pl.abi_version, DAO_PLUGIN_ABI_VERSION);
	assert_int_equal(pl.size, sizeof(struct dao_plugin));
	assert_int_equal(pl.version, DAO_PLUGIN_VERSION);
}

/* Pre-1.0 entry points whose structs changed are gone: a program built against
 * them does not load (an undefined symbol) instead of being written over. */
static void test_old_entry_points_gone(void **state)
{
	(void)state;
	static const char *const gone[] = {
		"dao_context_timings", "dao_context_noise", "dao_camera_from_intrinsics",
		"dao_camera_from_fov", "dao_camera_from_camera_info", "dao_oni_writer_get_status",
	};
	for (size_t i = 0; i < sizeof gone / sizeof gone[0]; i++) {
		if (dlsym(RTLD_DEFAULT, gone[i])) {
			/* (fputs: gcc 12 with UBSan's checks saw a null %s argument here) */
			fputs(gone[i], stdout);
			fputs(" is still exported\n", stdout);
		}
		assert_null(dlsym(RTLD_DEFAULT, gone[i]));
	}
	/* and what replaced them is */
	assert_non_null(dlsym(RTLD_DEFAULT, "dao_context_timings_sized"));
	assert_non_null(dlsym(RTLD_DEFAULT, "dao_camera_from_fov_sized"));
}

static void test_version(void **state)
{
	(void)state;
	assert_string_equal(dao_version(), DAO_VERSION_STRING); /* built and run together */
	char v[32];
	snprintf(v, sizeof v, "%d.%d.%d", DAO_VERSION_MAJOR, DAO_VERSION_MINOR, DAO_VERSION_MICRO);
	assert_string_equal(v, DAO_VERSION_STRING);
	assert_true(DAO_VERSION_MAJOR >= 1);
	assert_true(DAO_CHECK_VERSION(1, 0, 0));
	assert_true(DAO_CHECK_VERSION(DAO_VERSION_MAJOR, DAO_VERSION_MINOR, DAO_VERSION_MICRO));
	assert_false(DAO_CHECK_VERSION(DAO_VERSION_MAJOR, DAO_VERSION_MINOR, DAO_VERSION_MICRO + 1));
	assert_false(DAO_CHECK_VERSION(DAO_VERSION_MAJOR, DAO_VERSION_MINOR + 1, 0));
	assert_false(DAO_CHECK_VERSION(DAO_VERSION_MAJOR + 1, 0, 0));
	/* the soname's major is the version's */
	char so[32];
	snprintf(so, sizeof so, "libdepthao.so.%d", DAO_VERSION_MAJOR);
	void *h = dlopen(so, RTLD_NOW | RTLD_NOLOAD);
	if (!h)
		printf("%s is not the loaded library's soname: %s\n", so, dlerror());
	assert_non_null(h);
	dlclose(h);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_timings),
		cmocka_unit_test(test_noise_info),
		cmocka_unit_test(test_camera),
		cmocka_unit_test(test_oni_writer),
		cmocka_unit_test(test_frame),
		cmocka_unit_test(test_plugin_descriptor),
		cmocka_unit_test(test_old_entry_points_gone),
		cmocka_unit_test(test_version),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
