/* SPDX-License-Identifier: MIT */
#ifndef DAO_KERNELS_GTAO_SAMPLE_H
#define DAO_KERNELS_GTAO_SAMPLE_H

#include <math.h>
#include <stddef.h>

/* Which pixels a sample read and how it weighed them (dao_gtao_sample_taps),
 * so another plane can be sampled the same way (vbao's thickness). */
struct dao_gtao_taps {
	size_t i0, i1; /* the two taps, pixel indices (valid where used) */
	float f;       /* fraction from i0 to i1 */
	int pick;      /* -1: both, interpolated; 0: i0 alone; 1: i1 alone */
};

/* A value of plane `t` at the sample `tp` describes: interpolated linearly like
 * the taps' 1/z, or the one tap the sample took. */
static inline float dao_gtao_taps_value(const float *t, const struct dao_gtao_taps *tp)
{
	if (tp->pick < 0)
		return t[tp->i0] + tp->f * (t[tp->i1] - t[tp->i0]);
	return t[tp->pick ? tp->i1 : tp->i0];
}

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
static inline int dao_gtao_sample_taps(const float *z, int w, int h, int x, int y, float dx,
				       float dy, float t, float *u, float *v, float *zs,
				       struct dao_gtao_taps *tp)
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
	const size_t p0 = major_x ? (size_t)i0 * w + m : (size_t)m * w + i0;
	const size_t p1 = major_x ? p0 + (size_t)w : p0 + 1;
	if (i0 >= 0)
		z0 = z[p0];
	if (i0 + 1 < nmin)
		z1 = z[p1];

	float zz, fmin = fm;
	int pick = -1;
	if (z0 > 0.0f && z1 > 0.0f) {
		if (fabsf(z0 - z1) <= 0.1f * fminf(z0, z1)) {
			zz = 1.0f / ((1.0f - f) / z0 + f / z1);
		} else {
			/* a depth edge: the nearer tap, at its own position (a depth moved
			 * to another pixel would no longer lie on its surface) */
			int use1 = f >= 0.5f;
			zz = use1 ? z1 : z0;
			fmin = (float)(i0 + use1);
			pick = use1;
		}
	} else if (z0 > 0.0f && f < 1e-3f) {
		zz = z0; /* on the line: the other tap is not needed */
		pick = 0;
	} else if (z1 > 0.0f && f > 1.0f - 1e-3f) {
		zz = z1;
		pick = 1;
	} else {
		/* a tap is missing (a hole, or the point is off the image): a lone tap
		 * off the line could make a plane occlude itself, so no sample */
		return 0;
	}
	*zs = zz;
	if (tp)
		*tp = (struct dao_gtao_taps){ .i0 = p0, .i1 = p1, .f = f, .pick = pick };
	if (major_x) {
		*u = (float)m;
		*v = fmin;
	} else {
		*u = fmin;
		*v = (float)m;
	}
	return 1;
}

static inline int dao_gtao_sample(const float *z, int w, int h, int x, int y, float dx,
				  float dy, float t, float *u, float *v, float *zs)
{
	return dao_gtao_sample_taps(z, w, h, x, y, dx, dy, t, u, v, zs, NULL);
}

#endif
