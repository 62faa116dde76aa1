/* SPDX-License-Identifier: MIT */
/*
 * depthao synth --trajectory: what a moving camera's sequence writes beside
 * its frames (issue #37): the true pose per frame (TUM format, poses.txt) and
 * the true depth per frame (depth_gt/NNNN.png, millimetres).
 */
#ifndef DAO_TOOLS_SYNTH_MOTION_H
#define DAO_TOOLS_SYNTH_MOTION_H

#include <depthao/error.h>

#include "synth/synth.h"
#include "synth/trajectory.h"

/* "tune" for even scene variants, "heldout" for odd ones (the evaluation families). */
const char *synth_motion_set(int variant);

/* The shake's seed of a sequence: from the noise seed and the scene variant. */
uint64_t synth_motion_seed(uint64_t seed, int variant);

/*
 * Writes `frames` poses at `fps` to `path` in TUM format, with a header
 * naming the trajectory, scene, variant and family.  0, or 1 after a message.
 */
int synth_motion_write_poses(const char *path, const struct synth_trajectory *tr, int frames,
			     double fps, const char *scene, int variant);

/* The clean render's depth of frame i as DIR/NNNN.png (mm, 0 = nothing; 65535 caps). */
int synth_motion_write_depth_gt(const char *dir, int i, const struct synth_image *img,
				struct dao_error *err);

#endif
