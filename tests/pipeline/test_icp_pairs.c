/* SPDX-License-Identifier: MIT */
/*
 * The motion estimate's pair kernel (src/motion/icp_pairs*.c), checkasm
 * style: every kernel set this CPU runs against the reference on the room
 * scene of test_icp_scene.h (noisy, a pose off the truth so that the gates
 * and the biweight refuse some pairs), at every range end 1..67 and over the
 * whole grid; and the estimate with 1, 2 and 3 threads gives the same pose
 * to the bit (the chunks' sums are added in their order, whatever thread
 * summed them).
 *
 * Bound: the kernels compute the geometry with the reference's float
 * operations, so they accept the same pairs (n equal); they sum each lane in
 * floats over at most DAO_ICP_CHUNK pairs, so every sum may differ from the
 * reference's double sum by 1e-5 of the sum of the magnitudes of its terms
 * (2^-24 per addition times a chunk's 32 lanes' depth, with margin).
 */
#include <limits.h>
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
#include "pipeline/kernels.h"
#include "core/threadpool.h"
#include "test_icp_scene.h"

enum { STEP = 4, R = 6 };

struct bench {
	struct scene_fixture f;
	float *src;
	size_t cap;
	int count;
	struct dao_icp_step st;
};

/* the source grid with normals from central differences (towards the camera) */
static void make_source(struct bench *b)
{
	const struct dao_camera *cam = &b->f.cam;
	b->cap = ((size_t)(W / STEP) * (H / STEP) + DAO_ICP_PAD) / DAO_ICP_PAD * DAO_ICP_PAD;
	b->src = calloc(6 * b->cap, sizeof(float));
	assert_non_null(b->src);
	int k = 0;
	for (int y = R; y < H - R; y += STEP)
		for (int x = R; x < W - R; x += STEP) {
			const float *z = b->f.z1;
			const size_t i = (size_t)y * W + (size_t)x;
			if (!(z[i] > 0 && z[i - R] > 0 && z[i + R] > 0 && z[i - R * W] > 0 &&
			      z[i + R * W] > 0))
				continue;
			double p[3], l[3], r[3], u[3], d[3];
			dao_camera_pixel_to_view(cam, x, y, z[i], p);
			dao_camera_pixel_to_view(cam, x - R, y, z[i - R], l);
			dao_camera_pixel_to_view(cam, x + R, y, z[i + R], r);
			dao_camera_pixel_to_view(cam, x, y - R, z[i - R * W], u);
			dao_camera_pixel_to_view(cam, x, y + R, z[i + R * W], d);
			const double a[3] = {r[0] - l[0], r[1] - l[1], r[2] - l[2]};
			const double c[3] = {d[0] - u[0], d[1] - u[1], d[2] - u[2]};
			double n[3] = {a[1] * c[2] - a[2] * c[1], a[2] * c[0] - a[0] * c[2],
				       a[0] * c[1] - a[1] * c[0]};
			const double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
			if (!(len > 0))
				continue;
			const double sg = n[0] * p[0] + n[1] * p[1] + n[2] * p[2] > 0 ? -1 : 1;
			for (int j = 0; j < 3; j++) {
				b->src[(size_t)j * b->cap + (size_t)k] = (float)p[j];
				b->src[(size_t)(3 + j) * b->cap + (size_t)k] = (float)(sg * n[j] / len);
			}
			k++;
		}
	b->count = k;
}

static void bench_init(struct bench *b)
{
	fixture_init(&b->f);
	struct dao_pose prev_c, cur_c, truth, off;
	dao_pose_identity(&prev_c);
	pose_from(&cur_c, 1.0, 0.5, 0.01, 0.0, 0.01);
	render(&b->f, &prev_c, 1, 1.0, 11u, b->f.z0);
	render(&b->f, &cur_c, 1, 1.0, 23u, b->f.z1);
	relative(&prev_c, &cur_c, &truth);
	/* a step from 0.3 degree and 5 mm off the truth */
	pose_from(&off, 0.3, 0.0, 0.005, 0.0, 0.0);
	make_source(b);
	const struct dao_camera *cam = &b->f.cam;
	b->st = (struct dao_icp_step){
		.tz = b->f.z0, .w = W, .h = H, .r = R, .ax = cam->ax, .bx = cam->bx,
		.ay = cam->ay, .by = cam->by, .inv_ax = 1.0f / cam->ax, .inv_ay = 1.0f / cam->ay,
		.src = b->src, .cap = b->cap, .inv_scale = 1.0f / 2.5f, .gate2 = 0.1f * 0.1f,
		.cos_gate = 0.8660254f, .k2 = 0.0015f * 0.0015f, .q2 = 1e-6f / 12.0f,
		.tukey_c = 4.685f, .edge = 0.03f, .noise_weight = 1,
	};
	for (int i = 0; i < 3; i++) {
		for (int j = 0; j < 3; j++) {
			double s = 0;
			for (int k = 0; k < 3; k++)
				s += off.r[i * 3 + k] * truth.r[k * 3 + j];
			b->st.R[i * 3 + j] = (float)s;
		}
		double s = off.t[i];
		for (int k = 0; k < 3; k++)
			s += off.r[i * 3 + k] * truth.t[k];
		b->st.t[i] = (float)s;
	}
}

static void bench_free(struct bench *b)
{
	free(b->src);
	fixture_free(&b->f);
}

/* the sum of |terms| of each sum, from the reference run pair by pair */
static void magnitudes(const struct dao_icp_step *st, int i0, int i1, double mag[31])
{
	memset(mag, 0, 31 * sizeof(double));
	for (int i = i0; i < i1; i++) {
		struct dao_icp_sums one;
		dao_icp_pairs_ref(st, i, i + 1, &one);
		for (int k = 0; k < 21; k++)
			mag[k] += fabs(one.a[k]);
		for (int k = 0; k < 6; k++)
			mag[21 + k] += fabs(one.b[k]);
		mag[27] += one.r2, mag[28] += one.e2w, mag[29] += one.wsum;
	}
}

static void compare(const char *isa, const struct dao_icp_step *st, int i0, int i1,
		    dao_icp_pairs_fn fn)
{
	struct dao_icp_sums ref, got;
	dao_icp_pairs_ref(st, i0, i1, &ref);
	fn(st, i0, i1, &got);
	double mag[31];
	magnitudes(st, i0, i1, mag);
	if (got.n != ref.n)
		fail_msg("%s [%d, %d): %d pairs, reference %d", isa, i0, i1, got.n, ref.n);
	const double *gv[4] = {got.a, got.b, &got.r2, &got.e2w};
	const double *rv[4] = {ref.a, ref.b, &ref.r2, &ref.e2w};
	const int len[4] = {21, 6, 1, 2 + 0}, base[4] = {0, 21, 27, 28};
	for (int g = 0; g < 4; g++)
		for (int k = 0; k < len[g]; k++) {
			const double e = fabs(gv[g][k] - rv[g][k]);
			if (!(e <= 1e-5 * mag[base[g] + k] + 1e-30))
				fail_msg("%s [%d, %d): sum %d off by %g (bound %g)", isa, i0, i1,
					 base[g] + k, e, 1e-5 * mag[base[g] + k]);
		}
}

static void test_kernels(void **state)
{
	(void)state;
	struct bench b;
	bench_init(&b);
	struct dao_icp_sums all;
	dao_icp_pairs_ref(&b.st, 0, b.count, &all);
	printf("%d source points, %d pairs\n", b.count, all.n);
	/* the case refuses some and keeps most */
	assert_true(all.n > b.count / 2 && all.n < b.count);
	int tested = 0;
	for (int s = DAO_SIMD_GENERIC; s < DAO_SIMD_COUNT; s++) {
		if (!dao_simd_supported((enum dao_simd)s))
			continue;
		struct dao_kernels k;
		dao_kernels_select(&k, (enum dao_simd)s);
		char name[16];
		snprintf(name, sizeof name, "simd %d", s);
		for (int n = 1; n <= 67; n++)
			compare(name, &b.st, 1000, 1000 + n, k.icp_pairs);
		compare(name, &b.st, 0, b.count, k.icp_pairs);
		/* the biweight alone (the verdict's conditioning pass) */
		b.st.noise_weight = 0;
		compare(name, &b.st, 0, b.count, k.icp_pairs);
		b.st.noise_weight = 1;
		tested++;
	}
	printf("%d kernel sets against the reference\n", tested);
	assert_true(tested >= 1);
	bench_free(&b);
}

static void test_threads_identical(void **state)
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
	struct dao_kernels k;
	dao_kernels_select(&k, dao_simd_supported(DAO_SIMD_AVX2) ? DAO_SIMD_AVX2 : DAO_SIMD_GENERIC);
	s.pairs = k.icp_pairs;
	float *scratch = malloc(dao_icp_scratch_floats(&s, W, H) * sizeof(float));
	assert_non_null(scratch);
	struct dao_icp_result one;
	dao_icp_estimate(&s, &f.cam, f.inv0, NULL, f.z1, NULL, scratch, &one);
	assert_true(one.valid);
	for (int t = 1; t <= 3; t++) {
		struct dao_pool *pool;
		assert_int_equal(dao_pool_create(&pool, t), 0);
		s.pool = pool;
		/* every step's chunks on the threads (the default), then the steps
		 * on the caller alone (the source grid and the target on the threads) */
		for (int all = 1; all >= 0; all--) {
			s.pool_min_points = all ? 0 : INT_MAX;
			struct dao_icp_result r;
			dao_icp_estimate(&s, &f.cam, f.inv0, NULL, f.z1, NULL, scratch, &r);
			printf("%d threads%s: %d pairs, %d steps\n", t, all ? ", every step" : "",
			       r.inliers, r.iterations);
			assert_memory_equal(&r.pose, &one.pose, sizeof r.pose);
			assert_int_equal(r.inliers, one.inliers);
			assert_int_equal(r.iterations, one.iterations);
		}
		dao_pool_destroy(pool);
	}
	free(scratch);
	fixture_free(&f);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_kernels),
		cmocka_unit_test(test_threads_identical),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
