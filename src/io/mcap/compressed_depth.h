/* SPDX-License-Identifier: MIT */
#ifndef DAO_MCAP_COMPRESSED_DEPTH_H
#define DAO_MCAP_COMPRESSED_DEPTH_H

/*
 * image_transport's "compressedDepth" images (compressed_depth_image_transport):
 * a sensor_msgs CompressedImage whose format is "ENC; compressedDepth CODEC"
 * ("ENC; compressedDepth" alone in older versions: PNG), ENC 16UC1 (or
 * mono16) or 32FC1, CODEC png or rvl.  The data is a 12-byte ConfigHeader
 * (format int32, depthQuantA float32, depthQuantB float32; little-endian as
 * the machines that write it), then
 *   png: a PNG of 16-bit grey values;
 *   rvl: cols u32, rows u32, then RVL (Wilson 2017): 32-bit little-endian
 *        words read from their top nibble down; a value is nibbles of 3 bits,
 *        least significant first, the 4th bit set when another follows; the
 *        image is runs: a count of zeros, a count of non-zeros, then each
 *        non-zero as the zig-zag coded difference from the previous one.
 * 16UC1 values are the depth counts.  32FC1 values are quantised inverse
 * depth v: depth = depthQuantA / (v - depthQuantB) metres, v = 0 no data.
 */
#include <stddef.h>
#include <stdint.h>

enum dao_cdepth_codec { DAO_CDEPTH_PNG, DAO_CDEPTH_RVL };

struct dao_cdepth_format {
	int is_float;               /* 32FC1 (quantised inverse depth) */
	enum dao_cdepth_codec codec;
	int plain;                  /* a PNG alone, without the ConfigHeader (16-bit
				     * grey counts: foxglove.CompressedImage "png") */
};

#define DAO_CDEPTH_CONFIG_HEADER 12

/* 0, or -EINVAL if `format` is not a compressedDepth format depthao reads. */
int dao_cdepth_parse_format(const char *format, struct dao_cdepth_format *f);

/* The size of the image in `data` (from the PNG's IHDR or RVL's header): 0 or -EINVAL
 * (for a plain PNG, also when it is not 16-bit grey). */
int dao_cdepth_size(const struct dao_cdepth_format *f, const uint8_t *data, size_t len,
		    uint32_t *width, uint32_t *height);

/*
 * Decodes `data` into `out` (width x height values, rows `stride` bytes
 * apart: uint16 for 16UC1, float for 32FC1, NaN where there is no data),
 * whose size the image must have.  0, or -EINVAL with `why` set.
 * `scratch` (width x height uint16) is used for 32FC1.
 */
int dao_cdepth_decode(const struct dao_cdepth_format *f, const uint8_t *data, size_t len,
		      uint32_t width, uint32_t height, void *out, size_t stride,
		      uint16_t *scratch, char *why, size_t why_len);

/* RVL alone: `n` values from `in` (len bytes) into out; -EINVAL if it ends early. */
int dao_rvl_decode(const uint8_t *in, size_t len, uint16_t *out, size_t n);

#endif
