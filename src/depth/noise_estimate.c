/* SPDX-License-Identifier: MIT */
/* The noise of a depth frame from the frame itself (see noise_estimate.h). */
#include <errno.h>
#include <stdint.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/multiversion.h"
#include "depth/noise_estimate.h"

#define B DAO_NOISE_BLOCK
#define LANES 8 /* cells side by side in the medians */
/* columns per chunk of a block row: the chunk's rows and sums live on the stack */
#define CHUNK 256

static int batcher(int n, int scale, unsigned short (*net)[2]);

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
	g->row = dao_noise_row_ref;
	g->net_blocks_count = batcher(DAO_NOISE_CELL * DAO_NOISE_CELL, 3 * LANES, g->net_blocks);
	g->net_pairs_count = batcher(4 * DAO_NOISE_CELL * DAO_NOISE_CELL, LANES, g->net_pairs);
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
	 * (the others are 0: a table, as a test of x keeps the loop scalar; a
	 * select, not a product, so that a NaN or infinite 1/z of the block
	 * beside cannot make a usable block's link NaN) */
	float inside[CHUNK];
	for (int x = 0; x < n; x++)
		inside[x] = (x & (B - 1)) >= 1 && (x & (B - 1)) <= B - 3 ? 1.0f : 0.0f;
	for (int r = 0; r < B; r++)
		for (int x = 1; x + 2 < n; x++) {
			const float dm = w[r][x] - w[r][x - 1], d = w[r][x + 1] - w[r][x];
			const float dp = w[r][x + 2] - w[r][x + 1];
			const float e = inside[x] > 0.0f ? d - med3(dm, d, dp) : 0.0f;
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

void dao_noise_row_ref(const float *z, int stride, int nblocks, float *out)
{
	for (int bx0 = 0; bx0 < nblocks; bx0 += CHUNK / B) {
		const int nb = nblocks - bx0 < CHUNK / B ? nblocks - bx0 : CHUNK / B;
		chunk_stats(z, stride, bx0 * B, nb * B, out + DAO_NOISE_BLOCK_STATS * (size_t)bx0);
	}
}

void dao_noise_blocks(struct dao_noise_grid *g, const float *z, int by0, int by1)
{
	for (int by = by0; by < by1; by++)
		g->row(z + (size_t)by * B * g->width, g->width, g->bw,
		       g->block + DAO_NOISE_BLOCK_STATS * (size_t)by * g->bw);
}

void dao_noise_blocks_ref(struct dao_noise_grid *g, const float *z, int by0, int by1)
{
	for (int by = by0; by < by1; by++)
		dao_noise_row_ref(z + (size_t)by * B * g->width, g->width, g->bw,
				  g->block + DAO_NOISE_BLOCK_STATS * (size_t)by * g->bw);
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

/*
 * The cell's link: the median over its blocks with a non-zero link when
 * there are DAO_NOISE_MIN_BLOCKS of them, else over all n.  A block with no
 * non-zero difference lies on one band of quantised depth (a Kinect's
 * disparity step is 50 mm at 4 m): it has no link to measure, as a zero
 * difference has none inside a block.  Counted as 0, such blocks moved the
 * median between 0 and the step with the share of a cell the bands' edges
 * cross, which flickers from frame to frame (noise_estimate.h).  Reorders vl.
 */
static float median_links(float *vl, int n)
{
	int k = 0;
	for (int i = 0; i < n; i++) {
		const float t = vl[i];
		vl[i] = vl[k], vl[k] = t;
		k += t != 0.0f;
	}
	/* vl[0 .. k) the non-zero links */
	return k >= DAO_NOISE_MIN_BLOCKS ? median_blocks(vl, k) : median_blocks(vl, n);
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

/* One cell by the rank medians (the reference; dao_noise_cell_rows_ref). */
static void cell_rank_medians(struct dao_noise_grid *g, int cx, int cy)
{
	const int cw = g->cw, nc = cw * g->ch;
	float *area = g->cell, *link = g->cell + nc, *wm = g->cell + 2 * nc;
	float *slope = g->cell + 3 * nc;
	float va[NB], vl[NB], vw[NB], vs[4 * NB];
	int ns = 0;
	const int n = cell_blocks(g, cx, cy, va, vl, vw, vs, &ns);
	const int i = cy * cw + cx;
	slope[i] = ns >= DAO_NOISE_MIN_BLOCKS ? median_pairs(vs, ns) / DAO_NOISE_SLOPE_IID : NAN;
	if (n < DAO_NOISE_MIN_BLOCKS) {
		area[i] = link[i] = wm[i] = slope[i] = NAN;
		return;
	}
	area[i] = median_blocks(va, n);
	link[i] = median_links(vl, n);
	wm[i] = median_blocks(vw, n);
}

void dao_noise_cell_rows_ref(struct dao_noise_grid *g, int cy0, int cy1)
{
	for (int cy = cy0; cy < cy1; cy++)
		for (int cx = 0; cx < g->cw; cx++)
			cell_rank_medians(g, cx, cy);
}

/*
 * The cells by lanes: LANES cells side by side (a row of cells) at once.
 * Their values go into slots (a block's place in its cell; unusable blocks
 * and the cells past the frame's edge +inf), each slot a row of LANES, and a
 * sorting network (Batcher's odd-even merge sort, the comparators in the
 * grid) sorts every lane at once: the median is then the lane's n/2-th (and
 * n/2 - 1-th) value, the same order statistics as median_by_rank()
 * (dao_noise_cell_rows_ref, the oracle of tests/depth/test_noise_estimate.c).
 * The values of usable blocks are >= +0 or +inf, sorted as int32 bits; a
 * cell with a NaN or a sign bit among them (float overflow in corners of
 * float input) takes the reference's path.  callgrind, 640x480: the cells
 * 2.1 M -> 1.2 M instructions a frame (docs/perf/noise4.md).
 */
#define NP (4 * NB) /* slope pairs in a cell: 2 neighbours x 2 slopes per block */

/* Batcher's odd-even merge sort of n = 2^p values: its comparators into net
 * (the indices times `scale`: offsets of rows), their count */
static int batcher(int n, int scale, unsigned short (*net)[2])
{
	int c = 0;
	for (int p = 1; p < n; p <<= 1)
		for (int k = p; k >= 1; k >>= 1)
			for (int j = k % p; j + k < n; j += 2 * k)
				for (int i = 0; i < k && i + j + k < n; i++)
					if ((i + j) / (2 * p) == (i + j + k) / (2 * p)) {
						net[c][0] = (unsigned short)((i + j) * scale);
						net[c][1] = (unsigned short)((i + j + k) * scale);
						c++;
					}
	return c;
}

/*
 * Every lane sorted by the network, as int32: the values here are >= +0 or
 * +inf (no NaN, no sign bit: cell_slots sends a cell with one to the
 * reference), whose bits order as their values do, and integer min and max
 * vectorise without the care IEEE min and max need.  Two functions so that
 * the lanes are a constant.
 */
/* LANES int32 lanes (GCC and Clang vector extensions: one AVX2 register,
 * two SSE ones); the comparator's min and max as selects by the mask */
typedef int32_t lanes_i32 __attribute__((vector_size(4 * LANES), aligned(4)));

static inline void compare_exchange(int32_t *pa, int32_t *pb)
{
	lanes_i32 x, y;
	memcpy(&x, pa, sizeof(x));
	memcpy(&y, pb, sizeof(y));
	const lanes_i32 m = x < y;
	const lanes_i32 lo = (x & m) | (y & ~m), hi = (y & m) | (x & ~m);
	memcpy(pa, &lo, sizeof(lo));
	memcpy(pb, &hi, sizeof(hi));
}

DAO_MULTIVERSION
static void sort_blocks(int32_t *v, const unsigned short (*net)[2], int count)
{
	for (int c = 0; c < count; c++)
		for (int q = 0; q < 3; q++)
			compare_exchange(v + net[c][0] + q * LANES, v + net[c][1] + q * LANES);
}

DAO_MULTIVERSION
static void sort_pairs(int32_t *v, const unsigned short (*net)[2], int count)
{
	for (int c = 0; c < count; c++)
		compare_exchange(v + net[c][0], v + net[c][1]);
}

/* the float of bits v */
static inline float bits_float(int32_t v)
{
	float f;
	memcpy(&f, &v, sizeof(f));
	return f;
}

/* the median of lane l's n smallest values of sorted rows */
static inline float lane_median(const int32_t *v, int lanes, int l, int n)
{
	const int k = n / 2;
	const float hi = bits_float(v[k * lanes + l]);
	return n & 1 ? hi : 0.5f * (bits_float(v[(k - 1) * lanes + l]) + hi);
}

/* the bits of x >= +0 into *o where `use`, else +inf; 1 where a used x is
 * NaN or has its sign bit set */
static inline int slot(int32_t *o, float x, int use)
{
	int32_t v;
	memcpy(&v, &x, sizeof(x));
	*o = use ? v : 0x7f800000;
	return use & ((v < 0) | isnan(x));
}

/*
 * The slots of cell (cx, cy) as lane l: its blocks' area, link and mean 1/z
 * into vb (rows of 3 LANES: area lanes, link lanes, w lanes), their slope
 * pairs into vp (rows of LANES); *n, *ns: the counts, *nz: the blocks whose
 * link is 0.  0, or 1 where a value is NaN.
 */
static int cell_slots(const struct dao_noise_grid *g, int cx, int cy, int l, int32_t *vb,
		      int32_t *vp, int *n, int *ns, int *nz)
{
	const int32_t inf = 0x7f800000; /* +inf */
	int bad = 0;
	*n = *ns = *nz = 0;
	for (int s = 0; s < NB; s++) {
		const int bx = cx * DAO_NOISE_CELL + s % DAO_NOISE_CELL;
		const int by = cy * DAO_NOISE_CELL + s / DAO_NOISE_CELL;
		int32_t *o = vb + s * 3 * LANES + l, *p = vp + 4 * s * LANES + l;
		o[0] = o[LANES] = o[2 * LANES] = inf;
		p[0] = p[LANES] = p[2 * LANES] = p[3 * LANES] = inf;
		if (cx >= g->cw || bx >= g->bw || by >= g->bh)
			continue;
		const float *b = g->block + DAO_NOISE_BLOCK_STATS * ((size_t)by * g->bw + bx);
		if (isnan(b[0]))
			continue;
		bad |= slot(o, b[0], 1) | slot(o + LANES, b[1], 1) | slot(o + 2 * LANES, b[2], 1);
		(*n)++;
		*nz += b[1] == 0.0f;
		float pairs[4];
		const int k = slope_pairs(g, bx, by, pairs);
		for (int i = 0; i < k; i++)
			bad |= slot(p + i * LANES, pairs[i], 1);
		*ns += k;
	}
	return bad;
}

void dao_noise_cell_rows(struct dao_noise_grid *g, int cy0, int cy1)
{
	const int cw = g->cw, nc = cw * g->ch;
	float *area = g->cell, *link = g->cell + nc, *wm = g->cell + 2 * nc;
	float *slope = g->cell + 3 * nc;
	int32_t vb[NB * 3 * LANES], vp[NP * LANES];
	int n[LANES], ns[LANES], nz[LANES], odd[LANES];
	for (int cy = cy0; cy < cy1; cy++)
		for (int cx0 = 0; cx0 < cw; cx0 += LANES) {
			for (int l = 0; l < LANES; l++)
				odd[l] = cell_slots(g, cx0 + l, cy, l, vb, vp, &n[l], &ns[l], &nz[l]);
			sort_blocks(vb, g->net_blocks, g->net_blocks_count);
			sort_pairs(vp, g->net_pairs, g->net_pairs_count);
			for (int l = 0; l < LANES && cx0 + l < cw; l++) {
				const int i = cy * cw + cx0 + l;
				if (odd[l]) { /* the reference's rank medians */
					cell_rank_medians(g, cx0 + l, cy);
					continue;
				}
				if (n[l] < DAO_NOISE_MIN_BLOCKS) {
					area[i] = link[i] = wm[i] = slope[i] = NAN;
					continue;
				}
				slope[i] = ns[l] >= DAO_NOISE_MIN_BLOCKS
						   ? lane_median(vp, LANES, l, ns[l]) / DAO_NOISE_SLOPE_IID
						   : NAN;
				area[i] = lane_median(vb, 3 * LANES, l, n[l]);
				/* the zero links sort first: the non-zero ones from row nz
				 * (median_links) */
				const int nl = n[l] - nz[l], z0 = nl >= DAO_NOISE_MIN_BLOCKS ? nz[l] : 0;
				link[i] = lane_median(vb + LANES + (size_t)z0 * 3 * LANES, 3 * LANES, l,
						      n[l] - z0);
				wm[i] = lane_median(vb + 2 * LANES, 3 * LANES, l, n[l]);
			}
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
	*link = median_links(vl, n);
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
