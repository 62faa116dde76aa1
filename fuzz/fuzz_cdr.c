/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target: the input is a CDR message (its encapsulation header
 * first), parsed as a ROS 2 Image, CompressedImage and CameraInfo, then
 * read field by field with every primitive of the CDR reader.  Aborts on
 * data pointing outside the input, a string that is not NUL-terminated
 * where it says, or a parse that succeeds on a reader that went bad.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "mcap/cdr.h"
#include "mcap/ros2_msg.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void inside(const uint8_t *p, size_t n, const uint8_t *d, size_t size)
{
	if (n && (p < d || p + n > d + size))
		abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct dao_ros2_image img;
	struct dao_ros2_compressed_image ci;
	struct dao_ros2_camera_info cam;
	if (dao_ros2_image_parse(data, size, &img) == 0) {
		inside(img.data, img.data_len, data, size);
		if (!memchr(img.encoding, 0, sizeof img.encoding))
			abort();
	}
	if (dao_ros2_compressed_image_parse(data, size, &ci) == 0) {
		inside(ci.data, ci.data_len, data, size);
		if (!memchr(ci.format, 0, sizeof ci.format))
			abort();
	}
	(void)dao_ros2_camera_info_parse(data, size, &cam);
	/* the primitives in an order taken from the data */
	struct dao_cdr c;
	if (dao_cdr_init(&c, data, size) < 0)
		return 0;
	for (size_t k = 0; k < 64 && dao_cdr_ok(&c); k++) {
		uint32_t n;
		const char *s;
		switch (data[k % size] & 7) {
		case 0: (void)dao_cdr_u8(&c); break;
		case 1: (void)dao_cdr_u16(&c); break;
		case 2: (void)dao_cdr_u32(&c); break;
		case 3: (void)dao_cdr_f64(&c); break;
		case 4:
			s = dao_cdr_string(&c, &n);
			if (dao_cdr_ok(&c) && n && s[n] != 0)
				abort();
			inside((const uint8_t *)s, n, data, size);
			break;
		case 5: n = dao_cdr_seq(&c, 2); inside(dao_cdr_bytes(&c, 2 * (size_t)n), 2 * (size_t)n, data, size); break;
		case 6: (void)dao_cdr_f32(&c); break;
		default: (void)dao_cdr_u64(&c); break;
		}
		if (c.at > c.len)
			abort();
	}
	return 0;
}
