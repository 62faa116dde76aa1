/* SPDX-License-Identifier: MIT */
#ifndef DAO_CORE_MATH_UTIL_H
#define DAO_CORE_MATH_UTIL_H

#include <math.h>

#define DAO_PI 3.14159265358979323846
#define DAO_PI_F 3.14159265358979f
#define DAO_HALF_PI_F 1.57079632679490f

static inline float dao_clampf(float x, float lo, float hi)
{
	return x < lo ? lo : (x > hi ? hi : x);
}

static inline float dao_saturate(float x)
{
	return dao_clampf(x, 0.0f, 1.0f);
}

static inline float dao_lerpf(float a, float b, float t)
{
	return a + (b - a) * t;
}

static inline int dao_clampi(int x, int lo, int hi)
{
	return x < lo ? lo : (x > hi ? hi : x);
}

#endif
