/* SPDX-License-Identifier: MIT */
/*
 * depthao process --pose-out FILE: the camera pose of every frame as
 * the temporal depth filter followed it (depth-temporal-motion icp, source,
 * source+icp), accumulated from frame to frame (the context's track,
 * dao_context_pose_track), one line a frame in the TUM RGB-D trajectory format
 * that `depthao synth --trajectory` writes as poses.txt.
 */
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include <depthao/depthao.h>

#include "process.h"

int process_pose_open(const struct process_options *o, struct run_state *st)
{
	if (!o->pose_out)
		return 0;
	st->pose = fopen(o->pose_out, "w");
	if (!st->pose) {
		fprintf(stderr, "depthao: cannot write --pose-out '%s': %s\n", o->pose_out,
			strerror(errno));
		return 1;
	}
	fprintf(st->pose, "# depthao process: the camera pose, the frame-to-frame motions the "
		"temporal depth filter followed composed (depth-temporal-motion icp, source or "
		"source+icp); camera to world, world = the optical frame of the first frame\n"
		"# timestamp tx ty tz qx qy qz qw\n");
	return 0;
}

int process_pose_write(const struct process_options *o, struct run_state *st,
		       const struct dao_frame *depth, uint64_t n)
{
	if (!st->pose)
		return 0;
	struct dao_pose_track pt = DAO_POSE_TRACK_INIT;
	dao_context_pose_track(st->ctx, &pt);
	if (n == 0)
		st->pose_t0 = depth->timestamp_ns;
	/* the recording's clock from its first frame, else the frame number at --pose-fps */
	const double time = depth->timestamp_ns && st->pose_t0
				    ? (double)(depth->timestamp_ns - st->pose_t0) * 1e-9
				    : (double)n / o->pose_fps;
	double q[4];
	const double *t = pt.translation;
	dao_pose_matrix_to_quat(pt.rotation, q);
	if (fprintf(st->pose, "%.6f %.9f %.9f %.9f %.12f %.12f %.12f %.12f\n", time, t[0], t[1],
		    t[2], q[0], q[1], q[2], q[3]) < 0) {
		fprintf(stderr, "depthao: cannot write --pose-out '%s': %s\n", o->pose_out,
			strerror(errno));
		return 1;
	}
	return 0;
}

int process_pose_close(const struct process_options *o, struct run_state *st, int status)
{
	if (!st->pose)
		return status;
	if (fclose(st->pose) && !status) {
		fprintf(stderr, "depthao: cannot write --pose-out '%s': %s\n", o->pose_out,
			strerror(errno));
		status = 1;
	}
	st->pose = NULL;
	return status;
}
