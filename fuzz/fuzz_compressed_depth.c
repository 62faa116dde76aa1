/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target: image_transport's compressedDepth.  The first byte
 * picks the format (bit 0: 32FC1, bit 1: RVL), the rest is a
 * CompressedImage's data (ConfigHeader, then PNG or RVL).  The size it
 * announces is decoded when it is at most 512x512, into an exact-size
 * buffer (ASan sees any overrun).  Aborts on a failure without a reason.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "mcap/compressed_depth.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	static const char *const formats[] = {"16UC1; compressedDepth png", "32FC1; compressedDepth",
					      "16UC1; compressedDepth rvl", "32FC1; compressedDepth rvl"};
	struct dao_cdepth_format f;
	uint32_t w, h;
	if (size < 1 || dao_cdepth_parse_format(formats[data[0] & 3], &f) < 0)
		return 0;
	data++;
	size--;
	if (dao_cdepth_size(&f, data, size, &w, &h) < 0 || (uint64_t)w * h > 512 * 512)
		return 0;
	size_t bpp = f.is_float ? 4 : 2;
	uint8_t *out = malloc((size_t)w * h * bpp);
	uint16_t *scratch = malloc((size_t)w * h * sizeof(uint16_t));
	char why[160] = "";
	if (!out || !scratch)
		abort();
	if (dao_cdepth_decode(&f, data, size, w, h, out, (size_t)w * bpp, scratch, why,
			      sizeof why) < 0 && !why[0])
		abort();
	free(out);
	free(scratch);
	return 0;
}
