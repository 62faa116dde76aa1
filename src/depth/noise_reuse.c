/* SPDX-License-Identifier: MIT */
/* The noise measured when it changes (see noise_reuse.h). */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "depth/noise_reuse.h"

#define S DAO_NOISE_REUSE_STEP
#define SPAN (DAO_NOISE_BLOCK * DAO_NOISE_CELL) /* px per cell side */

int dao_noise_reuse_init(struct dao_noise_reuse *r, const struct dao_noise_grid *g)
{
	*r = (struct dao_noise_reuse){ .cw = g->cw, .ch = g->ch };
	const size_t nc = (size_t)g->cw * g->ch;
	r->cell = malloc(6 * nc * sizeof(float));
	r->changed = malloc(nc * sizeof(int));
	if (!r->cell || !r->changed) {
		dao_noise_reuse_free(r);
		return -ENOMEM;
	}
	r->sig_ref = r->cell + 2 * nc;
	r->sig_now = r->cell + 4 * nc;
	return 0;
}

void dao_noise_reuse_free(struct dao_noise_reuse *r)
{
	free(r->cell);
	free(r->changed);
	r->cell = r->sig_ref = r->sig_now = NULL;
	r->changed = NULL;
}

/*
 * Per cell the mean 1/z of the samples with depth and their share of the
 * samples: every S-th pixel of every S-th row, from S / 2, over the pixels
 * of the cell's blocks.  sig: mean 1/z (0 without depth), then the share.
 */
static void signature(const struct dao_noise_grid *g, const float *z, float *sig)
{
	const int cw = g->cw, nc = cw * g->ch;
	const int xe = g->bw * DAO_NOISE_BLOCK, ye = g->bh * DAO_NOISE_BLOCK;
	float *sum = sig, *cnt = sig + nc;
	memset(sig, 0, 2 * (size_t)nc * sizeof(float));
	for (int y = S / 2; y < ye; y += S) {
		const float *zr = z + (size_t)y * g->width;
		for (int cx = 0; cx < cw; cx++) {
			const int x1 = (cx + 1) * SPAN < xe ? (cx + 1) * SPAN : xe;
			float s = 0.0f, c = 0.0f;
			for (int x = cx * SPAN + S / 2; x < x1; x += S) {
				/* 1/z or 0, without a branch */
				const float v = zr[x], has = (float)(v > 0.0f);
				s += has / (v + (1.0f - has)), c += has;
			}
			sum[y / SPAN * cw + cx] += s, cnt[y / SPAN * cw + cx] += c;
		}
	}
	for (int cy = 0; cy < g->ch; cy++)
		for (int cx = 0; cx < cw; cx++) {
			/* samples in the cell: those of its columns times those of its rows */
			const int x0 = cx * SPAN, y0 = cy * SPAN;
			const int x1 = x0 + SPAN < xe ? x0 + SPAN : xe, y1 = y0 + SPAN < ye ? y0 + SPAN : ye;
			const int n = (x1 > x0 ? (x1 - x0) / S : 0) * (y1 > y0 ? (y1 - y0) / S : 0);
			const int i = cy * cw + cx;
			sum[i] = cnt[i] > 0.0f ? sum[i] / cnt[i] : 0.0f;
			cnt[i] = n > 0 ? cnt[i] / (float)n : 0.0f;
		}
}

void dao_noise_reuse_store(struct dao_noise_reuse *r, const struct dao_noise_grid *g,
			   const float *z, int interval)
{
	const size_t nc = (size_t)r->cw * r->ch;
	r->valid = g->usable_cells > 0;
	r->area = g->frame_area, r->link = g->frame_link;
	r->slope = g->frame_slope, r->w = g->frame_w;
	r->side_ratio = NAN;
	r->age = 0;
	memcpy(r->cell, g->cell + nc, 2 * nc * sizeof(float)); /* link, mean 1/z */
	if (interval > 1 && z)
		signature(g, z, r->sig_ref);
	/* 0, 1, 2, 4, 8, ... frames after the restart, then every `interval` */
	const uint64_t gap = r->since < 1 ? 1 : r->since;
	r->next = r->since + (gap < (uint64_t)interval ? gap : (uint64_t)interval);
}

int dao_noise_reuse_changes(struct dao_noise_reuse *r, const struct dao_noise_grid *g,
			    const float *z)
{
	const int nc = r->cw * r->ch;
	signature(g, z, r->sig_now);
	const float *m0 = r->sig_ref, *c0 = r->sig_ref + nc;
	const float *m1 = r->sig_now, *c1 = r->sig_now + nc;
	int moved = 0, with_depth = 0;
	for (int i = 0; i < nc; i++) {
		with_depth += c0[i] > 0.0f || c1[i] > 0.0f;
		if (fabsf(c1[i] - c0[i]) > DAO_NOISE_REUSE_COVER ||
		    (c0[i] > 0.0f && c1[i] > 0.0f && fabsf(m1[i] - m0[i]) > DAO_NOISE_REUSE_W * m0[i]))
			r->changed[moved++] = i;
	}
	return moved * DAO_NOISE_REUSE_CUT > with_depth ? -1 : moved;
}

void dao_noise_reuse_measure_cell(struct dao_noise_reuse *r, struct dao_noise_grid *g,
				  const float *z, int i)
{
	const int nc = r->cw * r->ch, c = r->changed[i];
	/* too few usable blocks now: the cell keeps what it had */
	dao_noise_cell_measure(g, z, c % r->cw, c / r->cw, &r->cell[c], &r->cell[nc + c]);
	r->sig_ref[c] = r->sig_now[c];
	r->sig_ref[nc + c] = r->sig_now[nc + c];
}
