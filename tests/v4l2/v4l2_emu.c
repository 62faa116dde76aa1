/* SPDX-License-Identifier: MIT */
#include "v4l2_emu.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#include <linux/videodev2.h>

#define MAX_NODES 8
#define MAX_FDS 16
#define MAX_BUFS 8
#define PAGE 4096u

struct node {
	char path[64], card[32], bus[32];
	int output;
	uint32_t formats[4];
	int nformats;
	struct emu_size sizes[8];
	int nsizes;
	unsigned fail_after;
	int unplugged;
	/* negotiated state (the device's, shared by its fds) */
	struct v4l2_pix_format pix;
	uint32_t fps;
	uint8_t *bufs[MAX_BUFS];
	size_t buflen;
	int nbufs, queued[MAX_BUFS], streaming;
	unsigned delivered;
	/* output */
	int no_room;
	unsigned written;
	uint8_t *last;
	size_t last_size;
	int fmt_set;
};

struct emu {
	struct v4l2_io io;
	struct node nodes[MAX_NODES];
	int nnodes;
	struct node *fds[MAX_FDS];
	unsigned protocol_errors;
};

static struct node *node_of(struct emu *e, int fd)
{
	return fd >= 100 && fd < 100 + MAX_FDS ? e->fds[fd - 100] : NULL;
}

/* An ioctl that breaks the rules: counted, and errno as a driver would set it. */
static int bad(struct emu *e, int err)
{
	e->protocol_errors++;
	errno = err;
	return -1;
}

uint16_t emu_depth_at(uint32_t frame, uint32_t x, uint32_t y)
{
	return (uint16_t)(500 + x + 2 * y + 10 * frame);
}

uint16_t emu_disparity_at(uint32_t frame, uint32_t x, uint32_t y)
{
	return (uint16_t)(400 + (x + y + frame) % 500);
}

static uint32_t bpl_of(uint32_t fmt, uint32_t w)
{
	switch (fmt) {
	case V4L2_PIX_FMT_Y10BPACK: return (w * 10 + 7) / 8;
	case V4L2_PIX_FMT_YUYV: return w * 2;
	case V4L2_PIX_FMT_RGB24: return w * 3;
	case V4L2_PIX_FMT_GREY: return w;
	default: return w * 2;
	}
}

/* The driver's adjustment: a supported format, the nearest offered size. */
static void adjust(const struct node *n, struct v4l2_pix_format *p)
{
	int ok = 0;
	for (int i = 0; i < n->nformats; i++)
		ok |= p->pixelformat == n->formats[i];
	if (!ok)
		p->pixelformat = n->formats[0];
	if (n->output) {
		if (p->width < 2)
			p->width = 2;
		if (p->pixelformat == V4L2_PIX_FMT_YUYV)
			p->width &= ~1u; /* YUYV pairs pixels */
		if (p->height < 1)
			p->height = 1;
	} else if (n->nsizes) {
		uint64_t best = UINT64_MAX;
		struct emu_size b = n->sizes[0];
		for (int i = 0; i < n->nsizes; i++) {
			int64_t dw = (int64_t)n->sizes[i].w - p->width, dh = (int64_t)n->sizes[i].h - p->height;
			uint64_t d = (uint64_t)(dw * dw + dh * dh);
			if (d < best) {
				best = d;
				b = n->sizes[i];
			}
		}
		p->width = b.w;
		p->height = b.h;
	} else {
		p->width = p->width < 16 ? 16 : p->width > 1280 ? 1280 : p->width & ~1u;
		p->height = p->height < 16 ? 16 : p->height > 720 ? 720 : p->height & ~1u;
	}
	p->field = V4L2_FIELD_NONE;
	p->bytesperline = bpl_of(p->pixelformat, p->width);
	p->sizeimage = p->bytesperline * p->height;
}

static void fill(struct node *n, uint8_t *buf)
{
	const struct v4l2_pix_format *p = &n->pix;
	for (uint32_t y = 0; y < p->height; y++) {
		uint8_t *row = buf + (size_t)y * p->bytesperline;
		if (p->pixelformat == V4L2_PIX_FMT_Y10BPACK) {
			uint32_t acc = 0;
			int bits = 0;
			for (uint32_t x = 0; x < p->width; x++) {
				acc = (acc << 10) | emu_disparity_at(n->delivered, x, y);
				bits += 10;
				while (bits >= 8) {
					bits -= 8;
					*row++ = (uint8_t)(acc >> bits);
				}
			}
			if (bits)
				*row = (uint8_t)(acc << (8 - bits));
		} else {
			for (uint32_t x = 0; x < p->width; x++) {
				uint16_t v = emu_depth_at(n->delivered, x, y);
				row[2 * x] = (uint8_t)v;
				row[2 * x + 1] = (uint8_t)(v >> 8);
			}
		}
	}
}

static void free_bufs(struct node *n)
{
	for (int i = 0; i < n->nbufs; i++)
		free(n->bufs[i]);
	n->nbufs = 0;
	memset(n->queued, 0, sizeof n->queued);
}

static int emu_ioctl(void *user, int fd, unsigned long req, void *arg)
{
	struct emu *e = user;
	struct node *n = node_of(e, fd);
	if (!n) {
		errno = EBADF;
		return -1;
	}
	if (n->unplugged) {
		errno = ENODEV;
		return -1;
	}
	const uint32_t type = n->output ? V4L2_BUF_TYPE_VIDEO_OUTPUT : V4L2_BUF_TYPE_VIDEO_CAPTURE;
	switch (req) {
	case VIDIOC_QUERYCAP: {
		struct v4l2_capability *c = arg;
		memset(c, 0, sizeof *c);
		snprintf((char *)c->driver, sizeof c->driver, "emu");
		snprintf((char *)c->card, sizeof c->card, "%s", n->card);
		snprintf((char *)c->bus_info, sizeof c->bus_info, "%s", n->bus);
		c->device_caps = (n->output ? V4L2_CAP_VIDEO_OUTPUT | V4L2_CAP_READWRITE
					    : V4L2_CAP_VIDEO_CAPTURE) | V4L2_CAP_STREAMING;
		c->capabilities = c->device_caps | V4L2_CAP_DEVICE_CAPS;
		return 0;
	}
	case VIDIOC_ENUM_FMT: {
		struct v4l2_fmtdesc *d = arg;
		if (d->type != type || d->index >= (uint32_t)n->nformats) {
			errno = EINVAL; /* the end of the list: not a protocol error */
			return -1;
		}
		d->pixelformat = n->formats[d->index];
		return 0;
	}
	case VIDIOC_ENUM_FRAMESIZES: {
		struct v4l2_frmsizeenum *s = arg;
		int ok = 0;
		for (int i = 0; i < n->nformats; i++)
			ok |= s->pixel_format == n->formats[i];
		if (!ok)
			return bad(e, EINVAL);
		if (n->nsizes) {
			if (s->index >= (uint32_t)n->nsizes) {
				errno = EINVAL;
				return -1;
			}
			s->type = V4L2_FRMSIZE_TYPE_DISCRETE;
			s->discrete.width = n->sizes[s->index].w;
			s->discrete.height = n->sizes[s->index].h;
		} else {
			if (s->index) {
				errno = EINVAL;
				return -1;
			}
			s->type = V4L2_FRMSIZE_TYPE_STEPWISE;
			s->stepwise = (struct v4l2_frmsize_stepwise){16, 1280, 2, 16, 720, 2};
		}
		return 0;
	}
	case VIDIOC_G_FMT:
	case VIDIOC_S_FMT:
	case VIDIOC_TRY_FMT: {
		struct v4l2_format *f = arg;
		if (f->type != type)
			return bad(e, EINVAL);
		if (req == VIDIOC_G_FMT) {
			f->fmt.pix = n->pix;
			return 0;
		}
		if (req == VIDIOC_S_FMT && (n->nbufs || n->streaming))
			return bad(e, EBUSY); /* the format is fixed while buffers exist */
		adjust(n, &f->fmt.pix);
		if (req == VIDIOC_S_FMT) {
			n->pix = f->fmt.pix;
			n->fmt_set = 1;
		}
		return 0;
	}
	case VIDIOC_G_PARM:
	case VIDIOC_S_PARM: {
		struct v4l2_streamparm *p = arg;
		if (p->type != type)
			return bad(e, EINVAL);
		struct v4l2_fract *tpf = n->output ? &p->parm.output.timeperframe : &p->parm.capture.timeperframe;
		if (req == VIDIOC_S_PARM && tpf->numerator && tpf->denominator) {
			uint32_t fps = tpf->denominator / tpf->numerator;
			n->fps = fps < 5 ? 5 : fps > 90 ? 90 : fps;
		}
		if (n->output)
			p->parm.output.capability = V4L2_CAP_TIMEPERFRAME;
		else
			p->parm.capture.capability = V4L2_CAP_TIMEPERFRAME;
		tpf->numerator = 1;
		tpf->denominator = n->fps;
		return 0;
	}
	case VIDIOC_REQBUFS: {
		struct v4l2_requestbuffers *r = arg;
		if (r->type != type || r->memory != V4L2_MEMORY_MMAP)
			return bad(e, EINVAL);
		if (n->streaming)
			return bad(e, EBUSY);
		free_bufs(n);
		if (!n->fmt_set)
			adjust(n, &n->pix);
		n->buflen = (n->pix.sizeimage + PAGE - 1) / PAGE * PAGE;
		uint32_t count = r->count > MAX_BUFS ? MAX_BUFS : r->count;
		for (uint32_t i = 0; i < count; i++)
			n->bufs[n->nbufs++] = calloc(1, n->buflen);
		r->count = count;
		return 0;
	}
	case VIDIOC_QUERYBUF:
	case VIDIOC_QBUF: {
		struct v4l2_buffer *b = arg;
		if (b->type != type || b->memory != V4L2_MEMORY_MMAP || b->index >= (uint32_t)n->nbufs)
			return bad(e, EINVAL);
		if (req == VIDIOC_QUERYBUF) {
			b->length = (uint32_t)n->buflen;
			b->m.offset = b->index * (uint32_t)n->buflen;
			b->flags = n->queued[b->index] ? V4L2_BUF_FLAG_QUEUED : 0;
			return 0;
		}
		if (n->queued[b->index])
			return bad(e, EINVAL); /* queued twice */
		n->queued[b->index] = 1;
		return 0;
	}
	case VIDIOC_DQBUF: {
		struct v4l2_buffer *b = arg;
		if (b->type != type || !n->streaming)
			return bad(e, EINVAL);
		for (int i = 0; i < n->nbufs; i++) {
			if (!n->queued[i])
				continue;
			n->queued[i] = 0;
			fill(n, n->bufs[i]);
			memset(b, 0, sizeof *b);
			b->type = type;
			b->memory = V4L2_MEMORY_MMAP;
			b->index = (uint32_t)i;
			b->bytesused = n->pix.sizeimage;
			b->sequence = n->delivered;
			b->timestamp.tv_sec = n->delivered / 30;
			b->timestamp.tv_usec = (n->delivered % 30) * 33333;
			b->flags = V4L2_BUF_FLAG_DONE;
			n->delivered++;
			if (n->fail_after && n->delivered >= n->fail_after)
				n->unplugged = 1; /* the cable goes after this frame */
			return 0;
		}
		errno = EAGAIN;
		return -1;
	}
	case VIDIOC_STREAMON:
	case VIDIOC_STREAMOFF: {
		if (*(int *)arg != (int)type)
			return bad(e, EINVAL);
		if (req == VIDIOC_STREAMON && !n->nbufs)
			return bad(e, EINVAL);
		n->streaming = req == VIDIOC_STREAMON;
		if (!n->streaming)
			memset(n->queued, 0, sizeof n->queued);
		return 0;
	}
	default:
		return bad(e, ENOTTY);
	}
}

static int emu_open(void *user, const char *path, int flags)
{
	struct emu *e = user;
	(void)flags;
	for (int i = 0; i < e->nnodes; i++) {
		if (strcmp(e->nodes[i].path, path))
			continue;
		if (e->nodes[i].unplugged) {
			errno = ENODEV;
			return -1;
		}
		for (int k = 0; k < MAX_FDS; k++)
			if (!e->fds[k]) {
				e->fds[k] = &e->nodes[i];
				return 100 + k;
			}
		errno = EMFILE;
		return -1;
	}
	errno = ENOENT;
	return -1;
}

static int emu_close(void *user, int fd)
{
	struct emu *e = user;
	struct node *n = node_of(e, fd);
	if (!n) {
		errno = EBADF;
		return -1;
	}
	e->fds[fd - 100] = NULL;
	for (int k = 0; k < MAX_FDS; k++)
		if (e->fds[k] == n)
			return 0;
	/* the last fd: the device resets, as a driver does */
	n->streaming = 0;
	free_bufs(n);
	n->fmt_set = 0;
	return 0;
}

static void *emu_mmap(void *user, size_t len, int prot, int flags, int fd, int64_t off)
{
	struct emu *e = user;
	struct node *n = node_of(e, fd);
	(void)prot;
	(void)flags;
	if (!n || !n->buflen || off % (int64_t)n->buflen || off / (int64_t)n->buflen >= n->nbufs ||
	    len > n->buflen) {
		e->protocol_errors++;
		errno = EINVAL;
		return MAP_FAILED;
	}
	return n->bufs[off / (int64_t)n->buflen];
}

static int emu_munmap(void *user, void *addr, size_t len)
{
	(void)user;
	(void)addr;
	(void)len;
	return 0;
}

static int emu_poll(void *user, struct pollfd *fds, nfds_t nfds, int timeout_ms)
{
	struct emu *e = user;
	(void)timeout_ms;
	int ready = 0;
	for (nfds_t i = 0; i < nfds; i++) {
		struct node *n = node_of(e, fds[i].fd);
		fds[i].revents = 0;
		if (!n)
			fds[i].revents = POLLNVAL;
		else if (n->unplugged)
			fds[i].revents = POLLERR;
		else if (n->output)
			fds[i].revents = POLLOUT & fds[i].events;
		else
			for (int k = 0; k < n->nbufs; k++)
				if (n->streaming && n->queued[k])
					fds[i].revents = POLLIN & fds[i].events;
		ready += fds[i].revents != 0;
	}
	return ready;
}

static ssize_t emu_write(void *user, int fd, const void *buf, size_t len)
{
	struct emu *e = user;
	struct node *n = node_of(e, fd);
	if (!n) {
		errno = EBADF;
		return -1;
	}
	if (n->unplugged) {
		errno = ENODEV;
		return -1;
	}
	if (!n->output || !n->fmt_set || len != n->pix.sizeimage) {
		e->protocol_errors++;
		errno = EINVAL;
		return -1;
	}
	if (n->no_room) {
		errno = EAGAIN;
		return -1;
	}
	free(n->last);
	n->last = malloc(len);
	memcpy(n->last, buf, len);
	n->last_size = len;
	n->written++;
	return (ssize_t)len;
}

static int emu_nodes(void *user, char (*names)[64], int max)
{
	struct emu *e = user;
	int k = 0;
	for (int i = 0; i < e->nnodes && k < max; i++)
		snprintf(names[k++], 64, "%s", e->nodes[i].path);
	return k;
}

struct emu *emu_create(void)
{
	struct emu *e = calloc(1, sizeof(*e));
	e->io = (struct v4l2_io){e, emu_open, emu_close, emu_ioctl, emu_mmap, emu_munmap, emu_poll,
				 emu_write, emu_nodes};
	return e;
}

void emu_destroy(struct emu *e)
{
	for (int i = 0; i < e->nnodes; i++) {
		free_bufs(&e->nodes[i]);
		free(e->nodes[i].last);
	}
	free(e);
}

const struct v4l2_io *emu_io(struct emu *e)
{
	return &e->io;
}

void emu_add_capture(struct emu *e, const char *path, const char *card, const char *bus,
		     const uint32_t *formats, int nformats, const struct emu_size *sizes, int nsizes,
		     unsigned fail_after)
{
	struct node *n = &e->nodes[e->nnodes++];
	memset(n, 0, sizeof *n);
	snprintf(n->path, sizeof n->path, "%s", path);
	snprintf(n->card, sizeof n->card, "%s", card);
	snprintf(n->bus, sizeof n->bus, "%s", bus);
	memcpy(n->formats, formats, (size_t)nformats * sizeof *formats);
	n->nformats = nformats;
	memcpy(n->sizes, sizes, (size_t)nsizes * sizeof *sizes);
	n->nsizes = nsizes;
	n->fail_after = fail_after;
	n->fps = 30;
	n->pix.pixelformat = formats[0];
	n->pix.width = nsizes ? sizes[0].w : 640;
	n->pix.height = nsizes ? sizes[0].h : 480;
}

void emu_add_output(struct emu *e, const char *path, const char *card)
{
	static const uint32_t f[] = {V4L2_PIX_FMT_YUYV, V4L2_PIX_FMT_RGB24, V4L2_PIX_FMT_GREY,
				     V4L2_PIX_FMT_Y16};
	struct node *n = &e->nodes[e->nnodes++];
	memset(n, 0, sizeof *n);
	snprintf(n->path, sizeof n->path, "%s", path);
	snprintf(n->card, sizeof n->card, "%s", card);
	snprintf(n->bus, sizeof n->bus, "platform:v4l2loopback-000");
	memcpy(n->formats, f, sizeof f);
	n->nformats = 4;
	n->output = 1;
	n->fps = 30;
}

static struct node *by_path(struct emu *e, const char *path)
{
	for (int i = 0; i < e->nnodes; i++)
		if (!strcmp(e->nodes[i].path, path))
			return &e->nodes[i];
	return NULL;
}

void emu_set_no_room(struct emu *e, const char *path, int no_room)
{
	by_path(e, path)->no_room = no_room;
}

unsigned emu_output_frames(struct emu *e, const char *path)
{
	return by_path(e, path)->written;
}

const uint8_t *emu_output_last(struct emu *e, const char *path, size_t *size, uint32_t *pixfmt,
			       uint32_t *w, uint32_t *h)
{
	struct node *n = by_path(e, path);
	*size = n->last_size;
	*pixfmt = n->pix.pixelformat;
	*w = n->pix.width;
	*h = n->pix.height;
	return n->last;
}

unsigned emu_protocol_errors(struct emu *e)
{
	return e->protocol_errors;
}
