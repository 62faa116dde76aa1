/* SPDX-License-Identifier: MIT */
/*
 * The scalar GTAO kernel against geometry with known answers.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "kernels/gtao.h"
#include "kernels/gtao_sample.h"
#include "common/floor_wall.h"
#include "synth/synth.h"


/* Depth of plane n.X = c through pixel (u, v): z = c / n.(u ax + bx, v ay + by, 1). */
static float plane_z(const struct dao_camera *cam, const double n[3], double c, double u, double v)
{
	double den = n[0] * (u * cam->ax + cam->bx) + n[1] * (v * cam->ay + cam->by) + n[2];
	return (float)(c / den);
}

static void render_plane(const struct dao_camera *cam, const double n[3], double c, float *z,
			 float *nrm)
{
	for (uint32_t y = 0; y < cam->height; y++)
		for (uint32_t x = 0; x < cam->width; x++) {
			size_t i = (size_t)y * cam->width + x;
			z[i] = plane_z(cam, n, c, x, y);
			for (int k = 0; k < 3; k++)
				nrm[3 * i + k] = (float)n[k];
		}
}

/* Tilted planes facing the camera, as (normal, offset): n.X = c with c < 0. */
static const double planes[][4] = {
	{ 0, 0, -1, -2 },
	{ 0.3, -0.5, -0.81, -1.6 },
	{ -0.6, 0.2, -0.77, -2.2 },
	{ 0.1, -0.85, -0.52, -1.0 },
};

static void normalize(double n[3])
{
	double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
	for (int k = 0; k < 3; k++)
		n[k] /= l;
}

/* Samples on the exact slice line of a plane lie on that plane. */
static void test_sample_on_plane(void **state)
{
	(void)state;
	struct dao_camera cam;
	dao_camera_from_intrinsics(&cam, 160, 120, 130, 130, 79.5, 59.5, NULL);
	float *z = malloc(160 * 120 * sizeof(float)), *nrm = malloc(3 * 160 * 120 * sizeof(float));
	for (size_t p = 0; p < sizeof planes / sizeof planes[0]; p++) {
		double n[3] = { planes[p][0], planes[p][1], planes[p][2] };
		normalize(n);
		render_plane(&cam, n, planes[p][3], z, nrm);
		/* every sample is inside the image, where the plane has depth: all
		 * must be taken (a sampler that refused them would pass unchecked) */
		int tried = 0, taken = 0;
		for (int k = 0; k < 64; k++) {
			float phi = (float)k * 0.0981f, dx = cosf(phi), dy = sinf(phi);
			for (float t = 1.0f; t < 50.0f; t += 3.7f) {
				float u, v, zs;
				tried++;
				if (!dao_gtao_sample(z, 160, 120, 80, 60, dx, dy, t, &u, &v, &zs))
					continue;
				taken++;
				/* on the line through (80, 60) */
				assert_true(fabsf((u - 80.0f) * dy - (v - 60.0f) * dx) < 1e-3f);
				double X[3];
				dao_camera_pixel_to_view(&cam, u, v, zs, X);
				double d = n[0] * X[0] + n[1] * X[1] + n[2] * X[2] - planes[p][3];
				assert_true(fabs(d) < 2e-6 * fabs(planes[p][3]) + 1e-6);
			}
		}
		assert_int_equal(tried, 64 * 14);
		if (taken != tried)
			fail_msg("plane %zu: %d of %d samples taken", p, taken, tried);
	}
	free(z);
	free(nrm);
}

static void run_ref(const struct dao_camera *cam, struct dao_params *p, const float *z,
		    const float *nrm, float *ao, uint64_t frame)
{
	struct dao_gtao_setup s;
	dao_gtao_setup_init(&s, cam, p, frame);
	dao_gtao_ref(&s, z, nrm, ao, 0, (int)cam->height);
}

/* An open plane is fully visible, at any tilt and slice count. */
static void test_open_plane(void **state)
{
	(void)state;
	struct dao_camera cam;
	dao_camera_from_intrinsics(&cam, 96, 72, 100, 100, 47.5, 35.5, NULL);
	const size_t np = 96 * 72;
	float *z = malloc(np * sizeof(float)), *nrm = malloc(3 * np * sizeof(float));
	float *ao = malloc(np * sizeof(float));
	static const int slices[] = { 1, 2, 3, 7 };
	for (size_t p = 0; p < sizeof planes / sizeof planes[0]; p++) {
		double n[3] = { planes[p][0], planes[p][1], planes[p][2] };
		normalize(n);
		render_plane(&cam, n, planes[p][3], z, nrm);
		for (size_t k = 0; k < sizeof slices / sizeof slices[0]; k++) {
			struct dao_params prm;
			dao_params_init(&prm, DAO_QUALITY_DEFAULT);
			prm.slices = slices[k];
			run_ref(&cam, &prm, z, nrm, ao, 3);
			float lo = 1.0f;
			size_t at = 0;
			for (size_t i = 0; i < np; i++)
				if (ao[i] < lo)
					lo = ao[i], at = i;
			if (lo <= 0.999f)
				print_message("plane %zu slices %d: %.5f at (%zu, %zu)\n", p, slices[k], lo,
					      at % 96, at / 96);
			assert_true(lo > 0.999f);
		}
	}
	free(z);
	free(nrm);
	free(ao);
}

/* The converged GTAO integral against the closed form of the floor-and-wall scene. */
static void test_floor_and_wall(void **state)
{
	(void)state;
	struct synth_scene s;
	floor_wall_scene(&s);
	struct dao_camera cam;
	dao_camera_from_intrinsics(&cam, 128, 96, 100, 100, 63.5, 47.5, NULL);
	struct synth_image img;
	assert_int_equal(synth_render(&s, &cam, 0.5, 0, 1, &img, NULL), 0);
	float *ao = malloc(128 * 96 * sizeof(float));
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.slices = 24;
	p.steps = 48;
	p.radius = 0.5f * 0.5f / dao_gtao_effective_radius(0.5f, 48); /* effective 0.5 m */
	p.falloff = 0.0f;
	p.thickness = 0.0f;
	p.distribution_power = 1.0f;
	p.max_screen_radius = 1000.0f;
	run_ref(&cam, &p, img.depth, img.normal, ao, 0);
	double sum = 0;
	int n = 0;
	for (int y = 40; y < 56; y++)
		for (int x = 0; x < 128; x++) {
			double X = (x - 63.5) / 100.0 * 2.0;
			if (X > 0.28)
				break;
			sum += fabs(ao[y * 128 + x] - floor_wall_visibility(X, 0.5));
			n++;
		}
	double mae = sum / n;
	print_message("floor-wall: GTAO vs closed form MAE %.4f over %d px\n", mae, n);
	/* the slice-wise horizon slightly over-occludes oblique slices (everything below
	 * the horizon counts as blocked, even where the wall is farther than R) */
	assert_true(mae < 0.02);
	free(ao);
	synth_image_free(&img);
}

static void test_invalid_and_noise(void **state)
{
	(void)state;
	struct dao_camera cam;
	dao_camera_from_intrinsics(&cam, 64, 48, 60, 60, 31.5, 23.5, NULL);
	const size_t np = 64 * 48;
	float *z = calloc(np, sizeof(float)), *nrm = calloc(3 * np, sizeof(float));
	float *a0 = malloc(np * sizeof(float)), *a1 = malloc(np * sizeof(float));
	/* a box-like bump on a plane gives occlusion that depends on the noise */
	for (int y = 0; y < 48; y++)
		for (int x = 0; x < 64; x++) {
			size_t i = (size_t)y * 64 + x;
			z[i] = (x > 28 && x < 36 && y > 20 && y < 28) ? 1.7f : 2.0f;
			nrm[3 * i + 2] = -1.0f;
		}
	z[5] = 0.0f; /* a hole */
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.invalid_value = 0.25f;
	run_ref(&cam, &p, z, nrm, a0, 0);
	run_ref(&cam, &p, z, nrm, a1, 0);
	assert_memory_equal(a0, a1, np * sizeof(float));
	assert_true(a0[5] == 0.25f);
	run_ref(&cam, &p, z, nrm, a1, 1);
	int differ = 0;
	for (size_t i = 0; i < np; i++)
		differ += a0[i] != a1[i];
	assert_true(differ > 0);
	free(z);
	free(nrm);
	free(a0);
	free(a1);
}

/* The block radius grid: 2^(k/8) times a power of two, at or above r. */
static void test_quantize_radius(void **state)
{
	(void)state;
	/* powers of two and grid points are kept */
	assert_true(dao_gtao_quantize_radius(1.0f) == 1.0f);
	assert_true(dao_gtao_quantize_radius(64.0f) == 64.0f);
	assert_true(dao_gtao_quantize_radius(2.0f * 1.414213562f) == 2.0f * 1.414213562f);
	/* just above a grid point: the next one */
	assert_true(dao_gtao_quantize_radius(1.0001f) == 1.090507733f);
	assert_true(dao_gtao_quantize_radius(1.95f * 32.0f) == 64.0f);
	/* 0 and non-finite values are left alone */
	assert_true(dao_gtao_quantize_radius(0.0f) == 0.0f);
	assert_true(isinf(dao_gtao_quantize_radius(INFINITY)));
	float prev = 0.0f;
	for (float r = 0.5f; r < 4096.0f; r *= 1.0137f) {
		const float q = dao_gtao_quantize_radius(r);
		assert_true(q >= r);
		assert_true(q <= r * 1.0906f); /* one grid step: 2^(1/8) */
		assert_true(q >= prev);        /* monotonic */
		/* on the grid: q / 2^floor(log2 q) is 2^(k/8) */
		const double k = 8.0 * (log2((double)q) - floor(log2((double)q)));
		assert_true(fabs(k - round(k)) < 1e-4);
		prev = q;
	}
}

static void test_finish(void **state)
{
	(void)state;
	struct dao_params p;
	struct dao_camera cam;
	dao_camera_from_intrinsics(&cam, 8, 8, 10, 10, 3.5, 3.5, NULL);
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	struct dao_gtao_setup s;
	dao_gtao_setup_init(&s, &cam, &p, 0);
	assert_true(fabsf(dao_gtao_finish(&s, 0.6f) - 0.6f) < 1e-7f);
	p.final_power = 2.0f;
	dao_gtao_setup_init(&s, &cam, &p, 0);
	assert_true(fabsf(dao_gtao_finish(&s, 0.6f) - 0.36f) < 1e-6f);
	/* multi-bounce brightens, more for brighter albedo, never beyond 1 */
	p.final_power = 1.0f;
	p.albedo = 0.3f;
	dao_gtao_setup_init(&s, &cam, &p, 0);
	float lo = dao_gtao_finish(&s, 0.5f);
	p.albedo = 0.9f;
	dao_gtao_setup_init(&s, &cam, &p, 0);
	float hi = dao_gtao_finish(&s, 0.5f);
	assert_true(lo > 0.5f && hi > lo && hi <= 1.0f);
	assert_true(dao_gtao_finish(&s, 1.0f) == 1.0f);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_sample_on_plane),
		cmocka_unit_test(test_open_plane),
		cmocka_unit_test(test_floor_and_wall),
		cmocka_unit_test(test_invalid_and_noise),
		cmocka_unit_test(test_quantize_radius),
		cmocka_unit_test(test_finish),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
