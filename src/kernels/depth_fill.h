/* SPDX-License-Identifier: MIT */
/*
 * The one-surface hole fill along rows (thickness_fill.c), shared by VBAO's
 * thickness passes (dao_thickness_fill_rows, fill_px) and the filtered depth
 * output (parameter depth-fill, dao_context_get_depth).
 */
#ifndef DAO_KERNELS_DEPTH_FILL_H
#define DAO_KERNELS_DEPTH_FILL_H

/*
 * Rows [y0, y1) of z (w pixels a row, 0 = no depth, metres) into zf: each hole
 * of at most max_px pixels along its row, with depth on both sides that lies
 * on one surface (the two depths within DAO_THICKNESS_JUMP, 3 %, of the
 * nearer: two neighbours of a thickness run), filled linearly between them;
 * every other pixel copied.  A hole at the image's border, across a step or
 * wider than max_px stays a hole.  max_px <= 0 copies.
 */
void dao_depth_fill_rows(const float *z, float *zf, int w, int y0, int y1, int max_px);

#endif
