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
 *   depth comes in quantised bands (Kinect disparity, millimetre counts);
 * - the plane's slopes in w along x and y, per px, for `slope`: per pair of
 *   usable blocks side by side (right, below) the |differences| of their
 *   slopes, divided by their median for independent noise of sigma 1
 *   (DAO_NOISE_SLOPE_IID).  Noise correlated over blobs and bands tilts
 *   whole blocks, which their residual does not see and their slopes do.
 * Per cell of 4 x 4 blocks (32 x 32 px): the median over the cell's blocks
 * (robust to the few blocks a depth edge, a crease or a hole boundary runs
 * through; `link` over the blocks with a non-zero link when at least
 * DAO_NOISE_MIN_BLOCKS have one: a block inside one quantised band has no
 * link to measure); cells with fewer than DAO_NOISE_MIN_BLOCKS blocks take the mean
 * of their neighbours, repeatedly, and the frame's median when none has any.
 * Per pixel: bilinear between cell centres (where prefilter=domain's passes
 * need a value, dao_domain_cell_knots in domain.h).
 *
 * (`slope`: the median over the cell's pairs).
 *
 * On independent Gaussian noise all three read sigma (within 1 %, `slope`
 * 2.3 %; a cell 3 % / 9 % / 19 % RMS).  On spatially correlated noise `area`
 * reads less (a plane absorbs part of an 8 px blob), `link` much less
 * (neighbouring samples move together) and `slope` more (1.4 - 3.4 sigma
 * for blobs of 0.5 - 4 px): they measure the noise as a filter sees it at
 * its scales, see README.md.  On clean renders they read the depth quantum
 * (`slope` at most that, often 0).  Creases and steps inflate `slope` (pairs
 * across them differ by the geometry): a step every 40 px reads 1.22 sigma.
 */
#include <math.h>
#include <stddef.h>

#define DAO_NOISE_BLOCK 8       /* px */
#define DAO_NOISE_CELL 4        /* blocks per cell side */
#define DAO_NOISE_MIN_BLOCKS 4  /* usable blocks a cell needs */
/* link statistic of independent Gaussian noise of sigma 1 (measured; with it
 * tests/depth/test_noise_estimate.c reads 0.996 - 1.004 sigma) */
#define DAO_NOISE_LINK_IID 1.98f
/* the median |difference| of the slopes of two 8 x 8 least-squares planes in
 * independent Gaussian noise of sigma 1: 0.6745 sqrt(2 / 336) (336 = the sum
 * of the squared pixel offsets along one axis of a block) */
#define DAO_NOISE_SLOPE_IID 0.05204f
/* floats per block: area, link, mean 1/z, slope along x, slope along y */
#define DAO_NOISE_BLOCK_STATS 5
/* floats per cell: area, link, mean 1/z, slope (planes of cw x ch) */
#define DAO_NOISE_CELL_STATS 4

struct dao_noise_grid {
	int width, height;
	int bw, bh, cw, ch;       /* blocks and cells across and down */
	float *block;             /* per block: DAO_NOISE_BLOCK_STATS (NAN: not usable) */
	float *cell;              /* per cell: DAO_NOISE_CELL_STATS planes */
	float *scratch;           /* cw * ch floats for the filling of empty cells */
	float frame_area, frame_link, frame_w, frame_slope; /* medians over the usable cells */
	int usable_cells;         /* cells with enough blocks; 0: nothing measured */
	/* the block statistics of one block row (dao_noise_row_ref or a kernel set's) */
	void (*row)(const float *z, int stride, int nblocks, float *out);
	/* the sorting networks of the cells' medians (noise_estimate.c): comparators */
	unsigned short net_blocks[64][2], net_pairs[576][2];
	int net_blocks_count, net_pairs_count;
};

/* Allocates the grid of a w x h frame (the only allocation). */
int dao_noise_grid_init(struct dao_noise_grid *g, int width, int height);
void dao_noise_grid_free(struct dao_noise_grid *g);

/* Block statistics of the block rows [by0, by1) from depth z (m, 0 = no data),
 * by g->row (the reference unless the caller set a kernel set's). */
void dao_noise_blocks(struct dao_noise_grid *g, const float *z, int by0, int by1);
/* The same by the scalar reference. */
void dao_noise_blocks_ref(struct dao_noise_grid *g, const float *z, int by0, int by1);

/* The statistics of the nblocks blocks of the 8 rows from z (stride floats
 * apart) into out (DAO_NOISE_BLOCK_STATS per block): the scalar reference,
 * and per kernel set (noise_blocks_simd.inc.c; bit-identical to it). */
void dao_noise_row_ref(const float *z, int stride, int nblocks, float *out);
void dao_noise_row_generic(const float *z, int stride, int nblocks, float *out);
void dao_noise_row_sse41(const float *z, int stride, int nblocks, float *out);
void dao_noise_row_avx2(const float *z, int stride, int nblocks, float *out);
void dao_noise_row_avx512(const float *z, int stride, int nblocks, float *out);

/* Cells from the blocks, and the frame's medians (after dao_noise_blocks on all rows). */
void dao_noise_cells(struct dao_noise_grid *g);

/* The same in two steps: the cells of the cell rows [cy0, cy1) (any rows
 * in any order, on any thread), then, after all rows, the frame's medians
 * and the filling of the empty cells. */
void dao_noise_cell_rows(struct dao_noise_grid *g, int cy0, int cy1);
/* The same by ranks, a cell at a time: the oracle of dao_noise_cell_rows. */
void dao_noise_cell_rows_ref(struct dao_noise_grid *g, int cy0, int cy1);
void dao_noise_cells_finish(struct dao_noise_grid *g);

/* One cell again from z (its blocks, then the medians; the other cells and
 * the frame's medians are left alone): 1 and the cell's link and mean 1/z
 * in *link and *w, or 0 (fewer than DAO_NOISE_MIN_BLOCKS usable blocks:
 * nothing written).  Cells are independent: any cells on any threads. */
int dao_noise_cell_measure(struct dao_noise_grid *g, const float *z, int cx, int cy,
			   float *link, float *w);

/*
 * noise-model=auto: from the estimate to the filters' settings (the gain,
 * exponent and share fitted on `depthao eval --set tune`, the Kinect .oni
 * frames 0-5 and Redwood 00000; held-out scenes and frames only reported):
 *
 * - range of the domain prefilter: prefilter-range x `link` (per pixel);
 *   the bilateral prefilter and the denoise take the frame's `area` as
 *   their depth-noise;
 * - spatial scale of the domain prefilter (per pixel):
 *     sigma_s = DAO_AUTO_SCALE_GAIN (slope f / w)^DAO_AUTO_SCALE_POWER px,
 *   clamped, with the frame's `slope` and the cell's mean 1/z w: the noise
 *   in units of the pixel's footprint (sigma_z / (z / f)).  `slope` rather
 *   than `area`: noise correlated over blobs and bands (structured light)
 *   tilts whole 8 x 8 planes, which the residual about them cannot see
 *   (Kinect walls: `slope` 5.3 `area`, independent noise: 1.0).  The
 *   frame's value, not the cell's: across a crease neighbouring planes
 *   differ by the crease, and cells of stairs read several times their
 *   noise (Gaussian stairs 0.0526 -> 0.0497 MAE at exponent 1/2);
 * - footprint of the normals (the frame's):
 *     r = DAO_AUTO_NORMAL_GAIN (slope f / w)^DAO_AUTO_NORMAL_POWER px,
 *   rounded, 1-8.  The normals' noise goes as sigma / (sigma_s r): with the
 *   two exponents summing to 1 it stays the same as the noise changes, so
 *   less noise (a temporally filtered stream) buys sharper geometry and is
 *   never worse, up to the clamps; with a square root here (sum 1.25) the
 *   temporally filtered boxes of tests/pipeline/test_temporal_depth.c
 *   came out worse than without the temporal filter (AO MAE 0.0356 against
 *   0.0346; 0.0335 now).  2 px for independent noise at 320 x 240 and
 *   640 x 480 (a share of sigma_s gave 1 px at 320 x 240, where a
 *   Gaussian-noisy plane reads 0.017 mean occlusion, test_noise_model.c;
 *   0.007 at 2 px), 4 px on the Kinect frames.
 */
/* 3.74 since the domain filter's side windows keep creases sharp (before
 * them 1.87: a wider scale rounded the creases, and fixed scales never
 * brought the structured-light stairs below 0.072 MAE) */
#define DAO_AUTO_SCALE_GAIN 3.74f
#define DAO_AUTO_SCALE_POWER 0.75f
#define DAO_AUTO_SCALE_MIN 1.0f    /* px */
#define DAO_AUTO_SCALE_MAX 16.0f   /* px */
#define DAO_AUTO_NORMAL_GAIN 2.0f
#define DAO_AUTO_NORMAL_POWER 0.25f

/* sigma_s of the domain prefilter for noise `slope` (1/m) at inverse depth w
 * (1/m) seen with focal length f (px) */
static inline float dao_auto_scale(float slope, float f, float w)
{
	float s = DAO_AUTO_SCALE_GAIN * powf(slope * f / w, DAO_AUTO_SCALE_POWER);
	s = s > DAO_AUTO_SCALE_MIN ? s : DAO_AUTO_SCALE_MIN;
	return s < DAO_AUTO_SCALE_MAX ? s : DAO_AUTO_SCALE_MAX;
}

/* the normals' footprint for the same */
static inline int dao_auto_normal_radius(float slope, float f, float w)
{
	const int r = (int)lrintf(DAO_AUTO_NORMAL_GAIN * powf(slope * f / w, DAO_AUTO_NORMAL_POWER));
	return r < 1 ? 1 : r > 8 ? 8 : r;
}

#endif
