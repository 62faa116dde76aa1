/* SPDX-License-Identifier: MIT */
#ifndef DAO_DEPTH_NOISE_ESTIMATE_H
#define DAO_DEPTH_NOISE_ESTIMATE_H

/*
 * The noise of a depth frame, measured from the frame itself
 * (noise-model=auto), as standard deviations of inverse depth w = 1/z:
 * structured-light noise is about constant in disparity, i.e. in 1/z, and a
 * plane is affine in 1/z, so planes give residuals without a model of the
 * scene.
 *
 * Per block of 8 x 8 pixels that all have depth:
 * - area: the RMS residual of the least-squares plane in w (61 degrees of
 *   freedom): all noise at scales up to the block, spatially correlated
 *   noise included as far as a plane cannot absorb it;
 * - link: the RMS of the non-zero slope-corrected neighbour differences
 *   e = d_n - med3(d_n-1, d_n, d_n+1) (d = w_n - w_n-1) inside the block,
 *   along rows and columns: exactly what prefilter=domain tests a link
 *   with (domain.h), divided by its value for independent Gaussian noise
 *   of sigma 1 (DAO_NOISE_LINK_IID) so that both read sigma on such noise.
 *   Counting only non-zero differences makes it the size of a step where
 *   depth comes in quantised bands (Kinect disparity, millimetre counts).
 * Per cell of 4 x 4 blocks (32 x 32 px): the median over the cell's blocks
 * (robust to the few blocks a depth edge, a crease or a hole boundary runs
 * through); cells with fewer than DAO_NOISE_MIN_BLOCKS blocks take the mean
 * of their neighbours, repeatedly, and the frame's median when none has any.
 * Per pixel: bilinear between cell centres (dao_noise_map_*).
 *
 * On independent Gaussian noise both read sigma (within 1 %; a cell 3 % / 9 %
 * RMS).  On spatially correlated noise `area` reads less (a plane absorbs
 * part of an 8 px blob) and `link` much less (neighbouring samples move
 * together): they measure the noise as a filter sees it at its two scales,
 * see README.md.  On clean renders they read the depth quantum.
 */
#include <math.h>
#include <stddef.h>

#define DAO_NOISE_BLOCK 8       /* px */
#define DAO_NOISE_CELL 4        /* blocks per cell side */
#define DAO_NOISE_MIN_BLOCKS 4  /* usable blocks a cell needs */
/* link statistic of independent Gaussian noise of sigma 1 (measured; with it
 * tests/depth/test_noise_estimate.c reads 0.996 - 1.004 sigma) */
#define DAO_NOISE_LINK_IID 1.98f

struct dao_noise_grid {
	int width, height;
	int bw, bh, cw, ch;       /* blocks and cells across and down */
	float *block;             /* per block: area, link, mean 1/z (NAN: not usable) */
	float *cell;              /* per cell: area, link, mean 1/z */
	float *scratch;           /* cw * ch floats for the filling of empty cells */
	float frame_area, frame_link, frame_w; /* medians over the usable cells */
	int usable_cells;         /* cells with enough blocks; 0: nothing measured */
};

/* Allocates the grid of a w x h frame (the only allocation). */
int dao_noise_grid_init(struct dao_noise_grid *g, int width, int height);
void dao_noise_grid_free(struct dao_noise_grid *g);

/* Block statistics of the block rows [by0, by1) from depth z (m, 0 = no data). */
void dao_noise_blocks(struct dao_noise_grid *g, const float *z, int by0, int by1);

/* Cells from the blocks, and the frame's medians (after dao_noise_blocks on all rows). */
void dao_noise_cells(struct dao_noise_grid *g);

/*
 * A per-pixel map of one value per cell (cell_values[cy * cw + cx]),
 * bilinear between cell centres and constant beyond the outer ones: rows
 * [y0, y1) of the frame's layout (map: w x h), or rows [x0, x1) of the
 * transposed layout (map_t: h x w, row x = column x of the frame).
 */
void dao_noise_map_rows(const struct dao_noise_grid *g, const float *cell_values, float *map,
			int y0, int y1);
void dao_noise_map_cols(const struct dao_noise_grid *g, const float *cell_values, float *map_t,
			int x0, int x1);

/*
 * noise-model=auto: from the estimate to the filters' settings.  First
 * choices with the right shape, not tuned (tuning is to be done on
 * structured-light scenes with ground truth, held-out frames aside):
 *
 * - range of the domain prefilter: prefilter-range x `link` (per pixel);
 *   the bilateral prefilter and the denoise take the frame's `area` as
 *   their depth-noise;
 * - spatial scale of the domain prefilter (per pixel):
 *     sigma_s = DAO_AUTO_SCALE_GAIN sqrt(area f / w) px, clamped,
 *   area f / w being the depth noise in units of the pixel's footprint
 *   (sigma_z / (z / f)); it grows with the square root of that: a filter
 *   of scale s averages ~s^2 samples, and the slopes that noise puts on the
 *   surface fall as sigma / s^2 (so s ~ sqrt);
 * - footprint of the normals: the frame's sigma_s x DAO_AUTO_NORMAL_SHARE.
 */
#define DAO_AUTO_SCALE_GAIN 3.0f
#define DAO_AUTO_SCALE_MIN 1.0f    /* px */
#define DAO_AUTO_SCALE_MAX 16.0f   /* px */
#define DAO_AUTO_NORMAL_SHARE 1.0f

/* sigma_s of the domain prefilter for noise `area` (1/m) at inverse depth w
 * (1/m) seen with focal length f (px) */
static inline float dao_auto_scale(float area, float f, float w)
{
	float s = DAO_AUTO_SCALE_GAIN * sqrtf(area * f / w);
	s = s > DAO_AUTO_SCALE_MIN ? s : DAO_AUTO_SCALE_MIN;
	return s < DAO_AUTO_SCALE_MAX ? s : DAO_AUTO_SCALE_MAX;
}

#endif
