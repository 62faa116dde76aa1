/* SPDX-License-Identifier: MIT */
/*
 * The ground truth itself must be right: ray intersections against analytic
 * answers, and the AO estimator against closed forms.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>

#include <cmocka.h>

#include "common/floor_wall.h"
#include "synth/synth.h"

static void test_sphere_hit(void **state)
{
	(void)state;
	struct synth_prim p = { .kind = SYNTH_SPHERE, .c = { 0, 0, 5 }, .r = 1 };
	synth_prim_bound(&p);
	double t;
	vec3 n;
	assert_true(synth_prim_intersect(&p, v3(0, 0, 0), v3(0, 0, 1), 0, 100, &t, &n));
	assert_true(fabs(t - 4.0) < 1e-12);
	assert_true(fabs(n.z + 1.0) < 1e-12);
	/* from inside, the far side */
	assert_true(synth_prim_intersect(&p, v3(0, 0, 5), v3(1, 0, 0), 0, 100, &t, &n));
	assert_true(fabs(t - 1.0) < 1e-12);
	/* tmax limits the hit */
	assert_false(synth_prim_intersect(&p, v3(0, 0, 0), v3(0, 0, 1), 0, 3.9, &t, &n));
	/* miss */
	assert_false(synth_prim_intersect(&p, v3(0, 2, 0), v3(0, 0, 1), 0, 100, &t, &n));
}

static void test_box_hit(void **state)
{
	(void)state;
	struct synth_prim p = { .kind = SYNTH_BOX, .c = { 0, 0, 3 }, .half = { 1, 2, 0.5 } };
	p.axis[0] = v3(1, 0, 0), p.axis[1] = v3(0, 1, 0), p.axis[2] = v3(0, 0, 1);
	synth_prim_bound(&p);
	double t;
	vec3 n;
	assert_true(synth_prim_intersect(&p, v3(0, 0, 0), v3(0, 0, 1), 0, 100, &t, &n));
	assert_true(fabs(t - 2.5) < 1e-12);
	assert_true(fabs(n.z + 1.0) < 1e-12);
	assert_true(synth_prim_intersect(&p, v3(5, 0, 3), v3(-1, 0, 0), 0, 100, &t, &n));
	assert_true(fabs(t - 4.0) < 1e-12 && fabs(n.x - 1.0) < 1e-12);
	assert_false(synth_prim_intersect(&p, v3(5, 0, 3), v3(1, 0, 0), 0, 100, &t, &n));
}

static void test_cylinder_hit(void **state)
{
	(void)state;
	struct synth_prim p = { .kind = SYNTH_CYLINDER, .c = { 0, 0, 4 }, .n = { 0, 1, 0 },
				.r = 0.5, .h = 1 };
	synth_prim_bound(&p);
	double t;
	vec3 n;
	assert_true(synth_prim_intersect(&p, v3(0, 0, 0), v3(0, 0, 1), 0, 100, &t, &n));
	assert_true(fabs(t - 3.5) < 1e-12 && fabs(n.z + 1.0) < 1e-12);
	/* cap from above */
	assert_true(synth_prim_intersect(&p, v3(0, -5, 4), v3(0, 1, 0), 0, 100, &t, &n));
	assert_true(fabs(t - 4.0) < 1e-12 && fabs(n.y + 1.0) < 1e-12);
	/* beyond the length */
	assert_false(synth_prim_intersect(&p, v3(0, 1.5, 0), v3(0, 0, 1), 0, 100, &t, &n));
}

static void test_ground_truth_corner(void **state)
{
	(void)state;
	/* the ground truth must match the closed form of the floor-and-wall scene */
	struct synth_scene s;
	floor_wall_scene(&s);
	struct dao_camera cam;
	assert_int_equal(dao_camera_from_intrinsics(&cam, 64, 8, 100, 100, 31.5, 3.5, NULL), 0);
	struct synth_image img;
	assert_int_equal(synth_render(&s, &cam, 0.5, 32, 2, &img, NULL), 0);
	int checked = 0;
	for (int x = 0; x < 64; x++) {
		double X = (x - 31.5) / 100.0 * 2.0; /* floor point x at z = 2 */
		if (X >= 0.29)
			break; /* pixels on the wall */
		double expect = floor_wall_visibility(X, 0.5);
		float got = img.gt[3 * 64 + x];
		/* 1024 stratified rays: error well below 0.01 */
		assert_true(fabs(got - expect) < 0.01);
		checked++;
	}
	assert_true(checked > 20);
	synth_image_free(&img);
}

/* The length of a camera ray inside what it hits: a board crossed at 60 degrees, the
 * board and the side panel it touches as one solid, a sphere's chord, a wall. */
static void test_ray_inside(void **state)
{
	(void)state;
	struct synth_scene s = { .name = "inside" };
	/* a board 2 cm thick (z in [2.99, 3.01]) ... */
	struct synth_prim *b = &s.prims[s.count++];
	*b = (struct synth_prim){ .kind = SYNTH_BOX, .c = { 0, 0, 3 }, .half = { 0.4, 0.3, 0.01 } };
	b->axis[0] = v3(1, 0, 0), b->axis[1] = v3(0, 1, 0), b->axis[2] = v3(0, 0, 1);
	/* ... touching a panel 5 cm thick at x = 0.4 (x in [0.4, 0.45]) */
	struct synth_prim *p = &s.prims[s.count++];
	*p = (struct synth_prim){ .kind = SYNTH_BOX, .c = { 0.425, 0, 3 }, .half = { 0.025, 0.3, 0.5 } };
	p->axis[0] = v3(1, 0, 0), p->axis[1] = v3(0, 1, 0), p->axis[2] = v3(0, 0, 1);
	s.prims[s.count++] = (struct synth_prim){ .kind = SYNTH_SPHERE, .c = { -2, 0, 3 }, .r = 0.5 };
	s.prims[s.count++] = (struct synth_prim){ .kind = SYNTH_HALFSPACE, .c = { 0, 0, 6 },
						  .n = { 0, 0, -1 } };
	for (int i = 0; i < s.count; i++)
		synth_prim_bound(&s.prims[i]);
	double t;
	/* straight through the board: 2 cm; at 60 degrees from its normal: 4 cm */
	vec3 d = v3(0, 0, 1);
	assert_int_equal(synth_trace(&s, v3(0, 0, 0), d, 0, 100, &t, NULL), 0);
	assert_true(fabs(synth_ray_inside(&s, v3(0, 0, 0), d, t, 0) - 0.02) < 1e-9);
	const vec3 o = v3(-1.7, 0, 2);
	d = v3(sqrt(3.0) / 2, 0, 0.5); /* 60 degrees from the board's normal */
	assert_int_equal(synth_trace(&s, o, d, 0, 100, &t, NULL), 0);
	assert_true(fabs(synth_ray_inside(&s, o, d, t, 0) - 0.04) < 1e-9);
	/* along the board into the panel it touches, out of the panel's far face:
	 * from x = 0.3 to 0.45 */
	const vec3 o2 = v3(-1, 0, 3.0);
	assert_int_equal(synth_trace(&s, o2, v3(1, 0, 0), 0, 100, &t, NULL), 0);
	assert_true(fabs(t - 0.6) < 1e-9);
	assert_true(fabs(synth_ray_inside(&s, o2, v3(1, 0, 0), t, 0) - 0.85) < 1e-6);
	/* the sphere 0.3 m off its centre: a chord of 2 sqrt(0.5^2 - 0.3^2) = 0.8 m */
	const vec3 o3 = v3(-2.3, 0, 0);
	assert_int_equal(synth_trace(&s, o3, v3(0, 0, 1), 0, 100, &t, NULL), 2);
	assert_true(fabs(synth_ray_inside(&s, o3, v3(0, 0, 1), t, 2) - 0.8) < 1e-9);
	/* a direction that is not unit: the same length in metres */
	assert_int_equal(synth_trace(&s, o, v3_scale(d, 3.0), 0, 100, &t, NULL), 0);
	assert_true(fabs(synth_ray_inside(&s, o, v3_scale(d, 3.0), t, 0) - 0.04) < 1e-9);
	/* a wall: a half-space the ray never leaves */
	const vec3 o4 = v3(2, 0, 0);
	assert_int_equal(synth_trace(&s, o4, v3(0, 0, 1), 0, 100, &t, NULL), 3);
	assert_true(isinf(synth_ray_inside(&s, o4, v3(0, 0, 1), t, 3)));
	/* a primitive's solid, its surface included */
	assert_true(synth_prim_inside(b, v3(0.4, 0.3, 3.01)));
	assert_false(synth_prim_inside(b, v3(0.4, 0.3, 3.02)));
	assert_true(synth_prim_inside(&s.prims[3], v3(0, 0, 7)));
	assert_false(synth_prim_inside(&s.prims[3], v3(0, 0, 5)));
}

static void test_noise_model(void **state)
{
	(void)state;
	enum { W = 200, H = 100 };
	float *d = malloc(W * H * sizeof(float));
	for (int i = 0; i < W * H; i++)
		d[i] = 2.0f;
	synth_sensor_noise(d, W, H, 0.0012, 0.0, 0.02, 7);
	double sum = 0, sum2 = 0;
	int n = 0, dropped = 0;
	for (int i = 0; i < W * H; i++) {
		if (d[i] == 0.0f) {
			dropped++;
			continue;
		}
		sum += d[i] - 2.0;
		sum2 += (d[i] - 2.0) * (d[i] - 2.0);
		n++;
	}
	double sd = sqrt(sum2 / n - (sum / n) * (sum / n));
	/* sigma = 0.0012 * 2^2 = 4.8 mm */
	assert_true(fabs(sd - 0.0048) < 0.0003);
	assert_true(fabs(sum / n) < 0.0003);
	assert_true(dropped >= 0.02 * W * H && dropped < 0.025 * W * H);
	free(d);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_sphere_hit),
		cmocka_unit_test(test_box_hit),
		cmocka_unit_test(test_cylinder_hit),
		cmocka_unit_test(test_ground_truth_corner),
		cmocka_unit_test(test_ray_inside),
		cmocka_unit_test(test_noise_model),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
