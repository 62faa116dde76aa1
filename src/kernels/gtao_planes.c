/* SPDX-License-Identifier: MIT */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "core/half.h"
#include "core/multiversion.h"
#include "core/planes_alloc.h"
#include "kernels/gtao.h"
#include "kernels/gtao_planes.h"

/* Offsets beyond the image width land off the image whatever the pixel: no
 * padding is needed past w + 4 (the kernel skips such taps). */
static int offset_cover(int w, float max_r_px)
{
	float r = ceilf(max_r_px);
	return r < (float)(w + 4) ? (int)r : w + 4;
}

/* the planes' sizes (dao_planes_alloc) */
static size_t izp_bytes(const struct dao_gtao_planes *pl)
{
	return ((size_t)pl->width + 2) * ((size_t)pl->height + 2) * sizeof(float);
}

static size_t phase_bytes(const struct dao_gtao_planes *pl)
{
	return ((size_t)pl->height + 2) * 4 * (size_t)pl->stride4 * sizeof(float);
}

int dao_gtao_planes_init(struct dao_gtao_planes *pl, int w, int h, float max_r_px)
{
	const int blocks = (w + DAO_GTAO_BLOCK_SPAN - 1) / DAO_GTAO_BLOCK_SPAN;
	*pl = (struct dao_gtao_planes){ .width = w, .height = h };
	/* +2: the second tap and the phase carry; +2 more entries of slack */
	pl->pad4 = (offset_cover(w, max_r_px) + 2 + 3) / 4 + 2;
	pl->max_offset = 4 * (pl->pad4 - 2);
	pl->stride4 = 2 * pl->pad4 + DAO_GTAO_BLOCK * blocks;
	if (((size_t)h + 2) * 4 * (size_t)pl->stride4 > INT32_MAX)
		return -EOVERFLOW; /* the tile kernel keeps tap offsets in 32 bits */
	pl->izp = dao_planes_alloc(izp_bytes(pl));
	pl->phase = dao_planes_alloc(phase_bytes(pl));
	if (!pl->izp || !pl->phase) {
		dao_gtao_planes_free(pl);
		return -ENOMEM;
	}
	return 0;
}

void dao_gtao_planes_free(struct dao_gtao_planes *pl)
{
	dao_planes_free(pl->izp, izp_bytes(pl));
	dao_planes_free(pl->phase, phase_bytes(pl));
	free(pl->thick);
	pl->izp = pl->phase = NULL;
	pl->thick = NULL;
}

int dao_gtao_planes_init_thickness(struct dao_gtao_planes *pl)
{
	if (pl->thick)
		return 0;
	pl->thick = calloc(((size_t)pl->height + 2) * 4 * (size_t)pl->stride4, sizeof(uint16_t));
	return pl->thick ? 0 : -ENOMEM;
}

void dao_gtao_planes_fill_thickness(struct dao_gtao_planes *pl, const float *t, int y0, int y1)
{
	dao_gtao_planes_fill_thickness_cols(pl, t, y0, y1, 0, pl->width);
}

void dao_gtao_planes_fill_thickness_cols(struct dao_gtao_planes *pl, const float *t, int y0,
					 int y1, int x0, int x1)
{
	const int w = pl->width;
	for (int y = y0; y < y1; y++)
		for (int q = 0; q < 4; q++) {
			/* the first column of phase q from x0 on (entry xq / 4), and how many */
			const int xq = x0 + ((q - x0) & 3);
			const int n = xq < x1 ? (x1 - xq + 3) / 4 : 0;
			uint16_t *o = (uint16_t *)dao_gtao_thick_row(pl, y, q) + (xq >> 2);
			const float *in = t + (size_t)y * w + xq;
			for (int j = 0; j < n; j++)
				o[j] = dao_half_from_float(in[4 * j]);
		}
}

int dao_gtao_planes_fit(const struct dao_gtao_planes *pl, float max_r_px)
{
	return offset_cover(pl->width, max_r_px) + 2 <= pl->max_offset;
}

DAO_MULTIVERSION
void dao_gtao_planes_fill(struct dao_gtao_planes *pl, const float *z, int phase, int y0, int y1)
{
	const int w = pl->width;
	for (int y = y0; y < y1; y++) {
		const float *zr = z + (size_t)y * w;
		if (!phase) {
			float *o = pl->izp + (size_t)(y + 1) * (w + 2) + 1;
			for (int x = 0; x < w; x++)
				o[x] = zr[x] > 0.0f ? 1.0f / zr[x] : 0.0f;
			continue;
		}
		for (int q = 0; q < 4; q++) {
			float *o = (float *)dao_gtao_phase_row(pl, y, q);
			for (int x = q, j = 0; x < w; x += 4, j++)
				o[j] = zr[x] > 0.0f ? 1.0f / zr[x] : 0.0f;
		}
	}
}
