/* SPDX-License-Identifier: MIT */
#include <math.h>

#include <depthao/params.h>

#include "core/math_util.h"
#include "shade/colormap.h"

static uint8_t to8(float v)
{
	return (uint8_t)lrintf(dao_saturate(v) * 255.0f);
}

/*
 * Turbo (Mikhailov 2019, "Turbo, An Improved Rainbow Colormap"): the
 * published degree-5 polynomial fit of each channel in t.
 */
static void turbo(float t, float rgb[3])
{
	static const float c[3][6] = {
		{ 0.13572138f, 4.61539260f, -42.66032258f, 132.13108234f, -152.94239396f, 59.28637943f },
		{ 0.09140261f, 2.19418839f, 4.84296658f, -14.18503333f, 4.27729857f, 2.82956604f },
		{ 0.10667330f, 12.64194608f, -60.58204836f, 110.36276771f, -89.90310912f, 27.34824973f },
	};
	for (int k = 0; k < 3; k++) {
		float v = c[k][5];
		for (int d = 4; d >= 0; d--)
			v = v * t + c[k][d];
		rgb[k] = v;
	}
}

/* Jet: piecewise-linear blue-cyan-yellow-red ramps centred at t = 1/4, 1/2, 3/4. */
static void jet(float t, float rgb[3])
{
	rgb[0] = 1.5f - fabsf(4.0f * t - 3.0f);
	rgb[1] = 1.5f - fabsf(4.0f * t - 2.0f);
	rgb[2] = 1.5f - fabsf(4.0f * t - 1.0f);
}

void dao_colormap_fill(struct dao_colormap *map, int mode)
{
	for (int i = 0; i < 256; i++) {
		float t = (float)i / 255.0f, rgb[3] = { t, t, t };
		if (mode == DAO_SHADE_TURBO)
			turbo(t, rgb);
		else if (mode == DAO_SHADE_JET)
			jet(t, rgb);
		for (int k = 0; k < 3; k++)
			map->rgb[i][k] = to8(rgb[k]);
	}
}
