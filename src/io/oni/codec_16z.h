/* SPDX-License-Identifier: MIT */
/*
 * OpenNI's lossless depth codecs.
 *
 * 16z ("16zP"): the first value as little-endian uint16, then the difference
 * d = previous - current of each further value as
 *   - a nibble d + 6 when |d| <= 6, two per byte (high nibble first); a
 *     pending nibble followed by a large difference is closed with 0xF, a
 *     nibble left over at the end with 0xD;
 *   - 0xFF (or a closing 0xF nibble), then one byte d + 192 when |d| <= 63;
 *   - 0xFF (or 0xF), then the value itself big-endian (its top bit clear);
 *   - runs of byte 0x66 (two unchanged values) as one byte 0xE0 + n, n <= 15.
 * 16zT: a table of the distinct values (uint16 count, then the values in
 * ascending order), then a 16z stream of indices into it.
 */
#ifndef DAO_ONI_CODEC_16Z_H
#define DAO_ONI_CODEC_16Z_H

#include <stddef.h>
#include <stdint.h>

/* Worst-case encoded size of n values (every value a 3-byte escape, plus table). */
size_t dao_16z_bound(size_t n, int with_table);

/*
 * Encodes n >= 1 values.  `scratch` (16zT only) is 65536 uint16 the caller
 * owns.  Returns the encoded size, -ERANGE when a value (16z) or the number of
 * distinct values (16zT) exceeds 32767 / 32768, or -ENOSPC if `cap` is short.
 */
long dao_16z_encode(const uint16_t *in, size_t n, uint8_t *out, size_t cap);
long dao_16zt_encode(const uint16_t *in, size_t n, uint8_t *out, size_t cap,
		     uint16_t *scratch);

/*
 * Decodes exactly n values.  Returns 0, or -EINVAL with *why set to a static
 * description when the stream is truncated, decodes to more or fewer than n
 * values, or (16zT) refers past the end of its table.  The decoding itself
 * (wrap-around arithmetic, the 0xE0..0xFE run bytes) matches OpenNI2's, so
 * any stream OpenNI2 decodes to n values decodes to the same values here.
 */
int dao_16z_decode(const uint8_t *in, size_t len, uint16_t *out, size_t n, const char **why);
int dao_16zt_decode(const uint8_t *in, size_t len, uint16_t *out, size_t n, const char **why);

#endif
