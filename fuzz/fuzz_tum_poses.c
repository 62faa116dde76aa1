/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target: the input is a TUM trajectory file (`timestamp tx ty tz
 * qx qy qz qw` a line), as depthao eval --sequence reads poses.txt
 * (tools/synth/trajectory_file.c).  Any outcome is fine except a crash, a
 * sanitizer report, an error without a message, or a pose list that breaks
 * the parser's promises: finite values, increasing timestamps, rotations
 * that are orthonormal.
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "synth/trajectory.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct synth_pose_list l;
	struct dao_error err = { 0 };
	if (synth_poses_parse((const char *)data, size, "fuzz", &l, &err)) {
		if (!err.message[0] || l.count || l.pose || l.time)
			abort();
		return 0;
	}
	if (l.count == 0)
		abort();
	for (size_t k = 0; k < l.count; k++) {
		if (!isfinite(l.time[k]) || (k && !(l.time[k] > l.time[k - 1])))
			abort();
		for (int i = 0; i < 3; i++) {
			if (!isfinite(l.pose[k].t[i]))
				abort();
			double n = 0.0;
			for (int j = 0; j < 3; j++)
				n += l.pose[k].R[i][j] * l.pose[k].R[i][j];
			if (!(fabs(n - 1.0) < 1e-9))
				abort();
		}
	}
	synth_pose_list_free(&l);
	return 0;
}
