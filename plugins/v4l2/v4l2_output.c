/* SPDX-License-Identifier: MIT */
#include "v4l2_output.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <linux/videodev2.h>


struct v4l2out {
	const struct v4l2_io *io;
	int fd;
	char path[256];
	uint32_t pixfmt, fps, width, height, sizeimage, bytesperline;
	int format_given;   /* ?format= named one (else YUYV for pictures, Y16 for depth) */
	enum dao_pixfmt in;
	uint8_t *buf;
	uint64_t dropped;
};

/* BT.601 limited range, 8-bit fixed point: Y = 16 + (66R + 129G + 25B) / 256, ... */
static inline uint8_t luma(int r, int g, int b)
{
	return (uint8_t)((66 * r + 129 * g + 25 * b + 128 + (16 << 8)) >> 8);
}

void v4l2_rgb_to_yuyv(const uint8_t *p, uint32_t w, uint8_t *o)
{
	for (uint32_t x = 0; x + 1 < w; x += 2, p += 6, o += 4) {
		int r = (p[0] + p[3] + 1) / 2, g = (p[1] + p[4] + 1) / 2, b = (p[2] + p[5] + 1) / 2;
		o[0] = luma(p[0], p[1], p[2]);
		o[1] = (uint8_t)((-38 * r - 74 * g + 112 * b + 128 + (128 << 8)) >> 8);
		o[2] = luma(p[3], p[4], p[5]);
		o[3] = (uint8_t)((112 * r - 94 * g - 18 * b + 128 + (128 << 8)) >> 8);
	}
}

void v4l2_gray_to_yuyv(const uint8_t *p, uint32_t w, uint8_t *o)
{
	for (uint32_t x = 0; x + 1 < w; x += 2, p += 2, o += 4) {
		o[0] = luma(p[0], p[0], p[0]);
		o[1] = 128;
		o[2] = luma(p[1], p[1], p[1]);
		o[3] = 128;
	}
}

/* One row of 16-bit pixels as Y16: little-endian whatever the host's order. */
static void copy_y16(const uint8_t *src, uint32_t w, uint8_t *dst)
{
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
	memcpy(dst, src, (size_t)w * 2);
#else
	for (uint32_t x = 0; x < w; x++) {
		uint16_t v;
		memcpy(&v, src + 2 * (size_t)x, 2);
		dst[2 * x] = (uint8_t)(v & 0xff);
		dst[2 * x + 1] = (uint8_t)(v >> 8);
	}
#endif
}

int v4l2out_open(const struct v4l2_io *io, const char *uri, struct v4l2out **out,
		 struct dao_error *err)
{
	struct v4l2out *o = calloc(1, sizeof(*o));
	if (!o)
		return dao_error_set(err, -ENOMEM, "out of memory");
	o->io = io;
	o->fd = -1;
	o->pixfmt = V4L2_PIX_FMT_YUYV;
	o->fps = 30;
	static const char *const known[] = {"format", "fps", NULL};
	static const char *const formats[] = {"YUYV", "RGB24", "GREY", "Y16", NULL};
	static const uint32_t pixfmts[] = {V4L2_PIX_FMT_YUYV, V4L2_PIX_FMT_RGB24, V4L2_PIX_FMT_GREY,
					   V4L2_PIX_FMT_Y16};
	size_t n = dao_uri_path_len(uri, known);
	int r;
	if (n == 0 || n >= sizeof o->path) {
		r = dao_error_set(err, -EINVAL, "v4l2 output: '%s' names no device (/dev/videoN)", uri);
		goto fail;
	}
	memcpy(o->path, uri, n);
	struct dao_options *opts;
	if ((r = dao_options_parse(&opts, "v4l2 output", uri[n] ? uri + n + 1 : NULL, known,
				   err)) < 0)
		goto fail;
	int format = 0;
	int64_t fps = o->fps;
	if ((r = dao_options_get_enum(opts, "format", formats, &format, err)) > 0) {
		o->pixfmt = pixfmts[format];
		o->format_given = 1;
	}
	if (r >= 0 && (r = dao_options_get_int(opts, "fps", 1, 1000, &fps, err)) >= 0)
		o->fps = (uint32_t)fps;
	dao_options_free(opts);
	if (r < 0)
		goto fail;
	o->fd = io->open(io->user, o->path, O_RDWR | O_NONBLOCK);
	if (o->fd < 0) {
		r = dao_error_set(err, errno == ENOENT ? -ENODEV : -errno,
				 "v4l2 output: cannot open %s: %s (is v4l2loopback loaded? see the "
				 "README)",
				 o->path, strerror(errno));
		goto fail;
	}
	struct v4l2_capability c;
	memset(&c, 0, sizeof c);
	if (v4l2_xioctl(io, o->fd, VIDIOC_QUERYCAP, &c) < 0) {
		r = dao_error_set(err, -ENOTSUP, "v4l2 output: %s is not a V4L2 device", o->path);
		goto fail;
	}
	uint32_t caps = (c.capabilities & V4L2_CAP_DEVICE_CAPS) ? c.device_caps : c.capabilities;
	if (!(caps & V4L2_CAP_VIDEO_OUTPUT)) {
		r = dao_error_set(err, -ENOTSUP,
				 "v4l2 output: %s (%.32s) is not a video output device (a v4l2loopback "
				 "device is)",
				 o->path, (const char *)c.card);
		goto fail;
	}
	*out = o;
	return 0;
fail:
	v4l2out_close(o);
	return r;
}

/*
 * The 16-bit streams (depth, filtered-depth; the AO with ?format=Y16) go out as Y16,
 * 16-bit little-endian grey, unchanged: 0 or the error, *done when fmt was changed
 * (the host asks again).
 */
static int negotiate_y16(struct v4l2out *o, struct dao_sink_format *fmt, int *done,
			 struct dao_error *err)
{
	*done = 0;
	if (!o->format_given) /* negotiated again before the first write: start over */
		o->pixfmt = V4L2_PIX_FMT_YUYV;
	if (fmt->format == DAO_PIXFMT_DEPTH16 && o->format_given && o->pixfmt != V4L2_PIX_FMT_Y16)
		return dao_error_set(err, -ENOTSUP,
				    "v4l2 output: depth is 16-bit and YUYV, RGB24 and GREY carry 8-bit "
				    "pictures: give ?format=Y16 (or leave format out) for the depth "
				    "and filtered-depth streams");
	if (fmt->format == DAO_PIXFMT_DEPTH16)
		o->pixfmt = V4L2_PIX_FMT_Y16;
	if (o->pixfmt == V4L2_PIX_FMT_Y16 && fmt->format != DAO_PIXFMT_DEPTH16 &&
	    fmt->format != DAO_PIXFMT_GRAY16) {
		fmt->format = DAO_PIXFMT_GRAY16; /* the 16-bit AO is the nearest */
		*done = 1;
	}
	return 0;
}

int v4l2out_negotiate(struct v4l2out *o, struct dao_sink_format *fmt, struct dao_error *err)
{
	int done, r = negotiate_y16(o, fmt, &done, err);
	if (r < 0 || done)
		return r;
	if (fmt->format == DAO_PIXFMT_GRAY16 && o->pixfmt != V4L2_PIX_FMT_Y16) {
		fmt->format = DAO_PIXFMT_GRAY8; /* cameras carry 8-bit pictures: the ao8 stream */
		return 0;
	}
	if (fmt->format != DAO_PIXFMT_RGB24 && fmt->format != DAO_PIXFMT_GRAY8 &&
	    o->pixfmt != V4L2_PIX_FMT_Y16)
		return dao_error_set(err, -ENOTSUP,
				    "v4l2 output: takes the shaded, overlay or ao8 stream, or with "
				    "?format=Y16 the ao, depth or filtered-depth stream, not %s",
				    dao_pixfmt_name(fmt->format));
	if (o->pixfmt == V4L2_PIX_FMT_YUYV && (fmt->width & 1))
		return dao_error_set(err, -EINVAL,
				    "v4l2 output: YUYV needs an even width, the stream is %u wide (use "
				    "?format=RGB24 or GREY)",
				    fmt->width);
	if (o->pixfmt == V4L2_PIX_FMT_RGB24 && fmt->format != DAO_PIXFMT_RGB24) {
		fmt->format = DAO_PIXFMT_RGB24;
		return 0;
	}
	if (o->pixfmt == V4L2_PIX_FMT_GREY && fmt->format != DAO_PIXFMT_GRAY8) {
		fmt->format = DAO_PIXFMT_GRAY8;
		return 0;
	}
	uint32_t bpp = o->pixfmt == V4L2_PIX_FMT_RGB24 ? 3 : o->pixfmt == V4L2_PIX_FMT_GREY ? 1 : 2;
	struct v4l2_format f;
	memset(&f, 0, sizeof f);
	f.type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
	f.fmt.pix.width = fmt->width;
	f.fmt.pix.height = fmt->height;
	f.fmt.pix.pixelformat = o->pixfmt;
	f.fmt.pix.field = V4L2_FIELD_NONE;
	f.fmt.pix.bytesperline = fmt->width * bpp;
	f.fmt.pix.sizeimage = fmt->width * bpp * fmt->height;
	f.fmt.pix.colorspace = V4L2_COLORSPACE_SRGB;
	if (v4l2_xioctl(o->io, o->fd, VIDIOC_S_FMT, &f) < 0)
		return dao_error_set(err, -errno, "v4l2 output: %s: cannot set the format: %s (a "
				    "v4l2loopback device in use by another writer keeps its format)",
				    o->path, strerror(errno));
	if (f.fmt.pix.width != fmt->width || f.fmt.pix.height != fmt->height ||
	    f.fmt.pix.pixelformat != o->pixfmt)
		return dao_error_set(err, -ENOTSUP, "v4l2 output: %s took %ux%u instead of %ux%u",
				    o->path, f.fmt.pix.width, f.fmt.pix.height, fmt->width, fmt->height);
	o->width = fmt->width;
	o->height = fmt->height;
	o->bytesperline = f.fmt.pix.bytesperline ? f.fmt.pix.bytesperline : fmt->width * bpp;
	o->sizeimage = o->bytesperline * fmt->height;
	o->in = fmt->format;
	struct v4l2_streamparm sp;
	memset(&sp, 0, sizeof sp);
	sp.type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
	sp.parm.output.timeperframe.numerator = 1;
	sp.parm.output.timeperframe.denominator = fmt->fps > 0 ? (uint32_t)(fmt->fps + 0.5) : o->fps;
	v4l2_xioctl(o->io, o->fd, VIDIOC_S_PARM, &sp); /* advisory; not every driver has it */
	free(o->buf);
	if (!(o->buf = calloc(1, o->sizeimage)))
		return dao_error_set(err, -ENOMEM, "out of memory");
	return 0;
}

int v4l2out_write(struct v4l2out *o, const struct dao_frame *f, struct dao_error *err)
{
	for (uint32_t y = 0; y < o->height; y++) {
		const uint8_t *src = (const uint8_t *)f->data + (size_t)y * (size_t)f->stride;
		uint8_t *dst = o->buf + (size_t)y * o->bytesperline;
		if (o->pixfmt == V4L2_PIX_FMT_YUYV) {
			if (o->in == DAO_PIXFMT_RGB24)
				v4l2_rgb_to_yuyv(src, o->width, dst);
			else
				v4l2_gray_to_yuyv(src, o->width, dst);
		} else if (o->pixfmt == V4L2_PIX_FMT_Y16) {
			copy_y16(src, o->width, dst);
		} else {
			memcpy(dst, src, (size_t)o->width * (o->pixfmt == V4L2_PIX_FMT_RGB24 ? 3 : 1));
		}
	}
	ssize_t w = o->io->write(o->io->user, o->fd, o->buf, o->sizeimage);
	if (w < 0 && (errno == EAGAIN || errno == EBUSY)) {
		o->dropped++; /* no room (no consumer, or a slow one): this frame is skipped */
		return 0;
	}
	if (w < 0)
		return dao_error_set(err, errno == ENODEV ? -ENODEV : -errno, "v4l2 output: %s: %s",
				    o->path, strerror(errno));
	if ((size_t)w != o->sizeimage)
		return dao_error_set(err, -EIO, "v4l2 output: %s took %zd of %u bytes", o->path, w,
				    o->sizeimage);
	return 0;
}

uint64_t v4l2out_dropped(const struct v4l2out *o)
{
	return o->dropped;
}

void v4l2out_close(struct v4l2out *o)
{
	if (!o)
		return;
	if (o->fd >= 0)
		o->io->close(o->io->user, o->fd);
	free(o->buf);
	free(o);
}
