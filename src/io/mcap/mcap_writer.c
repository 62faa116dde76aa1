/* SPDX-License-Identifier: MIT */
/* The MCAP writer (mcap_writer.h); records laid out as mcap_format.h describes. */
#define _GNU_SOURCE /* fallocate, FALLOC_FL_KEEP_SIZE, pwritev */
#include "mcap/mcap_writer.h"

#include <errno.h>
#include <fcntl.h>
#include <lz4frame.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/uio.h>
#include <unistd.h>
#include <zstd.h>

#include <depthao/depthao.h>

#include "core/clock.h"
#include "core/error_internal.h"
#include "file/write_fully.h"
#include "mcap/mcap_format.h"

/* Message record: header, then channel, sequence, log and publish time. */
#define MSG_HEAD (DAO_MCAP_RECORD_HEADER + DAO_MCAP_MESSAGE_FIXED)
/* A chunk record before its records: header, fixed fields, compression string, u64 length. */
#define CHUNK_HEAD_MAX (DAO_MCAP_RECORD_HEADER + DAO_MCAP_CHUNK_FIXED + 4 + 8 + 8)
/* The summary's fixed part (Data End, Statistics without its map, Summary Offsets, Footer,
 * magic) with room to spare; schemas, channels and chunk indexes are added to it. */
#define SUMMARY_FIXED 512

struct chan {
	uint16_t schema;
	uint64_t count;     /* messages in the file */
	uint8_t *idx;       /* the chunk's Message Index entries: (log_time, offset) */
	size_t nidx, idx_cap;
};

struct buf {
	uint8_t *p;
	size_t len, cap;
};

struct dao_mcap_writer {
	int fd;
	char *path;
	struct dao_mcap_writer_options o;
	uint64_t pos;           /* end of the last complete record */
	uint32_t data_crc;      /* of the file up to pos */
	uint64_t reserved_end;  /* space allocated up to here (fallocate) */
	int no_reserve;         /* the file system has no fallocate */
	int failed;             /* a write failed: the error, sticky */
	uint64_t last_sync_ns;
	struct buf schemas, channels, cidx; /* records, again in the summary */
	uint16_t nschemas, nchannels;
	struct chan ch[DAO_MCAP_MAX_CHANNELS];
	struct buf chunk;       /* the chunk's uncompressed records */
	uint64_t chunk_t0, chunk_t1, chunk_open_ns;
	uint8_t *z;             /* compressed records */
	size_t z_cap;
	struct buf mi;          /* the chunk's Message Index records */
	ZSTD_CCtx *zc;
	uint64_t nmsgs, nchunks, t_start, t_end;
};

static const char *const compression_name[] = {"zstd", "lz4", ""};

static int grow(struct buf *b, size_t need)
{
	if (need <= b->cap)
		return 0;
	size_t cap = b->cap ? b->cap : 256;
	while (cap < need)
		cap *= 2;
	uint8_t *p = realloc(b->p, cap);
	if (!p)
		return -ENOMEM;
	b->p = p;
	b->cap = cap;
	return 0;
}

static uint8_t *put_str(uint8_t *p, const char *s)
{
	uint32_t n = (uint32_t)strlen(s);
	dao_mcap_wr32(p, n);
	memcpy(p + 4, s, n);
	return p + 4 + n;
}

static uint8_t *put_record_head(uint8_t *p, uint8_t op, uint64_t len)
{
	p[0] = op;
	dao_mcap_wr64(p + 1, len);
	return p + DAO_MCAP_RECORD_HEADER;
}

/* Appends whole records at pos; a failure cuts off what it left (the file keeps its
 * complete records) and is sticky. */
static int append(struct dao_mcap_writer *w, struct iovec *iov, int n, const char *what,
		  struct dao_error *err)
{
	size_t total = 0;
	for (int i = 0; i < n; i++)
		total += iov[i].iov_len;
	struct iovec copy[4];
	memcpy(copy, iov, (size_t)n * sizeof(*iov));
	int r = dao_io_write_fully(w->fd, copy, n, w->pos);
	if (r < 0) {
		if (ftruncate(w->fd, (off_t)w->pos) != 0) {
			/* the reader's linear scan stops at the partial record */
		}
		w->failed = r;
		return dao_error_set(err, r,
				     "mcap: writing %s to %s failed: %s; the file keeps the %llu "
				     "chunk%s written before%s",
				     what, w->path, strerror(-r), (unsigned long long)w->nchunks,
				     w->nchunks == 1 ? "" : "s",
				     r == -ENOSPC || r == -EDQUOT ? " (the disk is full: free space "
								    "or record elsewhere)"
								  : "");
	}
	for (int i = 0; i < n; i++)
		w->data_crc = dao_mcap_crc32(w->data_crc, iov[i].iov_base, iov[i].iov_len);
	w->pos += total;
	return 0;
}

/* The chunk record's size for `n` bytes of records in the worst case. */
static size_t chunk_bound(const struct dao_mcap_writer *w, size_t n)
{
	size_t b = n;
	if (w->o.compression == DAO_MCAP_COMPRESS_ZSTD)
		b = ZSTD_compressBound(n);
	else if (w->o.compression == DAO_MCAP_COMPRESS_LZ4)
		b = LZ4F_compressFrameBound(n, NULL) + 64;
	return CHUNK_HEAD_MAX + (b > n ? b : n);
}

/* Space the file needs beyond pos once a message of `rec` bytes joins the chunk. */
static uint64_t space_needed(const struct dao_mcap_writer *w, size_t rec)
{
	uint64_t n = chunk_bound(w, w->chunk.len + rec);
	for (unsigned c = 0; c < w->nchannels; c++) /* Message Indexes, one more entry each */
		n += DAO_MCAP_RECORD_HEADER + 6 + 16 * (w->ch[c].nidx + 1);
	/* the summary: schemas, channels, the chunk indexes with the next one, the rest */
	n += w->schemas.len + w->channels.len + w->cidx.len + SUMMARY_FIXED +
	     (DAO_MCAP_RECORD_HEADER + 64 + 10 * (uint64_t)w->nchannels) + 10 * w->nchannels;
	return n;
}

/*
 * Makes sure the file system has room for everything accepted so far plus a
 * record of `rec` bytes (fallocate KEEP_SIZE, in steps of the chunk size so
 * that it is not a call per message).  -ENOSPC when it has not.
 */
static int reserve(struct dao_mcap_writer *w, size_t rec, struct dao_error *err)
{
	uint64_t need = w->pos + space_needed(w, rec);
	if (w->no_reserve || need <= w->reserved_end)
		return 0;
	uint64_t from = w->reserved_end > w->pos ? w->reserved_end : w->pos;
	uint64_t step = need - from + w->o.chunk_size;
	int r = fallocate(w->fd, FALLOC_FL_KEEP_SIZE, (off_t)from, (off_t)step);
	if (r != 0 && errno == ENOSPC) /* not the step: just what this message needs */
		r = fallocate(w->fd, FALLOC_FL_KEEP_SIZE, (off_t)from, (off_t)(step = need - from));
	if (r == 0) {
		w->reserved_end = from + step;
		return 0;
	}
	if (errno == EOPNOTSUPP || errno == ENOSYS || errno == EINVAL) {
		w->no_reserve = 1; /* chunks that fail are cut off (append) */
		return 0;
	}
	return dao_error_set(err, -errno,
			     "mcap: %s: no room for the next message: %s; the recording keeps the "
			     "%llu message%s before it (free space or record elsewhere)",
			     w->path, strerror(errno), (unsigned long long)w->nmsgs,
			     w->nmsgs == 1 ? "" : "s");
}

static void maybe_sync(struct dao_mcap_writer *w)
{
	if (dao_mono_us_since(w->last_sync_ns) >= (int64_t)DAO_MCAP_SYNC_INTERVAL_MS * 1000) {
		if (fdatasync(w->fd) != 0) {
			/* a write-back error shows at the next write or at finish */
		}
		w->last_sync_ns = dao_mono_ns();
	}
}

/* Compresses the chunk into w->z: its length, and the compression used ("" when
 * compression would not make it smaller). */
static size_t compress_chunk(struct dao_mcap_writer *w, const char **comp)
{
	size_t n = w->chunk.len, k = 0;
	*comp = "";
	if (w->o.compression == DAO_MCAP_COMPRESS_ZSTD) {
		k = ZSTD_compressCCtx(w->zc, w->z, w->z_cap, w->chunk.p, n, w->o.zstd_level);
		if (ZSTD_isError(k))
			k = 0;
	} else if (w->o.compression == DAO_MCAP_COMPRESS_LZ4) {
		LZ4F_preferences_t pr;
		memset(&pr, 0, sizeof(pr));
		pr.frameInfo.contentSize = n;
		k = LZ4F_compressFrame(w->z, w->z_cap, w->chunk.p, n, &pr);
		if (LZ4F_isError(k))
			k = 0;
	}
	if (k == 0 || k >= n)
		return n;
	*comp = compression_name[w->o.compression];
	return k;
}

/* The chunk's Message Index records into w->mi; the offsets of each in `offsets`. */
static int build_message_indexes(struct dao_mcap_writer *w, uint64_t at, uint8_t *offsets,
				 uint32_t *noffsets)
{
	size_t need = 0;
	for (unsigned c = 0; c < w->nchannels; c++)
		need += w->ch[c].nidx ? DAO_MCAP_RECORD_HEADER + 6 + 16 * w->ch[c].nidx : 0;
	if (grow(&w->mi, need) < 0)
		return -ENOMEM;
	uint8_t *p = w->mi.p;
	*noffsets = 0;
	for (unsigned c = 0; c < w->nchannels; c++) {
		struct chan *ch = &w->ch[c];
		if (!ch->nidx)
			continue;
		uint8_t *o = offsets + 10 * (*noffsets)++;
		dao_mcap_wr16(o, (uint16_t)c);
		dao_mcap_wr64(o + 2, at + (uint64_t)(p - w->mi.p));
		p = put_record_head(p, DAO_MCAP_OP_MESSAGE_INDEX, 6 + 16 * (uint64_t)ch->nidx);
		dao_mcap_wr16(p, (uint16_t)c);
		dao_mcap_wr32(p + 2, (uint32_t)(16 * ch->nidx));
		memcpy(p + 6, ch->idx, 16 * ch->nidx);
		p += 6 + 16 * ch->nidx;
	}
	w->mi.len = (size_t)(p - w->mi.p);
	return 0;
}

/* The summary's Chunk Index of the chunk just written at `start`. */
static int add_chunk_index(struct dao_mcap_writer *w, uint64_t start, uint64_t chunk_len,
			   const uint8_t *offsets, uint32_t noffsets, const char *comp,
			   uint64_t zlen)
{
	uint64_t len = 32 + 4 + 10 * (uint64_t)noffsets + 8 + 4 + strlen(comp) + 16;
	if (grow(&w->cidx, w->cidx.len + DAO_MCAP_RECORD_HEADER + len) < 0)
		return -ENOMEM;
	uint8_t *p = put_record_head(w->cidx.p + w->cidx.len, DAO_MCAP_OP_CHUNK_INDEX, len);
	dao_mcap_wr64(p, w->chunk_t0);
	dao_mcap_wr64(p + 8, w->chunk_t1);
	dao_mcap_wr64(p + 16, start);
	dao_mcap_wr64(p + 24, chunk_len);
	dao_mcap_wr32(p + 32, 10 * noffsets);
	memcpy(p + 36, offsets, 10 * noffsets);
	p += 36 + 10 * noffsets;
	dao_mcap_wr64(p, w->mi.len);
	p = put_str(p + 8, comp);
	dao_mcap_wr64(p, zlen);
	dao_mcap_wr64(p + 8, w->chunk.len);
	w->cidx.len += DAO_MCAP_RECORD_HEADER + len;
	return 0;
}

/* Writes the chunk being built and its Message Indexes; empties it. */
static int write_chunk(struct dao_mcap_writer *w, struct dao_error *err)
{
	if (w->chunk.len == 0)
		return 0;
	const char *comp;
	size_t zlen = compress_chunk(w, &comp);
	const uint8_t *data = *comp ? w->z : w->chunk.p;
	uint8_t head[CHUNK_HEAD_MAX], offsets[10 * DAO_MCAP_MAX_CHANNELS];
	uint64_t content = DAO_MCAP_CHUNK_FIXED + 4 + strlen(comp) + 8 + zlen;
	uint8_t *p = put_record_head(head, DAO_MCAP_OP_CHUNK, content);
	dao_mcap_wr64(p, w->chunk_t0);
	dao_mcap_wr64(p + 8, w->chunk_t1);
	dao_mcap_wr64(p + 16, w->chunk.len);
	dao_mcap_wr32(p + 24, dao_mcap_crc32(0, w->chunk.p, w->chunk.len));
	p = put_str(p + 28, comp);
	dao_mcap_wr64(p, zlen);
	p += 8;
	uint64_t start = w->pos, chunk_len = DAO_MCAP_RECORD_HEADER + content;
	uint32_t noffsets;
	if (build_message_indexes(w, start + chunk_len, offsets, &noffsets) < 0)
		return dao_error_set(err, -ENOMEM, "out of memory");
	struct iovec iov[3] = {{head, (size_t)(p - head)}, {(void *)data, zlen}, {w->mi.p, w->mi.len}};
	char what[48];
	snprintf(what, sizeof what, "chunk %llu", (unsigned long long)w->nchunks);
	int r = append(w, iov, 3, what, err);
	if (r < 0)
		return r;
	if (add_chunk_index(w, start, chunk_len, offsets, noffsets, comp, zlen) < 0)
		return dao_error_set(err, -ENOMEM, "out of memory");
	w->nchunks++;
	w->chunk.len = 0;
	for (unsigned c = 0; c < w->nchannels; c++)
		w->ch[c].nidx = 0;
	maybe_sync(w);
	return 0;
}

static int put_whole(struct dao_mcap_writer *w, const uint8_t *p, size_t n, const char *what,
		     struct dao_error *err)
{
	struct iovec v = {(void *)p, n};
	return append(w, &v, 1, what, err);
}

static int create_file(struct dao_mcap_writer *w, const char *path, struct dao_error *err)
{
	struct stat st;
	if (stat(path, &st) == 0) {
		if (S_ISDIR(st.st_mode))
			return dao_error_set(err, -EISDIR,
					     "mcap: %s is a directory; give the path of the .mcap "
					     "file to write", path);
		if (!S_ISREG(st.st_mode))
			return dao_error_set(err, -EINVAL,
					     "mcap: %s is not a regular file (a device, FIFO or "
					     "socket); recordings are written to files", path);
		if (!w->o.overwrite) /* (the caller applies the rule for replacing a file) */
			return dao_error_set(err, -EEXIST,
					     "mcap: %s exists; a recording never replaces a file", path);
	}
	w->fd = open(path, O_WRONLY | O_CREAT | O_CLOEXEC | (w->o.overwrite ? O_TRUNC : O_EXCL),
		     0666);
	if (w->fd < 0 && errno == EEXIST)
		return dao_error_set(err, -EEXIST,
				     "mcap: %s exists; a recording never replaces a file", path);
	if (w->fd < 0)
		return dao_error_set(err, -errno, "mcap: cannot create %s: %s", path,
				     strerror(errno));
	/* the new name survives a power cut too */
	const char *slash = strrchr(path, '/');
	char *dir = slash ? strndup(path, slash == path ? 1 : (size_t)(slash - path)) : strdup(".");
	int dfd = dir ? open(dir, O_RDONLY | O_CLOEXEC) : -1;
	if (dfd >= 0) {
		if (fsync(dfd) != 0) {
			/* best effort: some file systems refuse to sync directories */
		}
		close(dfd);
	}
	free(dir);
	return 0;
}

static void writer_free(struct dao_mcap_writer *w)
{
	if (w->fd >= 0)
		close(w->fd);
	for (unsigned c = 0; c < DAO_MCAP_MAX_CHANNELS; c++)
		free(w->ch[c].idx);
	free(w->schemas.p);
	free(w->channels.p);
	free(w->cidx.p);
	free(w->chunk.p);
	free(w->mi.p);
	free(w->z);
	ZSTD_freeCCtx(w->zc);
	free(w->path);
	free(w);
}

int dao_mcap_writer_open(const char *path, const struct dao_mcap_writer_options *o,
			 struct dao_mcap_writer **out, struct dao_error *err)
{
	*out = NULL;
	if ((unsigned)o->compression > DAO_MCAP_COMPRESS_NONE || o->zstd_level < 0 ||
	    o->zstd_level > ZSTD_maxCLevel() || o->chunk_size > DAO_MCAP_MAX_MESSAGE)
		return dao_error_set(err, -EINVAL, "mcap writer: invalid options");
	struct dao_mcap_writer *w = calloc(1, sizeof(*w));
	if (!w || !(w->path = strdup(path))) {
		free(w);
		return dao_error_set(err, -ENOMEM, "out of memory");
	}
	w->fd = -1;
	w->o = *o;
	w->o.profile = NULL;
	if (!w->o.zstd_level)
		w->o.zstd_level = 1;
	if (!w->o.chunk_size)
		w->o.chunk_size = DAO_MCAP_DEFAULT_CHUNK_SIZE;
	if (o->compression == DAO_MCAP_COMPRESS_ZSTD && !(w->zc = ZSTD_createCCtx())) {
		writer_free(w);
		return dao_error_set(err, -ENOMEM, "out of memory");
	}
	int r = create_file(w, path, err);
	if (r < 0) {
		writer_free(w);
		return r;
	}
	/* magic, Header (profile, library) */
	char lib[64];
	snprintf(lib, sizeof lib, "depthao %s", dao_version());
	const char *profile = o->profile ? o->profile : "";
	uint8_t head[DAO_MCAP_MAGIC_LEN + DAO_MCAP_RECORD_HEADER + 8 + 64 + 64];
	if (strlen(profile) > 60) {
		r = dao_error_set(err, -EINVAL, "mcap writer: profile too long");
	} else {
		memcpy(head, DAO_MCAP_MAGIC, DAO_MCAP_MAGIC_LEN);
		uint8_t *p = put_record_head(head + DAO_MCAP_MAGIC_LEN, DAO_MCAP_OP_HEADER,
					     8 + strlen(profile) + strlen(lib));
		p = put_str(put_str(p, profile), lib);
		w->last_sync_ns = dao_mono_ns();
		r = put_whole(w, head, (size_t)(p - head), "the header", err);
	}
	if (r < 0) {
		dao_mcap_writer_abort(w);
		return r;
	}
	*out = w;
	return 0;
}

/* A Schema or Channel record: written now (before any chunk) and kept for the summary. */
static int add_meta(struct dao_mcap_writer *w, struct buf *keep, const uint8_t *rec, size_t n,
		    const char *what, struct dao_error *err)
{
	if (w->nmsgs || w->chunk.len)
		return dao_error_set(err, -EINVAL, "mcap writer: %s added after a message", what);
	if (grow(keep, keep->len + n) < 0)
		return dao_error_set(err, -ENOMEM, "out of memory");
	int r = put_whole(w, rec, n, what, err);
	if (r < 0)
		return r;
	memcpy(keep->p + keep->len, rec, n);
	keep->len += n;
	return 0;
}

int dao_mcap_writer_add_schema(struct dao_mcap_writer *w, const char *name, const char *encoding,
			       const char *data, uint16_t *id, struct dao_error *err)
{
	size_t dn = strlen(data), n = 2 + 4 + strlen(name) + 4 + strlen(encoding) + 4 + dn;
	if (w->nschemas >= DAO_MCAP_MAX_CHANNELS || n > 1u << 20)
		return dao_error_set(err, -EINVAL, "mcap writer: too many schemas or one too large");
	uint8_t *rec = malloc(DAO_MCAP_RECORD_HEADER + n);
	if (!rec)
		return dao_error_set(err, -ENOMEM, "out of memory");
	uint16_t sid = (uint16_t)(w->nschemas + 1);
	uint8_t *p = put_record_head(rec, DAO_MCAP_OP_SCHEMA, n);
	dao_mcap_wr16(p, sid);
	p = put_str(put_str(p + 2, name), encoding);
	dao_mcap_wr32(p, (uint32_t)dn);
	memcpy(p + 4, data, dn);
	int r = add_meta(w, &w->schemas, rec, DAO_MCAP_RECORD_HEADER + n, "a schema", err);
	free(rec);
	if (r < 0)
		return r;
	w->nschemas++;
	*id = sid;
	return 0;
}

int dao_mcap_writer_add_channel(struct dao_mcap_writer *w, uint16_t schema_id, const char *topic,
				const char *message_encoding, uint16_t *id, struct dao_error *err)
{
	size_t n = 2 + 2 + 4 + strlen(topic) + 4 + strlen(message_encoding) + 4;
	if (w->nchannels >= DAO_MCAP_MAX_CHANNELS || n > 4096 || schema_id > w->nschemas)
		return dao_error_set(err, -EINVAL, "mcap writer: too many channels or a bad one");
	uint8_t rec[DAO_MCAP_RECORD_HEADER + 4096];
	uint16_t cid = w->nchannels;
	uint8_t *p = put_record_head(rec, DAO_MCAP_OP_CHANNEL, n);
	dao_mcap_wr16(p, cid);
	dao_mcap_wr16(p + 2, schema_id);
	p = put_str(put_str(p + 4, topic), message_encoding);
	dao_mcap_wr32(p, 0); /* metadata: an empty map */
	int r = add_meta(w, &w->channels, rec, DAO_MCAP_RECORD_HEADER + n, "a channel", err);
	if (r < 0)
		return r;
	w->ch[cid].schema = schema_id;
	w->nchannels++;
	*id = cid;
	return 0;
}

/* Room in the chunk buffer, its compressed bound and the channel's index for one more. */
static int make_room(struct dao_mcap_writer *w, struct chan *ch, size_t rec)
{
	if (grow(&w->chunk, w->chunk.len + rec) < 0)
		return -ENOMEM;
	size_t zb = chunk_bound(w, w->chunk.cap);
	if (w->o.compression != DAO_MCAP_COMPRESS_NONE && zb > w->z_cap) {
		uint8_t *z = realloc(w->z, zb);
		if (!z)
			return -ENOMEM;
		w->z = z;
		w->z_cap = zb;
	}
	if (ch->nidx == ch->idx_cap) {
		size_t cap = ch->idx_cap ? 2 * ch->idx_cap : 64;
		uint8_t *p = realloc(ch->idx, 16 * cap);
		if (!p)
			return -ENOMEM;
		ch->idx = p;
		ch->idx_cap = cap;
	}
	return 0;
}

int dao_mcap_writer_message(struct dao_mcap_writer *w, uint16_t channel, uint64_t log_time,
			    uint64_t publish_time, size_t len, uint8_t **data,
			    struct dao_error *err)
{
	int r;
	if (w->failed)
		return dao_error_set(err, w->failed,
				     "mcap: %s: an earlier write failed (%s); the file keeps the "
				     "chunks before it", w->path, strerror(-w->failed));
	if (channel >= w->nchannels || len > DAO_MCAP_MAX_MESSAGE)
		return dao_error_set(err, -EINVAL, "mcap writer: channel %u or size %zu invalid",
				     (unsigned)channel, len);
	size_t rec = MSG_HEAD + len;
	int full = w->chunk.len && w->chunk.len + rec > w->o.chunk_size;
	int old = w->chunk.len && dao_mono_us_since(w->chunk_open_ns) >=
					   (int64_t)DAO_MCAP_CHUNK_MAX_AGE_MS * 1000;
	if ((full || old) && (r = write_chunk(w, err)) < 0)
		return r;
	if ((r = reserve(w, rec, err)) < 0)
		return r;
	struct chan *ch = &w->ch[channel];
	if (make_room(w, ch, rec) < 0)
		return dao_error_set(err, -ENOMEM, "mcap: out of memory for a chunk of %zu bytes",
				     w->chunk.len + rec);
	if (w->chunk.len == 0) {
		w->chunk_open_ns = dao_mono_ns();
		w->chunk_t0 = w->chunk_t1 = log_time;
	}
	w->chunk_t0 = log_time < w->chunk_t0 ? log_time : w->chunk_t0;
	w->chunk_t1 = log_time > w->chunk_t1 ? log_time : w->chunk_t1;
	if (!w->nmsgs || log_time < w->t_start)
		w->t_start = log_time;
	w->t_end = log_time > w->t_end ? log_time : w->t_end;
	dao_mcap_wr64(ch->idx + 16 * ch->nidx, log_time);
	dao_mcap_wr64(ch->idx + 16 * ch->nidx + 8, w->chunk.len);
	ch->nidx++;
	uint8_t *p = put_record_head(w->chunk.p + w->chunk.len, DAO_MCAP_OP_MESSAGE,
				     DAO_MCAP_MESSAGE_FIXED + len);
	dao_mcap_wr16(p, channel);
	dao_mcap_wr32(p + 2, (uint32_t)ch->count);
	dao_mcap_wr64(p + 6, log_time);
	dao_mcap_wr64(p + 14, publish_time);
	*data = p + DAO_MCAP_MESSAGE_FIXED;
	w->chunk.len += rec;
	ch->count++;
	w->nmsgs++;
	return 0;
}

int dao_mcap_writer_flush(struct dao_mcap_writer *w, struct dao_error *err)
{
	if (w->failed)
		return 0; /* reported by the write that failed */
	int r = write_chunk(w, err);
	if (r < 0)
		return r;
	if (fdatasync(w->fd) != 0)
		return dao_error_set(err, -errno, "mcap: syncing %s: %s", w->path, strerror(errno));
	w->last_sync_ns = dao_mono_ns();
	return 0;
}

uint64_t dao_mcap_writer_messages(const struct dao_mcap_writer *w)
{
	return w->nmsgs;
}

uint64_t dao_mcap_writer_chunks(const struct dao_mcap_writer *w)
{
	return w->nchunks;
}

/* Statistics record into p; its length. */
static size_t statistics(const struct dao_mcap_writer *w, uint8_t *p)
{
	uint64_t len = 8 + 2 + 4 * 4 + 16 + 4 + 10 * (uint64_t)w->nchannels;
	uint8_t *q = put_record_head(p, DAO_MCAP_OP_STATISTICS, len);
	dao_mcap_wr64(q, w->nmsgs);
	dao_mcap_wr16(q + 8, w->nschemas);
	dao_mcap_wr32(q + 10, w->nchannels);
	dao_mcap_wr32(q + 14, 0);
	dao_mcap_wr32(q + 18, 0);
	dao_mcap_wr32(q + 22, (uint32_t)w->nchunks);
	dao_mcap_wr64(q + 26, w->nmsgs ? w->t_start : 0);
	dao_mcap_wr64(q + 34, w->t_end);
	dao_mcap_wr32(q + 42, 10u * w->nchannels);
	for (unsigned c = 0; c < w->nchannels; c++) {
		dao_mcap_wr16(q + 46 + 10 * c, (uint16_t)c);
		dao_mcap_wr64(q + 48 + 10 * c, w->ch[c].count);
	}
	return DAO_MCAP_RECORD_HEADER + len;
}

/* Data End, the summary, its offsets, the Footer and the magic, in one buffer. */
static int build_tail(struct dao_mcap_writer *w, struct buf *t)
{
	size_t n = SUMMARY_FIXED + 10 * w->nchannels + w->schemas.len + w->channels.len + w->cidx.len;
	if (grow(t, n) < 0)
		return -ENOMEM;
	uint8_t *p = put_record_head(t->p, DAO_MCAP_OP_DATA_END, DAO_MCAP_DATA_END_CONTENT);
	dao_mcap_wr32(p, w->data_crc);
	p += 4;
	uint64_t summary = w->pos + (uint64_t)(p - t->p);
	const struct buf *groups[4] = {&w->schemas, &w->channels, NULL, &w->cidx};
	const uint8_t ops[4] = {DAO_MCAP_OP_SCHEMA, DAO_MCAP_OP_CHANNEL, DAO_MCAP_OP_STATISTICS,
				DAO_MCAP_OP_CHUNK_INDEX};
	uint64_t gstart[4], glen[4];
	for (int g = 0; g < 4; g++) {
		gstart[g] = w->pos + (uint64_t)(p - t->p);
		if (groups[g]) {
			memcpy(p, groups[g]->p, groups[g]->len);
			p += groups[g]->len;
		} else {
			p += statistics(w, p);
		}
		glen[g] = w->pos + (uint64_t)(p - t->p) - gstart[g];
	}
	uint64_t offsets = w->pos + (uint64_t)(p - t->p);
	for (int g = 0; g < 4; g++) {
		if (!glen[g])
			continue;
		uint8_t *q = put_record_head(p, DAO_MCAP_OP_SUMMARY_OFFSET, 17);
		q[0] = ops[g];
		dao_mcap_wr64(q + 1, gstart[g]);
		dao_mcap_wr64(q + 9, glen[g]);
		p = q + 17;
	}
	uint8_t *f = put_record_head(p, DAO_MCAP_OP_FOOTER, DAO_MCAP_FOOTER_CONTENT);
	dao_mcap_wr64(f, summary);
	dao_mcap_wr64(f + 8, offsets);
	size_t from = (size_t)(summary - w->pos);
	dao_mcap_wr32(f + 16, dao_mcap_crc32(0, t->p + from, (size_t)(f + 16 - (t->p + from))));
	memcpy(f + 20, DAO_MCAP_MAGIC, DAO_MCAP_MAGIC_LEN);
	t->len = (size_t)(f + 20 + DAO_MCAP_MAGIC_LEN - t->p);
	return 0;
}

int dao_mcap_writer_finish(struct dao_mcap_writer *w, struct dao_error *err)
{
	struct dao_error e;
	struct buf t = {0};
	int r = w->failed ? 0 : write_chunk(w, err);
	if (build_tail(w, &t) < 0) {
		r = r < 0 ? r : dao_error_set(err, -ENOMEM, "out of memory");
	} else {
		/* after a failed chunk the file is finished with what it kept */
		w->failed = 0;
		int rt = put_whole(w, t.p, t.len, "the summary", r < 0 ? &e : err);
		r = r < 0 ? r : rt;
	}
	free(t.p);
	/* give back what was reserved past the end */
	if (w->reserved_end > w->pos && ftruncate(w->fd, (off_t)w->pos) != 0) {
		/* the file keeps its size; only the reservation stays */
	}
	if (fdatasync(w->fd) != 0 && r == 0)
		r = dao_error_set(err, -errno, "mcap: syncing %s: %s", w->path, strerror(errno));
	if (close(w->fd) != 0 && r == 0)
		r = dao_error_set(err, -errno, "mcap: closing %s: %s", w->path, strerror(errno));
	w->fd = -1;
	writer_free(w);
	return r;
}

void dao_mcap_writer_abort(struct dao_mcap_writer *w)
{
	if (!w)
		return;
	if (w->fd >= 0)
		unlink(w->path);
	writer_free(w);
}
