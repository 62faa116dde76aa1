/* SPDX-License-Identifier: MIT */
#ifndef DAO_KERNELS_GTAO_SAMPLE_H
#define DAO_KERNELS_GTAO_SAMPLE_H

#include <math.h>

/*
 * Depth at a point exactly on the slice line (x, y) + t (dx, dy).
 *
 * A sample rounded to the nearest pixel lies off the slice plane; on a
 * tilted surface that alone makes the surface occlude itself.  Instead the
 * sample is moved along the line until its major-axis coordinate is an
 * integer, and the depth is interpolated between the two pixels that
 * straddle the line on the minor axis.  Interpolation is in 1/z, which is
 * affine on any plane, so samples of a plane lie exactly on it.  Across a
 * depth edge (taps more than 10 % apart) the nearer tap is taken, at its own
 * position, instead of inventing a surface in between.  Where a tap has no
 * data there is no sample.
 *
 * Returns 0 when the point is off the image or has no data; otherwise the
 * pixel coordinates (*u, *v) and depth *zs of the sample.
 */
static inline int dao_gtao_sample(const float *z, int w, int h, int x, int y, float dx,
				  float dy, float t, float *u, float *v, float *zs)
{
	int major_x = fabsf(dx) >= fabsf(dy);
	float dmaj = major_x ? dx : dy, dmin = major_x ? dy : dx;
	int cmaj = major_x ? x : y, cmin = major_x ? y : x;
	int nmaj = major_x ? w : h, nmin = major_x ? h : w;

	/* offsets from the pixel first (an integer pixel plus an offset is exact, so
	 * kernels that share one offset between pixels round the same way) */
	int mo = (int)lrintf(dmaj * t);
	if (mo == 0)
		mo = dmaj > 0.0f ? 1 : -1;
	const int m = cmaj + mo;
	if (m < 0 || m >= nmaj)
		return 0;
	const float off = (float)mo * (dmin / dmaj);
	const float fo = floorf(off);
	const int i0 = cmin + (int)fo;
	const float f = off - fo, fm = (float)cmin + off;
	if (i0 < -1 || i0 >= nmin)
		return 0;

	float z0 = 0.0f, z1 = 0.0f;
	if (i0 >= 0)
		z0 = major_x ? z[(size_t)i0 * w + m] : z[(size_t)m * w + i0];
	if (i0 + 1 < nmin)
		z1 = major_x ? z[(size_t)(i0 + 1) * w + m] : z[(size_t)m * w + i0 + 1];

	float zz, fmin = fm;
	if (z0 > 0.0f && z1 > 0.0f) {
		if (fabsf(z0 - z1) <= 0.1f * fminf(z0, z1)) {
			zz = 1.0f / ((1.0f - f) / z0 + f / z1);
		} else {
			/* a depth edge: the nearer tap, at its own position (a depth moved
			 * to another pixel would no longer lie on its surface) */
			int use1 = f >= 0.5f;
			zz = use1 ? z1 : z0;
			fmin = (float)(i0 + use1);
		}
	} else if (z0 > 0.0f && f < 1e-3f) {
		zz = z0; /* on the line: the other tap is not needed */
	} else if (z1 > 0.0f && f > 1.0f - 1e-3f) {
		zz = z1;
	} else {
		/* a tap is missing (a hole, or the point is off the image): a lone tap
		 * off the line could make a plane occlude itself, so no sample */
		return 0;
	}
	*zs = zz;
	if (major_x) {
		*u = (float)m;
		*v = fmin;
	} else {
		*u = fmin;
		*v = (float)m;
	}
	return 1;
}

#endif
