/* SPDX-License-Identifier: MIT */
/*
 * An emulated V4L2 driver for the tests (this machine's kernel has no V4L2):
 * capture nodes that stream synthetic depth and output nodes that record what
 * is written, following the specification's rules: QUERYCAP, ENUM_FMT,
 * ENUM_FRAMESIZES, G/S/TRY_FMT with driver adjustment, G/S_PARM, REQBUFS
 * (EBUSY while streaming), QUERYBUF, mmap by offset, QBUF/DQBUF (EAGAIN when
 * nothing is ready on a non-blocking fd, EINVAL when not streaming),
 * STREAMON/OFF, poll, write, and ENODEV/POLLERR after an unplug.
 */
#ifndef DAO_TEST_V4L2_EMU_H
#define DAO_TEST_V4L2_EMU_H

#include <stddef.h>
#include <stdint.h>

#include "v4l2_io.h"

struct emu;

struct emu_size {
	uint32_t w, h;
};

struct emu *emu_create(void);
void emu_destroy(struct emu *e);
const struct v4l2_io *emu_io(struct emu *e);

/*
 * A capture node.  `sizes` are discrete (n > 0), or with n == 0 one
 * stepwise range 16..1280 x 16..720 in steps of 2 (odd sizes adjusted).
 * fail_after: the device disappears after delivering that many frames (0 = never).
 */
void emu_add_capture(struct emu *e, const char *path, const char *card, const char *bus,
		     const uint32_t *formats, int nformats, const struct emu_size *sizes, int nsizes,
		     unsigned fail_after);
/* An output node (like v4l2loopback). */
void emu_add_output(struct emu *e, const char *path, const char *card);
/* Output: writes fail with EAGAIN (no room, e.g. no consumer) while set. */
void emu_set_no_room(struct emu *e, const char *path, int no_room);

/* The pattern a capture node streams: Z16/Y16 counts, or Y10B disparity. */
uint16_t emu_depth_at(uint32_t frame, uint32_t x, uint32_t y);
uint16_t emu_disparity_at(uint32_t frame, uint32_t x, uint32_t y);

/* What an output node received: frames written, the last one, its format. */
unsigned emu_output_frames(struct emu *e, const char *path);
const uint8_t *emu_output_last(struct emu *e, const char *path, size_t *size, uint32_t *pixfmt,
			       uint32_t *w, uint32_t *h);
/* ioctl calls that broke the rules so far (a correct client makes none). */
unsigned emu_protocol_errors(struct emu *e);

#endif
