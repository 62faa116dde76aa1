/* SPDX-License-Identifier: MIT */
#include <math.h>

#include "synth/robust.h"

/* Hoare's selection with a median-of-three pivot: expected linear time. */
float synth_select(float *a, size_t n, size_t k)
{
	size_t lo = 0, hi = n - 1;
	while (lo < hi) {
		size_t mid = lo + (hi - lo) / 2;
		float x = a[lo], y = a[mid], z = a[hi];
		float pivot = (x < y) ? (y < z ? y : (x < z ? z : x)) : (x < z ? x : (y < z ? z : y));
		size_t i = lo, j = hi;
		while (i <= j) {
			while (a[i] < pivot)
				i++;
			while (a[j] > pivot)
				j--;
			if (i <= j) {
				float t = a[i];
				a[i] = a[j];
				a[j] = t;
				i++;
				if (j == 0)
					break;
				j--;
			}
		}
		if (k <= j)
			hi = j;
		else if (k >= i)
			lo = i;
		else
			return a[k];
	}
	return a[k];
}

float synth_median(float *a, size_t n)
{
	if (n == 0)
		return 0.0f;
	float m = synth_select(a, n, n / 2);
	if (n % 2)
		return m;
	/* the largest of the lower half */
	float lo = a[0];
	for (size_t i = 1; i < n / 2; i++)
		lo = a[i] > lo ? a[i] : lo;
	return 0.5f * (lo + m);
}

float synth_robust_sigma(float *a, size_t n)
{
	if (n == 0)
		return 0.0f;
	float m = synth_median(a, n);
	for (size_t i = 0; i < n; i++)
		a[i] = fabsf(a[i] - m);
	return 1.4826f * synth_median(a, n);
}
