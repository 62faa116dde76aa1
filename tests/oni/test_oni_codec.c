/* SPDX-License-Identifier: MIT */
/*
 * OpenNI's 16z ("16zP") and 16zT depth codecs: exact round trips of random
 * and structured data, the documented error codes of the encoders, and the
 * decoder's handling of truncated, overlong, short and out-of-table streams.
 * Two byte streams are worked out by hand from the format description in
 * src/io/oni/codec_16z.h and checked value by value.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/cmocka_all.h"
#include "common/test_common.h"
#include "oni/codec_16z.h"

/* Sentinel slots after the n decoded values: the decoder must never touch them. */
#define GUARD 64
#define SENTINEL 0xA5A5u

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;

static uint32_t rnd(void)
{
	/* xorshift64*: deterministic, so a failure reproduces */
	rng_state ^= rng_state >> 12;
	rng_state ^= rng_state << 25;
	rng_state ^= rng_state >> 27;
	return (uint32_t)((rng_state * 0x2545F4914F6CDD1Dull) >> 32);
}

static uint32_t rnd_below(uint32_t n)
{
	return rnd() % n;
}

static uint16_t *alloc_out(size_t n)
{
	uint16_t *out = malloc((n + GUARD) * sizeof(*out));
	assert_non_null(out);
	for (size_t i = 0; i < n + GUARD; i++)
		out[i] = SENTINEL;
	return out;
}

static void assert_guard(const uint16_t *out, size_t n)
{
	for (size_t i = n; i < n + GUARD; i++)
		if (out[i] != SENTINEL)
			fail_msg("decoder wrote past the %zu values it was asked for (slot %zu)", n, i);
}

static void assert_values_equal(const uint16_t *want, const uint16_t *got, size_t n,
				const char *what)
{
	for (size_t i = 0; i < n; i++)
		if (want[i] != got[i])
			fail_msg("%s: value %zu of %zu is %u, expected %u", what, i, n, got[i],
				 want[i]);
}

typedef long (*encode_fn)(const uint16_t *in, size_t n, uint8_t *out, size_t cap);
typedef int (*decode_fn)(const uint8_t *in, size_t len, uint16_t *out, size_t n,
			 const char **why);

static uint16_t *scratch; /* 65536 entries for 16zT */

static long enc_16zt(const uint16_t *in, size_t n, uint8_t *out, size_t cap)
{
	return dao_16zt_encode(in, n, out, cap, scratch);
}

/*
 * Encodes and decodes `v` with one codec and checks the result is exact, that
 * the encoded size is within the bound, that exactly the encoded size is
 * enough (one byte less is -ENOSPC), and that decoding into one value fewer
 * or more fails.  Returns the encoded size.
 */
static long round_trip(const uint16_t *v, size_t n, int table, const char *what)
{
	encode_fn enc = table ? enc_16zt : dao_16z_encode;
	decode_fn dec = table ? dao_16zt_decode : dao_16z_decode;
	size_t bound = dao_16z_bound(n, table);
	uint8_t *buf = malloc(bound);
	assert_non_null(buf);
	long len = enc(v, n, buf, bound);
	if (len <= 0)
		fail_msg("%s (%s, n=%zu): encode returned %ld", what, table ? "16zT" : "16z", n, len);
	assert_true((size_t)len <= bound);

	uint16_t *out = alloc_out(n + 1);
	const char *why = NULL;
	int r = dec(buf, (size_t)len, out, n, &why);
	if (r != 0)
		fail_msg("%s (%s, n=%zu): decode failed: %s", what, table ? "16zT" : "16z", n,
			 why ? why : "(no reason)");
	assert_values_equal(v, out, n, what);
	assert_guard(out, n); /* nothing written past n */

	/* one value too many in the stream for the frame */
	if (n > 1) {
		why = NULL;
		assert_int_equal(dec(buf, (size_t)len, out, n - 1, &why), -EINVAL);
		assert_non_null(why);
		assert_non_null(strstr(why, "more values"));
	}
	/* one value too few */
	why = NULL;
	assert_int_equal(dec(buf, (size_t)len, out, n + 1, &why), -EINVAL);
	assert_non_null(why);
	assert_non_null(strstr(why, "fewer values"));

	/* the exact size is enough, one byte less is not */
	uint8_t *tight = malloc((size_t)len);
	assert_non_null(tight);
	assert_int_equal(enc(v, n, tight, (size_t)len), len);
	assert_memory_equal(tight, buf, (size_t)len);
	assert_int_equal(enc(v, n, tight, (size_t)len - 1), -ENOSPC);
	free(tight);
	free(out);
	free(buf);
	return len;
}

static void round_trip_both(const uint16_t *v, size_t n, const char *what)
{
	int fits_16z = 1;
	for (size_t i = 0; i < n; i++)
		fits_16z &= v[i] < 32768;
	if (fits_16z)
		round_trip(v, n, 0, what);
	round_trip(v, n, 1, what);
}

/* ---------------------------------------------------------------------- */

static void test_hand_built_16z(void **state)
{
	(void)state;
	/*
	 * Worked out from the format description:
	 *   E8 03  first value 0x03E8                          -> 1000
	 *   68     nibble 6 (d=0) -> 1000; nibble 8 (d=2)      -> 998
	 *   39     nibble 3 (d=-3) -> 1001; nibble 9 (d=3)     -> 998
	 *   E2     run of 2 byte-0x66 pairs                    -> 998 998 998 998
	 *   FF 98  escape, one byte d = 0x98 - 192 = -40       -> 1038
	 *   7F     nibble 7 (d=1) -> 1037; nibble F: escape follows
	 *   7F FF  top bit clear: the value big-endian         -> 32767
	 *   7D     nibble 7 (d=1) -> 32766; nibble D: end
	 */
	static const uint8_t stream[] = {0xE8, 0x03, 0x68, 0x39, 0xE2, 0xFF,
					 0x98, 0x7F, 0x7F, 0xFF, 0x7D};
	static const uint16_t want[] = {1000, 1000, 998, 1001, 998,  998,  998,
					998,  998,  1038, 1037, 32767, 32766};
	const size_t n = sizeof(want) / sizeof(want[0]);
	uint16_t *out = alloc_out(n);
	const char *why = NULL;
	assert_int_equal(dao_16z_decode(stream, sizeof(stream), out, n, &why), 0);
	assert_values_equal(want, out, n, "hand-built 16z stream");
	assert_guard(out, n);

	/* the encoder produces exactly these bytes for these values */
	uint8_t enc[64];
	assert_int_equal(dao_16z_encode(want, n, enc, sizeof(enc)), (long)sizeof(stream));
	assert_memory_equal(enc, stream, sizeof(stream));

	/* 0xE0 is an empty run; the subtraction wraps like OpenNI's (0 - 1 = 65535) */
	static const uint8_t s2[] = {0x05, 0x00, 0xE0, 0x6D, 0x7D};
	assert_int_equal(dao_16z_decode(s2, sizeof(s2), out, 3, &why), 0);
	assert_int_equal(out[0], 5);
	assert_int_equal(out[1], 5);
	assert_int_equal(out[2], 4);
	static const uint8_t s3[] = {0x00, 0x00, 0x7D};
	assert_int_equal(dao_16z_decode(s3, sizeof(s3), out, 2, &why), 0);
	assert_int_equal(out[0], 0);
	assert_int_equal(out[1], 65535);
	/* a run byte 0xEF is 15 pairs: 30 more values */
	static const uint8_t s4[] = {0x10, 0x27, 0xEF};
	uint16_t *o31 = alloc_out(31);
	assert_int_equal(dao_16z_decode(s4, sizeof(s4), o31, 31, &why), 0);
	for (int i = 0; i < 31; i++)
		assert_int_equal(o31[i], 10000);
	assert_guard(o31, 31);
	free(o31);
	/*
	 * 62 equal values: the first, then 61 unchanged -> 30 pairs (two full
	 * run bytes 0xEF of 15 pairs each) and one nibble 6 closed with 0xD.
	 */
	uint16_t same[62];
	for (int i = 0; i < 62; i++)
		same[i] = 777; /* 0x0309 */
	static const uint8_t runs[] = {0x09, 0x03, 0xEF, 0xEF, 0x6D};
	assert_int_equal(dao_16z_encode(same, 62, enc, sizeof(enc)), (long)sizeof(runs));
	assert_memory_equal(enc, runs, sizeof(runs));
	uint16_t *o62 = alloc_out(62);
	assert_int_equal(dao_16z_decode(runs, sizeof(runs), o62, 62, &why), 0);
	assert_values_equal(same, o62, 62, "two full runs and a closing nibble");
	assert_guard(o62, 62);
	free(o62);
	free(out);
}

static void test_hand_built_16zt(void **state)
{
	(void)state;
	/*
	 *   03 00                 table of 3 values
	 *   00 00  F4 01  A0 0F   0, 500, 4000
	 *   02 00                 first index 2                  -> 4000
	 *   68                    d=0 -> index 2 (4000); d=2 -> index 0 (0)
	 *   5D                    d=-1 -> index 1 (500); end
	 */
	static const uint8_t stream[] = {0x03, 0x00, 0x00, 0x00, 0xF4, 0x01, 0xA0, 0x0F,
					 0x02, 0x00, 0x68, 0x5D};
	static const uint16_t want[] = {4000, 4000, 0, 500};
	uint16_t *out = alloc_out(4);
	const char *why = NULL;
	assert_int_equal(dao_16zt_decode(stream, sizeof(stream), out, 4, &why), 0);
	assert_values_equal(want, out, 4, "hand-built 16zT stream");
	assert_guard(out, 4);
	uint8_t enc[64];
	assert_int_equal(dao_16zt_encode(want, 4, enc, sizeof(enc), scratch), (long)sizeof(stream));
	assert_memory_equal(enc, stream, sizeof(stream));

	/* index past the table: first index 3 of a 3-entry table */
	uint8_t bad[sizeof(stream)];
	memcpy(bad, stream, sizeof(bad));
	bad[8] = 3;
	why = NULL;
	assert_int_equal(dao_16zt_decode(bad, sizeof(bad), out, 4, &why), -EINVAL);
	assert_non_null(why);
	assert_non_null(strstr(why, "past the end"));
	/* ... and reached by a difference: index 2, then d=-1 -> 3 */
	memcpy(bad, stream, sizeof(bad));
	bad[10] = 0x5D; /* 2 -> 3, end */
	why = NULL;
	assert_int_equal(dao_16zt_decode(bad, 11, out, 2, &why), -EINVAL);
	assert_non_null(why);
	assert_non_null(strstr(why, "past the end"));
	/* a table that claims more entries than the stream holds */
	memcpy(bad, stream, sizeof(bad));
	bad[0] = 0x10;
	why = NULL;
	assert_int_equal(dao_16zt_decode(bad, sizeof(bad), out, 4, &why), -EINVAL);
	assert_non_null(why);
	assert_non_null(strstr(why, "table"));
	bad[0] = 0xFF;
	bad[1] = 0xFF;
	why = NULL;
	assert_int_equal(dao_16zt_decode(bad, sizeof(bad), out, 4, &why), -EINVAL);
	assert_non_null(why);
	/* an empty table: every index is past its end */
	static const uint8_t empty_table[] = {0x00, 0x00, 0x00, 0x00};
	why = NULL;
	assert_int_equal(dao_16zt_decode(empty_table, sizeof(empty_table), out, 1, &why), -EINVAL);
	assert_non_null(why);
	assert_non_null(strstr(why, "past the end"));
	assert_guard(out, 4);
	free(out);
}

static void test_structured_round_trips(void **state)
{
	(void)state;
	enum { N = 5000 };
	uint16_t *v = malloc(N * sizeof(*v));
	assert_non_null(v);
	char what[96];

	/* every length from 1 to 70, odd and even, of a few patterns */
	for (size_t n = 1; n <= 70; n++) {
		for (size_t i = 0; i < n; i++)
			v[i] = (uint16_t)(1000 + i); /* ramp up by 1 */
		snprintf(what, sizeof(what), "ramp +1, n=%zu", n);
		round_trip_both(v, n, what);
		for (size_t i = 0; i < n; i++)
			v[i] = 4321; /* all equal: runs */
		snprintf(what, sizeof(what), "constant, n=%zu", n);
		round_trip_both(v, n, what);
		for (size_t i = 0; i < n; i++)
			v[i] = (uint16_t)((i & 1) ? 0 : 3000 + 7 * i); /* holes between big values */
		snprintf(what, sizeof(what), "holes, n=%zu", n);
		round_trip_both(v, n, what);
	}

	/* differences at the edges of each coding: +-6 nibble, +-7 / +-63 byte, +-64 full */
	static const int steps[] = {0, 1, -1, 5, -5, 6, -6, 7, -7, 62, -62, 63, -63, 64, -64, 1000, -1000};
	for (size_t s = 0; s < sizeof(steps) / sizeof(steps[0]); s++) {
		for (int phase = 0; phase < 2; phase++) {
			/* phase 1 puts a nibble before each step so it closes a half byte */
			size_t n = 0;
			int cur = 16000;
			v[n++] = (uint16_t)cur;
			if (phase)
				v[n++] = (uint16_t)cur;
			for (int k = 0; k < 40; k++) {
				cur += (k & 1) ? -steps[s] : steps[s];
				v[n++] = (uint16_t)cur;
				if (phase)
					v[n++] = (uint16_t)(cur + 1), v[n++] = (uint16_t)cur;
			}
			snprintf(what, sizeof(what), "step %d phase %d", steps[s], phase);
			round_trip_both(v, n, what);
			round_trip_both(v, n - 1, what);
		}
	}

	/* runs of every length up to 100 pairs (several 0xEF bytes), after even and odd prefixes */
	for (size_t run = 1; run <= 201; run += 4) {
		for (int odd = 0; odd < 2; odd++) {
			size_t n = 0;
			v[n++] = 700;
			if (odd)
				v[n++] = 702;
			for (size_t k = 0; k < run; k++)
				v[n++] = 705;
			v[n++] = 30000; /* a big jump right after the run */
			for (size_t k = 0; k < run; k++)
				v[n++] = 30000;
			snprintf(what, sizeof(what), "run %zu odd %d", run, odd);
			round_trip_both(v, n, what);
			round_trip_both(v, n - 1, what); /* ending inside a run */
		}
	}

	/* values near the top of 16z's range, and the whole uint16 range for 16zT */
	for (size_t i = 0; i < N; i++)
		v[i] = (uint16_t)(32767 - rnd_below(12));
	round_trip_both(v, N, "near 32767");
	v[0] = 32767, v[1] = 0, v[2] = 32767, v[3] = 0, v[4] = 32767;
	round_trip_both(v, 5, "0 and 32767 alternating");
	for (size_t i = 0; i < N; i++)
		v[i] = (uint16_t)(65535 - rnd_below(40000));
	round_trip(v, N, 1, "16zT over the whole uint16 range");
	v[0] = 65535, v[1] = 0, v[2] = 32768, v[3] = 65535;
	round_trip(v, 4, 1, "16zT extremes");

	/* a smooth depth-image-like ramp with holes, 640x480 */
	size_t big = 640 * 480;
	uint16_t *img = malloc(big * sizeof(*img));
	assert_non_null(img);
	for (size_t y = 0; y < 480; y++)
		for (size_t x = 0; x < 640; x++)
			img[y * 640 + x] = ((x / 37 + y / 29) % 7 == 0)
						   ? 0
						   : (uint16_t)(800 + 3 * y + x / 2 + (x * y) % 3);
	long l16z = round_trip(img, big, 0, "640x480 depth-like");
	long l16zt = round_trip(img, big, 1, "640x480 depth-like");
	/* the codecs must actually compress smooth depth (raw is 2 bytes a pixel) */
	assert_true((size_t)l16z < big);
	assert_true((size_t)l16zt < big);
	free(img);
	free(v);
}

static void test_random_round_trips(void **state)
{
	(void)state;
	enum { N = 4096 };
	uint16_t *v = malloc(N * sizeof(*v));
	assert_non_null(v);
	char what[64];
	for (int iter = 0; iter < 300; iter++) {
		size_t n = 1 + rnd_below(iter < 100 ? 40 : N);
		int kind = iter % 4;
		uint32_t cur = rnd_below(32768);
		for (size_t i = 0; i < n; i++) {
			switch (kind) {
			case 0: v[i] = (uint16_t)rnd_below(32768); break; /* uniform: all escapes */
			case 1: {                                        /* random walk, mostly small */
				int r = (int)rnd_below(100);
				int d = r < 70 ? (int)rnd_below(13) - 6
					: r < 90 ? (int)rnd_below(127) - 63
					: r < 95 ? 0
						 : (int)rnd_below(20000) - 10000;
				int c = (int)cur + d;
				cur = (uint32_t)(c < 0 ? 0 : c > 32767 ? 32767 : c);
				v[i] = (uint16_t)cur;
				break;
			}
			case 2: /* runs of random length with holes */
				if (rnd_below(8) == 0)
					cur = rnd_below(4) == 0 ? 0 : rnd_below(32768);
				v[i] = (uint16_t)cur;
				break;
			default: v[i] = (uint16_t)rnd(); break; /* full 16 bits: 16zT only */
			}
		}
		snprintf(what, sizeof(what), "random kind %d iteration %d", kind, iter);
		round_trip_both(v, n, what);
	}
	free(v);
}

static void test_encode_errors(void **state)
{
	(void)state;
	uint8_t buf[256];
	uint16_t v[4] = {100, 200, 32768, 5};
	/* 16z holds values below 32768 only: as the first value and later */
	assert_int_equal(dao_16z_encode(v, 4, buf, sizeof(buf)), -ERANGE);
	assert_int_equal(dao_16z_encode(v + 2, 2, buf, sizeof(buf)), -ERANGE);
	v[2] = 65535;
	assert_int_equal(dao_16z_encode(v, 4, buf, sizeof(buf)), -ERANGE);
	v[2] = 32767;
	assert_true(dao_16z_encode(v, 4, buf, sizeof(buf)) > 0);
	/* no values */
	assert_int_equal(dao_16z_encode(v, 0, buf, sizeof(buf)), -EINVAL);
	assert_int_equal(dao_16zt_encode(v, 0, buf, sizeof(buf), scratch), -EINVAL);
	/* outputs too short for the first value or the table */
	assert_int_equal(dao_16z_encode(v, 4, buf, 0), -ENOSPC);
	assert_int_equal(dao_16z_encode(v, 4, buf, 1), -ENOSPC);
	assert_int_equal(dao_16zt_encode(v, 4, buf, 0, scratch), -ENOSPC);
	assert_int_equal(dao_16zt_encode(v, 4, buf, 1, scratch), -ENOSPC);
	assert_int_equal(dao_16zt_encode(v, 4, buf, 2 + 2 * 4 - 1, scratch), -ENOSPC);

	/* 16zT: 32768 distinct values fit (indices 0..32767), 32769 do not */
	enum { M = 32769 };
	uint16_t *d = malloc(M * sizeof(*d));
	assert_non_null(d);
	for (size_t i = 0; i < M; i++)
		d[i] = (uint16_t)(2 * i); /* 0, 2, ..., 65534, then 65536 -> 0 again */
	/* 32768 distinct values (the last repeats 0) */
	size_t bound = dao_16z_bound(M, 1);
	uint8_t *out = malloc(bound);
	assert_non_null(out);
	long len = dao_16zt_encode(d, M, out, bound, scratch);
	assert_true(len > 0);
	assert_int_equal(out[0] | (out[1] << 8), 32768);
	uint16_t *back = alloc_out(M);
	const char *why = NULL;
	assert_int_equal(dao_16zt_decode(out, (size_t)len, back, M, &why), 0);
	assert_values_equal(d, back, M, "32768 distinct values");
	assert_guard(back, M);
	d[M - 1] = 1; /* now 32769 distinct */
	assert_int_equal(dao_16zt_encode(d, M, out, bound, scratch), -ERANGE);
	/* 16z rejects the same data for values >= 32768 */
	assert_int_equal(dao_16z_encode(d, M, out, bound), -ERANGE);
	free(back);
	free(out);
	free(d);
}

/*
 * Cuts a stream at every byte: decoding the prefix must not crash or write
 * past n values, and must fail with a reason or (if the prefix happens to
 * be a complete stream) give exactly the original n values.
 */
static void check_every_cut(const uint8_t *s, size_t len, const uint16_t *want, size_t n,
			    int table)
{
	decode_fn dec = table ? dao_16zt_decode : dao_16z_decode;
	uint16_t *out = alloc_out(n);
	int failures = 0;
	for (size_t cut = 0; cut < len; cut++) {
		const char *why = NULL;
		/* a heap copy of exactly `cut` bytes, so reading past it is caught by sanitizers */
		uint8_t *copy = malloc(cut ? cut : 1);
		assert_non_null(copy);
		if (cut)
			memcpy(copy, s, cut);
		int r = dec(copy, cut, out, n, &why);
		if (r == 0) {
			assert_values_equal(want, out, n, "valid prefix");
		} else {
			assert_int_equal(r, -EINVAL);
			if (!why || !why[0])
				fail_msg("cut at %zu of %zu: no reason given", cut, len);
			failures++;
		}
		assert_guard(out, n);
		free(copy);
	}
	/* a prefix lacks at least the final byte's values, so each cut must fail here */
	assert_int_equal(failures, (int)len);
	free(out);
}

static void test_truncated_streams(void **state)
{
	(void)state;
	/* a small stream using every kind of code: nibbles, runs, byte and full escapes */
	static const uint16_t v[] = {500, 500, 502, 499, 499, 499, 499, 499, 499, 499, 560,
				     561, 9000, 9000, 9001, 0, 0, 0, 12, 32767, 32760, 32761};
	const size_t n = sizeof(v) / sizeof(v[0]);
	uint8_t s[256];
	long len = dao_16z_encode(v, n, s, sizeof(s));
	assert_true(len > 10);
	check_every_cut(s, (size_t)len, v, n, 0);
	len = dao_16zt_encode(v, n, s, sizeof(s), scratch);
	assert_true(len > 10);
	check_every_cut(s, (size_t)len, v, n, 1);

	/* specific endings */
	uint16_t out[8 + GUARD];
	const char *why;
	static const uint8_t esc_end[] = {0x00, 0x00, 0xFF};
	why = NULL;
	assert_int_equal(dao_16z_decode(esc_end, 3, out, 2, &why), -EINVAL);
	assert_non_null(strstr(why, "escape"));
	static const uint8_t nib_esc_end[] = {0x00, 0x00, 0x7F};
	why = NULL;
	assert_int_equal(dao_16z_decode(nib_esc_end, 3, out, 3, &why), -EINVAL);
	assert_non_null(strstr(why, "escape"));
	static const uint8_t half_value[] = {0x00, 0x00, 0xFF, 0x12};
	why = NULL;
	assert_int_equal(dao_16z_decode(half_value, 4, out, 2, &why), -EINVAL);
	assert_non_null(strstr(why, "full value"));
	static const uint8_t one[] = {0x00};
	why = NULL;
	assert_int_equal(dao_16z_decode(one, 1, out, 1, &why), -EINVAL);
	assert_non_null(strstr(why, "first value"));
	why = NULL;
	assert_int_equal(dao_16zt_decode(one, 1, out, 1, &why), -EINVAL);
	assert_non_null(strstr(why, "table"));
	/* a stream with extra values after its end */
	static const uint8_t extra[] = {0x10, 0x00, 0x66, 0x66};
	why = NULL;
	assert_int_equal(dao_16z_decode(extra, 4, out, 3, &why), -EINVAL);
	assert_non_null(strstr(why, "more values"));
	why = NULL;
	assert_int_equal(dao_16z_decode(extra, 4, out, 5, &why), 0);
	/* a run that overflows the frame stops at the frame's end */
	static const uint8_t long_run[] = {0x10, 0x00, 0xEF};
	for (size_t i = 0; i < 8 + GUARD; i++)
		out[i] = SENTINEL;
	why = NULL;
	assert_int_equal(dao_16z_decode(long_run, 3, out, 8, &why), -EINVAL);
	assert_non_null(strstr(why, "more values"));
	assert_guard(out, 8);
}

/* Arbitrary bytes never crash the decoders and never write past n values. */
static void test_garbage_streams(void **state)
{
	(void)state;
	uint8_t buf[300];
	uint16_t *out = alloc_out(200);
	int ok = 0;
	for (int iter = 0; iter < 20000; iter++) {
		size_t len = rnd_below(sizeof(buf));
		for (size_t i = 0; i < len; i++) {
			/* bias towards the interesting bytes */
			uint32_t r = rnd_below(8);
			buf[i] = r == 0 ? 0xFF : r == 1 ? (uint8_t)(0xE0 + rnd_below(32)) : (uint8_t)rnd();
		}
		size_t n = 1 + rnd_below(200);
		for (size_t i = n; i < 200 + GUARD; i++)
			out[i] = SENTINEL;
		const char *why = NULL;
		int r = (iter & 1) ? dao_16zt_decode(buf, len, out, n, &why)
				   : dao_16z_decode(buf, len, out, n, &why);
		if (r == 0)
			ok++;
		else if (r != -EINVAL || !why || !why[0])
			fail_msg("garbage stream %d: r=%d why=%s", iter, r, why ? why : "(null)");
		for (size_t i = n; i < 200 + GUARD; i++)
			if (out[i] != SENTINEL)
				fail_msg("garbage stream %d: wrote slot %zu of n=%zu", iter, i, n);
	}
	(void)ok;
	free(out);
}

int main(void)
{
	scratch = malloc(65536 * sizeof(*scratch));
	if (!scratch)
		return 1;
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_hand_built_16z),
		cmocka_unit_test(test_hand_built_16zt),
		cmocka_unit_test(test_structured_round_trips),
		cmocka_unit_test(test_random_round_trips),
		cmocka_unit_test(test_encode_errors),
		cmocka_unit_test(test_truncated_streams),
		cmocka_unit_test(test_garbage_streams),
	};
	int r = cmocka_run_group_tests(tests, NULL, NULL);
	free(scratch);
	return r;
}
