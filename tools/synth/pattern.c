/* SPDX-License-Identifier: MIT */
#include <errno.h>
#include <math.h>
#include <string.h>

#include "synth/linalg.h"
#include "synth/pattern.h"

#define WIN SYNTH_PATTERN_WIN
#define NEIGH 8
#define OFFSET_BINS 3.0
#define SYNTH_PI 3.14159265358979323846

const float synth_pattern_freq[SYNTH_PATTERN_FREQS][2] = {
	{ 0.25f, 0.0f }, { 0.5f, 0.0f }, { 0.0f, 0.25f }, { 0.0f, 0.5f }, { 0.25f, 0.25f },
	{ 0.25f, -0.25f }, { 0.5f, 0.25f }, { 0.25f, 0.5f }, { 0.5f, 0.5f },
};

/* Mean AO below this: the window is occluded. */
#define OCCLUDED_MEAN 0.95
/* Largest second difference of 1/z (1/m) inside a smooth window. */
#define SMOOTH_INV_Z 0.02
/* Share of a window's pixels that must have depth. */
#define MIN_VALID 0.9

/* One frequency: its cosine and sine over a window's columns and rows. */
struct wave {
	double cx[WIN], sx[WIN], cy[WIN], sy[WIN];
};

static void wave_init(struct wave *wv, double fx, double fy)
{
	for (int i = 0; i < WIN; i++) {
		wv->cx[i] = cos(2.0 * SYNTH_PI * fx * i);
		wv->sx[i] = -sin(2.0 * SYNTH_PI * fx * i);
		wv->cy[i] = cos(2.0 * SYNTH_PI * fy * i);
		wv->sy[i] = -sin(2.0 * SYNTH_PI * fy * i);
	}
}

/* |sum v(x, y) e^(-2 pi i (fx x + fy y))|^2 */
static double power(const double v[WIN][WIN], const struct wave *wv)
{
	double re = 0.0, im = 0.0;
	for (int y = 0; y < WIN; y++) {
		double rr = 0.0, ri = 0.0;
		for (int x = 0; x < WIN; x++) {
			rr += v[y][x] * wv->cx[x];
			ri += v[y][x] * wv->sx[x];
		}
		re += rr * wv->cy[y] - ri * wv->sy[y];
		im += rr * wv->sy[y] + ri * wv->cy[y];
	}
	return re * re + im * im;
}

static int has_depth(const float *depth, int w, int x, int y)
{
	return depth[(size_t)y * w + x] > 0.0f;
}

static int window_qualifies(const float *ao, const float *depth, int w, int x0, int y0)
{
	double sum = 0.0;
	int n = 0;
	for (int y = y0; y < y0 + WIN; y++)
		for (int x = x0; x < x0 + WIN; x++)
			if (has_depth(depth, w, x, y)) {
				sum += ao[(size_t)y * w + x];
				n++;
			}
	if (n < MIN_VALID * WIN * WIN || sum >= OCCLUDED_MEAN * n)
		return 0;
	for (int y = y0; y < y0 + WIN; y++)
		for (int x = x0; x < x0 + WIN; x++) {
			if (!has_depth(depth, w, x, y))
				continue;
			const double d = 1.0 / depth[(size_t)y * w + x];
			if (x > x0 && x + 1 < x0 + WIN && has_depth(depth, w, x - 1, y) &&
			    has_depth(depth, w, x + 1, y) &&
			    fabs(1.0 / depth[(size_t)y * w + x - 1] - 2.0 * d +
				 1.0 / depth[(size_t)y * w + x + 1]) > SMOOTH_INV_Z)
				return 0;
			if (y > y0 && y + 1 < y0 + WIN && has_depth(depth, w, x, y - 1) &&
			    has_depth(depth, w, x, y + 1) &&
			    fabs(1.0 / depth[(size_t)(y - 1) * w + x] - 2.0 * d +
				 1.0 / depth[(size_t)(y + 1) * w + x]) > SMOOTH_INV_Z)
				return 0;
		}
	return 1;
}

/* Solves the 3 x 3 system m x = t; 0 where it is singular. */
static void solve3(const double m[3][3], const double t[3], double x[3])
{
	if (synth_solve3(m, t, x, 0.0))
		x[0] = x[1] = x[2] = 0.0;
}

int synth_pattern_measure(const float *ao, const float *depth, int w, int h,
			  struct synth_pattern *out)
{
	static const int ndx[NEIGH] = { -1, 0, 1, -1, 1, -1, 0, 1 };
	static const int ndy[NEIGH] = { -1, -1, -1, 0, 0, 1, 1, 1 };
	struct wave waves[SYNTH_PATTERN_FREQS][1 + NEIGH];
	for (int f = 0; f < SYNTH_PATTERN_FREQS; f++) {
		wave_init(&waves[f][0], synth_pattern_freq[f][0], synth_pattern_freq[f][1]);
		for (int k = 0; k < NEIGH; k++)
			wave_init(&waves[f][1 + k], synth_pattern_freq[f][0] + ndx[k] * OFFSET_BINS / WIN,
				  synth_pattern_freq[f][1] + ndy[k] * OFFSET_BINS / WIN);
	}
	double hann[WIN], hsum = 0.0;
	for (int i = 0; i < WIN; i++)
		hann[i] = 0.5 - 0.5 * cos(2.0 * SYNTH_PI * (i + 0.5) / WIN);
	for (int i = 0; i < WIN; i++)
		hsum += hann[i];

	double peak[SYNTH_PATTERN_FREQS] = { 0 }, around[SYNTH_PATTERN_FREQS] = { 0 };
	memset(out, 0, sizeof *out);
	double v[WIN][WIN];
	for (int y0 = 0; y0 + WIN <= h; y0 += WIN / 2)
		for (int x0 = 0; x0 + WIN <= w; x0 += WIN / 2) {
			if (!window_qualifies(ao, depth, w, x0, y0))
				continue;
			/* the AO's least-squares plane over the pixels with depth; the
			 * others (holes) count as on the plane */
			double m[3][3] = { { 0 } }, t[3] = { 0 }, c[3];
			for (int y = 0; y < WIN; y++)
				for (int x = 0; x < WIN; x++) {
					if (!has_depth(depth, w, x0 + x, y0 + y))
						continue;
					const double a = ao[(size_t)(y0 + y) * w + x0 + x];
					const double r[3] = { 1.0, x - (WIN - 1) * 0.5, y - (WIN - 1) * 0.5 };
					for (int i = 0; i < 3; i++) {
						t[i] += r[i] * a;
						for (int j = 0; j < 3; j++)
							m[i][j] += r[i] * r[j];
					}
				}
			solve3((const double(*)[3])m, t, c);
			for (int y = 0; y < WIN; y++)
				for (int x = 0; x < WIN; x++) {
					const double a = ao[(size_t)(y0 + y) * w + x0 + x];
					const double plane = c[0] + c[1] * (x - (WIN - 1) * 0.5) +
							     c[2] * (y - (WIN - 1) * 0.5);
					v[y][x] = has_depth(depth, w, x0 + x, y0 + y)
							  ? (a - plane) * hann[x] * hann[y]
							  : 0.0;
				}
			for (int f = 0; f < SYNTH_PATTERN_FREQS; f++) {
				peak[f] += power((const double(*)[WIN])v, &waves[f][0]);
				double s = 0.0;
				for (int k = 0; k < NEIGH; k++)
					s += power((const double(*)[WIN])v, &waves[f][1 + k]);
				around[f] += s / NEIGH;
			}
			out->windows++;
		}
	if (!out->windows)
		return -ENOENT;
	for (int f = 0; f < SYNTH_PATTERN_FREQS; f++) {
		out->ratio[f] = peak[f] / (around[f] > 0.0 ? around[f] : 1e-300);
		/* a sinusoid of amplitude A gives |DFT| = A/2 sum(hann)^2; at
		 * frequencies whose components are 0 or 1/2 (a real wave,
		 * +-1 per pixel) A sum(hann)^2 */
		const int real_wave = fmodf(synth_pattern_freq[f][0], 0.5f) == 0.0f &&
				      fmodf(synth_pattern_freq[f][1], 0.5f) == 0.0f;
		out->amplitude[f] = (real_wave ? 1.0 : 2.0) * sqrt(peak[f] / out->windows) /
				    (hsum * hsum);
		if (out->ratio[f] > out->max_ratio) {
			out->max_ratio = out->ratio[f];
			out->max_index = f;
		}
	}
	return 0;
}
