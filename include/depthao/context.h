/* SPDX-License-Identifier: MIT */
/*
 * The AO context: one camera, one parameter set, and the working buffers for
 * frames of that camera's size.  All memory is allocated when the context is
 * created; processing a frame allocates nothing.
 *
 * A context is used by one thread at a time; separate contexts are fully
 * independent (the library has no global mutable state).
 */
#ifndef DEPTHAO_CONTEXT_H
#define DEPTHAO_CONTEXT_H

#include <stddef.h>
#include <stdint.h>

#include <depthao/camera.h>
#include <depthao/error.h>
#include <depthao/frame.h>
#include <depthao/params.h>
#include <depthao/cpu.h>

#include <depthao/api.h>

#ifdef __cplusplus
extern "C" {
#endif

struct dao_context;

/*
 * Creates a context for frames of cam->width x cam->height.  `params` may be
 * NULL for the default preset.  Returns 0, -EINVAL (bad camera or params) or
 * -ENOMEM.
 */
DAO_API int dao_context_create(struct dao_context **out, const struct dao_camera *cam,
		       const struct dao_params *params, struct dao_error *err);

/* Destroys a context; NULL-safe. */
DAO_API void dao_context_destroy(struct dao_context *ctx);

/* Replaces the parameters (validated first; on error the old ones stay). */
DAO_API int dao_context_set_params(struct dao_context *ctx, const struct dao_params *params,
			   struct dao_error *err);

/*
 * Copies the current parameters into `out`, a struct dao_params of `size`
 * bytes (the fields that fit; out->size is set).  -EINVAL if `size` is
 * smaller than the first struct that carried a size.  Programs call
 * dao_context_get_params() below; bindings pass dao_params_size().
 */
DAO_API int dao_context_get_params_sized(const struct dao_context *ctx, struct dao_params *out,
					 size_t size);

/* Copies the current parameters. */
static inline void dao_context_get_params(const struct dao_context *ctx, struct dao_params *out)
{
	(void)dao_context_get_params_sized(ctx, out, sizeof(*out));
}

/* The camera the context was created with. */
DAO_API const struct dao_camera *dao_context_camera(const struct dao_context *ctx);

/*
 * Computes ambient occlusion for one depth frame.
 *
 * depth:   DAO_PIXFMT_DEPTH16 (with depth_unit > 0) or DAO_PIXFMT_DEPTH_F32,
 *          of the camera's size.
 * normals: NULL to derive normals from depth, or DAO_PIXFMT_NORMAL_F32 unit
 *          normals in the optical frame (facing the camera).
 * frame_index: selects the noise pattern, and tells the temporal filters
 *          (params `depth-temporal`, `temporal`) whether this frame follows
 *          the last one: an index 1 to DAO_TEMPORAL_MAX_GAP past the last
 *          processed frame continues their histories (a few dropped frames
 *          do not matter); the same index, an earlier one (a seek, a loop)
 *          or a larger jump starts them over.  With both filters off (the
 *          presets) the result is a pure function of (depth, normals,
 *          params, frame_index); on the first frame of a history it is too.
 * ao:      NULL, or DAO_PIXFMT_GRAY_F32 / GRAY16 / GRAY8 visibility
 *          (1 = open); pixels without depth get params.invalid_value.
 *          With params.algorithm DAO_ALGORITHM_NONE (depth only) no normals,
 *          AO, denoise or shading are computed: `normals` is not read, `ao`
 *          gets visibility 1 where the input has depth (invalid_value
 *          elsewhere), and dao_context_shade(), _get_normals() and
 *          _get_bent_normals() return -ENODATA; dao_context_get_depth()
 *          gives the filtered depth, the same as with an AO algorithm.
 *
 * The frame's depth, normals and AO stay in the context for dao_context_shade().
 * The calling thread takes part in the work and needs about 80 KB of stack
 * (the optimised GTAO keeps its step tables there).
 */
DAO_API int dao_context_process(struct dao_context *ctx, const struct dao_frame *depth,
			const struct dao_frame *normals, uint64_t frame_index,
			struct dao_frame *ao, struct dao_error *err);

/* Frames a stream may skip (frame_index steps) without restarting the
 * temporal filters' histories. */
#define DAO_TEMPORAL_MAX_GAP 4

/*
 * Starts the temporal filters' histories over, as a gap in frame_index
 * does: for a cut the indices do not show (the camera moved to another
 * scene, a different camera feeds the same context).  NULL-safe.
 */
DAO_API void dao_context_reset(struct dao_context *ctx);

/*
 * Renders the occlusion-shaded image of the last processed frame into `out`
 * (DAO_PIXFMT_RGB24, or GRAY8 for the AO/gray modes), using the shading
 * parameters.  Returns -EAGAIN if no frame was processed yet, -ENODATA after
 * a frame processed with algorithm=none (no normals or AO to shade).
 */
DAO_API int dao_context_shade(struct dao_context *ctx, struct dao_frame *out, struct dao_error *err);

/*
 * dao_context_process() and then dao_context_shade() into `shaded`, in one
 * call: the same AO and the same shaded image, byte for byte, with the
 * shading done on each band of rows while its AO is still in the core's
 * cache (one pass over the frame and one hand-off to the threads fewer).
 * `shaded` (RGB24 or GRAY8, the camera's size) is checked before the frame
 * is processed; NULL: as dao_context_process().  With algorithm=none the
 * frame is processed as by dao_context_process() and -ENODATA is returned,
 * as dao_context_shade() would.  dao_timings.shade_ms is then the shading's
 * share of the last stage, like output_ms.
 */
DAO_API int dao_context_process_shaded(struct dao_context *ctx, const struct dao_frame *depth,
				       const struct dao_frame *normals, uint64_t frame_index,
				       struct dao_frame *ao, struct dao_frame *shaded,
				       struct dao_error *err);

/*
 * Copies the normals (DAO_PIXFMT_NORMAL_F32, unit vectors in the optical
 * frame) of the last processed frame into the caller's frame.  -EAGAIN before
 * the first frame, -ENODATA after a frame processed with algorithm=none.
 */
DAO_API int dao_context_get_normals(const struct dao_context *ctx, struct dao_frame *out,
			    struct dao_error *err);

/*
 * The filtered depth of the last processed frame: the depth the normals and
 * the AO were computed from, after the decode (depth-min/max), the temporal
 * depth filter (depth-temporal) and the prefilter (docs/library.md, "The
 * filtered depth").  It holds depth only where the input did (or, with
 * depth-temporal-persist, where the history kept it); the filters fill no
 * holes, unless depth-fill N > 0 asks this output (not the normals or AO) to
 * fill each hole of at most N px along a row whose two sides lie on one
 * surface, linearly between them.  `out` is the caller's frame
 * of the camera's size, rows `stride` bytes apart, in one of:
 *
 *   DAO_PIXFMT_DEPTH_F32  metres, 0 = no depth;
 *   DAO_PIXFMT_DEPTH16    counts of out->depth_unit metres (positive and
 *                         finite, e.g. the input's unit, or 0.001), 0 = no
 *                         depth: rounded to the nearest count (ties to even);
 *                         a depth below half a count gives 1 and one beyond
 *                         65535 counts gives 65535, so a pixel with depth is
 *                         never 0.  Depth16 input read back in its own unit
 *                         keeps its counts where the filters left it alone.
 *
 * Returns 0; -EINVAL (NULL, wrong size, format or stride, a bad unit, with
 * the message in `err`); -EAGAIN if no frame was processed yet.
 */
DAO_API int dao_context_get_depth(const struct dao_context *ctx, struct dao_frame *out,
			  struct dao_error *err);

/*
 * Bent normals of the last frame (DAO_PIXFMT_NORMAL_F32, unit vectors in the
 * optical frame; 0 where there is no depth): the mean open direction of each
 * pixel from GTAO's horizons (Jimenez 2016), for lighting with environment
 * maps.  Computed on request by the reference kernel, so it costs about as
 * much as a reference GTAO pass; -EAGAIN before the first frame.
 */
DAO_API int dao_context_get_bent_normals(struct dao_context *ctx, struct dao_frame *out,
					 struct dao_error *err);

/*
 * Wall-clock time of each stage of the last frame, milliseconds.
 *
 * Filled by the library into the caller's struct: `size` first, fields only
 * ever appended (docs/abi.md).  dao_context_timings() passes the caller's
 * sizeof, so a program built against an older, shorter struct gets the
 * fields it knows and nothing past them is written; out->size tells how much
 * was filled (less than the caller's sizeof when the library is older).
 */
struct dao_timings {
	uint32_t size;        /* bytes filled, set by the library */
	double decode_ms;     /* depth input to metres */
	double prefilter_ms;  /* edge-preserving depth filter */
	double normals_ms;    /* normals (and the kernels' depth layout; vbao with
			       * vbao-thickness-mode=image: the thickness's row pass) */
	double gtao_ms;       /* the AO kernel (and the thickness's column pass) */
	/* the AO denoise */
	double denoise_ms;
	double output_ms;     /* AO to the caller's format (algorithm=none: the constant
			       * image, written beside the decode and taken out of
			       * decode_ms; the bands' time over the threads) */
	double process_ms;    /* all of the last dao_context_process() */
	double shade_ms;      /* the last dao_context_shade() (or the shading's share
			       * of dao_context_process_shaded()) */
	double noise_ms;      /* noise-model=auto: the frame's noise estimate and maps */
};

/* A struct dao_timings with its size set and every time 0. */
#define DAO_TIMINGS_INIT { .size = sizeof(struct dao_timings) }

/*
 * Copies the timings into `out`, a struct dao_timings of `size` bytes: the
 * fields that fit (min(size, this library's sizeof)), nothing past them, and
 * out->size.  -EINVAL if ctx or out is NULL or `size` cannot hold `size`.
 * Programs call dao_context_timings(); bindings pass their struct's size.
 */
DAO_API int dao_context_timings_sized(const struct dao_context *ctx, struct dao_timings *out,
				      size_t size);

/* Copies the stage timings of the last frame into `out` (dao_context_timings_sized()). */
static inline void dao_context_timings(const struct dao_context *ctx, struct dao_timings *out)
{
	(void)dao_context_timings_sized(ctx, out, sizeof(*out));
}

/*
 * The noise the last frame was filtered for (noise-model=auto: measured in
 * the frame, or with noise-interval > 1 in a recent one; fixed: the
 * depth-noise parameter), as standard deviations of
 * inverse depth 1/z in 1/m (sigma(z) = value x z^2 m), and the settings it
 * gave.  Filled like struct dao_timings: `size` first, fields appended.
 */
struct dao_noise_info {
	uint32_t size;          /* bytes filled, set by the library */
	int measured;           /* 1: estimated from the frame; 0: the model (fixed, or
				 * nothing measurable: no 8x8 block without holes) */
	float sigma_area;       /* median over the frame: RMS about local planes (8x8 px) */
	float sigma_link;       /* median: what neighbouring pixels differ by (independent-noise
				 * equivalent; the domain filter's range unit) */
	float prefilter_scale;  /* domain prefilter: sigma_s at the frame's median, px */
	int normal_radius;      /* footprint of the normals, px */
	float denoise_noise;    /* the denoise's noise k, 1/m */
	float sigma_slope;      /* median: how the slopes of neighbouring 8x8 planes differ
				 * (independent-noise equivalent; drives the prefilter's scale) */
	/* noise-interval > 1 (streams): the figures above are those of a full
	 * measurement `age` frames ago (0: this frame; measured 0 leaves it 0),
	 * and `cells_measured` cells of 32 x 32 px where the scene moved since
	 * were measured again in this frame (their range and spatial scale) */
	int age;
	/* cells of 32 x 32 px measured again in this frame (see above) */
	int cells_measured;
};

/* A struct dao_noise_info with its size set and every field 0. */
#define DAO_NOISE_INFO_INIT { .size = sizeof(struct dao_noise_info) }

/* Copies the noise figures into `out` of `size` bytes, as dao_context_timings_sized(). */
DAO_API int dao_context_noise_sized(const struct dao_context *ctx, struct dao_noise_info *out,
				    size_t size);

/* Copies the noise the last frame was filtered for into `out` (dao_context_noise_sized()). */
static inline void dao_context_noise(const struct dao_context *ctx, struct dao_noise_info *out)
{
	(void)dao_context_noise_sized(ctx, out, sizeof(*out));
}

/* What became of the camera-motion estimate of the last frame (dao_motion_info.state). */
enum dao_motion_state {
	DAO_MOTION_NONE = 0, /* not estimated: depth-temporal-motion off, the depth filter off,
			      * or no history to compare with (a first frame, a cut) */
	DAO_MOTION_REFUSED,  /* estimated and not trusted (`reason`): the history stayed */
	DAO_MOTION_STILL,    /* accepted, moving no surface by 0.02 px: the history stayed */
	DAO_MOTION_APPLIED,  /* accepted: the history followed the motion */
};

/*
 * The camera's motion from the last frame to the one before, as
 * depth-temporal-motion=icp estimated it: p_prev = R p + t for a view
 * position p of the last frame (optical frame: x right, y down, z forward;
 * metres).  Filled like struct dao_timings: `size` first, fields appended.
 */
struct dao_motion_info {
	uint32_t size;         /* bytes filled, set by the library */
	int state;             /* enum dao_motion_state */
	double rotation[9];    /* R, row-major (the identity with state NONE) */
	double translation[3]; /* t, m */
	int reason;            /* REFUSED: 1 too few pairs, 2 ill-posed (a flat wall),
				* 3 residual too large (a cut), 4 motion beyond 15 degrees or
				* 0.25 m, 5 the solve broke down; else 0 */
	int points;            /* source points (every 4th pixel with depth and a normal) */
	int pairs;             /* pairs of the last Gauss-Newton step */
	float rms;             /* their RMS point-to-plane residual, m */
	float condition;       /* smallest / largest eigenvalue of the scaled 6x6 system */
	int iterations;        /* Gauss-Newton steps run */
	/* where the motion came from: 0 the depth (ICP, or nothing with state NONE),
	 * 1 the poses given with dao_context_set_pose (depth-temporal-motion=source),
	 * 2 ICP seeded with them (source+icp) */
	int origin;
	uint32_t reserved;     /* 0; no tail padding a later field could fall into */
};

/* dao_motion_info.origin */
enum dao_motion_origin {
	DAO_MOTION_FROM_DEPTH = 0,
	DAO_MOTION_FROM_SOURCE,
	DAO_MOTION_FROM_SOURCE_ICP,
};

/* A struct dao_motion_info with its size set and every field 0. */
#define DAO_MOTION_INFO_INIT { .size = sizeof(struct dao_motion_info) }

/* Copies the motion figures into `out` of `size` bytes, as dao_context_timings_sized(). */
DAO_API int dao_context_motion_sized(const struct dao_context *ctx, struct dao_motion_info *out,
				     size_t size);

/* Copies the last frame's camera motion into `out` (dao_context_motion_sized()). */
static inline void dao_context_motion(const struct dao_context *ctx, struct dao_motion_info *out)
{
	(void)dao_context_motion_sized(ctx, out, sizeof(*out));
}

/*
 * Moves a camera pose by one frame's motion as dao_context_motion() reported
 * it: (rotation, translation), the pose of the frame before (a row-major
 * rotation matrix and metres, camera to a fixed frame: x_fixed = R x + t, as
 * <depthao/pose.h> has it), becomes this frame's, R M and R m + t for the
 * motion's M and m, where the motion was accepted (state STILL or APPLIED,
 * every value finite); R is kept a rotation through its unit quaternion
 * however many motions it composes.  From the identity at the first frame
 * this is the pose depthao process --pose-out prints and depthaod's sinks
 * carry: the camera in the first frame's optical frame.  1: the pose moved;
 * 0: the frame's motion is unknown or was refused (NONE, REFUSED, a value not
 * finite) and the pose is kept, the motion taken as none, as the depth filter
 * takes it; -EINVAL: a NULL argument or a motion whose size does not reach
 * its translation.
 */
DAO_API int dao_motion_accumulate(const struct dao_motion_info *motion, double rotation[9],
				  double translation[3]);

/*
 * The camera's pose as the context keeps it: the motions of the frames it
 * processed composed with dao_motion_accumulate() from the track's first
 * frame (its origin, the identity: the world is that frame's optical frame),
 * camera to world.  A track runs while the motion is followed (the
 * temporal depth filter on and depth-temporal-motion not off); switching
 * the motion off ends it (frames 0), dao_context_reset() too, and the next
 * frame that follows the motion starts a new one.  A frame whose motion is
 * unknown (a cut, a gap in the poses given) or refused keeps the pose: the
 * motion taken as none, as the depth filter takes it (dead reckoning).
 * depthao process --pose-out prints this pose for every frame, held ones
 * included; depthaod's sinks, the ROS node and Python hand it on only where
 * `current` is 1 (GStreamer's messages carry the flag).  Filled like struct
 * dao_motion_info: `size` first, fields appended.
 */
struct dao_pose_track {
	uint32_t size;          /* bytes filled, set by the library */
	int current;            /* 1: the pose is the last frame's (the origin, or its motion
				 * was accepted); 0: held from an earlier frame, or no track */
	uint64_t frames;        /* frames of the track, the origin and the last one included;
				 * 0: no track (the motion not followed, no frame since a reset) */
	uint64_t accepted;      /* ... after the origin whose motion moved the pose (STILL,
				 * APPLIED) */
	uint64_t refused;       /* ... after the origin whose estimate was refused (REFUSED) */
	double rotation[9];     /* camera to world, row-major (the identity without a track) */
	double translation[3];  /* the optical centre in the world, m */
	uint64_t frame_index;   /* the frame the pose is of, the last one where it was
				 * current (its frame_index for dao_context_process) ... */
	uint64_t timestamp_ns;  /* ... and that frame's depth timestamp_ns (0 without a track) */
};

/* A struct dao_pose_track with its size set and every field 0. */
#define DAO_POSE_TRACK_INIT { .size = sizeof(struct dao_pose_track) }

/* Copies the pose track into `out` of `size` bytes, as dao_context_timings_sized(). */
DAO_API int dao_context_pose_track_sized(const struct dao_context *ctx,
					 struct dao_pose_track *out, size_t size);

/* Copies the camera's pose track into `out` (dao_context_pose_track_sized()). */
static inline void dao_context_pose_track(const struct dao_context *ctx,
					  struct dao_pose_track *out)
{
	(void)dao_context_pose_track_sized(ctx, out, sizeof(*out));
}

/*
 * The camera's pose for the next dao_context_process() call, from the source
 * (a recording's tf or odometry, a trajectory file, a tracker): `rotation` a
 * unit quaternion x, y, z, w (w last) of the rotation from the camera's
 * optical frame (x right, y down, z forward) to a fixed world frame,
 * `translation` the optical centre in that frame, metres; x_world =
 * R x_camera + t.  rotation NULL: no pose for that frame.  The pose is used
 * by one process call, the next, and then forgotten; the motion between the
 * poses of two consecutive frames drives depth-temporal-motion=source (as is)
 * and source+icp (ICP's seed); the other modes ignore it.  -EINVAL with a
 * message for a NULL context, a non-finite value, a quaternion whose norm
 * is not 1 within 1e-3 (it is normalised), or a translation beyond 1e6 m;
 * the context then has no pose for the next frame.
 */
DAO_API int dao_context_set_pose(struct dao_context *ctx, const double rotation[4],
				 const double translation[3], struct dao_error *err);

/* The kernel set the context runs (its "simd" parameter with AUTO resolved). */
DAO_API enum dao_simd dao_context_simd(const struct dao_context *ctx);

#ifdef __cplusplus
}
#endif
#endif
