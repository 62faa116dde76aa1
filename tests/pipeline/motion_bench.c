/* SPDX-License-Identifier: MIT */
/*
 * motion-bench: the CPU time of the motion estimate and the history's
 * reprojection (src/motion) per frame pair of a depth sequence, with
 * CLOCK_PROCESS_CPUTIME_ID (the pool's threads included; then the calling
 * thread's alone, CLOCK_THREAD_CPUTIME_ID, and the wall time).  A measuring tool
 * (docs/perf/icp2.md), not a test.
 *
 *   motion-bench DIR SIMD THREADS ROUNDS [POOL_MIN_POINTS [ao|seeded [PART]]]
 *
 * (POOL_MIN_POINTS: dao_icp_setup's; "ao": the AO history's reprojection
 * alone instead, by the estimated motions, on the calling thread;
 * "seeded": each pair's estimate seeded by the last pair's accepted one, as
 * the pipeline's prior does, the first pair of each pass by none; any
 * other word, e.g. "-", unseeded; PART: "estimate" or "reproject" times that
 * part alone (the reprojection by poses estimated before the clock starts); default
 * both; "ao" takes no PART)
 *
 * DIR/depth/NNNN.png (mm) with camera.json's 640x480 at 525 px (synth's);
 * the previous frame is given as 1/z (the history's form).  Prints the mean
 * CPU ms per pair over ROUNDS passes of the sequence.  Built against main
 * with -DMOTION_BENCH_MAIN (no kernel or pool in the setup there).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <depthao/camera.h>
#include <depthao/png.h>

#include "motion/icp.h"
#include "motion/reproject.h"
#ifndef MOTION_BENCH_MAIN
#include "pipeline/kernels.h"
#include "core/threadpool.h"
#endif

enum { MAXF = 64 };

static double clock_ms(clockid_t c)
{
	struct timespec t;
	clock_gettime(c, &t);
	return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

static double cpu_ms(void)
{
	return clock_ms(CLOCK_PROCESS_CPUTIME_ID);
}

int main(int argc, char **argv)
{
	if (argc < 5) {
		fprintf(stderr, "usage: motion-bench DIR SIMD THREADS ROUNDS [POOL_MIN_POINTS "
				"[ao|seeded|- [both|estimate|reproject]]]\n");
		return 2;
	}
	struct dao_camera cam;
	struct dao_error err;
	if (dao_camera_from_intrinsics(&cam, 640, 480, 525.0, 525.0, 319.5, 239.5, &err))
		return 1;
	const size_t npix = 640 * 480;
	static float *z[MAXF], *inv[MAXF];
	int n = 0;
	for (; n < MAXF; n++) {
		char path[4096];
		struct dao_frame f;
		snprintf(path, sizeof path, "%s/depth/%04d.png", argv[1], n);
		if (dao_png_read_depth(path, 0.001f, &f, &err))
			break;
		z[n] = malloc(npix * 4), inv[n] = malloc(npix * 4);
		for (size_t i = 0; i < npix; i++) {
			const uint16_t v = ((const uint16_t *)f.data)[i];
			z[n][i] = v * 0.001f;
			inv[n][i] = v ? 1.0f / z[n][i] : 0.0f;
		}
		dao_frame_free(&f);
	}
	if (n < 2)
		return 1;
	struct dao_icp_setup s;
	dao_icp_setup_default(&s);
#ifndef MOTION_BENCH_MAIN
	struct dao_kernels k;
	dao_kernels_select(&k, (enum dao_simd)atoi(argv[2]));
	s.pairs = k.icp_pairs;
	s.source = k.icp_source;
	s.target = k.icp_target;
	struct dao_pool *pool = NULL;
	if (atoi(argv[3]) > 1 && dao_pool_create(&pool, atoi(argv[3])))
		return 1;
	s.pool = pool;
	if (argc > 5)
		s.pool_min_points = atoi(argv[5]);
#endif
	float *scratch = malloc(dao_icp_scratch_floats(&s, 640, 480) * sizeof(float));
	float *h = malloc(npix * 4);
	uint8_t *count = malloc(npix), *age = calloc(npix, 1), *c2 = malloc(npix), *a2 = malloc(npix);
	memset(count, 1, npix);
	const int rounds = atoi(argv[4]);
#ifndef MOTION_BENCH_MAIN
	if (argc > 6 && !strcmp(argv[6], "ao")) {
		/* the AO history's reprojection alone (on the calling thread), by the
		 * estimated motions, the previous depth as the history's depth */
		static struct dao_pose pose[MAXF];
		float *hao = malloc(npix * 4), *oao = malloc(npix * 4), *oz = malloc(npix * 4);
		for (size_t i = 0; i < npix; i++)
			hao[i] = 0.5f + 0.4f * (float)((i * 2654435761u) % 1000u) / 1000.0f;
		for (int i = 1; i < n; i++) {
			struct dao_icp_result res;
			dao_icp_estimate(&s, &cam, inv[i - 1], count, z[i], NULL, scratch, &res);
			pose[i] = res.pose;
		}
		double sum = 0.0;
		const double a0 = cpu_ms();
		for (int r = 0; r < rounds; r++)
			for (int i = 1; i < n; i++) {
				k.ao_reproject(&cam, &pose[i], 0.02f, z[i], hao, z[i - 1], oao, oz, 0, 480);
				sum += oao[npix / 2 + 320];
			}
		printf("%.3f ms CPU per frame (AO history reprojection; check %.6f)\n",
		       (cpu_ms() - a0) / ((n - 1) * rounds), sum / rounds);
		return 0;
	}
#endif
	const int seeded = argc > 6 && !strcmp(argv[6], "seeded");
	const char *part = argc > 7 ? argv[7] : "both";
	const int estimate = strcmp(part, "reproject") != 0, reproject = strcmp(part, "estimate") != 0;
	if (strcmp(part, "both") && strcmp(part, "estimate") && strcmp(part, "reproject")) {
		fprintf(stderr, "motion-bench: PART is both, estimate or reproject, not %s\n", part);
		return 2;
	}
	/* the poses of a pass, for the reprojection timed alone (not computed
	 * otherwise: "both" runs as before, without this warm-up) */
	static struct dao_icp_result fixed[MAXF];
	if (!estimate) {
		struct dao_pose last;
		int have = 0;
		for (int i = 1; i < n; i++) {
			dao_icp_estimate(&s, &cam, inv[i - 1], count, z[i],
					 seeded && have ? &last : NULL, scratch, &fixed[i]);
			if (fixed[i].valid)
				last = fixed[i].pose, have = 1;
		}
	}
	double t0 = cpu_ms(), ang = 0;
	const double c0 = clock_ms(CLOCK_THREAD_CPUTIME_ID), w0 = clock_ms(CLOCK_MONOTONIC);
	for (int r = 0; r < rounds; r++) {
		struct dao_pose last;
		int have = 0;
		for (int i = 1; i < n; i++) {
			struct dao_icp_result res = fixed[i];
			if (estimate)
				dao_icp_estimate(&s, &cam, inv[i - 1], count, z[i],
						 seeded && have ? &last : NULL, scratch, &res);
			if (res.valid)
				last = res.pose, have = 1;
			ang += dao_pose_angle(&res.pose);
			if (!reproject)
				continue;
#ifndef MOTION_BENCH_MAIN
			dao_history_reproject(&cam, &res.pose, inv[i - 1], count, age, h, c2, a2,
					      (int32_t *)(void *)scratch, k.reproject_land, pool);
#else
			dao_history_reproject(&cam, &res.pose, inv[i - 1], count, age, h, c2, a2);
#endif
		}
	}
	const double t = cpu_ms() - t0;
	const double tc = clock_ms(CLOCK_THREAD_CPUTIME_ID) - c0, tw = clock_ms(CLOCK_MONOTONIC) - w0;
	const double per = (n - 1) * rounds;
	printf("%.3f ms CPU per frame pair (%d pairs x %d rounds; check %.6f); the calling "
	       "thread %.3f ms, wall %.3f ms\n",
	       t / per, n - 1, rounds, ang / rounds, tc / per, tw / per);
	return 0;
}
