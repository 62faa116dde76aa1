/* SPDX-License-Identifier: MIT */
#ifndef DAO_DEPTH_DECODE_H
#define DAO_DEPTH_DECODE_H

#include <depthao/frame.h>

/*
 * Rows [y0, y1) of a DEPTH16 or DEPTH_F32 frame -> float metres in `z`
 * (tightly packed, frame width).  No-data (0, NaN, inf, outside
 * [zmin, zmax]) becomes 0.  The frame must have passed dao_frame_check().
 */
void dao_decode_depth(const struct dao_frame *in, float zmin, float zmax, float *z, int y0,
		      int y1);

#endif
