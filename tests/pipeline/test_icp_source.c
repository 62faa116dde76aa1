/* SPDX-License-Identifier: MIT */
/*
 * The motion estimate's source grid with its normals and the target's depth
 * (src/motion/icp_source*.c), checkasm style: every kernel set this CPU
 * runs gives the reference's output to the bit (the same float operations
 * in the same order), on the noisy room of test_icp_scene.h with holes,
 * NaNs and infinities dropped in, at every width 1..67 over several heights,
 * steps and normal radii (the pad columns included), and the target's depth
 * over every range end; and the estimate with a kernel set's source and
 * target gives the same pose to the bit as with the references'.
 */
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <depthao/cpu.h>

#include "motion/icp.h"
#include "motion/icp_pairs.h"
#include "motion/icp_source.h"
#include "pipeline/kernels.h"
#include "test_icp_scene.h"

static uint64_t rng = 0x9e3779b97f4a7c15u;
static uint32_t next(void)
{
	rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
	return (uint32_t)(rng >> 11);
}

/* the noisy room, with holes, NaNs, infinities and negative depth here and there */
static void spoil(float *z, size_t n)
{
	for (size_t i = 0; i < n; i++) {
		const uint32_t u = next() % 1000;
		if (u < 20)
			z[i] = 0.0f;
		else if (u == 20)
			z[i] = NAN;
		else if (u == 21)
			z[i] = INFINITY;
		else if (u == 22)
			z[i] = -1.0f;
	}
}

/* every grid row of a w x h crop of z (stride W) through fn and the reference */
static int compare_grid(const char *isa, dao_icp_source_fn fn, const float *zsrc, int w, int h,
			int step, int r)
{
	float *z = malloc((size_t)w * (size_t)h * sizeof(float));
	assert_non_null(z);
	for (int y = 0; y < h; y++)
		memcpy(z + (size_t)y * w, zsrc + (size_t)y * W, (size_t)w * sizeof(float));
	const int gw = (w + step - 1) / step;
	const size_t stride = ((size_t)gw + DAO_ICP_PAD - 1) / DAO_ICP_PAD * DAO_ICP_PAD + DAO_ICP_PAD;
	const struct dao_icp_grid g = {
		.z = z, .w = w, .h = h, .r = r, .step = step, .gw = gw, .stride = stride,
		.edge_r = 0.03f * (float)r, .ax = 1.0f / 525.0f, .bx = -0.5f * (float)w / 525.0f,
		.ay = 1.0f / 525.0f, .by = -0.5f * (float)h / 525.0f,
		.rax = (float)r / 525.0f, .ray = (float)r / 525.0f,
	};
	float *a = malloc(6 * stride * sizeof(float)), *b = malloc(6 * stride * sizeof(float));
	assert_non_null(a);
	assert_non_null(b);
	int points = 0;
	for (int y = 0; y < h; y += step) {
		/* canaries past the padded row */
		for (size_t i = 0; i < 6 * stride; i++)
			a[i] = b[i] = -7.0f;
		dao_icp_source_ref(&g, y, a);
		fn(&g, y, b);
		if (memcmp(a, b, 6 * stride * sizeof(float)))
			for (size_t i = 0; i < 6 * stride; i++)
				if (memcmp(a + i, b + i, sizeof(float)))
					fail_msg("%s %dx%d step %d r %d: row %d, plane %zu column %zu: %a, "
						 "reference %a",
						 isa, w, h, step, r, y, i / stride, i % stride, (double)b[i],
						 (double)a[i]);
		for (int x = 0; x < gw; x++)
			points += a[2 * stride + (size_t)x] > 0.0f;
	}
	free(a);
	free(b);
	free(z);
	return points;
}

static void compare_target(const char *isa, dao_icp_target_fn fn, const float *inv,
			   const uint8_t *count, size_t i0, size_t i1)
{
	float *a = malloc((i1 + 1) * sizeof(float)), *b = malloc((i1 + 1) * sizeof(float));
	assert_non_null(a);
	assert_non_null(b);
	a[i1] = b[i1] = -7.0f;
	dao_icp_target_ref(inv, count, a, i0, i1);
	fn(inv, count, b, i0, i1);
	assert_true(b[i1] == -7.0f);
	if (memcmp(a + i0, b + i0, (i1 - i0) * sizeof(float)))
		fail_msg("%s target [%zu, %zu)%s differs", isa, i0, i1, count ? "" : " (no count)");
	free(a);
	free(b);
}

static void test_kernels(void **state)
{
	(void)state;
	struct scene_fixture f;
	fixture_init(&f);
	struct dao_pose c;
	pose_from(&c, 1.0, 0.5, 0.01, 0.0, 0.01);
	render(&f, &c, 1, 1.0, 23u, f.z1);
	spoil(f.z1, f.npix);
	uint8_t *count = malloc(f.npix);
	assert_non_null(count);
	for (size_t i = 0; i < f.npix; i++) {
		f.inv0[i] = f.z1[i] > 0.0f ? 1.0f / f.z1[i] : (next() % 2 ? 0.0f : -f.z1[i]);
		count[i] = (uint8_t)(next() % 5 ? 1 + next() % 200 : 0);
	}
	int tested = 0;
	for (int s = DAO_SIMD_GENERIC; s < DAO_SIMD_COUNT; s++) {
		if (!dao_simd_supported((enum dao_simd)s))
			continue;
		struct dao_kernels k;
		dao_kernels_select(&k, (enum dao_simd)s);
		char name[16];
		snprintf(name, sizeof name, "simd %d", s);
		const int vga = compare_grid(name, k.icp_source, f.z1, W, H, 4, 6);
		assert_true(vga > 10000);
		for (int w = 1; w <= 67; w++)
			for (int step = 1; step <= 5; step++)
				for (int r = 1; r <= 7; r += 3)
					compare_grid(name, k.icp_source, f.z1 + 200 * W + 300, w, 21 + w % 7,
						     step, r);
		for (size_t n = 0; n <= 67; n++) {
			compare_target(name, k.icp_target, f.inv0, count, 1000 + n % 5, 1005 + n);
			compare_target(name, k.icp_target, f.inv0, NULL, 1000 + n % 5, 1005 + n);
		}
		compare_target(name, k.icp_target, f.inv0, count, 0, f.npix);
		tested++;
	}
	printf("%d kernel sets against the reference\n", tested);
	assert_true(tested >= 1);
	free(count);
	fixture_free(&f);
}

/* the estimate with a kernel set's source and target: the references' pose to the bit */
static void test_estimate_identical(void **state)
{
	(void)state;
	struct scene_fixture f;
	fixture_init(&f);
	struct dao_pose prev_c, cur_c;
	dao_pose_identity(&prev_c);
	pose_from(&cur_c, 1.0, 0.5, 0.01, 0.0, 0.01);
	render_pair(&f, &prev_c, &cur_c, 1, 1.0, 11u, 1.0, 23u);
	struct dao_icp_setup s;
	dao_icp_setup_default(&s);
	float *scratch = malloc(dao_icp_scratch_floats(&s, W, H) * sizeof(float));
	assert_non_null(scratch);
	struct dao_icp_result ref;
	dao_icp_estimate(&s, &f.cam, f.inv0, NULL, f.z1, NULL, scratch, &ref);
	assert_true(ref.valid);
	for (int si = DAO_SIMD_GENERIC; si < DAO_SIMD_COUNT; si++) {
		if (!dao_simd_supported((enum dao_simd)si))
			continue;
		struct dao_kernels k;
		dao_kernels_select(&k, (enum dao_simd)si);
		s.source = k.icp_source;
		s.target = k.icp_target;
		struct dao_icp_result r;
		dao_icp_estimate(&s, &f.cam, f.inv0, NULL, f.z1, NULL, scratch, &r);
		assert_memory_equal(&r, &ref, sizeof r);
	}
	free(scratch);
	fixture_free(&f);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_kernels),
		cmocka_unit_test(test_estimate_identical),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
