/* SPDX-License-Identifier: MIT */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/error.h>
#include "synth/robust.h"
#include "synth/sensor_stats.h"

#define EDGE_JUMP 0.05      /* a hole run lies on a depth edge if its sides differ by > 5 % */
#define MAX_SHADOW_RUN 48   /* px; longer hole runs are missing surfaces, not shadows */
#define FLY_JUMP 0.10       /* flying pixels: triples spanning a > 10 % jump ... */
#define FLY_MARGIN 0.15     /* ... whose middle lies > 15 % of the jump inside both sides */
#define FLY_FLAT 0.02       /* ... and whose sides are flat (2 %) for another pixel */
#define LEVEL_MIN_GAP 8     /* units: finer level steps are distorted by rounding */
#define SHADOW_B_MIN 0.02   /* m: hole runs implying a baseline in this range are shadows */
#define SHADOW_B_MAX 0.15
#define SHADOW_MIN_RUN 4    /* px: shorter runs are as often the failed matches of mixed
			       windows on either side of an edge */

int synth_plane_residual_map(const float *z, const struct dao_camera *cam,
			     const struct synth_plane *planes, const int32_t *labels, float *out)
{
	const int w = (int)cam->width, h = (int)cam->height;
	int32_t *lab = malloc((size_t)w * h * sizeof(int32_t));
	if (!lab)
		return -ENOMEM;
	memcpy(lab, labels, (size_t)w * h * sizeof(int32_t));
	if (synth_labels_erode(lab, w, h, SYNTH_STATS_ERODE)) {
		free(lab);
		return -ENOMEM;
	}
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			size_t i = (size_t)y * w + x;
			out[i] = lab[i] >= 0 ? (float)(1.0 / z[i] - synth_plane_w(&planes[lab[i]], cam, x, y))
					     : NAN;
		}
	free(lab);
	return 0;
}

/* Normalised autocorrelation of r along rows (dx = 1) or columns, within one region. */
static void autocorr(const float *r, const int32_t *lab, int w, int h, int dx, int dy,
		     double *acf)
{
	for (int k = 0; k <= SYNTH_STATS_LAGS; k++) {
		double sab = 0, saa = 0, sbb = 0;
		for (int y = 0; y + k * dy < h; y++)
			for (int x = 0; x + k * dx < w; x++) {
				size_t i = (size_t)y * w + x, j = i + (size_t)(k * dx) + (size_t)(k * dy) * w;
				if (lab[i] < 0 || lab[i] != lab[j])
					continue;
				sab += (double)r[i] * r[j];
				saa += (double)r[i] * r[i];
				sbb += (double)r[j] * r[j];
			}
		acf[k] = saa > 0 && sbb > 0 ? sab / sqrt(saa * sbb) : 0.0;
	}
}

/* First lag (linearly interpolated) where acf falls below 1/e; LAGS if never. */
static double corr_length(const double *acf)
{
	const double t = exp(-1.0);
	for (int k = 1; k <= SYNTH_STATS_LAGS; k++)
		if (acf[k] < t)
			return k - 1 + (acf[k - 1] - t) / (acf[k - 1] - acf[k]);
	return SYNTH_STATS_LAGS;
}

static int cmp_i32(const void *a, const void *b)
{
	int32_t x = *(const int32_t *)a, y = *(const int32_t *)b;
	return (x > y) - (x < y);
}

/*
 * Distinct depth levels per bin: the values (in source counts) held by at
 * least 0.1 % of the bin's pixels (and 5), the median step between adjacent
 * ones, and f b / q from each adjacent pair.  The frame counts as banded when
 * most adjacent populated levels have an empty one between them.
 */
static int levels(const float *z, size_t np, double unit, struct synth_sensor_stats *s)
{
	if (!(unit > 0))
		return 0;
	int32_t *v = malloc(np * sizeof(int32_t));
	float *gaps = malloc(np * sizeof(float)), *cs = malloc(np * sizeof(float));
	float *all_c = malloc(np * sizeof(float));
	if (!v || !gaps || !cs || !all_c) {
		free(v), free(gaps), free(cs), free(all_c);
		return -ENOMEM;
	}
	size_t n = 0, nall = 0, pairs = 0, sparse = 0;
	for (size_t i = 0; i < np; i++)
		if (z[i] > 0.0f)
			v[n++] = (int32_t)lrint(z[i] / unit);
	qsort(v, n, sizeof *v, cmp_i32);
	size_t i = 0;
	for (int b = 0; b < SYNTH_STATS_ZBINS; b++) {
		const double hi = (b + 1) * SYNTH_STATS_ZBIN;
		size_t start = i;
		while (i < n && v[i] * unit < hi)
			i++;
		size_t count = i - start;
		long need = (long)(0.001 * (double)count);
		if (need < 5)
			need = 5;
		int nlev = 0, ng = 0;
		int32_t prev = -1;
		for (size_t k = start; k < i;) {
			size_t e = k;
			while (e < i && v[e] == v[k])
				e++;
			if ((long)(e - k) >= need) {
				if (prev >= 0) {
					double z1 = prev * unit, z2 = v[k] * unit;
					pairs++;
					sparse += v[k] - prev >= 2;
					gaps[ng] = (float)(z2 - z1);
					cs[ng] = (float)(z1 * z2 / (z2 - z1));
					if (v[k] - prev >= LEVEL_MIN_GAP)
						all_c[nall++] = cs[ng];
					ng++;
				}
				prev = v[k];
				nlev++;
			}
			k = e;
		}
		struct synth_zbin_stats *zb = &s->bin[b];
		zb->levels = nlev;
		zb->gap = ng >= 3 ? synth_median(gaps, (size_t)ng) : 0.0;
		zb->band_c = ng >= 3 ? synth_median(cs, (size_t)ng) : 0.0;
	}
	/* banded: most populated levels have empty ones between them */
	const int banded = nall >= 3 && 2 * sparse > pairs;
	s->band_pairs = banded ? (long)nall : 0;
	s->band_c = banded ? synth_median(all_c, nall) : 0.0;
	free(v), free(gaps), free(cs), free(all_c);
	return 0;
}

int synth_band_constant(const float *z, int w, int h, double depth_unit, double *band_c)
{
	struct synth_sensor_stats s;
	memset(&s, 0, sizeof s);
	int r = levels(z, (size_t)w * h, depth_unit, &s);
	*band_c = s.band_c;
	return r;
}

/*
 * Holes along rows between a near and a far side.  A projector (or second
 * camera) b metres beside the camera hides a run of f b (1/z_near - 1/z_far)
 * px of the background next to a foreground edge, on the side away from it;
 * b_app = run length / (f (1/z_near - 1/z_far)) is the baseline a run
 * implies, and runs with b_app in [SHADOW_B_MIN, SHADOW_B_MAX] count as
 * shadows, by the side of the run their near side lies on.
 */
static void holes(const float *z, int w, int h, double f, struct synth_sensor_stats *s,
		  float *runs, float *bapp)
{
	long nh = 0, edge_holes = 0;
	size_t nruns = 0;
	for (size_t i = 0; i < (size_t)w * h; i++)
		nh += !(z[i] > 0.0f);
	for (int y = 0; y < h; y++) {
		const float *row = z + (size_t)y * w;
		for (int x = 1; x < w - 1; x++) {
			/*
			 * Flying pixels: a pixel between the two sides of a step, each
			 * side flat for two pixels (a slanted surface is a ramp instead)
			 */
			float a = row[x - 1], m = row[x], b = row[x + 1];
			if (x >= 2 && x < w - 2 && a > 0 && m > 0 && b > 0 && fabsf(a - b) > FLY_JUMP * m) {
				float a2 = row[x - 2], b2 = row[x + 2];
				if (a2 > 0 && b2 > 0 && fabsf(a2 - a) < FLY_FLAT * a && fabsf(b2 - b) < FLY_FLAT * b) {
					s->edge_pixels++;
					float lo = fminf(a, b), hi = fmaxf(a, b), margin = FLY_MARGIN * (hi - lo);
					s->flying_pixels += m > lo + margin && m < hi - margin;
				}
			}
			/* a hole run starting at x */
			if (row[x] > 0.0f || row[x - 1] <= 0.0f)
				continue;
			int e = x;
			while (e < w && row[e] <= 0.0f)
				e++;
			if (e < w && e - x <= MAX_SHADOW_RUN) {
				float l = row[x - 1], r = row[e];
				float zn = fminf(l, r), zf = fmaxf(l, r);
				if (zf - zn > EDGE_JUMP * zn) {
					edge_holes += e - x;
					double b_app = (e - x) / (f * (1.0 / zn - 1.0 / zf));
					if (b_app >= SHADOW_B_MIN && b_app <= SHADOW_B_MAX &&
					    e - x >= SHADOW_MIN_RUN) {
						if (r < l)
							s->shadow_left++;
						else
							s->shadow_right++;
						runs[nruns] = (float)(e - x);
						bapp[nruns++] = (float)b_app;
					}
				}
			}
			x = e - 1;
		}
	}
	s->hole_fraction = (double)nh / ((double)w * h);
	s->edge_hole_fraction = nh ? (double)edge_holes / (double)nh : 0.0;
	s->shadow_width = synth_median(runs, nruns);
	s->shadow_baseline = synth_median(bapp, nruns);
}

int synth_sensor_stats(const float *z, const struct dao_camera *cam, double depth_unit,
		       const struct synth_plane *planes, int nplanes, const int32_t *labels,
		       struct synth_sensor_stats *s, struct dao_error *err)
{
	const int w = (int)cam->width, h = (int)cam->height;
	const size_t np = (size_t)w * h;
	memset(s, 0, sizeof *s);
	s->planes = nplanes;
	float *r = malloc(np * sizeof(float)), *scratch = malloc(np * sizeof(float));
	float *rz = malloc(np * sizeof(float));
	int32_t *lab = malloc(np * sizeof(int32_t));
	int ret = 0;
	if (!r || !scratch || !rz || !lab) {
		ret = -ENOMEM;
		goto out;
	}
	memcpy(lab, labels, np * sizeof(int32_t));
	if (synth_labels_erode(lab, w, h, SYNTH_STATS_ERODE)) {
		ret = -ENOMEM;
		goto out;
	}
	/* residuals: 1/z and depth; per plane the mean taken out and outliers clipped at 4 sigma */
	double mean[SYNTH_PLANES_MAX] = { 0 };
	long cnt[SYNTH_PLANES_MAX] = { 0 };
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			size_t i = (size_t)y * w + x;
			if (lab[i] < 0)
				continue;
			double wp = synth_plane_w(&planes[lab[i]], cam, x, y);
			r[i] = (float)(1.0 / z[i] - wp);
			rz[i] = wp > 0 ? (float)(z[i] - 1.0 / wp) : 0.0f;
			mean[lab[i]] += r[i];
			cnt[lab[i]]++;
		}
	for (int p = 0; p < nplanes; p++)
		mean[p] = cnt[p] ? mean[p] / cnt[p] : 0.0;
	size_t n = 0;
	for (size_t i = 0; i < np; i++)
		if (lab[i] >= 0) {
			r[i] -= (float)mean[lab[i]];
			scratch[n++] = r[i];
		}
	s->plane_pixels = (long)n;
	s->sigma_w = synth_robust_sigma(scratch, n);
	const float clip = 4.0f * (float)s->sigma_w;
	for (size_t i = 0; i < np; i++)
		if (lab[i] >= 0)
			r[i] = fminf(fmaxf(r[i], -clip), clip);
	/* amplitude per depth bin */
	for (int b = 0; b < SYNTH_STATS_ZBINS; b++) {
		const double lo = b * SYNTH_STATS_ZBIN, hi = lo + SYNTH_STATS_ZBIN;
		size_t m = 0;
		for (size_t i = 0; i < np; i++)
			if (lab[i] >= 0 && z[i] >= lo && z[i] < hi)
				scratch[m++] = rz[i];
		s->bin[b].pixels = (long)m;
		s->bin[b].sigma_z = synth_robust_sigma(scratch, m);
		m = 0;
		for (size_t i = 0; i < np; i++)
			if (lab[i] >= 0 && z[i] >= lo && z[i] < hi)
				scratch[m++] = r[i];
		s->bin[b].sigma_w = synth_robust_sigma(scratch, m);
	}
	autocorr(r, lab, w, h, 1, 0, s->acf_row);
	autocorr(r, lab, w, h, 0, 1, s->acf_col);
	s->corr_len_row = corr_length(s->acf_row);
	s->corr_len_col = corr_length(s->acf_col);
	if (levels(z, np, depth_unit, s)) {
		ret = -ENOMEM;
		goto out;
	}
	holes(z, w, h, cam->fx, s, scratch, rz);
out:
	free(r);
	free(scratch);
	free(rz);
	free(lab);
	return ret ? dao_error_set(err, ret, "out of memory measuring the frame") : 0;
}

void synth_stats_acc_begin(struct synth_stats_acc *a)
{
	memset(a, 0, sizeof *a);
}

void synth_stats_acc_add(struct synth_stats_acc *a, const struct synth_sensor_stats *s)
{
	struct synth_sensor_stats *t = &a->sum;
	const double wp = (double)s->plane_pixels;
	t->planes += s->planes;
	t->plane_pixels += s->plane_pixels;
	t->sigma_w += wp * s->sigma_w;
	a->w_sigma += wp;
	for (int k = 0; k <= SYNTH_STATS_LAGS; k++) {
		t->acf_row[k] += wp * s->acf_row[k];
		t->acf_col[k] += wp * s->acf_col[k];
	}
	a->w_acf += wp;
	for (int b = 0; b < SYNTH_STATS_ZBINS; b++) {
		const struct synth_zbin_stats *zb = &s->bin[b];
		struct synth_zbin_stats *tb = &t->bin[b];
		tb->pixels += zb->pixels;
		tb->sigma_z += (double)zb->pixels * zb->sigma_z;
		tb->sigma_w += (double)zb->pixels * zb->sigma_w;
		a->w_bin[b] += (double)zb->pixels;
		if (zb->gap > 0) {
			tb->levels += zb->levels;
			tb->gap += zb->gap;
			tb->band_c += zb->band_c;
			a->w_gap[b] += 1.0;
		}
	}
	t->band_c += (double)s->band_pairs * s->band_c;
	t->band_pairs += s->band_pairs;
	t->hole_fraction += s->hole_fraction;
	t->edge_hole_fraction += s->edge_hole_fraction;
	const long runs = s->shadow_left + s->shadow_right;
	t->shadow_left += s->shadow_left;
	t->shadow_right += s->shadow_right;
	t->shadow_width += (double)runs * s->shadow_width;
	t->shadow_baseline += (double)runs * s->shadow_baseline;
	a->w_shadow += (double)runs;
	t->edge_pixels += s->edge_pixels;
	t->flying_pixels += s->flying_pixels;
	a->frames++;
}

void synth_stats_acc_end(struct synth_stats_acc *a, struct synth_sensor_stats *out)
{
	*out = a->sum;
	const double f = a->frames ? (double)a->frames : 1.0;
	if (a->w_sigma > 0)
		out->sigma_w /= a->w_sigma;
	if (a->w_acf > 0)
		for (int k = 0; k <= SYNTH_STATS_LAGS; k++) {
			out->acf_row[k] /= a->w_acf;
			out->acf_col[k] /= a->w_acf;
		}
	out->corr_len_row = corr_length(out->acf_row);
	out->corr_len_col = corr_length(out->acf_col);
	for (int b = 0; b < SYNTH_STATS_ZBINS; b++) {
		struct synth_zbin_stats *tb = &out->bin[b];
		if (a->w_bin[b] > 0) {
			tb->sigma_z /= a->w_bin[b];
			tb->sigma_w /= a->w_bin[b];
		}
		if (a->w_gap[b] > 0) {
			tb->levels = (int)lrint(tb->levels / a->w_gap[b]);
			tb->gap /= a->w_gap[b];
			tb->band_c /= a->w_gap[b];
		}
	}
	if (out->band_pairs > 0)
		out->band_c /= (double)out->band_pairs;
	out->hole_fraction /= f;
	out->edge_hole_fraction /= f;
	if (a->w_shadow > 0) {
		out->shadow_width /= a->w_shadow;
		out->shadow_baseline /= a->w_shadow;
	}
}
