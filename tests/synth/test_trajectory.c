/* SPDX-License-Identifier: MIT */
/*
 * The camera trajectories of the synthetic sequences (issue #37): rates and
 * amplitudes from the poses themselves, the TUM file round trip and its
 * errors, a frame ray-traced from a known pose against a hand-computed depth,
 * and the sequence metrics on hand-made frames with known answers.
 */
#define _GNU_SOURCE /* open_memstream */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "synth/sequence_metrics.h"
#include "synth/synth.h"
#include "synth/trajectory.h"

#define DEG (M_PI / 180.0)

static void traj(const char *name, const char *scene_name, uint64_t seed, struct synth_trajectory *tr)
{
	struct synth_scene s;
	struct dao_error err;
	assert_int_equal(synth_scene_build(scene_name, 0.0, &s, &err), 0);
	int r = synth_trajectory_init(tr, name, &s, seed, &err);
	if (r)
		fail_msg("%s: %s", name, err.message);
}

static void assert_identity(const struct synth_pose *p)
{
	for (int i = 0; i < 3; i++) {
		assert_true(fabs(p->t[i]) < 1e-12);
		for (int j = 0; j < 3; j++)
			assert_true(fabs(p->R[i][j] - (i == j)) < 1e-12);
	}
}

/* The angle between consecutive poses is the asked rate / fps; about "up", to the right. */
static void test_pan_rate(void **state)
{
	(void)state;
	const double rates[3] = { 15, 30, 60 };
	const char *names[3] = { "pan-15", "pan-30", "pan-60" };
	for (int k = 0; k < 3; k++) {
		struct synth_trajectory tr;
		traj(names[k], "boxes", 1, &tr);
		struct synth_pose a, b;
		synth_trajectory_pose(&tr, 0.0, &a);
		assert_identity(&a);
		for (int i = 0; i < 16; i++) {
			synth_trajectory_pose(&tr, i / 30.0, &a);
			synth_trajectory_pose(&tr, (i + 1) / 30.0, &b);
			double rate = synth_rotation_angle(a.R, b.R) * 30.0 / DEG;
			assert_true(fabs(rate - rates[k]) < 1e-6);
			for (int j = 0; j < 3; j++)
				assert_true(fabs(b.t[j]) < 1e-12);
			/* up is the rotation's axis: R up = up */
			for (int j = 0; j < 3; j++)
				assert_true(fabs(b.R[j][0] * tr.up[0] + b.R[j][1] * tr.up[1] +
						 b.R[j][2] * tr.up[2] - tr.up[j]) < 1e-12);
		}
		/* the optical axis turned right: its right component grew */
		double fwd_right = b.R[0][2] * tr.right[0] + b.R[1][2] * tr.right[1] + b.R[2][2] * tr.right[2];
		assert_true(fwd_right > 0.0);
	}
	/* boxes' camera looks down at the floor: up is not the camera's -y */
	struct synth_trajectory tr;
	traj("pan-30", "boxes", 1, &tr);
	assert_true(tr.up[2] < -0.1);
	assert_true(tr.up[1] < -0.5);
}

/* The shake: a few mm and tenths of a degree, 0.5-5 Hz, seeded, smooth. */
static void test_shake_bounds(void **state)
{
	(void)state;
	for (uint64_t seed = 1; seed <= 4; seed++) {
		struct synth_trajectory tr;
		traj("shake", "thin-pole", seed, &tr);
		const int n = 60 * 120; /* 60 s at 120 Hz */
		double s[6] = { 0 }, s2[6] = { 0 }, v2[6] = { 0 }, maxabs[6] = { 0 }, prev[6] = { 0 };
		for (int i = 0; i <= n; i++) {
			struct synth_pose p;
			synth_trajectory_pose(&tr, i / 120.0, &p);
			if (i == 0)
				assert_identity(&p);
			/* small angles: the rotation vector from the antisymmetric part */
			double x[6] = { p.t[0], p.t[1], p.t[2], 0.5 * (p.R[2][1] - p.R[1][2]),
					0.5 * (p.R[0][2] - p.R[2][0]), 0.5 * (p.R[1][0] - p.R[0][1]) };
			for (int c = 0; c < 6; c++) {
				s[c] += x[c];
				s2[c] += x[c] * x[c];
				maxabs[c] = fmax(maxabs[c], fabs(x[c]));
				if (i)
					v2[c] += (x[c] - prev[c]) * (x[c] - prev[c]) * 120.0 * 120.0;
				prev[c] = x[c];
			}
		}
		for (int c = 0; c < 6; c++) {
			double mean = s[c] / (n + 1), rms = sqrt(s2[c] / (n + 1) - mean * mean);
			double want = c < 3 ? SYNTH_SHAKE_RMS_M : SYNTH_SHAKE_RMS_DEG * DEG;
			/* 60 s of 6 sinusoids: the RMS within 15 % of the asked value */
			if (!(rms > 0.85 * want && rms < 1.15 * want))
				fail_msg("seed %d channel %d: rms %g, want %g", (int)seed, c, rms, want);
			assert_true(maxabs[c] < 8.0 * want);
			/* the velocity's RMS over the position's is 2 pi f_rms: within the band */
			double f = sqrt(v2[c] / n) / rms / (2.0 * M_PI);
			assert_true(f > SYNTH_SHAKE_F_MIN && f < SYNTH_SHAKE_F_MAX);
		}
	}
	/* seeded: the same seed the same path, another seed another */
	struct synth_trajectory a, b, c;
	traj("shake", "thin-pole", 7, &a);
	traj("shake", "thin-pole", 7, &b);
	traj("shake", "thin-pole", 8, &c);
	struct synth_pose pa, pb, pc;
	synth_trajectory_pose(&a, 0.3, &pa);
	synth_trajectory_pose(&b, 0.3, &pb);
	synth_trajectory_pose(&c, 0.3, &pc);
	assert_memory_equal(&pa, &pb, sizeof pa);
	assert_true(fabs(pa.t[0] - pc.t[0]) > 1e-7);
}

/* Walk, sideways and turn: their speeds and geometry from the poses. */
static void test_walk_sideways_turn(void **state)
{
	(void)state;
	struct synth_trajectory tr;
	struct synth_pose p, q;
	traj("walk", "boxes", 1, &tr);
	synth_trajectory_pose(&tr, 1.0, &p); /* whole periods of bob and sway: exactly 1 m ahead */
	for (int j = 0; j < 3; j++)
		assert_true(fabs(p.t[j] - SYNTH_WALK_SPEED * tr.forward[j]) < 1e-9);
	assert_true(fabs(tr.forward[0] * tr.up[0] + tr.forward[1] * tr.up[1] + tr.forward[2] * tr.up[2]) < 1e-12);
	traj("sideways", "boxes", 1, &tr);
	synth_trajectory_pose(&tr, 1.0 / 30.0, &p);
	double d = sqrt(p.t[0] * p.t[0] + p.t[1] * p.t[1] + p.t[2] * p.t[2]);
	assert_true(fabs(d * 30.0 - SYNTH_SIDEWAYS_SPEED) < 1e-12);
	assert_true(p.t[0] > 0.0); /* to the right */
	traj("turn", "boxes", 1, &tr);
	/* constant rate once accelerated; the optical centre on a circle around the axis */
	synth_trajectory_pose(&tr, 0.5, &p);
	synth_trajectory_pose(&tr, 0.5 + 1.0 / 30.0, &q);
	assert_true(fabs(synth_rotation_angle(p.R, q.R) * 30.0 / DEG - SYNTH_TURN_RATE_DEG) < 1e-6);
	double r = 0.0;
	for (int j = 0; j < 3; j++)
		r += pow(q.t[j] + SYNTH_TURN_OFFSET * tr.forward[j], 2);
	assert_true(fabs(sqrt(r) - SYNTH_TURN_OFFSET) < 1e-12);
	struct dao_error err;
	assert_int_equal(synth_trajectory_init(&tr, "pan-0", NULL, 1, &err), -EINVAL);
	assert_non_null(strstr(err.message, "pan-RATE"));
	assert_int_equal(synth_trajectory_init(&tr, "fly", NULL, 1, &err), -EINVAL);
	assert_non_null(strstr(err.message, "still"));
}

/*
 * Stop and start: 60 deg/s about up until (stop) or from (start) the middle frame,
 * frames / 2, and not a fraction of a pair in between; the length as synth sets it.
 */
static void test_stop_start(void **state)
{
	(void)state;
	const int frames[3] = { 16, 9, 16 };
	const double fps[3] = { 30.0, 30.0, 15.0 };
	for (int k = 0; k < 6; k++) {
		struct synth_trajectory tr;
		const int stop = k < 3, n = frames[k % 3], mid = n / 2;
		traj(stop ? "stop" : "start", "boxes", 1, &tr);
		if (k % 3)
			synth_trajectory_set_length(&tr, n, fps[k % 3]);
		struct synth_pose a, b;
		synth_trajectory_pose(&tr, 0.0, &a);
		assert_identity(&a);
		for (int i = 0; i + 1 < n; i++) {
			synth_trajectory_pose(&tr, i / fps[k % 3], &a);
			synth_trajectory_pose(&tr, (i + 1) / fps[k % 3], &b);
			const double rate = synth_rotation_angle(a.R, b.R) * fps[k % 3] / DEG;
			const double want = (i < mid) == stop ? SYNTH_STOP_RATE_DEG : 0.0;
			if (!(fabs(rate - want) < 1e-6))
				fail_msg("%s, %d frames: pair %d-%d at %g deg/s, want %g", tr.name, n, i,
					 i + 1, rate, want);
			for (int j = 0; j < 3; j++) {
				assert_true(fabs(b.t[j]) < 1e-12);
				assert_true(fabs(b.R[j][0] * tr.up[0] + b.R[j][1] * tr.up[1] +
						 b.R[j][2] * tr.up[2] - tr.up[j]) < 1e-12);
			}
		}
		/* to the right, and by the whole half's turn */
		struct synth_pose first;
		synth_trajectory_pose(&tr, 0.0, &first);
		const double turned = synth_rotation_angle(first.R, b.R);
		assert_true(fabs(turned / DEG - SYNTH_STOP_RATE_DEG * (stop ? mid : n - 1 - mid) /
					     fps[k % 3]) < 1e-9);
		assert_true(b.R[0][2] * tr.right[0] + b.R[1][2] * tr.right[1] + b.R[2][2] * tr.right[2] >
			    0.0);
	}
}

/* Poses written as TUM lines are read back: rotations within 1e-9, positions within 1e-9 m. */
static void test_tum_round_trip(void **state)
{
	(void)state;
	char *buf = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&buf, &len);
	const char *names[4] = { "shake", "turn", "walk", "pan-60" };
	struct synth_pose want[40];
	fputs("# comment\n\n", f);
	for (int k = 0; k < 40; k++) {
		struct synth_trajectory tr;
		traj(names[k % 4], "room-corner", (uint64_t)k, &tr);
		synth_trajectory_pose(&tr, 0.1 * k + 0.7, &want[k]);
		/* also rotations past 90 degrees, where the quaternion's w is small */
		if (k % 4 == 3) {
			const double ax[3] = { 0.6, 0.0, 0.8 };
			synth_rotation(ax, 2.9 + 0.01 * k, want[k].R);
		}
		assert_int_equal(synth_pose_write(f, k / 30.0, &want[k]), 0);
	}
	fclose(f);
	struct synth_pose_list l;
	struct dao_error err;
	assert_int_equal(synth_poses_parse(buf, len, "mem", &l, &err), 0);
	assert_int_equal(l.count, 40);
	for (int k = 0; k < 40; k++) {
		assert_true(fabs(l.time[k] - k / 30.0) < 1e-6);
		assert_true(synth_rotation_angle(l.pose[k].R, want[k].R) < 1e-9);
		for (int j = 0; j < 3; j++)
			assert_true(fabs(l.pose[k].t[j] - want[k].t[j]) < 1e-9);
	}
	synth_pose_list_free(&l);
	free(buf);
}

static void expect_parse_error(const char *text, const char *needle)
{
	struct synth_pose_list l;
	struct dao_error err = { 0 };
	assert_int_not_equal(synth_poses_parse(text, strlen(text), "t.txt", &l, &err), 0);
	if (!strstr(err.message, needle))
		fail_msg("'%s' not in '%s'", needle, err.message);
	assert_null(l.pose);
	assert_int_equal(l.count, 0);
}

static void test_tum_errors(void **state)
{
	(void)state;
	expect_parse_error("0 0 0 0 0 0 0\n", "t.txt:1: expected 8");
	expect_parse_error("0 0 0 0 0 0 0 1 9\n", "more than 8");
	expect_parse_error("0 0 0 0 0 0 0 2\n", "norm 2");
	expect_parse_error("0 0 0 0 0 0 0 1\n0 0 0 0 0 0 0 1\n", "t.txt:2: timestamp");
	expect_parse_error("0 nan 0 0 0 0 0 1\n", "not finite");
	expect_parse_error("# only a comment\n", "no poses");
	expect_parse_error("0 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1e999\n", "t.txt:2");
	/* a NUL inside a line */
	struct synth_pose_list l;
	struct dao_error err;
	const char nul[] = "0 0 0 0\0 0 0 0 1\n";
	assert_int_equal(synth_poses_parse(nul, sizeof nul - 1, "t", &l, &err), -EINVAL);
	assert_non_null(strstr(err.message, "NUL"));
	/* a line without its newline at the end is read */
	assert_int_equal(synth_poses_parse("0 1 2 3 0 0 0 1", 15, "t", &l, &err), 0);
	assert_int_equal(l.count, 1);
	assert_true(l.pose[0].t[2] == 3.0);
	synth_pose_list_free(&l);
}

/*
 * A wall z = 2 (world), seen from a camera at t = (0.1, 0.2, -0.3) turned 10 degrees
 * about its y axis: the depth at a pixel is (2 - t_z) / (R d).z with d = ((u - cx)/fx,
 * (v - cy)/fy, 1), worked out by hand here.
 */
static void test_render_from_pose(void **state)
{
	(void)state;
	struct synth_scene s = { .name = "wall", .count = 1 };
	s.prims[0] = (struct synth_prim){ .kind = SYNTH_HALFSPACE, .c = { 0, 0, 2 }, .n = { 0, 0, -1 } };
	synth_prim_bound(&s.prims[0]);
	const double th = 10.0 * DEG, c = cos(th), sn = sin(th);
	struct synth_pose p = { .R = { { c, 0, sn }, { 0, 1, 0 }, { -sn, 0, c } }, .t = { 0.1, 0.2, -0.3 } };
	synth_scene_view_from(&s, &p);
	struct dao_camera cam;
	synth_default_camera(&cam);
	struct synth_image img;
	struct dao_error err;
	assert_int_equal(synth_render(&s, &cam, 0.5, 0, 1, &img, &err), 0);
	const int px[3][2] = { { 320, 240 }, { 100, 50 }, { 600, 400 } };
	for (int k = 0; k < 3; k++) {
		double x = (px[k][0] - cam.cx) / cam.fx;
		double want = 2.3 / (-sn * x + c); /* (R d).z = -sin(th) x + cos(th) */
		float got = img.depth[(size_t)px[k][1] * cam.width + (size_t)px[k][0]];
		if (!(fabs(got - want) < 1e-5))
			fail_msg("pixel (%d, %d): %.6f, want %.6f", px[k][0], px[k][1], got, want);
	}
	synth_image_free(&img);
}

/*
 * The sequence metrics on 4 x 2 frames with known answers: MAE, the band a moving
 * step swept in the last frames, the per-pixel std on static pixels, the change.
 */
static void test_sequence_metrics(void **state)
{
	(void)state;
	struct synth_seq_masks m;
	struct synth_seq_column col;
	assert_int_equal(synth_seq_masks_init(&m, 4, 2, 1), 0);
	assert_int_equal(synth_seq_column_init(&col, 4, 2), 0);
	/* the true depth: a step (1 m) moving right over a wall (2 m), one column a frame */
	const float truth[3][8] = { { 2, 2, 2, 2, 2, 2, 2, 2 },
				    { 1, 2, 2, 2, 1, 2, 2, 2 },
				    { 1, 1, 2, 2, 1, 1, 2, 2 } };
	const float depth[8] = { 2, 2, 2, 2, 2, 2, 2, 0 }; /* the last pixel has no input */
	const float gt[8] = { 0.5f, 0.5f, 0.5f, 0.5f, 1, 1, 1, 1 };
	/* AO: 0.4, 0.6, 0.4 on pixels 0, 2, 3; 1 on the wall but once (0.7) */
	const float ao[3][8] = { { 0.4f, 0.5f, 0.4f, 0.4f, 1, 1, 1, 1 },
				 { 0.6f, 0.5f, 0.6f, 0.6f, 1, 1, 1, 1 },
				 { 0.4f, 0.5f, 0.4f, 0.4f, 0.7f, 1, 1, 1 } };
	struct synth_seq_frame r[3];
	for (int k = 0; k < 3; k++) {
		synth_seq_masks_add(&m, depth, truth[k]);
		synth_seq_column_add(&col, &m, ao[k], gt, depth, &r[k]);
	}
	/* frame 0: |0.4-0.5| x 3 + 0 over 7 valid pixels */
	assert_true(fabs(r[0].mae - 0.3 / 7) < 1e-6);
	assert_int_equal(r[0].trail_count, 0);
	/* frame 1: the step covered column 0 (pixels 0 and 4) */
	assert_int_equal(r[1].trail_count, 2);
	assert_true(fabs(r[1].trail_mae - 0.05) < 1e-6);
	/* frame 2: columns 0 and 1 in the band (swept within the last 4 frames) */
	assert_int_equal(r[2].trail_count, 4);
	assert_true(fabs(r[2].trail_mae - (0.1 + 0 + 0.3 + 0) / 4) < 1e-6);
	/* static: columns 2 and 3 with input in every frame: pixels 2, 3, 6 */
	long n;
	double fl = synth_seq_flicker(&col, &m, &n);
	assert_int_equal(n, 3);
	/* 0.4, 0.6, 0.4: mean 0.4667, population std 0.0943; pixel 6: 0 */
	const double want = (2 * sqrt(2.0 / 3.0 * 1.0 / 3.0) * 0.2 + 0.0) / 3.0;
	assert_true(fabs(fl - want) < 1e-6);
	/* change: frames 0->1 and 1->2 over 7 pixels with input: (3 x 0.2 + 0) x 2 + 0.3 */
	assert_true(fabs(synth_seq_change(&col) - (1.2 + 0.3) / 14.0) < 1e-6);
	synth_seq_column_free(&col);
	synth_seq_masks_free(&m);
}

/*
 * The tracked flicker: a wall at 2 m, the camera moving right by exactly one pixel's
 * footprint (2 / fx) a frame, the AO pattern moving one pixel left with the wall: zero
 * per surface point, not per pixel; with a still camera, the per-pixel value.
 */
static void test_tracked_flicker(void **state)
{
	(void)state;
	enum { W = 8, H = 4, F = 3 };
	const double fx = 10.0, cx = 3.5, cy = 1.5;
	struct synth_seq_masks m;
	struct synth_seq_track t;
	struct synth_seq_column moving, still;
	assert_int_equal(synth_seq_masks_init(&m, W, H, 1), 0);
	assert_int_equal(synth_seq_track_init(&t, W, H, fx, fx, cx, cy), 0);
	assert_int_equal(synth_seq_column_init(&moving, W, H), 0);
	assert_int_equal(synth_seq_column_init(&still, W, H), 0);
	float depth[W * H], ao[W * H];
	for (int i = 0; i < W * H; i++)
		depth[i] = 2.0f;
	for (int k = 0; k < F; k++) {
		struct synth_pose p = { .R = { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } },
					.t = { k * 2.0 / fx, 0, 0 } };
		for (int y = 0; y < H; y++)
			for (int x = 0; x < W; x++)
				ao[y * W + x] = 0.1f * (float)((x + k) % 5); /* the wall's pattern */
		synth_seq_masks_add(&m, depth, depth);
		synth_seq_track_frame(&t, depth, &p);
		synth_seq_column_add(&moving, &m, ao, NULL, depth, NULL);
		synth_seq_column_track(&moving, &t, ao, depth, depth, &p);
	}
	long n;
	assert_true(synth_seq_flicker_tracked(&moving, &t, &n) < 1e-7);
	assert_int_equal(n, (W - 2) * H); /* the two right columns leave the image */
	assert_true(synth_seq_flicker(&moving, &m, &n) > 0.05);
	/* still: tracked = per pixel */
	struct synth_seq_track ts;
	struct synth_seq_masks ms;
	assert_int_equal(synth_seq_masks_init(&ms, W, H, 1), 0);
	assert_int_equal(synth_seq_track_init(&ts, W, H, fx, fx, cx, cy), 0);
	const struct synth_pose id = { .R = { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } } };
	for (int k = 0; k < F; k++) {
		for (int i = 0; i < W * H; i++)
			ao[i] = 0.5f + 0.1f * (float)(((i + 1) * (k + 2)) % 3);
		synth_seq_masks_add(&ms, depth, depth);
		synth_seq_track_frame(&ts, depth, &id);
		synth_seq_column_add(&still, &ms, ao, NULL, depth, NULL);
		synth_seq_column_track(&still, &ts, ao, depth, depth, &id);
	}
	long n2;
	double a = synth_seq_flicker_tracked(&still, &ts, &n), b = synth_seq_flicker(&still, &ms, &n2);
	assert_int_equal(n, W * H);
	assert_int_equal(n2, W * H);
	assert_true(a > 0.01 && fabs(a - b) < 1e-9);
	synth_seq_column_free(&moving);
	synth_seq_column_free(&still);
	synth_seq_track_free(&t);
	synth_seq_track_free(&ts);
	synth_seq_masks_free(&m);
	synth_seq_masks_free(&ms);
}

/*
 * A wall whose AO rises linearly across it, seen by a camera moving 0.3 px a
 * frame to the right and 0.15 px down: the tracked flicker samples each point
 * between pixels (bilinear, exact on a linear pattern), so a still surface does
 * not flicker, from frame 0 or from frame 2 (a `skip` column); the nearest
 * pixel would jump by up to half a pixel (its std here about 0.003).
 */
static void test_tracked_flicker_subpixel(void **state)
{
	(void)state;
	enum { W = 16, H = 6, F = 6 };
	const double fx = 10.0, cx = 7.5, cy = 2.5, z = 2.0, sx = 0.3, sy = 0.15;
	struct synth_seq_masks m;
	struct synth_seq_track t;
	struct synth_seq_column c, late;
	assert_int_equal(synth_seq_masks_init(&m, W, H, 1), 0);
	assert_int_equal(synth_seq_track_init(&t, W, H, fx, fx, cx, cy), 0);
	assert_int_equal(synth_seq_column_init(&c, W, H), 0);
	assert_int_equal(synth_seq_column_init(&late, W, H), 0);
	late.skip = 2;
	float depth[W * H], ao[W * H];
	for (int i = 0; i < W * H; i++)
		depth[i] = (float)z;
	for (int k = 0; k < F; k++) {
		/* pixel (x, y) sees the wall's point (x + sx k, y + sy k) of frame 0 */
		struct synth_pose p = { .R = { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } },
					.t = { k * sx * z / fx, k * sy * z / fx, 0 } };
		for (int y = 0; y < H; y++)
			for (int x = 0; x < W; x++)
				ao[y * W + x] = (float)(0.2 + 0.01 * (x + sx * k) + 0.02 * (y + sy * k));
		synth_seq_masks_add(&m, depth, depth);
		synth_seq_track_frame(&t, depth, &p);
		synth_seq_column_add(&c, &m, ao, NULL, depth, NULL);
		synth_seq_column_track(&c, &t, ao, depth, depth, &p);
		synth_seq_column_add(&late, &m, ao, NULL, depth, NULL);
		synth_seq_column_track(&late, &t, ao, depth, depth, &p);
	}
	long n, n2;
	const double fl = synth_seq_flicker_tracked(&c, &t, &n);
	const double fl2 = synth_seq_flicker_tracked(&late, &t, &n2);
	/* the points whose four pixels stay in the image: x - 0.3 k >= 0 and
	 * y - 0.15 k >= 0 for k <= 5 (x >= 2, y >= 1); from frame 2, k >= 2 too */
	assert_int_equal(n, (W - 2) * (H - 1));
	assert_int_equal(n2, (W - 2) * (H - 1));
	assert_true(fl < 1e-6 && fl2 < 1e-6);
	synth_seq_column_free(&c);
	synth_seq_column_free(&late);
	synth_seq_track_free(&t);
	synth_seq_masks_free(&m);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_pan_rate),
		cmocka_unit_test(test_shake_bounds),
		cmocka_unit_test(test_walk_sideways_turn),
		cmocka_unit_test(test_stop_start),
		cmocka_unit_test(test_tum_round_trip),
		cmocka_unit_test(test_tum_errors),
		cmocka_unit_test(test_render_from_pose),
		cmocka_unit_test(test_sequence_metrics),
		cmocka_unit_test(test_tracked_flicker),
		cmocka_unit_test(test_tracked_flicker_subpixel),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
