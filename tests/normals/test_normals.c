/* SPDX-License-Identifier: MIT */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/cmocka_all.h"
#include "common/test_common.h"
#include "normals/normals.h"

enum { W = 96, H = 72 };
#define DEG (180.0 / 3.14159265358979323846)

static struct dao_camera camera(void)
{
	struct dao_camera cam;
	dao_camera_from_intrinsics(&cam, W, H, 90, 90, 47.5, 35.5, NULL);
	return cam;
}

static void render_plane(const struct dao_camera *cam, const double n[3], double c, float *z)
{
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			double r[3] = { (x - cam->cx) / cam->fx, (y - cam->cy) / cam->fy, 1 };
			z[y * W + x] = (float)(c / (n[0] * r[0] + n[1] * r[1] + n[2] * r[2]));
		}
}

static double angle_deg(const float *a, const double *b)
{
	double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
	return acos(fmin(1.0, fmax(-1.0, d))) * DEG;
}

static void test_planes(void **state)
{
	(void)state;
	static const double planes[][4] = {
		{ 0, 0, -1, -2 }, { 0.5, 0, -0.866, -1.8 }, { 0, -0.7, -0.714, -1.2 },
		{ -0.3, 0.4, -0.866, -2.5 }, { 0.6, 0.6, -0.529, -1.0 },
	};
	struct dao_camera cam = camera();
	float *z = malloc(W * H * sizeof(float)), *n = malloc(3 * W * H * sizeof(float));
	for (size_t p = 0; p < sizeof planes / sizeof planes[0]; p++) {
		double nn[3] = { planes[p][0], planes[p][1], planes[p][2] };
		double l = sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
		for (int k = 0; k < 3; k++)
			nn[k] /= l;
		render_plane(&cam, nn, planes[p][3] / l, z);
		for (int r = 1; r <= 4; r += 3) {
			dao_normals_from_depth(&cam, z, r, n, 0, H);
			double worst = 0;
			int valid = 0;
			for (int i = 0; i < W * H; i++) {
				if (!(z[i] > 0.0f))
					continue; /* the plane is behind the camera there */
				valid++;
				worst = fmax(worst, angle_deg(n + 3 * i, nn));
				/* facing the camera */
				double P[3];
				dao_camera_pixel_to_view(&cam, i % W, i / W, z[i], P);
				assert_true(n[3 * i] * P[0] + n[3 * i + 1] * P[1] + n[3 * i + 2] * P[2] < 0);
			}
			print_message("plane %zu radius %d: worst %.4f deg over %d px\n", p, r, worst, valid);
			assert_true(valid > W * H / 2);
			assert_true(worst < 0.5);
		}
	}
	free(z);
	free(n);
}

static void test_holes_and_edges(void **state)
{
	(void)state;
	struct dao_camera cam = camera();
	float *z = malloc(W * H * sizeof(float)), *n = malloc(3 * W * H * sizeof(float));
	/* left half: a plane tilted about y; right half: a fronto-parallel plane 0.5 m behind */
	const double tilted[3] = { 0.5, 0, -0.866 };
	render_plane(&cam, tilted, -1.5 * 0.866, z);
	for (int y = 0; y < H; y++)
		for (int x = 48; x < W; x++)
			z[y * W + x] = 2.5f;
	z[20 * W + 20] = 0.0f; /* a hole */
	dao_normals_from_depth(&cam, z, 2, n, 0, H);
	const float *hole = n + 3 * (20 * W + 20);
	assert_true(hole[0] == 0.0f && hole[1] == 0.0f && hole[2] == -1.0f);
	/* beside the hole the other side is used: still the plane's normal */
	assert_true(angle_deg(n + 3 * (20 * W + 21), tilted) < 0.5);
	assert_true(angle_deg(n + 3 * (20 * W + 19), tilted) < 0.5);
	/* at the depth step each side keeps its own normal (smaller |dz| rule) */
	const double front[3] = { 0, 0, -1 };
	for (int y = 5; y < H - 5; y++) {
		assert_true(angle_deg(n + 3 * (y * W + 47), tilted) < 1.0);
		assert_true(angle_deg(n + 3 * (y * W + 48), front) < 1.0);
	}
	free(z);
	free(n);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_planes),
		cmocka_unit_test(test_holes_and_edges),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
