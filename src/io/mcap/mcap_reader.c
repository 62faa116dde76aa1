/* SPDX-License-Identifier: MIT */
/* MCAP reader (see mcap_reader.h and mcap_format.h for the layout). */
#include "mcap/mcap_reader.h"

#include <errno.h>
#include <fcntl.h>
#include <lz4frame.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zstd.h>

#include "core/error_internal.h"
#include "mcap/mcap_format.h"

/* Schema and channel records hold names and a definition: small. */
#define MCAP_MAX_META (4u << 20)
/* The summary (schemas, channels, chunk and other indexes) read whole. */
#define MCAP_MAX_SUMMARY (256u << 20)
/* Recorders make a channel per topic: a few hundred at most. */
#define MCAP_MAX_CHANNELS 4096
#define MCAP_MAX_SCHEMAS 4096
/* Messages indexed over all channels (24 bytes each). */
#define MCAP_MAX_MESSAGES (8u << 20)
#define NO_CHUNK UINT32_MAX

enum compression { COMP_NONE, COMP_ZSTD, COMP_LZ4 };

struct chunk {
	uint64_t pos;        /* of the chunk record */
	uint64_t data_pos;   /* of its (compressed) records */
	uint64_t data_len;
	uint64_t size;       /* uncompressed */
	uint32_t crc;        /* of the uncompressed records, 0: none */
	enum compression comp;
};

struct entry {
	uint64_t time;
	uint64_t off;        /* of the message record: in the uncompressed chunk, or the file */
	uint32_t chunk;      /* NO_CHUNK: a message outside chunks */
	uint32_t order;      /* as found, for a stable sort */
};

struct schema {
	uint16_t id;
	char *name, *encoding;
};

struct topic {
	struct dao_mcap_topic pub;
	uint16_t id;
	char *name, *encoding;
	struct entry *entries;
	uint32_t count, cap;
};

struct dao_mcap {
	char *path;
	int fd;
	uint64_t size;
	uint64_t max_chunk;
	struct schema *schemas;
	uint32_t nschemas;
	struct topic *topics;
	uint32_t ntopics;
	int32_t *topic_of_id;  /* channel id -> topic index, -1 */
	struct chunk *chunks;
	uint32_t nchunks, chunks_cap;
	uint64_t nmessages;
	int indexed;
	uint8_t *raw;          /* compressed data of the cached chunk, or a record */
	size_t raw_cap;
	uint8_t *buf;          /* uncompressed data of the cached chunk */
	size_t buf_cap;
	int64_t cached;        /* chunk in buf, -1 for none */
	ZSTD_DCtx *zstd;
	LZ4F_dctx *lz4;
	char warning[256];
};

static int read_at(struct dao_mcap *m, uint64_t pos, void *dst, size_t n, struct dao_error *err)
{
	uint8_t *d = dst;
	if (pos > m->size || n > m->size - pos)
		return dao_error_set(err, -EINVAL, "%s: byte %llu: %zu bytes run past the end of the "
				     "file (%llu bytes)", m->path, (unsigned long long)pos, n,
				     (unsigned long long)m->size);
	while (n) {
		ssize_t r = pread(m->fd, d, n, (off_t)pos);
		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0)
			return dao_error_set(err, -EIO, "%s: read error at byte %llu: %s", m->path,
					     (unsigned long long)pos, strerror(errno));
		if (r == 0)
			return dao_error_set(err, -EINVAL, "%s: byte %llu: the file ends early",
					     m->path, (unsigned long long)pos);
		d += r;
		pos += (uint64_t)r;
		n -= (size_t)r;
	}
	return 0;
}

static int grow(uint8_t **buf, size_t *cap, uint64_t n, struct dao_error *err)
{
	if (n <= *cap)
		return 0;
	uint8_t *p = realloc(*buf, (size_t)n);
	if (!p)
		return dao_error_set(err, -ENOMEM, "out of memory (%llu bytes)",
				     (unsigned long long)n);
	*buf = p;
	*cap = (size_t)n;
	return 0;
}

static char *dup_str(struct dao_mcap_str s)
{
	char *p = malloc((size_t)s.len + 1);
	if (p) {
		memcpy(p, s.ptr, s.len);
		p[s.len] = 0;
	}
	return p;
}

static int corrupt(struct dao_mcap *m, uint64_t pos, const char *what, struct dao_error *err)
{
	return dao_error_set(err, -EINVAL, "%s: byte %llu: %s", m->path,
			     (unsigned long long)pos, what);
}

static int add_schema(struct dao_mcap *m, const uint8_t *c, uint64_t n, uint64_t pos,
		      struct dao_error *err)
{
	struct dao_mcap_schema s;
	if (dao_mcap_parse_schema(c, n, &s) < 0 || s.id == 0)
		return corrupt(m, pos, "a schema record is damaged", err);
	for (uint32_t i = 0; i < m->nschemas; i++)
		if (m->schemas[i].id == s.id)
			return 0; /* the summary repeats the data section's */
	if (m->nschemas >= MCAP_MAX_SCHEMAS)
		return dao_error_set(err, -EFBIG, "%s: more than %u schemas", m->path,
				     MCAP_MAX_SCHEMAS);
	if (!(m->nschemas & (m->nschemas - 1)) || !m->nschemas) {
		struct schema *p = realloc(m->schemas, sizeof(*p) * (m->nschemas ? 2 * m->nschemas : 8));
		if (!p)
			return dao_error_set(err, -ENOMEM, "out of memory");
		m->schemas = p;
	}
	struct schema *sc = &m->schemas[m->nschemas];
	sc->id = s.id;
	sc->name = dup_str(s.name);
	sc->encoding = dup_str(s.encoding);
	m->nschemas++;
	if (!sc->name || !sc->encoding)
		return dao_error_set(err, -ENOMEM, "out of memory");
	return 0;
}

static int add_channel(struct dao_mcap *m, const uint8_t *c, uint64_t n, uint64_t pos,
		       struct dao_error *err)
{
	struct dao_mcap_channel ch;
	if (dao_mcap_parse_channel(c, n, &ch) < 0)
		return corrupt(m, pos, "a channel record is damaged", err);
	if (m->topic_of_id[ch.id] >= 0)
		return 0;
	if (m->ntopics >= MCAP_MAX_CHANNELS)
		return dao_error_set(err, -EFBIG, "%s: more than %u channels", m->path,
				     MCAP_MAX_CHANNELS);
	if (!(m->ntopics & (m->ntopics - 1)) || !m->ntopics) {
		struct topic *p = realloc(m->topics, sizeof(*p) * (m->ntopics ? 2 * m->ntopics : 8));
		if (!p)
			return dao_error_set(err, -ENOMEM, "out of memory");
		m->topics = p;
	}
	struct topic *t = &m->topics[m->ntopics];
	memset(t, 0, sizeof(*t));
	t->id = ch.id;
	t->pub.schema = (const char *)(uintptr_t)ch.schema_id; /* resolved after opening */
	t->name = dup_str(ch.topic);
	t->encoding = dup_str(ch.message_encoding);
	m->topic_of_id[ch.id] = (int32_t)m->ntopics++;
	if (!t->name || !t->encoding)
		return dao_error_set(err, -ENOMEM, "out of memory");
	return 0;
}

static int add_entry(struct dao_mcap *m, uint16_t channel, uint64_t time, uint64_t off,
		     uint32_t chunk, uint64_t pos, struct dao_error *err)
{
	int32_t ti = m->topic_of_id[channel];
	if (ti < 0)
		return dao_error_set(err, -EINVAL, "%s: byte %llu: a message of channel %u, which no "
				     "channel record defines", m->path, (unsigned long long)pos,
				     channel);
	if (m->nmessages >= MCAP_MAX_MESSAGES)
		return dao_error_set(err, -EFBIG, "%s: more than %u messages", m->path,
				     MCAP_MAX_MESSAGES);
	struct topic *t = &m->topics[ti];
	if (t->count == t->cap) {
		uint32_t cap = t->cap ? 2 * t->cap : 64;
		struct entry *p = realloc(t->entries, sizeof(*p) * cap);
		if (!p)
			return dao_error_set(err, -ENOMEM, "out of memory");
		t->entries = p;
		t->cap = cap;
	}
	t->entries[t->count++] = (struct entry){time, off, chunk, (uint32_t)m->nmessages++};
	return 0;
}

static int parse_compression(struct dao_mcap *m, struct dao_mcap_str s, enum compression *c,
			     uint64_t pos, struct dao_error *err)
{
	if (s.len == 0)
		*c = COMP_NONE;
	else if (dao_mcap_str_eq(s, "zstd"))
		*c = COMP_ZSTD;
	else if (dao_mcap_str_eq(s, "lz4"))
		*c = COMP_LZ4;
	else
		return dao_error_set(err, -EINVAL, "%s: byte %llu: a chunk compressed with '%.*s' "
				     "(supported: none, zstd, lz4)", m->path,
				     (unsigned long long)pos, (int)(s.len < 32 ? s.len : 32), s.ptr);
	return 0;
}

static int add_chunk(struct dao_mcap *m, const struct chunk *c, struct dao_error *err)
{
	if (m->nchunks == m->chunks_cap) {
		uint32_t cap = m->chunks_cap ? 2 * m->chunks_cap : 64;
		struct chunk *p = realloc(m->chunks, sizeof(*p) * cap);
		if (!p)
			return dao_error_set(err, -ENOMEM, "out of memory");
		m->chunks = p;
		m->chunks_cap = cap;
	}
	m->chunks[m->nchunks++] = *c;
	return 0;
}

static int check_chunk_size(struct dao_mcap *m, const struct chunk *c, struct dao_error *err)
{
	if (c->size > m->max_chunk)
		return dao_error_set(err, -EFBIG, "%s: byte %llu: a chunk of %llu bytes uncompressed, "
				     "more than the limit of %llu", m->path,
				     (unsigned long long)c->pos, (unsigned long long)c->size,
				     (unsigned long long)m->max_chunk);
	if (c->comp == COMP_NONE && c->data_len != c->size)
		return corrupt(m, c->pos, "an uncompressed chunk whose size is not its length", err);
	/* no codec makes data much larger: past this it is not a chunk of that size */
	if (c->data_len > c->size + (c->size >> 4) + 4096)
		return corrupt(m, c->pos, "a chunk's compressed records are larger than they "
			       "can be", err);
	return 0;
}

/* Decompresses `in` (the chunk's records) into m->buf. */
static int decompress(struct dao_mcap *m, const struct chunk *c, const uint8_t *in,
		      struct dao_error *err)
{
	int r = grow(&m->buf, &m->buf_cap, c->size ? c->size : 1, err);
	if (r < 0)
		return r;
	if (c->comp == COMP_NONE) {
		memcpy(m->buf, in, (size_t)c->size);
	} else if (c->comp == COMP_ZSTD) {
		if (!m->zstd && !(m->zstd = ZSTD_createDCtx()))
			return dao_error_set(err, -ENOMEM, "out of memory");
		size_t got = ZSTD_decompressDCtx(m->zstd, m->buf, (size_t)c->size, in,
						 (size_t)c->data_len);
		if (ZSTD_isError(got) || got != c->size)
			return dao_error_set(err, -EINVAL, "%s: byte %llu: a zstd chunk does not "
					     "decompress to its %llu bytes: %s", m->path,
					     (unsigned long long)c->pos, (unsigned long long)c->size,
					     ZSTD_isError(got) ? ZSTD_getErrorName(got) : "other size");
	} else {
		if (!m->lz4) {
			if (LZ4F_isError(LZ4F_createDecompressionContext(&m->lz4, LZ4F_VERSION)))
				return dao_error_set(err, -ENOMEM, "out of memory");
		} else {
			LZ4F_resetDecompressionContext(m->lz4);
		}
		size_t out_at = 0, in_at = 0;
		for (;;) {
			size_t dst = (size_t)c->size - out_at, src = (size_t)c->data_len - in_at;
			size_t hint = LZ4F_decompress(m->lz4, m->buf + out_at, &dst, in + in_at, &src,
						      NULL);
			if (LZ4F_isError(hint))
				return dao_error_set(err, -EINVAL, "%s: byte %llu: an lz4 chunk is "
						     "damaged: %s", m->path, (unsigned long long)c->pos,
						     LZ4F_getErrorName(hint));
			out_at += dst;
			in_at += src;
			if (hint == 0 || (dst == 0 && src == 0))
				break;
			if (out_at == c->size && in_at == c->data_len)
				break;
		}
		if (out_at != c->size)
			return dao_error_set(err, -EINVAL, "%s: byte %llu: an lz4 chunk decompresses "
					     "to other than its %llu bytes", m->path,
					     (unsigned long long)c->pos, (unsigned long long)c->size);
	}
	if (c->crc && dao_mcap_crc32(0, m->buf, (size_t)c->size) != c->crc)
		return corrupt(m, c->pos, "a chunk's CRC does not match its records", err);
	return 0;
}

/* Chunk `i` into m->buf (cached). */
static int load_chunk(struct dao_mcap *m, uint32_t i, struct dao_error *err)
{
	if (m->cached == (int64_t)i)
		return 0;
	const struct chunk *c = &m->chunks[i];
	int r;
	m->cached = -1;
	if ((r = grow(&m->raw, &m->raw_cap, c->data_len ? c->data_len : 1, err)) < 0 ||
	    (r = read_at(m, c->data_pos, m->raw, (size_t)c->data_len, err)) < 0 ||
	    (r = decompress(m, c, m->raw, err)) < 0)
		return r;
	m->cached = i;
	return 0;
}

/* The records of the chunk in m->buf: schemas, channels and messages indexed. */
static int scan_chunk(struct dao_mcap *m, uint32_t ci, struct dao_error *err)
{
	const struct chunk *c = &m->chunks[ci];
	uint64_t at = 0;
	int r;
	while (at < c->size) {
		if (c->size - at < DAO_MCAP_RECORD_HEADER)
			return corrupt(m, c->pos, "a chunk ends inside a record", err);
		uint8_t op = m->buf[at];
		uint64_t len = dao_mcap_rd64(m->buf + at + 1);
		if (len > c->size - at - DAO_MCAP_RECORD_HEADER)
			return corrupt(m, c->pos, "a record in a chunk runs past the chunk's end", err);
		const uint8_t *content = m->buf + at + DAO_MCAP_RECORD_HEADER;
		if (op == DAO_MCAP_OP_SCHEMA)
			r = add_schema(m, content, len, c->pos, err);
		else if (op == DAO_MCAP_OP_CHANNEL)
			r = add_channel(m, content, len, c->pos, err);
		else if (op == DAO_MCAP_OP_MESSAGE) {
			if (len < DAO_MCAP_MESSAGE_FIXED)
				return corrupt(m, c->pos, "a message record in a chunk is too short", err);
			r = add_entry(m, dao_mcap_rd16(content), dao_mcap_rd64(content + 6), at, ci,
				      c->pos, err);
		} else
			r = 0;
		if (r < 0)
			return r;
		at += DAO_MCAP_RECORD_HEADER + len;
	}
	return 0;
}

/* A chunk record's content, in memory: its table entry. */
static int chunk_from_record(struct dao_mcap *m, const uint8_t *content, uint64_t len,
			     uint64_t pos, struct chunk *c, struct dao_error *err)
{
	struct dao_mcap_chunk ch;
	int r;
	if (dao_mcap_parse_chunk(content, len, &ch) < 0)
		return corrupt(m, pos, "a chunk record is damaged", err);
	memset(c, 0, sizeof(*c));
	c->pos = pos;
	c->data_pos = pos + DAO_MCAP_RECORD_HEADER + (uint64_t)(ch.records - content);
	c->data_len = ch.records_len;
	c->size = ch.uncompressed_size;
	c->crc = ch.uncompressed_crc;
	if ((r = parse_compression(m, ch.compression, &c->comp, pos, err)) < 0)
		return r;
	return check_chunk_size(m, c, err);
}

/*
 * The data section, record by record from the header on: up to Data End,
 * or to the first record cut short by the end of the file (a warning).
 */
static int scan_data(struct dao_mcap *m, uint64_t pos, uint32_t crc, struct dao_error *err)
{
	uint8_t hdr[DAO_MCAP_RECORD_HEADER];
	int r;
	m->indexed = 0;
	for (;;) {
		if (m->size - pos < DAO_MCAP_RECORD_HEADER) {
			snprintf(m->warning, sizeof(m->warning),
				 "the MCAP file is cut short (no Data End record): read up to byte "
				 "%llu of %llu", (unsigned long long)pos, (unsigned long long)m->size);
			break;
		}
		if ((r = read_at(m, pos, hdr, sizeof hdr, err)) < 0)
			return r;
		uint8_t op = hdr[0];
		uint64_t len = dao_mcap_rd64(hdr + 1);
		if (len > m->size - pos - DAO_MCAP_RECORD_HEADER) {
			snprintf(m->warning, sizeof(m->warning),
				 "the MCAP file is cut short (a record of %llu bytes at byte %llu runs "
				 "past its end): read up to there", (unsigned long long)len,
				 (unsigned long long)pos);
			break;
		}
		if (op == DAO_MCAP_OP_FOOTER)
			break;
		if (len > m->max_chunk + 4096)
			return dao_error_set(err, -EFBIG, "%s: byte %llu: a record of %llu bytes, more "
					     "than the limit of %llu", m->path,
					     (unsigned long long)pos, (unsigned long long)len,
					     (unsigned long long)m->max_chunk);
		/* the message data itself is not needed, but the CRC covers it */
		if ((r = grow(&m->raw, &m->raw_cap, len + 1, err)) < 0 ||
		    (r = read_at(m, pos + DAO_MCAP_RECORD_HEADER, m->raw, (size_t)len, err)) < 0)
			return r;
		if (op == DAO_MCAP_OP_DATA_END) {
			if (len < DAO_MCAP_DATA_END_CONTENT)
				return corrupt(m, pos, "the Data End record is too short", err);
			uint32_t want = dao_mcap_rd32(m->raw);
			if (want && want != crc)
				return corrupt(m, pos, "the data section's CRC does not match", err);
			break;
		}
		crc = dao_mcap_crc32(crc, hdr, sizeof hdr);
		crc = dao_mcap_crc32(crc, m->raw, (size_t)len);
		if (op == DAO_MCAP_OP_SCHEMA)
			r = add_schema(m, m->raw, len, pos, err);
		else if (op == DAO_MCAP_OP_CHANNEL)
			r = add_channel(m, m->raw, len, pos, err);
		else if (op == DAO_MCAP_OP_MESSAGE) {
			if (len < DAO_MCAP_MESSAGE_FIXED)
				return corrupt(m, pos, "a message record is too short", err);
			r = add_entry(m, dao_mcap_rd16(m->raw), dao_mcap_rd64(m->raw + 6), pos,
				      NO_CHUNK, pos, err);
		} else if (op == DAO_MCAP_OP_CHUNK) {
			struct chunk c;
			if ((r = chunk_from_record(m, m->raw, len, pos, &c, err)) < 0 ||
			    (r = add_chunk(m, &c, err)) < 0)
				return r;
			m->cached = -1;
			const uint8_t *in = m->raw + (c.data_pos - pos - DAO_MCAP_RECORD_HEADER);
			if ((r = decompress(m, &c, in, err)) < 0)
				return r;
			m->cached = m->nchunks - 1;
			r = scan_chunk(m, m->nchunks - 1, err);
		} else
			r = 0;
		if (r < 0)
			return r;
		pos += DAO_MCAP_RECORD_HEADER + len;
	}
	return 0;
}

/* The message indexes of chunk ci (after it in the file, in `block`), or its records. */
static int index_chunk(struct dao_mcap *m, uint32_t ci, const struct dao_mcap_chunk_index *x,
		       struct dao_error *err)
{
	int r;
	if (x->index_offsets_count == 0) {
		/* no message index: read the chunk itself */
		if ((r = load_chunk(m, ci, err)) < 0)
			return r;
		return scan_chunk(m, ci, err);
	}
	uint64_t start = x->chunk_start_offset + x->chunk_length;
	if (x->message_index_length > m->size - start || x->message_index_length > MCAP_MAX_SUMMARY)
		return corrupt(m, x->chunk_start_offset, "a chunk's message indexes run past the end "
			       "of the file", err);
	if ((r = grow(&m->raw, &m->raw_cap, x->message_index_length + 1, err)) < 0 ||
	    (r = read_at(m, start, m->raw, (size_t)x->message_index_length, err)) < 0)
		return r;
	for (uint32_t k = 0; k < x->index_offsets_count; k++) {
		const uint8_t *e = x->index_offsets + 10 * (size_t)k;
		uint16_t channel = dao_mcap_rd16(e);
		uint64_t off = dao_mcap_rd64(e + 2);
		if (off < start || off - start > x->message_index_length ||
		    x->message_index_length - (off - start) < DAO_MCAP_RECORD_HEADER)
			return corrupt(m, x->chunk_start_offset, "a message index offset lies outside "
				       "the chunk's message indexes", err);
		const uint8_t *rec = m->raw + (off - start);
		uint64_t len = dao_mcap_rd64(rec + 1);
		struct dao_mcap_message_index mi;
		if (rec[0] != DAO_MCAP_OP_MESSAGE_INDEX ||
		    len > x->message_index_length - (off - start) - DAO_MCAP_RECORD_HEADER ||
		    dao_mcap_parse_message_index(rec + DAO_MCAP_RECORD_HEADER, len, &mi) < 0 ||
		    mi.channel_id != channel)
			return corrupt(m, off, "a message index record is damaged", err);
		for (uint32_t j = 0; j < mi.count; j++) {
			const uint8_t *p = mi.entries + 16 * (size_t)j;
			uint64_t moff = dao_mcap_rd64(p + 8);
			if (moff >= m->chunks[ci].size)
				return corrupt(m, off, "a message index entry points past its chunk", err);
			if ((r = add_entry(m, channel, dao_mcap_rd64(p), moff, ci, off, err)) < 0)
				return r;
		}
	}
	return 0;
}

/*
 * One chunk index record of the summary (content c, len bytes, at pos): the
 * chunk it points at checked against it (place, size, compression, limits)
 * and its messages indexed.  summary_start bounds the data section.
 */
static int summary_chunk_index(struct dao_mcap *m, uint64_t summary_start, const uint8_t *c,
			       uint64_t len, uint64_t pos, struct dao_error *err)
{
	struct dao_mcap_chunk_index x;
	struct chunk ch = {0};
	int r;
	if (dao_mcap_parse_chunk_index(c, len, &x) < 0)
		return corrupt(m, pos, "a chunk index record is damaged", err);
	/* the chunk record: opcode, length, fixed fields, compression, records */
	uint64_t head = DAO_MCAP_RECORD_HEADER + DAO_MCAP_CHUNK_FIXED + 4 +
			(uint64_t)x.compression.len + 8;
	if (x.chunk_start_offset < DAO_MCAP_MAGIC_LEN || x.chunk_start_offset > summary_start ||
	    x.chunk_length > summary_start - x.chunk_start_offset ||
	    x.chunk_length != head + x.compressed_size)
		return corrupt(m, pos, "a chunk index points outside the data section or at a "
			       "chunk of another size", err);
	ch.pos = x.chunk_start_offset;
	ch.data_pos = ch.pos + head;
	ch.data_len = x.compressed_size;
	ch.size = x.uncompressed_size;
	uint8_t h[DAO_MCAP_RECORD_HEADER + DAO_MCAP_CHUNK_FIXED];
	if ((r = parse_compression(m, x.compression, &ch.comp, pos, err)) < 0 ||
	    (r = check_chunk_size(m, &ch, err)) < 0 ||
	    (r = read_at(m, ch.pos, h, sizeof h, err)) < 0)
		return r;
	if (h[0] != DAO_MCAP_OP_CHUNK ||
	    dao_mcap_rd64(h + 1) != x.chunk_length - DAO_MCAP_RECORD_HEADER ||
	    dao_mcap_rd64(h + DAO_MCAP_RECORD_HEADER + 16) != ch.size)
		return corrupt(m, ch.pos, "a chunk index points at no chunk of its size", err);
	ch.crc = dao_mcap_rd32(h + DAO_MCAP_RECORD_HEADER + 24);
	if ((r = add_chunk(m, &ch, err)) < 0)
		return r;
	return index_chunk(m, m->nchunks - 1, &x, err);
}

/*
 * The summary section, when the footer has one: its schemas, channels and
 * chunk indexes.  1 if it indexes every message (chunk indexes present), 0
 * if the data section must be scanned.
 */
static int read_summary(struct dao_mcap *m, struct dao_error *err)
{
	uint8_t tail[DAO_MCAP_FOOTER_RECORD + DAO_MCAP_MAGIC_LEN];
	int r;
	if (m->size < 2 * DAO_MCAP_MAGIC_LEN + DAO_MCAP_FOOTER_RECORD)
		return 0;
	uint64_t fpos = m->size - sizeof tail;
	if ((r = read_at(m, fpos, tail, sizeof tail, err)) < 0)
		return r;
	struct dao_mcap_footer f;
	if (memcmp(tail + DAO_MCAP_FOOTER_RECORD, DAO_MCAP_MAGIC, DAO_MCAP_MAGIC_LEN) ||
	    tail[0] != DAO_MCAP_OP_FOOTER || dao_mcap_rd64(tail + 1) != DAO_MCAP_FOOTER_CONTENT)
		return 0; /* cut short, or still being written */
	dao_mcap_parse_footer(tail + DAO_MCAP_RECORD_HEADER, DAO_MCAP_FOOTER_CONTENT, &f);
	if (f.summary_start == 0)
		return 0;
	if (f.summary_start < DAO_MCAP_MAGIC_LEN || f.summary_start > fpos)
		return corrupt(m, fpos, "the footer's summary start lies outside the file", err);
	uint64_t slen = fpos - f.summary_start;
	if (slen > MCAP_MAX_SUMMARY)
		return dao_error_set(err, -EFBIG, "%s: a summary of %llu bytes, more than the limit "
				     "of %u", m->path, (unsigned long long)slen, MCAP_MAX_SUMMARY);
	uint8_t *s = malloc(slen + 1);
	if (!s)
		return dao_error_set(err, -ENOMEM, "out of memory");
	if ((r = read_at(m, f.summary_start, s, (size_t)slen, err)) < 0)
		goto out;
	if (f.summary_crc) {
		uint32_t crc = dao_mcap_crc32(0, s, (size_t)slen);
		crc = dao_mcap_crc32(crc, tail, DAO_MCAP_RECORD_HEADER + 16);
		if (crc != f.summary_crc) {
			r = corrupt(m, f.summary_start, "the summary's CRC does not match", err);
			goto out;
		}
	}
	/* schemas and channels first: chunk indexes name channels */
	uint32_t nindex = 0;
	for (int pass = 0; pass < 2; pass++) {
		uint64_t at = 0;
		while (at < slen) {
			uint64_t pos = f.summary_start + at;
			if (slen - at < DAO_MCAP_RECORD_HEADER) {
				r = corrupt(m, pos, "the summary ends inside a record", err);
				goto out;
			}
			uint8_t op = s[at];
			uint64_t len = dao_mcap_rd64(s + at + 1);
			if (len > slen - at - DAO_MCAP_RECORD_HEADER) {
				r = corrupt(m, pos, "a summary record runs past the footer", err);
				goto out;
			}
			const uint8_t *c = s + at + DAO_MCAP_RECORD_HEADER;
			r = 0;
			if (pass == 0 && op == DAO_MCAP_OP_SCHEMA)
				r = add_schema(m, c, len, pos, err);
			else if (pass == 0 && op == DAO_MCAP_OP_CHANNEL)
				r = add_channel(m, c, len, pos, err);
			else if (pass == 1 && op == DAO_MCAP_OP_CHUNK_INDEX) {
				r = summary_chunk_index(m, f.summary_start, c, len, pos, err);
				nindex += r >= 0;
			}
			if (r < 0)
				goto out;
			at += DAO_MCAP_RECORD_HEADER + len;
		}
	}
	r = nindex > 0 && m->ntopics > 0;
out:
	free(s);
	return r;
}

static int cmp_entry(const void *a, const void *b)
{
	const struct entry *x = a, *y = b;
	if (x->time != y->time)
		return x->time < y->time ? -1 : 1;
	return x->order < y->order ? -1 : x->order > y->order;
}

static void free_index(struct dao_mcap *m)
{
	for (uint32_t i = 0; i < m->ntopics; i++) {
		free(m->topics[i].name);
		free(m->topics[i].encoding);
		free(m->topics[i].entries);
	}
	free(m->topics);
	for (uint32_t i = 0; i < m->nschemas; i++) {
		free(m->schemas[i].name);
		free(m->schemas[i].encoding);
	}
	free(m->schemas);
	free(m->chunks);
	m->topics = NULL;
	m->schemas = NULL;
	m->chunks = NULL;
	m->ntopics = m->nschemas = m->nchunks = m->chunks_cap = 0;
	m->nmessages = 0;
	memset(m->topic_of_id, 0xff, 65536 * sizeof(int32_t));
}

int dao_mcap_open(const char *path, uint64_t max_chunk, struct dao_mcap **out,
		  struct dao_error *err)
{
	struct dao_mcap *m = calloc(1, sizeof(*m));
	int r;
	*out = NULL;
	if (m)
		m->fd = -1;
	if (!m || !(m->path = strdup(path)) ||
	    !(m->topic_of_id = malloc(65536 * sizeof(int32_t)))) {
		r = dao_error_set(err, -ENOMEM, "out of memory");
		goto fail;
	}
	memset(m->topic_of_id, 0xff, 65536 * sizeof(int32_t));
	m->max_chunk = max_chunk;
	m->cached = -1;
	m->fd = -1;
	m->fd = open(path, O_RDONLY | O_CLOEXEC);
	if (m->fd < 0) {
		r = dao_error_set(err, errno == EACCES ? -EACCES : -ENOENT, "%s: %s", path,
				  strerror(errno));
		goto fail;
	}
	struct stat st;
	if (fstat(m->fd, &st) < 0 || !S_ISREG(st.st_mode)) {
		r = dao_error_set(err, -EINVAL, "%s: not a regular file", path);
		goto fail;
	}
	m->size = (uint64_t)st.st_size;
	uint8_t head[DAO_MCAP_MAGIC_LEN + DAO_MCAP_RECORD_HEADER];
	if (m->size < sizeof head || read_at(m, 0, head, sizeof head, err) < 0 ||
	    memcmp(head, DAO_MCAP_MAGIC, DAO_MCAP_MAGIC_LEN)) {
		r = dao_error_set(err, -EINVAL, "%s: not an MCAP file (no MCAP magic)", path);
		goto fail;
	}
	if (head[DAO_MCAP_MAGIC_LEN] != DAO_MCAP_OP_HEADER) {
		r = corrupt(m, DAO_MCAP_MAGIC_LEN, "the first record is not the MCAP header", err);
		goto fail;
	}
	if ((r = read_summary(m, err)) < 0)
		goto fail;
	m->indexed = r;
	if (!m->indexed) {
		free_index(m); /* what a summary without chunk indexes gave is found again */
		uint32_t crc = dao_mcap_crc32(0, DAO_MCAP_MAGIC, DAO_MCAP_MAGIC_LEN);
		if ((r = scan_data(m, DAO_MCAP_MAGIC_LEN, crc, err)) < 0)
			goto fail;
		if (m->nmessages == 0 && m->warning[0]) {
			r = dao_error_set(err, -EINVAL, "%s: %s, and holds no complete message", path,
					  m->warning);
			goto fail;
		}
	}
	for (uint32_t i = 0; i < m->ntopics; i++) {
		struct topic *t = &m->topics[i];
		uint16_t sid = (uint16_t)(uintptr_t)t->pub.schema;
		t->pub.schema = "";
		t->pub.schema_encoding = "";
		for (uint32_t k = 0; sid && k < m->nschemas; k++)
			if (m->schemas[k].id == sid) {
				t->pub.schema = m->schemas[k].name;
				t->pub.schema_encoding = m->schemas[k].encoding;
			}
		t->pub.name = t->name;
		t->pub.encoding = t->encoding;
		t->pub.message_count = t->count;
		if (t->count > 1)
			qsort(t->entries, t->count, sizeof(*t->entries), cmp_entry);
	}
	*out = m;
	return 0;
fail:
	dao_mcap_close(m);
	return r;
}

void dao_mcap_close(struct dao_mcap *m)
{
	if (!m)
		return;
	if (m->topic_of_id)
		free_index(m);
	if (m->fd >= 0)
		close(m->fd);
	ZSTD_freeDCtx(m->zstd);
	if (m->lz4)
		LZ4F_freeDecompressionContext(m->lz4);
	free(m->topic_of_id);
	free(m->raw);
	free(m->buf);
	free(m->path);
	free(m);
}

const char *dao_mcap_path(const struct dao_mcap *m)
{
	return m->path;
}

const char *dao_mcap_warning(const struct dao_mcap *m)
{
	return m->warning[0] ? m->warning : NULL;
}

int dao_mcap_indexed(const struct dao_mcap *m)
{
	return m->indexed;
}

uint32_t dao_mcap_topic_count(const struct dao_mcap *m)
{
	return m->ntopics;
}

const struct dao_mcap_topic *dao_mcap_topic(const struct dao_mcap *m, uint32_t i)
{
	return i < m->ntopics ? &m->topics[i].pub : NULL;
}

int dao_mcap_find_topic(const struct dao_mcap *m, const char *name)
{
	for (uint32_t i = 0; i < m->ntopics; i++)
		if (!strcmp(m->topics[i].name, name))
			return (int)i;
	return -1;
}

uint64_t dao_mcap_message_time(const struct dao_mcap *m, uint32_t topic, uint32_t i)
{
	if (topic >= m->ntopics || i >= m->topics[topic].count)
		return 0;
	return m->topics[topic].entries[i].time;
}

int dao_mcap_read_message(struct dao_mcap *m, uint32_t topic, uint32_t i, const uint8_t **data,
			  uint64_t *len, uint64_t *log_time, struct dao_error *err)
{
	if (topic >= m->ntopics || i >= m->topics[topic].count)
		return dao_error_set(err, -EINVAL, "%s: no message %u of topic %u", m->path, i, topic);
	const struct topic *t = &m->topics[topic];
	const struct entry *e = &t->entries[i];
	const uint8_t *rec;
	uint64_t rlen, where;
	int r;
	if (e->chunk != NO_CHUNK) {
		if ((r = load_chunk(m, e->chunk, err)) < 0)
			return r;
		const struct chunk *c = &m->chunks[e->chunk];
		where = c->pos;
		if (e->off > c->size || c->size - e->off < DAO_MCAP_RECORD_HEADER)
			return corrupt(m, where, "a message lies past its chunk's end", err);
		rec = m->buf + e->off;
		rlen = dao_mcap_rd64(rec + 1);
		if (rlen > c->size - e->off - DAO_MCAP_RECORD_HEADER)
			return corrupt(m, where, "a message runs past its chunk's end", err);
	} else {
		uint8_t h[DAO_MCAP_RECORD_HEADER];
		where = e->off;
		if ((r = read_at(m, e->off, h, sizeof h, err)) < 0)
			return r;
		rlen = dao_mcap_rd64(h + 1);
		if (rlen > m->max_chunk + 4096)
			return corrupt(m, where, "a message larger than the limit", err);
		if ((r = grow(&m->raw, &m->raw_cap, DAO_MCAP_RECORD_HEADER + rlen, err)) < 0 ||
		    (r = read_at(m, e->off, m->raw, (size_t)(DAO_MCAP_RECORD_HEADER + rlen), err)) < 0)
			return r;
		rec = m->raw;
	}
	struct dao_mcap_message msg;
	if (rec[0] != DAO_MCAP_OP_MESSAGE ||
	    dao_mcap_parse_message(rec + DAO_MCAP_RECORD_HEADER, rlen, &msg) < 0 ||
	    msg.channel_id != t->id)
		return corrupt(m, where, "an index points at no message of its channel", err);
	*data = msg.data;
	*len = msg.data_len;
	if (log_time)
		*log_time = msg.log_time;
	return 0;
}
