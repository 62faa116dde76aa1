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

static void match_band(void *ctx, int band, int y0, int y1)
{
	struct job *j = ctx;
	const struct synth_match_options *o = j->o;
	const int w = j->w, h = j->h, r = o->window / 2, wr = o->right_width;
	const float n = (float)(o->window * o->window);
	const int rows = y1 - y0 + 2 * r;
	float *hs = malloc((size_t)rows * w * sizeof(float));
	float *vs = malloc((size_t)w * sizeof(float));
	float *best = malloc((size_t)(y1 - y0) * w * sizeof(float) * 6);
	float *rbest = o->left_right ? malloc((size_t)(y1 - y0) * wr * sizeof(float) * 2) : NULL;
	if (!hs || !vs || !best || (o->left_right && !rbest)) {
		free(hs), free(vs), free(best), free(rbest);
		j->failed[band] = 1;
		return;
	}
	const size_t np = (size_t)(y1 - y0) * w;
	float *bs = best, *bd = best + np, *sm = best + 2 * np, *sp = best + 3 * np;
	float *s2 = best + 4 * np, *prev = best + 5 * np;
	for (size_t i = 0; i < np; i++)
		bs[i] = -2.0f, bd[i] = NAN, sm[i] = NAN, sp[i] = NAN, s2[i] = -2.0f, prev[i] = NAN;
	float *rs = rbest, *rd = rbest ? rbest + (size_t)(y1 - y0) * wr : NULL;
	if (rbest)
		for (size_t i = 0; i < (size_t)(y1 - y0) * wr; i++)
			rs[i] = -2.0f, rd[i] = NAN;
	for (int d = o->dmin; d <= o->dmax; d++) {
		/* horizontal sums of L(u) R(u - d + off) over rows y0 - r .. y1 + r */
		const int shift = o->right_offset - d;
		/* columns u whose whole window pairs with right columns inside the image */
		int ulo = r - shift > r ? r - shift : r;
		int uhi = wr - 1 - r - shift < w - 1 - r ? wr - 1 - r - shift : w - 1 - r;
		for (int yy = 0; yy < rows; yy++) {
			int y = y0 - r + yy;
			float *out = hs + (size_t)yy * w;
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
		if (ulo > uhi)
			continue;
		for (int y = y0; y < y1; y++) {
			if (y < r || y >= h - r)
				continue;
			const int yy = y - y0 + r;
			/*
			 * Vertical window sums: summed afresh at the first row of the band
			 * and every VSUM_BLOCK rows (band limits are multiples of it), else
			 * updated from the row above: the same arithmetic for a row
			 * whatever the bands, so the result does not depend on them.
			 */
			if (y == y0 || y % VSUM_BLOCK == 0 || y - 1 < r) {
				for (int u = ulo; u <= uhi; u++) {
					float s = 0;
					for (int k = -r; k <= r; k++)
						s += hs[(size_t)(yy + k) * w + u];
					vs[u] = s;
				}
			} else {
				const float *add = hs + (size_t)(yy + r) * w, *sub = hs + (size_t)(yy - r - 1) * w;
				for (int u = ulo; u <= uhi; u++)
					vs[u] += add[u] - sub[u];
			}
			const size_t row = (size_t)(y - y0) * w;
			const float *ml = j->mean_l + (size_t)y * w, *il = j->inv_l + (size_t)y * w;
			const float *mr = j->mean_r + (size_t)y * wr + shift, *ir = j->inv_r + (size_t)y * wr + shift;
			for (int u = ulo; u <= uhi; u++) {
				const size_t i = row + (size_t)u;
				float c = (vs[u] - n * ml[u] * mr[u]) * il[u] * ir[u];
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
				if (rbest) {
					const size_t ri = (size_t)(y - y0) * wr + (size_t)(u + shift);
					if (c > rs[ri])
						rs[ri] = c, rd[ri] = (float)d;
				}
			}
			/* pixels this disparity does not reach lose their "previous" score */
			for (int u = 0; u < ulo; u++)
				prev[row + u] = NAN;
			for (int u = uhi + 1; u < w; u++)
				prev[row + u] = NAN;
		}
	}
	for (int y = y0; y < y1; y++)
		for (int u = 0; u < w; u++) {
			const size_t i = (size_t)(y - y0) * w + u, o_i = (size_t)y * w + u;
			float disp = NAN;
			if (!isnan(bd[i]) && !isnan(sm[i]) && !isnan(sp[i])) {
				float den = sm[i] - 2.0f * bs[i] + sp[i];
				float delta = den < 0 ? 0.5f * (sm[i] - sp[i]) / den : 0.0f;
				delta = fmaxf(-0.5f, fminf(0.5f, delta));
				disp = bd[i] + delta;
			}
			j->m->disparity[o_i] = disp;
			j->m->score[o_i] = bs[i];
			j->m->second[o_i] = s2[i];
		}
	if (rbest)
		for (int y = y0; y < y1; y++)
			memcpy(j->m->right_disparity + (size_t)y * wr, rd + (size_t)(y - y0) * wr,
			       (size_t)wr * sizeof(float));
	free(hs), free(vs), free(best), free(rbest);
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
