/* SPDX-License-Identifier: MIT */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "synth/sensor_field.h"

double synth_gaussian(uint64_t *state)
{
	double u = synth_rng_uniform(state), v = synth_rng_uniform(state);
	return sqrt(-2.0 * log(u)) * cos(6.283185307179586 * v);
}

/* Box filter of radius r along rows (dx = 1) or columns, edges clamped. */
static void box(float *img, float *tmp, int w, int h, int r, int rows)
{
	const int n = rows ? w : h, lines = rows ? h : w;
	const size_t step = rows ? 1 : (size_t)w, next = rows ? (size_t)w : 1;
	for (int l = 0; l < lines; l++) {
		float *p = img + (size_t)l * next;
		double s = 0;
		for (int k = -r; k <= r; k++)
			s += p[(size_t)(k < 0 ? 0 : k >= n ? n - 1 : k) * step];
		for (int i = 0; i < n; i++) {
			tmp[i] = (float)(s / (2 * r + 1));
			int add = i + r + 1, sub = i - r;
			s += p[(size_t)(add >= n ? n - 1 : add) * step] - p[(size_t)(sub < 0 ? 0 : sub) * step];
		}
		for (int i = 0; i < n; i++)
			p[(size_t)i * step] = tmp[i];
	}
}

int synth_smooth_field(float *out, int w, int h, double scale, uint64_t seed)
{
	if (!(scale >= 1.0))
		scale = 1.0;
	const int gw = (int)ceil(w / scale) + 2, gh = (int)ceil(h / scale) + 2;
	float *g = malloc((size_t)gw * gh * sizeof(float));
	float *tmp = malloc((size_t)(w > h ? w : h) * sizeof(float));
	if (!g || !tmp) {
		free(g);
		free(tmp);
		return -ENOMEM;
	}
	uint64_t rng = seed * 0xd1342543de82ef95ull + 0x7f4a7c15ull;
	for (int i = 0; i < gw * gh; i++)
		g[i] = (float)synth_gaussian(&rng);
	for (int y = 0; y < h; y++) {
		double fy = y / scale;
		int iy = (int)fy;
		double ty = fy - iy;
		for (int x = 0; x < w; x++) {
			double fx = x / scale;
			int ix = (int)fx;
			double tx = fx - ix;
			const float *a = g + (size_t)iy * gw + ix, *b = a + gw;
			out[(size_t)y * w + x] = (float)((1 - ty) * ((1 - tx) * a[0] + tx * a[1]) +
							 ty * ((1 - tx) * b[0] + tx * b[1]));
		}
	}
	const int r = (int)(scale / 4.0);
	for (int pass = 0; pass < 2 && r > 0; pass++) {
		box(out, tmp, w, h, r, 1);
		box(out, tmp, w, h, r, 0);
	}
	double s = 0, q = 0;
	for (size_t i = 0; i < (size_t)w * h; i++)
		s += out[i], q += (double)out[i] * out[i];
	double n = (double)w * h, mean = s / n, sd = sqrt(fmax(q / n - mean * mean, 1e-30));
	for (size_t i = 0; i < (size_t)w * h; i++)
		out[i] = (float)((out[i] - mean) / sd);
	free(g);
	free(tmp);
	return 0;
}

int synth_remove_speckles(float *disp, int w, int h, float max_diff, int min_area)
{
	const size_t np = (size_t)w * h;
	uint8_t *seen = calloc(np, 1);
	int32_t *queue = malloc(np * sizeof(int32_t));
	if (!seen || !queue) {
		free(seen);
		free(queue);
		return -ENOMEM;
	}
	for (size_t s = 0; s < np; s++) {
		if (seen[s] || isnan(disp[s]))
			continue;
		long head = 0, tail = 0;
		queue[tail++] = (int32_t)s;
		seen[s] = 1;
		while (head < tail) {
			int32_t i = queue[head++];
			int x = i % w, y = i / w;
			const int32_t nb[4] = { x > 0 ? i - 1 : -1, x + 1 < w ? i + 1 : -1,
						y > 0 ? i - w : -1, y + 1 < h ? i + w : -1 };
			for (int k = 0; k < 4; k++) {
				int32_t j = nb[k];
				if (j >= 0 && !seen[j] && !isnan(disp[j]) && fabsf(disp[j] - disp[i]) <= max_diff) {
					seen[j] = 1;
					queue[tail++] = j;
				}
			}
		}
		if (tail < min_area)
			for (long k = 0; k < tail; k++)
				disp[queue[k]] = NAN;
	}
	free(seen);
	free(queue);
	return 0;
}

int synth_pattern_make(struct synth_pattern *p, int u0, int u1, int h, double pitch,
		       double sigma, uint64_t seed)
{
	p->u0 = u0;
	p->h = h;
	p->width = (u1 - u0) * SYNTH_PATTERN_OVERSAMPLE + 1;
	p->v = calloc((size_t)p->width * h, sizeof(float));
	if (!p->v)
		return -ENOMEM;
	const double s2 = sigma * sigma + 1.0 / 12.0, reach = 3.0 * sqrt(s2);
	const int span = (int)(2.0 * reach * SYNTH_PATTERN_OVERSAMPLE) + 2;
	float *wu = malloc((size_t)span * sizeof(float));
	if (!wu) {
		free(p->v);
		p->v = NULL;
		return -ENOMEM;
	}
	uint64_t rng = seed;
	const int nu = (int)ceil((u1 - u0) / pitch) + 1, nv = (int)ceil(h / pitch) + 1;
	for (int gy = -1; gy < nv; gy++)
		for (int gx = -1; gx < nu; gx++) {
			double cu = u0 + (gx + synth_rng_uniform(&rng)) * pitch;
			double cv = (gy + synth_rng_uniform(&rng)) * pitch;
			float a = (float)(0.5 + 0.5 * synth_rng_uniform(&rng));
			int s0 = (int)ceil((cu - reach - u0) * SYNTH_PATTERN_OVERSAMPLE);
			int s1 = (int)floor((cu + reach - u0) * SYNTH_PATTERN_OVERSAMPLE);
			if (s0 < 0)
				s0 = 0;
			if (s1 > p->width - 1)
				s1 = p->width - 1;
			if (s1 < s0 || s1 - s0 >= span)
				continue;
			for (int s = s0; s <= s1; s++) {
				double du = u0 + (double)s / SYNTH_PATTERN_OVERSAMPLE - cu;
				wu[s - s0] = (float)exp(-du * du / (2.0 * s2));
			}
			for (int y = (int)ceil(cv - reach); y <= (int)floor(cv + reach); y++) {
				if (y < 0 || y >= h)
					continue;
				float wv = a * (float)exp(-(y - cv) * (y - cv) / (2.0 * s2));
				float *row = p->v + (size_t)y * p->width;
				for (int s = s0; s <= s1; s++)
					row[s] += wv * wu[s - s0];
			}
		}
	free(wu);
	return 0;
}
