/* SPDX-License-Identifier: MIT */
/*
 * Protocol Buffers wire format, the little the foxglove sink writes: varints,
 * fixed32, doubles and length-delimited fields into a buffer the caller sized
 * (fox_pb_*_size give the bytes of each piece, so a message is measured first
 * and written once, in place).  The field numbers are proto/foxglove/schemas.proto's.
 */
#ifndef DAO_FOX_PROTO_H
#define DAO_FOX_PROTO_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

enum { PB_VARINT = 0, PB_I64 = 1, PB_LEN = 2, PB_I32 = 5 };

static inline size_t fox_pb_varint_size(uint64_t v)
{
	size_t n = 1;
	while (v >= 0x80) {
		v >>= 7;
		n++;
	}
	return n;
}

static inline uint8_t *fox_pb_varint(uint8_t *p, uint64_t v)
{
	while (v >= 0x80) {
		*p++ = (uint8_t)(v | 0x80);
		v >>= 7;
	}
	*p++ = (uint8_t)v;
	return p;
}

static inline uint8_t *fox_pb_tag(uint8_t *p, unsigned field, unsigned wire)
{
	return fox_pb_varint(p, (uint64_t)field << 3 | wire);
}

static inline uint8_t *fox_pb_fixed32(uint8_t *p, unsigned field, uint32_t v)
{
	p = fox_pb_tag(p, field, PB_I32);
	for (int i = 0; i < 4; i++)
		*p++ = (uint8_t)(v >> (8 * i));
	return p;
}

static inline uint8_t *fox_pb_double(uint8_t *p, unsigned field, double d)
{
	uint64_t v;
	memcpy(&v, &d, sizeof v);
	p = fox_pb_tag(p, field, PB_I64);
	for (int i = 0; i < 8; i++)
		*p++ = (uint8_t)(v >> (8 * i));
	return p;
}

/* The tag and length of a length-delimited field; its `len` bytes follow. */
static inline uint8_t *fox_pb_len(uint8_t *p, unsigned field, size_t len)
{
	return fox_pb_varint(fox_pb_tag(p, field, PB_LEN), len);
}

/* The size of a length-delimited field of `len` bytes (fields < 16). */
static inline size_t fox_pb_len_size(size_t len)
{
	return 1 + fox_pb_varint_size(len) + len;
}

static inline uint8_t *fox_pb_bytes(uint8_t *p, unsigned field, const void *data, size_t len)
{
	p = fox_pb_len(p, field, len);
	memcpy(p, data, len);
	return p + len;
}

static inline uint8_t *fox_pb_string(uint8_t *p, unsigned field, const char *s)
{
	return fox_pb_bytes(p, field, s, strlen(s));
}

/* google.protobuf.Timestamp {seconds = 1, nanos = 2} as field `field`. */
static inline size_t fox_pb_time_size(uint64_t ns)
{
	const size_t inner = 1 + fox_pb_varint_size(ns / 1000000000u) + 1 +
			     fox_pb_varint_size(ns % 1000000000u);
	return fox_pb_len_size(inner);
}

static inline uint8_t *fox_pb_time(uint8_t *p, unsigned field, uint64_t ns)
{
	const uint64_t sec = ns / 1000000000u, nsec = ns % 1000000000u;
	p = fox_pb_len(p, field, 2 + fox_pb_varint_size(sec) + fox_pb_varint_size(nsec));
	p = fox_pb_varint(fox_pb_tag(p, 1, PB_VARINT), sec);
	return fox_pb_varint(fox_pb_tag(p, 2, PB_VARINT), nsec);
}

#endif
