/* SPDX-License-Identifier: MIT */
/*
 * Accuracy of a depth image against the true depth (tools and tests only;
 * `depthao eval --depth`, docs/depth-accuracy.md): the error of a raw and a
 * filtered depth on the pixels where the truth and both have depth, split
 * into the interior (>= DEPTH_ACC_EDGE_PX px from a true depth discontinuity)
 * and the edge band (nearer), the precision of filled pixels, and the flying
 * pixels near the discontinuities.  And the plane-fit residual used on real
 * frames, where there is no truth.
 */
#ifndef DAO_SYNTH_DEPTH_ACCURACY_H
#define DAO_SYNTH_DEPTH_ACCURACY_H

#include <stdint.h>

#include <depthao/camera.h>
#include <depthao/error.h>

/* The edge band: pixels nearer than this (chessboard distance) to a discontinuity. */
#define DEPTH_ACC_EDGE_PX 3
/* The flying-pixel band: pixels at most this far from a discontinuity. */
#define DEPTH_ACC_FLY_PX 2
/* A true discontinuity: 4-neighbours whose depths differ by more than this share of the
 * nearer one (or one without a surface). */
#define DEPTH_ACC_JUMP_REL 0.03
/* A filled pixel is right within this distance of the truth, m. */
#define DEPTH_ACC_FILL_TOL 0.01
/* A pixel is flying when its depth is off the truth by more than the larger of these. */
#define DEPTH_ACC_FLY_ABS 0.03
#define DEPTH_ACC_FLY_REL 0.03

/* Sums of absolute and squared errors over a set of pixels. */
struct depth_err {
	double abs_sum, sq_sum;
	long n;
};

struct depth_acc {
	/* on the pixels where the truth, the raw and the filtered depth all have depth */
	struct depth_err raw_in, filt_in;       /* interior */
	struct depth_err raw_edge, filt_edge;   /* edge band */
	/* filling: pixels without raw depth that got depth, and those within FILL_TOL */
	long filled, filled_ok;
	long filled_in, filled_in_ok;  /* ... of them in the interior (>= EDGE_PX) */
	/* pixels with raw and filtered depth, and those within FILL_TOL: the precision
	 * of the filtered depth a fill starts from, the most a fill can hope for */
	long kept, kept_ok;
	/* ... of them those beside a hole along their row (the samples a row fill starts
	 * from) */
	long rim, rim_ok;
	long dropped;            /* pixels with raw depth (and truth) the filter emptied */
	/* flying pixels within FLY_PX of a discontinuity, both with depth */
	long fly_raw, fly_filt, fly_created;
	long fly_px;             /* pixels of that band where truth, raw and filtered have depth */
};

static inline double depth_err_mae(const struct depth_err *e)
{
	return e->n ? e->abs_sum / (double)e->n : 0.0;
}

double depth_err_rmse(const struct depth_err *e);

/*
 * dist[i] = chessboard distance of pixel i to the nearest true discontinuity
 * pixel (a pixel with a surface whose 4-neighbour has none or a depth more
 * than DEPTH_ACC_JUMP_REL of the nearer apart), capped at 255; w x h.
 */
void depth_acc_edge_distance(const float *truth, int w, int h, uint8_t *dist);

/*
 * Adds the comparison of `raw` and `filt` against `truth` (metres, 0 = no
 * depth, w x h) to *acc, with `dist` from depth_acc_edge_distance(truth).
 */
void depth_acc_add(const float *truth, const float *raw, const float *filt, const uint8_t *dist,
		   int w, int h, struct depth_acc *acc);

/* The reduction of the filtered error against the raw, 1 - filt/raw (0 if raw is 0). */
double depth_acc_reduction(const struct depth_err *raw, const struct depth_err *filt);

/* The crude anchor's window, px per side (odd) */
#define DEPTH_BOX_SIDE 9

/*
 * A crude edge-aware mean, the anchor a noise-scaled filter has to beat
 * (issue #36): each pixel with depth takes the plain mean of the pixels of
 * the DEPTH_BOX_SIDE x DEPTH_BOX_SIDE window around it that have depth
 * within DEPTH_ACC_JUMP_REL of its own (itself included); pixels without
 * depth stay without.  `in` and `out` metres (0 = none), w x h, distinct.
 */
void depth_box_mean(const float *in, float *out, int w, int h);

/*
 * The plane-fit residual of `z` (metres, 0 = none) over the pixels i with
 * mask[i] and z[i] > 0: the least-squares plane in 1/z (1/z = a + b x' + c y',
 * x' = (u - cx)/fx, y' = (v - cy)/fy), and the RMS of z - 1/w_fit in metres.
 * *n gets the pixels used.  -1 if fewer than 3 or degenerate, else 0.
 */
int depth_plane_residual(const float *z, const uint8_t *mask, const struct dao_camera *cam,
			 double *rms, long *n);

/* The same over the rectangle [x0, x0 + rw) x [y0, y0 + rh) of the image only. */
int depth_plane_residual_rect(const float *z, const uint8_t *mask, const struct dao_camera *cam,
			      int x0, int y0, int rw, int rh, double *rms, long *n);

#endif
