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
 *
 * Two passes: where each pixel lands (a kernel per instruction set, the
 * reference below its oracle: the same float operations, so the same
 * pixels to the bit, tests/pipeline/test_reproject.c), then the splat by
 * bands of output rows, each band visiting the source pixels in row order
 * (only the source rows whose landing rows reach the band), so that the
 * result does not depend on the bands or the threads.
 */
#ifndef DAO_MOTION_REPROJECT_H
#define DAO_MOTION_REPROJECT_H

#include <stdint.h>

#include <depthao/camera.h>

#include "motion/icp.h"

struct dao_pool;

/* The landing pass's inputs and outputs (prev -> cur: R, T; pixel -> ray
 * x ax + bx; u = x' / ax - ub with ub = bx / ax, likewise v). */
struct dao_reproject_land {
	const float *hist;     /* 1/z (0 = none) */
	const uint8_t *count;  /* 0 = no history */
	int32_t *dest;         /* where each pixel lands, y w + x, or -1 */
	float *zinv;           /* its 1/z in the current view (where dest >= 0) */
	int32_t *rows;         /* per source row: its lowest and highest landing row
				* (h and -1: none) */
	int w, h;
	float R[9], T[3];
	float ax, bx, ay, by, inv_ax, inv_ay, ub, vb;
};

/* source rows [y0, y1) */
typedef void (*dao_reproject_land_fn)(const struct dao_reproject_land *s, int y0, int y1);

void dao_reproject_land_ref(const struct dao_reproject_land *s, int y0, int y1);
#define DAO_REPROJECT_LAND_PROTO(isa)                                                         \
	void dao_reproject_land_##isa(const struct dao_reproject_land *s, int y0, int y1)
DAO_REPROJECT_LAND_PROTO(generic);
DAO_REPROJECT_LAND_PROTO(sse41);
DAO_REPROJECT_LAND_PROTO(avx2);
DAO_REPROJECT_LAND_PROTO(avx512);

/* int32 of the scratch dao_history_reproject needs: 2 w h + 2 h */
size_t dao_history_reproject_scratch(int w, int h);

/*
 * hist, count, age: the previous frame's history (cam->width x cam->height);
 * cur_to_prev: the motion (motion/icp.h's convention, p_prev = R p_cur + t).
 * Writes the history as the current view sees it to hist_out, count_out,
 * age_out (no pixel without history: count 0, 1/z 0, age 255).  `scratch`
 * holds dao_history_reproject_scratch() int32.  No allocation; the outputs
 * must not alias the inputs.  A pixel goes to the nearest pixel, a tie
 * (u + 0.5 whole) to the right and down.  `land`: the landing kernel (NULL:
 * the reference); `pool`: the threads of both passes (NULL: the caller's);
 * neither changes the result.
 */
void dao_history_reproject(const struct dao_camera *cam, const struct dao_pose *cur_to_prev,
			   const float *hist, const uint8_t *count, const uint8_t *age,
			   float *hist_out, uint8_t *count_out, uint8_t *age_out, int32_t *scratch,
			   dao_reproject_land_fn land, struct dao_pool *pool);

#endif
