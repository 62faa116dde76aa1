/* SPDX-License-Identifier: MIT */
/*
 * prefilter=domain (src/depth/domain.c), reference passes: planes stay in
 * place, steps stay steps, holes stay holes, noise goes down by a measured
 * factor (independent and spatially correlated), creases stay sharp with
 * side windows, and the schedule of the iterations adds up to the spatial
 * scale.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/cmocka_all.h"
#include "common/noise_fields.h"
#include "common/test_common.h"
#include "depth/domain.h"

enum { W = 160, H = 120 };

static float *scratch_buf(void)
{
	float *s = malloc(dao_domain_scratch_floats(W, H) * sizeof(float));
	assert_non_null(s);
	return s;
}

/* side windows in setup_fixed (the tests of planes and steps run with and without) */
static int use_sides;

static void setup_fixed(struct dao_domain_setup *s, float scale, float noise, float unit)
{
	*s = (struct dao_domain_setup){
		.width = W, .height = H, .iterations = 3,
		.inv_scale = 1.0f / scale,
		.range_coef = dao_domain_range_coef(3.0f),
		.noise = noise, .unit = unit,
		.sides = use_sides,
	};
}

static void filter(const struct dao_domain_setup *s, const float *z, float *out)
{
	float *tmp = malloc(W * H * sizeof(float)), *sc = scratch_buf();
	assert_non_null(tmp);
	dao_domain_filter(s, dao_domain_pass_ref, z, tmp, out, sc);
	free(tmp);
	free(sc);
}

/* Depth of plane n.X = c at pixel (x, y) for a 70 px focal length. */
static float plane_at(int x, int y, const double n[3], double c)
{
	double rx = (x - 79.5) / 70.0, ry = (y - 59.5) / 70.0;
	return (float)(c / (n[0] * rx + n[1] * ry + n[2]));
}

static void test_schedule(void **state)
{
	(void)state;
	for (int n = 1; n <= DAO_DOMAIN_MAX_ITERATIONS; n++) {
		double var = 0;
		for (int i = 1; i <= n; i++)
			var += pow(dao_domain_schedule(i, n), 2);
		assert_true(fabs(var - 1.0) < 1e-6);
		/* each iteration half the scale of the one before */
		for (int i = 2; i <= n; i++)
			assert_true(fabsf(dao_domain_schedule(i, n) * 2.0f -
					  dao_domain_schedule(i - 1, n)) < 1e-6f);
	}
}

/*
 * Tilted planes stay where they are, next to holes, a depth edge and the
 * image border too: the local linear fit reproduces any w affine along a
 * line.  Bound: float rounding (measured below 1e-6 relative).
 */
static void test_planes_exact(void **state)
{
	(void)state;
	static const double planes[][4] = { { 0, 0, -1, -2 },
					    { 0.4, -0.3, -0.866, -1.5 },
					    { -0.45, 0.2, -0.87, -1.2 } }; /* 1 - 9.6 m, 0.8 - 6.4 m */
	float *z = malloc(W * H * sizeof(float)), *out = malloc(W * H * sizeof(float));
	static const float scales[] = { 2.0f, 8.0f, 32.0f };
	for (int p = 0; p < 6; p++)
		for (int si = 0; si < 3; si++) {
			use_sides = p >= 3;
			for (int y = 0; y < H; y++)
				for (int x = 0; x < W; x++)
					z[y * W + x] = plane_at(x, y, planes[p % 3], planes[p % 3][3]);
			/* holes: a block, a line, single pixels */
			for (int y = 40; y < 50; y++)
				for (int x = 30; x < 45; x++)
					z[y * W + x] = 0.0f;
			for (int x = 0; x < W; x++)
				z[90 * W + x] = x % 7 ? z[90 * W + x] : 0.0f;
			z[10 * W + 100] = 0.0f;
			struct dao_domain_setup s;
			setup_fixed(&s, scales[si], 0.0012f, 0.0f);
			filter(&s, z, out);
			double worst = 0;
			for (int i = 0; i < W * H; i++) {
				if (z[i] == 0.0f) {
					assert_true(out[i] == 0.0f);
					continue;
				}
				double e = fabs(out[i] - z[i]) / z[i];
				worst = e > worst ? e : worst;
			}
			print_message("plane %d, scale %4.0f px, sides %d: largest relative change %.2e\n",
				      p % 3, (double)scales[si], use_sides, worst);
			assert_true(worst < 2e-6);
		}
	free(z);
	free(out);
}

/* A step between two tilted planes: every pixel a column or more from the
 * step keeps its plane (the edge moves by less than 1 px). */
static void test_step(void **state)
{
	(void)state;
	float *z = malloc(W * H * sizeof(float)), *out = malloc(W * H * sizeof(float));
	static const double near_p[4] = { 0.2, -0.1, -0.97, -1.5 }, far_p[4] = { -0.3, 0.1, -0.95, -2.0 };
	uint64_t seed = 3;
	static const float scales[] = { 4.0f, 16.0f };
	for (int si = 0; si < 4; si++) {
		use_sides = si >= 2;
		for (int y = 0; y < H; y++)
			for (int x = 0; x < W; x++) {
				const double *pl = x < 80 ? near_p : far_p;
				float t = plane_at(x, y, pl, pl[3]);
				z[y * W + x] = t + (float)(dao_test_gauss(&seed) * 0.0012 * t * t);
			}
		struct dao_domain_setup s;
		setup_fixed(&s, scales[si % 2], 0.0012f, 0.0f);
		filter(&s, z, out);
		double worst_near = 0, worst_far = 0;
		for (int y = 0; y < H; y++)
			for (int x = 77; x < 83; x++) {
				const double *pl = x < 80 ? near_p : far_p;
				double t = plane_at(x, y, pl, pl[3]);
				double e = fabs(out[y * W + x] - t) / (0.0012 * t * t); /* in noise sigmas */
				if (x == 79 || x == 80)
					worst_near = e > worst_near ? e : worst_near;
				else
					worst_far = e > worst_far ? e : worst_far;
			}
		print_message("step, scale %2.0f px, sides %d: largest error beside it %.2f sigma, 2+ px "
			      "away %.2f sigma\n", (double)scales[si % 2], use_sides, worst_near, worst_far);
		/* the step is ~150 sigma: a pixel pulled across would be off by far more */
		assert_true(worst_near < 6.0);
		assert_true(worst_far < 3.0);
	}
	free(z);
	free(out);
}

/*
 * A crease: two planes meeting along x = 80 (in 1/z: slopes +0.002 and
 * -0.003 per px across it), independent noise of sigma = 0.0012 in 1/z.
 * The two-sided line rounds the crease over the scale; the side windows
 * extrapolate each plane to it.  RMS error in sigmas within 6 px of the
 * crease and beyond 12 px, without and with side windows: the crease must
 * come out at most half as wrong, the planes at most 1.3 times as noisy.
 */
static void crease_rms(float scale, int sides, double *near, double *far)
{
	float *z = malloc(W * H * sizeof(float)), *out = malloc(W * H * sizeof(float));
	assert_non_null(z);
	assert_non_null(out);
	uint64_t seed = 11;
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			const double w = 0.5 + 0.0004 * y + (x < 80 ? 0.002 * (x - 80) : -0.003 * (x - 80));
			z[y * W + x] = (float)(1.0 / (w + 0.0012 * dao_test_gauss(&seed)));
		}
	struct dao_domain_setup s;
	use_sides = sides;
	setup_fixed(&s, scale, 0.0012f, 0.0f);
	filter(&s, z, out);
	double sn = 0, sf = 0;
	int nn = 0, nf = 0;
	for (int y = 16; y < H - 16; y++)
		for (int x = 16; x < W - 16; x++) {
			const double w = 0.5 + 0.0004 * y + (x < 80 ? 0.002 * (x - 80) : -0.003 * (x - 80));
			const double e = (1.0 / out[y * W + x] - w) / 0.0012;
			if (abs(x - 80) <= 6)
				sn += e * e, nn++;
			else if (abs(x - 80) > 12)
				sf += e * e, nf++;
		}
	*near = sqrt(sn / nn), *far = sqrt(sf / nf);
	free(z);
	free(out);
}

static void test_crease(void **state)
{
	(void)state;
	static const float scales[] = { 4.0f, 8.0f, 16.0f };
	for (int si = 0; si < 3; si++) {
		double n0, f0, n1, f1;
		crease_rms(scales[si], 0, &n0, &f0);
		crease_rms(scales[si], 1, &n1, &f1);
		print_message("crease, scale %2.0f px: RMS within 6 px %.2f -> %.2f sigma, beyond 12 px "
			      "%.3f -> %.3f sigma (without -> with side windows)\n",
			      (double)scales[si], n0, n1, f0, f1);
		assert_true(n1 <= 0.5 * n0);
		assert_true(f1 <= 1.3 * f0);
	}
}

/* RMS of the 1/z error against the plane over the inner pixels */
static double inner_rms(const float *z, const double *pl)
{
	double s = 0;
	int n = 0;
	for (int y = 16; y < H - 16; y++)
		for (int x = 16; x < W - 16; x++) {
			double t = 1.0 / plane_at(x, y, pl, pl[3]);
			double e = 1.0 / z[y * W + x] - t;
			s += e * e, n++;
		}
	return sqrt(s / n);
}

/* Noise in 1/z goes down by a factor that grows with the scale, for
 * independent and for spatially correlated noise. */
static void test_noise_reduction(void **state)
{
	(void)state;
	static const double pl[4] = { 0.3, -0.4, -0.866, -2.0 };
	float *z = malloc(W * H * sizeof(float)), *out = malloc(W * H * sizeof(float));
	float *nz = malloc(W * H * sizeof(float));
	use_sides = 1; /* as the pipeline runs it */
	const double sigma = 0.0012;
	/* blur 0: independent; bounds: measured factors less a margin */
	static const struct {
		double blur;
		float scale;
		double min_factor;
	} cases[] = {
		{ 0, 2, 3.5 }, { 0, 4, 7.0 }, { 0, 8, 12.0 },
		{ 1, 4, 2.5 }, { 1, 8, 5.0 }, { 2, 8, 2.5 }, { 2, 16, 4.5 },
	};
	for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
		dao_test_correlated_noise(nz, W, H, sigma, cases[c].blur, 11 + c);
		for (int y = 0; y < H; y++)
			for (int x = 0; x < W; x++) {
				double w = 1.0 / plane_at(x, y, pl, pl[3]) + nz[y * W + x];
				z[y * W + x] = (float)(1.0 / w);
			}
		struct dao_domain_setup s;
		setup_fixed(&s, cases[c].scale, (float)sigma, 0.0f);
		filter(&s, z, out);
		const double before = inner_rms(z, pl), after = inner_rms(out, pl);
		print_message("noise blur %.0f px, scale %2.0f px: %.2e -> %.2e in 1/z (%.1fx)\n",
			      cases[c].blur, (double)cases[c].scale, before, after, before / after);
		assert_true(before / after >= cases[c].min_factor);
	}
	free(z);
	free(out);
	free(nz);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_schedule),
		cmocka_unit_test(test_planes_exact),
		cmocka_unit_test(test_step),
		cmocka_unit_test(test_crease),
		cmocka_unit_test(test_noise_reduction),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
