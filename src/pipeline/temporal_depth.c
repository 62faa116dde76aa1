/* SPDX-License-Identifier: MIT */
#include <math.h>
#include <stddef.h>

#include "pipeline/temporal_depth.h"

/*
 * One pixel; the optimised kernels (temporal_depth_simd.inc.c) do the same
 * operations in the same order, so they agree bit for bit.  var is the
 * variance of 1/z expected for this sample.
 */
static void pixel(const struct dao_temporal_depth_setup *s, float *z, float *hist,
		  uint8_t *count, uint8_t *age, size_t i, float inv, float var)
{
	const float zi = z[i], h = hist[i];
	const float n = s->fresh ? 0.0f : (float)count[i];
	const float a = s->fresh ? 255.0f : (float)age[i];
	const float d = inv - h;
	/* 1/m and 1/(m + 1) from one division (the kernels' cost is in their
	 * divisions; m (m + 1) <= 65280 is exact) */
	const float m = fmaxf(n, 1.0f), q = 1.0f / (m * (m + 1.0f));
	/* d is the difference of the sample and the history: its variance is
	 * var (1 + that of the history, in units of var: 1/n while it is a
	 * plain mean, (1 - alpha)/(1 + alpha) once exponential) */
	const float vh = fmaxf((m + 1.0f) * q, (1.0f - s->alpha) / (1.0f + s->alpha));
	const int keep = n > 0.0f && d * d <= s->reject * s->reject * (var * (1.0f + vh));
	const float n1 = keep ? fminf(n + 1.0f, (float)DAO_TEMPORAL_DEPTH_MAX_COUNT) : 1.0f;
	/* the new sample's weight, 1/(n + 1) (used where keep: n >= 1; at the
	 * count's cap 1/256 is below any 1 - alpha as 1/255 is) */
	const float w = fmaxf(m * q, 1.0f - s->alpha);
	const float h1 = keep ? h + w * d : inv;
	if (zi > 0.0f) {
		/* a new history, or one equal to the sample's 1/z (a still, clean
		 * scene), gives the sample itself, bit for bit (not 1/(1/z)) */
		z[i] = n1 == 1.0f || h1 == inv ? zi : 1.0f / h1;
		hist[i] = h1;
		count[i] = (uint8_t)n1;
		age[i] = 0;
	} else {
		z[i] = n > 0.0f && a < (float)s->persist ? 1.0f / h : 0.0f;
		count[i] = (uint8_t)n;
		age[i] = (uint8_t)fminf(a + 1.0f, 255.0f);
	}
}

void dao_temporal_depth_span_ref(const struct dao_temporal_depth_setup *s, float *z, float *hist,
				 uint8_t *count, uint8_t *age, size_t i0, size_t i1)
{
	/* sigma^2 = k^2 + (q / z^2)^2 / 12: the sensor's noise and the rounding
	 * of its output (a step q in z is q / z^2 in 1/z), which dominates for
	 * near, clean or finely modelled depth */
	const float k2 = s->noise_k * s->noise_k, q2 = s->quantum * s->quantum / 12.0f;
	for (size_t i = i0; i < i1; i++) {
		const float inv = z[i] > 0.0f ? 1.0f / z[i] : 0.0f;
		const float inv2 = inv * inv;
		const float var = s->sigma ? s->sigma[i] * s->sigma[i] : k2 + q2 * inv2 * inv2;
		pixel(s, z, hist, count, age, i, inv, var);
	}
}

void dao_temporal_depth_ref(const struct dao_temporal_depth_setup *s, float *z, float *hist,
			    uint8_t *count, uint8_t *age, int y0, int y1)
{
	dao_temporal_depth_span_ref(s, z, hist, count, age, (size_t)y0 * (size_t)s->width,
				    (size_t)y1 * (size_t)s->width);
}
