/* SPDX-License-Identifier: MIT */
/* ROS 2 messages in CDR (ros2_msg.h). */
#include "mcap/ros2_msg.h"

#include <errno.h>
#include <string.h>

#include "mcap/cdr.h"

static void header(struct dao_cdr *c, struct dao_ros2_header *h)
{
	int32_t sec = dao_cdr_i32(c);
	uint32_t nsec = dao_cdr_u32(c);
	uint32_t n;
	(void)dao_cdr_string(c, &n); /* frame_id */
	h->stamp_ns = sec < 0 ? 0 : (uint64_t)sec * 1000000000u + nsec;
}

static int start(struct dao_cdr *c, const uint8_t *msg, uint64_t len)
{
	return dao_cdr_init(c, msg, len > SIZE_MAX ? SIZE_MAX : (size_t)len);
}

int dao_ros2_image_parse(const uint8_t *msg, uint64_t len, struct dao_ros2_image *img)
{
	struct dao_cdr c;
	int r = start(&c, msg, len);
	memset(img, 0, sizeof(*img));
	if (r < 0)
		return r;
	header(&c, &img->header);
	img->height = dao_cdr_u32(&c);
	img->width = dao_cdr_u32(&c);
	dao_cdr_string_copy(&c, img->encoding, sizeof img->encoding);
	img->is_bigendian = dao_cdr_u8(&c);
	img->step = dao_cdr_u32(&c);
	img->data_len = dao_cdr_seq(&c, 1);
	img->data = dao_cdr_bytes(&c, img->data_len);
	return dao_cdr_ok(&c) ? 0 : -EINVAL;
}

int dao_ros2_compressed_image_parse(const uint8_t *msg, uint64_t len,
				    struct dao_ros2_compressed_image *img)
{
	struct dao_cdr c;
	int r = start(&c, msg, len);
	memset(img, 0, sizeof(*img));
	if (r < 0)
		return r;
	header(&c, &img->header);
	dao_cdr_string_copy(&c, img->format, sizeof img->format);
	img->data_len = dao_cdr_seq(&c, 1);
	img->data = dao_cdr_bytes(&c, img->data_len);
	return dao_cdr_ok(&c) ? 0 : -EINVAL;
}

int dao_ros2_camera_info_parse(const uint8_t *msg, uint64_t len, struct dao_ros2_camera_info *ci)
{
	struct dao_cdr c;
	int r = start(&c, msg, len);
	memset(ci, 0, sizeof(*ci));
	if (r < 0)
		return r;
	header(&c, &ci->header);
	ci->height = dao_cdr_u32(&c);
	ci->width = dao_cdr_u32(&c);
	dao_cdr_string_copy(&c, ci->distortion_model, sizeof ci->distortion_model);
	ci->distortion_count = dao_cdr_seq(&c, 8);
	for (uint32_t i = 0; i < ci->distortion_count; i++) {
		double v = dao_cdr_f64(&c);
		if (i < DAO_ROS2_MAX_DISTORTION)
			ci->d[i] = v;
	}
	for (int i = 0; i < 9; i++)
		ci->k[i] = dao_cdr_f64(&c);
	for (int i = 0; i < 9; i++)
		ci->r[i] = dao_cdr_f64(&c);
	for (int i = 0; i < 12; i++)
		ci->p[i] = dao_cdr_f64(&c);
	/* binning_x, binning_y, roi (x_offset, y_offset, height, width, do_rectify): not used */
	return dao_cdr_ok(&c) ? 0 : -EINVAL;
}
