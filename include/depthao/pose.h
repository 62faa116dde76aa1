/* SPDX-License-Identifier: MIT */
/*
 * Rigid poses: the rotation as a unit quaternion or a matrix, and
 * interpolation between two poses.
 *
 * The convention is dao_context_set_pose()'s: a quaternion q = (x, y, z, w),
 * w last; a rotation matrix R of 9 doubles, row-major (R[3 * row + col]); a
 * translation t in metres; a pose maps a point of the camera's frame into
 * the world's: x_world = R x_camera + t.
 *
 * Pure arithmetic, no allocation, thread-safe: the arguments are not
 * checked (no NULL, no non-finite value, no norm); a NaN in gives NaNs out.
 * The output arrays may be the input arrays.
 */
#ifndef DEPTHAO_POSE_H
#define DEPTHAO_POSE_H

#include <depthao/api.h>

#ifdef __cplusplus
extern "C" {
#endif

/*
 * The rotation matrix r of the unit quaternion q.  q must have norm 1
 * (normalise it first otherwise: of another norm, r is not a rotation);
 * q and -q give the same r.
 */
DAO_API void dao_pose_quat_to_matrix(const double q[4], double r[9]);

/*
 * The unit quaternion q of the rotation matrix r, with w >= 0 (of q and -q,
 * the one with w >= 0; for a half turn, w = 0, either).  Shepperd's method:
 * the largest of |w|, |x|, |y|, |z| is taken from the trace or the largest
 * diagonal term, the others from the off-diagonal terms, so that no
 * rotation loses precision (half turns included).  r should be a rotation
 * (orthonormal, determinant +1); one that drifted from it by rounding (a
 * product of many rotations) gives the unit quaternion of a rotation close
 * to it, q normalised.
 */
DAO_API void dao_pose_matrix_to_quat(const double r[9], double q[4]);

/*
 * The pose the fraction s of the way from pose a (qa, ta; s = 0) to pose b
 * (qb, tb; s = 1): the translation t = (1 - s) ta + s tb, the rotation q
 * spherical (slerp) along the shorter arc between qa and qb (qb is taken as
 * -qb when qa . qb < 0: the same rotation), at the constant angular rate;
 * q is a unit quaternion.  Rotations less than about 0.1 degree apart
 * (|qa . qb| > 0.9999995) are interpolated linearly, then normalised (for s
 * in [0, 1] within 4e-11 radians of slerp).  s outside [0, 1] extrapolates:
 * the translation along the same line, the rotation along the same arc
 * (s = 2: twice as far from a as b is; s = -1: as far from a as b, the
 * other way).  qa and qb must be unit quaternions.  s = 0 gives ta exactly
 * and qa to rounding (q is normalised), s = 1 tb exactly and qb (or -qb) to
 * rounding.
 */
DAO_API void dao_pose_interpolate(const double qa[4], const double ta[3], const double qb[4],
				  const double tb[3], double s, double q[4], double t[3]);

#ifdef __cplusplus
}
#endif
#endif
