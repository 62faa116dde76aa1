/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target: the input is an .oni file.  It is opened with
 * dao_oni_reader_open() and every frame of every depth and colour stream is
 * read (colour: JPEG through libturbojpeg, raw RGB/YUV/grey), and each
 * depth frame's colour partner is looked up.
 * Any outcome is fine except a crash, a sanitizer report, an error without
 * a message, or an error code the API does not document.
 */
#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/frame.h>
#include <depthao/oni.h>

#include "harness.h"

/* Output frames larger than this are not allocated (the reader itself caps sizes at 16384). */
#define MAX_PIXELS (4096u * 4096u)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* documented codes only, always with a message */
static const int codes[] = { -EINVAL, -EIO, -ENOMEM, -ENOENT, -EACCES, -ENOTSUP, 0 };

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	static struct fuzz_file file;
	fuzz_file_store(&file, "fuzz.oni", NULL, data, size);

	struct dao_oni_reader *r = NULL;
	struct dao_error err = {0};
	int ret = dao_oni_reader_open(file.path, &r, &err);
	if (ret < 0) {
		if (r)
			abort();
		fuzz_check_error(ret, &err, codes);
		return 0;
	}
	uint32_t n = dao_oni_reader_stream_count(r);
	if (dao_oni_reader_stream(r, n) != NULL)
		abort();
	(void)dao_oni_reader_depth_stream(r, &err);
	int color = dao_oni_reader_color_stream(r, &err);
	for (uint32_t s = 0; s < n; s++) {
		const struct dao_oni_stream_info *in = dao_oni_reader_stream(r, s);
		if (!in || memchr(in->name, 0, sizeof(in->name)) == NULL || in->codec_fourcc[4] != 0)
			abort();
		if (in->sensor == DAO_ONI_SENSOR_COLOR && in->width && in->height &&
		    (uint64_t)in->width * in->height <= MAX_PIXELS) {
			struct dao_frame c = {.format = DAO_PIXFMT_RGB24, .width = in->width,
					.height = in->height,
					      .stride = (int32_t)(in->width * 3)};
			if (!(c.data = malloc((size_t)in->width * in->height * 3)))
				abort();
			for (uint32_t k = 0; k <= in->frame_count; k++) {
				err.message[0] = 0;
				ret = dao_oni_reader_read_color(r, s, k, &c, &err);
				if (ret < 0)
					fuzz_check_error(ret, &err, codes);
				else if (k == in->frame_count)
					abort();
			}
			free(c.data);
		}
		if (in->sensor != DAO_ONI_SENSOR_DEPTH)
			continue;
		for (uint32_t k = 0; color >= 0 && k < in->frame_count; k++) {
			uint32_t m;
			if (dao_oni_reader_match_frame(r, s, k, (uint32_t)color, &m) == 0 &&
			    m >= dao_oni_reader_stream(r, (uint32_t)color)->frame_count)
				abort();
		}
		if (in->width == 0 || in->height == 0 ||
		    (uint64_t)in->width * in->height > MAX_PIXELS)
			continue;
		struct dao_frame f = {.format = DAO_PIXFMT_DEPTH16, .width = in->width,
				.height = in->height,
				      .stride = (int32_t)(in->width * 2)};
		f.data = malloc((size_t)in->width * in->height * 2);
		if (!f.data)
			abort();
		for (uint32_t k = 0; k <= in->frame_count; k++) {
			err.message[0] = 0;
			ret = dao_oni_reader_read_depth(r, s, k, &f, &err);
			if (ret < 0)
				fuzz_check_error(ret, &err, codes);
			else if (k == in->frame_count)
				abort(); /* one past the end must fail */
		}
		free(f.data);
	}
	dao_oni_reader_close(r);
	return 0;
}
