/* SPDX-License-Identifier: MIT */
/*
 * The depth planes the optimised GTAO kernels read, made once per frame from
 * the filtered depth (1/z, 0 = no data, so a sample's two taps interpolate
 * without a division):
 *  - izp: with a one-pixel border of zeros, (w + 2) x (h + 2), read by the
 *    per-pixel (gather) kernel;
 *  - phase: split by column phase x mod 4 (entry j of phase q is column
 *    4 j + q), the four phases of a row next to each other, zero rows above
 *    and below and zero entries left and right.  With tile noise the pixels
 *    of one phase share their sample offsets, so the lanes' taps are
 *    consecutive entries of one phase row: one load instead of a gather.
 */
#ifndef DAO_KERNELS_GTAO_PLANES_H
#define DAO_KERNELS_GTAO_PLANES_H

#include <stddef.h>
#include <stdint.h>

struct dao_gtao_planes {
	int width, height;
	float *izp;     /* pixel (-1, -1) of the bordered plane */
	float *phase;   /* row -1, phase 0, entry -pad4 */
	int pad4;       /* zero entries before and after each phase row */
	int stride4;    /* entries per phase row: pad4 + DAO_GTAO_BLOCK x blocks + pad4 */
	int max_offset; /* largest |column offset| of a tap the padding covers */
	uint16_t *thick; /* vbao's occluder thickness (m) laid out as `phase`, as IEEE
			  * halves (core/half.h), or NULL */
};

/* Allocates the planes for w x h and samples up to max_r_px away (zeroed). */
int dao_gtao_planes_init(struct dao_gtao_planes *pl, int w, int h, float max_r_px);
void dao_gtao_planes_free(struct dao_gtao_planes *pl);

/* Allocates pl->thick (zeroed), for vbao with a thickness plane. */
int dao_gtao_planes_init_thickness(struct dao_gtao_planes *pl);

/* Rows [y0, y1) of pl->thick from the per-pixel plane t (w x h, metres),
 * rounded to the nearest half. */
void dao_gtao_planes_fill_thickness(struct dao_gtao_planes *pl, const float *t, int y0, int y1);

/* ... of columns [x0, x1) only (for a pass that finishes the plane a block of
 * columns at a time). */
void dao_gtao_planes_fill_thickness_cols(struct dao_gtao_planes *pl, const float *t, int y0,
					 int y1, int x0, int x1);

/* Whether planes made for max_r_px `have` serve max_r_px `want` as well. */
int dao_gtao_planes_fit(const struct dao_gtao_planes *pl, float max_r_px);

/* Rows [y0, y1) of the bordered plane (phase = 0) or the phase plane (1) from z. */
void dao_gtao_planes_fill(struct dao_gtao_planes *pl, const float *z, int phase, int y0, int y1);

/* First entry of phase q of row r (-1 <= r <= height). */
static inline const float *dao_gtao_phase_row(const struct dao_gtao_planes *pl, int r, int q)
{
	return pl->phase + ((size_t)(r + 1) * 4 + (size_t)q) * (size_t)pl->stride4 + pl->pad4;
}

/* First entry of phase q of row r of pl->thick (-1 <= r <= height). */
static inline const uint16_t *dao_gtao_thick_row(const struct dao_gtao_planes *pl, int r, int q)
{
	return pl->thick + ((size_t)(r + 1) * 4 + (size_t)q) * (size_t)pl->stride4 + pl->pad4;
}

#endif
