/* SPDX-License-Identifier: MIT */
/*
 * depth-fill (dao_params.depth_fill): the filtered depth output's one-surface
 * hole fill (kernels/depth_fill.h).  A hole between two samples of one plane
 * takes the plane's depth; one across a depth step, at the border or wider
 * than the limit stays a hole; the normals and the AO never see the fill.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/cmocka_all.h"
#include "common/test_common.h"

enum { W = 128, H = 96, STEP_X = 96 };

/* A tilted plane, z = 1 m + 2 mm per column; right of STEP_X a surface 0.3 m
 * farther (a depth step of 26 %, far beyond the 3 % of one surface). */
static float truth(int x)
{
	return 1.0f + 0.002f * (float)x + (x >= STEP_X ? 0.3f : 0.0f);
}

/* The holes of the scene, one row each, and the smallest limit that fills them
 * (0: none does). */
static const struct hole {
	int y, x0, x1, fill_from;
	const char *what;
} holes[] = {
	{ 20, 30, 34, 5, "5 px inside the plane" },
	{ 40, 50, 59, 10, "10 px inside the plane" },
	{ 60, 93, 98, 0, "across the depth step" },
	{ 70, 0, 2, 0, "at the border" },
};
#define NHOLES (sizeof holes / sizeof holes[0])

static int filled_at(const struct hole *h, int limit)
{
	return h->fill_from && limit >= h->fill_from;
}

/* What every case uses: the scene, outputs for it, the camera and parameters
 * (one thread, no AO). */
struct fixture {
	float *in, *out, *off;
	uint16_t *ao0, *ao1, *counts;
	struct dao_camera cam;
	struct dao_params p;
	struct dao_context *ctx;
};

static int setup(void **state)
{
	struct fixture *fx = calloc(1, sizeof *fx);
	assert_non_null(fx);
	fx->in = malloc(3 * sizeof(float) * W * H); /* in, out, off */
	fx->ao0 = malloc(3 * sizeof(uint16_t) * W * H); /* ao0, ao1, counts */
	assert_true(fx->in && fx->ao0);
	fx->out = fx->in + W * H;
	fx->off = fx->out + W * H;
	fx->ao1 = fx->ao0 + W * H;
	fx->counts = fx->ao1 + W * H;
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++)
			fx->in[y * W + x] = truth(x);
	for (size_t k = 0; k < NHOLES; k++)
		for (int x = holes[k].x0; x <= holes[k].x1; x++)
			fx->in[holes[k].y * W + x] = 0.0f;
	assert_int_equal(dao_camera_from_intrinsics(&fx->cam, W, H, 110, 110, 63.5, 47.5, NULL), 0);
	dao_params_init(&fx->p, DAO_QUALITY_DEFAULT);
	fx->p.threads = 1;
	fx->p.algorithm = DAO_ALGORITHM_NONE;
	*state = fx;
	return 0;
}

static int teardown(void **state)
{
	struct fixture *fx = *state;
	dao_context_destroy(fx->ctx);
	free(fx->in);
	free(fx->ao0);
	free(fx);
	return 0;
}

static struct dao_frame f32_frame(float *z)
{
	return (struct dao_frame){ .format = DAO_PIXFMT_DEPTH_F32, .width = W, .height = H,
				   .stride = 4 * W, .data = z };
}

/* Frame `t` of the scene with depth-fill FILL through the fixture's context
 * (made at the first frame, its parameters set after): the filtered depth into
 * `depth`, the AO into `ao` unless NULL. */
static void process(struct fixture *fx, int fill, uint64_t t, struct dao_frame *depth,
		    uint16_t *ao)
{
	struct dao_error err;
	struct dao_frame d = f32_frame(fx->in);
	struct dao_frame a = { .format = DAO_PIXFMT_GRAY16, .width = W, .height = H,
			       .stride = 2 * W, .data = ao };
	fx->p.depth_fill = fill;
	if ((fx->ctx ? dao_context_set_params(fx->ctx, &fx->p, &err)
		     : dao_context_create(&fx->ctx, &fx->cam, &fx->p, &err)) ||
	    dao_context_process(fx->ctx, &d, NULL, t, ao ? &a : NULL, &err) ||
	    dao_context_get_depth(fx->ctx, depth, &err))
		fail_msg("fill %d, frame %d: %s", fill, (int)t, err.message);
}

/* The filtered depth of a fresh context into `out` (and the AO into `ao` unless NULL). */
static void run(struct fixture *fx, int algorithm, int fill, float *out, uint16_t *ao)
{
	struct dao_frame o = f32_frame(out);
	dao_context_destroy(fx->ctx);
	fx->ctx = NULL;
	fx->p.algorithm = algorithm;
	process(fx, fill, 0, &o, ao);
}

static int in_hole(int i, const struct hole *h)
{
	return i / W == h->y && i % W >= h->x0 && i % W <= h->x1;
}

/* Each limit fills the holes it reaches with the plane's depth (the samples beside
 * them are the prefilter's, exact on a noise-free plane to well within a millimetre),
 * leaves the others holes, and changes nothing else: the unfilled output, bit for bit. */
static void test_fill_rule(void **state)
{
	struct fixture *fx = *state;
	static const int limits[] = { 0, 4, 8, 10, 16 };
	run(fx, DAO_ALGORITHM_NONE, 0, fx->off, NULL);
	for (size_t l = 0; l < sizeof limits / sizeof limits[0]; l++) {
		run(fx, DAO_ALGORITHM_NONE, limits[l], fx->out, NULL);
		for (size_t k = 0; k < NHOLES; k++) {
			const struct hole *h = &holes[k];
			for (int x = h->x0; x <= h->x1; x++) {
				const float got = fx->out[h->y * W + x];
				if (filled_at(h, limits[l]) ? !(fabsf(got - truth(x)) < 0.5e-3f)
							    : got != 0.0f)
					fail_msg("limit %d, hole %s, x = %d: %.5f m (the plane %.5f m)",
						 limits[l], h->what, x, (double)got, (double)truth(x));
			}
		}
		for (int i = 0; i < W * H; i++) {
			int filled = 0;
			for (size_t k = 0; k < NHOLES; k++)
				filled |= in_hole(i, &holes[k]) && filled_at(&holes[k], limits[l]);
			if (!filled)
				assert_memory_equal(&fx->out[i], &fx->off[i], sizeof(float));
		}
	}
}

/* The counts output is filled too: it is the same plane converted. */
static void test_fill_counts(void **state)
{
	struct fixture *fx = *state;
	struct dao_frame o = { .format = DAO_PIXFMT_DEPTH16, .width = W, .height = H,
			       .stride = 2 * W, .data = fx->counts, .depth_unit = 0.001f };
	process(fx, 8, 0, &o, NULL);
	for (size_t k = 0; k < NHOLES; k++)
		for (int x = holes[k].x0; x <= holes[k].x1; x++) {
			const int got = fx->counts[holes[k].y * W + x];
			if (filled_at(&holes[k], 8))
				assert_true(abs(got - (int)lrintf(truth(x) * 1000.0f)) <= 1);
			else
				assert_int_equal(got, 0);
		}
}

/* The AO (GTAO; VBAO with the thickness from the image, whose own dropout fill
 * is the same rule) is the same to the bit with and without depth-fill. */
static void test_ao_unchanged(void **state)
{
	struct fixture *fx = *state;
	static const int algos[] = { DAO_ALGORITHM_GTAO, DAO_ALGORITHM_VBAO };
	for (size_t k = 0; k < sizeof algos / sizeof algos[0]; k++) {
		run(fx, algos[k], 0, fx->out, fx->ao0);
		assert_true(fx->out[20 * W + 32] == 0.0f);
		run(fx, algos[k], 16, fx->out, fx->ao1);
		assert_true(fx->out[20 * W + 32] > 0.0f);         /* the fill ran ... */
		assert_memory_equal(fx->ao0, fx->ao1, 2 * W * H); /* ... and the AO did not see it */
	}
}

/* depth-fill is a runtime parameter: turned on and off on a running context, the next
 * frame's output follows (its plane allocated when it is first turned on). */
static void test_fill_runtime(void **state)
{
	struct fixture *fx = *state;
	static const int fills[] = { 0, 8, 0 };
	struct dao_frame o = f32_frame(fx->out);
	for (int k = 0; k < 3; k++) {
		process(fx, fills[k], (uint64_t)k, &o, NULL);
		if (fills[k])
			assert_true(fabsf(fx->out[20 * W + 32] - truth(32)) < 0.5e-3f);
		else
			assert_true(fx->out[20 * W + 32] == 0.0f);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(test_fill_rule, setup, teardown),
		cmocka_unit_test_setup_teardown(test_fill_counts, setup, teardown),
		cmocka_unit_test_setup_teardown(test_ao_unchanged, setup, teardown),
		cmocka_unit_test_setup_teardown(test_fill_runtime, setup, teardown),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
