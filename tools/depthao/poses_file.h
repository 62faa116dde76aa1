/* SPDX-License-Identifier: MIT */
/*
 * depthao process --poses: a camera trajectory in the TUM RGB-D benchmark's
 * format ("timestamp tx ty tz qx qy qz qw" a line, '#' comments), the pose
 * of the camera's optical frame in a fixed world frame, looked up at a
 * frame's timestamp (interpolated between neighbours: linear in the
 * translation, slerp in the rotation: dao_pose_interpolate()).
 */
#ifndef DAO_TOOLS_POSES_FILE_H
#define DAO_TOOLS_POSES_FILE_H

#include <stddef.h>

#include <depthao/error.h>

#include "synth/trajectory.h"

/* Poses more than this apart in time (s) are not interpolated between. */
#define POSES_MAX_GAP 0.25
/* A timestamp within this (s) of a pose takes it as it is. */
#define POSES_EXACT 1e-6

struct poses_file {
	struct synth_pose_list list; /* read by tools/synth/trajectory_file.c */
	double *q;                   /* its rotations as quaternions x, y, z, w */
};

/* 0, or a negative errno with what is wrong (and where) in err. */
int poses_file_read(const char *path, struct poses_file *pf, struct dao_error *err);
void poses_file_free(struct poses_file *pf);

/* 1 and the pose at time t (q = x, y, z, w; p = translation), or 0 where the
 * file has none (outside it, or between poses more than POSES_MAX_GAP apart). */
int poses_file_at(const struct poses_file *pf, double t, double q[4], double p[3]);

/* The timestamp of a frame file named like the TUM benchmark's
 * ("1305031102.160407.png": seconds with a fraction): 1 and *t, else 0. */
int poses_name_time(const char *name, double *t);

#endif
