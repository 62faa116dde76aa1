/* SPDX-License-Identifier: MIT */
/*
 * Kinect-like depth noise: axial noise growing with z^2 (Khoshelham and
 * Elberink 2012 measured sigma ~ 1.4 mm at 1 m to 4 cm at 5 m for Kinect v1;
 * we use sigma = k z^2), quantisation, and dropouts in small clumps.
 */
#include <math.h>
#include <stdlib.h>

#include "synth/rng.h"
#include "synth/synth.h"

/* Box-Muller: one standard normal deviate. */
static double gaussian(uint64_t *s)
{
	double u = synth_rng_uniform(s), v = synth_rng_uniform(s);
	return sqrt(-2.0 * log(u)) * cos(6.283185307179586 * v);
}

void synth_sensor_noise(float *depth, int w, int h, double k, double quantum,
			double drop_fraction, uint64_t seed)
{
	uint64_t rng = seed * 0x2545f4914f6cdd1dull + 1;
	const size_t np = (size_t)w * h;
	for (size_t i = 0; i < np; i++) {
		double z = depth[i];
		if (z <= 0.0)
			continue;
		z += gaussian(&rng) * k * z * z;
		if (quantum > 0.0)
			z = floor(z / quantum + 0.5) * quantum;
		depth[i] = z > 0.0 ? (float)z : 0.0f;
	}
	/* dropouts: discs of radius 1..3 px at random places until the fraction is reached */
	size_t target = (size_t)(drop_fraction * (double)np), dropped = 0;
	for (size_t i = 0; i < np; i++)
		dropped += depth[i] <= 0.0f;
	target += dropped;
	for (int guard = 0; dropped < target && guard < 1000000; guard++) {
		int cx = (int)(synth_rng_uniform(&rng) * w), cy = (int)(synth_rng_uniform(&rng) * h);
		int r = 1 + (int)(synth_rng_uniform(&rng) * 3.0);
		for (int y = cy - r; y <= cy + r; y++)
			for (int x = cx - r; x <= cx + r; x++) {
				if (x < 0 || y < 0 || x >= w || y >= h)
					continue;
				if ((x - cx) * (x - cx) + (y - cy) * (y - cy) > r * r)
					continue;
				float *d = &depth[(size_t)y * w + x];
				if (*d > 0.0f) {
					*d = 0.0f;
					dropped++;
				}
			}
	}
}
