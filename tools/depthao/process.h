/* SPDX-License-Identifier: MIT */
/* depthao process: what the PNG path (cmd_process.c) and the stream path share. */
#ifndef DAO_TOOLS_PROCESS_H
#define DAO_TOOLS_PROCESS_H

#include <stdint.h>
#include <stdio.h>

#include <depthao/depthao.h>
#include <depthao/io.h>
#include <depthao/plugin.h>

/* Kinect v1 / PrimeSense-like field of view used when nothing else is known. */
#define DEG2RAD (3.14159265358979323846 / 180.0)
#define DEFAULT_HFOV_DEG 58.5
#define DEFAULT_VFOV_DEG 45.6

/* --depth-out of float-metre input (32FC1 topics) without --depth-out-unit: millimetres,
 * the unit of most 16-bit depth cameras and of ROS's 16UC1 depth. */
#define PROCESS_FLOAT_DEPTH_OUT_UNIT 0.001

struct process_options {
	const char *input;
	const char *cmd;        /* the command its usage errors name: NULL = "process" */
	const char *ao_out, *shaded_out, *overlay_out;
	const char *cloud_out;  /* --cloud-out: a directory, or one FILE.ply */
	const char *mcap_out;   /* --mcap-out: FILE.mcap[?sink options] */
	const char *depth_out;  /* --depth-out: the filtered depth, 16-bit PNGs */
	const char *poses;      /* --poses: a TUM-format trajectory beside PNG input */
	/* --pose-frame, --pose-topic, --pose-gap: how a ROS recording's poses are read
	 * (its source's URI options pose_frame, pose_topic, pose_gap) */
	const char *pose_frame, *pose_topic, *pose_gap;
	double depth_out_unit;  /* --depth-out-unit: metres per count written (0 = the input's) */
	int cloud_filtered;     /* --cloud-depth filtered: clouds of the filtered depth */
	double depth_unit;
	const char *intrinsics, *fov, *intrinsics_file;
	double k[4];   /* parsed --intrinsics */
	double f[2];   /* parsed --fov, degrees */
	uint64_t frame_index;
	uint32_t start;        /* --start: first frame of a recording, 0-based */
	uint32_t max_frames;   /* --frames: 0 = all */
	int realtime;          /* --realtime: pace a recording by its timestamps */
	int quiet;
	uint64_t max_pixels;   /* --max-pixels: largest decoded depth image (0 = the default) */
	const char *pose_out;  /* --pose-out: the estimated camera poses (pose_out.c) */
	double pose_fps;       /* --pose-fps: their timestamps without the source's clock */
	struct dao_params params;
};

struct run_state {
	struct dao_context *ctx;
	struct dao_frame ao, rgb, overlay;
	struct dao_frame depth16;   /* --depth-out: the filtered depth in counts */
	struct dao_frame depth_m;   /* --cloud-depth filtered: the filtered depth in metres */
	double ms_total;
	size_t frames;
	size_t skipped;     /* a recording's frames that could not be read (warned, skipped) */
	struct dao_plugins *mcap_plugins; /* --mcap-out: the built-in sinks */
	struct dao_sink *mcap;
	unsigned mcap_streams; /* the streams it asked for besides (1u << enum dao_stream) */
	FILE *pose;            /* --pose-out: the file, the camera-to-world pose so far */
	uint64_t pose_t0;      /* the first frame's timestamp_ns */
	size_t source_posed;   /* frames the source gave a pose (depth-temporal-motion source) */
	size_t source_unposed; /* ... and frames it had none for (a gap) */
	char first_gap[256];   /* why the first of those had none */
};

double process_now_ms(void);
/* "depthao: MESSAGE" on stderr, with what to do when it was the pixel limit. */
void process_print_error(const struct dao_error *err);
int process_ensure_dir(const char *path);

/* --intrinsics, --fov and --intrinsics-file: at most one, the numbers parsed into
 * o->k and o->f.  0 or the usage error's exit status. */
int process_camera_options(struct process_options *o);

/*
 * The camera for w x h images: --intrinsics, --fov, --intrinsics-file, else
 * the source's intrinsics or field of view (src may be NULL), else the camera
 * file beside PNG input (camera_file_beside), else a default field of view
 * (with a warning).  0 or an exit status.
 */
int process_resolve_camera(const struct process_options *o, uint32_t w, uint32_t h,
			   const struct dao_source_info *src, struct dao_camera *cam);

/* The output paths of one frame; NULL where that output is not wanted. */
struct process_paths {
	const char *ao, *shaded, *overlay, *cloud, *depth;
};

/*
 * AO (and shading, the overlay of `color` when paths->overlay, the point cloud)
 * of one depth frame, written to the paths that are not NULL.
 */
int process_depth(const struct process_options *o, struct run_state *st,
		  const struct dao_frame *depth, const struct dao_frame *color,
		  const struct process_paths *paths, uint64_t index);

/* The frames of the options' outputs besides the AO and shaded image (the filtered depth
 * in counts and in metres), w x h: 0 or a negative errno (err set). */
int process_alloc_depth_outputs(const struct process_options *o, struct run_state *st,
				uint32_t w, uint32_t h, struct dao_error *err);
void process_free_outputs(struct run_state *st);

/* --cloud-out names one file (a name ending in .ply, or anything there that is not a
 * directory: /dev/stdout, a FIFO), else a directory of them. */
int process_cloud_is_file(const struct process_options *o);
/* The usage error for a .ply file with `frames` frames to write (0 if frames <= 1);
 * `stream`: a recording or device (--frames applies). */
int process_check_cloud_frames(const struct process_options *o, uint64_t frames, int stream);
/* DIR/BASE.ply for an input file name BASE.png (or any BASE.EXT, or BASE). */
char *process_cloud_name(const char *dir, const char *input_name);

/* --mcap-out: opens and negotiates the sink (0 or the exit status; nothing without the
 * option), writes a frame's depth, AO and shaded image (the shading done here unless
 * have_shaded), and closes it (finalises the file) keeping a non-zero status. */
int process_mcap_open(const struct process_options *o, struct run_state *st,
		      const struct dao_camera *cam, double fps);
int process_mcap_write(struct run_state *st, const struct dao_frame *depth, int have_shaded,
		       uint64_t index);
int process_mcap_close(struct run_state *st, int status);

/* --pose-out (pose_out.c): opens the file (0 or the exit status; nothing without the
 * option), writes the line of the frame just processed, the n-th of the run (0-based),
 * and closes it keeping a non-zero status. */
int process_pose_open(const struct process_options *o, struct run_state *st);
int process_pose_write(const struct process_options *o, struct run_state *st,
		       const struct dao_frame *depth, uint64_t n);
int process_pose_close(const struct process_options *o, struct run_state *st, int status);

/* process_source_poses.c: does the run take the source's poses (depth-temporal-motion
 * source or source+icp on a recording)?  The source's URI with the --pose-* options
 * (allocated; NULL for out of memory).  The pose of frame f given to the context
 * (0, or the exit status when the source cannot give poses), and the run's report. */
int process_wants_source_poses(const struct process_options *o);
char *process_source_uri(const struct process_options *o);
int process_source_pose(const struct process_options *o, struct run_state *st,
			struct dao_source *src, const struct dao_source_frame *f);
void process_source_poses_report(const struct process_options *o, const struct run_state *st);

/* Input that goes through a source plugin: "NAME:URI" or a path ending in .oni. */
int process_input_is_stream(const char *input);
/* The input without its "NAME:" prefix, if it has one. */
const char *process_input_path(const char *input);
/*
 * The source of o->input (any input: PNG files and directories through the
 * built-in images source), its plugins loaded: the built-in ones first, the
 * modules only when none takes it.  0 or the exit status, the message printed.
 */
int process_open_source(const struct process_options *o, struct dao_plugins **plugins,
			struct dao_source **src);
/* The whole run for such input; returns the exit status. */
int process_stream(const struct process_options *o);
/* "N frames, M ms/frame (AO), wrote OUTPUTS" on stderr, after a run. */
void process_print_summary(const struct process_options *o, const struct run_state *st);

#endif
