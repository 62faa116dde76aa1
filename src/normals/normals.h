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

/* One pixel of the same (the fallback of the optimised kernels). */
void dao_normal_pixel(const struct dao_camera *cam, const float *z, int r, int x, int y,
		      float out[3]);

/* The same over SIMD lanes (normals_simd.inc.c, one build per instruction set). */
void dao_normals_from_depth_generic(const struct dao_camera *cam, const float *z, int r, float *n,
				    int y0, int y1);
void dao_normals_from_depth_sse41(const struct dao_camera *cam, const float *z, int r, float *n,
				  int y0, int y1);
void dao_normals_from_depth_avx2(const struct dao_camera *cam, const float *z, int r, float *n,
				 int y0, int y1);
void dao_normals_from_depth_avx512(const struct dao_camera *cam, const float *z, int r, float *n,
				   int y0, int y1);

#endif
