/* SPDX-License-Identifier: MIT */
#include <errno.h>
#include <math.h>
#include <stdlib.h>

#include "synth/synth.h"

static int cmp_float(const void *a, const void *b)
{
	float x = *(const float *)a, y = *(const float *)b;
	return (x > y) - (x < y);
}

int synth_metrics(const float *ao, const float *gt, const float *depth, int w, int h,
		  struct synth_metrics *m)
{
	const size_t np = (size_t)w * h;
	float *err = malloc(np * sizeof(float));
	if (!err)
		return -ENOMEM;
	double sum_abs = 0.0, sum = 0.0, occ = 0.0;
	long n = 0, nan = 0, bad_invalid = 0;
	for (size_t i = 0; i < np; i++) {
		float a = ao[i];
		if (!(a >= 0.0f && a <= 1.0f)) {
			nan++;
			continue;
		}
		if (depth[i] <= 0.0f) {
			bad_invalid += a != 1.0f;
			continue;
		}
		float e = a - gt[i];
		err[n++] = fabsf(e);
		sum_abs += fabsf(e);
		sum += e;
		occ += 1.0 - a;
	}
	*m = (struct synth_metrics){ 0 };
	m->count = n;
	m->nan_count = nan;
	m->invalid_not_one = bad_invalid;
	if (n > 0) {
		m->mae = sum_abs / n;
		m->bias = sum / n;
		m->mean_occlusion = occ / n;
		qsort(err, (size_t)n, sizeof(float), cmp_float);
		m->p99 = err[(size_t)((n - 1) * 0.99)];
	}
	free(err);
	return 0;
}
