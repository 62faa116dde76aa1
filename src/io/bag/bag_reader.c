/* SPDX-License-Identifier: MIT */
/*
 * ROS bag 2.0 reader (see bag_reader.h).  Layout of the file:
 *
 *   "#ROSBAG V2.0\n", then records: header_len (u32), header, data_len
 *   (u32), data.  A header is a list of fields: field_len (u32) then
 *   "name=value" (binary values little-endian).  The field "op" (u8) names
 *   the record: 0x03 bag header (index_pos u64, conn_count u32,
 *   chunk_count u32), 0x05 chunk (compression "none"/"bz2"/"lz4", size u32
 *   = uncompressed data size; the data holds connection and message
 *   records), 0x04 index data after each chunk (ver u32 = 1, conn u32,
 *   count u32; data: count x (time u64 as sec u32 + nsec u32, offset u32
 *   into the uncompressed chunk)), 0x07 connection (conn u32, topic; the
 *   data is a header with "type", "md5sum", ...), 0x06 chunk info (ver u32,
 *   chunk_pos u64, start_time, end_time, count u32), 0x02 message data
 *   (conn u32, time u64).  At index_pos come every connection record, then
 *   every chunk info record.
 */
#include "bag/bag_reader.h"

#include <depthao/output_file.h>

#include <bzlib.h>
#include <errno.h>
#include <fcntl.h>
#include <lz4frame.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error_internal.h"

#define BAG_MAGIC "#ROSBAG V2.0\n"
#define BAG_MAGIC_LEN 13
/* Record headers are a few fields; a connection's data carries the message definition. */
#define BAG_MAX_HEADER (1u << 20)
#define BAG_MAX_CONN_DATA (4u << 20)
/* Recorders make one connection per topic and publisher: a few hundred at most. */
#define BAG_MAX_CONNS 4096

enum {
	OP_MSG_DATA = 0x02,
	OP_BAG_HEADER = 0x03,
	OP_INDEX_DATA = 0x04,
	OP_CHUNK = 0x05,
	OP_CHUNK_INFO = 0x06,
	OP_CONNECTION = 0x07,
};

enum compression { COMP_NONE, COMP_BZ2, COMP_LZ4 };

struct chunk {
	uint64_t pos;      /* of the chunk record */
	uint64_t data_pos; /* of its (compressed) data */
	uint32_t data_len;
	uint32_t size;     /* uncompressed */
	enum compression comp;
};

struct entry {
	uint64_t time_ns;
	uint32_t chunk;    /* index into chunks */
	uint32_t offset;   /* of the message record in the uncompressed chunk */
	uint32_t conn;
};

struct conn {
	uint32_t id;
	uint32_t topic;    /* index into topics */
};

struct topic {
	struct dao_bag_topic pub;
	char *name, *type;
	struct entry *entries;
	uint32_t count, cap;
};

struct dao_bag {
	char *path;
	int fd;
	uint64_t size;
	uint64_t max_chunk;
	struct conn *conns; /* sorted by id */
	uint32_t nconns;
	uint64_t index_pos;  /* 0 for an unindexed bag */
	uint64_t scanned;    /* messages found by scanning chunks */
	struct topic *topics;
	uint32_t ntopics;
	struct chunk *chunks;
	uint32_t nchunks;
	uint8_t *raw;      /* compressed data of the cached chunk */
	size_t raw_cap;
	uint8_t *buf;      /* uncompressed data of the cached chunk */
	size_t buf_cap;
	int64_t cached;    /* chunk in buf, -1 for none */
	LZ4F_dctx *lz4;    /* made at the first lz4 chunk, reset for each next one */
	char warning[256]; /* an unindexed bag: how far it was read */
};

/* One parsed record header: the fields this reader uses. */
struct rec {
	uint64_t pos;      /* of the record */
	uint64_t data_pos;
	uint32_t data_len;
	int op;            /* -1 if absent */
	uint32_t conn, ver, count, size, conn_count, chunk_count;
	uint64_t index_pos, chunk_pos, time_ns;
	int has_conn, has_ver, has_count, has_size, has_index_pos, has_chunk_pos, has_time;
	char compression[8];
	char topic[256];
	int has_topic;
};

static uint32_t rd32(const uint8_t *p)
{
	return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static uint64_t rd64(const uint8_t *p)
{
	return (uint64_t)rd32(p) | (uint64_t)rd32(p + 4) << 32;
}

/* ROS time (sec u32, nsec u32) in ns. */
static uint64_t rd_time(const uint8_t *p)
{
	return (uint64_t)rd32(p) * 1000000000u + rd32(p + 4);
}

static int read_at(struct dao_bag *b, uint64_t pos, void *dst, size_t n, struct dao_error *err)
{
	uint8_t *d = dst;
	while (n) {
		ssize_t r = pread(b->fd, d, n, (off_t)pos);
		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0)
			return dao_error_set(err, -EIO, "%s: read error at byte %llu: %s", b->path,
					     (unsigned long long)pos, strerror(errno));
		if (r == 0)
			return dao_error_set(err, -EINVAL, "%s: byte %llu: the file ends early",
					     b->path, (unsigned long long)pos);
		d += r;
		pos += (uint64_t)r;
		n -= (size_t)r;
	}
	return 0;
}

/* A field's value of exactly `n` bytes. */
static int fixed(const uint8_t *v, uint32_t vlen, uint32_t n)
{
	return v && vlen == n;
}

/*
 * Parses the header fields at h[0..len) into r.  `where` is the file
 * position of the header, for messages.
 */
static int parse_header(const struct dao_bag *b, const uint8_t *h, uint32_t len, uint64_t where,
			struct rec *r, struct dao_error *err)
{
	uint32_t at = 0;
	while (at < len) {
		if (len - at < 4)
			return dao_error_set(err, -EINVAL, "%s: byte %llu: a record header field is cut short",
					     b->path, (unsigned long long)(where + at));
		uint32_t flen = rd32(h + at);
		at += 4;
		if (flen > len - at)
			return dao_error_set(err, -EINVAL,
					     "%s: byte %llu: a record header field of %u bytes runs past "
					     "its header",
					     b->path, (unsigned long long)(where + at - 4), flen);
		const uint8_t *f = h + at;
		const uint8_t *eq = memchr(f, '=', flen);
		if (!eq)
			return dao_error_set(err, -EINVAL,
					     "%s: byte %llu: a record header field has no '='", b->path,
					     (unsigned long long)(where + at));
		size_t nlen = (size_t)(eq - f);
		const uint8_t *v = eq + 1;
		uint32_t vlen = flen - (uint32_t)nlen - 1;
		int ok = 1;
#define NAME(s) (nlen == sizeof(s) - 1 && !memcmp(f, s, nlen))
		if (NAME("op")) {
			ok = fixed(v, vlen, 1);
			if (ok)
				r->op = v[0];
		} else if (NAME("conn")) {
			if ((ok = fixed(v, vlen, 4)))
				r->conn = rd32(v), r->has_conn = 1;
		} else if (NAME("ver")) {
			if ((ok = fixed(v, vlen, 4)))
				r->ver = rd32(v), r->has_ver = 1;
		} else if (NAME("count")) {
			if ((ok = fixed(v, vlen, 4)))
				r->count = rd32(v), r->has_count = 1;
		} else if (NAME("size")) {
			if ((ok = fixed(v, vlen, 4)))
				r->size = rd32(v), r->has_size = 1;
		} else if (NAME("conn_count")) {
			if ((ok = fixed(v, vlen, 4)))
				r->conn_count = rd32(v);
		} else if (NAME("chunk_count")) {
			if ((ok = fixed(v, vlen, 4)))
				r->chunk_count = rd32(v);
		} else if (NAME("index_pos")) {
			if ((ok = fixed(v, vlen, 8)))
				r->index_pos = rd64(v), r->has_index_pos = 1;
		} else if (NAME("chunk_pos")) {
			if ((ok = fixed(v, vlen, 8)))
				r->chunk_pos = rd64(v), r->has_chunk_pos = 1;
		} else if (NAME("time")) {
			if ((ok = fixed(v, vlen, 8)))
				r->time_ns = rd_time(v), r->has_time = 1;
		} else if (NAME("compression")) {
			ok = vlen < sizeof(r->compression);
			if (ok) {
				memcpy(r->compression, v, vlen);
				r->compression[vlen] = 0;
			}
		} else if (NAME("topic")) {
			ok = vlen < sizeof(r->topic) && !memchr(v, 0, vlen);
			if (ok) {
				memcpy(r->topic, v, vlen);
				r->topic[vlen] = 0;
				r->has_topic = 1;
			}
		}
#undef NAME
		if (!ok)
			return dao_error_set(err, -EINVAL,
					     "%s: byte %llu: the record header field '%.*s' has a bad "
					     "size (%u bytes)",
					     b->path, (unsigned long long)(where + at), (int)nlen,
					     (const char *)f, vlen);
		at += flen;
	}
	return 0;
}

/* Reads the record at `pos` of the file: its header parsed, its data located (not read). */
static int read_record(struct dao_bag *b, uint64_t pos, struct rec *r, struct dao_error *err)
{
	uint8_t len4[4];
	int ret;
	memset(r, 0, sizeof(*r));
	r->op = -1;
	r->pos = pos;
	if (pos > b->size || b->size - pos < 8)
		return dao_error_set(err, -EINVAL, "%s: byte %llu: a record is cut short (the file "
				     "ends at byte %llu)", b->path, (unsigned long long)pos,
				     (unsigned long long)b->size);
	if ((ret = read_at(b, pos, len4, 4, err)) < 0)
		return ret;
	uint32_t hlen = rd32(len4);
	if (hlen > BAG_MAX_HEADER || hlen > b->size - pos - 8)
		return dao_error_set(err, -EINVAL,
				     "%s: byte %llu: a record header of %u bytes is larger than the "
				     "rest of the file or the limit of %u",
				     b->path, (unsigned long long)pos, hlen, BAG_MAX_HEADER);
	uint8_t *h = malloc(hlen ? hlen : 1);
	if (!h)
		return dao_error_set(err, -ENOMEM, "out of memory reading %s", b->path);
	if ((ret = read_at(b, pos + 4, h, hlen, err)) == 0)
		ret = parse_header(b, h, hlen, pos + 4, r, err);
	free(h);
	if (ret < 0)
		return ret;
	if ((ret = read_at(b, pos + 4 + hlen, len4, 4, err)) < 0)
		return ret;
	r->data_len = rd32(len4);
	r->data_pos = pos + 8 + hlen;
	if (r->data_len > b->size - r->data_pos)
		return dao_error_set(err, -EINVAL,
				     "%s: byte %llu: a record's data of %u bytes runs past the end of "
				     "the file",
				     b->path, (unsigned long long)pos, r->data_len);
	if (r->op < 0)
		return dao_error_set(err, -EINVAL, "%s: byte %llu: a record without an 'op' field",
				     b->path, (unsigned long long)pos);
	return 0;
}

static int missing(const struct dao_bag *b, const struct rec *r, const char *what,
		   struct dao_error *err)
{
	return dao_error_set(err, -EINVAL, "%s: byte %llu: a record of op 0x%02x lacks '%s'",
			     b->path, (unsigned long long)r->pos, r->op, what);
}

/* The first of b->conns whose id is >= id (binary search). */
static uint32_t conn_slot(const struct dao_bag *b, uint32_t id)
{
	uint32_t lo = 0, hi = b->nconns;
	while (lo < hi) {
		uint32_t mid = lo + (hi - lo) / 2;
		if (b->conns[mid].id < id)
			lo = mid + 1;
		else
			hi = mid;
	}
	return lo;
}

static struct conn *find_conn(struct dao_bag *b, uint32_t id)
{
	uint32_t i = conn_slot(b, id);
	return i < b->nconns && b->conns[i].id == id ? &b->conns[i] : NULL;
}

/*
 * The "type=" field of a connection record's data d[0..len) (a header);
 * `where` is the file position of the data, for messages.
 */
static int conn_type_of(struct dao_bag *b, const uint8_t *d, uint32_t len, uint64_t where,
			char **type, struct dao_error *err)
{
	for (uint32_t at = 0; len - at >= 4;) {
		uint32_t flen = rd32(d + at);
		at += 4;
		if (flen > len - at)
			return dao_error_set(err, -EINVAL,
					     "%s: byte %llu: a connection header field runs past its "
					     "record", b->path, (unsigned long long)(where + at - 4));
		if (flen > 5 && !memcmp(d + at, "type=", 5) && !memchr(d + at + 5, 0, flen - 5)) {
			*type = strndup((const char *)d + at + 5, flen - 5);
			return *type ? 0 : dao_error_set(err, -ENOMEM, "out of memory");
		}
		at += flen;
	}
	return dao_error_set(err, -EINVAL, "%s: byte %llu: a connection record without a type",
			     b->path, (unsigned long long)where);
}

/* The same for a connection record in the file. */
static int conn_type(struct dao_bag *b, const struct rec *r, char **type, struct dao_error *err)
{
	if (r->data_len > BAG_MAX_CONN_DATA)
		return dao_error_set(err, -EINVAL, "%s: byte %llu: a connection record of %u bytes",
				     b->path, (unsigned long long)r->pos, r->data_len);
	uint8_t *d = malloc(r->data_len ? r->data_len : 1);
	int ret;
	if (!d)
		return dao_error_set(err, -ENOMEM, "out of memory reading %s", b->path);
	if ((ret = read_at(b, r->data_pos, d, r->data_len, err)) == 0)
		ret = conn_type_of(b, d, r->data_len, r->data_pos, type, err);
	free(d);
	return ret;
}

/* Adds connection r->conn of topic r->topic and `type` (taken over, freed on failure). */
static int add_conn_typed(struct dao_bag *b, const struct rec *r, char *type,
			  struct dao_error *err)
{
	uint32_t t;
	if (b->nconns >= BAG_MAX_CONNS) {
		free(type);
		return dao_error_set(err, -EINVAL, "%s: byte %llu: more than %u connections",
				     b->path, (unsigned long long)r->pos, BAG_MAX_CONNS);
	}
	for (t = 0; t < b->ntopics; t++)
		if (!strcmp(b->topics[t].name, r->topic) && !strcmp(b->topics[t].type, type))
			break;
	if (t == b->ntopics) {
		struct topic *nt = realloc(b->topics, (b->ntopics + 1) * sizeof(*nt));
		if (!nt)
			goto oom;
		b->topics = nt;
		memset(&nt[t], 0, sizeof(*nt));
		if (!(nt[t].name = strdup(r->topic)))
			goto oom;
		nt[t].type = type;
		type = NULL;
		b->ntopics++;
	}
	free(type);
	struct conn *nc = realloc(b->conns, (b->nconns + 1) * sizeof(*nc));
	if (!nc)
		return dao_error_set(err, -ENOMEM, "out of memory reading %s", b->path);
	b->conns = nc;
	uint32_t at = conn_slot(b, r->conn);
	memmove(&nc[at + 1], &nc[at], (b->nconns - at) * sizeof(*nc));
	nc[at].id = r->conn;
	nc[at].topic = t;
	b->nconns++;
	return 0;
oom:
	free(type);
	return dao_error_set(err, -ENOMEM, "out of memory reading %s", b->path);
}

static int check_conn(struct dao_bag *b, const struct rec *r, struct dao_error *err)
{
	if (!r->has_conn)
		return missing(b, r, "conn", err);
	if (!r->has_topic)
		return missing(b, r, "topic", err);
	return 0;
}

/* A connection record of the index (each is defined once there). */
static int add_connection(struct dao_bag *b, const struct rec *r, struct dao_error *err)
{
	char *type = NULL;
	int ret;
	if ((ret = check_conn(b, r, err)) < 0)
		return ret;
	if (find_conn(b, r->conn))
		return dao_error_set(err, -EINVAL, "%s: byte %llu: connection %u is defined twice",
				     b->path, (unsigned long long)r->pos, r->conn);
	if ((ret = conn_type(b, r, &type, err)) < 0)
		return ret;
	return add_conn_typed(b, r, type, err);
}

/*
 * Appends an entry to the topic of connection `conn` (scanning a chunk).  An
 * index costs 12 bytes of file per message; scanned chunks, decompressed,
 * could name far more: at most a message per 4 bytes of file (or 2^20).
 */
static int add_entry(struct dao_bag *b, uint32_t conn, uint64_t time_ns, uint32_t chunk,
		     uint32_t offset, uint64_t where, struct dao_error *err)
{
	uint64_t cap_msgs = b->size / 4 > (1u << 20) ? b->size / 4 : (1u << 20);
	if (++b->scanned > cap_msgs)
		return dao_error_set(err, -EINVAL,
				     "%s: byte %llu: more than %llu messages in the chunks of a %llu "
				     "byte file", b->path, (unsigned long long)where,
				     (unsigned long long)cap_msgs, (unsigned long long)b->size);
	struct conn *cn = find_conn(b, conn);
	if (!cn)
		return dao_error_set(err, -EINVAL,
				     "%s: byte %llu: a message of connection %u, which the bag does "
				     "not define (before it)", b->path, (unsigned long long)where, conn);
	struct topic *t = &b->topics[cn->topic];
	if (t->count == UINT32_MAX)
		return dao_error_set(err, -EINVAL, "%s: too many messages", b->path);
	if (t->count == t->cap) {
		uint32_t cap = t->cap ? (t->cap > UINT32_MAX / 2 ? UINT32_MAX : t->cap * 2) : 64;
		struct entry *ne = realloc(t->entries, (size_t)cap * sizeof(*ne));
		if (!ne)
			return dao_error_set(err, -ENOMEM, "out of memory reading %s", b->path);
		t->entries = ne;
		t->cap = cap;
	}
	t->entries[t->count++] = (struct entry){time_ns, chunk, offset, conn};
	return 0;
}

/* The chunk record r, checked, appended to b->chunks (its index in *ci). */
static int add_chunk_record(struct dao_bag *b, const struct rec *r, uint32_t *ci,
			    struct dao_error *err)
{
	if (!r->has_size)
		return missing(b, r, "size", err);
	struct chunk c = {r->pos, r->data_pos, r->data_len, r->size, COMP_NONE};
	if (!strcmp(r->compression, "none"))
		c.comp = COMP_NONE;
	else if (!strcmp(r->compression, "bz2"))
		c.comp = COMP_BZ2;
	else if (!strcmp(r->compression, "lz4"))
		c.comp = COMP_LZ4;
	else
		return dao_error_set(err, -EINVAL,
				     "%s: byte %llu: chunk compression '%s' (known: none, bz2, lz4)",
				     b->path, (unsigned long long)r->pos, r->compression);
	if (c.comp == COMP_NONE && c.size != c.data_len)
		return dao_error_set(err, -EINVAL,
				     "%s: byte %llu: an uncompressed chunk of %u bytes says its size "
				     "is %u", b->path, (unsigned long long)r->pos, c.data_len, c.size);
	if (b->nchunks == UINT32_MAX)
		return dao_error_set(err, -EINVAL, "%s: too many chunks", b->path);
	struct chunk *nc = realloc(b->chunks, (b->nchunks + 1) * sizeof(*nc));
	if (!nc)
		return dao_error_set(err, -ENOMEM, "out of memory reading %s", b->path);
	b->chunks = nc;
	*ci = b->nchunks++;
	nc[*ci] = c;
	return 0;
}

static int add_chunk(struct dao_bag *b, const struct rec *info, struct dao_error *err)
{
	struct rec r;
	int ret;
	if (!info->has_chunk_pos)
		return missing(b, info, "chunk_pos", err);
	if (info->has_ver && info->ver != 1)
		return dao_error_set(err, -EINVAL, "%s: byte %llu: chunk info version %u (only 1 is "
				     "known)", b->path, (unsigned long long)info->pos, info->ver);
	if ((ret = read_record(b, info->chunk_pos, &r, err)) < 0)
		return ret;
	if (r.op != OP_CHUNK)
		return dao_error_set(err, -EINVAL,
				     "%s: byte %llu: the chunk info at byte %llu points to a record "
				     "of op 0x%02x, not a chunk",
				     b->path, (unsigned long long)r.pos,
				     (unsigned long long)info->pos, r.op);
	/* chunks in file order, apart, before the index: each index entry is read once */
	uint64_t after = b->nchunks ? b->chunks[b->nchunks - 1].data_pos +
					      b->chunks[b->nchunks - 1].data_len
				    : 0;
	if (r.pos < after || r.data_pos + r.data_len > b->index_pos)
		return dao_error_set(err, -EINVAL,
				     "%s: byte %llu: the chunk info at byte %llu points to a chunk "
				     "that overlaps another one or the index",
				     b->path, (unsigned long long)r.pos,
				     (unsigned long long)info->pos);
	uint32_t ci = 0;
	if ((ret = add_chunk_record(b, &r, &ci, err)) < 0)
		return ret;
	const struct chunk c = b->chunks[ci];

	/* the index data records that follow the chunk */
	uint64_t pos = r.data_pos + r.data_len;
	while (pos < b->size) {
		struct rec x;
		if ((ret = read_record(b, pos, &x, err)) < 0)
			return ret;
		if (x.op != OP_INDEX_DATA)
			break;
		if (!x.has_conn || !x.has_count)
			return missing(b, &x, x.has_conn ? "count" : "conn", err);
		if (x.has_ver && x.ver != 1)
			return dao_error_set(err, -EINVAL, "%s: byte %llu: index data version %u (only "
					     "1 is known)", b->path, (unsigned long long)x.pos, x.ver);
		if ((uint64_t)x.count * 12 != x.data_len)
			return dao_error_set(err, -EINVAL,
					     "%s: byte %llu: index data of %u entries has %u bytes, not "
					     "%llu", b->path, (unsigned long long)x.pos, x.count,
					     x.data_len, (unsigned long long)x.count * 12);
		struct conn *cn = find_conn(b, x.conn);
		if (!cn)
			return dao_error_set(err, -EINVAL,
					     "%s: byte %llu: index data of connection %u, which the bag "
					     "does not define", b->path, (unsigned long long)x.pos,
					     x.conn);
		struct topic *t = &b->topics[cn->topic];
		if (x.count > UINT32_MAX - t->count)
			return dao_error_set(err, -EINVAL, "%s: too many messages", b->path);
		if (t->count + x.count > t->cap) {
			uint32_t cap = t->cap ? t->cap : 64;
			while (cap < t->count + x.count)
				cap = cap > UINT32_MAX / 2 ? t->count + x.count : cap * 2;
			struct entry *ne = realloc(t->entries, (size_t)cap * sizeof(*ne));
			if (!ne)
				return dao_error_set(err, -ENOMEM, "out of memory reading %s", b->path);
			t->entries = ne;
			t->cap = cap;
		}
		uint8_t *d = malloc(x.data_len ? x.data_len : 1);
		if (!d)
			return dao_error_set(err, -ENOMEM, "out of memory reading %s", b->path);
		if ((ret = read_at(b, x.data_pos, d, x.data_len, err)) < 0) {
			free(d);
			return ret;
		}
		for (uint32_t k = 0; k < x.count; k++) {
			const uint8_t *e = d + (size_t)k * 12;
			uint32_t off = rd32(e + 8);
			if (off >= c.size) {
				free(d);
				return dao_error_set(err, -EINVAL,
						     "%s: byte %llu: index entry %u points to offset %u "
						     "of a chunk of %u bytes",
						     b->path, (unsigned long long)x.data_pos, k, off,
						     c.size);
			}
			t->entries[t->count++] = (struct entry){rd_time(e), ci, off, x.conn};
		}
		free(d);
		pos = x.data_pos + x.data_len;
	}
	return 0;
}

static int cmp_entry(const void *pa, const void *pb)
{
	const struct entry *a = pa, *b = pb;
	if (a->time_ns != b->time_ns)
		return a->time_ns < b->time_ns ? -1 : 1;
	if (a->chunk != b->chunk)
		return a->chunk < b->chunk ? -1 : 1;
	return a->offset < b->offset ? -1 : a->offset > b->offset;
}

static int load_chunk(struct dao_bag *b, uint32_t ci, struct dao_error *err);

/*
 * The connection and message records of chunk `ci` (decompressed): what an
 * unindexed bag has instead of its index.  Connections may repeat (a chunk
 * defines those it uses), with the same topic.
 */
static int scan_chunk(struct dao_bag *b, uint32_t ci, struct dao_error *err)
{
	int ret = load_chunk(b, ci, err);
	if (ret < 0)
		return ret;
	const struct chunk *c = &b->chunks[ci];
	const uint8_t *p = b->buf;
	for (uint32_t at = 0; at < c->size;) {
		struct rec r;
		memset(&r, 0, sizeof(r));
		r.op = -1;
		r.pos = c->pos;
		if (c->size - at < 8 || rd32(p + at) > c->size - at - 8)
			return dao_error_set(err, -EINVAL,
					     "%s: byte %llu: the record at offset %u of the chunk runs "
					     "past it", b->path, (unsigned long long)c->pos, at);
		uint32_t hlen = rd32(p + at);
		if ((ret = parse_header(b, p + at + 4, hlen, c->pos, &r, err)) < 0)
			return ret;
		uint32_t dlen = rd32(p + at + 4 + hlen), dpos = at + 8 + hlen;
		if (dlen > c->size - dpos)
			return dao_error_set(err, -EINVAL,
					     "%s: byte %llu: the record at offset %u of the chunk has %u "
					     "bytes of data, more than the chunk holds",
					     b->path, (unsigned long long)c->pos, at, dlen);
		if (r.op == OP_CONNECTION) {
			char *type = NULL;
			if ((ret = check_conn(b, &r, err)) < 0)
				return ret;
			if (!find_conn(b, r.conn)) {
				if ((ret = conn_type_of(b, p + dpos, dlen, c->pos, &type, err)) < 0 ||
				    (ret = add_conn_typed(b, &r, type, err)) < 0)
					return ret;
			}
		} else if (r.op == OP_MSG_DATA) {
			if (!r.has_conn || !r.has_time)
				return missing(b, &r, r.has_conn ? "time" : "conn", err);
			if ((ret = add_entry(b, r.conn, r.time_ns, ci, at, c->pos, err)) < 0)
				return ret;
		} else {
			return dao_error_set(err, -EINVAL,
					     "%s: byte %llu: a record of op 0x%02x inside a chunk",
					     b->path, (unsigned long long)c->pos, r.op);
		}
		at = dpos + dlen;
	}
	return 0;
}

/*
 * A bag without an index (its recording was not finished: the header's
 * index_pos is still 0): its chunks are read one after the other, up to the
 * end or to the first that is cut short or damaged; a warning says how far.
 */
static int scan_unindexed(struct dao_bag *b, uint64_t pos, struct dao_error *err)
{
	struct dao_error why = {0};
	while (pos < b->size) {
		struct rec r;
		uint32_t ci;
		if (read_record(b, pos, &r, &why) < 0)
			break;
		if (r.op == OP_CHUNK) {
			uint32_t before = b->nchunks;
			if (add_chunk_record(b, &r, &ci, &why) < 0)
				break;
			if (scan_chunk(b, ci, &why) < 0) {
				/* drop what the damaged chunk added */
				for (uint32_t t = 0; t < b->ntopics; t++)
					while (b->topics[t].count &&
					       b->topics[t].entries[b->topics[t].count - 1].chunk == ci)
						b->topics[t].count--;
				b->nchunks = before;
				b->cached = -1;
				break;
			}
		} else if (r.op == OP_CONNECTION) {
			char *type = NULL;
			if (check_conn(b, &r, &why) < 0)
				break;
			if (!find_conn(b, r.conn) && (conn_type(b, &r, &type, &why) < 0 ||
						      add_conn_typed(b, &r, type, &why) < 0))
				break;
		} else if (r.op != OP_INDEX_DATA && r.op != OP_CHUNK_INFO) {
			dao_error_set(&why, -EINVAL, "%s: byte %llu: a record of op 0x%02x", b->path,
				      (unsigned long long)r.pos, r.op);
			break;
		}
		pos = r.data_pos + r.data_len;
	}
	if (why.code == -ENOMEM)
		return dao_error_set(err, -ENOMEM, "%s", why.message);
	const char *base = strrchr(b->path, '/'), *stop = strstr(why.message, "byte ");
	if (b->nchunks == 0)
		return dao_error_set(err, -EINVAL,
				     "%s: the bag is not indexed (its recording was not finished) and "
				     "has no complete chunk%s%s", b->path, why.message[0] ? "; " : "",
				     stop ? stop : why.message);
	snprintf(b->warning, sizeof(b->warning),
		 "%.60s is not indexed (its recording was not finished): read %u chunks%s%.90s",
		 base ? base + 1 : b->path, b->nchunks, why.message[0] ? ", up to " : "",
		 stop ? stop : why.message);
	return 0;
}

static int load_index(struct dao_bag *b, struct dao_error *err)
{
	uint8_t magic[BAG_MAGIC_LEN];
	struct rec r;
	int ret;
	if (b->size < BAG_MAGIC_LEN)
		return dao_error_set(err, -EINVAL, "%s: not a ROS bag (%llu bytes)", b->path,
				     (unsigned long long)b->size);
	if ((ret = read_at(b, 0, magic, BAG_MAGIC_LEN, err)) < 0)
		return ret;
	if (memcmp(magic, BAG_MAGIC, BAG_MAGIC_LEN)) {
		if (!memcmp(magic, "#ROSBAG V", 9))
			return dao_error_set(err, -EINVAL,
					     "%s: ROS bag format %.3s; only 2.0 is read ('rosbag "
					     "filter IN OUT True' writes a 2.0 copy)", b->path, (const char *)magic + 9);
		return dao_error_set(err, -EINVAL, "%s: not a ROS bag (no '#ROSBAG V2.0' line)",
				     b->path);
	}
	if ((ret = read_record(b, BAG_MAGIC_LEN, &r, err)) < 0)
		return ret;
	if (r.op != OP_BAG_HEADER)
		return dao_error_set(err, -EINVAL, "%s: byte %d: the first record is op 0x%02x, not "
				     "the bag header", b->path, BAG_MAGIC_LEN, r.op);
	if (!r.has_index_pos)
		return missing(b, &r, "index_pos", err);
	uint32_t want_conns = r.conn_count, want_chunks = r.chunk_count;
	uint64_t first = r.data_pos + r.data_len;
	b->index_pos = r.index_pos;
	if (r.index_pos == 0) {
		if ((ret = scan_unindexed(b, first, err)) < 0)
			return ret;
		goto sort;
	}
	if (r.index_pos < first || r.index_pos >= b->size)
		return dao_error_set(err, -EINVAL,
				     "%s: byte %llu: the index position %llu is outside the file's "
				     "records (%llu..%llu; a truncated copy?)",
				     b->path, (unsigned long long)r.pos,
				     (unsigned long long)r.index_pos, (unsigned long long)first,
				     (unsigned long long)b->size);
	/* connections first, then the chunk infos (each reads its chunk's index) */
	for (int pass = 0; pass < 2; pass++) {
		for (uint64_t pos = r.index_pos; pos < b->size;) {
			struct rec x;
			if ((ret = read_record(b, pos, &x, err)) < 0)
				return ret;
			if (x.op == OP_CONNECTION && pass == 0)
				ret = add_connection(b, &x, err);
			else if (x.op == OP_CHUNK_INFO && pass == 1)
				ret = add_chunk(b, &x, err);
			else if (x.op != OP_CONNECTION && x.op != OP_CHUNK_INFO)
				ret = dao_error_set(err, -EINVAL,
						    "%s: byte %llu: a record of op 0x%02x in the index "
						    "(connections and chunk infos only)",
						    b->path, (unsigned long long)x.pos, x.op);
			if (ret < 0)
				return ret;
			pos = x.data_pos + x.data_len;
		}
	}
	if (b->nconns != want_conns || b->nchunks != want_chunks)
		return dao_error_set(err, -EINVAL,
				     "%s: the index holds %u connections and %u chunks, the bag header "
				     "says %u and %u", b->path, b->nconns, b->nchunks, want_conns,
				     want_chunks);
sort:
	for (uint32_t t = 0; t < b->ntopics; t++) {
		struct topic *tp = &b->topics[t];
		if (tp->count > 1) /* a topic without messages has no array: qsort(NULL) is UB */
			qsort(tp->entries, tp->count, sizeof(*tp->entries), cmp_entry);
		tp->pub = (struct dao_bag_topic){tp->name, tp->type, tp->count};
	}
	return 0;
}

int dao_bag_open(const char *path, uint64_t max_chunk, struct dao_bag **out,
		 struct dao_error *err)
{
	if (!path || !out)
		return dao_error_set(err, -EINVAL, "dao_bag_open: path and out are required");
	*out = NULL;
	struct dao_bag *b = calloc(1, sizeof(*b));
	if (!b || !(b->path = strdup(path))) {
		free(b);
		return dao_error_set(err, -ENOMEM, "out of memory opening %s", path);
	}
	b->cached = -1;
	b->max_chunk = max_chunk;
	b->fd = dao_input_file_open(path, "bag", 0, &b->size, err);
	int ret;
	if (b->fd < 0) {
		ret = b->fd;
		goto fail;
	}
	if ((ret = load_index(b, err)) < 0)
		goto fail;
	*out = b;
	return 0;
fail:
	dao_bag_close(b);
	return ret;
}

void dao_bag_close(struct dao_bag *b)
{
	if (!b)
		return;
	if (b->fd >= 0)
		close(b->fd);
	for (uint32_t t = 0; t < b->ntopics; t++) {
		free(b->topics[t].name);
		free(b->topics[t].type);
		free(b->topics[t].entries);
	}
	free(b->topics);
	free(b->conns);
	free(b->chunks);
	free(b->raw);
	free(b->buf);
	if (b->lz4)
		LZ4F_freeDecompressionContext(b->lz4);
	free(b->path);
	free(b);
}

const char *dao_bag_path(const struct dao_bag *b)
{
	return b->path;
}

const char *dao_bag_warning(const struct dao_bag *b)
{
	return b->warning[0] ? b->warning : NULL;
}

uint32_t dao_bag_topic_count(const struct dao_bag *b)
{
	return b->ntopics;
}

const struct dao_bag_topic *dao_bag_topic(const struct dao_bag *b, uint32_t i)
{
	return i < b->ntopics ? &b->topics[i].pub : NULL;
}

int dao_bag_find_topic(const struct dao_bag *b, const char *name)
{
	for (uint32_t t = 0; t < b->ntopics; t++)
		if (!strcmp(b->topics[t].name, name))
			return (int)t;
	return -1;
}

static int grow(uint8_t **p, size_t *cap, size_t n)
{
	if (n <= *cap)
		return 0;
	uint8_t *q = realloc(*p, n);
	if (!q)
		return -ENOMEM;
	*p = q;
	*cap = n;
	return 0;
}

static int lz4_decompress(struct dao_bag *b, const uint8_t *src, size_t n, uint8_t *dst,
			  size_t size)
{
	if (!b->lz4 && LZ4F_isError(LZ4F_createDecompressionContext(&b->lz4, LZ4F_VERSION))) {
		b->lz4 = NULL;
		return -ENOMEM;
	}
	LZ4F_dctx *dc = b->lz4;
	LZ4F_resetDecompressionContext(dc); /* after an error, or a frame left unfinished */
	size_t in_at = 0, out_at = 0, hint = 1;
	int ret = 0;
	while (hint != 0) {
		size_t in_n = n - in_at, out_n = size - out_at;
		if (in_n == 0) {
			ret = -EINVAL; /* the frame is not complete */
			break;
		}
		hint = LZ4F_decompress(dc, dst + out_at, &out_n, src + in_at, &in_n, NULL);
		if (LZ4F_isError(hint)) {
			ret = -EINVAL;
			break;
		}
		in_at += in_n;
		out_at += out_n;
		if (in_n == 0 && out_n == 0 && hint != 0) {
			ret = -EINVAL; /* no progress: the output is full */
			break;
		}
	}
	return ret == 0 && out_at == size ? 0 : -EINVAL;
}

/* Makes chunk `ci` the cached one, uncompressed in b->buf. */
static int load_chunk(struct dao_bag *b, uint32_t ci, struct dao_error *err)
{
	const struct chunk *c = &b->chunks[ci];
	int ret;
	if (b->cached == (int64_t)ci)
		return 0;
	b->cached = -1;
	if (c->size > b->max_chunk)
		return dao_error_set(err, -EINVAL,
				     "%s: byte %llu: a chunk of %u bytes is larger than the limit of "
				     "%llu (from the pixel limit)",
				     b->path, (unsigned long long)c->pos, c->size,
				     (unsigned long long)b->max_chunk);
	/* compressed data much larger than the output is not what these codecs write */
	if (c->comp != COMP_NONE && c->data_len > (uint64_t)c->size + c->size / 4 + 4096)
		return dao_error_set(err, -EINVAL,
				     "%s: byte %llu: a compressed chunk of %u bytes for %u bytes of "
				     "data", b->path, (unsigned long long)c->pos, c->data_len, c->size);
	if (grow(&b->buf, &b->buf_cap, c->size ? c->size : 1) < 0)
		return dao_error_set(err, -ENOMEM, "out of memory reading %s", b->path);
	if (c->comp == COMP_NONE)
		return (ret = read_at(b, c->data_pos, b->buf, c->size, err)) < 0
			       ? ret
			       : (b->cached = ci, 0);
	if (grow(&b->raw, &b->raw_cap, c->data_len ? c->data_len : 1) < 0)
		return dao_error_set(err, -ENOMEM, "out of memory reading %s", b->path);
	if ((ret = read_at(b, c->data_pos, b->raw, c->data_len, err)) < 0)
		return ret;
	if (c->comp == COMP_BZ2) {
		unsigned int out_n = c->size;
		int bz = BZ2_bzBuffToBuffDecompress((char *)b->buf, &out_n, (char *)b->raw,
						    c->data_len, 0, 0);
		if (bz == BZ_MEM_ERROR)
			return dao_error_set(err, -ENOMEM, "out of memory decompressing %s", b->path);
		if (bz != BZ_OK || out_n != c->size)
			return dao_error_set(err, -EINVAL,
					     "%s: byte %llu: the bz2 chunk does not decompress to its "
					     "%u bytes (bzip2 error %d)",
					     b->path, (unsigned long long)c->pos, c->size, bz);
	} else if ((ret = lz4_decompress(b, b->raw, c->data_len, b->buf, c->size)) < 0) {
		if (ret == -ENOMEM)
			return dao_error_set(err, -ENOMEM, "out of memory decompressing %s", b->path);
		return dao_error_set(err, -EINVAL,
				     "%s: byte %llu: the lz4 chunk does not decompress to its %u bytes",
				     b->path, (unsigned long long)c->pos, c->size);
	}
	b->cached = ci;
	return 0;
}

uint64_t dao_bag_message_time(const struct dao_bag *b, uint32_t topic, uint32_t i)
{
	if (topic >= b->ntopics || i >= b->topics[topic].count)
		return 0;
	return b->topics[topic].entries[i].time_ns;
}

int dao_bag_read_message(struct dao_bag *b, uint32_t topic, uint32_t i, const uint8_t **data,
			 uint32_t *len, uint64_t *time_ns, struct dao_error *err)
{
	if (topic >= b->ntopics || i >= b->topics[topic].count)
		return dao_error_set(err, -EINVAL, "%s: no message %u of topic %u", b->path, i, topic);
	const struct entry *e = &b->topics[topic].entries[i];
	const struct chunk *c = &b->chunks[e->chunk];
	int ret = load_chunk(b, e->chunk, err);
	if (ret < 0)
		return ret;
	/* the message record inside the chunk: header_len, header, data_len, data */
	const uint8_t *p = b->buf;
	uint32_t at = e->offset, size = c->size;
	struct rec r;
	memset(&r, 0, sizeof(r));
	r.op = -1;
	if (size - at < 8 || rd32(p + at) > size - at - 8)
		return dao_error_set(err, -EINVAL,
				     "%s: byte %llu: the message at offset %u of the chunk runs past it",
				     b->path, (unsigned long long)c->pos, at);
	uint32_t hlen = rd32(p + at);
	if ((ret = parse_header(b, p + at + 4, hlen, c->pos, &r, err)) < 0)
		return ret;
	uint32_t dlen = rd32(p + at + 4 + hlen);
	uint32_t dpos = at + 8 + hlen;
	if (dlen > size - dpos)
		return dao_error_set(err, -EINVAL,
				     "%s: byte %llu: the message at offset %u of the chunk has %u bytes "
				     "of data, more than the chunk holds",
				     b->path, (unsigned long long)c->pos, at, dlen);
	if (r.op != OP_MSG_DATA || !r.has_conn || r.conn != e->conn)
		return dao_error_set(err, -EINVAL,
				     "%s: byte %llu: the index points to offset %u of the chunk, which "
				     "is not a message of connection %u",
				     b->path, (unsigned long long)c->pos, at, e->conn);
	*data = p + dpos;
	*len = dlen;
	if (time_ns)
		*time_ns = r.has_time ? r.time_ns : e->time_ns;
	return 0;
}
