/* SPDX-License-Identifier: MIT */
/* Writes a 64x48 16-bit depth PNG (mm) of a box on a floor-like ramp, for the install test. */
#include <stdio.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

int main(int argc, char **argv)
{
	if (argc != 2)
		return 2;
	struct dao_frame f;
	struct dao_error err;
	if (dao_frame_alloc(&f, DAO_PIXFMT_DEPTH16, 64, 48, &err))
		return 1;
	for (uint32_t y = 0; y < 48; y++)
		for (uint32_t x = 0; x < 64; x++) {
			int box = x > 24 && x < 40 && y > 16 && y < 32;
			((uint16_t *)f.data)[y * 64 + x] = (uint16_t)(box ? 1500 : 2000 - 4 * y);
		}
	int r = dao_png_write(argv[1], &f, &err);
	if (r)
		fprintf(stderr, "%s\n", err.message);
	dao_frame_free(&f);
	return r ? 1 : 0;
}
