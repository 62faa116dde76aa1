/* SPDX-License-Identifier: MIT */
/* Prints "WIDTH HEIGHT FORMAT [MIN MAX]" of a PNG read by the library (for the CLI tests). */
#include <stdio.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

int main(int argc, char **argv)
{
	if (argc != 2) {
		fprintf(stderr, "usage: png_info FILE\n");
		return 2;
	}
	struct dao_frame f;
	struct dao_error err;
	if (dao_png_read(argv[1], &f, &err)) {
		fprintf(stderr, "%s\n", err.message);
		return 1;
	}
	unsigned lo = 0xffffffffu, hi = 0;
	for (uint32_t y = 0; y < f.height; y++)
		for (uint32_t x = 0; x < f.width; x++) {
			const unsigned char *row = (const unsigned char *)f.data + (size_t)y * f.stride;
			unsigned v = f.format == DAO_PIXFMT_GRAY16 ? ((const uint16_t *)(const void *)row)[x]
								   : row[x * dao_pixfmt_bytes_per_pixel(f.format)];
			lo = v < lo ? v : lo;
			hi = v > hi ? v : hi;
		}
	printf("%u %u %s %u %u\n", f.width, f.height, dao_pixfmt_name(f.format), lo, hi);
	dao_frame_free(&f);
	return 0;
}
