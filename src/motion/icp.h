/* SPDX-License-Identifier: MIT */
/*
 * The camera's motion from one depth frame to the next: projective
 * point-to-plane ICP on a subsampled grid.
 *
 * Point-to-plane error: Chen & Medioni 1991 ("Object modelling by
 * registration of multiple range images"); projective data association (a
 * point is paired with the previous frame's pixel it projects to, no
 * search): Newcombe et al. 2011 (KinectFusion).  Each Gauss-Newton step
 * linearises the rotation (small angles) and solves the 6x6 normal equations
 * by Cholesky; the pose is updated on the left, T <- exp(xi) T.
 *
 * Convention: the pose maps the current frame's view positions into the
 * previous frame's, p_prev = R p_cur + t (optical frame, metres).
 */
#ifndef DAO_MOTION_ICP_H
#define DAO_MOTION_ICP_H

#include <stddef.h>
#include <stdint.h>

#include <depthao/camera.h>

#include "motion/icp_pairs.h"
#include "motion/icp_source.h"

struct dao_pool;

struct dao_pose {
	double r[9]; /* row-major rotation */
	double t[3]; /* metres */
};

void dao_pose_identity(struct dao_pose *p);
/* Rotation angle (radians) and translation length (metres) of a pose. */
double dao_pose_angle(const struct dao_pose *p);
double dao_pose_distance(const struct dao_pose *p);

struct dao_icp_setup {
	int step;          /* grid stride in pixels (source points), >= 1 */
	int coarse_iterations; /* Gauss-Newton steps on the coarse grid (every 2 step px), >= 1 */
	int iterations;    /* ... then on the whole grid, >= 1 (both end early on a tiny step) */
	/* the same two counts when a prior seeds the estimate (its start is
	 * then near: the last frame's motion), >= 1 */
	int seeded_coarse_iterations, seeded_iterations;
	/* ... unless the last of those coarse steps still moved a point at the
	 * mean depth by more than this (m): the motion changed, the prior was
	 * wrong, and the estimate runs on to the unseeded counts */
	float seeded_far;
	int normal_radius; /* pixels between the neighbours of a normal's differences */
	float dist_gate;   /* pairs farther apart than this (m) are not used */
	float cos_gate;    /* ... nor pairs whose normals differ by more (cosine) */
	float edge;        /* a normal's neighbour at r px off by more than edge r z: a
			    * depth edge, no normal */
	float tukey;       /* Tukey's biweight cut, in units of the residual's sigma */
	float noise_k;     /* the depth noise: sigma(z) = noise_k z^2 (m) ... */
	float quantum;     /* ... and the depth's step (m, rounding: q^2 / 12) */
	float max_angle;   /* bounded motion: larger rotations (rad) are rejected */
	float max_dist;    /* ... and larger translations (m) */
	float min_inlier_share; /* share of the source points that must pair */
	int min_inliers;        /* and at least this many */
	float min_cond;    /* smallest / largest eigenvalue of the scaled 6x6 system */
	float max_rms;     /* largest RMS point-to-plane residual of the inliers (m) */
	/* the prior: how much the motion may change from one frame to the next
	 * (rad, m; one sigma; 0 = no prior, the previous motion seeds only) */
	float prior_angle, prior_dist;
	/* the pair kernel (NULL: the reference, motion/icp_pairs.h) and the
	 * threads that run its chunks (NULL: the caller), one band a thread;
	 * neither changes the result but by the kernel's float rounding */
	dao_icp_pairs_fn pairs;
	struct dao_pool *pool;
	/* a step over fewer source points runs on the calling thread (the
	 * default 0: every step on the pool, as the source grid, the target
	 * and the reprojection are) */
	int pool_min_points;
	/* the source grid's and the target's kernels (NULL: the references,
	 * motion/icp_source.h; the same result to the bit) */
	dao_icp_source_fn source;
	dao_icp_target_fn target;
};

/* Defaults for a VGA-class sensor at 30 fps. */
void dao_icp_setup_default(struct dao_icp_setup *s);

/* Why an estimate was rejected (dao_icp_result.reason). */
enum dao_icp_verdict {
	DAO_ICP_OK = 0,
	DAO_ICP_FEW_POINTS,   /* too few source points or pairs */
	DAO_ICP_DEGENERATE,   /* the 6x6 system is ill-conditioned (a flat wall) */
	DAO_ICP_RESIDUAL,     /* the residual stayed large (a scene cut) */
	DAO_ICP_MOTION,       /* the motion is out of bounds */
	DAO_ICP_NOT_FINITE,   /* the solve broke down */
};

struct dao_icp_result {
	struct dao_pose pose;  /* the estimate (identity-seeded from the prior) */
	int valid;             /* 1: use it; 0: see reason */
	enum dao_icp_verdict reason;
	int points;            /* source points on the grid with data */
	int inliers;           /* pairs used in the last step */
	float rms;             /* RMS point-to-plane residual of the inliers (m) */
	float cond;            /* smallest / largest eigenvalue of the scaled system */
	float near_z;          /* nearest source depth (m), for the motion's pixel extent */
	int iterations;        /* steps run */
	float step;            /* the last step's largest move of a point at the mean depth (m) */
};

/* Floats of the caller-owned scratch for an image of w x h pixels. */
size_t dao_icp_scratch_floats(const struct dao_icp_setup *s, int w, int h);

/*
 * Estimates the pose from the current depth `cur_z` (metres, 0 = no data)
 * to the previous frame, given as inverse depth `prev_inv` (1/m, 0 = no data)
 * and, when not NULL, `prev_count` (0 = no data).  Both planes are
 * cam->width x cam->height, tightly packed.  `prior` seeds the estimate (the
 * previous frame's motion; NULL: identity).  `scratch` holds
 * dao_icp_scratch_floats() floats.  No allocation.
 */
void dao_icp_estimate(const struct dao_icp_setup *s, const struct dao_camera *cam,
		      const float *prev_inv, const uint8_t *prev_count, const float *cur_z,
		      const struct dao_pose *prior, float *scratch, struct dao_icp_result *out);

/*
 * Largest displacement (pixels) the pose gives a point at depth z seen at
 * the image's corners or centre: below a small fraction of a pixel the
 * frames are taken as still.
 */
double dao_pose_pixel_extent(const struct dao_pose *p, const struct dao_camera *cam, double z);

#endif
