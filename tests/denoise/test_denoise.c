/* SPDX-License-Identifier: MIT */
#include <math.h>
#include <stdlib.h>

#include "common/cmocka_all.h"
#include "common/test_common.h"
#include "denoise/denoise.h"

enum { W = 64, H = 48 };

struct scene {
	struct dao_denoise_setup s;
	float z[W * H], n[3 * W * H], ao[W * H], out[W * H], tmp[W * H];
};

/* Fronto-parallel: left half at 1.5 m, right half at 2.5 m. */
static struct scene *make_scene(void)
{
	struct scene *sc = calloc(1, sizeof *sc);
	struct dao_camera cam;
	dao_camera_from_intrinsics(&cam, W, H, 60, 60, 31.5, 23.5, NULL);
	sc->s = (struct dao_denoise_setup){ .width = W, .height = H, .ax = cam.ax, .ay = cam.ay,
					    .bx = cam.bx, .by = cam.by, .noise_k = 0.0012f,
					    .sharpness = 4.0f, .radius = 4, .invalid_value = 1.0f };
	for (int i = 0; i < W * H; i++) {
		sc->z[i] = (i % W) < 32 ? 1.5f : 2.5f;
		sc->n[3 * i + 2] = -1.0f;
	}
	return sc;
}

static void run(struct scene *sc, int bilateral)
{
	if (bilateral) {
		dao_denoise_bilateral_h(&sc->s, sc->z, sc->n, sc->ao, sc->tmp, 0, H);
		dao_denoise_bilateral_v(&sc->s, sc->z, sc->n, sc->tmp, sc->out, 0, H);
	} else {
		dao_denoise_plane(&sc->s, sc->z, sc->ao, sc->out, 0, H);
	}
}

static void test_constant_and_edges(void **state)
{
	(void)state;
	for (int b = 0; b < 2; b++) {
		struct scene *sc = make_scene();
		for (int i = 0; i < W * H; i++)
			sc->ao[i] = 0.7f;
		run(sc, b);
		for (int i = 0; i < W * H; i++)
			assert_true(fabsf(sc->out[i] - 0.7f) < 1e-6f);
		/* AO 0.2 on the near side, 1.0 on the far side: no mixing across the step */
		for (int i = 0; i < W * H; i++)
			sc->ao[i] = (i % W) < 32 ? 0.2f : 1.0f;
		run(sc, b);
		for (int y = 0; y < H; y++)
			for (int x = 0; x < W; x++) {
				float want = x < 32 ? 0.2f : 1.0f;
				if (fabsf(sc->out[y * W + x] - want) > 0.01f)
					fail_msg("%s: (%d, %d) = %f, want %f", b ? "bilateral" : "plane", x, y,
						 sc->out[y * W + x], want);
			}
		free(sc);
	}
}

static void test_variance_and_invalid(void **state)
{
	(void)state;
	for (int b = 0; b < 2; b++) {
		struct scene *sc = make_scene();
		unsigned seed = 7;
		double in2 = 0, out2 = 0;
		for (int i = 0; i < W * H; i++) {
			seed = seed * 1664525u + 1013904223u;
			sc->ao[i] = 0.6f + 0.2f * ((float)(seed >> 9) / 8388608.0f - 0.5f);
		}
		sc->z[10 * W + 10] = 0.0f;
		run(sc, b);
		assert_true(sc->out[10 * W + 10] == 1.0f);
		int n = 0;
		for (int y = 4; y < H - 4; y++)
			for (int x = 4; x < 28; x++) {
				in2 += (sc->ao[y * W + x] - 0.6) * (sc->ao[y * W + x] - 0.6);
				out2 += (sc->out[y * W + x] - 0.6) * (sc->out[y * W + x] - 0.6);
				n++;
			}
		print_message("%s: AO noise sd %.4f -> %.4f\n", b ? "bilateral" : "plane",
			      sqrt(in2 / n), sqrt(out2 / n));
		assert_true(out2 < in2 / 4.0);
		free(sc);
	}
}

/* On a tilted plane the tolerance must follow the slope, not cut the kernel. */
static void test_slope(void **state)
{
	(void)state;
	for (int b = 0; b < 2; b++) {
		struct scene *sc = make_scene();
		const double nn[3] = { 0.0, -0.8, -0.6 };
		for (int y = 0; y < H; y++)
			for (int x = 0; x < W; x++) {
				double ry = (y - 23.5) / 60.0;
				int i = y * W + x;
				sc->z[i] = (float)(-1.2 / (nn[1] * ry + nn[2]));
				sc->n[3 * i + 1] = (float)nn[1];
				sc->n[3 * i + 2] = (float)nn[2];
				sc->ao[i] = (x + y) % 2 ? 0.4f : 0.8f; /* a checkerboard averages to 0.6 */
			}
		run(sc, b);
		for (int y = 8; y < H - 8; y++)
			for (int x = 8; x < W - 8; x++)
				if (fabsf(sc->out[y * W + x] - 0.6f) > 0.1f)
					fail_msg("%s: slope at (%d, %d) = %f", b ? "bilateral" : "plane", x, y,
						 sc->out[y * W + x]);
		free(sc);
	}
}

/*
 * A pattern of period 4 (the GTAO noise tile: 16 arbitrary values repeated)
 * on a plane leaves the denoise as its mean, with no trace of the grid
 * (a 5 x 5 box passes a fifth of the 1/4 and 1/2 cycle/px components).
 */
static void test_tile_pattern_cancelled(void **state)
{
	(void)state;
	static const float tile[16] = { 0.31f, 0.92f, 0.55f, 0.12f, 0.77f, 0.40f, 0.66f, 0.05f,
					0.88f, 0.23f, 0.49f, 0.71f, 0.18f, 0.60f, 0.95f, 0.35f };
	double mean = 0.0;
	for (int i = 0; i < 16; i++)
		mean += tile[i] / 16.0;
	for (int b = 0; b < 2; b++) {
		struct scene *sc = make_scene();
		for (int i = 0; i < W * H; i++)
			sc->z[i] = 2.0f;
		for (int y = 0; y < H; y++)
			for (int x = 0; x < W; x++)
				sc->ao[y * W + x] = tile[(y & 3) * 4 + (x & 3)];
		run(sc, b);
		const int m = b ? sc->s.radius : 2;
		for (int y = m; y < H - m; y++)
			for (int x = m; x < W - m; x++)
				if (fabs(sc->out[y * W + x] - mean) > 1e-5)
					fail_msg("%s: (%d, %d) = %f, the tile's mean is %f",
						 b ? "bilateral" : "plane", x, y, sc->out[y * W + x], mean);
		free(sc);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_constant_and_edges),
		cmocka_unit_test(test_variance_and_invalid),
		cmocka_unit_test(test_slope),
		cmocka_unit_test(test_tile_pattern_cancelled),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
