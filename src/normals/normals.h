/* SPDX-License-Identifier: MIT */
#ifndef DAO_NORMALS_NORMALS_H
#define DAO_NORMALS_NORMALS_H

#include <depthao/camera.h>

/*
 * View-space normals from depth (seed 002 "TakeSmallerAbsDelta", seed 003
 * "MinDiff"): along each image axis, of the two one-sided differences
 * P(x) - P(x-r) and P(x+r) - P(x) take the one with the smaller |dz|, so a
 * depth edge on one side does not bend the normal; N = normalize(dPdx x dPdy),
 * oriented towards the camera.  When a side has no data, the other side is
 * used; when neither has, the normal faces the camera (N = -P/|P|).
 *
 * z: w x h metres (0 = no data).  n: 3 floats per pixel (x, y, z).  r >= 1.
 * Pixels without depth get (0, 0, -1).  Processes rows [y0, y1).
 */
void dao_normals_from_depth(const struct dao_camera *cam, const float *z, int r, float *n,
			    int y0, int y1);

#endif
