/* SPDX-License-Identifier: MIT */
/*
 * Block matching along image rows, as the depth sensors do it (tools and
 * tests only): for each pixel of a "left" image the integer disparity d
 * whose window in the "right" image (column u - d) correlates best
 * (zero-mean normalised cross-correlation over a square window), the
 * sub-pixel vertex of a parabola through the scores at d - 1, d, d + 1, and
 * the numbers the validity rules of a sensor need: the best score, the best
 * score of a disparity farther than 1 from it (ambiguity), the window's
 * texture, and optionally the right-to-left match for a consistency check.
 */
#ifndef DAO_SYNTH_BLOCK_MATCH_H
#define DAO_SYNTH_BLOCK_MATCH_H

struct synth_match_options {
	int window;            /* odd, px */
	int dmin, dmax;        /* integer disparities searched, dmin >= 0 */
	int right_offset;      /* left pixel u pairs with right column u - d + right_offset */
	int right_width;       /* columns of the right image */
	int left_right;        /* also the best left match of every right pixel */
};

struct synth_match {
	float *disparity;      /* sub-pixel, NAN where no window fits */
	float *score;          /* best ZNCC */
	float *second;         /* best ZNCC at |d - best| > 1 */
	float *texture;        /* standard deviation of the left window */
	float *right_disparity;/* left_right: per right pixel (right_width x h), NAN if none */
};

/*
 * Matches `left` (w x h) against `right` (right_width x h); the arrays of
 * `m` are caller-allocated (w x h floats; right_disparity right_width x h
 * if left_right).  Rows are split over `threads` threads; the result does
 * not depend on their number.  Returns 0 or -ENOMEM / -EINVAL.
 */
int synth_block_match(const float *left, const float *right, int w, int h,
		      const struct synth_match_options *o, int threads, struct synth_match *m);

/*
 * Means and 1/(sqrt(n) s) of the win x win windows of an image (n = win^2, s
 * the standard deviation; both 0 where the window leaves the image, 1/(...)
 * 0 where it is flat), and s itself in sdev if not NULL.  0 or -ENOMEM.
 */
int synth_window_stats(const float *img, int w, int h, int win, float *mean, float *inv,
		       float *sdev);

#endif
