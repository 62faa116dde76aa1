/* SPDX-License-Identifier: MIT */
/* Part of libdepthao-io (pkg-config depthao-io, <depthao/io.h>), not of the AO core libdepthao. */
/*
 * PNG files through libpng.  16-bit samples are big-endian on disk and host
 * order in memory.  Writes go to a temporary file in the same directory that
 * is renamed into place, so a failed write never leaves a half-written file.
 */
#ifndef DEPTHAO_PNG_H
#define DEPTHAO_PNG_H

#include <stddef.h>
#include <stdint.h>

#include <depthao/error.h>
#include <depthao/frame.h>

#include <depthao/api.h>

#ifdef __cplusplus
extern "C" {
#endif

/*
 * Reads a PNG into a newly allocated frame (free with dao_frame_free()).
 * `out` is overwritten whole, not read: a frame it held is not freed (free
 * it first to reuse the struct); timestamp_ns and sequence are 0.
 * Gray 8-bit -> GRAY8, gray 16-bit -> GRAY16, RGB 8-bit -> RGB24; other
 * layouts (palette, alpha, 16-bit RGB) are converted to RGB24 when 8-bit
 * and rejected otherwise.  Images larger than DAO_DEFAULT_MAX_PIXELS are
 * refused (dao_png_read_limited() takes another limit).  Errors:
 * -ENOENT/-EACCES (cannot open), -EINVAL (not a PNG, truncated or corrupt,
 * unsupported layout), -EFBIG (over the pixel limit), -ENOMEM.
 */
DAO_API int dao_png_read(const char *path, struct dao_frame *out, struct dao_error *err);

/*
 * dao_png_read() with a limit on width x height (0 = DAO_DEFAULT_MAX_PIXELS):
 * the size the file declares is checked before any pixel memory is
 * allocated, so a small file that claims a huge image costs nothing.
 * -EFBIG with a message giving the size and the limit when it is over.
 */
DAO_API int dao_png_read_limited(const char *path, uint64_t max_pixels, struct dao_frame *out,
				 struct dao_error *err);

/*
 * Reads a depth image: a single-channel 16-bit PNG, returned as
 * DAO_PIXFMT_DEPTH16 with the given unit (metres per count).  Any other
 * layout is -EINVAL with a message saying what the file is.  The pixel
 * limit is DAO_DEFAULT_MAX_PIXELS, as in dao_png_read().
 */
DAO_API int dao_png_read_depth(const char *path, float depth_unit, struct dao_frame *out,
		       struct dao_error *err);

/* dao_png_read_depth() with a pixel limit, as dao_png_read_limited(). */
DAO_API int dao_png_read_depth_limited(const char *path, float depth_unit, uint64_t max_pixels,
				       struct dao_frame *out, struct dao_error *err);

/*
 * dao_png_write()'s compression: zlib level 1 with the PNG "Up" filter on
 * every row (and zlib's run-length matching for GRAY8/GRAY16 images, not for
 * DEPTH16, where it made files 1.6-4.6x larger and slower), the fastest
 * setting that still compresses well: a 640x480 frame in 4-14 ms instead of
 * 28-76 ms at level 6 with adaptive filters, 0-15 % larger (docs/daemon.md,
 * docs/perf/png-output.md; measured on AO, 8-bit AO and shaded frames).
 */
#define DAO_PNG_COMPRESSION_DEFAULT 1

/*
 * Writes GRAY8, GRAY16, DEPTH16 (as 16-bit gray) or RGB24 frames at
 * DAO_PNG_COMPRESSION_DEFAULT.  Errors: -EINVAL (bad frame or format), or
 * the errno of the failing create/write/rename (e.g. -ENOENT, -EACCES,
 * -ENOSPC).
 */
DAO_API int dao_png_write(const char *path, const struct dao_frame *frame, struct dao_error *err);

/*
 * dao_png_write() at another compression: 0 stores the pixels unfiltered
 * and uncompressed (fastest, largest); 1..9 are zlib's levels, every row
 * with the Up filter (1 also with run-length matching for gray images);
 * higher is slower and a little smaller.  -EINVAL outside 0..9.
 */
DAO_API int dao_png_write_compressed(const char *path, const struct dao_frame *frame,
				     int compression, struct dao_error *err);

/*
 * The PNG dao_png_write_compressed() would write, in memory: *data (malloc'ed,
 * release it with free()) holds *size bytes.  For servers and pipes that send
 * the picture rather than store it.  Errors: -EINVAL (bad frame, format or
 * compression), -ENOMEM; *data is NULL and *size 0 on failure.
 */
DAO_API int dao_png_encode(const struct dao_frame *frame, int compression, void **data,
			   size_t *size, struct dao_error *err);

#ifdef __cplusplus
}
#endif
#endif
