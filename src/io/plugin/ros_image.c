/* SPDX-License-Identifier: MIT */
/* Pixels and intrinsics of ROS messages, shared by the bag and mcap sources (ros_image.h). */
#include "plugin/ros_image.h"

#include <depthao/camera.h>

#include <depthao/uri.h>

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error_internal.h"

const char *const dao_ros_uri_options[] = {"topic", "unit", "color", "pose_frame", "pose_topic",
					    "pose_gap", NULL};

int dao_ros_uri_parse(const char *uri, const char *scheme, struct dao_ros_uri *u,
		      struct dao_error *err)
{
	size_t plen = dao_uri_path_len(uri, dao_ros_uri_options);
	memset(u, 0, sizeof(*u));
	u->pose_gap = 0.5;
	if (!(u->path = strndup(uri, plen)))
		return dao_error_set(err, -ENOMEM, "out of memory");
	if (!uri[plen])
		return 0;
	struct dao_options *o;
	int r = dao_options_parse(&o, scheme, uri + plen + 1, dao_ros_uri_options, err);
	if (r < 0)
		return r;
	double unit = 0;
	if ((r = dao_options_get_string(o, "topic", u->topic, sizeof u->topic, err)) >= 0 &&
	    (r = dao_options_get_string(o, "color", u->color, sizeof u->color, err)) >= 0 &&
	    (r = dao_options_get_string(o, "pose_frame", u->pose_frame, sizeof u->pose_frame,
					err)) >= 0 &&
	    (r = dao_options_get_string(o, "pose_topic", u->pose_topic, sizeof u->pose_topic,
					err)) >= 0 &&
	    (r = dao_options_get_double(o, "pose_gap", 0, 60, DAO_OPTIONS_MIN_EXCLUSIVE,
					&u->pose_gap, err)) >= 0 &&
	    (r = dao_options_get_double(o, "unit", 0, 1, DAO_OPTIONS_MIN_EXCLUSIVE, &unit, err)) > 0)
		u->unit = (float)unit;
	dao_options_free(o);
	return r < 0 ? r : 0;
}

void dao_ros_uri_free(struct dao_ros_uri *u)
{
	free(u->path);
	u->path = NULL;
}

void dao_ros_keep_frame_id(char *buf, uint32_t *len, const char *id, uint32_t n)
{
	*len = n;
	if (n <= DAO_TF_NAME_MAX && id)
		memcpy(buf, id, n);
	else if (!id)
		*len = 0;
}

void dao_ros_topic_list_add(char *buf, size_t cap, const char *name, const char *enc)
{
	size_t len = strlen(buf);
	if (len + 8 < cap)
		snprintf(buf + len, cap - len, "%s%s (%s)", len ? ", " : "", name, enc);
}

int dao_ros_depth_kind(const char *enc)
{
	if (!strcmp(enc, "16UC1") || !strcmp(enc, "mono16"))
		return 1;
	if (!strcmp(enc, "32FC1"))
		return 2;
	return 0;
}

uint32_t dao_ros_color_bytes(const char *enc)
{
	if (!strcmp(enc, "rgb8") || !strcmp(enc, "bgr8"))
		return 3;
	if (!strcmp(enc, "rgba8") || !strcmp(enc, "bgra8"))
		return 4;
	return !strcmp(enc, "mono8") ? 1 : 0;
}

int dao_ros_host_is_big_endian(void)
{
	const uint16_t one = 1;
	uint8_t b;
	memcpy(&b, &one, 1);
	return b == 0;
}

void dao_ros_copy_depth(struct dao_frame *dst, const uint8_t *src_data, uint32_t step,
			uint32_t bpp, int swap)
{
	for (uint32_t y = 0; y < dst->height; y++) {
		const uint8_t *src = src_data + (size_t)y * step;
		uint8_t *d = (uint8_t *)dst->data + (size_t)y * (size_t)dst->stride;
		if (!swap) {
			memcpy(d, src, (size_t)dst->width * bpp);
			continue;
		}
		for (uint32_t x = 0; x < dst->width; x++)
			for (uint32_t k = 0; k < bpp; k++)
				d[x * bpp + k] = src[x * bpp + bpp - 1 - k];
	}
}

void dao_ros_color_to_rgb(struct dao_frame *dst, const uint8_t *src_data, uint32_t step,
			  const char *encoding)
{
	const uint32_t bpp = dao_ros_color_bytes(encoding);
	const int bgr = encoding[0] == 'b';
	for (uint32_t y = 0; y < dst->height; y++) {
		const uint8_t *src = src_data + (size_t)y * step;
		uint8_t *d = (uint8_t *)dst->data + (size_t)y * (size_t)dst->stride;
		for (uint32_t x = 0; x < dst->width; x++, src += bpp, d += 3) {
			if (bpp == 1) {
				d[0] = d[1] = d[2] = src[0];
				continue;
			}
			d[0] = src[bgr ? 2 : 0];
			d[1] = src[1];
			d[2] = src[bgr ? 0 : 2];
		}
	}
}

int dao_ros_camera_info_intrinsics(struct dao_source_info *info, const char *path,
				   const char *name, uint32_t width, uint32_t height,
				   const double k[9], const double p[12], const double *d, uint32_t nd,
				   struct dao_error *err)
{
	struct dao_camera cam;
	enum dao_camera_info_matrix from;
	struct dao_error e;
	if (width != info->width || height != info->height) {
		snprintf(info->warning, sizeof(info->warning),
			 "%.150s is for %ux%u images, the depth is %ux%u: not used", name, width,
			 height, info->width, info->height);
		return 0;
	}
	/* impossible numbers are a damaged or forged calibration, not a camera */
	if (dao_camera_from_camera_info(&cam, width, height, k, p, d, nd, &from, &e))
		return dao_error_set(err, -EINVAL, "%s: %s is damaged, fix or drop it: %s", path,
				     name, e.message);
	info->has_intrinsics = 1;
	info->fx = cam.fx;
	info->fy = cam.fy;
	info->cx = cam.cx;
	info->cy = cam.cy;
	info->has_fov = 1;
	dao_camera_fov(&cam, &info->hfov, &info->vfov);
	if (from != DAO_CAMERA_INFO_K)
		snprintf(info->warning, sizeof(info->warning),
			 "%.120s has lens distortion: the depth must be rectified "
			 "(depthao does not undistort; used as it is); intrinsics %s",
			 name, from == DAO_CAMERA_INFO_P_RECTIFIED ? "from P, the rectified image's"
								   : "from K (no usable P)");
	return 0;
}
