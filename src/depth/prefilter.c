/* SPDX-License-Identifier: MIT */
/* Separable bilateral depth prefilter, reference passes (see prefilter.h). */
#include <math.h>
#include <stddef.h>

#include "depth/prefilter.h"

void dao_prefilter_setup_init(struct dao_prefilter_setup *s, int width, int height, int radius,
			      float noise_k, float unit)
{
	const float sigma_s = 0.5f * (float)radius + 0.5f;
	*s = (struct dao_prefilter_setup){
		.width = width, .height = height, .radius = radius,
		.noise_k = noise_k, .unit = unit,
		.inv_2ss = 1.0f / (2.0f * sigma_s * sigma_s),
	};
}

float dao_prefilter_h_pixel(const struct dao_prefilter_setup *s, const float *z, int x, int y)
{
	const float *row = z + (size_t)y * s->width;
	if (row[x] <= 0.0f)
		return 0.0f;
	const float wc = 1.0f / row[x];
	const float inv_2rr = dao_prefilter_inv_2rr(s, wc);
	const int a = x - s->radius < 0 ? 0 : x - s->radius;
	const int b = x + s->radius >= s->width ? s->width - 1 : x + s->radius;
	float sum = 0.0f, wsum = 0.0f;
	for (int i = a; i <= b; i++) {
		if (row[i] <= 0.0f)
			continue;
		const float ws = 1.0f / row[i], d = ws - wc;
		const float wt = expf(-(float)((i - x) * (i - x)) * s->inv_2ss - d * d * inv_2rr);
		sum += wt * ws;
		wsum += wt;
	}
	return sum / wsum; /* the centre has weight 1 */
}

float dao_prefilter_v_pixel(const struct dao_prefilter_setup *s, const float *tmp, int x, int y)
{
	const size_t w = (size_t)s->width;
	const float wc = tmp[(size_t)y * w + x];
	if (wc <= 0.0f)
		return 0.0f;
	const float inv_2rr = dao_prefilter_inv_2rr(s, wc);
	const int a = y - s->radius < 0 ? 0 : y - s->radius;
	const int b = y + s->radius >= s->height ? s->height - 1 : y + s->radius;
	float sum = 0.0f, wsum = 0.0f;
	for (int j = a; j <= b; j++) {
		const float ws = tmp[(size_t)j * w + x];
		if (ws <= 0.0f)
			continue;
		const float d = ws - wc;
		const float wt = expf(-(float)((j - y) * (j - y)) * s->inv_2ss - d * d * inv_2rr);
		sum += wt * ws;
		wsum += wt;
	}
	return 1.0f / (sum / wsum);
}

void dao_prefilter_h_ref(const struct dao_prefilter_setup *s, const float *z, float *tmp, int y0,
			 int y1)
{
	for (int y = y0; y < y1; y++)
		for (int x = 0; x < s->width; x++)
			tmp[(size_t)y * s->width + x] = dao_prefilter_h_pixel(s, z, x, y);
}

void dao_prefilter_v_ref(const struct dao_prefilter_setup *s, const float *tmp, float *out,
			 int y0, int y1)
{
	for (int y = y0; y < y1; y++)
		for (int x = 0; x < s->width; x++)
			out[(size_t)y * s->width + x] = dao_prefilter_v_pixel(s, tmp, x, y);
}
