/* SPDX-License-Identifier: MIT */
/* Noise of known statistics for the filter and noise-estimate tests. */
#ifndef DAO_TEST_NOISE_FIELDS_H
#define DAO_TEST_NOISE_FIELDS_H

#include <stdint.h>

/* A standard normal deviate (Box-Muller on a 64-bit LCG), deterministic. */
double dao_test_gauss(uint64_t *state);

/*
 * w x h samples of spatially correlated Gaussian noise: white noise blurred
 * by a Gaussian of blur px (0: independent), scaled so that the field's
 * standard deviation over the w x h samples is exactly sigma.  Neighbours
 * k px apart then correlate by exp(-k^2 / (4 blur^2)).
 */
void dao_test_correlated_noise(float *out, int w, int h, double sigma, double blur, uint64_t seed);

#endif
