/* SPDX-License-Identifier: MIT */
/*
 * The measuring instrument: the plane finder finds synthetic planes exactly,
 * and each simulated sensor has the statistics that were measured on real
 * frames (docs/sensor-models.md), within bands derived from those
 * measurements; every model is deterministic for a seed and any thread count.
 *
 * The bands for structured light come from `depthao sensorstats --compare` on
 * ../shared/data: the Kinect .oni (12 frames) and TUM frames give residual
 * sigma(1/z) 0.0025 / 0.0031 1/m; autocorrelation along rows 0.85 / 0.93 at
 * 1 px, 0.58 / 0.78 at 4 px, 0.38 / 0.65 at 8 px (columns 0.87 / 0.89,
 * 0.63 / 0.75, 0.46 / 0.67); band constant f b / q 345 / 342 m px (the
 * theory of a 1/8-px disparity of a 580-px camera with a 7.5 cm baseline:
 * 348); projector shadows left of the foreground in 84-90 % of the shadow
 * runs.  The bands below span both frames with a margin.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "synth/open_planes.h"
#include "synth/planes.h"
#include "synth/rng.h"
#include "synth/robust.h"
#include "synth/sensor.h"
#include "synth/sensor_stats.h"
#include "synth/suite.h"

#define W 640
#define H 480
#define NP ((size_t)W * H)

/* Kinect v1: 8 f b for 1/8-px disparity, f = 580 px, b = 7.5 cm */
#define KINECT_BAND_C (8.0 * 580.0 * 0.075)

struct rendered {
	struct synth_scene scene;
	struct dao_camera cam;
	struct synth_image img;
};

static void render(const char *name, struct rendered *r)
{
	synth_default_camera(&r->cam);
	assert_int_equal(synth_scene_build(name, 0.0, &r->scene, NULL), 0);
	assert_int_equal(synth_render(&r->scene, &r->cam, 0.5, 0, 2, &r->img, NULL), 0);
}

/* What `sensor` delivers, in millimetres as the suite does, back in metres. */
static float *simulate(const struct rendered *r, enum synth_sensor sensor, uint64_t seed,
		       int threads)
{
	struct synth_case c;
	struct dao_error err;
	int ret = synth_case_simulate(&c, &r->scene, 0, &r->cam, &r->img, sensor, seed, threads, &err);
	if (ret)
		print_error("%s\n", err.message);
	assert_int_equal(ret, 0);
	float *z = malloc(NP * sizeof(float));
	memcpy(z, c.depth_m, NP * sizeof(float));
	synth_case_free(&c);
	return z;
}

static void measure(const float *z, const struct dao_camera *cam, struct synth_sensor_stats *s)
{
	struct synth_plane planes[SYNTH_PLANES_MAX];
	int n;
	int32_t *lab = malloc(NP * sizeof(int32_t));
	assert_int_equal(synth_planes_find_frame(z, cam, 0.001, planes, &n, lab, NULL), 0);
	assert_int_equal(synth_sensor_stats(z, cam, 0.001, planes, n, lab, s, NULL), 0);
	free(lab);
}

static int cmp_float(const void *a, const void *b)
{
	float x = *(const float *)a, y = *(const float *)b;
	return (x > y) - (x < y);
}

static void test_order_statistics(void **state)
{
	(void)state;
	uint64_t rng = 3;
	for (size_t n = 1; n < 300; n += 37) {
		float *a = malloc(n * sizeof(float)), *b = malloc(n * sizeof(float));
		for (size_t i = 0; i < n; i++)
			a[i] = (float)(synth_rng_uniform(&rng) < 0.2 ? 1.0 : synth_rng_uniform(&rng)); /* ties */
		memcpy(b, a, n * sizeof(float));
		qsort(b, n, sizeof(float), cmp_float);
		for (size_t k = 0; k < n; k += 7) {
			float *c = malloc(n * sizeof(float));
			memcpy(c, a, n * sizeof(float));
			assert_true(synth_select(c, n, k) == b[k]);
			free(c);
		}
		float med = n % 2 ? b[n / 2] : 0.5f * (b[n / 2 - 1] + b[n / 2]);
		assert_true(synth_median(a, n) == med);
		free(a);
		free(b);
	}
	/* robust sigma of a Gaussian sample */
	float g[20000];
	for (int i = 0; i < 20000; i++) {
		double u = synth_rng_uniform(&rng), v = synth_rng_uniform(&rng);
		g[i] = (float)(0.5 * sqrt(-2.0 * log(u)) * cos(6.283185307179586 * v));
	}
	assert_true(fabs(synth_robust_sigma(g, 20000) - 0.5) < 0.02);
}

/* The plane of a half-space primitive: unit normal towards the camera and distance. */
static void halfspace_plane(const struct synth_prim *p, double n[3], double *dist)
{
	double d = v3_dot(p->n, p->c); /* n.X = d on the plane */
	double s = d < 0 ? 1.0 : -1.0; /* the camera (origin) side */
	n[0] = s * p->n.x, n[1] = s * p->n.y, n[2] = s * p->n.z;
	*dist = fabs(d);
}

static void test_ransac_exact(void **state)
{
	(void)state;
	static const char *const scenes[] = { "plane", "room-corner" };
	for (int k = 0; k < 2; k++) {
		struct rendered r;
		render(scenes[k], &r);
		struct synth_plane planes[SYNTH_PLANES_MAX];
		int n;
		int32_t *lab = malloc(NP * sizeof(int32_t));
		struct synth_plane_options po;
		synth_plane_options_default(&po);
		assert_int_equal(synth_planes_find(r.img.depth, &r.cam, &po, planes, &n, lab, NULL), 0);
		assert_true(n >= 1);
		long labelled = 0;
		for (size_t i = 0; i < NP; i++)
			labelled += lab[i] >= 0;
		/* every plane found is one of the scene's half-spaces, to float precision */
		for (int p = 0; p < n; p++) {
			double best = 1e9, dd = 0;
			for (int q = 0; q < r.scene.count; q++) {
				if (r.scene.prims[q].kind != SYNTH_HALFSPACE)
					continue;
				double nn[3], dist;
				halfspace_plane(&r.scene.prims[q], nn, &dist);
				double e = fabs(nn[0] - planes[p].normal[0]) + fabs(nn[1] - planes[p].normal[1]) +
					   fabs(nn[2] - planes[p].normal[2]);
				if (e < best)
					best = e, dd = fabs(dist - planes[p].distance);
			}
			print_message("%s plane %d: %ld px, normal error %.2g, distance error %.2g m\n",
				      scenes[k], p, planes[p].pixels, best, dd);
			assert_true(best < 1e-5);
			assert_true(dd < 1e-5);
		}
		/* the tilted plane is one plane covering the image; the corner's faces all */
		if (k == 0) {
			assert_int_equal(n, 1);
			assert_true(labelled >= (long)(0.98 * NP));
		} else {
			assert_true(n >= 3);
			assert_true(labelled >= (long)(0.95 * NP));
		}
		free(lab);
		synth_image_free(&r.img);
	}
}

static void test_structured_light_statistics(void **state)
{
	(void)state;
	struct rendered r;
	render("room-corner", &r);
	float *z = simulate(&r, SYNTH_SENSOR_STRUCTURED_LIGHT, 1, 2);
	struct synth_sensor_stats s;
	measure(z, &r.cam, &s);
	print_message("structured light, room corner: sigma(1/z) %.4f, ACF rows %.2f %.2f %.2f, "
		      "cols %.2f %.2f %.2f, f b/q %.0f\n", s.sigma_w, s.acf_row[1], s.acf_row[4],
		      s.acf_row[8], s.acf_col[1], s.acf_col[4], s.acf_col[8], s.band_c);
	/* amplitude: the real Kinect frames' 0.0026-0.0034, with a margin */
	assert_true(s.sigma_w > 0.0020 && s.sigma_w < 0.0040);
	/* correlated like the real frames (an i.i.d. model is near 0 here) */
	assert_true(s.acf_row[1] > 0.75 && s.acf_row[1] < 0.96);
	assert_true(s.acf_col[1] > 0.75 && s.acf_col[1] < 0.96);
	assert_true(s.acf_row[4] > 0.45 && s.acf_row[4] < 0.85);
	assert_true(s.acf_col[4] > 0.45 && s.acf_col[4] < 0.85);
	assert_true(s.acf_row[8] > 0.25 && s.acf_row[8] < 0.75);
	assert_true(s.acf_col[8] > 0.25 && s.acf_col[8] < 0.75);
	/* bands: within 10 % of the 1/8-px theory */
	assert_true(fabs(s.band_c - KINECT_BAND_C) < 0.1 * KINECT_BAND_C);
	/* the band step at 2-2.5 m: z^2 / (f b / q), 1.3 cm */
	const struct synth_zbin_stats *b = &s.bin[(int)(2.25 / SYNTH_STATS_ZBIN)];
	assert_true(b->gap > 0.8 * 2.25 * 2.25 / KINECT_BAND_C && b->gap < 1.2 * 2.25 * 2.25 / KINECT_BAND_C);
	free(z);
	synth_image_free(&r.img);

	/* projector shadows: left of foreground objects (the projector is on the +x side) */
	render("boxes", &r);
	z = simulate(&r, SYNTH_SENSOR_STRUCTURED_LIGHT, 1, 2);
	measure(z, &r.cam, &s);
	long runs = s.shadow_left + s.shadow_right;
	print_message("structured light, boxes: %ld shadow runs, %.0f %% left of the foreground\n", runs,
		      runs ? 100.0 * s.shadow_left / runs : 0.0);
	assert_true(runs >= 50);
	assert_true(s.shadow_left >= 0.7 * runs);
	/* the same measure on the clean render finds no shadows at all */
	struct synth_sensor_stats clean;
	measure(r.img.depth, &r.cam, &clean);
	assert_int_equal(clean.shadow_left + clean.shadow_right, 0);
	free(z);
	synth_image_free(&r.img);
}

/* The 1/z difference of two frames split at 32 x 32 px blocks: the robust sigma
 * of the blocks' means (the slow part) and of the pixels about their block's
 * mean (the rest), over the blocks with depth in 3/4 of both frames. */
static void diff_scales(const float *a, const float *b, double *slow, double *fast)
{
	enum { B = 32 };
	float *means = malloc((NP / (B * B)) * sizeof(float)), *rest = malloc(NP * sizeof(float));
	size_t nm = 0, nr = 0;
	for (int by = 0; by + B <= H; by += B)
		for (int bx = 0; bx + B <= W; bx += B) {
			double sum = 0.0;
			int n = 0;
			for (int y = by; y < by + B; y++)
				for (int x = bx; x < bx + B; x++) {
					const size_t i = (size_t)y * W + x;
					if (a[i] > 0.0f && b[i] > 0.0f)
						sum += 1.0 / a[i] - 1.0 / b[i], n++;
				}
			if (n < B * B * 3 / 4)
				continue;
			const double m = sum / n;
			means[nm++] = (float)m;
			for (int y = by; y < by + B; y++)
				for (int x = bx; x < bx + B; x++) {
					const size_t i = (size_t)y * W + x;
					if (a[i] > 0.0f && b[i] > 0.0f)
						rest[nr++] = (float)(1.0 / a[i] - 1.0 / b[i] - m);
				}
		}
	assert_true(nm >= 100);
	*slow = synth_robust_sigma(means, nm);
	*fast = synth_robust_sigma(rest, nr);
	free(means);
	free(rest);
}

/* Two frames of one structured-light device share its slow pattern deviation
 * (the real recording's error repeats from frame to frame) and differ in the
 * speckle; two devices differ in both. */
static void test_structured_light_device(void **state)
{
	(void)state;
	struct rendered r;
	render("plane", &r);
	float *z[3];
	const uint64_t seeds[3][2] = { { 1, 1 }, { 1, 2 }, { 2, 2 } };   /* device, frame */
	for (int k = 0; k < 3; k++) {
		struct synth_case c;
		struct dao_error err;
		assert_int_equal(synth_case_simulate_frame(&c, &r.scene, 0, &r.cam, &r.img,
							   SYNTH_SENSOR_STRUCTURED_LIGHT, seeds[k][0],
							   seeds[k][1], 2, &err), 0);
		z[k] = malloc(NP * sizeof(float));
		memcpy(z[k], c.depth_m, NP * sizeof(float));
		synth_case_free(&c);
	}
	/* a frame alone is the first frame of its device */
	float *alone = simulate(&r, SYNTH_SENSOR_STRUCTURED_LIGHT, 1, 2);
	assert_memory_equal(alone, z[0], NP * sizeof(float));
	double slow_same, fast_same, slow_other, fast_other;
	diff_scales(z[0], z[1], &slow_same, &fast_same);
	diff_scales(z[0], z[2], &slow_other, &fast_other);
	print_message("structured light, plane, 1/z difference of two frames: one device: "
		      "slow %.5f, rest %.5f; two devices: slow %.5f, rest %.5f (1/m)\n",
		      slow_same, fast_same, slow_other, fast_other);
	assert_true(slow_same < 0.5 * slow_other);
	assert_true(fast_same > 0.7 * fast_other);
	for (int k = 0; k < 3; k++)
		free(z[k]);
	free(alone);
	synth_image_free(&r.img);
}

static void test_determinism(void **state)
{
	(void)state;
	struct rendered r;
	render("spheres", &r);
	static const enum synth_sensor models[] = {
		SYNTH_SENSOR_STRUCTURED_LIGHT, SYNTH_SENSOR_ACTIVE_STEREO, SYNTH_SENSOR_TOF,
	};
	for (size_t k = 0; k < sizeof models / sizeof models[0]; k++) {
		float *a = simulate(&r, models[k], 5, 1), *b = simulate(&r, models[k], 5, 2);
		float *c = simulate(&r, models[k], 6, 2);
		assert_memory_equal(a, b, NP * sizeof(float));
		assert_memory_not_equal(a, c, NP * sizeof(float));
		free(a), free(b), free(c);
	}
	synth_image_free(&r.img);
}

static void test_active_stereo(void **state)
{
	(void)state;
	struct rendered r;
	render("plane", &r);
	float *z = simulate(&r, SYNTH_SENSOR_ACTIVE_STEREO, 1, 2);
	/*
	 * Pixel locking: a parabola vertex clusters at integer disparities, so on
	 * a slanted plane more than half of the disparities lie within 1/4 px of
	 * an integer (half would for an unbiased estimate).
	 */
	const double fb = r.cam.fx * 0.05;
	long near_int = 0, valid = 0, first_col_valid = 0;
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			float d = z[(size_t)y * W + x];
			if (!(d > 0))
				continue;
			double disp = fb / d, frac = disp - floor(disp + 0.5);
			near_int += fabs(frac) < 0.25;
			valid++;
			first_col_valid += x < 8;
		}
	print_message("active stereo, plane: %.1f %% of disparities within 1/4 px of an integer\n",
		      100.0 * near_int / valid);
	assert_true(valid > (long)(0.8 * NP));
	assert_true(near_int > 0.6 * valid);
	/* the left band: what the right camera cannot see (disparity > 8 px everywhere here) */
	assert_int_equal(first_col_valid, 0);
	free(z);
	synth_image_free(&r.img);
}

static void test_tof(void **state)
{
	(void)state;
	struct rendered r;
	/* flying pixels at depth edges: between the two sides, unlike structured light */
	render("boxes", &r);
	float *t = simulate(&r, SYNTH_SENSOR_TOF, 1, 2), *sl = simulate(&r, SYNTH_SENSOR_STRUCTURED_LIGHT, 1, 2);
	struct synth_sensor_stats st, ss;
	measure(t, &r.cam, &st);
	measure(sl, &r.cam, &ss);
	double ft = (double)st.flying_pixels / (double)st.edge_pixels;
	double fs = ss.edge_pixels ? (double)ss.flying_pixels / (double)ss.edge_pixels : 0.0;
	print_message("flying pixels: tof %.1f %% of %ld edge px, structured light %.1f %% of %ld\n",
		      100 * ft, st.edge_pixels, 100 * fs, ss.edge_pixels);
	assert_true(st.edge_pixels > 500);
	assert_true(ft > 0.15 && ft > 2.0 * fs);
	/* the measure itself: a clean render has steps but nothing between their sides */
	struct synth_sensor_stats sc;
	measure(r.img.depth, &r.cam, &sc);
	assert_true(sc.edge_pixels > 500);
	assert_int_equal(sc.flying_pixels, 0);
	free(t), free(sl);
	synth_image_free(&r.img);
	/* multipath: biased away from the camera in the concave room corner, not on the open plane */
	static const char *const scenes[] = { "room-corner", "plane" };
	double bias[2];
	for (int k = 0; k < 2; k++) {
		render(scenes[k], &r);
		t = simulate(&r, SYNTH_SENSOR_TOF, 1, 2);
		double sum = 0;
		long n = 0;
		for (size_t i = 0; i < NP; i++)
			if (t[i] > 0 && r.img.depth[i] > 0)
				sum += t[i] - r.img.depth[i], n++;
		bias[k] = sum / n;
		free(t);
		synth_image_free(&r.img);
	}
	print_message("tof mean bias: room corner %.1f mm, plane %.1f mm\n", 1e3 * bias[0], 1e3 * bias[1]);
	assert_true(bias[0] > 0.01);
	assert_true(fabs(bias[1]) < 0.002);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_order_statistics),
		cmocka_unit_test(test_ransac_exact),
		cmocka_unit_test(test_structured_light_statistics),
		cmocka_unit_test(test_structured_light_device),
		cmocka_unit_test(test_determinism),
		cmocka_unit_test(test_active_stereo),
		cmocka_unit_test(test_tof),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
