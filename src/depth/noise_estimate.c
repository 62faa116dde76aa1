/* SPDX-License-Identifier: MIT */
/* The noise of a depth frame from the frame itself (see noise_estimate.h). */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/multiversion.h"
#include "depth/noise_estimate.h"

#define B DAO_NOISE_BLOCK
/* columns per chunk of a block row: the chunk's rows and sums live on the stack */
#define CHUNK 256

int dao_noise_grid_init(struct dao_noise_grid *g, int width, int height)
{
	*g = (struct dao_noise_grid){ .width = width, .height = height };
	g->bw = width / B, g->bh = height / B;
	g->cw = (g->bw + DAO_NOISE_CELL - 1) / DAO_NOISE_CELL;
	g->ch = (g->bh + DAO_NOISE_CELL - 1) / DAO_NOISE_CELL;
	if (g->cw < 1)
		g->cw = 1;
	if (g->ch < 1)
		g->ch = 1;
	const size_t nb = (size_t)g->bw * g->bh, nc = (size_t)g->cw * g->ch;
	g->block = malloc((DAO_NOISE_BLOCK_STATS * nb + 1) * sizeof(float));
	g->cell = malloc(DAO_NOISE_CELL_STATS * nc * sizeof(float));
	g->scratch = malloc(nc * sizeof(float));
	if (!g->block || !g->cell || !g->scratch) {
		dao_noise_grid_free(g);
		return -ENOMEM;
	}
	return 0;
}

void dao_noise_grid_free(struct dao_noise_grid *g)
{
	free(g->block);
	free(g->cell);
	free(g->scratch);
	g->block = g->cell = g->scratch = NULL;
}

static inline float med3(float a, float b, float c)
{
	const float lo = a < b ? a : b, hi = a < b ? b : a;
	const float m = hi < c ? hi : c;
	return lo > m ? lo : m;
}

/*
 * One chunk of a block row: 8 rows of `n` columns (whole blocks) from x0.
 * Per column the sums over the 8 rows, then per block over its 8 columns.
 * Simple loops over the columns, so that the compiler vectorises them.
 */
DAO_MULTIVERSION
static void chunk_stats(const float *z, int stride, int x0, int n, float *out)
{
	float w[B][CHUNK];
	float valid[CHUNK], e2[CHUNK], nz[CHUNK];
	double c0[CHUNK], cv[CHUNK], c2[CHUNK];
	for (int r = 0; r < B; r++) {
		const float *zr = z + (size_t)r * stride + x0;
		for (int x = 0; x < n; x++) {
			/* 1/z or 0, without a branch (a conditional division is not vectorised) */
			const float v = zr[x], has = (float)(v > 0.0f);
			w[r][x] = has / (v + (1.0f - has));
		}
	}
	for (int x = 0; x < n; x++) {
		valid[x] = 0.0f, e2[x] = 0.0f, nz[x] = 0.0f;
		c0[x] = 0.0, cv[x] = 0.0, c2[x] = 0.0;
	}
	for (int r = 0; r < B; r++) {
		const double v = r - 3.5;
		for (int x = 0; x < n; x++) {
			const double c = w[r][x];
			valid[x] += w[r][x] > 0.0f ? 1.0f : 0.0f;
			c0[x] += c;
			cv[x] += v * c;
			c2[x] += c * c;
		}
	}
	/* links down the columns between rows r and r + 1, rows r - 1 .. r + 2 in the block */
	for (int r = 1; r <= B - 3; r++)
		for (int x = 0; x < n; x++) {
			const float dm = w[r][x] - w[r - 1][x], d = w[r + 1][x] - w[r][x];
			const float dp = w[r + 2][x] - w[r + 1][x];
			const float e = d - med3(dm, d, dp);
			e2[x] += e * e;
			nz[x] += e != 0.0f ? 1.0f : 0.0f;
		}
	/* links along the rows between x and x + 1, x - 1 .. x + 2 in the block
	 * (the others weigh 0: a table, as a test of x keeps the loop scalar) */
	float inside[CHUNK];
	for (int x = 0; x < n; x++)
		inside[x] = (x & (B - 1)) >= 1 && (x & (B - 1)) <= B - 3 ? 1.0f : 0.0f;
	for (int r = 0; r < B; r++)
		for (int x = 1; x + 2 < n; x++) {
			const float dm = w[r][x] - w[r][x - 1], d = w[r][x + 1] - w[r][x];
			const float dp = w[r][x + 2] - w[r][x + 1];
			const float e = inside[x] * (d - med3(dm, d, dp));
			e2[x] += e * e;
			nz[x] += e != 0.0f ? 1.0f : 0.0f;
		}
	for (int b = 0; b < n / B; b++) {
		double s0 = 0.0, su = 0.0, sv = 0.0, s2 = 0.0;
		float nv = 0.0f, se = 0.0f, sn = 0.0f;
		for (int k = 0; k < B; k++) {
			const int x = b * B + k;
			s0 += c0[x], su += (k - 3.5) * c0[x], sv += cv[x], s2 += c2[x];
			nv += valid[x], se += e2[x], sn += nz[x];
		}
		float *o = out + DAO_NOISE_BLOCK_STATS * b;
		if (nv < (float)(B * B)) {
			o[0] = o[1] = o[2] = o[3] = o[4] = NAN;
			continue;
		}
		/* residual of the least-squares plane: sum u^2 = sum v^2 = 8 * 42 */
		const double ss = s2 - s0 * s0 / 64.0 - su * su / 336.0 - sv * sv / 336.0;
		o[0] = (float)sqrt((ss > 0.0 ? ss : 0.0) / 61.0);
		o[1] = sn > 0.0f ? sqrtf(se / sn) / DAO_NOISE_LINK_IID : 0.0f;
		o[2] = (float)(s0 / 64.0);
		/* the plane's slopes along x and y, 1/m per px */
		o[3] = (float)(su / 336.0);
		o[4] = (float)(sv / 336.0);
	}
}

void dao_noise_blocks(struct dao_noise_grid *g, const float *z, int by0, int by1)
{
	for (int by = by0; by < by1; by++)
		for (int bx0 = 0; bx0 < g->bw; bx0 += CHUNK / B) {
			const int nb = g->bw - bx0 < CHUNK / B ? g->bw - bx0 : CHUNK / B;
			chunk_stats(z + (size_t)by * B * g->width, g->width, bx0 * B, nb * B,
				    g->block + DAO_NOISE_BLOCK_STATS * ((size_t)by * g->bw + bx0));
		}
}

/* the k-th smallest of n values (reordered in place; quickselect, no
 * allocation: glibc's qsort takes memory from the heap for more than 1 KB) */
static float select_kth(float *v, int n, int k)
{
	int lo = 0, hi = n - 1;
	while (hi > lo) {
		const float pivot = v[lo + (hi - lo) / 2];
		int i = lo, j = hi;
		while (i <= j) {
			while (v[i] < pivot)
				i++;
			while (v[j] > pivot)
				j--;
			if (i <= j) {
				const float t = v[i];
				v[i] = v[j], v[j] = t;
				i++, j--;
			}
		}
		if (k <= j)
			hi = j;
		else if (k >= i)
			lo = i;
		else
			break;
	}
	return v[k];
}

/*
 * The median of a cell's few values (its blocks, its slope pairs) by rank:
 * the value with as many smaller ones (equal ones counted by their index)
 * as the median's rank.  n^2 comparisons, but no branch on the data:
 * quickselect's branches on 16 values are mispredicted about as often as
 * not and took as long as the blocks' statistics.  v has room for `cap`
 * values: the n .. cap - 1 take +inf (never smaller than, nor equal to, a
 * value), so that the comparisons run over a fixed count the compiler
 * vectorises whole.  The same value as median() (the same order
 * statistics).
 */
static inline float median_by_rank(float *v, int n, int cap)
{
	const int k = n / 2;
	float lo = 0.0f, hi = 0.0f;
	for (int j = n; j < cap; j++)
		v[j] = INFINITY;
	for (int i = 0; i < n; i++) {
		const float t = v[i];
		int rank = 0;
		for (int j = 0; j < cap; j++)
			rank += (v[j] < t) | ((v[j] == t) & (j < i));
		hi = rank == k ? t : hi;
		lo = rank == k - 1 ? t : lo;
	}
	return n & 1 ? hi : 0.5f * (lo + hi);
}

#define NB (DAO_NOISE_CELL * DAO_NOISE_CELL) /* blocks in a cell */

DAO_MULTIVERSION
static float median_blocks(float *v, int n)
{
	return median_by_rank(v, n, NB);
}

DAO_MULTIVERSION
static float median_pairs(float *v, int n)
{
	return median_by_rank(v, n, 4 * NB);
}

/* median of n values (reordered in place) */
static float median(float *v, int n)
{
	const float hi = select_kth(v, n, n / 2);
	if (n & 1)
		return hi;
	float lo = v[0]; /* the largest of the lower half */
	for (int i = 1; i < n / 2; i++)
		lo = v[i] > lo ? v[i] : lo;
	return 0.5f * (lo + hi);
}

/* Cells without a value (NAN) take the mean of their neighbours that have
 * one, round after round; what is still empty then takes `fallback`. */
static void fill_empty(struct dao_noise_grid *g, float *v, float fallback)
{
	const int cw = g->cw, ch = g->ch;
	for (int round = 0; round < cw + ch; round++) {
		int empty = 0;
		memcpy(g->scratch, v, (size_t)cw * ch * sizeof(float));
		for (int cy = 0; cy < ch; cy++)
			for (int cx = 0; cx < cw; cx++) {
				if (!isnan(g->scratch[cy * cw + cx]))
					continue;
				float s = 0.0f;
				int n = 0;
				for (int dy = -1; dy <= 1; dy++)
					for (int dx = -1; dx <= 1; dx++) {
						const int x = cx + dx, y = cy + dy;
						if (x < 0 || y < 0 || x >= cw || y >= ch)
							continue;
						const float t = g->scratch[y * cw + x];
						if (!isnan(t))
							s += t, n++;
					}
				if (n)
					v[cy * cw + cx] = s / (float)n;
				else
					empty++;
			}
		if (!empty)
			return;
	}
	for (int i = 0; i < cw * ch; i++)
		if (isnan(v[i]))
			v[i] = fallback;
}

/*
 * The slope differences of block (bx, by) with its right and lower
 * neighbours, where both are usable: both slopes each way (4 values), into v.
 */
static int slope_pairs(const struct dao_noise_grid *g, int bx, int by, float *v)
{
	const float *b = g->block + DAO_NOISE_BLOCK_STATS * ((size_t)by * g->bw + bx);
	int n = 0;
	if (isnan(b[0]))
		return 0;
	const float *nb[2] = {
		bx + 1 < g->bw ? b + DAO_NOISE_BLOCK_STATS : NULL,
		by + 1 < g->bh ? b + DAO_NOISE_BLOCK_STATS * (size_t)g->bw : NULL,
	};
	for (int k = 0; k < 2; k++)
		if (nb[k] && !isnan(nb[k][0])) {
			v[n++] = fabsf(b[3] - nb[k][3]);
			v[n++] = fabsf(b[4] - nb[k][4]);
		}
	return n;
}

/*
 * The usable blocks of cell (cx, cy): their area, link and mean 1/z into
 * va, vl, vw (n of them, returned) and, with vs, their slope pairs with the
 * blocks right and below (*ns values).
 */
static int cell_blocks(const struct dao_noise_grid *g, int cx, int cy, float *va, float *vl,
		       float *vw, float *vs, int *ns)
{
	int n = 0;
	for (int by = cy * DAO_NOISE_CELL; by < (cy + 1) * DAO_NOISE_CELL && by < g->bh; by++)
		for (int bx = cx * DAO_NOISE_CELL; bx < (cx + 1) * DAO_NOISE_CELL && bx < g->bw; bx++) {
			const float *b = g->block + DAO_NOISE_BLOCK_STATS * ((size_t)by * g->bw + bx);
			if (isnan(b[0]))
				continue;
			va[n] = b[0], vl[n] = b[1], vw[n] = b[2];
			n++;
			if (vs)
				*ns += slope_pairs(g, bx, by, vs + *ns);
		}
	return n;
}

void dao_noise_cell_rows(struct dao_noise_grid *g, int cy0, int cy1)
{
	const int cw = g->cw, nc = cw * g->ch;
	float *area = g->cell, *link = g->cell + nc, *wm = g->cell + 2 * nc;
	float *slope = g->cell + 3 * nc;
	float va[NB], vl[NB], vw[NB], vs[4 * NB];
	for (int cy = cy0; cy < cy1; cy++)
		for (int cx = 0; cx < cw; cx++) {
			int ns = 0;
			const int n = cell_blocks(g, cx, cy, va, vl, vw, vs, &ns);
			const int i = cy * cw + cx;
			slope[i] = ns >= DAO_NOISE_MIN_BLOCKS ? median_pairs(vs, ns) / DAO_NOISE_SLOPE_IID : NAN;
			if (n < DAO_NOISE_MIN_BLOCKS) {
				area[i] = link[i] = wm[i] = slope[i] = NAN;
				continue;
			}
			area[i] = median_blocks(va, n);
			link[i] = median_blocks(vl, n);
			wm[i] = median_blocks(vw, n);
		}
}

int dao_noise_cell_measure(struct dao_noise_grid *g, const float *z, int cx, int cy,
			   float *link, float *w)
{
	const int bx0 = cx * DAO_NOISE_CELL, by0 = cy * DAO_NOISE_CELL;
	const int nb = g->bw - bx0 < DAO_NOISE_CELL ? g->bw - bx0 : DAO_NOISE_CELL;
	for (int by = by0; by < by0 + DAO_NOISE_CELL && by < g->bh; by++)
		chunk_stats(z + (size_t)by * B * g->width, g->width, bx0 * B, nb * B,
			    g->block + DAO_NOISE_BLOCK_STATS * ((size_t)by * g->bw + bx0));
	float va[NB], vl[NB], vw[NB];
	const int n = cell_blocks(g, cx, cy, va, vl, vw, NULL, NULL);
	if (n < DAO_NOISE_MIN_BLOCKS)
		return 0;
	*link = median_blocks(vl, n);
	*w = median_blocks(vw, n);
	return 1;
}

void dao_noise_cells_finish(struct dao_noise_grid *g)
{
	const int nc = g->cw * g->ch;
	float *area = g->cell, *link = g->cell + nc, *wm = g->cell + 2 * nc;
	float *slope = g->cell + 3 * nc;
	g->usable_cells = 0;
	for (int i = 0; i < nc; i++)
		g->usable_cells += !isnan(area[i]);
	/* the frame: medians over the usable cells (the scratch holds a copy) */
	float *tmp = g->scratch;
	float *planes[4] = { area, link, wm, slope };
	float *frame[4] = { &g->frame_area, &g->frame_link, &g->frame_w, &g->frame_slope };
	for (int k = 0; k < 4; k++) {
		int n = 0;
		for (int i = 0; i < nc; i++)
			if (!isnan(planes[k][i]))
				tmp[n++] = planes[k][i];
		*frame[k] = n ? median(tmp, n) : NAN;
	}
	if (!g->usable_cells)
		return;
	/* usable blocks but no two side by side: the slopes' noise as the residual's */
	if (isnan(g->frame_slope))
		g->frame_slope = g->frame_area;
	for (int k = 0; k < 4; k++)
		fill_empty(g, planes[k], *frame[k]);
}

void dao_noise_cells(struct dao_noise_grid *g)
{
	dao_noise_cell_rows(g, 0, g->ch);
	dao_noise_cells_finish(g);
}
