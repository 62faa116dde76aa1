/* SPDX-License-Identifier: MIT */
/*
 * The AO history (the temporal accumulation's last output and the depth it
 * was computed for) carried into the current view by the camera's motion,
 * as temporal anti-aliasing does: every current pixel with depth is placed
 * in 3-D, moved into the previous camera by the accepted motion, and its
 * history is read where it lands there (a backward lookup: the current
 * depth is known at every pixel the AO is computed for).
 *
 * The read is bilinear over the four previous pixels around the landing
 * point, each used only where its history depth agrees with the point's
 * depth in the previous view within `reject` of it (the temporal
 * accumulation's own disocclusion test), the weights renormalised over the
 * taps that agree.  A landing point within 1/1000 px of a pixel centre takes
 * that pixel alone, so the identity motion copies the history bit for bit.
 * A pixel without depth, landing outside the previous image or behind its
 * camera, or whose taps all disagree (a disocclusion), gets no history
 * (depth 0): the accumulation starts over there from the current AO.
 *
 * The history depth written is that of the history's surface point in the
 * current view, so the accumulation's test |z - hz| <= reject z runs on it
 * unchanged.
 */
#ifndef DAO_MOTION_AO_REPROJECT_H
#define DAO_MOTION_AO_REPROJECT_H

#include <depthao/camera.h>

#include "motion/icp.h"

/*
 * z: the current frame's depth (m, 0 = none); hist_ao, hist_z: the previous
 * frame's AO history and its depth (0 = no history); cur_to_prev: the motion
 * (motion/icp.h's convention, p_prev = R p_cur + t).  Writes rows y0..y1-1
 * of ao_out and z_out (cam->width x cam->height planes, not aliasing the
 * inputs; rows are independent, so bands can run on several threads).
 * No allocation.
 */
void dao_ao_history_reproject_rows(const struct dao_camera *cam,
				   const struct dao_pose *cur_to_prev, float reject, const float *z,
				   const float *hist_ao, const float *hist_z, float *ao_out,
				   float *z_out, int y0, int y1);

/* The same per instruction set (motion/ao_reproject_simd.inc.c: floats, within
 * the bound tests/pipeline/test_ao_history.c states of the reference above). */
typedef void (*dao_ao_reproject_fn)(const struct dao_camera *cam,
				    const struct dao_pose *cur_to_prev, float reject,
				    const float *z, const float *hist_ao, const float *hist_z,
				    float *ao_out, float *z_out, int y0, int y1);
#define DAO_AO_REPROJECT_PROTO(isa)                                                           \
	void dao_ao_history_reproject_rows_##isa(                                             \
		const struct dao_camera *cam, const struct dao_pose *cur_to_prev, float reject, \
		const float *z, const float *hist_ao, const float *hist_z, float *ao_out,      \
		float *z_out, int y0, int y1)
DAO_AO_REPROJECT_PROTO(generic);
DAO_AO_REPROJECT_PROTO(sse41);
DAO_AO_REPROJECT_PROTO(avx2);
DAO_AO_REPROJECT_PROTO(avx512);

#endif
