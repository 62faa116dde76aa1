/* SPDX-License-Identifier: MIT */
/*
 * ZNCC block matching by box sums: for each disparity d the products
 * L(u) R(u - d) are summed over the window with running sums (a horizontal
 * then a vertical pass), so the cost per pixel and disparity is a few
 * operations whatever the window.  With window means m and standard
 * deviations s over n pixels,
 *     ZNCC = (sum L R - n mL mR) / (n sL sR).
 */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "synth/block_match.h"
#include "synth/parallel.h"

#define VSUM_BLOCK 16

struct job {
	const float *left, *right;
	int w, h;
	const struct synth_match_options *o;
	struct synth_match *m;
	const float *mean_l, *inv_l, *mean_r, *inv_r;
	int failed[64];          /* per band: out of memory */
};

int synth_window_stats(const float *img, int w, int h, int win, float *mean, float *inv,
			float *sdev)
{
	const int r = win / 2;
	const double n = (double)win * win;
	double *hs = malloc((size_t)w * h * sizeof(double)), *hq = malloc((size_t)w * h * sizeof(double));
	if (!hs || !hq) {
		free(hs);
		free(hq);
		return -ENOMEM;
	}
	for (int y = 0; y < h; y++) {
		const float *row = img + (size_t)y * w;
		for (int x = r; x < w - r; x++) {
			double s = 0, q = 0;
			for (int k = -r; k <= r; k++) {
				s += row[x + k];
				q += (double)row[x + k] * row[x + k];
			}
			hs[(size_t)y * w + x] = s;
			hq[(size_t)y * w + x] = q;
		}
	}
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			size_t i = (size_t)y * w + x;
			mean[i] = 0, inv[i] = 0;
			if (sdev)
				sdev[i] = 0;
			if (x < r || x >= w - r || y < r || y >= h - r)
				continue;
			double s = 0, q = 0;
			for (int k = -r; k <= r; k++) {
				s += hs[i + (size_t)((long)k * w)];
				q += hq[i + (size_t)((long)k * w)];
			}
			double mu = s / n, var = q / n - mu * mu;
			mean[i] = (float)mu;
			if (sdev)
				sdev[i] = var > 0 ? (float)sqrt(var) : 0.0f;
			inv[i] = var > 1e-12 ? (float)(1.0 / sqrt(n * var)) : 0.0f;
		}
	free(hs);
	free(hq);
	return 0;
}

/* One band's scratch: window sums and, per pixel, the best scores so far. */
struct band {
	int y0, y1, rows;     /* rows of the band; rows of horizontal sums (with the margins) */
	float *hs, *vs;       /* horizontal sums of the band's rows; vertical sums of a row */
	float *best;          /* the allocation of bs .. prev */
	float *bs, *bd;       /* best score and its disparity */
	float *sm, *sp;       /* the scores at the best disparity - 1 and + 1 */
	float *s2, *prev;     /* the best score away from the peak; the previous disparity's */
	float *rbest, *rs, *rd; /* left-right check: best score and disparity per right pixel */
};

static void band_free(struct band *b)
{
	free(b->hs), free(b->vs), free(b->best), free(b->rbest);
}

static int band_alloc(struct band *b, const struct job *j, int y0, int y1)
{
	const struct synth_match_options *o = j->o;
	const int w = j->w, r = o->window / 2, wr = o->right_width;
	b->y0 = y0, b->y1 = y1, b->rows = y1 - y0 + 2 * r;
	b->hs = malloc((size_t)b->rows * w * sizeof(float));
	b->vs = malloc((size_t)w * sizeof(float));
	b->best = malloc((size_t)(y1 - y0) * w * sizeof(float) * 6);
	b->rbest = o->left_right ? malloc((size_t)(y1 - y0) * wr * sizeof(float) * 2) : NULL;
	if (!b->hs || !b->vs || !b->best || (o->left_right && !b->rbest)) {
		band_free(b);
		return -ENOMEM;
	}
	const size_t np = (size_t)(y1 - y0) * w;
	b->bs = b->best, b->bd = b->best + np, b->sm = b->best + 2 * np, b->sp = b->best + 3 * np;
	b->s2 = b->best + 4 * np, b->prev = b->best + 5 * np;
	for (size_t i = 0; i < np; i++)
		b->bs[i] = -2.0f, b->bd[i] = NAN, b->sm[i] = NAN, b->sp[i] = NAN, b->s2[i] = -2.0f,
		b->prev[i] = NAN;
	b->rs = b->rbest, b->rd = b->rbest ? b->rbest + (size_t)(y1 - y0) * wr : NULL;
	if (b->rbest)
		for (size_t i = 0; i < (size_t)(y1 - y0) * wr; i++)
			b->rs[i] = -2.0f, b->rd[i] = NAN;
	return 0;
}

/* Horizontal sums of L(u) R(u + shift) over rows y0 - r .. y1 + r, columns ulo..uhi. */
static void horizontal_products(const struct job *j, struct band *b, int shift, int ulo, int uhi)
{
	const int w = j->w, h = j->h, r = j->o->window / 2, wr = j->o->right_width;
	for (int yy = 0; yy < b->rows; yy++) {
		int y = b->y0 - r + yy;
		float *out = b->hs + (size_t)yy * w;
		if (y < 0 || y >= h || ulo > uhi)
			continue;
		const float *L = j->left + (size_t)y * w, *R = j->right + (size_t)y * wr + shift;
		float s = 0;
		for (int k = ulo - r; k <= ulo + r; k++)
			s += L[k] * R[k];
		out[ulo] = s;
		for (int u = ulo + 1; u <= uhi; u++) {
			s += L[u + r] * R[u + r] - L[u - r - 1] * R[u - r - 1];
			out[u] = s;
		}
	}
}

/*
 * Vertical window sums of row y: summed afresh at the first row of the band
 * and every VSUM_BLOCK rows (band limits are multiples of it), else updated
 * from the row above: the same arithmetic for a row whatever the bands, so
 * the result does not depend on them.
 */
static void vertical_sums(const struct job *j, struct band *b, int y, int ulo, int uhi)
{
	const int w = j->w, r = j->o->window / 2;
	const int yy = y - b->y0 + r;
	if (y == b->y0 || y % VSUM_BLOCK == 0 || y - 1 < r) {
		for (int u = ulo; u <= uhi; u++) {
			float s = 0;
			for (int k = -r; k <= r; k++)
				s += b->hs[(size_t)(yy + k) * w + u];
			b->vs[u] = s;
		}
	} else {
		const float *add = b->hs + (size_t)(yy + r) * w, *sub = b->hs + (size_t)(yy - r - 1) * w;
		for (int u = ulo; u <= uhi; u++)
			b->vs[u] += add[u] - sub[u];
	}
}

/* The ZNCC of row y at disparity d, kept where it beats the best so far. */
static void score_row(const struct job *j, struct band *b, int y, int d, int shift, int ulo,
		      int uhi)
{
	const int w = j->w, wr = j->o->right_width;
	const float n = (float)(j->o->window * j->o->window);
	float *bs = b->bs, *bd = b->bd, *sm = b->sm, *sp = b->sp, *s2 = b->s2, *prev = b->prev;
	const size_t row = (size_t)(y - b->y0) * w;
	const float *ml = j->mean_l + (size_t)y * w, *il = j->inv_l + (size_t)y * w;
	const float *mr = j->mean_r + (size_t)y * wr + shift, *ir = j->inv_r + (size_t)y * wr + shift;
	for (int u = ulo; u <= uhi; u++) {
		const size_t i = row + (size_t)u;
		float c = (b->vs[u] - n * ml[u] * mr[u]) * il[u] * ir[u];
		if (!(il[u] > 0 && ir[u] > 0))
			c = -1.0f;
		if (c > bs[i]) {
			if (!isnan(bd[i]) && d > bd[i] + 1)
				s2[i] = fmaxf(s2[i], bs[i]);
			sm[i] = prev[i];
			sp[i] = NAN;
			bs[i] = c;
			bd[i] = (float)d;
		} else if (d == bd[i] + 1) {
			sp[i] = c;
		} else {
			s2[i] = fmaxf(s2[i], c);
		}
		prev[i] = c;
		if (b->rbest) {
			const size_t ri = (size_t)(y - b->y0) * wr + (size_t)(u + shift);
			if (c > b->rs[ri])
				b->rs[ri] = c, b->rd[ri] = (float)d;
		}
	}
	/* pixels this disparity does not reach lose their "previous" score */
	for (int u = 0; u < ulo; u++)
		prev[row + u] = NAN;
	for (int u = uhi + 1; u < w; u++)
		prev[row + u] = NAN;
}

/* The band's disparities refined by a parabola through the best score and its neighbours. */
static void write_band(const struct job *j, const struct band *b)
{
	const int w = j->w, wr = j->o->right_width;
	for (int y = b->y0; y < b->y1; y++)
		for (int u = 0; u < w; u++) {
			const size_t i = (size_t)(y - b->y0) * w + u, o_i = (size_t)y * w + u;
			float disp = NAN;
			if (!isnan(b->bd[i]) && !isnan(b->sm[i]) && !isnan(b->sp[i])) {
				float den = b->sm[i] - 2.0f * b->bs[i] + b->sp[i];
				float delta = den < 0 ? 0.5f * (b->sm[i] - b->sp[i]) / den : 0.0f;
				delta = fmaxf(-0.5f, fminf(0.5f, delta));
				disp = b->bd[i] + delta;
			}
			j->m->disparity[o_i] = disp;
			j->m->score[o_i] = b->bs[i];
			j->m->second[o_i] = b->s2[i];
		}
	if (b->rbest)
		for (int y = b->y0; y < b->y1; y++)
			memcpy(j->m->right_disparity + (size_t)y * wr, b->rd + (size_t)(y - b->y0) * wr,
			       (size_t)wr * sizeof(float));
}

static void match_band(void *ctx, int band, int y0, int y1)
{
	struct job *j = ctx;
	const struct synth_match_options *o = j->o;
	const int w = j->w, h = j->h, r = o->window / 2, wr = o->right_width;
	struct band b;
	if (band_alloc(&b, j, y0, y1)) {
		j->failed[band] = 1;
		return;
	}
	for (int d = o->dmin; d <= o->dmax; d++) {
		const int shift = o->right_offset - d;
		/* columns u whose whole window pairs with right columns inside the image */
		int ulo = r - shift > r ? r - shift : r;
		int uhi = wr - 1 - r - shift < w - 1 - r ? wr - 1 - r - shift : w - 1 - r;
		horizontal_products(j, &b, shift, ulo, uhi);
		if (ulo > uhi)
			continue;
		for (int y = y0; y < y1; y++) {
			if (y < r || y >= h - r)
				continue;
			vertical_sums(j, &b, y, ulo, uhi);
			score_row(j, &b, y, d, shift, ulo, uhi);
		}
	}
	write_band(j, &b);
	band_free(&b);
}

int synth_block_match(const float *left, const float *right, int w, int h,
		      const struct synth_match_options *o, int threads, struct synth_match *m)
{
	if (o->window < 3 || !(o->window & 1) || o->dmin < 0 || o->dmax < o->dmin ||
	    o->right_width < 1)
		return -EINVAL;
	const size_t nl = (size_t)w * h, nr = (size_t)o->right_width * h;
	float *ml = malloc(nl * sizeof(float)), *il = malloc(nl * sizeof(float));
	float *mr = malloc(nr * sizeof(float)), *ir = malloc(nr * sizeof(float));
	int ret = -ENOMEM;
	if (ml && il && mr && ir &&
	    !synth_window_stats(left, w, h, o->window, ml, il, m->texture) &&
	    !synth_window_stats(right, o->right_width, h, o->window, mr, ir, NULL)) {
		struct job j = { left, right, w, h, o, m, ml, il, mr, ir, { 0 } };
		synth_parallel_rows(h, threads, VSUM_BLOCK, match_band, &j);
		ret = 0;
		for (int k = 0; k < 64; k++)
			if (j.failed[k])
				ret = -ENOMEM;
	}
	free(ml), free(il), free(mr), free(ir);
	return ret;
}
