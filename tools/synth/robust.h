/* SPDX-License-Identifier: MIT */
/* Order statistics for the sensor measurements (tools and tests only). */
#ifndef DAO_SYNTH_ROBUST_H
#define DAO_SYNTH_ROBUST_H

#include <stddef.h>

/* The k-th smallest of a[0..n) (0-based); reorders a.  n > 0. */
float synth_select(float *a, size_t n, size_t k);

/* Median of a[0..n); reorders a.  0 for n == 0. */
float synth_median(float *a, size_t n);

/*
 * Robust standard deviation: 1.4826 x the median absolute deviation from the
 * median (equals sigma for Gaussian data); reorders a.  0 for n == 0.
 */
float synth_robust_sigma(float *a, size_t n);

#endif
