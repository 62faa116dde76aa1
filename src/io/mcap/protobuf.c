/* SPDX-License-Identifier: MIT */
/* The protobuf wire format (protobuf.h). */
#include "mcap/protobuf.h"

#include <string.h>

static int left(struct dao_pb *r, size_t n)
{
	if (r->bad || (size_t)(r->end - r->p) < n) {
		r->bad = 1;
		return 0;
	}
	return 1;
}

uint64_t dao_pb_varint(struct dao_pb *r)
{
	uint64_t v = 0;
	for (int i = 0; i < 10; i++) {
		if (!left(r, 1))
			return 0;
		uint8_t b = *r->p++;
		v |= (uint64_t)(b & 0x7F) << (7 * i);
		if (!(b & 0x80))
			return v;
	}
	r->bad = 1;
	return 0;
}

int dao_pb_next(struct dao_pb *r, uint32_t *field, uint32_t *wire)
{
	if (r->bad || r->p >= r->end)
		return 0;
	uint64_t key = dao_pb_varint(r);
	*field = (uint32_t)(key >> 3);
	*wire = (uint32_t)(key & 7);
	if (r->bad || key >> 3 == 0 || key >> 32) {
		r->bad = 1;
		return 0;
	}
	return 1;
}

uint32_t dao_pb_fixed32(struct dao_pb *r)
{
	if (!left(r, 4))
		return 0;
	uint32_t v = (uint32_t)r->p[0] | (uint32_t)r->p[1] << 8 | (uint32_t)r->p[2] << 16 |
		     (uint32_t)r->p[3] << 24;
	r->p += 4;
	return v;
}

uint64_t dao_pb_fixed64(struct dao_pb *r)
{
	uint64_t lo = dao_pb_fixed32(r);
	uint64_t hi = dao_pb_fixed32(r);
	return lo | hi << 32;
}

double dao_pb_double(struct dao_pb *r)
{
	uint64_t u = dao_pb_fixed64(r);
	double d;
	memcpy(&d, &u, sizeof d);
	return d;
}

const uint8_t *dao_pb_bytes(struct dao_pb *r, size_t *len)
{
	uint64_t n = dao_pb_varint(r);
	*len = 0;
	if (r->bad || n > (uint64_t)(r->end - r->p)) {
		r->bad = 1;
		return NULL;
	}
	const uint8_t *p = r->p;
	r->p += n;
	*len = (size_t)n;
	return p;
}

void dao_pb_skip(struct dao_pb *r, uint32_t wire)
{
	size_t n;
	switch (wire) {
	case DAO_PB_VARINT:
		(void)dao_pb_varint(r);
		break;
	case DAO_PB_I64:
		(void)dao_pb_fixed64(r);
		break;
	case DAO_PB_LEN:
		(void)dao_pb_bytes(r, &n);
		break;
	case DAO_PB_I32:
		(void)dao_pb_fixed32(r);
		break;
	default: /* groups, and the wire types 6 and 7 that do not exist */
		r->bad = 1;
	}
}
