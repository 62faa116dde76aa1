/* SPDX-License-Identifier: MIT */
/*
 * Steady state allocates nothing: the test interposes the C allocator
 * (glibc) and counts every malloc/calloc/realloc/aligned allocation made by
 * any code in the process while 100 frames are processed and shaded, with
 * worker threads and for each preset, both temporal filters on.  Creating a context must be seen to
 * allocate, or the counter is not working and the test fails.
 */
#define _GNU_SOURCE
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/depthao.h>

#include "common/alloc_count.h"
#include "common/test_common.h"

#ifdef __GLIBC__

/* VBAO with the thickness estimated from the image instead of GTAO (its plane is
 * made with the context, never per frame) */
static int vbao_image;
/* HBAO instead of GTAO (its tile kernel, in strips at 640 wide) */
static int hbao;
/* depth-temporal-motion with the measured noise: icp, or source / source+icp with a
 * pose given before every frame (1 mm sideways a frame) */
static int motion_mode = DAO_DEPTH_MOTION_ICP;

static int give_pose(struct dao_context *ctx, int i, struct dao_error *err)
{
	const double q[4] = {0, 0, 0, 1}, t[3] = {0.001 * i, 0, 0};
	return motion_mode == DAO_DEPTH_MOTION_ICP ? 0 : dao_context_set_pose(ctx, q, t, err);
}

/* frames of W x H (at most 640 x 480: the noise estimate's cells are then
 * more than a small sort keeps on the stack) */
static int run_size(int W, int H, enum dao_quality q, int noise, int prefilter, int noise_model)
{
	static uint16_t depth[640 * 480];
	static uint8_t rgb[640 * 480 * 3];
	static uint16_t ao16[640 * 480];
	const int s = W / 160;
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) /* a floor meeting a wall, with a box, and noise */
			depth[y * W + x] = (uint16_t)((y > 75 * s ? 1500 + (H - y) * 16 / s : 2500) -
					   ((x > 50 * s && x < 90 * s && y > 45 * s && y < 85 * s) ? 600 : 0) +
					   (int)((unsigned)(x * 7919 + y * 104729) % 5u) - 2);
	struct dao_camera cam;
	struct dao_params p;
	struct dao_context *ctx;
	struct dao_error err;
	if (dao_camera_from_fov(&cam, W, H, 1.0210, 0.7959, &err)) {
		fprintf(stderr, "camera: %s\n", err.message);
		return 1;
	}
	dao_params_init(&p, q);
	dao_params_stream_defaults(&p); /* both temporal filters too */
	p.temporal = 0.8f;
	p.depth_temporal_persist = 2;
	p.depth_fill = 8; /* the depth output's fill: its plane allocated once */
	p.threads = 2;
	p.noise = noise;
	p.prefilter = prefilter;
	p.noise_model = noise_model;
	/* the camera-motion estimate with the measured noise (with the fixed
	 * model the temporal filter runs fused in the decode, as by default) */
	if (noise_model != DAO_NOISE_MODEL_FIXED)
		p.depth_temporal_motion = motion_mode;
	if (vbao_image) {
		p.algorithm = DAO_ALGORITHM_VBAO;
		p.vbao_thickness_mode = DAO_VBAO_THICKNESS_IMAGE;
	}
	if (hbao)
		p.algorithm = DAO_ALGORITHM_HBAO;
	dao_test_alloc_start();
	if (dao_context_create(&ctx, &cam, &p, &err)) {
		fprintf(stderr, "create: %s\n", err.message);
		return 1;
	}
	long at_create = dao_test_alloc_stop();
	if (at_create == 0) {
		fprintf(stderr, "FAIL: the allocation counter saw nothing while creating a context\n");
		return 1;
	}
	struct dao_frame in = { .format = DAO_PIXFMT_DEPTH16, .width = W, .height = H,
				.stride = 2 * W, .data = depth, .depth_unit = 0.001f };
	struct dao_frame ao = { .format = DAO_PIXFMT_GRAY16, .width = W, .height = H,
				.stride = 2 * W, .data = ao16 };
	struct dao_frame sh = { .format = DAO_PIXFMT_RGB24, .width = W, .height = H,
				.stride = 3 * W, .data = rgb };
	int r = 0;
	/* warm-up: the first frames may fill lazily built tables */
	for (int i = 0; i < 3 && !r; i++)
		r = give_pose(ctx, i, &err) ||
		    dao_context_process(ctx, &in, NULL, (uint64_t)i, &ao, &err) ||
		    dao_context_shade(ctx, &sh, &err);
	dao_test_alloc_start();
	for (int i = 3; i < 103 && !r; i++) {
		/* every other frame the AO and the shading in one call */
		r = give_pose(ctx, i, &err);
		if (r)
			break;
		if (i & 1)
			r = dao_context_process_shaded(ctx, &in, NULL, (uint64_t)i, &ao, &sh, &err);
		else
			r = dao_context_process(ctx, &in, NULL, (uint64_t)i, &ao, &err) ||
			    dao_context_shade(ctx, &sh, &err);
		if (i == 50) { /* run-time parameter changes, as the daemon's `set` makes */
			struct dao_params changed = p;
			changed.radius = 1.5f * p.radius;
			changed.slices = p.slices + 2;
			changed.steps = p.steps + 4;
			changed.thickness = 0.3f;
			changed.shade_power = 2.0f;
			r = r || dao_context_set_params(ctx, &changed, &err);
		}
		if (i == 60) /* and back */
			r = r || dao_context_set_params(ctx, &p, &err);
		if (i == 70) /* a cut: the histories start over */
			dao_context_reset(ctx);
	}
	long steady = dao_test_alloc_stop();
	dao_context_destroy(ctx);
	if (r) {
		fprintf(stderr, "FAIL: processing: %s\n", err.message);
		return 1;
	}
	printf("%dx%d %-6s noise %d prefilter %d noise model %d%s: %ld allocations creating the "
	       "context, %ld in 100 frames\n", W, H, dao_quality_name(q), noise, prefilter,
	       noise_model, vbao_image ? " vbao image" : hbao ? " hbao" : "", at_create, steady);
	if (steady != 0) {
		fprintf(stderr, "FAIL: %ld heap allocations in steady state\n", steady);
		return 1;
	}
	return 0;
}

static int run(enum dao_quality q, int noise, int prefilter, int noise_model)
{
	return run_size(160, 120, q, noise, prefilter, noise_model);
}

int main(void)
{
	int r = 0;
	for (int q = 0; q < DAO_QUALITY_COUNT; q++)
		r |= run((enum dao_quality)q, DAO_NOISE_TILE, DAO_PREFILTER_BILATERAL,
			 DAO_NOISE_MODEL_FIXED);
	r |= run(DAO_QUALITY_DEFAULT, DAO_NOISE_IGN, DAO_PREFILTER_BILATERAL, DAO_NOISE_MODEL_FIXED);
	r |= run(DAO_QUALITY_DEFAULT, DAO_NOISE_R2, DAO_PREFILTER_BILATERAL, DAO_NOISE_MODEL_FIXED);
	/* the domain prefilter, with the fixed and the measured noise */
	for (int m = DAO_NOISE_MODEL_FIXED; m <= DAO_NOISE_MODEL_AUTO_PREFILTER; m++)
		r |= run(DAO_QUALITY_DEFAULT, DAO_NOISE_TILE, DAO_PREFILTER_DOMAIN, m);
	r |= run(DAO_QUALITY_DEFAULT, DAO_NOISE_TILE, DAO_PREFILTER_BILATERAL, DAO_NOISE_MODEL_AUTO);
	r |= run_size(640, 480, DAO_QUALITY_DEFAULT, DAO_NOISE_TILE, DAO_PREFILTER_DOMAIN,
		      DAO_NOISE_MODEL_AUTO);
	for (motion_mode = DAO_DEPTH_MOTION_SOURCE; motion_mode <= DAO_DEPTH_MOTION_SOURCE_ICP;
	     motion_mode++)
		r |= run(DAO_QUALITY_DEFAULT, DAO_NOISE_TILE, DAO_PREFILTER_DOMAIN, DAO_NOISE_MODEL_AUTO);
	motion_mode = DAO_DEPTH_MOTION_ICP;
	vbao_image = 1;
	r |= run(DAO_QUALITY_DEFAULT, DAO_NOISE_TILE, DAO_PREFILTER_DOMAIN, DAO_NOISE_MODEL_AUTO);
	vbao_image = 0;
	hbao = 1;
	r |= run_size(640, 480, DAO_QUALITY_DEFAULT, DAO_NOISE_TILE, DAO_PREFILTER_BILATERAL,
		      DAO_NOISE_MODEL_FIXED);
	return r;
}
#else
static int run(enum dao_quality q, int noise, int prefilter, int noise_model)
{
	return run_size(160, 120, q, noise, prefilter, noise_model);
}

int main(void)
{
	printf("SKIP: the allocation counter interposes glibc's allocator; this is not glibc\n");
	return DAO_TEST_SKIP;
}
#endif
