/* SPDX-License-Identifier: MIT */
/*
 * The filtered depth in image_transport's "compressedDepth" format
 * (compressed_depth_image_transport), for a sensor_msgs/CompressedImage on
 * IMAGE_TOPIC/compressedDepth that its subscriber plugin decodes:
 *
 *   format: "16UC1; compressedDepth png" (or rvl), "32FC1; compressedDepth png"
 *   data:   a 12-byte ConfigHeader: int32 format (0, inverse depth), float32
 *           depthQuantA, float32 depthQuantB (little-endian, as on the machines
 *           that write it), then
 *           png: a PNG of 16-bit grey values;
 *           rvl: width u32, height u32 (little-endian), then RVL (Wilson 2017,
 *                "Fast lossless depth image compression"): 32-bit little-endian
 *                words filled with 4-bit nibbles from the top; a number is
 *                3-bit groups, least significant first, the nibble's 4th bit
 *                set when another group follows; the image is runs of a zero
 *                count, a non-zero count, then each non-zero value as the
 *                zig-zag coded difference from the previous non-zero value.
 *   16UC1: the values are the depth counts (A = B = 0 in the header).
 *   32FC1: the values are quantised inverse depth, v = trunc(A / z + B) with
 *          A = q (q + 1), B = 1 - A / depth_max (q: depth_quantization),
 *          0 for no depth or z >= depth_max; z = A / (v - B) decoded.
 */
#ifndef DAO_ROS_CDEPTH_H
#define DAO_ROS_CDEPTH_H

#include <stddef.h>
#include <stdint.h>

#include "dao_ros.h"

#ifdef __cplusplus
extern "C" {
#endif

enum dao_ros_cdepth_codec { DAO_ROS_CDEPTH_PNG = 0, DAO_ROS_CDEPTH_RVL };

struct dao_ros_cdepth {
	enum dao_ros_cdepth_codec codec; /* "format": png (default) or rvl */
	int png_level;                   /* 1..9 (1) */
	double depth_max;                /* 32FC1: metres, 1..100 (10) */
	double depth_quantization;       /* 32FC1: 1..150 (100) */
	uint8_t *buf;                    /* the last encoding, kept for the next */
	size_t cap, len;
	char format[48];                 /* the message's format field */
};

/* The defaults of compressed_depth_image_transport's publisher. */
void dao_ros_cdepth_init(struct dao_ros_cdepth *c);
void dao_ros_cdepth_free(struct dao_ros_cdepth *c);

/* Sets "format", "png_level", "depth_max" or "depth_quantization" from text:
 * 0, -ENOENT for another name, -EINVAL with a message. */
int dao_ros_cdepth_set(struct dao_ros_cdepth *c, const char *name, const char *value,
		       struct dao_error *err);

/*
 * Encodes a depth image (dao_ros_proc_depth's: "16UC1" counts or "32FC1"
 * metres, NaN or 0 = no depth) into c->buf (c->len bytes) and c->format.
 * The buffer grows to the largest frame and is kept.  0, -EINVAL, -ENOMEM.
 */
int dao_ros_cdepth_encode(struct dao_ros_cdepth *c, const struct dao_ros_output *depth,
			  struct dao_error *err);

/* RVL alone: n values into out (room for dao_ros_rvl_bound(n) bytes); the bytes written. */
size_t dao_ros_rvl_encode(const uint16_t *in, size_t n, uint8_t *out);
static inline size_t dao_ros_rvl_bound(size_t n)
{
	return 4 * n + 16; /* a pixel: at most 8 nibbles (two counts and 6 of value) */
}

#ifdef __cplusplus
}
#endif
#endif
