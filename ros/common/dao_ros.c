/* SPDX-License-Identifier: MIT */
/*
 * ROS messages' fields to depthao frames and back, and the AO parameters as
 * node parameters (see dao_ros.h).  Public API only.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dao_ros.h"

struct dao_ros_proc {
	struct dao_ros_settings settings;
	struct dao_params params;
	struct dao_context *ctx;        /* NULL until the first frame */
	struct dao_camera cam;
	double k[4];                    /* fx fy cx cy the context was made for */
	uint8_t *swapped;               /* byte-swapped depth of a big-endian image */
	size_t swapped_size;
	struct dao_frame depth;         /* the prepared frame (points into the message or swapped) */
	uint64_t frames, index;
	uint64_t last_stamp;
};

void dao_ros_settings_init(struct dao_ros_settings *s)
{
	s->depth_unit = 0.001f;
	s->ao_encoding = DAO_ROS_AO_MONO16;
}

const char *dao_ros_ao_encoding_name(enum dao_ros_ao_encoding e)
{
	return e == DAO_ROS_AO_32FC1 ? "32FC1" : "mono16";
}

int dao_ros_settings_set(struct dao_ros_settings *s, const char *name, const char *value,
			 struct dao_error *err)
{
	if (!name || !value)
		return dao_error_set(err, -EINVAL, "a node setting needs a name and a value");
	if (strcmp(name, "depth_unit") == 0) {
		char *end;
		double v = strtod(value, &end);
		if (*end || end == value || !isfinite(v) || v <= 0.0 || v > 1.0)
			return dao_error_set(err, -EINVAL,
				    "depth_unit: '%s' is not a unit in metres per count in (0, 1] "
				    "(0.001 for millimetres, 0.0001 for a D405)", value);
		s->depth_unit = (float)v;
		return 0;
	}
	if (strcmp(name, "ao_encoding") == 0) {
		if (strcmp(value, "mono16") == 0 || strcmp(value, "16UC1") == 0)
			s->ao_encoding = DAO_ROS_AO_MONO16;
		else if (strcmp(value, "32FC1") == 0)
			s->ao_encoding = DAO_ROS_AO_32FC1;
		else
			return dao_error_set(err, -EINVAL, "ao_encoding: '%s' is not mono16 or 32FC1", value);
		return 0;
	}
	return dao_error_set(err, -ENOENT, "'%s' is not a node setting", name);
}

int dao_ros_proc_create(struct dao_ros_proc **out, const struct dao_ros_settings *s,
			const struct dao_params *params, struct dao_error *err)
{
	if (!out || !s)
		return dao_error_set(err, -EINVAL, "dao_ros_proc_create: NULL argument");
	*out = NULL;
	struct dao_params p;
	if (params) {
		p = *params;
	} else {
		dao_params_init(&p, DAO_QUALITY_DEFAULT);
		dao_params_stream_defaults(&p);
	}
	int r = dao_params_validate(&p, err);
	if (r)
		return r;
	if (!isfinite(s->depth_unit) || s->depth_unit <= 0.0f)
		return dao_error_set(err, -EINVAL, "depth_unit %g is not a positive number of metres",
			    (double)s->depth_unit);
	struct dao_ros_proc *proc = calloc(1, sizeof *proc);
	if (!proc)
		return dao_error_set(err, -ENOMEM, "out of memory");
	proc->settings = *s;
	proc->params = p;
	*out = proc;
	return 0;
}

void dao_ros_proc_destroy(struct dao_ros_proc *proc)
{
	if (!proc)
		return;
	dao_context_destroy(proc->ctx);
	free(proc->swapped);
	free(proc);
}

/* The encodings a depth image may have, and what they become. */
static int depth_format(const char *encoding, enum dao_pixfmt *fmt)
{
	if (!strcmp(encoding, "16UC1") || !strcmp(encoding, "mono16"))
		*fmt = DAO_PIXFMT_DEPTH16;
	else if (!strcmp(encoding, "32FC1"))
		*fmt = DAO_PIXFMT_DEPTH_F32;
	else
		return -EINVAL;
	return 0;
}

static int host_big_endian(void)
{
	const uint16_t one = 1;
	return *(const uint8_t *)&one == 0;
}

static int check_image(const struct dao_ros_image *img, enum dao_pixfmt *fmt,
		       struct dao_error *err)
{
	if (!img->encoding || depth_format(img->encoding, fmt))
		return dao_error_set(err, -EINVAL,
			    "depth image encoding '%s' is not accepted: depthao takes 16UC1 or "
			    "mono16 (counts of depth_unit metres) or 32FC1 (metres)",
			    img->encoding ? img->encoding : "");
	if (!img->width || !img->height || img->width > DAO_MAX_DIMENSION ||
	    img->height > DAO_MAX_DIMENSION)
		return dao_error_set(err, -EINVAL, "depth image of %ux%u: width and height must be 1..%d",
			    img->width, img->height, DAO_MAX_DIMENSION);
	size_t bpp = dao_pixfmt_bytes_per_pixel(*fmt);
	if ((size_t)img->step < img->width * bpp)
		return dao_error_set(err, -EINVAL, "depth image %ux%u %s: step %u is below width x %zu bytes",
			    img->width, img->height, img->encoding, img->step, bpp);
	if (img->step > INT32_MAX || !img->data ||
	    img->size < (size_t)img->step * img->height)
		return dao_error_set(err, -EINVAL,
			    "depth image %ux%u %s: %zu bytes of data, step %u x height needs %zu",
			    img->width, img->height, img->encoding, img->size, img->step,
			    (size_t)img->step * img->height);
	return 0;
}

static int check_info(const struct dao_ros_camera_info *info, const struct dao_ros_image *img,
		      struct dao_error *err)
{
	if (!info->k)
		return dao_error_set(err, -EINVAL, "the camera info has no K matrix");
	if (info->width != img->width || info->height != img->height)
		return dao_error_set(err, -EINVAL,
			    "the camera info is for %ux%u, the depth image is %ux%u: publish the "
			    "camera info of the depth image (binned or cropped images are not handled)",
			    info->width, info->height, img->width, img->height);
	const double *k = info->k;
	if (!(k[0] > 0.0) || !(k[4] > 0.0) || !isfinite(k[0]) || !isfinite(k[4]) ||
	    !isfinite(k[2]) || !isfinite(k[5]))
		return dao_error_set(err, -EINVAL,
			    "the camera info's K has fx %g, fy %g, cx %g, cy %g: a calibrated "
			    "camera has fx, fy > 0 (an uncalibrated driver publishes zeros)",
			    k[0], k[4], k[2], k[5]);
	return 0;
}

static void set_layout(struct dao_ros_output *o, const char *encoding, uint32_t w, uint32_t h,
		       uint32_t bpp)
{
	o->encoding = encoding;
	o->width = w;
	o->height = h;
	o->step = w * bpp;
	o->size = (size_t)o->step * h;
	o->data = NULL;
}

int dao_ros_proc_prepare(struct dao_ros_proc *proc, const struct dao_ros_image *depth,
			 const struct dao_ros_camera_info *info, struct dao_ros_output *ao,
			 struct dao_ros_output *shaded, int *distorted, struct dao_error *err)
{
	enum dao_pixfmt fmt = DAO_PIXFMT_NONE;
	int r = check_image(depth, &fmt, err);
	if (!r)
		r = check_info(info, depth, err);
	if (r)
		return r;
	/* with distortion, the rectified image's intrinsics (P), as image_geometry */
	struct dao_camera cam;
	enum dao_camera_info_matrix from;
	r = dao_camera_from_camera_info(&cam, depth->width, depth->height, info->k, info->p,
					info->d, info->d ? info->d_count : 0, &from, err);
	if (r)
		return r;
	*distorted = from == DAO_CAMERA_INFO_P_RECTIFIED   ? DAO_ROS_DISTORTED_P
		     : from == DAO_CAMERA_INFO_K_DISTORTED ? DAO_ROS_DISTORTED_K
							   : DAO_ROS_UNDISTORTED;
	const double use[4] = { cam.fx, cam.fy, cam.cx, cam.cy };
	if (!proc->ctx || proc->cam.width != depth->width || proc->cam.height != depth->height ||
	    memcmp(use, proc->k, sizeof proc->k)) {
		struct dao_context *ctx;
		if ((r = dao_context_create(&ctx, &cam, &proc->params, err)))
			return r;
		dao_context_destroy(proc->ctx);
		proc->ctx = ctx;
		proc->cam = cam;
		memcpy(proc->k, use, sizeof proc->k);
		proc->index = 0;
	}
	size_t bpp = dao_pixfmt_bytes_per_pixel(fmt);
	const void *data = depth->data;
	uint32_t step = depth->step;
	if (bpp > 1 && (depth->is_bigendian != 0) != host_big_endian()) {
		/* the other byte order: swap into a buffer kept for the next frames */
		size_t row = depth->width * bpp, need = row * depth->height;
		if (need > proc->swapped_size) {
			uint8_t *b = realloc(proc->swapped, need);
			if (!b)
				return dao_error_set(err, -ENOMEM, "out of memory for a %zu-byte depth image",
					    need);
			proc->swapped = b;
			proc->swapped_size = need;
		}
		for (uint32_t y = 0; y < depth->height; y++) {
			const uint8_t *s = (const uint8_t *)depth->data + (size_t)y * depth->step;
			uint8_t *d = proc->swapped + y * row;
			for (size_t x = 0; x < row; x += bpp)
				for (size_t b = 0; b < bpp; b++)
					d[x + b] = s[x + bpp - 1 - b];
		}
		data = proc->swapped;
		step = (uint32_t)row;
	}
	proc->depth = (struct dao_frame){
		.size = DAO_FRAME_SIZE,
		.format = fmt, .width = depth->width, .height = depth->height,
		.stride = (int32_t)step, .data = (void *)(uintptr_t)data,
		.depth_unit = fmt == DAO_PIXFMT_DEPTH16 ? proc->settings.depth_unit : 0.0f,
	};
	if (proc->settings.ao_encoding == DAO_ROS_AO_32FC1)
		set_layout(ao, "32FC1", depth->width, depth->height, 4);
	else
		set_layout(ao, "mono16", depth->width, depth->height, 2);
	set_layout(shaded, "rgb8", depth->width, depth->height, 3);
	return 0;
}

/* The camera is the same and frames follow each other (the indices say so to
 * the temporal filters), unless time went back: a bag played again. */
static void follow_or_restart(struct dao_ros_proc *proc, uint64_t stamp_ns)
{
	if (proc->frames && stamp_ns < proc->last_stamp) {
		dao_context_reset(proc->ctx); /* the pose track starts over too */
	}
	proc->last_stamp = stamp_ns;
}

int dao_ros_proc_set_pose(struct dao_ros_proc *proc, uint64_t stamp_ns, const double rotation[4],
			  const double translation[3], struct dao_error *err)
{
	if (!proc->ctx || !proc->depth.data)
		return dao_error_set(err, -EINVAL, "dao_ros_proc_set_pose: the image was not prepared");
	/* a reset forgets a pose given before it: restart first, then the pose */
	follow_or_restart(proc, stamp_ns);
	return dao_context_set_pose(proc->ctx, rotation, translation, err);
}

int dao_ros_proc_run(struct dao_ros_proc *proc, const struct dao_ros_image *depth,
		     uint64_t stamp_ns, struct dao_ros_output *ao, struct dao_ros_output *shaded,
		     struct dao_error *err)
{
	if (!proc->ctx || !proc->depth.data || proc->depth.width != depth->width ||
	    proc->depth.height != depth->height)
		return dao_error_set(err, -EINVAL, "dao_ros_proc_run: the image was not prepared");
	if (!ao->data)
		return dao_error_set(err, -EINVAL, "dao_ros_proc_run: no AO buffer");
	follow_or_restart(proc, stamp_ns);
	struct dao_frame out = {
		.size = DAO_FRAME_SIZE,
		.format = proc->settings.ao_encoding == DAO_ROS_AO_32FC1 ? DAO_PIXFMT_GRAY_F32
									 : DAO_PIXFMT_GRAY16,
		.width = ao->width, .height = ao->height, .stride = (int32_t)ao->step,
		.data = ao->data,
	};
	proc->depth.timestamp_ns = stamp_ns;
	int r = dao_context_process(proc->ctx, &proc->depth, NULL, proc->index, &out, err);
	if (r)
		return r;
	proc->index++;
	proc->frames++;
	if (shaded && shaded->data) {
		struct dao_frame rgb = {
			.size = DAO_FRAME_SIZE,
			.format = DAO_PIXFMT_RGB24, .width = shaded->width,
			.height = shaded->height, .stride = (int32_t)shaded->step,
			.data = shaded->data,
		};
		r = dao_context_shade(proc->ctx, &rgb, err);
	}
	return r;
}

void dao_ros_proc_depth_layout(const struct dao_ros_proc *proc, struct dao_ros_output *out)
{
	if (proc->depth.format == DAO_PIXFMT_DEPTH_F32)
		set_layout(out, "32FC1", proc->depth.width, proc->depth.height, 4);
	else
		set_layout(out, "16UC1", proc->depth.width, proc->depth.height, 2);
}

int dao_ros_proc_depth(struct dao_ros_proc *proc, struct dao_ros_output *out,
		       struct dao_error *err)
{
	if (!proc->ctx || !proc->frames)
		return dao_error_set(err, -EAGAIN, "dao_ros_proc_depth: no frame was run yet");
	const int f32 = proc->depth.format == DAO_PIXFMT_DEPTH_F32;
	if (!out->data || out->width != proc->depth.width || out->height != proc->depth.height ||
	    out->step < out->width * (f32 ? 4u : 2u) || out->step > INT32_MAX)
		return dao_error_set(err, -EINVAL, "dao_ros_proc_depth: no buffer of the depth's layout");
	struct dao_frame d = {
		.size = DAO_FRAME_SIZE,
		.format = f32 ? DAO_PIXFMT_DEPTH_F32 : DAO_PIXFMT_DEPTH16,
		.width = out->width, .height = out->height, .stride = (int32_t)out->step,
		.data = out->data, .depth_unit = f32 ? 0.0f : proc->settings.depth_unit,
	};
	int r = dao_context_get_depth(proc->ctx, &d, err);
	if (r || !f32)
		return r;
	for (uint32_t y = 0; y < out->height; y++) { /* REP 118: NaN = no depth */
		float *row = (float *)((uint8_t *)out->data + (size_t)y * out->step);
		for (uint32_t x = 0; x < out->width; x++)
			if (row[x] == 0.0f)
				row[x] = NAN;
	}
	return 0;
}

void dao_ros_proc_get_params(const struct dao_ros_proc *proc, struct dao_params *out)
{
	*out = proc->params;
}

int dao_ros_proc_set_params(struct dao_ros_proc *proc, const struct dao_params *params,
			    struct dao_error *err)
{
	int r = proc->ctx ? dao_context_set_params(proc->ctx, params, err)
			  : dao_params_validate(params, err);
	if (r)
		return r;
	proc->params = *params; /* switched off, the context's pose track ends there */
	return 0;
}

uint64_t dao_ros_proc_frames(const struct dao_ros_proc *proc)
{
	return proc->frames;
}

static int enum_count(const struct dao_param_info *pi)
{
	int n = 0;
	while (pi->enum_names[n])
		n++;
	return n;
}

void dao_ros_param_describe(const struct dao_param_info *pi, struct dao_ros_param_desc *out)
{
	snprintf(out->name, sizeof out->name, "%s", pi->name);
	for (char *c = out->name; *c; c++)
		if (*c == '-')
			*c = '_';
	out->info = pi;
	out->min = pi->min;
	out->max = pi->max;
	switch (pi->type) {
	case DAO_PARAM_FLOAT:
		out->kind = DAO_ROS_PARAM_DOUBLE;
		break;
	case DAO_PARAM_INT:
		out->kind = DAO_ROS_PARAM_INT;
		break;
	case DAO_PARAM_ENUM:
		out->kind = DAO_ROS_PARAM_INT;
		out->min = 0;
		out->max = enum_count(pi) - 1;
		break;
	case DAO_PARAM_COLOR:
		out->kind = DAO_ROS_PARAM_STRING;
		break;
	}
}

static const void *field(const struct dao_params *p, const struct dao_param_info *pi)
{
	return (const char *)p + pi->offset;
}

double dao_ros_param_get_double(const struct dao_params *p, const struct dao_param_info *pi)
{
	if (pi->type == DAO_PARAM_FLOAT)
		return *(const float *)field(p, pi);
	return (double)dao_ros_param_get_int(p, pi);
}

long dao_ros_param_get_int(const struct dao_params *p, const struct dao_param_info *pi)
{
	switch (pi->type) {
	case DAO_PARAM_FLOAT:
		return lround(*(const float *)field(p, pi));
	case DAO_PARAM_COLOR:
		return (long)*(const uint32_t *)field(p, pi);
	default:
		return *(const int *)field(p, pi);
	}
}

int dao_ros_param_get_string(const struct dao_params *p, const struct dao_param_info *pi,
			     char *buf, size_t len, struct dao_error *err)
{
	if (pi->type == DAO_PARAM_FLOAT) {
		/* %.9g: the float back exactly (dao_params_get's %g keeps 6 digits) */
		int n = snprintf(buf, len, "%.9g", (double)*(const float *)field(p, pi));
		return n < 0 || (size_t)n >= len ? dao_error_set(err, -EOVERFLOW, "%s: buffer too small",
							 pi->name) : 0;
	}
	return dao_params_get(p, pi->name, buf, len, err);
}

int dao_ros_param_set_double(struct dao_params *p, const struct dao_param_info *pi, double v,
			     struct dao_error *err)
{
	char text[64];
	if (pi->type != DAO_PARAM_FLOAT) {
		if (v != floor(v) || fabs(v) > 1e9)
			return dao_error_set(err, -EINVAL, "%s: %g is not an integer", pi->name, v);
		return dao_ros_param_set_int(p, pi, (long)v, err);
	}
	snprintf(text, sizeof text, "%.17g", v);
	return dao_params_set(p, pi->name, text, err);
}

int dao_ros_param_set_int(struct dao_params *p, const struct dao_param_info *pi, long v,
			  struct dao_error *err)
{
	char text[32];
	switch (pi->type) {
	case DAO_PARAM_ENUM: {
		int n = enum_count(pi);
		if (v < 0 || v >= n) {
			char list[192];
			size_t used = 0;
			list[0] = '\0';
			for (int i = 0; i < n && used < sizeof list; i++)
				used += (size_t)snprintf(list + used, sizeof list - used, "%s%d %s",
							 i ? ", " : "", i, pi->enum_names[i]);
			return dao_error_set(err, -EINVAL, "%s: %ld is not one of: %s", pi->name, v, list);
		}
		return dao_params_set(p, pi->name, pi->enum_names[v], err);
	}
	case DAO_PARAM_COLOR:
		if (v < 0 || v > 0xffffff)
			return dao_error_set(err, -EINVAL, "%s: %ld is not a colour 0xRRGGBB", pi->name, v);
		snprintf(text, sizeof text, "%06lx", (unsigned long)v);
		return dao_params_set(p, pi->name, text, err);
	default:
		snprintf(text, sizeof text, "%ld", v);
		return dao_params_set(p, pi->name, text, err);
	}
}

int dao_ros_param_set_string(struct dao_params *p, const struct dao_param_info *pi,
			     const char *v, struct dao_error *err)
{
	return dao_params_set(p, pi->name, v, err);
}

int dao_ros_proc_pose(const struct dao_ros_proc *proc, double rotation[4], double translation[3])
{
	struct dao_pose_track pt = DAO_POSE_TRACK_INIT;
	if (!proc->ctx)
		return 0;
	dao_context_pose_track(proc->ctx, &pt);
	if (!pt.current)
		return 0;
	dao_pose_matrix_to_quat(pt.rotation, rotation);
	memcpy(translation, pt.translation, 3 * sizeof *translation);
	return 1;
}
