/* SPDX-License-Identifier: MIT */
#include <math.h>
#include <string.h>

#include "core/multiversion.h"
#include "depth/decode.h"

DAO_MULTIVERSION
void dao_decode_depth(const struct dao_frame *in, float zmin, float zmax, float *z, int y0,
		      int y1)
{
	const int w = (int)in->width;
	for (int y = y0; y < y1; y++) {
		const unsigned char *row = (const unsigned char *)in->data + (size_t)y * in->stride;
		float *out = z + (size_t)y * w;
		if (in->format == DAO_PIXFMT_DEPTH16) {
			const float unit = in->depth_unit;
			for (int x = 0; x < w; x++) {
				uint16_t c;
				memcpy(&c, row + 2 * (size_t)x, 2); /* rows may be unaligned */
				const float m = (float)c * unit;
				/* & rather than &&: no branch, so the loop vectorises */
				const int ok = (c != 0) & (m >= zmin) & (m <= zmax);
				out[x] = ok ? m : 0.0f;
			}
		} else {
			for (int x = 0; x < w; x++) {
				float m;
				memcpy(&m, row + 4 * (size_t)x, 4);
				/* the comparisons are false for NaN; isfinite rejects inf */
				out[x] = (isfinite(m) && m > 0.0f && m >= zmin && m <= zmax) ? m : 0.0f;
			}
		}
	}
}
