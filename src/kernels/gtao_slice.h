/* SPDX-License-Identifier: MIT */
/*
 * The slice geometry GTAO and VBAO share (Jimenez 2016, sec. 4): for screen
 * direction (dx, dy) the slice is the plane through the camera centre that
 * contains the view vector V and the view-space direction (dx/fx, dy/fy, 0);
 * the normal N projected into it has length lpn and the signed angle n from V.
 */
#ifndef DAO_KERNELS_GTAO_SLICE_H
#define DAO_KERNELS_GTAO_SLICE_H

#include <math.h>

#include "core/math_util.h"
#include "kernels/gtao.h"

static inline float dao_dot3(const float a[3], const float b[3])
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void dao_cross3(const float a[3], const float b[3], float o[3])
{
	o[0] = a[1] * b[2] - a[2] * b[1];
	o[1] = a[2] * b[0] - a[0] * b[2];
	o[2] = a[0] * b[1] - a[1] * b[0];
}

struct dao_slice {
	float ortho[3]; /* the slice direction without its V part (not normalised) */
	float lpn;      /* |N projected into the slice| */
	float cos_n, n; /* angle of the projected normal from V, positive towards ortho */
};

/* Fills *sl; returns 0 when N is (almost) perpendicular to the slice. */
static inline int dao_slice_frame(const struct dao_gtao_setup *s, float dx, float dy,
				  const float V[3], const float N[3], struct dao_slice *sl)
{
	const float dir[3] = { dx * s->ax, dy * s->ay, 0.0f };
	float dv = dao_dot3(dir, V);
	sl->ortho[0] = dir[0] - dv * V[0];
	sl->ortho[1] = dir[1] - dv * V[1];
	sl->ortho[2] = dir[2] - dv * V[2];
	float axis[3];
	dao_cross3(sl->ortho, V, axis);
	float la = sqrtf(dao_dot3(axis, axis));
	axis[0] /= la, axis[1] /= la, axis[2] /= la;
	float na = dao_dot3(N, axis);
	float pn[3] = { N[0] - axis[0] * na, N[1] - axis[1] * na, N[2] - axis[2] * na };
	sl->lpn = sqrtf(dao_dot3(pn, pn));
	if (!(sl->lpn > 1e-6f))
		return 0;
	sl->cos_n = dao_clampf(dao_dot3(pn, V) / sl->lpn, -1.0f, 1.0f);
	sl->n = acosf(sl->cos_n);
	if (dao_dot3(sl->ortho, pn) < 0.0f)
		sl->n = -sl->n;
	return 1;
}

#endif
