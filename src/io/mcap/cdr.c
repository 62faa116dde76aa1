/* SPDX-License-Identifier: MIT */
/* CDR (XCDR1) reading: see cdr.h. */
#include "mcap/cdr.h"

#include <errno.h>
#include <string.h>

int dao_cdr_init(struct dao_cdr *c, const uint8_t *msg, size_t len)
{
	memset(c, 0, sizeof(*c));
	if (len < 4) {
		c->bad = 1;
		return -EINVAL;
	}
	/* the representation identifier: CDR_BE 0x0000, CDR_LE 0x0001 */
	if (msg[0] != 0 || msg[1] > 1) {
		c->bad = 1;
		return -ENOTSUP;
	}
	c->big_endian = msg[1] == 0;
	c->base = msg + 4;
	c->len = len - 4;
	return 0;
}

/* n bytes at the cursor after aligning it to `align`; NULL (and bad) past the end. */
static const uint8_t *take(struct dao_cdr *c, size_t align, size_t n)
{
	if (c->bad)
		return NULL;
	size_t at = (c->at + align - 1) & ~(align - 1);
	if (at > c->len || n > c->len - at) {
		c->bad = 1;
		return NULL;
	}
	c->at = at + n;
	return c->base + at;
}

static uint64_t get(struct dao_cdr *c, size_t n)
{
	const uint8_t *p = take(c, n, n);
	uint64_t v = 0;
	if (!p)
		return 0;
	for (size_t i = 0; i < n; i++)
		v |= (uint64_t)p[c->big_endian ? n - 1 - i : i] << (8 * i);
	return v;
}

uint8_t dao_cdr_u8(struct dao_cdr *c)
{
	return (uint8_t)get(c, 1);
}

uint16_t dao_cdr_u16(struct dao_cdr *c)
{
	return (uint16_t)get(c, 2);
}

uint32_t dao_cdr_u32(struct dao_cdr *c)
{
	return (uint32_t)get(c, 4);
}

int32_t dao_cdr_i32(struct dao_cdr *c)
{
	uint32_t u = dao_cdr_u32(c);
	int32_t v;
	memcpy(&v, &u, 4);
	return v;
}

uint64_t dao_cdr_u64(struct dao_cdr *c)
{
	return get(c, 8);
}

float dao_cdr_f32(struct dao_cdr *c)
{
	uint32_t u = dao_cdr_u32(c);
	float v;
	memcpy(&v, &u, 4);
	return v;
}

double dao_cdr_f64(struct dao_cdr *c)
{
	uint64_t u = dao_cdr_u64(c);
	double v;
	memcpy(&v, &u, 8);
	return v;
}

const char *dao_cdr_string(struct dao_cdr *c, uint32_t *len)
{
	uint32_t n = dao_cdr_u32(c);
	*len = 0;
	if (c->bad)
		return "";
	/* the count includes the NUL (a few writers send 0 for the empty string) */
	if (n == 0)
		return "";
	const uint8_t *p = take(c, 1, n);
	if (!p || p[n - 1] != 0) {
		c->bad = 1;
		return "";
	}
	*len = n - 1;
	return (const char *)p;
}

static void string_copy(struct dao_cdr *c, char *dst, size_t cap, int strict)
{
	uint32_t n;
	const char *s = dao_cdr_string(c, &n);
	if (n >= cap || (strict && memchr(s, 0, n))) {
		c->bad = 1;
		n = 0;
	}
	memcpy(dst, s, n);
	dst[n] = 0;
}

void dao_cdr_string_copy(struct dao_cdr *c, char *dst, size_t cap)
{
	string_copy(c, dst, cap, 0);
}

void dao_cdr_string_copy_strict(struct dao_cdr *c, char *dst, size_t cap)
{
	string_copy(c, dst, cap, 1);
}

uint32_t dao_cdr_seq(struct dao_cdr *c, size_t item_size)
{
	uint32_t n = dao_cdr_u32(c);
	if (!c->bad && item_size && n > (c->len - c->at) / item_size) {
		c->bad = 1;
		return 0;
	}
	return c->bad ? 0 : n;
}

const uint8_t *dao_cdr_bytes(struct dao_cdr *c, size_t n)
{
	return take(c, 1, n);
}
