/* SPDX-License-Identifier: MIT */
/*
 * The temporal depth history carried by the camera's motion
 * (src/motion/reproject.c) against a brute-force reference written here
 * independently (double precision: every source pixel moved, each target
 * keeping the nearest), and against the truth: the previous frame's depth
 * moved by the true motion is the current frame's depth.
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

#include "motion/reproject.h"
#include "pipeline/kernels.h"
#include "core/threadpool.h"
#include "motion_fixture.h"

struct planes {
	float *hist, *out;
	uint8_t *count, *age, *count_out, *age_out;
	double *ref;   /* reference 1/z, 0 = none */
	long *ref_src; /* reference: the source pixel that won */
	int32_t *scratch;
};

static void planes_init(struct planes *p, size_t n)
{
	p->hist = calloc(n, sizeof(float));
	p->out = calloc(n, sizeof(float));
	p->count = calloc(n, 1);
	p->age = calloc(n, 1);
	p->count_out = calloc(n, 1);
	p->age_out = calloc(n, 1);
	p->ref = calloc(n, sizeof(double));
	p->ref_src = calloc(n, sizeof(long));
	p->scratch = calloc(dao_history_reproject_scratch(W, H), sizeof(int32_t));
	assert_true(p->hist && p->out && p->count && p->age && p->count_out && p->age_out &&
		    p->ref && p->ref_src && p->scratch);
}

static void planes_free(struct planes *p)
{
	free(p->hist), free(p->out), free(p->count), free(p->age);
	free(p->count_out), free(p->age_out), free(p->ref), free(p->ref_src);
	free(p->scratch);
}

/* every source pixel through the inverse pose in double, z-buffered */
static void reference(const struct dao_camera *cam, const struct dao_pose *cur_to_prev,
		      const struct planes *p)
{
	const size_t n = (size_t)cam->width * cam->height;
	for (size_t i = 0; i < n; i++)
		p->ref[i] = 0.0, p->ref_src[i] = -1;
	for (size_t i = 0; i < n; i++) {
		if (!p->count[i] || !(p->hist[i] > 0.0f))
			continue;
		double a[3], b[3], u, v;
		dao_camera_pixel_to_view(cam, (double)(i % cam->width), (double)(i / cam->width),
					 1.0 / p->hist[i], a);
		pose_apply_inverse(cur_to_prev, a, b); /* b = R^T (a - t) */
		if (dao_camera_view_to_pixel(cam, b, &u, &v))
			continue;
		const double xu = floor(u + 0.5), yv = floor(v + 0.5);
		if (xu < 0 || yv < 0 || xu >= cam->width || yv >= cam->height)
			continue;
		const size_t o = (size_t)yv * cam->width + (size_t)xu;
		if (p->ref_src[o] < 0 || 1.0 / b[2] > p->ref[o])
			p->ref[o] = 1.0 / b[2], p->ref_src[o] = (long)i;
	}
}

static void test_against_reference(void **state)
{
	(void)state;
	struct scene_fixture f;
	fixture_init(&f);
	struct planes p;
	planes_init(&p, f.npix);
	struct two_views v;
	two_views_make(&v, (const double[5]){0.0, 0.0, 0.0, 0.0, 0.0},
		       (const double[5]){1.5, -0.7, 0.02, 0.005, -0.01});
	render(&f, &v.prev, 1, 1.0, 3u, f.z0);
	for (size_t i = 0; i < f.npix; i++) {
		/* holes, and counts and ages that tell the sources apart */
		const int hole = (i * 2654435761u) % 13u == 0;
		p.hist[i] = f.z0[i] > 0.0f ? 1.0f / f.z0[i] : 0.0f;
		p.count[i] = hole ? 0 : (uint8_t)(1 + i % 200);
		p.age[i] = (uint8_t)(i % 7);
	}
	dao_history_reproject(&f.cam, &v.motion, p.hist, p.count, p.age, p.out, p.count_out,
			      p.age_out, p.scratch, NULL, NULL);
	reference(&f.cam, &v.motion, &p);
	size_t filled = 0, differ = 0, value_off = 0;
	for (size_t i = 0; i < f.npix; i++) {
		const int have = p.count_out[i] != 0, ref_have = p.ref_src[i] >= 0;
		filled += (size_t)ref_have;
		if (have != ref_have) {
			differ++;
			continue;
		}
		if (!have) {
			assert_true(p.out[i] == 0.0f && p.age_out[i] == 255);
			continue;
		}
		/* the same winner (count and age identify it), or a tie at a
		 * rounding boundary */
		const long s = p.ref_src[i];
		if (p.count_out[i] != p.count[s] || p.age_out[i] != p.age[s]) {
			differ++;
			continue;
		}
		if (fabs(p.out[i] - p.ref[i]) > 1e-5 * p.ref[i])
			value_off++;
	}
	printf("reprojection: %zu of %zu pixels filled, %zu differ from the reference "
	       "(pixel-centre rounding), %zu values off\n", filled, f.npix, differ, value_off);
	assert_true(filled > f.npix * 8 / 10);
	assert_true(differ * 1000 < filled); /* under 0.1 % */
	assert_int_equal(value_off, 0);
	planes_free(&p);
	fixture_free(&f);
}

/* the previous frame's clean depth carried by the true motion is the
 * current frame's, but where the view uncovers what was hidden */
static void test_against_truth(void **state)
{
	(void)state;
	struct scene_fixture f;
	fixture_init(&f);
	struct planes p;
	planes_init(&p, f.npix);
	struct two_views v;
	two_views_make(&v, (const double[5]){-2.0, 0.0, 0.0, 0.0, 0.0},
		       (const double[5]){0.0, 1.0, 0.03, 0.0, 0.02});
	two_views_render(&f, &v, 0.0, 0u, 0u);
	for (size_t i = 0; i < f.npix; i++) {
		p.hist[i] = 1.0f / f.z0[i];
		p.count[i] = 1;
	}
	dao_history_reproject(&f.cam, &v.motion, p.hist, p.count, p.age, p.out, p.count_out,
			      p.age_out, p.scratch, NULL, NULL);
	size_t have = 0, close = 0;
	for (size_t i = 0; i < f.npix; i++) {
		if (!p.count_out[i])
			continue;
		have++;
		close += fabsf(1.0f / p.out[i] - f.z1[i]) < 0.005f * f.z1[i];
	}
	printf("against the truth: %zu pixels with history, %zu within 0.5 %%\n", have, close);
	assert_true(have > f.npix * 9 / 10);
	assert_true(close > have * 97 / 100);
	planes_free(&p);
	fixture_free(&f);
}

/* random and hostile poses (huge, behind the camera, NaN, infinite): every
 * output pixel is either empty or a source's history, nothing else written */
static void test_fuzzed_poses(void **state)
{
	(void)state;
	struct scene_fixture f;
	fixture_init(&f);
	struct planes p;
	planes_init(&p, f.npix);
	struct dao_pose id;
	dao_pose_identity(&id);
	render(&f, &id, 1, 1.0, 9u, f.z0);
	for (size_t i = 0; i < f.npix; i++) {
		p.hist[i] = 1.0f / f.z0[i];
		p.count[i] = 7;
		p.age[i] = 1;
	}
	uint64_t st = 12345u;
	for (int k = 0; k < 40; k++) {
		struct dao_pose m;
		fuzzed_motion(&st, k, 40, &m);
		dao_history_reproject(&f.cam, &m, p.hist, p.count, p.age, p.out, p.count_out,
				      p.age_out, p.scratch, NULL, NULL);
		for (size_t i = 0; i < f.npix; i++) {
			if (p.count_out[i]) {
				assert_int_equal(p.count_out[i], 7);
				assert_int_equal(p.age_out[i], 1);
				assert_true(p.out[i] > 0.0f && isfinite(p.out[i]));
			} else {
				assert_true(p.out[i] == 0.0f && p.age_out[i] == 255);
			}
		}
	}
	planes_free(&p);
	fixture_free(&f);
}

/* the landing pass of every kernel set, and the splat by output bands on 1, 2
 * and 3 threads: the reference's output to the bit, on the noisy room moved
 * by small and fuzzed poses, with holes */
static void test_kernels_threads(void **state)
{
	(void)state;
	struct scene_fixture f;
	fixture_init(&f);
	struct planes p, q;
	planes_init(&p, f.npix);
	planes_init(&q, f.npix);
	struct dao_pose id;
	dao_pose_identity(&id);
	render(&f, &id, 1, 1.0, 5u, f.z0);
	for (size_t i = 0; i < f.npix; i++) {
		const int hole = (i * 2654435761u) % 11u == 0;
		p.hist[i] = f.z0[i] > 0.0f ? 1.0f / f.z0[i] : 0.0f;
		p.count[i] = hole ? 0 : (uint8_t)(1 + i % 200);
		p.age[i] = (uint8_t)(i % 7);
	}
	struct dao_pool *pools[3];
	for (int t = 0; t < 3; t++)
		assert_int_equal(dao_pool_create(&pools[t], t + 1), 0);
	const size_t n = f.npix;
	int32_t *dest = q.scratch;
	float *zinv = (float *)(q.scratch + n);
	uint64_t st = 777u;
	int sets = 0;
	for (int k = 0; k < 12; k++) {
		struct dao_pose m;
		const double sc = k < 8 ? 0.02 : 1.0;
		pose_from(&m, sc * 100.0 * gauss(&st), sc * 100.0 * gauss(&st), sc * gauss(&st),
			  sc * gauss(&st), sc * gauss(&st));
		if (k == 0)
			dao_pose_identity(&m);
		dao_history_reproject(&f.cam, &m, p.hist, p.count, p.age, p.out, p.count_out,
				      p.age_out, p.scratch, NULL, NULL);
		sets = 0;
		for (int s = DAO_SIMD_REFERENCE; s < DAO_SIMD_COUNT; s++) {
			if (s != DAO_SIMD_REFERENCE &&
			    (s < DAO_SIMD_GENERIC || !dao_simd_supported((enum dao_simd)s)))
				continue;
			struct dao_kernels kern;
			dao_kernels_select(&kern, (enum dao_simd)s);
			for (int t = 0; t < 3; t++) {
				memset(q.out, 0x55, n * sizeof(float));
				memset(q.count_out, 0x55, n);
				memset(q.age_out, 0x55, n);
				dao_history_reproject(&f.cam, &m, p.hist, p.count, p.age, q.out,
						      q.count_out, q.age_out, q.scratch,
						      kern.reproject_land, pools[t]);
				assert_memory_equal(q.out, p.out, n * sizeof(float));
				assert_memory_equal(q.count_out, p.count_out, n);
				assert_memory_equal(q.age_out, p.age_out, n);
				/* the landing pass itself */
				assert_memory_equal(dest, p.scratch, n * sizeof(int32_t));
				assert_memory_equal(q.scratch + 2 * n, p.scratch + 2 * n,
						    2 * (size_t)H * sizeof(int32_t));
				for (size_t i = 0; i < n; i++)
					if (dest[i] >= 0 &&
					    memcmp(zinv + i, (float *)(p.scratch + n) + i, sizeof(float)))
						fail_msg("simd %d pose %d: 1/z of pixel %zu differs", s, k,
							 i);
			}
			sets++;
		}
	}
	printf("%d kernel sets (the reference included) on 1, 2 and 3 threads\n", sets);
	assert_true(sets >= 2);
	for (int t = 0; t < 3; t++)
		dao_pool_destroy(pools[t]);
	planes_free(&p);
	planes_free(&q);
	fixture_free(&f);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_against_reference),
		cmocka_unit_test(test_against_truth),
		cmocka_unit_test(test_fuzzed_poses),
		cmocka_unit_test(test_kernels_threads),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
