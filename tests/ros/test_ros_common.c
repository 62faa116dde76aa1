/* SPDX-License-Identifier: MIT */
/*
 * ros/common, the C layer of the ROS nodes, without ROS: message fields to
 * frames (every accepted encoding and byte order, padded rows give the same AO;
 * the errors name what is wrong), the camera followed, time going back starts
 * the temporal filters over, the parameter table as node parameters, and no
 * allocation per frame (the C allocator interposed, as test_no_alloc.c does).
 * The filtered depth (16UC1 in the input's unit, 32FC1 with NaN) equals the
 * library's of the same frames; RVL of a hand-worked example; the
 * compressedDepth header, settings and errors.
 */
#define _GNU_SOURCE
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/alloc_count.h"
#include "common/cmocka_all.h"
#include "common/test_common.h"
#include "dao_ros.h"
#include "dao_ros_cdepth.h"


#define W 64
#define H 48

static const double K[9] = { 60.0, 0, 31.5, 0, 61.0, 23.25, 0, 0, 1 };

/* a wall with a box in front of it (counts of 1 mm), holes on a lattice, and
 * +-2 mm of noise that changes from frame to frame */
static uint16_t count_at(int x, int y, int i)
{
	if ((x * 7 + y * 3 + i) % 29 == 0)
		return 0;
	int noise = (int)((unsigned)(x * 7919 + y * 104729 + i * 15485863) % 5u) - 2;
	if (x >= 16 + i && x < 40 + i && y >= 12 && y < 36)
		return (uint16_t)(1800 + x + noise);
	return (uint16_t)(2000 + 9 * y + 2 * x + noise);
}

/* the frame as a message would carry it: 16UC1 (or mono16) or 32FC1, either
 * byte order, rows `pad` bytes longer than needed */
static size_t make_image(uint8_t *buf, struct dao_ros_image *img, const char *encoding, int big,
			 int pad, int i)
{
	int f32 = !strcmp(encoding, "32FC1");
	size_t bpp = f32 ? 4 : 2, step = W * bpp + (size_t)pad;
	memset(buf, 0xee, step * H);
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			uint16_t c = count_at(x, y, i);
			uint8_t b[4];
			if (f32) {
				float m = c ? (float)c * 0.001f : NAN;
				memcpy(b, &m, 4);
			} else {
				memcpy(b, &c, 2);
			}
			uint8_t *d = buf + (size_t)y * step + (size_t)x * bpp;
			for (size_t k = 0; k < bpp; k++)
				d[k] = big ? b[bpp - 1 - k] : b[k];
		}
	*img = (struct dao_ros_image){ W, H, encoding, big, (uint32_t)step, buf, step * H };
	return step * H;
}

static const struct dao_ros_camera_info info = { W, H, K, NULL, 0, NULL };

static uint8_t in_buf[W * H * 4 + 64 * H];
static float ao_f[W * H];
static uint16_t ao_16[W * H];
static uint8_t rgb[W * H * 3];

/* one frame through prepare + run; the outputs in ao_16 / ao_f and rgb */
static int run_frame(struct dao_ros_proc *proc, const struct dao_ros_image *img, uint64_t stamp,
		     struct dao_error *err)
{
	struct dao_ros_output ao, sh;
	int distorted;
	int r = dao_ros_proc_prepare(proc, img, &info, &ao, &sh, &distorted, err);
	if (r)
		return r;
	ao.data = !strcmp(ao.encoding, "32FC1") ? (void *)ao_f : (void *)ao_16;
	sh.data = rgb;
	return dao_ros_proc_run(proc, img, stamp, &ao, &sh, err);
}

static struct dao_ros_proc *make_proc(const char *ao_encoding, struct dao_params *p)
{
	struct dao_ros_settings s;
	struct dao_ros_proc *proc;
	struct dao_error err;
	dao_ros_settings_init(&s);
	assert_int_equal(dao_ros_settings_set(&s, "ao_encoding", ao_encoding, &err), 0);
	if (dao_ros_proc_create(&proc, &s, p, &err))
		fail_msg("create: %s", err.message);
	return proc;
}

static void test_settings(void **state)
{
	(void)state;
	struct dao_ros_settings s;
	struct dao_error err;
	dao_ros_settings_init(&s);
	assert_true(s.depth_unit == 0.001f && s.ao_encoding == DAO_ROS_AO_MONO16);
	assert_int_equal(dao_ros_settings_set(&s, "depth_unit", "0.0001", &err), 0);
	assert_true(s.depth_unit == 0.0001f);
	assert_int_equal(dao_ros_settings_set(&s, "depth_unit", "-1", &err), -EINVAL);
	assert_non_null(strstr(err.message, "depth_unit: '-1' is not a unit in metres"));
	assert_int_equal(dao_ros_settings_set(&s, "ao_encoding", "32FC1", &err), 0);
	assert_int_equal(s.ao_encoding, DAO_ROS_AO_32FC1);
	assert_int_equal(dao_ros_settings_set(&s, "ao_encoding", "mono8", &err), -EINVAL);
	assert_non_null(strstr(err.message, "'mono8' is not mono16 or 32FC1"));
	assert_int_equal(dao_ros_settings_set(&s, "radius", "1", &err), -ENOENT);
	assert_string_equal(dao_ros_ao_encoding_name(DAO_ROS_AO_32FC1), "32FC1");
}

/* 16UC1 and mono16 in both byte orders, with padded rows: one AO; 32FC1 in
 * both byte orders: one AO, within a count of the counts' (the unit's product
 * rounds differently from the float metres) */
static void test_encodings_agree(void **state)
{
	(void)state;
	static uint16_t first[W * H];
	static uint8_t first_rgb[W * H * 3];
	struct dao_ros_image img;
	struct dao_error err;
	const struct { const char *enc; int big, pad; } cases[] = {
		{ "16UC1", 0, 0 }, { "16UC1", 1, 0 }, { "mono16", 0, 6 }, { "mono16", 1, 2 },
	};
	for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
		struct dao_ros_proc *proc = make_proc("mono16", NULL);
		make_image(in_buf, &img, cases[c].enc, cases[c].big, cases[c].pad, 0);
		if (run_frame(proc, &img, 1, &err))
			fail_msg("%s big %d: %s", cases[c].enc, cases[c].big, err.message);
		if (c == 0) {
			memcpy(first, ao_16, sizeof first);
			memcpy(first_rgb, rgb, sizeof first_rgb);
		} else {
			assert_memory_equal(ao_16, first, sizeof first);
			assert_memory_equal(rgb, first_rgb, sizeof first_rgb);
		}
		dao_ros_proc_destroy(proc);
	}
	int lo = 65535, hi = 0;
	for (int k = 0; k < W * H; k++) {
		lo = first[k] < lo ? first[k] : lo;
		hi = first[k] > hi ? first[k] : hi;
	}
	if (hi - lo < 5000) /* the box occludes the wall: there is AO to compare */
		fail_msg("AO from %d to %d only", lo, hi);
	static float f32_le[W * H];
	for (int big = 0; big < 2; big++) {
		struct dao_ros_proc *proc = make_proc("32FC1", NULL);
		make_image(in_buf, &img, "32FC1", big, big ? 4 : 0, 0);
		if (run_frame(proc, &img, 1, &err))
			fail_msg("32FC1 big %d: %s", big, err.message);
		if (!big)
			memcpy(f32_le, ao_f, sizeof f32_le);
		else
			assert_memory_equal(ao_f, f32_le, sizeof f32_le);
		dao_ros_proc_destroy(proc);
	}
	int worst = 0;
	for (int k = 0; k < W * H; k++) {
		int d = abs((int)lrintf(f32_le[k] * 65535.0f) - (int)first[k]);
		worst = d > worst ? d : worst;
	}
	if (worst > 64)
		fail_msg("32FC1 metres and 16UC1 counts differ by %d / 65535", worst);
}

/* the filtered depth equals dao_context_get_depth of a context of our own on the
 * same frames (stream defaults, indices from 0); 16UC1 in the input's unit, 32FC1
 * metres with NaN where there is no depth */
static void test_filtered_depth(void **state)
{
	(void)state;
	static uint16_t got16[W * H], ref16[W * H];
	static float got32[W * H], ref32[W * H];
	struct dao_ros_image img;
	struct dao_error err;
	struct dao_camera cam;
	struct dao_params p;
	struct dao_context *ctx;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	dao_params_stream_defaults(&p);
	assert_int_equal(dao_camera_from_intrinsics(&cam, W, H, K[0], K[4], K[2], K[5], &err), 0);
	for (int f32 = 0; f32 < 2; f32++) {
		struct dao_ros_proc *proc = make_proc("mono16", NULL);
		struct dao_ros_output d;
		assert_int_equal(dao_context_create(&ctx, &cam, &p, &err), 0);
		for (int i = 0; i < 3; i++) {
			make_image(in_buf, &img, f32 ? "32FC1" : "16UC1", i == 1, 0, i);
			if (i == 0) {
				struct dao_ros_output ao, sh;
				int dist;
				assert_int_equal(dao_ros_proc_prepare(proc, &img, &info, &ao, &sh, &dist,
								      &err), 0);
				dao_ros_proc_depth_layout(proc, &d);
				d.data = f32 ? (void *)got32 : (void *)got16;
				assert_int_equal(dao_ros_proc_depth(proc, &d, &err), -EAGAIN);
			}
			if (run_frame(proc, &img, 10 + (uint64_t)i, &err))
				fail_msg("frame %d: %s", i, err.message);
			dao_ros_proc_depth_layout(proc, &d);
			assert_string_equal(d.encoding, f32 ? "32FC1" : "16UC1");
			assert_int_equal(d.step, W * (f32 ? 4 : 2));
			d.data = f32 ? (void *)got32 : (void *)got16;
			assert_int_equal(dao_ros_proc_depth(proc, &d, &err), 0);
			/* the same frame, host order, into our own context */
			make_image(in_buf, &img, f32 ? "32FC1" : "16UC1", 0, 0, i);
			struct dao_frame in = { .size = DAO_FRAME_SIZE, .width = W, .height = H,
						.stride = (int32_t)img.step, .data = in_buf,
						.format = f32 ? DAO_PIXFMT_DEPTH_F32 : DAO_PIXFMT_DEPTH16,
						.depth_unit = f32 ? 0.0f : 0.001f };
			struct dao_frame out = { .size = DAO_FRAME_SIZE, .width = W, .height = H,
						 .format = f32 ? DAO_PIXFMT_DEPTH_F32 : DAO_PIXFMT_DEPTH16,
						 .stride = W * (f32 ? 4 : 2), .depth_unit = 0.001f,
						 .data = f32 ? (void *)ref32 : (void *)ref16 };
			assert_int_equal(dao_context_process(ctx, &in, NULL, (uint64_t)i, NULL, &err), 0);
			assert_int_equal(dao_context_get_depth(ctx, &out, &err), 0);
			int holes = 0, changed = 0;
			for (int k = 0; k < W * H; k++) {
				if (!f32) {
					assert_int_equal(got16[k], ref16[k]);
					holes += got16[k] == 0;
					changed += got16[k] && got16[k] != count_at(k % W, k / W, i);
				} else if (ref32[k] == 0.0f) {
					assert_true(isnan(got32[k]));
					holes++;
				} else {
					assert_true(got32[k] == ref32[k]);
				}
			}
			assert_true(holes > 0 && holes < W * H / 10);
			assert_true(f32 || changed > W * H / 10); /* the filter did something */
		}
		dao_context_destroy(ctx);
		dao_ros_proc_destroy(proc);
	}
}

/* RVL of a worked example: 0 0 5 6 0 is the numbers 2 (zeros), 2 (non-zeros),
 * zig-zag(5) = 10 = 3-bit groups 2, 1 (nibbles 0xA 0x1), zig-zag(1) = 2, 1 (zeros),
 * 0 (non-zeros): nibbles 2 2 A 1 2 1 0, then one 0 to fill the word 0x22A12100,
 * stored little-endian */
static void test_rvl(void **state)
{
	(void)state;
	const uint16_t in[] = { 0, 0, 5, 6, 0 };
	uint8_t out[64];
	const uint8_t want[] = { 0x00, 0x21, 0xA1, 0x22 };
	assert_int_equal(dao_ros_rvl_encode(in, 5, out), 4);
	assert_memory_equal(out, want, 4);
	/* 9 values 0x7fff apart: 9 words' worth of nibbles, within the bound */
	uint16_t big[9];
	for (int i = 0; i < 9; i++)
		big[i] = (uint16_t)(i % 2 ? 65535 : 1);
	size_t n = dao_ros_rvl_encode(big, 9, out);
	assert_true(n % 4 == 0 && n <= dao_ros_rvl_bound(9));
	assert_int_equal(dao_ros_rvl_encode(big, 0, out), 0);
}

static void test_compressed_depth(void **state)
{
	(void)state;
	struct dao_ros_cdepth c;
	struct dao_error err;
	dao_ros_cdepth_init(&c);
	assert_true(c.codec == DAO_ROS_CDEPTH_PNG && c.png_level == 1 && c.depth_max == 10.0 &&
		    c.depth_quantization == 100.0);
	assert_int_equal(dao_ros_cdepth_set(&c, "format", "jpeg", &err), -EINVAL);
	assert_non_null(strstr(err.message, "compressedDepth/format: 'jpeg' is not png or rvl"));
	assert_int_equal(dao_ros_cdepth_set(&c, "png_level", "0", &err), -EINVAL);
	assert_int_equal(dao_ros_cdepth_set(&c, "png_level", "2.5", &err), -EINVAL);
	assert_int_equal(dao_ros_cdepth_set(&c, "depth_max", "101", &err), -EINVAL);
	assert_non_null(strstr(err.message, "depth_max: '101' is not a number in [1, 100]"));
	assert_int_equal(dao_ros_cdepth_set(&c, "quality", "1", &err), -ENOENT);
	uint16_t px[W * H];
	for (int k = 0; k < W * H; k++)
		px[k] = count_at(k % W, k / W, 0);
	struct dao_ros_output d = { "16UC1", W, H, W * 2, sizeof px, px };
	for (int codec = 0; codec < 2; codec++) {
		assert_int_equal(dao_ros_cdepth_set(&c, "format", codec ? "rvl" : "png", &err), 0);
		assert_int_equal(dao_ros_cdepth_encode(&c, &d, &err), 0);
		assert_string_equal(c.format, codec ? "16UC1; compressedDepth rvl"
						     : "16UC1; compressedDepth png");
		const uint8_t zeros[12] = {0};
		assert_memory_equal(c.buf, zeros, 12); /* format 0, A = B = 0 */
		if (codec) {
			assert_true(c.buf[12] == W && c.buf[16] == H && c.len > 20 && c.len < W * H * 2);
		} else {
			assert_memory_equal(c.buf + 12, "\x89PNG", 4);
		}
	}
	float z[4] = { 1.0f, NAN, 0.0f, 20.0f };
	struct dao_ros_output f = { "32FC1", 4, 1, 16, 16, z };
	assert_int_equal(dao_ros_cdepth_encode(&c, &f, &err), 0);
	assert_string_equal(c.format, "32FC1; compressedDepth rvl");
	float a, b;
	memcpy(&a, c.buf + 4, 4);
	memcpy(&b, c.buf + 8, 4);
	assert_true(a == 10100.0f && b == 1.0f - 10100.0f / 10.0f);
	struct dao_ros_output bad = { "mono8", W, H, W, W * H, px };
	assert_int_equal(dao_ros_cdepth_encode(&c, &bad, &err), -EINVAL);
	dao_ros_cdepth_free(&c);
}

static void test_errors(void **state)
{
	(void)state;
	struct dao_ros_proc *proc = make_proc("mono16", NULL);
	struct dao_ros_image img;
	struct dao_ros_output ao, sh;
	struct dao_error err;
	int distorted;
	make_image(in_buf, &img, "16UC1", 0, 0, 0);
	struct dao_ros_image bad = img;
	bad.encoding = "rgb8";
	assert_int_equal(dao_ros_proc_prepare(proc, &bad, &info, &ao, &sh, &distorted, &err), -EINVAL);
	assert_string_equal(err.message, "depth image encoding 'rgb8' is not accepted: depthao takes "
			    "16UC1 or mono16 (counts of depth_unit metres) or 32FC1 (metres)");
	bad = img;
	bad.step = 2 * W - 2;
	assert_int_equal(dao_ros_proc_prepare(proc, &bad, &info, &ao, &sh, &distorted, &err), -EINVAL);
	assert_non_null(strstr(err.message, "step 126 is below width x 2 bytes"));
	bad = img;
	bad.size = img.size - 1;
	assert_int_equal(dao_ros_proc_prepare(proc, &bad, &info, &ao, &sh, &distorted, &err), -EINVAL);
	assert_non_null(strstr(err.message, "6143 bytes of data, step 128 x height needs 6144"));
	struct dao_ros_camera_info ci = info;
	ci.width = W / 2;
	assert_int_equal(dao_ros_proc_prepare(proc, &img, &ci, &ao, &sh, &distorted, &err), -EINVAL);
	assert_non_null(strstr(err.message, "the camera info is for 32x48, the depth image is 64x48"));
	const double zero[9] = { 0 };
	ci = info;
	ci.k = zero;
	assert_int_equal(dao_ros_proc_prepare(proc, &img, &ci, &ao, &sh, &distorted, &err), -EINVAL);
	assert_non_null(strstr(err.message, "fx 0, fy 0"));
	/* run before a successful prepare */
	ao.data = ao_16;
	assert_int_equal(dao_ros_proc_run(proc, &img, 1, &ao, NULL, &err), -EINVAL);
	/* distortion is reported, the frame still processed */
	const double d[5] = { 0.1, 0, 0, 0, 0 };
	ci = info;
	ci.d = d;
	ci.d_count = 5;
	assert_int_equal(dao_ros_proc_prepare(proc, &img, &ci, &ao, &sh, &distorted, &err), 0);
	assert_int_equal(distorted, DAO_ROS_DISTORTED_K);
	assert_string_equal(ao.encoding, "mono16");
	assert_int_equal(ao.step, 2 * W);
	assert_int_equal(ao.size, 2 * W * H);
	assert_string_equal(sh.encoding, "rgb8");
	assert_int_equal(sh.step, 3 * W);
	ao.data = ao_16;
	sh.data = NULL; /* no shaded image wanted */
	assert_int_equal(dao_ros_proc_run(proc, &img, 1, &ao, &sh, &err), 0);
	assert_int_equal(dao_ros_proc_frames(proc), 1);
	dao_ros_proc_destroy(proc);
}

/* The AO of frame 0 with camera info `ci` into out; *distorted as prepare says it. */
static void ao_with(const struct dao_ros_camera_info *ci, uint16_t *out, int *distorted)
{
	struct dao_ros_proc *proc = make_proc("mono16", NULL);
	struct dao_ros_image img;
	struct dao_ros_output ao, sh;
	struct dao_error err;
	make_image(in_buf, &img, "16UC1", 0, 0, 0);
	assert_int_equal(dao_ros_proc_prepare(proc, &img, ci, &ao, &sh, distorted, &err), 0);
	ao.data = out;
	assert_int_equal(dao_ros_proc_run(proc, &img, 1, &ao, NULL, &err), 0);
	dao_ros_proc_destroy(proc);
}

/*
 * With distortion and a usable P, P's intrinsics (the rectified image's, as
 * image_geometry): the AO equals that of a camera info whose K is P's; K
 * without distortion or without a usable P.
 */
static void test_projection_with_distortion(void **state)
{
	(void)state;
	static uint16_t of_k[W * H], of_pk[W * H], got[W * H];
	const double d[5] = { -0.12, 0.03, 0.001, 0, 0 };
	/* the rectified camera: another focal length and principal point than K */
	const double p[12] = { 45.0, 0, 30.0, 0, 0, 46.5, 22.0, 0, 0, 0, 1, 0 };
	const double pk[9] = { 45.0, 0, 30.0, 0, 46.5, 22.0, 0, 0, 1 };
	struct dao_ros_camera_info plain = info, ci = info;
	int distorted;
	ao_with(&info, of_k, &distorted);
	assert_int_equal(distorted, DAO_ROS_UNDISTORTED);
	plain.k = pk;
	ao_with(&plain, of_pk, &distorted);
	assert_true(memcmp(of_k, of_pk, sizeof of_k) != 0); /* the two cameras differ */

	ci.d = d;
	ci.d_count = 5;
	ci.p = p;
	ao_with(&ci, got, &distorted);
	assert_int_equal(distorted, DAO_ROS_DISTORTED_P);
	assert_memory_equal(got, of_pk, sizeof got);

	/* no distortion: K, whatever P says */
	ci.d_count = 0;
	ao_with(&ci, got, &distorted);
	assert_int_equal(distorted, DAO_ROS_UNDISTORTED);
	assert_memory_equal(got, of_k, sizeof got);

	/* distortion, P of an uncalibrated driver (zeros), non-finite or absent: K */
	const double p0[12] = { 0 };
	const double pnan[12] = { 45.0, 0, NAN, 0, 0, 46.5, 22.0, 0, 0, 0, 1, 0 };
	const double *bad[3] = { p0, pnan, NULL };
	ci.d_count = 5;
	for (int i = 0; i < 3; i++) {
		ci.p = bad[i];
		ao_with(&ci, got, &distorted);
		assert_int_equal(distorted, DAO_ROS_DISTORTED_K);
		assert_memory_equal(got, of_k, sizeof got);
	}
}

/* new intrinsics make a new camera: the AO changes */
static void test_camera_followed(void **state)
{
	(void)state;
	static uint16_t before[W * H];
	struct dao_ros_proc *proc = make_proc("mono16", NULL);
	struct dao_ros_image img;
	struct dao_ros_output ao, sh;
	struct dao_error err;
	int distorted;
	make_image(in_buf, &img, "16UC1", 0, 0, 0);
	assert_int_equal(run_frame(proc, &img, 1, &err), 0);
	memcpy(before, ao_16, sizeof before);
	double k2[9];
	memcpy(k2, K, sizeof k2);
	k2[0] = k2[4] = 30.0; /* a wider lens: the same radius covers fewer pixels */
	struct dao_ros_camera_info ci = info;
	ci.k = k2;
	assert_int_equal(dao_ros_proc_prepare(proc, &img, &ci, &ao, &sh, &distorted, &err), 0);
	ao.data = ao_16;
	assert_int_equal(dao_ros_proc_run(proc, &img, 2, &ao, NULL, &err), 0);
	assert_true(memcmp(before, ao_16, sizeof before) != 0);
	dao_ros_proc_destroy(proc);
}

/* a stamp earlier than the last one starts the temporal histories over: the
 * result equals a processor whose history holds other frames, reset there */
static void test_time_back_resets(void **state)
{
	(void)state;
	static uint16_t a[W * H], b[W * H], c[W * H];
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	dao_params_stream_defaults(&p);
	assert_true(p.depth_temporal > 0.0f);
	struct dao_ros_image img;
	struct dao_error err;
	struct dao_ros_proc *pa = make_proc("mono16", &p), *pb = make_proc("mono16", &p),
			    *pc = make_proc("mono16", &p);
	for (int i = 0; i < 3; i++) {
		make_image(in_buf, &img, "16UC1", 0, 0, i + 1);
		assert_int_equal(run_frame(pa, &img, 10 + (uint64_t)i, &err), 0);
		assert_int_equal(run_frame(pc, &img, 10 + (uint64_t)i, &err), 0);
		make_image(in_buf, &img, "16UC1", 0, 0, 5 - i);
		assert_int_equal(run_frame(pb, &img, 10 + (uint64_t)i, &err), 0);
	}
	make_image(in_buf, &img, "16UC1", 0, 0, 0);
	assert_int_equal(run_frame(pa, &img, 5, &err), 0); /* back in time */
	memcpy(a, ao_16, sizeof a);
	assert_int_equal(run_frame(pb, &img, 5, &err), 0);
	memcpy(b, ao_16, sizeof b);
	assert_int_equal(run_frame(pc, &img, 13, &err), 0); /* onwards: the history counts */
	memcpy(c, ao_16, sizeof c);
	assert_memory_equal(a, b, sizeof a);
	assert_true(memcmp(a, c, sizeof a) != 0);
	double q[4], t[3]; /* the motion is not followed (off): no pose out */
	assert_int_equal(dao_ros_proc_pose(pa, q, t), 0);
	dao_ros_proc_destroy(pa);
	dao_ros_proc_destroy(pb);
	dao_ros_proc_destroy(pc);
}

/* one frame with a pose (rotation NULL: none) through prepare + set_pose + run */
static int run_posed(struct dao_ros_proc *proc, const struct dao_ros_image *img, uint64_t stamp,
		     const double *q, const double *t, struct dao_error *err)
{
	struct dao_ros_output ao, sh;
	int distorted;
	int r = dao_ros_proc_prepare(proc, img, &info, &ao, &sh, &distorted, err);
	if (!r)
		r = dao_ros_proc_set_pose(proc, stamp, q, t, err);
	if (r)
		return r;
	ao.data = ao_16;
	sh.data = NULL;
	return dao_ros_proc_run(proc, img, stamp, &ao, &sh, err);
}

/* poses from the shell (tf) reach depth_temporal_motion=source; a bag played
 * again (the stamp goes back) starts over before the pose is taken, so its
 * frames equal those of a processor whose history was other frames, and its
 * first frame's pose is kept (the second frame follows the motion); bad poses
 * are refused with the library's message; the pose starts over when the motion
 * is switched off and on again between two frames */
static void test_poses(void **state)
{
	(void)state;
	static uint16_t fresh[3][W * H], again[3][W * H], none[3][W * H];
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	dao_params_stream_defaults(&p);
	p.depth_temporal_motion = DAO_DEPTH_MOTION_SOURCE;
	struct dao_ros_image img;
	struct dao_error err;
	struct dao_ros_proc *pa = make_proc("mono16", &p), *pb = make_proc("mono16", &p),
			    *pc = make_proc("mono16", &p);
	const double q[4] = { 0.0, 0.0, 0.0, 1.0 };
	double t[3] = { 0.0, 0.0, 0.0 };

	make_image(in_buf, &img, "16UC1", 0, 0, 0);
	assert_int_equal(dao_ros_proc_set_pose(pa, 1, q, t, &err), -EINVAL);
	assert_non_null(strstr(err.message, "not prepared"));
	for (int i = 0; i < 3; i++) { /* a first play: other frames, later stamps (the */
		make_image(in_buf, &img, "16UC1", 0, 0, 7 - i); /* indices go on: same counts) */
		t[0] = 0.02 * i;
		assert_int_equal(run_posed(pa, &img, 20 + (uint64_t)i, q, t, &err), 0);
		make_image(in_buf, &img, "16UC1", 0, 0, 9 + i);
		assert_int_equal(run_posed(pb, &img, 20 + (uint64_t)i, NULL, NULL, &err), 0);
		assert_int_equal(run_posed(pc, &img, 20 + (uint64_t)i, NULL, NULL, &err), 0);
	}
	for (int i = 0; i < 3; i++) {
		make_image(in_buf, &img, "16UC1", 0, 0, i);
		t[0] = 0.03 * i; /* 3 cm a frame to the right */
		assert_int_equal(run_posed(pa, &img, 5 + (uint64_t)i, q, t, &err), 0);
		memcpy(again[i], ao_16, sizeof again[i]);
		/* the pose out: the given ones' motion since the restart (frame 5 the origin) */
		double pq[4], pt[3];
		assert_int_equal(dao_ros_proc_pose(pa, pq, pt), 1);
		assert_true(fabs(pt[0] - 0.03 * i) < 1e-9 && fabs(pt[1]) < 1e-9 && fabs(pt[2]) < 1e-9);
		assert_true(fabs(pq[3] - 1.0) < 1e-12);
		/* without poses in source mode the motion is unknown: no pose after the first */
		assert_int_equal(run_posed(pc, &img, 5 + (uint64_t)i, NULL, NULL, &err), 0);
		memcpy(none[i], ao_16, sizeof none[i]);
		assert_int_equal(dao_ros_proc_pose(pc, pq, pt), i == 0);
		assert_int_equal(run_posed(pb, &img, 5 + (uint64_t)i, q, t, &err), 0);
		memcpy(fresh[i], ao_16, sizeof fresh[i]);
		assert_memory_equal(again[i], fresh[i], sizeof fresh[i]);
	}
	/* the poses were used from the second frame after the stamp went back on: the
	 * first one's pose was not lost to the restart */
	assert_memory_equal(again[0], none[0], sizeof none[0]);
	assert_true(memcmp(again[1], none[1], sizeof none[1]) != 0);
	assert_true(memcmp(again[2], none[2], sizeof none[2]) != 0);

	const double bad[4] = { 0.0, 0.0, 0.0, 2.0 }, inf[3] = { INFINITY, 0.0, 0.0 };
	struct dao_ros_output ao, sh;
	int distorted;
	assert_int_equal(dao_ros_proc_prepare(pc, &img, &info, &ao, &sh, &distorted, &err), 0);
	assert_int_equal(dao_ros_proc_set_pose(pc, 9, bad, t, &err), -EINVAL);
	assert_non_null(strstr(err.message, "camera pose: the rotation quaternion"));
	assert_int_equal(dao_ros_proc_set_pose(pc, 9, q, inf, &err), -EINVAL);
	assert_non_null(strstr(err.message, "is not a finite"));

	/* the motion switched off and on again between two frames (a reconfigure): the
	 * pose starts over at the next frame, 3 cm on from the last (0.06 from frame 5) */
	struct dao_params off = p;
	off.depth_temporal_motion = DAO_DEPTH_MOTION_OFF;
	assert_int_equal(dao_ros_proc_set_params(pa, &off, &err), 0);
	assert_int_equal(dao_ros_proc_set_params(pa, &p, &err), 0);
	make_image(in_buf, &img, "16UC1", 0, 0, 3);
	t[0] = 0.09;
	assert_int_equal(run_posed(pa, &img, 8, q, t, &err), 0);
	double pq[4], pt[3];
	assert_int_equal(dao_ros_proc_pose(pa, pq, pt), 1);
	assert_true(fabs(pt[0]) < 1e-12 && fabs(pq[3] - 1.0) < 1e-12); /* the origin again */
	/* a jump beyond 0.25 m a frame is refused: no pose for that frame; the next
	 * one's motion (2 cm) moves the pose held since, the jump lost */
	t[0] = 0.9;
	assert_int_equal(run_posed(pa, &img, 9, q, t, &err), 0);
	assert_int_equal(dao_ros_proc_pose(pa, pq, pt), 0);
	t[0] = 0.92;
	assert_int_equal(run_posed(pa, &img, 10, q, t, &err), 0);
	assert_int_equal(dao_ros_proc_pose(pa, pq, pt), 1);
	assert_true(fabs(pt[0] - 0.02) < 1e-9);
	dao_ros_proc_destroy(pa);
	dao_ros_proc_destroy(pb);
	dao_ros_proc_destroy(pc);
}

static void test_params(void **state)
{
	(void)state;
	size_t n;
	const struct dao_param_info *t = dao_param_table(&n);
	struct dao_params p, q;
	struct dao_error err;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	for (size_t k = 0; k < n; k++) {
		struct dao_ros_param_desc d;
		dao_ros_param_describe(&t[k], &d);
		assert_null(strchr(d.name, '-'));
		assert_ptr_equal(dao_param_find(d.name), &t[k]);
		char text[64];
		assert_int_equal(dao_ros_param_get_string(&p, &t[k], text, sizeof text, &err), 0);
		q = p;
		/* each kind's value round-trips through its node parameter type */
		switch (d.kind) {
		case DAO_ROS_PARAM_DOUBLE:
			assert_int_equal(t[k].type, DAO_PARAM_FLOAT);
			assert_int_equal(dao_ros_param_set_double(&q, &t[k], d.max, &err), 0);
			assert_true(dao_ros_param_get_double(&q, &t[k]) == (double)(float)d.max);
			assert_int_equal(dao_ros_param_set_double(&q, &t[k], d.max * 2 + 1, &err), -EINVAL);
			assert_non_null(strstr(err.message, t[k].name));
			assert_non_null(strstr(err.message, "out of range"));
			break;
		case DAO_ROS_PARAM_INT:
			assert_int_equal(dao_ros_param_set_int(&q, &t[k], (long)d.max, &err), 0);
			assert_int_equal(dao_ros_param_get_int(&q, &t[k]), (long)d.max);
			assert_int_equal(dao_ros_param_set_int(&q, &t[k], (long)d.max + 1, &err), -EINVAL);
			assert_int_equal(dao_ros_param_set_double(&q, &t[k], d.min, &err), 0);
			assert_int_equal(dao_ros_param_get_int(&q, &t[k]), (long)d.min);
			assert_int_equal(dao_ros_param_set_double(&q, &t[k], d.min + 0.5, &err), -EINVAL);
			assert_non_null(strstr(err.message, "is not an integer"));
			break;
		case DAO_ROS_PARAM_STRING:
			assert_int_equal(t[k].type, DAO_PARAM_COLOR);
			assert_int_equal(dao_ros_param_set_string(&q, &t[k], "a0b1c2", &err), 0);
			assert_int_equal(dao_ros_param_get_int(&q, &t[k]), 0xa0b1c2);
			assert_int_equal(dao_ros_param_set_int(&q, &t[k], 0x102030, &err), 0);
			assert_int_equal(dao_ros_param_get_string(&q, &t[k], text, sizeof text, &err), 0);
			assert_string_equal(text, "102030");
			break;
		}
	}
	/* enums: by index and by name; a wrong index lists the choices */
	const struct dao_param_info *pf = dao_param_find("prefilter");
	struct dao_ros_param_desc d;
	dao_ros_param_describe(pf, &d);
	assert_int_equal(d.kind, DAO_ROS_PARAM_INT);
	assert_true(d.min == 0 && d.max == 2);
	assert_int_equal(dao_ros_param_set_int(&p, pf, 1, &err), 0);
	assert_int_equal(p.prefilter, DAO_PREFILTER_BILATERAL);
	assert_int_equal(dao_ros_param_set_string(&p, pf, "domain", &err), 0);
	assert_int_equal(p.prefilter, DAO_PREFILTER_DOMAIN);
	assert_int_equal(dao_ros_param_set_int(&p, pf, 3, &err), -EINVAL);
	assert_string_equal(err.message, "prefilter: 3 is not one of: 0 none, 1 bilateral, 2 domain");
	/* floats come back exactly as text (%.9g) */
	const struct dao_param_info *pr = dao_param_find("depth_max");
	assert_int_equal(dao_ros_param_set_double(&p, pr, 7.123456789, &err), 0);
	char text[64];
	assert_int_equal(dao_ros_param_get_string(&p, pr, text, sizeof text, &err), 0);
	assert_true(strtof(text, NULL) == p.depth_max);
	/* the processor takes new parameters at once, and refuses invalid ones */
	struct dao_ros_proc *proc = make_proc("mono16", NULL);
	dao_ros_proc_get_params(proc, &q);
	q.radius = 0.2f;
	assert_int_equal(dao_ros_proc_set_params(proc, &q, &err), 0);
	q.radius = -1.0f;
	assert_int_equal(dao_ros_proc_set_params(proc, &q, &err), -EINVAL);
	dao_ros_proc_get_params(proc, &q);
	assert_true(q.radius == 0.2f);
	dao_ros_proc_destroy(proc);
}

/* steady state: 30 frames, big-endian 16UC1 (the swap buffer) and 32FC1 AO, a
 * parameter change among them: no allocation by anything in the process */
static void test_no_allocation(void **state)
{
	(void)state;
#ifdef __GLIBC__
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	dao_params_stream_defaults(&p);
	p.threads = 2;
	struct dao_ros_image img;
	struct dao_error err;
	dao_test_alloc_start();
	struct dao_ros_proc *proc = make_proc("32FC1", &p);
	make_image(in_buf, &img, "16UC1", 1, 4, 0);
	int r = run_frame(proc, &img, 1, &err);
	long made = dao_test_alloc_stop();
	assert_int_equal(r, 0);
	if (made == 0)
		fail_msg("the counter saw no allocation while the context was made");
	for (int i = 1; i < 3; i++) /* warm-up */
		assert_int_equal(run_frame(proc, &img, 1 + (uint64_t)i, &err), 0);
	struct dao_params q = p;
	q.radius = 0.3f;
	dao_test_alloc_start();
	for (int i = 3; i < 33 && !r; i++) {
		r = run_frame(proc, &img, 1 + (uint64_t)i, &err);
		if (i == 10)
			r = r || dao_ros_proc_set_params(proc, &q, &err);
	}
	long n = dao_test_alloc_stop();
	if (r)
		fail_msg("frame: %s", err.message);
	if (n)
		fail_msg("%ld allocations in 30 frames", n);
	dao_ros_proc_destroy(proc);
#else
	skip();
#endif
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_settings),
		cmocka_unit_test(test_encodings_agree),
		cmocka_unit_test(test_errors),
		cmocka_unit_test(test_camera_followed),
		cmocka_unit_test(test_projection_with_distortion),
		cmocka_unit_test(test_time_back_resets),
		cmocka_unit_test(test_poses),
		cmocka_unit_test(test_params),
		cmocka_unit_test(test_no_allocation),
		cmocka_unit_test(test_filtered_depth),
		cmocka_unit_test(test_rvl),
		cmocka_unit_test(test_compressed_depth),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
