/* SPDX-License-Identifier: MIT */
#include <math.h>
#include <stdlib.h>

#include "common/noise_fields.h"

double dao_test_gauss(uint64_t *s)
{
	*s = *s * 6364136223846793005ull + 1442695040888963407ull;
	const double u = ((double)(*s >> 11) + 0.5) / 9007199254740992.0;
	*s = *s * 6364136223846793005ull + 1442695040888963407ull;
	const double v = ((double)(*s >> 11) + 0.5) / 9007199254740992.0;
	return sqrt(-2.0 * log(u)) * cos(6.283185307179586 * v);
}

void dao_test_correlated_noise(float *out, int w, int h, double sigma, double blur, uint64_t seed)
{
	uint64_t s = seed * 0x9e3779b97f4a7c15ull + 1;
	if (blur <= 0.0) {
		double sum2 = 0.0;
		for (int i = 0; i < w * h; i++) {
			out[i] = (float)dao_test_gauss(&s);
			sum2 += (double)out[i] * out[i];
		}
		const double k = sigma / sqrt(sum2 / (w * h));
		for (int i = 0; i < w * h; i++)
			out[i] = (float)(out[i] * k);
		return;
	}
	/* separable blur over a padded field, kernel cut at 4 blur */
	const int r = (int)ceil(4.0 * blur), pw = w + 2 * r, ph = h + 2 * r;
	double *a = malloc(sizeof(double) * (size_t)pw * ph), *b = malloc(sizeof(double) * (size_t)pw * ph);
	double *k = malloc(sizeof(double) * (size_t)(2 * r + 1));
	if (!a || !b || !k)
		abort();
	double ksum = 0.0;
	for (int i = -r; i <= r; i++)
		ksum += k[i + r] = exp(-0.5 * i * i / (blur * blur));
	for (int i = 0; i < pw * ph; i++)
		a[i] = dao_test_gauss(&s);
	for (int y = 0; y < ph; y++)
		for (int x = r; x < pw - r; x++) {
			double t = 0.0;
			for (int i = -r; i <= r; i++)
				t += k[i + r] * a[(size_t)y * pw + x + i];
			b[(size_t)y * pw + x] = t / ksum;
		}
	double sum2 = 0.0;
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			double t = 0.0;
			for (int i = -r; i <= r; i++)
				t += k[i + r] * b[(size_t)(y + r + i) * pw + x + r];
			a[(size_t)y * w + x] = t / ksum;
			sum2 += (t / ksum) * (t / ksum);
		}
	const double scale = sigma / sqrt(sum2 / (w * h));
	for (int i = 0; i < w * h; i++)
		out[i] = (float)(a[i] * scale);
	free(a);
	free(b);
	free(k);
}
