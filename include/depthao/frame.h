/* SPDX-License-Identifier: MIT */
/*
 * Frames: the images every stage of depthao exchanges.  The caller owns the
 * pixel memory; rows are `stride` bytes apart (stride >= width * bytes per
 * pixel).  Multi-byte samples are in host byte order.
 */
#ifndef DEPTHAO_FRAME_H
#define DEPTHAO_FRAME_H

#include <stddef.h>
#include <stdint.h>

#include <depthao/error.h>

#include <depthao/api.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Largest accepted width or height (keeps width * height * 16 far from overflow). */
#define DAO_MAX_DIMENSION 16384

/*
 * Default limit on width x height of images decoded from files (PNG, .oni):
 * 4096 x 4096, far above what depth sensors deliver (about 1 MP), far below
 * DAO_MAX_DIMENSION squared.  A small file can declare a huge image; readers
 * check the declared size against the limit before they allocate anything.
 */
#define DAO_DEFAULT_MAX_PIXELS (4096ull * 4096ull)

/* Pixel formats of frames. */
enum dao_pixfmt {
	DAO_PIXFMT_NONE = 0,
	DAO_PIXFMT_DEPTH16,    /* uint16 depth counts; metres = count * depth_unit; 0 = no data */
	DAO_PIXFMT_DEPTH_F32,  /* float metres; 0, NaN and +-inf = no data */
	DAO_PIXFMT_GRAY8,      /* uint8 (visibility * 255) */
	DAO_PIXFMT_GRAY16,     /* uint16 (visibility * 65535) */
	DAO_PIXFMT_GRAY_F32,   /* float visibility in [0, 1] */
	DAO_PIXFMT_RGB24,      /* 3 x uint8, R G B */
	DAO_PIXFMT_NORMAL_F32, /* 3 x float unit normal, camera optical frame */
};

/*
 * An image: format, size, row stride and caller-owned pixels.
 *
 * A frame's sizeof never changes (it is embedded in other structs, e.g.
 * struct dao_source_frame): fields a later version adds take the reserved
 * space, and `size` says which of them a frame holds (docs/abi.md).  Start a
 * frame from DAO_FRAME_INIT, dao_frame_alloc() or zeros (a positional or
 * designated initialiser zeroes what it leaves out): size 0 is read as the
 * first layout, whose fields end before `size`.  The library's own frames
 * (dao_frame_alloc, dao_png_read) carry DAO_FRAME_SIZE.
 */
struct dao_frame {
	/* the pixel format */
	enum dao_pixfmt format;
	/* size in pixels */
	uint32_t width, height;
	int32_t stride;          /* bytes from one row to the next, > 0 */
	/* the first row's first pixel; the caller owns the memory */
	void *data;
	float depth_unit;        /* metres per count, DAO_PIXFMT_DEPTH16 only */
	uint64_t timestamp_ns;   /* capture time, 0 if unknown */
	uint64_t sequence;       /* frame number; gaps mean dropped frames */
	uint32_t size;           /* 0 or DAO_FRAME_SIZE as the program was built */
	uint32_t reserved0;      /* 0: room for later fields */
	uint64_t reserved[4];    /* 0: room for later fields */
};

/* The bytes of struct dao_frame this header's fields occupy (the value of `size`). */
#define DAO_FRAME_SIZE offsetof(struct dao_frame, reserved0)

/* A frame with its size set and every field 0. */
#define DAO_FRAME_INIT { .size = DAO_FRAME_SIZE }

/* Bytes per pixel of a format, 0 for DAO_PIXFMT_NONE or unknown values. */
DAO_API size_t dao_pixfmt_bytes_per_pixel(enum dao_pixfmt format);

/* Lower-case name of a format ("depth16", "rgb24", ...), "invalid" if unknown. */
DAO_API const char *dao_pixfmt_name(enum dao_pixfmt format);

/*
 * Checks that `frame` is usable as `what` (a noun for messages, e.g. "depth
 * input"): non-NULL data, a known format, 0 < size <= DAO_MAX_DIMENSION,
 * stride >= width * bytes per pixel.  If `width`/`height` are non-zero the
 * frame must have exactly that size.  Returns 0 or -EINVAL.
 */
DAO_API int dao_frame_check(const struct dao_frame *frame, const char *what,
		    uint32_t width, uint32_t height, struct dao_error *err);

/*
 * Allocates pixel memory for a frame of the given format and size (tightly
 * packed rows, zeroed).  Free it with dao_frame_free().
 */
DAO_API int dao_frame_alloc(struct dao_frame *frame, enum dao_pixfmt format,
		    uint32_t width, uint32_t height, struct dao_error *err);

/* Frees memory from dao_frame_alloc() or dao_png_read*(); NULL-safe. */
DAO_API void dao_frame_free(struct dao_frame *frame);

#ifdef __cplusplus
}
#endif
#endif
