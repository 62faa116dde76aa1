/* SPDX-License-Identifier: MIT */
/*
 * The ROS-independent core of depthao's ROS nodes, in C on the public API.
 *
 * A ROS node is a shell around this layer: it copies the fields of the
 * sensor_msgs/Image and sensor_msgs/CameraInfo it receives (the same fields in
 * ROS 1 and ROS 2) into the plain structs below, lets dao_ros_proc_* check
 * them, follow the camera and compute AO and the shaded image into buffers the
 * shell owns (its outgoing messages' data), and maps its node parameters onto
 * the AO parameter table with dao_ros_param_*.  Nothing here knows ROS: the
 * ROS 1 node (ros/ros1/depthao_node.cpp) is its only C++, and a ROS 2 node
 * would reuse this file unchanged.
 *
 * Steady state allocates nothing: buffers are made when the first frame or a
 * new camera (size or intrinsics) arrives.
 */
#ifndef DAO_ROS_H
#define DAO_ROS_H

#include <stddef.h>
#include <stdint.h>

#include <depthao/depthao.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The fields of a sensor_msgs/Image that depthao reads (data is not copied). */
struct dao_ros_image {
	uint32_t width, height;
	const char *encoding;   /* "16UC1", "mono16" (counts) or "32FC1" (metres) */
	int is_bigendian;
	uint32_t step;          /* bytes per row */
	const void *data;
	size_t size;            /* bytes at data */
};

/* The fields of a sensor_msgs/CameraInfo that depthao reads. */
struct dao_ros_camera_info {
	uint32_t width, height;
	const double *k;        /* 9 values, row-major: fx 0 cx, 0 fy cy, 0 0 1 */
	const double *d;        /* distortion coefficients (may be NULL) */
	size_t d_count;
	const double *p;        /* 12 values, row-major 3x4: the rectified image's projection
				 * (fx' 0 cx' Tx, 0 fy' cy' Ty, 0 0 1 0); may be NULL */
};

/* What dao_ros_proc_prepare() says of the camera info's distortion. */
enum dao_ros_distortion {
	DAO_ROS_UNDISTORTED = 0,        /* D all zeros (or none): K's intrinsics */
	DAO_ROS_DISTORTED_K,            /* distortion and no usable P: K's intrinsics */
	DAO_ROS_DISTORTED_P,            /* distortion: P's intrinsics, the rectified image's */
};

/* The AO image's encoding. */
enum dao_ros_ao_encoding {
	DAO_ROS_AO_MONO16 = 0,  /* round(visibility x 65535) */
	DAO_ROS_AO_32FC1,       /* visibility in [0, 1] */
};

/* What a node is told at start, beside the AO parameters. */
struct dao_ros_settings {
	float depth_unit;                   /* metres per count of 16UC1 / mono16 (0.001) */
	enum dao_ros_ao_encoding ao_encoding;
};

/* Defaults: depth_unit 0.001, mono16. */
void dao_ros_settings_init(struct dao_ros_settings *s);

/*
 * Sets one node setting from text: "depth_unit" (metres, > 0), "ao_encoding"
 * ("mono16" or "32FC1").  Returns 0,
 * -ENOENT when `name` is not a node setting, or -EINVAL with a message.
 */
int dao_ros_settings_set(struct dao_ros_settings *s, const char *name, const char *value,
			 struct dao_error *err);

/* The encoding name of an AO encoding ("mono16", "32FC1"). */
const char *dao_ros_ao_encoding_name(enum dao_ros_ao_encoding e);

/* An output image: its layout is given by dao_ros_proc_prepare(); the shell
 * points `data` at `size` bytes it owns before dao_ros_proc_run(). */
struct dao_ros_output {
	const char *encoding;   /* "mono16", "32FC1" or "rgb8" */
	uint32_t width, height;
	uint32_t step;
	size_t size;            /* step x height */
	void *data;
};

struct dao_ros_proc;

/* `params` may be NULL: the default preset with the stream defaults
 * (dao_params_stream_defaults: a topic is a stream from one camera). */
int dao_ros_proc_create(struct dao_ros_proc **out, const struct dao_ros_settings *s,
			const struct dao_params *params, struct dao_error *err);
void dao_ros_proc_destroy(struct dao_ros_proc *proc);

/*
 * Checks a depth image and its camera info and gives the layout of the
 * outputs for it.  A new size or new intrinsics (re)create the AO context
 * (allocation happens here only).  The intrinsics are K's (fx K[0], fy
 * K[4], cx K[2], cy K[5]) unless D has a coefficient that is not 0 and P is
 * usable (P[0], P[5] > 0, finite): then P's (fx P[0], fy P[5], cx P[2], cy
 * P[6]), the rectified image's, as ROS's image_geometry takes them.
 * *distorted is an enum dao_ros_distortion: not 0 when D is, and depthao
 * does not undistort, so the depth must be rectified (the shell warns
 * once).  Errors name
 * what was wrong: an encoding that is not accepted, a step or data size that
 * does not hold the image, an image and camera info of different sizes.
 */
int dao_ros_proc_prepare(struct dao_ros_proc *proc, const struct dao_ros_image *depth,
			 const struct dao_ros_camera_info *info, struct dao_ros_output *ao,
			 struct dao_ros_output *shaded, int *distorted, struct dao_error *err);

/*
 * Computes AO (and the shaded image when shaded->data is not NULL) of the
 * depth image last given to dao_ros_proc_prepare() into the outputs' data.
 * stamp_ns is the image's capture time: frames continue the temporal
 * filters' histories unless the stamp goes back (a bag played again).
 */
int dao_ros_proc_run(struct dao_ros_proc *proc, const struct dao_ros_image *depth,
		     uint64_t stamp_ns, struct dao_ros_output *ao, struct dao_ros_output *shaded,
		     struct dao_error *err);

/*
 * The camera's pose for the frame of `stamp_ns`, to be run next (after
 * dao_ros_proc_prepare(), before dao_ros_proc_run()): the depth image's
 * frame in a fixed frame, as the shell looked it up in tf, given to the
 * context as dao_context_set_pose() takes it (`rotation` x, y, z, w of the
 * rotation from the image's optical frame to the fixed frame, `translation`
 * its origin there, metres).  rotation NULL: this frame has no pose.
 * depth_temporal_motion source and source+icp follow the motion between
 * the poses of consecutive frames; the other modes ignore them.  A stamp
 * that goes back starts the histories over here, as in dao_ros_proc_run().
 * -EINVAL before a prepare, or with the library's message for a pose that
 * is not one (a non-finite value, a quaternion that is not a unit one):
 * the frame then has no pose.
 */
int dao_ros_proc_set_pose(struct dao_ros_proc *proc, uint64_t stamp_ns, const double rotation[4],
			  const double translation[3], struct dao_error *err);

/*
 * The filtered depth of the frame last run (dao_context_get_depth: the depth
 * the AO was computed from), as a depth image for depth_image_proc and the
 * other image-pipeline nodes.  dao_ros_proc_depth_layout() gives its layout
 * after dao_ros_proc_prepare(): "16UC1" counts of depth_unit (the input's
 * unit) for 16UC1 and mono16 input, "32FC1" metres for 32FC1 input.
 * dao_ros_proc_depth() fills out->data after dao_ros_proc_run(): 0 where
 * there is no depth in 16UC1, NaN in 32FC1 (REP 118).  -EAGAIN before a
 * frame was run.
 */
void dao_ros_proc_depth_layout(const struct dao_ros_proc *proc, struct dao_ros_output *out);
int dao_ros_proc_depth(struct dao_ros_proc *proc, struct dao_ros_output *out,
		       struct dao_error *err);

/*
 * The camera's pose after the last dao_ros_proc_run(), where the motion is
 * followed (depth_temporal > 0, depth_temporal_motion not off): the context's
 * pose track (dao_context_pose_track), the motions accepted since the first
 * followed frame composed, as depthao process --pose-out and depthaod give it
 * (x_first = R x + t; `rotation` x, y, z, w from the image's optical frame to
 * the first followed frame's, `translation` metres).  It starts over with the
 * histories (new intrinsics, a stamp going back) and when the motion is
 * followed again.  1 with the pose; 0: none to give (the motion not
 * followed, a frame whose motion estimate was refused or is unknown: after a
 * cut, or without a pose in source mode).
 */
int dao_ros_proc_pose(const struct dao_ros_proc *proc, double rotation[4], double translation[3]);

/* The AO parameters now in use, and new ones (validated; applied at once). */
void dao_ros_proc_get_params(const struct dao_ros_proc *proc, struct dao_params *out);
int dao_ros_proc_set_params(struct dao_ros_proc *proc, const struct dao_params *params,
			    struct dao_error *err);

/* Frames processed since creation. */
uint64_t dao_ros_proc_frames(const struct dao_ros_proc *proc);

/*
 * The AO parameters as node parameters.  ROS names allow no '-': a node
 * parameter is the table's name with '_' ("depth_min"); dao_param_find()
 * takes either.
 */
enum dao_ros_param_kind {
	DAO_ROS_PARAM_DOUBLE = 0,  /* FLOAT entries */
	DAO_ROS_PARAM_INT,         /* INT entries, and ENUM entries by index */
	DAO_ROS_PARAM_STRING,      /* COLOR entries, "RRGGBB" */
};

struct dao_ros_param_desc {
	char name[64];                   /* with '_' */
	enum dao_ros_param_kind kind;
	double min, max;                 /* ENUM: 0 .. count - 1 */
	const struct dao_param_info *info;
};

void dao_ros_param_describe(const struct dao_param_info *pi, struct dao_ros_param_desc *out);

/* Values of the parameter `pi` in `p`: as a double (DOUBLE), an int (INT,
 * ENUM index, COLOR 0xRRGGBB), text (any kind: "0.4", "domain", "202040"). */
double dao_ros_param_get_double(const struct dao_params *p, const struct dao_param_info *pi);
long dao_ros_param_get_int(const struct dao_params *p, const struct dao_param_info *pi);
int dao_ros_param_get_string(const struct dao_params *p, const struct dao_param_info *pi,
			     char *buf, size_t len, struct dao_error *err);

/*
 * Sets a parameter from a node parameter of any ROS type: a double (FLOAT;
 * INT when it is integral), an int (INT, FLOAT, ENUM by index, COLOR as
 * 0xRRGGBB) or a string (any entry, as dao_params_set() parses it: an
 * enum by name).  Range-checked; errors name the parameter and the range.
 */
int dao_ros_param_set_double(struct dao_params *p, const struct dao_param_info *pi, double v,
			     struct dao_error *err);
int dao_ros_param_set_int(struct dao_params *p, const struct dao_param_info *pi, long v,
			  struct dao_error *err);
int dao_ros_param_set_string(struct dao_params *p, const struct dao_param_info *pi,
			     const char *v, struct dao_error *err);

/* Nanoseconds of a ROS time (sec, nsec). */
static inline uint64_t dao_ros_stamp_ns(uint32_t sec, uint32_t nsec)
{
	return (uint64_t)sec * 1000000000u + nsec;
}

#ifdef __cplusplus
}
#endif
#endif
