/* SPDX-License-Identifier: MIT */
/* Small dense linear algebra of the plane fits: 3 x 3 systems by Cramer's rule. */
#ifndef DAO_SYNTH_LINALG_H
#define DAO_SYNTH_LINALG_H

#include <math.h>
#include <string.h>

static inline double synth_det3(const double m[3][3])
{
	return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
	       m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
	       m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

/*
 * Solves m x = t; -1 (x untouched) where |det m| is not above `eps` times the
 * product of the diagonal's magnitudes (0 for an exact test: det != 0).
 */
static inline int synth_solve3(const double m[3][3], const double t[3], double x[3], double eps)
{
	const double det = synth_det3(m);
	const double scale = fabs(m[0][0] * m[1][1] * m[2][2]) + 1e-300;
	if (!(fabs(det) > eps * scale) || det == 0.0)
		return -1;
	for (int k = 0; k < 3; k++) {
		double a[3][3];
		memcpy(a, m, sizeof a);
		for (int i = 0; i < 3; i++)
			a[i][k] = t[i];
		x[k] = synth_det3(a) / det;
	}
	return 0;
}

#endif
