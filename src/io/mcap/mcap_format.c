/* SPDX-License-Identifier: MIT */
/* Parsers of MCAP record contents (mcap_format.h): every length checked against the record. */
#include "mcap/mcap_format.h"

#include <errno.h>
#include <string.h>
#include <zlib.h>

/* A cursor over one record's content. */
struct cur {
	const uint8_t *p;
	uint64_t left;
	int bad;
};

static const uint8_t *take(struct cur *c, uint64_t n)
{
	if (c->bad || n > c->left) {
		c->bad = 1;
		return NULL;
	}
	const uint8_t *p = c->p;
	c->p += n;
	c->left -= n;
	return p;
}

static uint8_t u8(struct cur *c)
{
	const uint8_t *p = take(c, 1);
	return p ? p[0] : 0;
}

static uint16_t u16(struct cur *c)
{
	const uint8_t *p = take(c, 2);
	return p ? dao_mcap_rd16(p) : 0;
}

static uint32_t u32(struct cur *c)
{
	const uint8_t *p = take(c, 4);
	return p ? dao_mcap_rd32(p) : 0;
}

static uint64_t u64(struct cur *c)
{
	const uint8_t *p = take(c, 8);
	return p ? dao_mcap_rd64(p) : 0;
}

static struct dao_mcap_str str(struct cur *c)
{
	struct dao_mcap_str s = {"", 0};
	uint32_t n = u32(c);
	const uint8_t *p = take(c, n);
	if (p) {
		s.ptr = (const char *)p;
		s.len = n;
	}
	return s;
}

/* A u32-length field of `item`-byte entries: its start and count. */
static const uint8_t *array32(struct cur *c, uint32_t item, uint32_t *count)
{
	uint32_t n = u32(c);
	const uint8_t *p = take(c, n);
	if (!p || n % item) {
		c->bad = 1;
		*count = 0;
		return NULL;
	}
	*count = n / item;
	return p;
}

static int done(const struct cur *c)
{
	return c->bad ? -EINVAL : 0;
}

int dao_mcap_str_eq(struct dao_mcap_str a, const char *s)
{
	size_t n = strlen(s);
	return a.len == n && !memcmp(a.ptr, s, n);
}

int dao_mcap_parse_header(const uint8_t *p, uint64_t n, struct dao_mcap_header *h)
{
	struct cur c = {p, n, 0};
	h->profile = str(&c);
	h->library = str(&c);
	return done(&c);
}

int dao_mcap_parse_footer(const uint8_t *p, uint64_t n, struct dao_mcap_footer *f)
{
	struct cur c = {p, n, 0};
	f->summary_start = u64(&c);
	f->summary_offset_start = u64(&c);
	f->summary_crc = u32(&c);
	return done(&c);
}

int dao_mcap_parse_schema(const uint8_t *p, uint64_t n, struct dao_mcap_schema *s)
{
	struct cur c = {p, n, 0};
	s->id = u16(&c);
	s->name = str(&c);
	s->encoding = str(&c);
	s->data_len = u32(&c);
	s->data = take(&c, s->data_len);
	return done(&c);
}

int dao_mcap_parse_channel(const uint8_t *p, uint64_t n, struct dao_mcap_channel *ch)
{
	struct cur c = {p, n, 0};
	ch->id = u16(&c);
	ch->schema_id = u16(&c);
	ch->topic = str(&c);
	ch->message_encoding = str(&c);
	uint32_t mlen = u32(&c); /* metadata, skipped */
	take(&c, mlen);
	return done(&c);
}

int dao_mcap_parse_message(const uint8_t *p, uint64_t n, struct dao_mcap_message *m)
{
	struct cur c = {p, n, 0};
	m->channel_id = u16(&c);
	m->sequence = u32(&c);
	m->log_time = u64(&c);
	m->publish_time = u64(&c);
	m->data_len = c.left;
	m->data = c.p;
	return done(&c);
}

int dao_mcap_parse_chunk(const uint8_t *p, uint64_t n, struct dao_mcap_chunk *ch)
{
	struct cur c = {p, n, 0};
	ch->message_start_time = u64(&c);
	ch->message_end_time = u64(&c);
	ch->uncompressed_size = u64(&c);
	ch->uncompressed_crc = u32(&c);
	ch->compression = str(&c);
	ch->records_len = u64(&c);
	ch->records = take(&c, ch->records_len);
	return done(&c);
}

int dao_mcap_parse_message_index(const uint8_t *p, uint64_t n, struct dao_mcap_message_index *mi)
{
	struct cur c = {p, n, 0};
	mi->channel_id = u16(&c);
	mi->entries = array32(&c, 16, &mi->count);
	return done(&c);
}

int dao_mcap_parse_chunk_index(const uint8_t *p, uint64_t n, struct dao_mcap_chunk_index *ci)
{
	struct cur c = {p, n, 0};
	ci->message_start_time = u64(&c);
	ci->message_end_time = u64(&c);
	ci->chunk_start_offset = u64(&c);
	ci->chunk_length = u64(&c);
	ci->index_offsets = array32(&c, 10, &ci->index_offsets_count);
	ci->message_index_length = u64(&c);
	ci->compression = str(&c);
	ci->compressed_size = u64(&c);
	ci->uncompressed_size = u64(&c);
	return done(&c);
}

int dao_mcap_parse_statistics(const uint8_t *p, uint64_t n, struct dao_mcap_statistics *s)
{
	struct cur c = {p, n, 0};
	s->message_count = u64(&c);
	s->schema_count = u16(&c);
	s->channel_count = u32(&c);
	s->attachment_count = u32(&c);
	s->metadata_count = u32(&c);
	s->chunk_count = u32(&c);
	s->message_start_time = u64(&c);
	s->message_end_time = u64(&c);
	return done(&c);
}

int dao_mcap_parse_summary_offset(const uint8_t *p, uint64_t n,
				  struct dao_mcap_summary_offset *so)
{
	struct cur c = {p, n, 0};
	so->group_opcode = u8(&c);
	so->group_start = u64(&c);
	so->group_length = u64(&c);
	return done(&c);
}

uint32_t dao_mcap_crc32(uint32_t crc, const void *data, size_t n)
{
	const uint8_t *p = data;
	while (n) {
		uInt k = n > (1u << 30) ? (1u << 30) : (uInt)n;
		crc = (uint32_t)crc32(crc, p, k);
		p += k;
		n -= k;
	}
	return crc;
}
