/* SPDX-License-Identifier: MIT */
#include <errno.h>
#include <stdlib.h>

#include <depthao/frame.h>

#include "core/error_internal.h"

size_t dao_pixfmt_bytes_per_pixel(enum dao_pixfmt format)
{
	switch (format) {
	case DAO_PIXFMT_DEPTH16: return 2;
	case DAO_PIXFMT_DEPTH_F32: return 4;
	case DAO_PIXFMT_GRAY8: return 1;
	case DAO_PIXFMT_GRAY16: return 2;
	case DAO_PIXFMT_GRAY_F32: return 4;
	case DAO_PIXFMT_RGB24: return 3;
	case DAO_PIXFMT_NORMAL_F32: return 12;
	case DAO_PIXFMT_NONE: break;
	}
	return 0;
}

const char *dao_pixfmt_name(enum dao_pixfmt format)
{
	switch (format) {
	case DAO_PIXFMT_DEPTH16: return "depth16";
	case DAO_PIXFMT_DEPTH_F32: return "depth-f32";
	case DAO_PIXFMT_GRAY8: return "gray8";
	case DAO_PIXFMT_GRAY16: return "gray16";
	case DAO_PIXFMT_GRAY_F32: return "gray-f32";
	case DAO_PIXFMT_RGB24: return "rgb24";
	case DAO_PIXFMT_NORMAL_F32: return "normal-f32";
	case DAO_PIXFMT_NONE: break;
	}
	return "invalid";
}

int dao_frame_check(const struct dao_frame *f, const char *what, uint32_t width,
		    uint32_t height, struct dao_error *err)
{
	if (!f)
		return dao_error_set(err, -EINVAL, "%s: frame is NULL", what);
	size_t bpp = dao_pixfmt_bytes_per_pixel(f->format);
	if (!bpp)
		return dao_error_set(err, -EINVAL, "%s: unknown pixel format %d", what,
				     (int)f->format);
	if (!f->data)
		return dao_error_set(err, -EINVAL, "%s: pixel data pointer is NULL", what);
	if (f->width == 0 || f->height == 0 || f->width > DAO_MAX_DIMENSION ||
	    f->height > DAO_MAX_DIMENSION)
		return dao_error_set(err, -EINVAL,
				     "%s: size %ux%u is out of range (1..%d per side)", what,
				     f->width, f->height, DAO_MAX_DIMENSION);
	if ((width && f->width != width) || (height && f->height != height))
		return dao_error_set(err, -EINVAL,
				     "%s: size %ux%u does not match the camera's %ux%u", what,
				     f->width, f->height, width, height);
	/* width <= 16384 and bpp <= 12, so the product fits easily in int64 */
	int64_t row = (int64_t)f->width * (int64_t)bpp;
	if (f->stride <= 0 || (int64_t)f->stride < row)
		return dao_error_set(err, -EINVAL,
				     "%s: stride %d is smaller than a row of %ux%s (%lld bytes)",
				     what, (int)f->stride, f->width, dao_pixfmt_name(f->format),
				     (long long)row);
	return 0;
}

int dao_frame_alloc(struct dao_frame *f, enum dao_pixfmt format, uint32_t width,
		    uint32_t height, struct dao_error *err)
{
	size_t bpp = dao_pixfmt_bytes_per_pixel(format);
	if (!f)
		return dao_error_set(err, -EINVAL, "frame to allocate is NULL");
	if (!bpp)
		return dao_error_set(err, -EINVAL, "cannot allocate a frame of format %d",
				     (int)format);
	if (width == 0 || height == 0 || width > DAO_MAX_DIMENSION || height > DAO_MAX_DIMENSION)
		return dao_error_set(err, -EINVAL, "frame size %ux%u is out of range (1..%d per side)",
				     width, height, DAO_MAX_DIMENSION);
	size_t stride = (size_t)width * bpp;
	void *data = calloc(height, stride);
	if (!data)
		return dao_error_set(err, -ENOMEM, "out of memory for a %ux%u %s frame", width,
				     height, dao_pixfmt_name(format));
	*f = (struct dao_frame){
		.format = format,
		.width = width,
		.height = height,
		.stride = (int32_t)stride,
		.data = data,
		.size = DAO_FRAME_SIZE,
	};
	return 0;
}

void dao_frame_free(struct dao_frame *f)
{
	if (!f)
		return;
	free(f->data);
	f->data = NULL;
}
