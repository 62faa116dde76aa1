/* SPDX-License-Identifier: MIT */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

#include <depthao/error.h>
#include "synth/real_frames.h"

#define KINECT "Kinect v1 (OpenNI 1.5 recording)"
#define ONI(n) { "kinect-oni-" #n, "oni/3DJ_test.oni", KINECT, SYNTH_SENSOR_STRUCTURED_LIGHT, \
		 0.001, 0, 0, 0, 0, n }

/* ../shared/data/README.md */
static const struct synth_real_frame frames[] = {
	ONI(0), ONI(1), ONI(2), ONI(3), ONI(4), ONI(5),
	ONI(6), ONI(7), ONI(8), ONI(9), ONI(10), ONI(11),
	{ "redwood-0", "redwood_open3d/depth_00000.png", "PrimeSense (Redwood)",
	  SYNTH_SENSOR_STRUCTURED_LIGHT, 0.001, 525, 525, 319.5, 239.5, -1 },
	{ "redwood-1", "redwood_open3d/depth_00001.png", "PrimeSense (Redwood)",
	  SYNTH_SENSOR_STRUCTURED_LIGHT, 0.001, 525, 525, 319.5, 239.5, -1 },
	{ "tum", "tum_open3d/TUM_depth.png", "Kinect v1 (TUM RGB-D)",
	  SYNTH_SENSOR_STRUCTURED_LIGHT, 0.0002, 525, 525, 319.5, 239.5, -1 },
	{ "realsense", "realsense_6dpose/depth.png", "RealSense (librealsense 1.x)",
	  SYNTH_SENSOR_ACTIVE_STEREO, 0.001, 622.439, 622.439, 315.746, 250.804, -1 },
};

const struct synth_real_frame *synth_real_frames(int *count)
{
	*count = (int)(sizeof frames / sizeof frames[0]);
	return frames;
}

const char *synth_real_data_dir(void)
{
	const char *d = getenv("DAO_SHARED_DATA");
	return d && *d ? d : "../shared/data";
}

static int ends_with(const char *s, const char *tail)
{
	size_t n = strlen(s), m = strlen(tail);
	return n >= m && strcmp(s + n - m, tail) == 0;
}

int synth_depth_frame_count(const char *path, struct dao_error *err)
{
	if (!ends_with(path, ".oni"))
		return 1;
	struct dao_oni_reader *r;
	int ret = dao_oni_reader_open(path, &r, err);
	if (ret)
		return ret;
	int s = dao_oni_reader_depth_stream(r, err);
	if (s >= 0)
		s = (int)dao_oni_reader_stream(r, (uint32_t)s)->frame_count;
	dao_oni_reader_close(r);
	return s;
}

int synth_depth_load(const char *path, int frame, double png_unit, float **z, uint32_t *w,
		     uint32_t *h, double *unit, struct dao_camera *cam, int *has_cam,
		     struct dao_error *err)
{
	struct dao_frame f = { 0 };
	int mirrored = 0, ret;
	*z = NULL;
	if (has_cam)
		*has_cam = 0;
	if (ends_with(path, ".oni")) {
		struct dao_oni_reader *r;
		if ((ret = dao_oni_reader_open(path, &r, err)))
			return ret;
		int s = dao_oni_reader_depth_stream(r, err);
		if (s < 0) {
			dao_oni_reader_close(r);
			return s;
		}
		const struct dao_oni_stream_info *si = dao_oni_reader_stream(r, (uint32_t)s);
		if (frame < 0 || (uint32_t)frame >= si->frame_count) {
			dao_oni_reader_close(r);
			return dao_error_set(err, -EINVAL, "%s has %u frames, frame %d does not exist",
					     path, si->frame_count, frame);
		}
		ret = dao_frame_alloc(&f, DAO_PIXFMT_DEPTH16, si->width, si->height, err);
		if (!ret)
			ret = dao_oni_reader_read_depth(r, (uint32_t)s, (uint32_t)frame, &f, err);
		if (!ret && si->has_fov && cam) {
			ret = dao_camera_from_fov(cam, si->width, si->height, si->hfov, si->vfov, err);
			if (!ret && has_cam)
				*has_cam = 1;
		}
		mirrored = si->mirrored;
		dao_oni_reader_close(r);
	} else {
		if (!(png_unit > 0))
			return dao_error_set(err, -EINVAL, "%s: a depth unit > 0 is needed", path);
		ret = dao_png_read_depth(path, (float)png_unit, &f, err);
	}
	if (ret) {
		dao_frame_free(&f);
		return ret;
	}
	*w = f.width, *h = f.height;
	*unit = f.depth_unit;
	*z = malloc((size_t)f.width * f.height * sizeof(float));
	if (!*z) {
		dao_frame_free(&f);
		return dao_error_set(err, -ENOMEM, "out of memory reading %s", path);
	}
	for (uint32_t y = 0; y < f.height; y++) {
		const uint8_t *row = (const uint8_t *)f.data + (size_t)y * (size_t)f.stride;
		for (uint32_t x = 0; x < f.width; x++) {
			uint16_t v;
			memcpy(&v, row + 2 * (mirrored ? f.width - 1 - x : x), 2);
			(*z)[(size_t)y * f.width + x] = (float)(v * (double)f.depth_unit);
		}
	}
	dao_frame_free(&f);
	return 0;
}

int synth_real_frame_load(const struct synth_real_frame *f, const char *data_dir, float **z,
			  struct dao_camera *cam, double *unit, struct dao_error *err)
{
	char path[1024];
	snprintf(path, sizeof path, "%s/%s", data_dir, f->file);
	uint32_t w, h;
	int has_cam = 0;
	int r = synth_depth_load(path, f->frame, f->unit, z, &w, &h, unit, cam, &has_cam, err);
	if (r)
		return r;
	if (f->fx > 0)
		r = dao_camera_from_intrinsics(cam, w, h, f->fx, f->fy, f->cx, f->cy, err);
	else if (!has_cam)
		r = dao_error_set(err, -EINVAL, "%s has no field of view", path);
	if (r) {
		free(*z);
		*z = NULL;
	}
	return r;
}
