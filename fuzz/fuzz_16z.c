/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target for the 16z and 16zT decoders.  The first two bytes
 * (little-endian) give the number of values n, the rest is the stream; both
 * decoders get it.  Whatever decodes must re-encode and decode back to the
 * same values (the encoders' rules permitting), and failures must say why.
 */
#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "oni/codec_16z.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static uint16_t scratch[65536];

static void check_round_trip(const uint16_t *v, size_t n, int table)
{
	size_t cap = dao_16z_bound(n, table);
	uint8_t *enc = malloc(cap);
	uint16_t *back = malloc(n * sizeof(*back));
	if (!enc || !back)
		abort();
	long len = table ? dao_16zt_encode(v, n, enc, cap, scratch) : dao_16z_encode(v, n, enc, cap);
	if (len == -ERANGE) {
		/* only legitimate for 16z values >= 32768 or > 32768 distinct values */
		if (!table) {
			int big = 0;
			for (size_t i = 0; i < n; i++)
				big |= v[i] >= 32768;
			if (!big)
				abort();
		}
	} else {
		const char *why = NULL;
		if (len <= 0 || (size_t)len > cap)
			abort();
		int r = table ? dao_16zt_decode(enc, (size_t)len, back, n, &why)
			      : dao_16z_decode(enc, (size_t)len, back, n, &why);
		if (r != 0 || memcmp(back, v, n * sizeof(*v)) != 0)
			abort();
	}
	free(enc);
	free(back);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size < 2)
		return 0;
	size_t n = (size_t)(data[0] | (data[1] << 8));
	/* exact-size copies so that any read or write past the end is caught */
	size_t len = size - 2;
	uint8_t *in = malloc(len ? len : 1);
	uint16_t *out = malloc(n ? n * sizeof(*out) : 1);
	if (!in || !out)
		abort();
	memcpy(in, data + 2, len);
	for (int table = 0; table < 2; table++) {
		const char *why = NULL;
		int r = table ? dao_16zt_decode(in, len, out, n, &why)
			      : dao_16z_decode(in, len, out, n, &why);
		if (r == 0) {
			if (n == 0)
				abort(); /* a stream always holds at least its first value */
			check_round_trip(out, n, table);
		} else if (r != -EINVAL || !why || !why[0]) {
			abort();
		}
	}
	free(in);
	free(out);
	return 0;
}
