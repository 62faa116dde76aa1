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
 * Turbo (Mikhailov 2019, "Turbo, An Improved Rainbow Colormap for
 * Visualization", Google AI blog; the colormap is Apache-2.0): the published
 * 256-entry sRGB table at every 8th entry (0, 8, ..., 248) and entry 255,
 * linear between them: within 3/255 of every published entry
 * (tests/shade/test_shade.c checks it).  The degree-5 polynomial used before
 * was 32/255 off at places (entry 0 came out (35, 23, 27), not (48, 18, 59)).
 */
static const uint8_t turbo_knots[33][3] = {
	{  48,  18,  59 }, {  57,  42, 115 }, {  64,  64, 162 }, {  68,  86, 199 },
	{  70, 107, 227 }, {  70, 128, 246 }, {  66, 148, 255 }, {  55, 168, 250 },
	{  40, 188, 235 }, {  28, 205, 216 }, {  24, 221, 194 }, {  31, 233, 175 },
	{  50, 242, 152 }, {  78, 249, 125 }, { 109, 254,  98 }, { 139, 255,  75 },
	{ 164, 252,  60 }, { 185, 246,  53 }, { 205, 236,  52 }, { 223, 223,  55 },
	{ 238, 207,  58 }, { 248, 190,  57 }, { 253, 172,  52 }, { 254, 150,  43 },
	{ 251, 126,  33 }, { 244, 102,  23 }, { 235,  80,  14 }, { 223,  63,   8 },
	{ 208,  47,   5 }, { 190,  33,   2 }, { 169,  22,   1 }, { 146,  11,   1 },
	{ 122,   4,   3 },
};

/* entry i (0..255) of the table: knot k sits at entry 8k, the last at 255 */
static void turbo(int i, float rgb[3])
{
	int k = i / 8 < 31 ? i / 8 : 31;
	const float k0 = 8.0f * (float)k, k1 = k == 31 ? 255.0f : k0 + 8.0f;
	const float f = ((float)i - k0) / (k1 - k0);
	for (int c = 0; c < 3; c++)
		rgb[c] = ((1.0f - f) * turbo_knots[k][c] + f * turbo_knots[k + 1][c]) / 255.0f;
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
			turbo(i, rgb);
		else if (mode == DAO_SHADE_JET)
			jet(t, rgb);
		for (int k = 0; k < 3; k++)
			map->rgb[i][k] = to8(rgb[k]);
	}
}
