/* SPDX-License-Identifier: MIT */
/*
 * The ABI growth path (plugin.h "Growing the interface", params.h, README
 * "ABI policy"): the first layouts of the extensible structs are frozen
 * (every field keeps its offset; a struct has no tail padding a later field
 * could fall into), and the library reads and writes no more of a caller's
 * or plugin's struct than its `size` says, in both directions: structs from
 * an older program (shorter) and from a newer one (longer), ops tables of a
 * newer plugin (loaded, used by what this library knows) and of one that
 * forgot its version (refused: test_source_oni.c).
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <depthao/depthao.h>
#include <depthao/io.h>
#include <depthao/plugin.h>

#include "params/params_abi.h"
#include "plugin/struct_sizes.h"

#define POISON 0xab

struct frozen {
	const char *name;
	size_t offset, frozen;
};

#define F(st, field, off) { #st "." #field, offsetof(struct st, field), off }

/* The first extensible layouts (plugin ABI 2 for the plugin structs, depthao
 * 1.0 and plugin ABI 3 for the rest; symbol version DEPTHAO_1) on LP64
 * targets: a field may be appended after the last one of its struct (for
 * dao_frame: into its reserved space), never inserted, moved or resized.
 * Adding one: append it to the struct and to this table, give the struct
 * explicit padding if it would end in padding. */
static const struct frozen layout[] = {
	F(dao_params, size, 0),
	F(dao_params, depth_min, 4),
	F(dao_params, depth_max, 8),
	F(dao_params, prefilter, 12),
	F(dao_params, depth_noise, 16),
	F(dao_params, prefilter_radius, 20),
	F(dao_params, prefilter_scale, 24),
	F(dao_params, prefilter_range, 28),
	F(dao_params, prefilter_iterations, 32),
	F(dao_params, noise_model, 36),
	F(dao_params, normals, 40),
	F(dao_params, normal_radius, 44),
	F(dao_params, algorithm, 48),
	F(dao_params, radius, 52),
	F(dao_params, falloff, 56),
	F(dao_params, slices, 60),
	F(dao_params, steps, 64),
	F(dao_params, thickness, 68),
	F(dao_params, max_screen_radius, 72),
	F(dao_params, min_screen_radius, 76),
	F(dao_params, distribution_power, 80),
	F(dao_params, noise, 84),
	F(dao_params, final_power, 88),
	F(dao_params, albedo, 92),
	F(dao_params, invalid_value, 96),
	F(dao_params, strength, 100),
	F(dao_params, hbao_bias, 104),
	F(dao_params, ssao_min, 108),
	F(dao_params, ssao_max, 112),
	F(dao_params, edl_radius, 116),
	F(dao_params, vbao_thickness, 120),
	F(dao_params, temporal, 124),
	F(dao_params, temporal_reject, 128),
	F(dao_params, depth_temporal, 132),
	F(dao_params, depth_temporal_reject, 136),
	F(dao_params, depth_temporal_persist, 140),
	F(dao_params, threads, 144),
	F(dao_params, simd, 148),
	F(dao_params, denoise, 152),
	F(dao_params, denoise_radius, 156),
	F(dao_params, denoise_sharpness, 160),
	F(dao_params, shade, 164),
	F(dao_params, near_m, 168),
	F(dao_params, far_m, 172),
	F(dao_params, shade_power, 176),
	F(dao_params, occlusion_color, 180),
	F(dao_source_info, size, 0),
	F(dao_source_info, width, 4),
	F(dao_source_info, height, 8),
	F(dao_source_info, format, 12),
	F(dao_source_info, depth_unit, 16),
	F(dao_source_info, has_fov, 20),
	F(dao_source_info, hfov, 24),
	F(dao_source_info, vfov, 32),
	F(dao_source_info, fps, 40),
	F(dao_source_info, frame_count, 48),
	F(dao_source_info, live, 56),
	F(dao_source_info, mirrored, 60),
	F(dao_source_info, registered, 64),
	F(dao_source_info, has_color, 68),
	F(dao_source_info, color_width, 72),
	F(dao_source_info, color_height, 76),
	F(dao_source_info, description, 80),
	F(dao_source_info, warning, 240),
	F(dao_source_info, has_intrinsics, 496),
	F(dao_source_info, fx, 504),
	F(dao_source_info, fy, 512),
	F(dao_source_info, cx, 520),
	F(dao_source_info, cy, 528),
	F(dao_source_pose, size, 0),
	F(dao_source_pose, reserved, 4),
	F(dao_source_pose, rotation, 8),
	F(dao_source_pose, translation, 40),
	F(dao_source_pose, description, 64),
	F(dao_source_pose, warning, 224),
	F(dao_source_ops, frame_pose, 88),
	F(dao_source_options, size, 0),
	F(dao_source_options, playback, 4),
	F(dao_source_options, loop, 8),
	F(dao_source_options, start_frame, 12),
	F(dao_source_options, step, 16),
	F(dao_source_options, want_color, 20),
	F(dao_source_options, depth_unit, 24),
	F(dao_sink_format, size, 0),
	F(dao_sink_format, format, 4),
	F(dao_sink_format, width, 8),
	F(dao_sink_format, height, 12),
	F(dao_sink_format, fps, 16),
	F(dao_sink_format, depth_unit, 24),
	F(dao_sink_format, has_fov, 28),
	F(dao_sink_format, hfov, 32),
	F(dao_sink_format, vfov, 40),
	F(dao_sink_format, mirrored, 48),
	F(dao_sink_format, reserved, 52),
	F(dao_sink_host, size, 0),
	F(dao_sink_host, user, 8),
	F(dao_sink_host, get_param, 16),
	F(dao_sink_host, set_param, 24),
	F(dao_sink_host, log, 32),
	F(dao_sink_host, set_params, 40),
	F(dao_sink_host, stats_json, 48),
	F(dao_sink_host, want_streams, 56),
	F(dao_sink_frame_info, size, 0),
	F(dao_sink_frame_info, stream, 4),
	F(dao_sink_frame_info, capture_ns, 8),
	F(dao_sink_frame_info, has_pose, 16),
	F(dao_sink_frame_info, reserved, 20),
	F(dao_sink_frame_info, pose_rotation, 24),
	F(dao_sink_frame_info, pose_translation, 56),
	F(dao_timings, size, 0),
	F(dao_timings, decode_ms, 8),
	F(dao_timings, prefilter_ms, 16),
	F(dao_timings, normals_ms, 24),
	F(dao_timings, gtao_ms, 32),
	F(dao_timings, denoise_ms, 40),
	F(dao_timings, output_ms, 48),
	F(dao_timings, process_ms, 56),
	F(dao_timings, shade_ms, 64),
	F(dao_timings, noise_ms, 72),
	F(dao_noise_info, size, 0),
	F(dao_noise_info, measured, 4),
	F(dao_noise_info, sigma_area, 8),
	F(dao_noise_info, sigma_link, 12),
	F(dao_noise_info, prefilter_scale, 16),
	F(dao_noise_info, normal_radius, 20),
	F(dao_noise_info, denoise_noise, 24),
	F(dao_noise_info, sigma_slope, 28),
	F(dao_noise_info, age, 32),
	F(dao_noise_info, cells_measured, 36),
	F(dao_camera, size, 0),
	F(dao_camera, width, 4),
	F(dao_camera, height, 8),
	F(dao_camera, fx, 16),
	F(dao_camera, fy, 24),
	F(dao_camera, cx, 32),
	F(dao_camera, cy, 40),
	F(dao_camera, ax, 48),
	F(dao_camera, ay, 52),
	F(dao_camera, bx, 56),
	F(dao_camera, by, 60),
	F(dao_frame, format, 0),
	F(dao_frame, width, 4),
	F(dao_frame, height, 8),
	F(dao_frame, stride, 12),
	F(dao_frame, data, 16),
	F(dao_frame, depth_unit, 24),
	F(dao_frame, timestamp_ns, 32),
	F(dao_frame, sequence, 40),
	F(dao_frame, size, 48),
	F(dao_frame, reserved0, 52),
	F(dao_frame, reserved, 56),
	F(dao_oni_writer_options, size, 0),
	F(dao_oni_writer_options, width, 4),
	F(dao_oni_writer_options, height, 8),
	F(dao_oni_writer_options, fps, 12),
	F(dao_oni_writer_options, codec, 16),
	F(dao_oni_writer_options, pixel_format, 20),
	F(dao_oni_writer_options, max_depth, 24),
	F(dao_oni_writer_options, hfov, 32),
	F(dao_oni_writer_options, vfov, 40),
	F(dao_oni_writer_options, mirrored, 48),
	F(dao_oni_writer_options, overwrite, 52),
	F(dao_oni_writer_status, size, 0),
	F(dao_oni_writer_status, frames, 4),
	F(dao_oni_writer_status, synced_frames, 8),
	F(dao_oni_writer_status, syncs, 12),
	F(dao_oni_writer_status, error, 16),
	F(dao_oni_writer_status, bytes, 24),
	F(dao_plugin, abi_version, 0),
	F(dao_plugin, size, 4),
	F(dao_plugin, version, 8),
	F(dao_plugin, name, 16),
	F(dao_plugin, description, 24),
	F(dao_plugin, source, 32),
	F(dao_plugin, sink, 40),
	F(dao_motion_info, origin, 128),
	F(dao_motion_info, reserved, 132),
	F(dao_pose_track, size, 0),
	F(dao_pose_track, current, 4),
	F(dao_pose_track, frames, 8),
	F(dao_pose_track, accepted, 16),
	F(dao_pose_track, refused, 24),
	F(dao_pose_track, rotation, 32),
	F(dao_pose_track, translation, 104),
	F(dao_pose_track, frame_index, 128),
	F(dao_pose_track, timestamp_ns, 136),
};

static void test_layout_frozen(void **state)
{
	(void)state;
#if UINTPTR_MAX != UINT64_MAX
	skip(); /* the table is of LP64 offsets */
#endif
	int moved = 0;
	for (size_t i = 0; i < sizeof layout / sizeof layout[0]; i++)
		if (layout[i].offset != layout[i].frozen) {
			printf("%s moved from offset %zu to %zu: fields may only be appended\n",
			       layout[i].name, layout[i].frozen, layout[i].offset);
			moved++;
		}
	assert_int_equal(moved, 0);
	/* no tail padding: each struct ends with its last field (name the new last
	 * field here when appending one) */
	assert_int_equal(sizeof(struct dao_params),
			 DAO_END_OF(struct dao_params, depth_fill));
	assert_int_equal(sizeof(struct dao_source_info), DAO_END_OF(struct dao_source_info, cy));
	assert_int_equal(sizeof(struct dao_source_pose), DAO_END_OF(struct dao_source_pose, warning));
	assert_int_equal(sizeof(struct dao_source_ops),
			 DAO_END_OF(struct dao_source_ops, frame_pose));
	assert_int_equal(sizeof(struct dao_source_options),
			 DAO_END_OF(struct dao_source_options, depth_unit));
	assert_int_equal(sizeof(struct dao_sink_format),
			 DAO_END_OF(struct dao_sink_format, reserved));
	assert_int_equal(sizeof(struct dao_sink_host), DAO_END_OF(struct dao_sink_host, want_streams));
	assert_int_equal(sizeof(struct dao_sink_frame_info),
			 DAO_END_OF(struct dao_sink_frame_info, pose_translation));
	assert_int_equal(sizeof(struct dao_timings), DAO_END_OF(struct dao_timings, noise_ms));
	assert_int_equal(sizeof(struct dao_motion_info),
			 DAO_END_OF(struct dao_motion_info, reserved));
	assert_int_equal(sizeof(struct dao_pose_track),
			 DAO_END_OF(struct dao_pose_track, timestamp_ns));
	assert_int_equal(sizeof(struct dao_noise_info),
			 DAO_END_OF(struct dao_noise_info, cells_measured));
	assert_int_equal(sizeof(struct dao_camera), DAO_END_OF(struct dao_camera, by));
	assert_int_equal(sizeof(struct dao_oni_writer_options),
			 DAO_END_OF(struct dao_oni_writer_options, overwrite));
	assert_int_equal(sizeof(struct dao_oni_writer_status),
			 DAO_END_OF(struct dao_oni_writer_status, bytes));
	assert_int_equal(sizeof(struct dao_plugin), DAO_END_OF(struct dao_plugin, sink));
	/* dao_frame never changes its sizeof (embedded in dao_source_frame): later
	 * fields go into its reserved space, and DAO_FRAME_SIZE moves past them */
	assert_int_equal(sizeof(struct dao_frame), 88);
	assert_int_equal(DAO_FRAME_SIZE, DAO_END_OF(struct dao_frame, size));
	/* the smallest structs the library takes never change */
	assert_int_equal(DAO_PARAMS_SIZE_FIRST, 184);
	assert_int_equal(SOURCE_INFO_SIZE_FIRST, 536);
	assert_int_equal(SOURCE_OPTIONS_SIZE_FIRST, 28);
	assert_int_equal(SINK_FORMAT_SIZE_FIRST, 56);
	assert_int_equal(SINK_HOST_SIZE_FIRST, 64);
	assert_int_equal(SINK_FRAME_INFO_SIZE_FIRST, 16);
	assert_int_equal(PLUGIN_SIZE_FIRST, 48);
}

static int poisoned(const void *p, size_t from, size_t to)
{
	const unsigned char *b = p;
	for (size_t i = from; i < to; i++)
		if (b[i] != POISON)
			return 0;
	return 1;
}

/* A struct dao_params from a newer program (longer) is refused with a
 * message; one of the first size is taken, and nothing past a caller's size
 * is read or written. */
static void test_params_sizes(void **state)
{
	(void)state;
	struct {
		struct dao_params p;
		float later[4]; /* fields a newer depthao might have */
	} big;
	struct dao_error err;
	memset(&big, POISON, sizeof big);
	assert_int_equal(dao_params_init_sized(&big.p, sizeof big, DAO_QUALITY_DEFAULT), -EINVAL);
	assert_true(poisoned(&big, 0, sizeof big)); /* refused before writing */
	assert_int_equal(dao_params_init_sized(&big.p, DAO_PARAMS_SIZE_FIRST - 4, DAO_QUALITY_DEFAULT),
			 -EINVAL);
	assert_int_equal(dao_params_init_sized(&big.p, sizeof big.p, DAO_QUALITY_HIGH), 0);
	assert_int_equal(big.p.size, sizeof big.p);
	assert_true(poisoned(&big, sizeof big.p, sizeof big));
	assert_int_equal(big.p.slices, 4);

	/* a caller claiming the newer size */
	big.p.size = sizeof big;
	struct dao_camera cam;
	assert_int_equal(dao_camera_from_fov(&cam, 32, 24, 1.0, 0.8, &err), 0);
	struct dao_context *ctx = NULL;
	assert_int_equal(dao_context_create(&ctx, &cam, &big.p, &err), -EINVAL);
	assert_non_null(strstr(err.message, "dao_params_init"));
	assert_int_equal(dao_params_validate(&big.p, &err), -EINVAL);
	char v[32];
	assert_int_equal(dao_params_get(&big.p, "radius", v, sizeof v, &err), -EINVAL);
	assert_int_equal(dao_params_set(&big.p, "radius", "0.3", &err), -EINVAL);
	/* a struct set up by hand, without its size */
	struct dao_params zero;
	memset(&zero, 0, sizeof zero);
	assert_int_equal(dao_params_set(&zero, "radius", "0.3", &err), -EINVAL);

	/* the first size (a program built before the VBAO thickness fields were
	 * appended): taken, the later fields at their defaults, never touched */
	memset(&big, POISON, sizeof big);
	assert_int_equal(dao_params_init_sized(&big.p, DAO_PARAMS_SIZE_FIRST, DAO_QUALITY_HIGH), 0);
	assert_true(poisoned(&big, DAO_PARAMS_SIZE_FIRST, sizeof big));
	assert_true(DAO_PARAMS_SIZE_FIRST <= offsetof(struct dao_params, vbao_thickness_mode));
	assert_int_equal(dao_params_set(&big.p, "vbao-thickness-mode", "image", &err), -ENOENT);
	assert_non_null(strstr(err.message, "newer than the program's struct"));
	assert_int_equal(dao_params_get(&big.p, "vbao-thickness-max", v, sizeof v, &err), -ENOENT);
	assert_int_equal(dao_params_validate(&big.p, &err), 0);
	assert_true(poisoned(&big, DAO_PARAMS_SIZE_FIRST, sizeof big));
	assert_int_equal(dao_params_set(&big.p, "radius", "0.3", &err), 0);
	assert_int_equal(dao_context_create(&ctx, &cam, &big.p, &err), 0);
	{
		struct dao_params now, def;
		dao_params_init(&def, DAO_QUALITY_DEFAULT);
		dao_context_get_params(ctx, &now);
		assert_int_equal(now.vbao_thickness_mode, def.vbao_thickness_mode);
		assert_true(now.vbao_thickness_max == def.vbao_thickness_max);
		assert_true(now.radius == 0.3f && now.slices == 4);
	}
	memset(&big, POISON, sizeof big);
	assert_int_equal(dao_context_get_params_sized(ctx, &big.p, DAO_PARAMS_SIZE_FIRST), 0);
	assert_int_equal(big.p.size, DAO_PARAMS_SIZE_FIRST);
	assert_true(poisoned(&big, DAO_PARAMS_SIZE_FIRST, sizeof big));
	assert_true(big.p.radius == 0.3f && big.p.slices == 4); /* HIGH, then radius */
	assert_int_equal(dao_context_get_params_sized(ctx, &big.p, DAO_PARAMS_SIZE_FIRST - 1),
			 -EINVAL);
	/* and a newer caller's get gets this library's size back */
	assert_int_equal(dao_context_get_params_sized(ctx, &big.p, sizeof big), 0);
	assert_int_equal(big.p.size, sizeof big.p);
	dao_context_destroy(ctx);
}

static struct dao_plugins *fake_plugins(void)
{
	const char *dir = getenv("DAO_FAKE_PLUGIN_DIR");
	if (!dir)
		return NULL;
	struct dao_plugins *p = NULL;
	struct dao_error err;
	assert_int_equal(dao_plugins_load(&p, dir, &err), 0);
	return p;
}

/* Source options and info of other sizes. */
static void test_source_sizes(void **state)
{
	(void)state;
	struct dao_plugins *p = fake_plugins();
	if (!p)
		skip();
	struct dao_error err;
	struct dao_source *s = NULL;
	struct dao_source_options none;
	memset(&none, 0, sizeof none);
	assert_int_equal(dao_source_open(p, "fakebig:64x48", &none, &s, &err), -EINVAL);
	assert_non_null(strstr(err.message, "DAO_SOURCE_OPTIONS_INIT"));
	assert_null(s);

	struct {
		struct dao_source_options o;
		int later[8];
	} newer;
	memset(&newer, POISON, sizeof newer);
	newer.o = (struct dao_source_options)DAO_SOURCE_OPTIONS_INIT;
	newer.o.size = sizeof newer;
	assert_int_equal(dao_source_open(p, "fakebig:64x48", &newer.o, &s, &err), 0);

	struct {
		struct dao_source_info in;
		unsigned char later[64];
	} info;
	memset(&info, POISON, sizeof info);
	assert_int_equal(dao_source_get_info_sized(s, &info.in, SOURCE_INFO_SIZE_FIRST - 1), -EINVAL);
	assert_true(poisoned(&info, 0, sizeof info));
	assert_int_equal(dao_source_get_info_sized(s, &info.in, sizeof info), 0);
	assert_int_equal(info.in.size, sizeof info.in);
	assert_true(info.in.width == 64 && info.in.height == 48);
	assert_int_equal(info.in.has_intrinsics, 0); /* what the source does not set is 0 */
	assert_true(poisoned(&info, sizeof info.in, sizeof info));
	dao_source_close(s);
	dao_plugins_free(p);
}

/* A sink built for a newer interface loads; it is handed this library's
 * struct (it checks the size before reading a field this library lacks), and
 * a caller's longer struct gets back no more than this library's fields. */
static void test_newer_sink(void **state)
{
	(void)state;
	struct dao_plugins *p = fake_plugins();
	if (!p)
		skip();
	struct dao_error err;
	const struct dao_plugin *pl = dao_plugins_find(p, "newersink");
	assert_non_null(pl);
	assert_true(pl->sink->version > DAO_SINK_OPS_VERSION);
	struct dao_sink *s = NULL;
	assert_int_equal(dao_sink_open(p, "newersink:x", &s, &err), 0);

	struct dao_sink_format none;
	memset(&none, 0, sizeof none);
	none.format = DAO_PIXFMT_GRAY16;
	none.width = 8;
	none.height = 4;
	assert_int_equal(dao_sink_negotiate(s, &none, &err), -EINVAL);
	assert_non_null(strstr(err.message, "DAO_SINK_FORMAT_INIT"));

	struct {
		struct dao_sink_format f;
		unsigned char later[32];
	} fmt;
	memset(&fmt, POISON, sizeof fmt);
	fmt.f = (struct dao_sink_format)DAO_SINK_FORMAT_INIT;
	fmt.f.size = sizeof fmt;
	fmt.f.format = DAO_PIXFMT_GRAY16;
	fmt.f.width = 8;
	fmt.f.height = 4;
	assert_int_equal(dao_sink_negotiate(s, &fmt.f, &err), 0);
	assert_int_equal(fmt.f.format, DAO_PIXFMT_GRAY8); /* the sink's choice comes back */
	assert_int_equal(fmt.f.size, sizeof fmt.f);
	assert_true(poisoned(&fmt, sizeof fmt.f, sizeof fmt));

	struct dao_frame frame;
	assert_int_equal(dao_frame_alloc(&frame, DAO_PIXFMT_GRAY8, 8, 4, &err), 0);
	assert_int_equal(dao_sink_write(s, &frame, &err), 0);
	dao_frame_free(&frame);
	assert_int_equal(dao_sink_close(s, &err), 0); /* the sink saw exactly one frame */
	dao_plugins_free(p);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_layout_frozen),
		cmocka_unit_test(test_params_sizes),
		cmocka_unit_test(test_source_sizes),
		cmocka_unit_test(test_newer_sink),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
