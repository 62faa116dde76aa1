/* SPDX-License-Identifier: MIT */
/*
 * The temporal depth filter's history (pipeline/temporal_depth.h: 1/z, the
 * count of samples in it, the frames since the pixel had data) carried into
 * the current view by the camera's motion.
 *
 * A forward splat with a depth test: every previous pixel with history is
 * placed in 3-D at its filtered depth, moved into the current camera and
 * written to the nearest pixel it projects to; where two land on one pixel
 * the nearer wins (the larger 1/z; on a tie the first in row order).  A
 * backward lookup would need the current depth at every pixel, which the
 * history exists to fill where the sensor has none.  Pixels nothing lands on
 * (disocclusions, the edge the camera turned towards, cracks where the view
 * magnifies) have no history and start over from their sample, as the
 * filter does for a new pixel.
 */
#ifndef DAO_MOTION_REPROJECT_H
#define DAO_MOTION_REPROJECT_H

#include <stdint.h>

#include <depthao/camera.h>

#include "motion/icp.h"

/*
 * hist, count, age: the previous frame's history (cam->width x cam->height);
 * cur_to_prev: the motion (motion/icp.h's convention, p_prev = R p_cur + t).
 * Writes the history as the current view sees it to hist_out, count_out,
 * age_out (no pixel without history: count 0, 1/z 0, age 255).  `scratch`
 * holds 2 w h int32 (where each pixel lands).  No allocation; the outputs
 * must not alias the inputs.  A pixel goes to the nearest pixel, a tie
 * (u + 0.5 whole) to the right and down.
 */
void dao_history_reproject(const struct dao_camera *cam, const struct dao_pose *cur_to_prev,
			   const float *hist, const uint8_t *count, const uint8_t *age,
			   float *hist_out, uint8_t *count_out, uint8_t *age_out, int32_t *scratch);

#endif
