/* SPDX-License-Identifier: MIT */
/*
 * Colour frames of .oni image nodes to RGB24: JPEG (libturbojpeg), raw
 * RGB888, YUV422 (UYVY, OpenNI's "YUV422"), YUYV and 8-bit grey.
 */
#ifndef DAO_ONI_COLOR_H
#define DAO_ONI_COLOR_H

#include <stddef.h>
#include <stdint.h>

#include <depthao/frame.h>

/* OniPixelFormat of an OpenNI 1 xnPixelFormat (XnPixelFormat) value, 0 if unknown. */
int dao_oni_color_format_from_xn(uint64_t xn);

/* Bytes a raw (codec NONE) frame of this format holds, 0 if not a raw colour format. */
size_t dao_oni_color_raw_size(int pixel_format, uint32_t width, uint32_t height);

/*
 * Raw pixels of `pixel_format` (w x h, tightly packed) into an RGB24 frame of
 * that size.  YUV is BT.601 full range (JFIF), as libjpeg converts.
 */
void dao_oni_color_convert_raw(int pixel_format, const uint8_t *src, uint32_t width,
			       uint32_t height, struct dao_frame *out);

struct dao_jpeg;

int dao_jpeg_create(struct dao_jpeg **out);
void dao_jpeg_destroy(struct dao_jpeg *j);

/*
 * Decodes a JPEG into `out` (RGB24), which must have the image's size.
 * 0, or -EINVAL with `why` set: an error or a warning of libjpeg (damaged
 * entropy data decodes to a partly grey image with only a warning), or an
 * arithmetic-coded frame.
 */
int dao_jpeg_decode(struct dao_jpeg *j, const uint8_t *data, size_t size,
		    struct dao_frame *out, char *why, size_t why_len);

#endif
