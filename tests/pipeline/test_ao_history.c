/* SPDX-License-Identifier: MIT */
/*
 * The AO history carried by the camera's motion (src/motion/ao_reproject.c):
 * against a brute-force reference written here independently (double
 * precision, through the world frame with the two cameras' own poses, every
 * tap of every pixel tested); the identity motion copies the history bit for
 * bit; surfaces the previous view did not see (disocclusions) and pixels the
 * previous image did not cover get no history; hostile poses write nothing
 * but history values.  In the pipeline: a still camera with the AO history
 * on gives the same AO with and without depth-temporal-motion=icp, bit for
 * bit, and a panning one follows the motion (its AO closer to the frame's
 * own AO without history than with the history left in place).  Every
 * kernel set (motion/ao_reproject_simd.inc.c, floats) passes the same tests,
 * and against the reference kernel (doubles) at most 0.01 % of the pixels
 * differ in having history and 0.01 % in value by more than 1e-5.
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

#include <depthao/context.h>
#include <depthao/params.h>

#include <depthao/cpu.h>

#include "motion/ao_reproject.h"
#include "pipeline/kernels.h"
#include "motion_fixture.h"

#define REJECT 0.02f

struct planes {
	float *ao, *hz, *ao_out, *z_out;
	double *ref_ao, *ref_z; /* the reference: ref_z 0 = no history */
};

static void planes_init(struct planes *p, size_t n)
{
	p->ao = calloc(n, sizeof(float));
	p->hz = calloc(n, sizeof(float));
	p->ao_out = calloc(n, sizeof(float));
	p->z_out = calloc(n, sizeof(float));
	p->ref_ao = calloc(n, sizeof(double));
	p->ref_z = calloc(n, sizeof(double));
	assert_true(p->ao && p->hz && p->ao_out && p->z_out && p->ref_ao && p->ref_z);
}

static void planes_free(struct planes *p)
{
	free(p->ao), free(p->hz), free(p->ao_out), free(p->z_out), free(p->ref_ao), free(p->ref_z);
}

/* Every current pixel through the world into the previous camera, its four
 * bilinear taps weighed one by one (a tap counts where its depth agrees
 * within REJECT), the history's point moved back into the current camera. */
static void reference(const struct dao_camera *cam, const struct dao_pose *prev_c,
		      const struct dao_pose *cur_c, const float *z, struct planes *p)
{
	for (size_t i = 0; i < (size_t)W * H; i++) {
		p->ref_ao[i] = p->ref_z[i] = 0.0;
		if (!(z[i] > 0.0f))
			continue;
		double a[3], w[3], q[3], u, v;
		dao_camera_pixel_to_view(cam, (double)(i % W), (double)(i / W), z[i], a);
		pose_apply(cur_c, a, w);
		pose_apply_inverse(prev_c, w, q);
		if (dao_camera_view_to_pixel(cam, q, &u, &v) || u <= -0.5 || v <= -0.5 ||
		    u >= W - 0.5 || v >= H - 0.5)
			continue;
		double sw = 0.0, sa = 0.0, sz = 0.0;
		for (int dy = 0; dy < 2; dy++)
			for (int dx = 0; dx < 2; dx++) {
				const int x = (int)floor(u) + dx, y = (int)floor(v) + dy;
				const double wt = (1.0 - fabs(u - x)) * (1.0 - fabs(v - y));
				if (x < 0 || y < 0 || x >= W || y >= H || wt <= 0.0)
					continue;
				const double hz = p->hz[(size_t)y * W + x];
				if (hz > 0.0 && fabs(hz - q[2]) <= REJECT * q[2])
					sw += wt, sa += wt * p->ao[(size_t)y * W + x], sz += wt * hz;
			}
		if (sw <= 1e-6)
			continue;
		/* the history's point: on the previous camera's ray through q, at depth sz / sw */
		double hp[3], hw[3], hc[3];
		for (int k = 0; k < 3; k++)
			hp[k] = q[k] * (sz / sw) / q[2];
		pose_apply(prev_c, hp, hw);
		pose_apply_inverse(cur_c, hw, hc);
		p->ref_ao[i] = sa / sw;
		p->ref_z[i] = hc[2];
	}
}

/* the history of the previous view: its depth, and an AO that varies over the image */
static void make_history(const struct scene_fixture *f, struct planes *p)
{
	for (size_t i = 0; i < f->npix; i++) {
		p->hz[i] = f->z0[i];
		p->ao[i] = (float)(0.5 + 0.4 * sin(0.05 * (double)(i % W)) * cos(0.07 * (double)(i / W)));
	}
}

/* the kernel the tests run: the reference, then each kernel set's (test_kernel_sets) */
static dao_ao_reproject_fn kernel = dao_ao_history_reproject_rows;

static void run_rows(const struct scene_fixture *f, const struct dao_pose *m, const float *z,
		     struct planes *p)
{
	/* in three bands, as the pool would split it */
	kernel(&f->cam, m, REJECT, z, p->ao, p->hz, p->ao_out, p->z_out, 0, 100);
	kernel(&f->cam, m, REJECT, z, p->ao, p->hz, p->ao_out, p->z_out, 100, 101);
	kernel(&f->cam, m, REJECT, z, p->ao, p->hz, p->ao_out, p->z_out, 101, H);
}

static void test_against_reference(void **state)
{
	(void)state;
	struct scene_fixture f;
	fixture_init(&f);
	struct planes p;
	planes_init(&p, f.npix);
	struct two_views tv;
	two_views_make(&tv, (const double[5]){0.3, 0.2, 0.0, 0.0, 0.0},
		       (const double[5]){2.1, -0.6, 0.03, 0.004, -0.01});
	two_views_render(&f, &tv, 1.0, 3u, 4u);
	make_history(&f, &p);
	run_rows(&f, &tv.motion, f.z1, &p);
	reference(&f.cam, &tv.prev, &tv.cur, f.z1, &p);
	size_t filled = 0, differ = 0, off = 0;
	for (size_t i = 0; i < f.npix; i++) {
		const int have = p.z_out[i] > 0.0f, ref_have = p.ref_z[i] > 0.0;
		filled += (size_t)ref_have;
		if (!have)
			assert_true(p.ao_out[i] == 0.0f && p.z_out[i] == 0.0f);
		if (have != ref_have) {
			differ++; /* a tap at the gate's edge, or a landing point at the border */
			continue;
		}
		if (have && (fabs(p.ao_out[i] - p.ref_ao[i]) > 1e-5 ||
			     fabs(p.z_out[i] - p.ref_z[i]) > 1e-5 * p.ref_z[i]))
			off++;
	}
	printf("AO history: %zu of %zu pixels with history, %zu differ from the reference, "
	       "%zu values off\n", filled, f.npix, differ, off);
	assert_true(filled > f.npix * 8 / 10);
	assert_true(differ * 10000 < filled); /* under 0.01 % */
	assert_true(off * 10000 < filled);
	planes_free(&p);
	fixture_free(&f);
}

/* the identity motion: the history as it was, bit for bit, where the depth agrees */
static void test_identity_bit_identical(void **state)
{
	(void)state;
	struct scene_fixture f;
	fixture_init(&f);
	struct planes p;
	planes_init(&p, f.npix);
	struct dao_pose id;
	dao_pose_identity(&id);
	render(&f, &id, 1, 1.0, 5u, f.z0);
	render(&f, &id, 1, 1.0, 6u, f.z1); /* new noise: the depths differ by millimetres */
	make_history(&f, &p);
	run_rows(&f, &id, f.z1, &p);
	size_t same = 0;
	for (size_t i = 0; i < f.npix; i++) {
		if (!(f.z1[i] > 0.0f) || !(f.z0[i] > 0.0f) ||
		    !(fabsf(f.z0[i] - f.z1[i]) <= REJECT * f.z1[i]))
			continue;
		assert_memory_equal(&p.ao_out[i], &p.ao[i], sizeof(float));
		assert_memory_equal(&p.z_out[i], &p.hz[i], sizeof(float));
		same++;
	}
	assert_true(same > f.npix * 9 / 10);
	planes_free(&p);
	fixture_free(&f);
}

/*
 * A step sideways past the box: the wall the box hid before is seen now.
 * The history's AO is a function of its depth (z / 10), so a value taken
 * from the wrong surface shows.  Every current pixel whose surface the
 * previous camera did not see (its point lands on a surface nearer by more
 * than 10 %, all four taps) has no history; every pixel with history took it
 * from its own surface.
 */
static void test_disocclusion(void **state)
{
	(void)state;
	struct scene_fixture f;
	fixture_init(&f);
	struct planes p;
	planes_init(&p, f.npix);
	struct two_views tv;
	two_views_make(&tv, (const double[5]){0.0, 0.0, -0.10, 0.0, 0.0},
		       (const double[5]){0.0, 0.0, 0.10, 0.0, 0.0});
	two_views_render(&f, &tv, 0.0, 0u, 0u);
	for (size_t i = 0; i < f.npix; i++) {
		p.hz[i] = f.z0[i];
		p.ao[i] = f.z0[i] / 10.0f;
	}
	run_rows(&f, &tv.motion, f.z1, &p);
	size_t hidden = 0, with = 0;
	for (size_t i = 0; i < f.npix; i++) {
		double a[3], w[3], q[3], u, v;
		dao_camera_pixel_to_view(&f.cam, (double)(i % W), (double)(i / W), f.z1[i], a);
		pose_apply(&tv.cur, a, w);
		pose_apply_inverse(&tv.prev, w, q);
		if (dao_camera_view_to_pixel(&f.cam, q, &u, &v) || u < 1.0 || v < 1.0 ||
		    u > W - 2.0 || v > H - 2.0)
			continue;
		int nearer = 0;
		for (int k = 0; k < 4; k++) {
			const float hz = f.z0[(size_t)((int)v + (k >> 1)) * W + (size_t)((int)u + (k & 1))];
			nearer += hz < 0.9 * q[2];
		}
		if (nearer == 4) {
			hidden++;
			assert_true(p.z_out[i] == 0.0f);
		}
		if (p.z_out[i] > 0.0f) {
			with++;
			assert_true(fabs(10.0 * p.ao_out[i] - q[2]) <= REJECT * q[2] + 1e-4);
		}
	}
	printf("disocclusion: %zu pixels uncovered (no history), %zu with history\n", hidden, with);
	assert_true(hidden > 1000);
	assert_true(with > f.npix * 8 / 10);
	planes_free(&p);
	fixture_free(&f);
}

/* a pan of 4 degrees: the columns the previous image did not cover have no
 * history, the others have it */
static void test_out_of_frame(void **state)
{
	(void)state;
	struct scene_fixture f;
	fixture_init(&f);
	struct planes p;
	planes_init(&p, f.npix);
	struct two_views tv;
	two_views_make(&tv, (const double[5]){0.0, 0.0, 0.0, 0.0, 0.0},
		       (const double[5]){4.0, 0.0, 0.0, 0.0, 0.0});
	two_views_render(&f, &tv, 0.0, 0u, 0u);
	make_history(&f, &p);
	run_rows(&f, &tv.motion, f.z1, &p);
	size_t outside = 0, inside = 0, inside_with = 0;
	for (size_t i = 0; i < f.npix; i++) {
		double a[3], q[3], u, v;
		dao_camera_pixel_to_view(&f.cam, (double)(i % W), (double)(i / W), f.z1[i], a);
		pose_apply(&tv.motion, a, q);
		if (dao_camera_view_to_pixel(&f.cam, q, &u, &v))
			continue;
		if (u < -0.501 || u > W - 0.499) {
			outside++;
			assert_true(p.z_out[i] == 0.0f && p.ao_out[i] == 0.0f);
		} else if (u > 0.0 && u < W - 1.0) {
			inside++;
			inside_with += p.z_out[i] > 0.0f;
		}
	}
	printf("out of frame: %zu pixels outside the previous image, %zu of %zu inside with "
	       "history\n", outside, inside_with, inside);
	/* 4 degrees at f = 525 px: 48 columns at the image's edge, 31.3 degrees off the axis
	 * (525 tan(35.3 degrees) - 319.5); a pixel whose four taps straddle a depth edge has
	 * none either */
	assert_true(outside >= 47 * H && outside <= 49 * H);
	assert_true(inside_with > inside * 98 / 100);
	planes_free(&p);
	fixture_free(&f);
}

/* random and hostile poses: every output is no history or a history value */
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
	make_history(&f, &p);
	uint64_t st = 777u;
	for (int k = 0; k < 30; k++) {
		struct dao_pose m;
		fuzzed_motion(&st, k, 30, &m);
		run_rows(&f, &m, f.z0, &p);
		for (size_t i = 0; i < f.npix; i++) {
			if (p.z_out[i] == 0.0f) {
				assert_true(p.ao_out[i] == 0.0f);
				continue;
			}
			assert_true(isfinite(p.z_out[i]) && p.z_out[i] > 0.0f);
			assert_true(p.ao_out[i] >= 0.1f - 1e-6f && p.ao_out[i] <= 0.9f + 1e-6f);
		}
	}
	planes_free(&p);
	fixture_free(&f);
}

static struct dao_context *make(const struct dao_camera *cam, int motion, float temporal)
{
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_LOW);
	dao_params_stream_defaults(&p);
	p.temporal = temporal;
	return motion_context(cam, &p, motion);
}

/* the same frame again and again with the AO history on: the motion is the
 * identity (still), so the AO is that without motion, bit for bit */
static void test_pipeline_still(void **state)
{
	(void)state;
	struct scene_fixture f;
	fixture_init(&f);
	struct dao_context *off = make(&f.cam, DAO_DEPTH_MOTION_OFF, 0.8f);
	struct dao_context *icp = make(&f.cam, DAO_DEPTH_MOTION_ICP, 0.8f);
	float *a0 = malloc(f.npix * 4), *a1 = malloc(f.npix * 4);
	assert_true(a0 && a1);
	struct dao_pose id;
	dao_pose_identity(&id);
	render(&f, &id, 1, 1.0, 11u, f.z0);
	for (unsigned k = 0; k < 4; k++) {
		memcpy(f.z1, f.z0, f.npix * 4);
		run_frame(off, f.z0, k, a0, NULL);
		run_frame(icp, f.z1, k, a1, NULL);
		assert_memory_equal(a0, a1, f.npix * 4);
	}
	struct dao_motion_info mi = DAO_MOTION_INFO_INIT;
	dao_context_motion(icp, &mi);
	assert_int_equal(mi.state, DAO_MOTION_STILL);
	dao_context_destroy(off);
	dao_context_destroy(icp);
	free(a0), free(a1);
	fixture_free(&f);
}

/* mean |a - b| over the pixels with depth */
static double ao_mae(const float *a, const float *b, const float *z)
{
	double s = 0.0;
	size_t n = 0;
	for (size_t i = 0; i < (size_t)W * H; i++)
		if (z[i] > 0.0f)
			s += fabs(a[i] - b[i]), n++;
	return n ? s / n : 0.0;
}

/* a pan of 1 degree a frame on clean depth: the frame's own AO (the same
 * depth, no AO history) is the reference; the history left in place smears,
 * carried it does not */
static void test_pipeline_pan(void **state)
{
	(void)state;
	struct scene_fixture f;
	fixture_init(&f);
	struct dao_context *ref = make(&f.cam, DAO_DEPTH_MOTION_ICP, 0.0f);
	struct dao_context *off = make(&f.cam, DAO_DEPTH_MOTION_OFF, 0.8f);
	struct dao_context *icp = make(&f.cam, DAO_DEPTH_MOTION_ICP, 0.8f);
	float *ar = malloc(f.npix * 4), *a0 = malloc(f.npix * 4), *a1 = malloc(f.npix * 4);
	float *z = malloc(f.npix * 4);
	assert_true(ar && a0 && a1 && z);
	double e_off = 0.0, e_icp = 0.0;
	for (unsigned k = 0; k < 6; k++) {
		struct dao_pose c;
		pose_from(&c, 1.0 * k, 0.0, 0.0, 0.0, 0.0);
		render(&f, &c, 1, 0.0, 0u, f.z0);
		memcpy(z, f.z0, f.npix * 4), run_frame(ref, z, k, ar, NULL);
		memcpy(z, f.z0, f.npix * 4), run_frame(off, z, k, a0, NULL);
		memcpy(z, f.z0, f.npix * 4), run_frame(icp, z, k, a1, NULL);
		struct dao_motion_info mi = DAO_MOTION_INFO_INIT;
		dao_context_motion(icp, &mi);
		if (k >= 1)
			assert_int_equal(mi.state, DAO_MOTION_APPLIED);
		if (k >= 2) {
			e_off += ao_mae(a0, ar, f.z0);
			e_icp += ao_mae(a1, ar, f.z0);
		}
	}
	printf("pan 1 deg/frame, AO against the frame's own: history in place %.5f, carried "
	       "%.5f\n", e_off / 4, e_icp / 4);
	assert_true(e_icp < 0.5 * e_off);
	dao_context_destroy(ref);
	dao_context_destroy(off);
	dao_context_destroy(icp);
	free(ar), free(a0), free(a1), free(z);
	fixture_free(&f);
}

/* a kernel set's output against the reference kernel's on a pan with a step:
 * whether a pixel has history may differ where a tap sits at the depth test's
 * edge or the landing point at the snap's or the image's border; elsewhere
 * the AO within 1e-5 and the depth within 1e-5 of it */
static void compare_to_reference(const char *isa)
{
	struct scene_fixture f;
	fixture_init(&f);
	struct planes p, q;
	planes_init(&p, f.npix);
	planes_init(&q, f.npix);
	struct dao_pose prev_c, cur_c, motion;
	pose_from(&prev_c, 0.3, 0.2, 0.0, 0.0, 0.0);
	pose_from(&cur_c, 1.3, -0.4, 0.01, 0.004, -0.01);
	relative(&prev_c, &cur_c, &motion);
	render(&f, &prev_c, 1, 1.0, 3u, f.z0);
	render(&f, &cur_c, 1, 1.0, 4u, f.z1);
	make_history(&f, &p);
	make_history(&f, &q);
	const dao_ao_reproject_fn k = kernel;
	kernel = dao_ao_history_reproject_rows;
	run_rows(&f, &motion, f.z1, &p);
	kernel = k;
	run_rows(&f, &motion, f.z1, &q);
	size_t filled = 0, differ = 0, off = 0;
	double worst_ao = 0.0, worst_z = 0.0;
	for (size_t i = 0; i < f.npix; i++) {
		const int have = q.z_out[i] > 0.0f, ref_have = p.z_out[i] > 0.0f;
		filled += (size_t)ref_have;
		if (have != ref_have) {
			differ++;
			continue;
		}
		if (!have)
			continue;
		const double dao = fabs(q.ao_out[i] - p.ao_out[i]);
		const double dz = fabs(q.z_out[i] - p.z_out[i]) / p.z_out[i];
		worst_ao = dao > worst_ao ? dao : worst_ao;
		worst_z = dz > worst_z ? dz : worst_z;
		off += dao > 1e-5 || dz > 1e-5;
	}
	printf("%s: %zu pixels with history, %zu differ in having it, %zu values off "
	       "(largest: AO %.3g, depth %.3g relative)\n", isa, filled, differ, off, worst_ao,
	       worst_z);
	assert_true(filled > f.npix * 8 / 10);
	assert_true(differ * 10000 < filled); /* under 0.01 % */
	assert_true(off * 10000 < filled);
	planes_free(&p);
	planes_free(&q);
	fixture_free(&f);
}

/* every kernel set: against the reference kernel, and every test above */
static void test_kernel_sets(void **state)
{
	int tested = 0;
	for (int s = DAO_SIMD_GENERIC; s < DAO_SIMD_COUNT; s++) {
		if (!dao_simd_supported((enum dao_simd)s))
			continue;
		struct dao_kernels k;
		dao_kernels_select(&k, (enum dao_simd)s);
		kernel = k.ao_reproject;
		char name[16];
		snprintf(name, sizeof name, "simd %d", s);
		compare_to_reference(name);
		test_against_reference(state);
		test_identity_bit_identical(state);
		test_disocclusion(state);
		test_out_of_frame(state);
		test_fuzzed_poses(state);
		tested++;
	}
	kernel = dao_ao_history_reproject_rows;
	printf("%d kernel sets\n", tested);
	assert_true(tested >= 1);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_against_reference),
		cmocka_unit_test(test_identity_bit_identical),
		cmocka_unit_test(test_disocclusion),
		cmocka_unit_test(test_out_of_frame),
		cmocka_unit_test(test_fuzzed_poses),
		cmocka_unit_test(test_kernel_sets),
		cmocka_unit_test(test_pipeline_still),
		cmocka_unit_test(test_pipeline_pan),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
