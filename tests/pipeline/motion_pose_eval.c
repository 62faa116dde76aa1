/* SPDX-License-Identifier: MIT */
/*
 * motion-pose-eval: the camera-motion estimate (depth-temporal-motion=icp)
 * against the true poses of a `depthao synth --trajectory` sequence.
 *
 *   motion-pose-eval DIR [simd] [threads] [frames] [seeded-coarse seeded-fine]
 *
 * DIR holds depth/NNNN.png, depth/camera.json and poses.txt.  The frames run
 * in order through a context with the streams' defaults (depth-temporal 0.8)
 * and depth-temporal-motion=icp, as the CLI would; after every frame the
 * estimate (dao_context_motion) is compared with the truth's relative pose
 * p_prev = R_prev^T (R_cur p + t_cur - t_prev).  Prints one line per frame
 * and a summary line "worst ANGLE deg DIST mm" over the frames with an
 * accepted estimate, how many were refused, and the worst over all frames.  A measuring tool, not a
 * test (docs/perf/icp2.md).  simd: 0 auto, 1 reference, 4 avx2, 5 avx512.
 * seeded-coarse, seeded-fine: the steps of an estimate a prior seeds
 * (dao_icp_setup.seeded_*; 4 3 gives every estimate the unseeded counts), set by
 * linking with -Wl,--wrap=dao_icp_estimate: the library unchanged but for
 * them (docs/perf/icp-seeded.md).
 * With DAO_EVAL_ROTATION_SEED=B in the environment, depth-temporal-motion is
 * source+icp and every frame is given the true rotation (no translation), as
 * an IMU gives it through a recording's pose_topic, with a gyro bias of B
 * degrees a second about the axis (1, 2, 3) (0: an ideal IMU); with
 * DAO_EVAL_SEED_LAST_T as well, the seed's translation is the last accepted
 * estimate's instead of the poses' (docs/perf/imu.md: not kept).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/camera.h>
#include <depthao/context.h>
#include <depthao/params.h>
#include <depthao/png.h>
#include <depthao/pose.h>

#include "motion/icp.h"
#include "tf/rigid.h"

static int seeded_steps[2]; /* coarse, fine; 0: the setup's */

void __real_dao_icp_estimate(const struct dao_icp_setup *s, const struct dao_camera *cam,
			     const float *prev_inv, const uint8_t *prev_count, const float *cur_z,
			     const struct dao_pose *prior, float *scratch,
			     struct dao_icp_result *out);
void __wrap_dao_icp_estimate(const struct dao_icp_setup *s, const struct dao_camera *cam,
			     const float *prev_inv, const uint8_t *prev_count, const float *cur_z,
			     const struct dao_pose *prior, float *scratch,
			     struct dao_icp_result *out);

/* the context's call, with the seeded steps asked for */
void __wrap_dao_icp_estimate(const struct dao_icp_setup *s, const struct dao_camera *cam,
			     const float *prev_inv, const uint8_t *prev_count, const float *cur_z,
			     const struct dao_pose *prior, float *scratch,
			     struct dao_icp_result *out)
{
	struct dao_icp_setup t = *s;
	if (seeded_steps[0] > 0) {
		t.seeded_coarse_iterations = seeded_steps[0];
		t.seeded_iterations = seeded_steps[1];
	}
	/* DAO_EVAL_SEED_LAST_T: a seed's translation replaced by the last accepted
	 * estimate's (the rotation from the poses given, the translation as icp's prior) */
	static struct dao_pose last;
	static int have_last;
	struct dao_pose seed;
	if (prior && have_last && getenv("DAO_EVAL_SEED_LAST_T")) {
		seed = *prior;
		memcpy(seed.t, last.t, sizeof seed.t);
		prior = &seed;
	}
	__real_dao_icp_estimate(&t, cam, prev_inv, prev_count, cur_z, prior, scratch, out);
	have_last = out->valid;
	last = out->pose;
}

struct pose {
	double r[9], t[3];
};

static int read_poses(const char *path, struct pose *out, int cap)
{
	FILE *f = fopen(path, "r");
	if (!f)
		return -1;
	char line[512];
	int n = 0;
	while (n < cap && fgets(line, sizeof line, f)) {
		double ts, t[3], q[4];
		if (line[0] == '#')
			continue;
		if (sscanf(line, "%lf %lf %lf %lf %lf %lf %lf %lf", &ts, &t[0], &t[1], &t[2], &q[0],
			   &q[1], &q[2], &q[3]) != 8)
			continue;
		dao_pose_quat_to_matrix(q, out[n].r);
		memcpy(out[n].t, t, sizeof t);
		n++;
	}
	fclose(f);
	return n;
}

static int read_camera(const char *path, struct dao_camera *cam)
{
	FILE *f = fopen(path, "r");
	if (!f)
		return -1;
	char buf[8192];
	const size_t n = fread(buf, 1, sizeof buf - 1, f);
	fclose(f);
	buf[n] = 0;
	const char *w = strstr(buf, "\"width\""), *h = strstr(buf, "\"height\"");
	const char *k = strstr(buf, "\"intrinsic_matrix\"");
	double m[9];
	unsigned width, height;
	if (!w || !h || !k || sscanf(strchr(w, ':') + 1, "%u", &width) != 1 ||
	    sscanf(strchr(h, ':') + 1, "%u", &height) != 1)
		return -1;
	k = strchr(k, '[');
	if (!k || sscanf(k + 1, "%lf , %lf , %lf , %lf , %lf , %lf , %lf , %lf , %lf", &m[0], &m[1],
			 &m[2], &m[3], &m[4], &m[5], &m[6], &m[7], &m[8]) != 9)
		return -1;
	struct dao_error err;
	return dao_camera_from_intrinsics(cam, width, height, m[0], m[4], m[6], m[7], &err);
}

/* truth: p_prev = Rp^T (Rc p + tc - tp); error = truth^-1 est */
static void pose_error(const struct pose *prev, const struct pose *cur,
		       const struct dao_motion_info *mi, double *deg, double *mm)
{
	struct pose tr;
	for (int i = 0; i < 3; i++) {
		for (int j = 0; j < 3; j++) {
			double s = 0;
			for (int k = 0; k < 3; k++)
				s += prev->r[k * 3 + i] * cur->r[k * 3 + j];
			tr.r[i * 3 + j] = s;
		}
		double s = 0;
		for (int k = 0; k < 3; k++)
			s += prev->r[k * 3 + i] * (cur->t[k] - prev->t[k]);
		tr.t[i] = s;
	}
	double e[9], et[3];
	for (int i = 0; i < 3; i++) {
		for (int j = 0; j < 3; j++) {
			double s = 0;
			for (int k = 0; k < 3; k++)
				s += tr.r[k * 3 + i] * mi->rotation[k * 3 + j];
			e[i * 3 + j] = s;
		}
		double s = 0;
		for (int k = 0; k < 3; k++)
			s += tr.r[k * 3 + i] * (mi->translation[k] - tr.t[k]);
		et[i] = s;
	}
	const double c = 0.5 * (e[0] + e[4] + e[8] - 1.0);
	const double sn = 0.5 * sqrt((e[7] - e[5]) * (e[7] - e[5]) + (e[2] - e[6]) * (e[2] - e[6]) +
				     (e[3] - e[1]) * (e[3] - e[1]));
	*deg = atan2(sn, c) * 57.29577951308232;
	*mm = sqrt(et[0] * et[0] + et[1] * et[1] + et[2] * et[2]) * 1000.0;
}

int main(int argc, char **argv)
{
	if (argc < 2) {
		fprintf(stderr, "usage: motion-pose-eval DIR [simd] [threads] [frames]\n");
		return 2;
	}
	char path[4096];
	struct dao_camera cam;
	snprintf(path, sizeof path, "%s/depth/camera.json", argv[1]);
	if (read_camera(path, &cam)) {
		fprintf(stderr, "motion-pose-eval: cannot read %s\n", path);
		return 1;
	}
	static struct pose poses[1024];
	snprintf(path, sizeof path, "%s/poses.txt", argv[1]);
	const int np = read_poses(path, poses, 1024);
	if (np < 2) {
		fprintf(stderr, "motion-pose-eval: cannot read %s\n", path);
		return 1;
	}
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	dao_params_stream_defaults(&p);
	p.depth_temporal_motion = DAO_DEPTH_MOTION_ICP;
	p.simd = argc > 2 ? atoi(argv[2]) : 0;
	p.threads = argc > 3 ? atoi(argv[3]) : 0;
	const int frames = argc > 4 && atoi(argv[4]) > 0 && atoi(argv[4]) < np ? atoi(argv[4]) : np;
	if (argc > 6) {
		seeded_steps[0] = atoi(argv[5]), seeded_steps[1] = atoi(argv[6]);
		if (seeded_steps[0] < 1 || seeded_steps[1] < 1) {
			fprintf(stderr, "motion-pose-eval: the seeded steps are >= 1\n");
			return 2;
		}
	}
	const char *seed = getenv("DAO_EVAL_ROTATION_SEED");
	const double bias = seed ? atof(seed) * 0.017453292519943295 : 0.0;
	if (seed)
		p.depth_temporal_motion = DAO_DEPTH_MOTION_SOURCE_ICP;
	struct dao_context *ctx;
	struct dao_error err;
	if (dao_context_create(&ctx, &cam, &p, &err)) {
		fprintf(stderr, "motion-pose-eval: %s\n", err.message);
		return 1;
	}
	double all_a = 0, all_d = 0, worst_a = 0, worst_d = 0, sum_a = 0, sum_d = 0;
	int accepted = 0, refused = 0;
	for (int i = 0; i < frames; i++) {
		struct dao_frame f;
		snprintf(path, sizeof path, "%s/depth/%04d.png", argv[1], i);
		if (seed) { /* the true rotation after the bias's drift over i / 30 s */
			const double zero[3] = { 0.0, 0.0, 0.0 }, n = sqrt(14.0);
			const double h = 0.5 * bias * (double)i / 30.0;
			struct dao_rigid truth = { .t = { 0.0 } }, drift = {
				.q = { sin(h) / n, 2.0 * sin(h) / n, 3.0 * sin(h) / n, cos(h) } }, seen;
			dao_pose_matrix_to_quat(poses[i].r, truth.q);
			dao_rigid_compose(&truth, &drift, &seen);
			if (dao_context_set_pose(ctx, seen.q, zero, &err)) {
				fprintf(stderr, "motion-pose-eval: %s\n", err.message);
				return 1;
			}
		}
		if (dao_png_read_depth(path, 0.001f, &f, &err) ||
		    dao_context_process(ctx, &f, NULL, (uint64_t)i, NULL, &err)) {
			fprintf(stderr, "motion-pose-eval: %s: %s\n", path, err.message);
			return 1;
		}
		dao_frame_free(&f);
		if (i == 0)
			continue;
		struct dao_motion_info mi = DAO_MOTION_INFO_INIT;
		dao_context_motion(ctx, &mi);
		double a, d;
		pose_error(&poses[i - 1], &poses[i], &mi, &a, &d);
		const int ok = mi.state == DAO_MOTION_APPLIED || mi.state == DAO_MOTION_STILL;
		const double *R = mi.rotation;
		const double ang = acos(fmin(1.0, fmax(-1.0, 0.5 * (R[0] + R[4] + R[8] - 1.0))));
		printf("frame %2d: state %d reason %d error %.4f deg %.3f mm (estimate %.3f deg "
		       "%.1f mm), %d/%d pairs, rms %.2f mm, cond %.3g, %d steps\n",
		       i, mi.state, mi.reason, a, d, ang * 57.29577951308232,
		       1e3 * sqrt(mi.translation[0] * mi.translation[0] +
				  mi.translation[1] * mi.translation[1] +
				  mi.translation[2] * mi.translation[2]),
		       mi.pairs, mi.points, mi.rms * 1e3, mi.condition, mi.iterations);
		all_a = fmax(all_a, a), all_d = fmax(all_d, d);
		if (!ok) {
			refused++;
			continue;
		}
		accepted++;
		worst_a = fmax(worst_a, a), worst_d = fmax(worst_d, d);
		sum_a += a, sum_d += d;
	}
	printf("worst %.4f deg %.3f mm mean %.4f deg %.3f mm accepted %d refused %d "
	       "(all frames: worst %.4f deg %.3f mm)\n", worst_a, worst_d,
	       accepted ? sum_a / accepted : 0.0, accepted ? sum_d / accepted : 0.0, accepted,
	       refused, all_a, all_d);
	dao_context_destroy(ctx);
	return 0;
}
