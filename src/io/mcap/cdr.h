/* SPDX-License-Identifier: MIT */
#ifndef DAO_MCAP_CDR_H
#define DAO_MCAP_CDR_H

/*
 * A reader of OMG CDR (XCDR version 1, "plain CDR") as ROS 2 serializes
 * messages (rmw's Fast DDS / Cyclone DDS, and MCAP's "cdr" message
 * encoding): a 4-byte encapsulation header (0x00 0x00 big-endian, 0x00
 * 0x01 little-endian, then two option bytes), then the fields.  Each
 * primitive is aligned to its own size (1, 2, 4 or 8) counted from the end
 * of the encapsulation header.  A string is a u32 length that counts its
 * terminating NUL, then the bytes; a sequence is a u32 count then the
 * items; a fixed array is its items.  Reading past the end, a string
 * without its NUL or a count larger than what is left sets `bad`, after
 * which every read gives 0: check dao_cdr_ok() once at the end.
 */
#include <stddef.h>
#include <stdint.h>

struct dao_cdr {
	const uint8_t *base; /* the first byte after the encapsulation header */
	size_t len, at;
	int big_endian;
	int bad;
};

/* 0, or -EINVAL (too short) / -ENOTSUP (another encapsulation: XCDR2, parameter lists). */
int dao_cdr_init(struct dao_cdr *c, const uint8_t *msg, size_t len);
static inline int dao_cdr_ok(const struct dao_cdr *c)
{
	return !c->bad;
}

uint8_t dao_cdr_u8(struct dao_cdr *c);
uint16_t dao_cdr_u16(struct dao_cdr *c);
uint32_t dao_cdr_u32(struct dao_cdr *c);
int32_t dao_cdr_i32(struct dao_cdr *c);
uint64_t dao_cdr_u64(struct dao_cdr *c);
float dao_cdr_f32(struct dao_cdr *c);
double dao_cdr_f64(struct dao_cdr *c);
/* A string: its bytes (NUL-terminated in the message) and length without the NUL. */
const char *dao_cdr_string(struct dao_cdr *c, uint32_t *len);
/* A string copied into dst (cap bytes, empty and bad if it does not fit). */
void dao_cdr_string_copy(struct dao_cdr *c, char *dst, size_t cap);
/* ... and bad too if it holds a NUL (Foxglove's strings, as its protobuf reader takes them). */
void dao_cdr_string_copy_strict(struct dao_cdr *c, char *dst, size_t cap);
/* A sequence's count, checked against the bytes left for items of item_size bytes. */
uint32_t dao_cdr_seq(struct dao_cdr *c, size_t item_size);
/* n raw bytes (a uint8[] or octet sequence's items). */
const uint8_t *dao_cdr_bytes(struct dao_cdr *c, size_t n);

#endif
