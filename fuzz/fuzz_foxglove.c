/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target: Foxglove's image schemas (src/io/mcap/foxglove_msg.c,
 * and src/io/mcap/ros2_msg.c for their ROS 2 form) and the protobuf
 * wire-format reader under them.  The first byte chooses the schema (bits
 * 0-1: RawImage, CompressedImage, CameraCalibration) and the encoding (bit 3:
 * foxglove_msgs/msg/... in CDR, else bit 2: JSON, else protobuf); the rest
 * is the message.  The
 * rest is also read field by field with the wire-format primitives, and
 * base64-decoded into a buffer of its exact size.  Aborts on data outside
 * the message (protobuf) or the buffer (JSON), a string without its NUL, an
 * error code the parsers do not document, or a base64 result past its buffer.
 */
#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "mcap/foxglove_msg.h"
#include "mcap/protobuf.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void inside(const uint8_t *p, size_t n, const uint8_t *d, size_t size)
{
	if (n && (!p || p < d || p + n > d + size))
		abort();
}

static void image(int compressed, enum dao_fg_encoding enc, const uint8_t *msg, size_t n,
		  struct dao_fg_buf *buf)
{
	struct dao_fg_image img;
	int r = compressed ? dao_fg_compressed_image_parse(enc, msg, n, buf, &img)
			   : dao_fg_raw_image_parse(enc, msg, n, buf, &img);
	if (r != 0 && r != -EINVAL && r != -ENOMEM && r != -EFBIG &&
	    !(r == -ENOTSUP && enc == DAO_FG_CDR))
		abort();
	if (r < 0)
		return;
	if (!memchr(img.encoding, 0, sizeof img.encoding) ||
	    !memchr(img.frame_id, 0, sizeof img.frame_id))
		abort();
	if (enc == DAO_FG_JSON)
		inside(img.data, img.data_len, buf->p, buf->cap);
	else
		inside(img.data, img.data_len, msg, n);
}

static void wire(const uint8_t *msg, size_t n)
{
	struct dao_pb r;
	uint32_t f, w;
	size_t len;
	dao_pb_init(&r, msg, n);
	while (dao_pb_next(&r, &f, &w)) {
		if (f == 0 || w > 7)
			abort();
		if (w == DAO_PB_LEN && (f & 1)) {
			const uint8_t *p = dao_pb_bytes(&r, &len);
			if (!r.bad)
				inside(p, len, msg, n);
		} else {
			dao_pb_skip(&r, w);
		}
		if (r.p > r.end)
			abort();
	}
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size < 1)
		return 0;
	const uint8_t *msg = data + 1;
	size_t n = size - 1;
	enum dao_fg_encoding enc = data[0] & 8   ? DAO_FG_CDR
				   : data[0] & 4 ? DAO_FG_JSON
						 : DAO_FG_PROTOBUF;
	struct dao_fg_buf buf = {NULL, 0, 1u << 20};
	switch (data[0] & 3) {
	case 0:
	case 1:
		image(data[0] & 1, enc, msg, n, &buf);
		break;
	default: {
		struct dao_fg_calibration c;
		int r = dao_fg_calibration_parse(enc, msg, n, &c);
		if (r != 0 && r != -EINVAL && !(r == -ENOTSUP && enc == DAO_FG_CDR))
			abort();
		if (r == 0 && c.d_count > DAO_FG_MAX_DISTORTION && c.d_count > n)
			abort(); /* more D values than the message can hold */
	}
	}
	dao_fg_buf_free(&buf);
	wire(msg, n);
	size_t cap = n / 4 * 3 + 2;
	uint8_t *out = malloc(cap ? cap : 1);
	if (!out)
		return 0;
	long got = dao_base64_decode((const char *)msg, n, out, cap);
	if (got > (long)cap)
		abort();
	free(out);
	return 0;
}
