/* SPDX-License-Identifier: MIT */
#ifndef DAO_MCAP_PROTOBUF_H
#define DAO_MCAP_PROTOBUF_H

/*
 * A reader of the protobuf wire format (protobuf.dev/programming-guides/
 * encoding): a message is fields, each a key varint (field number << 3 |
 * wire type) then its value: 0 varint (7 bits a byte, least significant
 * first, the top bit set when another byte follows; at most 10 bytes), 1
 * eight little-endian bytes, 2 a varint length then that many bytes
 * (strings, bytes, sub-messages, packed repeated numbers), 5 four
 * little-endian bytes.  Groups (3, 4) are refused.  Reading past the end,
 * a varint longer than 10 bytes or a length past the end sets `bad`, after
 * which every read gives 0 and dao_pb_next() ends.
 */
#include <stddef.h>
#include <stdint.h>

struct dao_pb {
	const uint8_t *p, *end;
	int bad;
};

enum { DAO_PB_VARINT = 0, DAO_PB_I64 = 1, DAO_PB_LEN = 2, DAO_PB_I32 = 5 };

static inline void dao_pb_init(struct dao_pb *r, const uint8_t *msg, size_t len)
{
	r->p = msg;
	r->end = msg + len;
	r->bad = 0;
}

/* The next field's number and wire type: 1, or 0 at the end (or once bad). */
int dao_pb_next(struct dao_pb *r, uint32_t *field, uint32_t *wire);
uint64_t dao_pb_varint(struct dao_pb *r);
uint32_t dao_pb_fixed32(struct dao_pb *r);
uint64_t dao_pb_fixed64(struct dao_pb *r);
double dao_pb_double(struct dao_pb *r);
/* A length-delimited value: its bytes (in the message) and length. */
const uint8_t *dao_pb_bytes(struct dao_pb *r, size_t *len);
/* Skips a value of wire type `wire` (a field not read). */
void dao_pb_skip(struct dao_pb *r, uint32_t wire);

#endif
