/* SPDX-License-Identifier: MIT */
#include "v4l2_capture.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/mman.h>

#include <linux/videodev2.h>


#define RING 4
#define DEFAULT_W 640
#define DEFAULT_H 480

struct buffer {
	void *start;
	size_t length;
};

struct v4l2cap {
	const struct v4l2_io *io;
	int fd;
	char path[256], card[64], bus[64];
	uint32_t pixfmt, width, height, bytesperline;
	double fps;
	float unit;
	struct buffer bufs[RING];
	unsigned nbufs;
	int streaming;
	int lost;                 /* the device went away */
	uint16_t *depth;          /* the converted frame, width x height */
	uint16_t kinect_lut[1024];
	uint64_t delivered;
};

struct request {
	char device[256];
	uint32_t w, h, fps, pixfmt;
	float unit;
};

static const uint32_t depth_formats[] = {V4L2_PIX_FMT_Z16, V4L2_PIX_FMT_Y16, V4L2_PIX_FMT_Y10BPACK};

static const char *fourcc_str(uint32_t f, char out[5])
{
	for (int i = 0; i < 4; i++)
		out[i] = (char)((f >> (8 * i)) & 0xff);
	out[4] = '\0';
	for (int i = 3; i > 0 && out[i] == ' '; i--) /* "Z16 " -> "Z16" */
		out[i] = '\0';
	return out;
}

static int is_depth_format(uint32_t f)
{
	for (size_t i = 0; i < sizeof depth_formats / sizeof depth_formats[0]; i++)
		if (f == depth_formats[i])
			return 1;
	return 0;
}

uint16_t v4l2_kinect_disparity_to_mm(unsigned d)
{
	/* Burrus' fit for the Kinect v1: z = 1 / (d * -0.0030711016 + 3.3309495161) m */
	if (d >= 2047)
		return 0;
	double inv = (double)d * -0.0030711016 + 3.3309495161;
	if (inv <= 0)
		return 0;
	double mm = 1000.0 / inv;
	return mm > 0 && mm < 10000 ? (uint16_t)lrint(mm) : 0;
}

static const char *const request_options[] = {"size", "fps", "format", "unit", NULL};

/* The options of a request (the library's parser: errors name the key and the value). */
static int parse_options(const char *text, struct request *r, struct dao_error *err)
{
	static const char *const formats[] = {"Z16", "Y16", "Y10B", NULL};
	static const uint32_t pixfmts[] = {V4L2_PIX_FMT_Z16, V4L2_PIX_FMT_Y16,
					   V4L2_PIX_FMT_Y10BPACK};
	struct dao_options *o;
	int ret = dao_options_parse(&o, "v4l2", text, request_options, err);
	if (ret < 0)
		return ret;
	const char *size = dao_options_value(o, "size");
	char tail;
	int64_t fps = 0;
	int format = 0;
	double unit = r->unit;
	if (size && (sscanf(size, "%ux%u%c", &r->w, &r->h, &tail) != 2 || !r->w || !r->h ||
		     r->w > 16384 || r->h > 16384))
		ret = dao_error_set(err, -EINVAL, "v4l2: 'size' must be WxH (1..16384 each), got "
				    "'%.40s'", size);
	if (ret >= 0 && (ret = dao_options_get_int(o, "fps", 1, 1000, &fps, err)) > 0)
		r->fps = (unsigned)fps;
	if (ret >= 0 && (ret = dao_options_get_enum(o, "format", formats, &format, err)) > 0)
		r->pixfmt = pixfmts[format];
	/* metres per count: RealSense 0.001, D405 0.0001 */
	if (ret >= 0 && (ret = dao_options_get_double(o, "unit", 0, 1, DAO_OPTIONS_MIN_EXCLUSIVE,
						      &unit, err)) > 0)
		r->unit = (float)unit;
	dao_options_free(o);
	return ret < 0 ? ret : 0;
}

static int parse_request(const char *uri, const struct dao_source_options *o, struct request *r,
			 struct dao_error *err)
{
	memset(r, 0, sizeof(*r));
	size_t n = dao_uri_path_len(uri, request_options);
	if (n == 0 || n >= sizeof r->device)
		return dao_error_set(err, -EINVAL, "v4l2: '%s' names no device (use /dev/videoN, card=NAME, "
				    "bus=INFO or any)", uri);
	memcpy(r->device, uri, n);
	r->device[n] = '\0';
	r->unit = o->depth_unit > 0 ? o->depth_unit : 0.001f;
	return uri[n] ? parse_options(uri + n + 1, r, err) : 0;
}

/* Capability and identity of an open node; 1 if it captures video with streaming. */
static int query(const struct v4l2_io *io, int fd, char *card, char *bus, size_t cap)
{
	struct v4l2_capability c;
	memset(&c, 0, sizeof c);
	if (v4l2_xioctl(io, fd, VIDIOC_QUERYCAP, &c) < 0)
		return 0;
	uint32_t caps = (c.capabilities & V4L2_CAP_DEVICE_CAPS) ? c.device_caps : c.capabilities;
	if (card)
		snprintf(card, cap, "%.32s", (const char *)c.card);
	if (bus)
		snprintf(bus, cap, "%.32s", (const char *)c.bus_info);
	return (caps & V4L2_CAP_VIDEO_CAPTURE) && (caps & V4L2_CAP_STREAMING);
}

/* The best depth format of an open node (the requested one if given), 0 if none. */
static uint32_t pick_format(const struct v4l2_io *io, int fd, uint32_t want)
{
	uint32_t best = 0;
	int best_rank = 99;
	for (uint32_t i = 0; i < 64; i++) {
		struct v4l2_fmtdesc d;
		memset(&d, 0, sizeof d);
		d.index = i;
		d.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
		if (v4l2_xioctl(io, fd, VIDIOC_ENUM_FMT, &d) < 0)
			break;
		if (want && d.pixelformat == want)
			return want;
		for (int k = 0; k < 3; k++)
			if (d.pixelformat == depth_formats[k] && k < best_rank) {
				best_rank = k;
				best = d.pixelformat;
			}
	}
	return want ? 0 : best;
}

/* The frame size: the requested one if offered, else the offered size nearest to it. */
static void pick_size(const struct v4l2_io *io, int fd, uint32_t pixfmt, uint32_t *w, uint32_t *h)
{
	uint32_t tw = *w ? *w : DEFAULT_W, th = *h ? *h : DEFAULT_H;
	uint64_t best = UINT64_MAX;
	uint32_t bw = tw, bh = th;
	for (uint32_t i = 0; i < 256; i++) {
		struct v4l2_frmsizeenum s;
		memset(&s, 0, sizeof s);
		s.index = i;
		s.pixel_format = pixfmt;
		if (v4l2_xioctl(io, fd, VIDIOC_ENUM_FRAMESIZES, &s) < 0)
			break;
		if (s.type == V4L2_FRMSIZE_TYPE_DISCRETE) {
			int64_t dw = (int64_t)s.discrete.width - tw, dh = (int64_t)s.discrete.height - th;
			uint64_t dist = (uint64_t)(dw * dw + dh * dh);
			if (dist < best) {
				best = dist;
				bw = s.discrete.width;
				bh = s.discrete.height;
			}
		} else { /* stepwise or continuous: clamp (S_FMT snaps to the steps) */
			bw = tw < s.stepwise.min_width ? s.stepwise.min_width
			     : tw > s.stepwise.max_width ? s.stepwise.max_width : tw;
			bh = th < s.stepwise.min_height ? s.stepwise.min_height
			     : th > s.stepwise.max_height ? s.stepwise.max_height : th;
			break;
		}
	}
	*w = bw;
	*h = bh;
}

/* Finds the node for "card=", "bus=" or "any"; a path is taken as is. */
static int resolve_device(const struct v4l2_io *io, const char *dev, uint32_t pixfmt, char *path,
			  struct dao_error *err)
{
	if (dev[0] == '/') {
		snprintf(path, 256, "%.255s", dev);
		return 0;
	}
	int any = !strcmp(dev, "any"), by_card = !strncmp(dev, "card=", 5),
	    by_bus = !strncmp(dev, "bus=", 4);
	if (!any && !by_card && !by_bus)
		return dao_error_set(err, -EINVAL,
				    "v4l2: '%s' is not a device (use /dev/videoN, card=NAME, bus=INFO "
				    "or any)",
				    dev);
	char names[64][64];
	int n = io->nodes(io->user, names, 64);
	for (int i = 0; i < n; i++) {
		int fd = io->open(io->user, names[i], O_RDWR | O_NONBLOCK);
		if (fd < 0)
			continue;
		char card[64], bus[64];
		int ok = query(io, fd, card, bus, sizeof card) && pick_format(io, fd, pixfmt);
		io->close(io->user, fd);
		if (ok && (any || (by_card && !strcmp(card, dev + 5)) || (by_bus && !strcmp(bus, dev + 4)))) {
			snprintf(path, 256, "%.63s", names[i]);
			return 0;
		}
	}
	return dao_error_set(err, -ENODEV, "v4l2: no depth camera matches '%s' (%d video nodes; see "
			    "'depthao devices')", dev, n);
}

static void unmap_all(struct v4l2cap *c)
{
	for (unsigned i = 0; i < c->nbufs; i++)
		if (c->bufs[i].start && c->bufs[i].start != MAP_FAILED)
			c->io->munmap(c->io->user, c->bufs[i].start, c->bufs[i].length);
	c->nbufs = 0;
}

static int setup_buffers(struct v4l2cap *c, struct dao_error *err)
{
	struct v4l2_requestbuffers rb;
	memset(&rb, 0, sizeof rb);
	rb.count = RING;
	rb.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
	rb.memory = V4L2_MEMORY_MMAP;
	if (v4l2_xioctl(c->io, c->fd, VIDIOC_REQBUFS, &rb) < 0)
		return dao_error_set(err, -errno, "v4l2: %s: cannot get buffers: %s", c->path,
				    strerror(errno));
	if (rb.count < 2)
		return dao_error_set(err, -ENOMEM, "v4l2: %s: only %u buffer(s)", c->path, rb.count);
	for (unsigned i = 0; i < rb.count && i < RING; i++) {
		struct v4l2_buffer b;
		memset(&b, 0, sizeof b);
		b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
		b.memory = V4L2_MEMORY_MMAP;
		b.index = i;
		if (v4l2_xioctl(c->io, c->fd, VIDIOC_QUERYBUF, &b) < 0)
			return dao_error_set(err, -errno, "v4l2: %s: QUERYBUF: %s", c->path, strerror(errno));
		c->bufs[i].length = b.length;
		c->bufs[i].start = c->io->mmap(c->io->user, b.length, PROT_READ | PROT_WRITE, MAP_SHARED,
					       c->fd, b.m.offset);
		if (c->bufs[i].start == MAP_FAILED)
			return dao_error_set(err, -errno, "v4l2: %s: mmap: %s", c->path, strerror(errno));
		c->nbufs++;
	}
	return 0;
}

int v4l2cap_open(const struct v4l2_io *io, const char *uri, const struct dao_source_options *opts,
		 struct v4l2cap **out, struct dao_error *err)
{
	struct request rq;
	int r = parse_request(uri, opts, &rq, err);
	if (r < 0)
		return r;
	struct v4l2cap *c = calloc(1, sizeof(*c));
	if (!c)
		return dao_error_set(err, -ENOMEM, "out of memory");
	c->io = io;
	c->fd = -1;
	c->unit = rq.unit;
	if ((r = resolve_device(io, rq.device, rq.pixfmt, c->path, err)) < 0)
		goto fail;
	c->fd = io->open(io->user, c->path, O_RDWR | O_NONBLOCK);
	if (c->fd < 0) {
		r = dao_error_set(err, errno == ENOENT ? -ENODEV : -errno, "v4l2: cannot open %s: %s",
				 c->path, strerror(errno));
		goto fail;
	}
	if (!query(io, c->fd, c->card, c->bus, sizeof c->card)) {
		r = dao_error_set(err, -ENOTSUP, "v4l2: %s is not a streaming capture device", c->path);
		goto fail;
	}
	char fcc[5];
	if (!(c->pixfmt = pick_format(io, c->fd, rq.pixfmt))) {
		r = dao_error_set(err, -ENOTSUP,
				 rq.pixfmt ? "v4l2: %s (%s) does not offer %s"
					   : "v4l2: %s (%s) offers no depth format (Z16, Y16 or Y10B)%s",
				 c->path, c->card, rq.pixfmt ? fourcc_str(rq.pixfmt, fcc) : "");
		goto fail;
	}
	uint32_t w = rq.w, h = rq.h;
	pick_size(io, c->fd, c->pixfmt, &w, &h);
	struct v4l2_format f;
	memset(&f, 0, sizeof f);
	f.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
	f.fmt.pix.width = w;
	f.fmt.pix.height = h;
	f.fmt.pix.pixelformat = c->pixfmt;
	f.fmt.pix.field = V4L2_FIELD_NONE;
	if (v4l2_xioctl(io, c->fd, VIDIOC_S_FMT, &f) < 0) {
		r = dao_error_set(err, -errno, "v4l2: %s: cannot set %s %ux%u: %s", c->path,
				 fourcc_str(c->pixfmt, fcc), w, h, strerror(errno));
		goto fail;
	}
	if (f.fmt.pix.pixelformat != c->pixfmt || !f.fmt.pix.width || !f.fmt.pix.height) {
		r = dao_error_set(err, -ENOTSUP, "v4l2: %s changed the format to %s", c->path,
				 fourcc_str(f.fmt.pix.pixelformat, fcc));
		goto fail;
	}
	c->width = f.fmt.pix.width;
	c->height = f.fmt.pix.height;
	uint32_t min_bpl = c->pixfmt == V4L2_PIX_FMT_Y10BPACK ? (c->width * 10 + 7) / 8 : c->width * 2;
	c->bytesperline = f.fmt.pix.bytesperline >= min_bpl ? f.fmt.pix.bytesperline : min_bpl;
	/* frame rate: asked for if the driver takes it, read back either way */
	struct v4l2_streamparm sp;
	memset(&sp, 0, sizeof sp);
	sp.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
	if (v4l2_xioctl(io, c->fd, VIDIOC_G_PARM, &sp) == 0) {
		if (rq.fps && (sp.parm.capture.capability & V4L2_CAP_TIMEPERFRAME)) {
			sp.parm.capture.timeperframe.numerator = 1;
			sp.parm.capture.timeperframe.denominator = rq.fps;
			v4l2_xioctl(io, c->fd, VIDIOC_S_PARM, &sp);
		}
		if (sp.parm.capture.timeperframe.numerator)
			c->fps = (double)sp.parm.capture.timeperframe.denominator /
				 sp.parm.capture.timeperframe.numerator;
	}
	if (c->pixfmt == V4L2_PIX_FMT_Y10BPACK) {
		c->unit = 0.001f; /* converted to millimetres */
		for (unsigned d = 0; d < 1024; d++)
			c->kinect_lut[d] = v4l2_kinect_disparity_to_mm(d);
	}
	if (!(c->depth = malloc((size_t)c->width * c->height * 2))) {
		r = dao_error_set(err, -ENOMEM, "out of memory");
		goto fail;
	}
	if ((r = setup_buffers(c, err)) < 0)
		goto fail;
	*out = c;
	return 0;
fail:
	v4l2cap_close(c);
	return r;
}

void v4l2cap_info(const struct v4l2cap *c, struct dao_source_info *in)
{
	char fcc[5];
	in->width = c->width;
	in->height = c->height;
	in->format = DAO_PIXFMT_DEPTH16;
	in->depth_unit = c->unit;
	in->has_fov = 0; /* V4L2 does not know it: the config or a default gives it */
	in->fps = c->fps;
	in->frame_count = -1;
	in->live = 1;
	snprintf(in->description, sizeof in->description, "V4L2 %.40s (%.40s, %.40s): %s %ux%u@%.0f",
		 c->card, c->path, c->bus, fourcc_str(c->pixfmt, fcc), c->width, c->height, c->fps);
}

int v4l2cap_start(struct v4l2cap *c, struct dao_error *err)
{
	for (unsigned i = 0; i < c->nbufs; i++) {
		struct v4l2_buffer b;
		memset(&b, 0, sizeof b);
		b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
		b.memory = V4L2_MEMORY_MMAP;
		b.index = i;
		if (v4l2_xioctl(c->io, c->fd, VIDIOC_QBUF, &b) < 0)
			return dao_error_set(err, errno == ENODEV ? -ENODEV : -errno, "v4l2: %s: QBUF: %s",
					    c->path, strerror(errno));
	}
	int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
	if (v4l2_xioctl(c->io, c->fd, VIDIOC_STREAMON, &type) < 0)
		return dao_error_set(err, errno == ENODEV ? -ENODEV : -errno, "v4l2: %s: STREAMON: %s",
				    c->path, strerror(errno));
	c->streaming = 1;
	return 0;
}

/* Y10B: 10-bit samples packed most significant bit first, 4 samples in 5 bytes. */
static void unpack_y10b(const uint8_t *row, uint32_t w, const uint16_t *lut, uint16_t *out)
{
	uint32_t acc = 0;
	int bits = 0;
	for (uint32_t x = 0; x < w; x++) {
		while (bits < 10) {
			acc = (acc << 8) | *row++;
			bits += 8;
		}
		bits -= 10;
		out[x] = lut[(acc >> bits) & 0x3ff];
	}
}

static void convert(struct v4l2cap *c, const uint8_t *src)
{
	for (uint32_t y = 0; y < c->height; y++) {
		const uint8_t *row = src + (size_t)y * c->bytesperline;
		uint16_t *out = c->depth + (size_t)y * c->width;
		if (c->pixfmt == V4L2_PIX_FMT_Y10BPACK)
			unpack_y10b(row, c->width, c->kinect_lut, out);
		else
			for (uint32_t x = 0; x < c->width; x++) /* little-endian on the wire */
				out[x] = (uint16_t)(row[2 * x] | (row[2 * x + 1] << 8));
	}
}

static int gone(struct v4l2cap *c, struct dao_error *err)
{
	return dao_error_set(err, -ENODEV, "v4l2: %s (%s) was disconnected", c->path, c->card);
}

int v4l2cap_read(struct v4l2cap *c, struct dao_source_frame *f, int timeout_ms,
		 struct dao_error *err)
{
	if (!c->streaming)
		return dao_error_set(err, -EINVAL, "v4l2: %s is not streaming", c->path);
	if (c->lost)
		return gone(c, err);
	for (;;) {
		struct pollfd p = {c->fd, POLLIN, 0};
		int n = c->io->poll(c->io->user, &p, 1, timeout_ms);
		if (n < 0 && errno == EINTR)
			continue;
		if (n < 0)
			return dao_error_set(err, -errno, "v4l2: %s: poll: %s", c->path, strerror(errno));
		if (n == 0)
			return -EAGAIN;
		if (p.revents & (POLLERR | POLLHUP | POLLNVAL))
			return gone(c, err);
		struct v4l2_buffer b;
		memset(&b, 0, sizeof b);
		b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
		b.memory = V4L2_MEMORY_MMAP;
		if (v4l2_xioctl(c->io, c->fd, VIDIOC_DQBUF, &b) < 0) {
			if (errno == EAGAIN)
				continue;
			if (errno == ENODEV || errno == EIO)
				return gone(c, err);
			return dao_error_set(err, -errno, "v4l2: %s: DQBUF: %s", c->path, strerror(errno));
		}
		size_t need = (size_t)c->bytesperline * (c->height - 1) +
			      (c->pixfmt == V4L2_PIX_FMT_Y10BPACK ? (c->width * 10 + 7) / 8 : c->width * 2);
		int ok = b.index < c->nbufs && b.bytesused >= need && !(b.flags & V4L2_BUF_FLAG_ERROR);
		if (ok)
			convert(c, c->bufs[b.index].start);
		if (v4l2_xioctl(c->io, c->fd, VIDIOC_QBUF, &b) < 0 && errno == ENODEV)
			c->lost = 1; /* this frame is good; the next read reports the loss */
		if (!ok) {
			if (c->lost)
				return gone(c, err);
			continue; /* a short or damaged frame: wait for the next */
		}
		f->depth = (struct dao_frame){.format = DAO_PIXFMT_DEPTH16, .width = c->width,
				.height = c->height,
					      .stride = (int32_t)(c->width * 2), .data = c->depth, .depth_unit = c->unit,
					      .timestamp_ns = (uint64_t)b.timestamp.tv_sec * 1000000000u +
						      (uint64_t)b.timestamp.tv_usec * 1000u,
					      .sequence = b.sequence};
		f->color.format = DAO_PIXFMT_NONE;
		f->index = c->delivered++;
		return 0;
	}
}

void v4l2cap_stop(struct v4l2cap *c)
{
	if (c->streaming) {
		int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
		v4l2_xioctl(c->io, c->fd, VIDIOC_STREAMOFF, &type);
		c->streaming = 0;
	}
}

void v4l2cap_close(struct v4l2cap *c)
{
	if (!c)
		return;
	v4l2cap_stop(c);
	unmap_all(c);
	if (c->fd >= 0)
		c->io->close(c->io->user, c->fd);
	free(c->depth);
	free(c);
}

int v4l2cap_list(const struct v4l2_io *io, dao_device_cb cb, void *user, struct dao_error *err)
{
	(void)err;
	char names[64][64];
	int n = io->nodes(io->user, names, 64), found = 0;
	for (int i = 0; i < n; i++) {
		int fd = io->open(io->user, names[i], O_RDWR | O_NONBLOCK);
		if (fd < 0)
			continue;
		char card[64], bus[64];
		if (query(io, fd, card, bus, sizeof card)) {
			struct dao_device_entry e;
			memset(&e, 0, sizeof e);
			size_t len = 0;
			for (uint32_t k = 0; k < 64; k++) {
				struct v4l2_fmtdesc d;
				memset(&d, 0, sizeof d);
				d.index = k;
				d.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
				if (v4l2_xioctl(io, fd, VIDIOC_ENUM_FMT, &d) < 0)
					break;
				if (!is_depth_format(d.pixelformat))
					continue;
				char fcc[5];
				uint32_t w = 0, h = 0;
				pick_size(io, fd, d.pixelformat, &w, &h);
				int k2 = snprintf(e.detail + len, sizeof e.detail - len, "%s%s %ux%u",
						  len ? ", " : "", fourcc_str(d.pixelformat, fcc), w, h);
				if (k2 > 0 && (size_t)k2 < sizeof e.detail - len)
					len += (size_t)k2;
			}
			if (len) {
				snprintf(e.uri, sizeof e.uri, "%.63s", names[i]);
				snprintf(e.name, sizeof e.name, "%.60s (%.60s)", card, bus);
				cb(user, &e);
				found++;
			}
		}
		io->close(io->user, fd);
	}
	return found;
}
