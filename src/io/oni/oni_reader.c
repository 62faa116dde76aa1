/* SPDX-License-Identifier: MIT */
/*
 * .oni reader: one pass over the record headers builds a per-node frame
 * index (the file's own seek table and frame counts are not trusted; files
 * without them, or with stale ones, read the same); frames are then decoded
 * on demand with pread, so any frame can be read in any order and from any
 * thread holding the reader exclusively.
 *
 * Recovery: a recording that was never finished (the writer crashed, was
 * killed, lost power or ran out of disk) ends without an end record, maybe
 * in a record cut short, maybe in zeros (blocks allocated whose data never
 * reached the disk).  Such a tail ends the index at the last complete record
 * and is reported by dao_oni_reader_warning(); anything else that is not a
 * record (bad magic followed by non-zero bytes) is corruption, as before.
 */
#include <depthao/oni.h>
#include <depthao/output_file.h>

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error_internal.h"
#include "oni/codec_16z.h"
#include "oni/oni_color.h"
#include "oni/oni_format.h"

/* Property and node records are small; anything bigger is corruption. */
#define ONI_MAX_FIELDS_SIZE (16u << 20)

struct frame_ref {
	uint64_t payload_pos;
	uint32_t payload_size;
	uint32_t number;
	uint64_t timestamp_us;
};

struct node {
	uint32_t id;
	struct dao_oni_stream_info info;
	uint32_t codec_fourcc;
	int pixel_format_set;
	char unusable[320]; /* colour nodes: why they cannot be decoded, empty if they can */
	struct frame_ref *frames;
	uint32_t nframes, cap;
};

/* How an unfinished file ends (the tail the index stops before). */
enum tail_kind {
	TAIL_END_RECORD = 0, /* finished: the end record */
	TAIL_NO_END,         /* the last record is complete, no end record follows */
	TAIL_CUT,            /* a record cut short */
	TAIL_ZEROS,          /* zeros instead of a record */
};

struct dao_oni_reader {
	int fd;
	char warning[DAO_ERROR_MESSAGE_MAX + 256]; /* empty unless recovered */
	uint64_t file_size;
	int old32;
	uint32_t max_node_id;
	struct node *nodes;
	uint32_t nnodes;
	uint8_t *payload; /* largest depth or colour payload */
	size_t payload_cap;
	uint16_t *pixels; /* largest depth frame, contiguous */
	size_t pixels_cap;
	uint64_t max_pixels; /* depth nodes with frames may not be larger */
	struct dao_jpeg *jpeg; /* colour nodes with the JPEG codec */
};

static int read_at(struct dao_oni_reader *r, void *buf, size_t n, uint64_t pos)
{
	uint8_t *p = buf;
	while (n) {
		ssize_t k = pread(r->fd, p, n, (off_t)pos);
		if (k < 0) {
			if (errno == EINTR)
				continue;
			return -errno;
		}
		if (k == 0)
			return -ENODATA;
		p += k;
		n -= (size_t)k;
		pos += (uint64_t)k;
	}
	return 0;
}

static struct node *find_node(struct dao_oni_reader *r, uint32_t id)
{
	for (uint32_t i = 0; i < r->nnodes; i++)
		if (r->nodes[i].id == id)
			return &r->nodes[i];
	return NULL;
}

static enum dao_oni_codec codec_of(uint32_t fourcc)
{
	switch (fourcc) {
	case ONI_CODEC_NONE: return DAO_ONI_CODEC_NONE;
	case ONI_CODEC_16Z: return DAO_ONI_CODEC_16Z;
	case ONI_CODEC_16ZT: return DAO_ONI_CODEC_16ZT;
	case ONI_CODEC_JPEG: return DAO_ONI_CODEC_JPEG;
	case ONI_CODEC_8Z: return DAO_ONI_CODEC_8Z;
	default: return DAO_ONI_CODEC_OTHER;
	}
}

/* A counted string at f[*off]; fails unless it fits and ends in NUL. */
static int take_string(const uint8_t *f, size_t len, size_t *off, const char **s)
{
	if (len - *off < 4)
		return -EINVAL;
	uint32_t n = oni_rd32(f + *off);
	*off += 4;
	if (n == 0 || n > len - *off || f[*off + n - 1] != '\0')
		return -EINVAL;
	*s = (const char *)f + *off;
	*off += n;
	return 0;
}

struct scan {
	const char *path;
	uint64_t pos;  /* of the current record */
	uint32_t index;
	struct dao_error *err;
	enum tail_kind tail;
	uint64_t tail_need; /* TAIL_CUT: bytes the cut record needs */
};

#define CORRUPT(sc, ...)                                                                       \
	dao_error_set((sc)->err, -EINVAL, "%s: corrupt .oni file: record %u at byte %llu: "   \
		      __VA_ARGS__)
#define AT(sc) (sc)->path, (sc)->index, (unsigned long long)(sc)->pos

static int add_node(struct dao_oni_reader *r, struct scan *sc, uint32_t id, uint32_t type,
		    const uint8_t *f, size_t len)
{
	size_t off = 0;
	const char *name;
	if (take_string(f, len, &off, &name) < 0 || len - off < 8)
		return CORRUPT(sc, "the node record is cut short", AT(sc));
	if (find_node(r, id))
		return CORRUPT(sc, "node %u is added twice", AT(sc), id);
	struct node *nodes = realloc(r->nodes, (r->nnodes + 1) * sizeof(*nodes));
	if (!nodes)
		return dao_error_set(sc->err, -ENOMEM, "out of memory reading %s", sc->path);
	r->nodes = nodes;
	struct node *n = &nodes[r->nnodes++];
	memset(n, 0, sizeof(*n));
	n->id = id;
	snprintf(n->info.name, sizeof(n->info.name), "%s", name);
	uint32_t node_type = oni_rd32(f + off);
	n->codec_fourcc = oni_rd32(f + off + 4);
	memcpy(n->info.codec_fourcc, f + off + 4, 4);
	for (int i = 0; i < 4; i++)
		if (n->info.codec_fourcc[i] < 0x20 || n->info.codec_fourcc[i] > 0x7e)
			n->info.codec_fourcc[i] = '?';
	n->info.codec = codec_of(n->codec_fourcc);
	n->info.sensor = node_type == ONI_NODE_TYPE_DEPTH   ? DAO_ONI_SENSOR_DEPTH
			 : node_type == ONI_NODE_TYPE_IMAGE ? DAO_ONI_SENSOR_COLOR
			 : node_type == ONI_NODE_TYPE_IR    ? DAO_ONI_SENSOR_IR
							    : DAO_ONI_SENSOR_OTHER;
	if (n->info.sensor == DAO_ONI_SENSOR_DEPTH) {
		n->info.pixel_format = DAO_ONI_PIXEL_DEPTH_1_MM; /* OpenNI2's default */
		n->info.depth_unit = 0.001f;
	}
	(void)type;
	return 0;
}

static void apply_int(struct node *n, const char *name, uint64_t v)
{
	if (!strcmp(name, "xnDeviceMaxDepth"))
		n->info.max_depth = v > UINT32_MAX ? UINT32_MAX : (uint32_t)v;
	else if (!strcmp(name, "xnMirror"))
		n->info.mirrored = v != 0;
	else if (!strcmp(name, "AlternativeViewPoint"))
		n->info.registered = v != 0;
	else if (n->info.sensor == DAO_ONI_SENSOR_COLOR && !strcmp(name, "oniPixelFormat"))
		n->info.pixel_format = (int)v;
	else if (n->info.sensor == DAO_ONI_SENSOR_COLOR && !strcmp(name, "xnPixelFormat") &&
		 !n->info.pixel_format)
		n->info.pixel_format = dao_oni_color_format_from_xn(v);
	else if (!strcmp(name, "oniPixelFormat") && n->info.sensor == DAO_ONI_SENSOR_DEPTH) {
		n->info.pixel_format = (int)v;
		n->info.depth_unit = v == DAO_ONI_PIXEL_DEPTH_100_UM ? 0.0001f
				     : v == DAO_ONI_PIXEL_DEPTH_1_MM ? 0.001f
								     : 0.0f;
	}
}

static int apply_general(struct node *n, struct scan *sc, const char *name, const uint8_t *d,
			 uint32_t size)
{
	if (!strcmp(name, "xnMapOutputMode")) {
		if (size != 12)
			return CORRUPT(sc, "xnMapOutputMode has %u bytes, expected 12", AT(sc), size);
		n->info.width = oni_rd32(d);
		n->info.height = oni_rd32(d + 4);
		n->info.fps = oni_rd32(d + 8);
	} else if (!strcmp(name, "xnFOV")) {
		if (size != 16)
			return CORRUPT(sc, "xnFOV has %u bytes, expected 16", AT(sc), size);
		n->info.hfov = oni_rdf64(d);
		n->info.vfov = oni_rdf64(d + 8);
		n->info.has_fov = 1;
	}
	return 0;
}

static int add_property(struct dao_oni_reader *r, struct scan *sc, uint32_t type, uint32_t id,
			const uint8_t *f, size_t len)
{
	size_t off = 0;
	const char *name;
	if (take_string(f, len, &off, &name) < 0 || len - off < 4)
		return CORRUPT(sc, "the property record is cut short", AT(sc));
	uint32_t size = oni_rd32(f + off);
	off += 4;
	if (size > len - off)
		return CORRUPT(sc, "property %s claims %u bytes, the record holds %zu", AT(sc),
			       name, size, len - off);
	struct node *n = find_node(r, id);
	if (!n)
		return 0; /* properties of nodes we do not know (e.g. removed) */
	if (type == ONI_REC_INT_PROPERTY && size == 8)
		apply_int(n, name, oni_rd64(f + off));
	else if (type == ONI_REC_GENERAL_PROPERTY)
		return apply_general(n, sc, name, f + off, size);
	return 0;
}

static int add_frame(struct dao_oni_reader *r, struct scan *sc, uint32_t id, const uint8_t *f,
		     size_t len, uint64_t payload_pos, uint32_t payload_size)
{
	struct node *n = find_node(r, id);
	if (!n)
		return CORRUPT(sc, "frame data for node %u, which was never added", AT(sc), id);
	if (len < 12)
		return CORRUPT(sc, "the frame record is cut short", AT(sc));
	if (n->nframes == n->cap) {
		uint32_t cap = n->cap ? 2 * n->cap : 64;
		struct frame_ref *fr = realloc(n->frames, cap * sizeof(*fr));
		if (!fr)
			return dao_error_set(sc->err, -ENOMEM, "out of memory reading %s", sc->path);
		n->frames = fr;
		n->cap = cap;
	}
	struct frame_ref *fr = &n->frames[n->nframes++];
	fr->timestamp_us = oni_rd64(f);
	fr->number = oni_rd32(f + 8);
	fr->payload_pos = payload_pos;
	fr->payload_size = payload_size;
	return 0;
}

/* 1 if every byte from `pos` to the end of the file is zero, 0 if not, < 0 on errors. */
static int zeros_to_end(struct dao_oni_reader *r, uint64_t pos)
{
	uint8_t buf[4096];
	while (pos < r->file_size) {
		size_t n = r->file_size - pos < sizeof(buf) ? (size_t)(r->file_size - pos) : sizeof(buf);
		int ret = read_at(r, buf, n, pos);
		if (ret < 0)
			return ret;
		for (size_t i = 0; i < n; i++)
			if (buf[i])
				return 0;
		pos += n;
	}
	return 1;
}

struct record_header {
	uint32_t type, id, fsize, psize;   /* fsize: the header and fields; psize: the payload */
};

static const char *plural(uint64_t n)
{
	return n == 1 ? "" : "s";
}

static int known_type(uint32_t t)
{
	return (t >= ONI_REC_NODE_ADDED_1_0_0_4 && t <= ONI_REC_SEEK_TABLE);
}

/*
 * Where a complete, plausible record header starts in [from, file end), or 0
 * (< 0 on read errors).  A record whose size runs past the end of the file
 * while records follow it was damaged (its size field); one that simply ends
 * with the file was cut short by an interrupted recording.  The scan stops
 * at the first hit, so it reads about one frame in a damaged file and the
 * cut record's bytes in a truncated one.
 */
static int64_t record_after(struct dao_oni_reader *r, size_t hsize, uint64_t from)
{
	uint8_t buf[65536];
	for (uint64_t pos = from; pos + hsize <= r->file_size;) {
		uint64_t left = r->file_size - pos;
		size_t n = left < sizeof(buf) ? (size_t)left : sizeof(buf);
		int ret = read_at(r, buf, n, pos);
		if (ret < 0)
			return ret;
		for (size_t i = 0; i + hsize <= n; i++) {
			const uint8_t *h = buf + i;
			if (h[0] != 'N' || oni_rd32(h) != ONI_RECORD_MAGIC)
				continue;
			uint32_t type = oni_rd32(h + 4), id = oni_rd32(h + 8);
			uint32_t fsize = oni_rd32(h + 12), psize = oni_rd32(h + 16);
			if (known_type(type) && (type == ONI_REC_END || id <= r->max_node_id) &&
			    fsize >= hsize && fsize <= ONI_MAX_FIELDS_SIZE &&
			    (uint64_t)fsize + psize <= r->file_size - (pos + i))
				return (int64_t)(pos + i);
		}
		if (n < sizeof(buf))
			break;
		pos += n - (hsize - 1); /* a header across the buffer's end is seen next time */
	}
	return 0;
}

static uint64_t frames_indexed(const struct dao_oni_reader *r)
{
	uint64_t frames = 0;
	for (uint32_t i = 0; i < r->nnodes; i++)
		frames += r->nodes[i].nframes;
	return frames;
}

/*
 * The header of the record at sc->pos, checked against the file: 0, or 1
 * where the records end (sc->tail says how: no end record, cut short, zeros),
 * or < 0 on errors.
 */
static int read_record_header(struct dao_oni_reader *r, struct scan *sc, size_t hsize,
			      struct record_header *rec)
{
	uint8_t h[ONI_RECORD_HEADER_SIZE];
	int ret;
	/* an unfinished recording: stop at the last complete record */
	if (sc->pos == r->file_size) {
		sc->tail = TAIL_NO_END;
		return 1;
	}
	if (r->file_size - sc->pos < hsize) {
		sc->tail = TAIL_CUT;
		sc->tail_need = hsize;
		return 1;
	}
	if ((ret = read_at(r, h, hsize, sc->pos)) < 0)
		return dao_error_set(sc->err, ret == -ENODATA ? -EIO : ret,
				     "%s: cannot read: %s", sc->path, strerror(-ret));
	uint32_t magic = oni_rd32(h);
	rec->type = oni_rd32(h + 4), rec->id = oni_rd32(h + 8);
	rec->fsize = oni_rd32(h + 12), rec->psize = oni_rd32(h + 16);
	if (magic != ONI_RECORD_MAGIC) {
		int z = zeros_to_end(r, sc->pos);
		if (z == 1) {
			sc->tail = TAIL_ZEROS;
			return 1;
		}
		return z < 0 ? dao_error_set(sc->err, -EIO, "%s: cannot read: %s", sc->path,
					     strerror(z == -ENODATA ? EIO : -z))
			     : CORRUPT(sc, "bad record magic 0x%08x", AT(sc), magic);
	}
	if (rec->fsize < hsize || rec->fsize > ONI_MAX_FIELDS_SIZE)
		return CORRUPT(sc, "impossible fields size %u", AT(sc), rec->fsize);
	if ((uint64_t)rec->fsize + rec->psize > r->file_size - sc->pos) {
		int64_t next = record_after(r, hsize, sc->pos + hsize);
		if (next < 0)
			return dao_error_set(sc->err, -EIO, "%s: cannot read: %s", sc->path,
					     strerror(next == -ENODATA ? EIO : (int)-next));
		if (next > 0) {
			uint64_t frames = frames_indexed(r);
			return CORRUPT(sc, "size %llu runs past the end, yet a record follows "
				       "at byte %lld: damage, not an interrupted recording; "
				       "head -c %llu keeps the %llu frame%s before it",
				       AT(sc), (unsigned long long)rec->fsize + rec->psize,
				       (long long)next, (unsigned long long)sc->pos,
				       (unsigned long long)frames, plural(frames));
		}
		sc->tail = TAIL_CUT;
		sc->tail_need = (uint64_t)rec->fsize + rec->psize;
		return 1;
	}
	if (rec->type != ONI_REC_END && rec->id > r->max_node_id)
		return CORRUPT(sc, "node id %u above the header's maximum %u", AT(sc), rec->id,
			       r->max_node_id);
	return 0;
}

/* The record's flen bytes of fields after its header, into *fields (grown as needed). */
static int read_record_fields(struct dao_oni_reader *r, struct scan *sc, size_t hsize, size_t flen,
			      uint8_t **fields, size_t *fields_cap)
{
	int ret;
	if (flen > *fields_cap) {
		uint8_t *nf = realloc(*fields, flen);
		if (!nf)
			return dao_error_set(sc->err, -ENOMEM, "out of memory reading %s", sc->path);
		*fields = nf;
		*fields_cap = flen;
	}
	if (flen && (ret = read_at(r, *fields, flen, sc->pos + hsize)) < 0)
		return dao_error_set(sc->err, -EIO, "%s: cannot read: %s", sc->path,
				     strerror(ret == -ENODATA ? EIO : -ret));
	return 0;
}

/* What a record says: nodes, their properties and frames (*ended at the end record). */
static int apply_record(struct dao_oni_reader *r, struct scan *sc, const struct record_header *rec,
			const uint8_t *fields, size_t flen, int *ended)
{
	switch (rec->type) {
	case ONI_REC_NODE_ADDED_1_0_0_4:
	case ONI_REC_NODE_ADDED_1_0_0_5:
	case ONI_REC_NODE_ADDED:
		return add_node(r, sc, rec->id, rec->type, fields, flen);
	case ONI_REC_INT_PROPERTY:
	case ONI_REC_REAL_PROPERTY:
	case ONI_REC_STRING_PROPERTY:
	case ONI_REC_GENERAL_PROPERTY:
		return add_property(r, sc, rec->type, rec->id, fields, flen);
	case ONI_REC_NEW_DATA:
		return add_frame(r, sc, rec->id, fields, flen, sc->pos + rec->fsize, rec->psize);
	case ONI_REC_NODE_REMOVED:
	case ONI_REC_NODE_DATA_BEGIN:
	case ONI_REC_NODE_STATE_READY:
	case ONI_REC_SEEK_TABLE:
		return 0;
	case ONI_REC_END:
		*ended = 1;
		return 0;
	default:
		return CORRUPT(sc, "unknown record type %u", AT(sc), rec->type);
	}
}

static int scan_records(struct dao_oni_reader *r, struct scan *sc)
{
	const size_t hsize = r->old32 ? ONI_RECORD_HEADER_SIZE_OLD32 : ONI_RECORD_HEADER_SIZE;
	uint8_t *fields = NULL;
	size_t fields_cap = 0;
	int ret = 0, ended = 0;

	sc->pos = ONI_FILE_HEADER_SIZE;
	for (sc->index = 0; !ended; sc->index++) {
		struct record_header rec = { 0 };
		if ((ret = read_record_header(r, sc, hsize, &rec)) != 0) {
			ret = ret > 0 ? 0 : ret; /* > 0: the records end before an end record */
			break;
		}
		const size_t flen = rec.fsize - hsize;
		if ((ret = read_record_fields(r, sc, hsize, flen, &fields, &fields_cap)) < 0 ||
		    (ret = apply_record(r, sc, &rec, fields, flen, &ended)) < 0)
			break;
		sc->pos += (uint64_t)rec.fsize + rec.psize;
	}
	free(fields);
	return ret;
}

/* Checks a depth node once, so reads only have to check the data itself. */
static int check_depth_node(struct dao_oni_reader *r, struct node *n, const char *path,
			    struct dao_error *err)
{
	struct dao_oni_stream_info *in = &n->info;
	if (in->width == 0 || in->height == 0 || in->width > DAO_MAX_DIMENSION ||
	    in->height > DAO_MAX_DIMENSION)
		return dao_error_set(err, -EINVAL,
				     "%s: depth node '%s' has no usable size (xnMapOutputMode "
				     "%ux%u)",
				     path, in->name, in->width, in->height);
	size_t npix = (size_t)in->width * in->height;
	if (n->nframes && npix > r->max_pixels)
		return dao_error_set(err, -EFBIG,
				     "%s: depth node '%s' is %ux%u (%zu pixels), more than the "
				     "limit of %llu pixels for decoded images",
				     path, in->name, in->width, in->height, npix,
				     (unsigned long long)r->max_pixels);
	size_t bound;
	switch (in->codec) {
	case DAO_ONI_CODEC_NONE: bound = 2 * npix; break;
	case DAO_ONI_CODEC_16Z: bound = dao_16z_bound(npix, 0); break;
	case DAO_ONI_CODEC_16ZT: bound = dao_16z_bound(npix, 1); break;
	default:
		return dao_error_set(err, -EINVAL,
				     "%s: depth node '%s' uses codec '%s', which depthao cannot "
				     "decode (it reads NONE, 16zP and 16zT)",
				     path, in->name, in->codec_fourcc);
	}
	for (uint32_t i = 0; i < n->nframes; i++) {
		uint32_t ps = n->frames[i].payload_size;
		if (ps > bound)
			return dao_error_set(err, -EINVAL,
					     "%s: frame %u of '%s' has %u bytes of data, more than a "
					     "%ux%u %s frame can hold (%zu)",
					     path, i, in->name, ps, in->width, in->height,
					     in->codec_fourcc, bound);
		/* NONE holds every pixel; one 16z byte stands for at most 60 values */
		if ((in->codec == DAO_ONI_CODEC_NONE && ps != bound) ||
		    (in->codec != DAO_ONI_CODEC_NONE && npix > 1 + 60 * (size_t)ps))
			return dao_error_set(err, -EINVAL,
					     "%s: frame %u of '%s' has %u bytes of data, too few for a "
					     "%ux%u %s frame",
					     path, i, in->name, ps, in->width, in->height,
					     in->codec_fourcc);
		if (ps > r->payload_cap)
			r->payload_cap = ps;
	}
	/* only nodes with frames need a decode buffer (a declared size alone costs nothing) */
	if (n->nframes && npix > r->pixels_cap)
		r->pixels_cap = npix;
	return 0;
}

/*
 * Checks a colour node once: decodable nodes get their largest payload into
 * the read buffer's size; others keep the reason in n->unusable (the depth
 * of the file is still readable, and opening fails only for memory).
 */
static int check_color_node(struct dao_oni_reader *r, struct node *n, const char *path,
			    struct dao_error *err)
{
	struct dao_oni_stream_info *in = &n->info;
	size_t npix = (size_t)in->width * in->height;
	size_t raw = dao_oni_color_raw_size(in->pixel_format, in->width, in->height);
	if (in->width == 0 || in->height == 0 || in->width > DAO_MAX_DIMENSION ||
	    in->height > DAO_MAX_DIMENSION) {
		snprintf(n->unusable, sizeof(n->unusable),
			 "colour node '%s' has no usable size (xnMapOutputMode %ux%u)", in->name,
			 in->width, in->height);
		return 0;
	}
	if (npix > r->max_pixels) {
		snprintf(n->unusable, sizeof(n->unusable),
			 "colour node '%s' is %ux%u, more than the limit of %llu pixels", in->name,
			 in->width, in->height, (unsigned long long)r->max_pixels);
		return 0;
	}
	/* a JPEG frame larger than the raw RGB of its size plus headers is not an image */
	size_t bound = 3 * npix + 65536;
	if (in->codec == DAO_ONI_CODEC_NONE) {
		if (!raw) {
			snprintf(n->unusable, sizeof(n->unusable),
				 "colour node '%s' has pixel format %d, which depthao cannot "
				 "convert (it reads RGB888, YUV422, YUYV, GRAY8 and JPEG)",
				 in->name, in->pixel_format);
			return 0;
		}
		bound = raw;
	} else if (in->codec != DAO_ONI_CODEC_JPEG) {
		snprintf(n->unusable, sizeof(n->unusable),
			 "colour node '%s' uses codec '%s', which depthao cannot decode (it "
			 "reads JPEG and NONE)",
			 in->name, in->codec_fourcc);
		return 0;
	}
	/* a frame that cannot be one: the colour is left out, the depth still plays */
	size_t largest = 0;
	for (uint32_t i = 0; i < n->nframes; i++) {
		uint32_t ps = n->frames[i].payload_size;
		if (ps > bound || (in->codec == DAO_ONI_CODEC_NONE && ps != bound)) {
			snprintf(n->unusable, sizeof(n->unusable),
				 "frame %u of colour node '%s' has %u bytes of data, %s %ux%u %s "
				 "frame (%zu)", i, in->name, ps,
				 ps > bound ? "more than a" : "not what a raw", in->width, in->height,
				 in->codec_fourcc, bound);
			return 0;
		}
		if (ps > largest)
			largest = ps;
	}
	if (largest > r->payload_cap)
		r->payload_cap = largest;
	if (in->codec == DAO_ONI_CODEC_JPEG && !r->jpeg && n->nframes &&
	    dao_jpeg_create(&r->jpeg) < 0)
		return dao_error_set(err, -ENOMEM, "out of memory opening %s (JPEG decoder)", path);
	return 0;
}

/* An unfinished file: the warning, or an error when not one frame is complete. */
static int recovered(struct dao_oni_reader *r, const struct scan *sc)
{
	uint64_t frames = frames_indexed(r);
	const unsigned long long at = (unsigned long long)sc->pos;
	const unsigned long long left = (unsigned long long)(r->file_size - sc->pos);
	if (frames == 0)
		return dao_error_set(sc->err, -EINVAL,
				     "%s: truncated .oni file: it ends at byte %llu before its first "
				     "complete frame (an interrupted recording with nothing to "
				     "recover)",
				     sc->path, at + (sc->tail == TAIL_ZEROS ? 0 : left));
	char detail[160];
	if (sc->tail == TAIL_NO_END)
		snprintf(detail, sizeof(detail), "it ends without an end record after %llu bytes",
			 at);
	else if (sc->tail == TAIL_CUT)
		snprintf(detail, sizeof(detail),
			 "a record cut short at byte %llu (%llu of %llu bytes) was left out", at,
			 left, (unsigned long long)sc->tail_need);
	else
		snprintf(detail, sizeof(detail), "%llu zero bytes at its end were left out", left);
	snprintf(r->warning, sizeof(r->warning),
		 "%s: the recording was not finalised (interrupted by a crash, kill or power "
		 "cut?); recovered %llu frame%s up to byte %llu: %s",
		 sc->path, (unsigned long long)frames, plural(frames), at, detail);
	return 0;
}

int dao_oni_reader_open(const char *path, struct dao_oni_reader **out, struct dao_error *err)
{
	return dao_oni_reader_open_limited(path, DAO_DEFAULT_MAX_PIXELS, out, err);
}

int dao_oni_reader_open_limited(const char *path, uint64_t max_pixels,
				struct dao_oni_reader **out, struct dao_error *err)
{
	struct dao_oni_reader *r;
	uint8_t h[ONI_FILE_HEADER_SIZE];
	int ret;

	if (!path || !out)
		return dao_error_set(err, -EINVAL, "dao_oni_reader_open: path and out are required");
	*out = NULL;
	r = calloc(1, sizeof(*r));
	if (!r)
		return dao_error_set(err, -ENOMEM, "out of memory opening %s", path);
	r->max_pixels = max_pixels ? max_pixels : DAO_DEFAULT_MAX_PIXELS;
	r->fd = dao_input_file_open(path, "recording", 0, &r->file_size, err);
	if (r->fd < 0) {
		ret = r->fd;
		free(r);
		return ret;
	}
	if (r->file_size < ONI_FILE_HEADER_SIZE || read_at(r, h, sizeof(h), 0) < 0) {
		ret = dao_error_set(err, -EINVAL,
				    "%s: not an .oni file (%llu bytes, shorter than the 24-byte "
				    "header)",
				    path, (unsigned long long)r->file_size);
		goto fail;
	}
	if (memcmp(h, "NI10", 4) != 0) {
		ret = dao_error_set(err, -EINVAL,
				    "%s: not an .oni file (starts with %02x %02x %02x %02x, "
				    "expected \"NI10\")",
				    path, h[0], h[1], h[2], h[3]);
		goto fail;
	}
	/* version {u8, u8, u16, u32}: 1.0.0.4 (oldest OpenNI reads) to 1.0.1.0 */
	uint64_t ver = ((uint64_t)h[4] << 56) | ((uint64_t)h[5] << 48) |
		       ((uint64_t)oni_rd16(h + 6) << 32) | oni_rd32(h + 8);
	const uint64_t v1004 = (1ull << 56) | 4, v1010 = (1ull << 56) | (1ull << 32);
	if (ver < v1004 || ver > v1010) {
		ret = dao_error_set(err, -EINVAL,
				    "%s: .oni format version %u.%u.%u.%u is not supported "
				    "(1.0.0.4 to 1.0.1.0 are)",
				    path, h[4], h[5], oni_rd16(h + 6), oni_rd32(h + 8));
		goto fail;
	}
	r->old32 = ver < v1010;
	r->max_node_id = oni_rd32(h + 20);

	struct scan sc = {path, 0, 0, err, TAIL_END_RECORD, 0};
	if ((ret = scan_records(r, &sc)) < 0)
		goto fail;
	if (sc.tail != TAIL_END_RECORD && (ret = recovered(r, &sc)) < 0)
		goto fail;
	for (uint32_t i = 0; i < r->nnodes; i++) {
		struct node *n = &r->nodes[i];
		n->info.frame_count = n->nframes;
		if (n->nframes) {
			n->info.first_timestamp_us = n->frames[0].timestamp_us;
			n->info.last_timestamp_us = n->frames[n->nframes - 1].timestamp_us;
		}
		if (n->info.sensor == DAO_ONI_SENSOR_DEPTH &&
		    (ret = check_depth_node(r, n, path, err)) < 0)
			goto fail;
		if (n->info.sensor == DAO_ONI_SENSOR_COLOR &&
		    (ret = check_color_node(r, n, path, err)) < 0)
			goto fail;
	}
	/* drop nodes that carry no images (the device node) from the stream list */
	uint32_t k = 0;
	for (uint32_t i = 0; i < r->nnodes; i++) {
		if (r->nodes[i].info.sensor == DAO_ONI_SENSOR_OTHER && r->nodes[i].nframes == 0) {
			free(r->nodes[i].frames);
			continue;
		}
		r->nodes[k++] = r->nodes[i];
	}
	r->nnodes = k;
	if (r->payload_cap && !(r->payload = malloc(r->payload_cap))) {
		ret = dao_error_set(err, -ENOMEM, "out of memory opening %s", path);
		goto fail;
	}
	if (r->pixels_cap && !(r->pixels = malloc(r->pixels_cap * sizeof(uint16_t)))) {
		ret = dao_error_set(err, -ENOMEM, "out of memory opening %s", path);
		goto fail;
	}
	*out = r;
	return 0;
fail:
	dao_oni_reader_close(r);
	return ret;
}

void dao_oni_reader_close(struct dao_oni_reader *r)
{
	if (!r)
		return;
	if (r->fd >= 0)
		close(r->fd);
	for (uint32_t i = 0; i < r->nnodes; i++)
		free(r->nodes[i].frames);
	free(r->nodes);
	free(r->payload);
	free(r->pixels);
	dao_jpeg_destroy(r->jpeg);
	free(r);
}

const char *dao_oni_reader_warning(const struct dao_oni_reader *r)
{
	return r && r->warning[0] ? r->warning : NULL;
}

uint32_t dao_oni_reader_stream_count(const struct dao_oni_reader *r)
{
	return r ? r->nnodes : 0;
}

const struct dao_oni_stream_info *dao_oni_reader_stream(const struct dao_oni_reader *r,
							 uint32_t index)
{
	return r && index < r->nnodes ? &r->nodes[index].info : NULL;
}

int dao_oni_reader_depth_stream(const struct dao_oni_reader *r, struct dao_error *err)
{
	for (uint32_t i = 0; r && i < r->nnodes; i++)
		if (r->nodes[i].info.sensor == DAO_ONI_SENSOR_DEPTH)
			return (int)i;
	return dao_error_set(err, -ENOENT, "the recording has no depth stream");
}

int dao_oni_reader_read_depth(struct dao_oni_reader *r, uint32_t stream, uint32_t frame,
			      struct dao_frame *out, struct dao_error *err)
{
	if (!r || stream >= r->nnodes)
		return dao_error_set(err, -EINVAL, "read_depth: no stream %u", stream);
	struct node *n = &r->nodes[stream];
	const struct dao_oni_stream_info *in = &n->info;
	if (in->sensor != DAO_ONI_SENSOR_DEPTH)
		return dao_error_set(err, -EINVAL, "stream %u ('%s') is not a depth stream",
				     stream, in->name);
	if (in->depth_unit == 0.0f)
		return dao_error_set(err, -EINVAL,
				     "depth stream '%s' has pixel format %d, which is not in "
				     "millimetres or 100 um; depthao reads only metric depth",
				     in->name, in->pixel_format);
	if (frame >= n->nframes)
		return dao_error_set(err, -EINVAL, "frame %u is past the end of '%s' (%u frames)",
				     frame, in->name, n->nframes);
	int ret = dao_frame_check(out, "oni depth output", in->width, in->height, err);
	if (ret < 0)
		return ret;
	if (out->format != DAO_PIXFMT_DEPTH16)
		return dao_error_set(err, -EINVAL, "oni depth output must be depth16, not %s",
				     dao_pixfmt_name(out->format));
	const struct frame_ref *fr = &n->frames[frame];
	if ((ret = read_at(r, r->payload, fr->payload_size, fr->payload_pos)) < 0)
		return dao_error_set(err, -EIO, "cannot read frame %u of '%s': %s", frame,
				     in->name, ret == -ENODATA ? "the file has shrunk" : strerror(-ret));
	size_t npix = (size_t)in->width * in->height;
	const char *why = "";
	if (in->codec == DAO_ONI_CODEC_NONE) {
		for (size_t i = 0; i < npix; i++)
			r->pixels[i] = oni_rd16(r->payload + 2 * i);
	} else {
		ret = in->codec == DAO_ONI_CODEC_16Z
			      ? dao_16z_decode(r->payload, fr->payload_size, r->pixels, npix, &why)
			      : dao_16zt_decode(r->payload, fr->payload_size, r->pixels, npix, &why);
		if (ret < 0)
			return dao_error_set(err, -EINVAL,
					     "frame %u of '%s' is corrupt: %s (%s, %u bytes)", frame,
					     in->name, why, in->codec_fourcc, fr->payload_size);
	}
	for (uint32_t y = 0; y < in->height; y++)
		memcpy((uint8_t *)out->data + (size_t)y * (size_t)out->stride,
		       r->pixels + (size_t)y * in->width, in->width * sizeof(uint16_t));
	out->depth_unit = in->depth_unit;
	out->timestamp_ns = fr->timestamp_us * 1000u;
	out->sequence = fr->number;
	return 0;
}

int dao_oni_reader_color_stream(const struct dao_oni_reader *r, struct dao_error *err)
{
	for (uint32_t i = 0; r && i < r->nnodes; i++)
		if (r->nodes[i].info.sensor == DAO_ONI_SENSOR_COLOR)
			return (int)i;
	return dao_error_set(err, -ENOENT, "the recording has no colour stream");
}

int dao_oni_reader_color_usable(const struct dao_oni_reader *r, uint32_t stream,
				struct dao_error *err)
{
	if (!r || stream >= r->nnodes || r->nodes[stream].info.sensor != DAO_ONI_SENSOR_COLOR)
		return dao_error_set(err, -EINVAL, "stream %u is not a colour stream", stream);
	if (r->nodes[stream].unusable[0])
		return dao_error_set(err, -ENOTSUP, "%s", r->nodes[stream].unusable);
	return 0;
}

int dao_oni_reader_read_color(struct dao_oni_reader *r, uint32_t stream, uint32_t frame,
			      struct dao_frame *out, struct dao_error *err)
{
	int ret = dao_oni_reader_color_usable(r, stream, err);
	if (ret < 0)
		return ret;
	struct node *n = &r->nodes[stream];
	const struct dao_oni_stream_info *in = &n->info;
	if (frame >= n->nframes)
		return dao_error_set(err, -EINVAL, "frame %u is past the end of '%s' (%u frames)",
				     frame, in->name, n->nframes);
	if ((ret = dao_frame_check(out, "oni colour output", in->width, in->height, err)) < 0)
		return ret;
	if (out->format != DAO_PIXFMT_RGB24)
		return dao_error_set(err, -EINVAL, "oni colour output must be rgb24, not %s",
				     dao_pixfmt_name(out->format));
	const struct frame_ref *fr = &n->frames[frame];
	if ((ret = read_at(r, r->payload, fr->payload_size, fr->payload_pos)) < 0)
		return dao_error_set(err, -EIO, "cannot read frame %u of '%s': %s", frame,
				     in->name, ret == -ENODATA ? "the file has shrunk" : strerror(-ret));
	if (in->codec == DAO_ONI_CODEC_JPEG) {
		char why[160];
		if (dao_jpeg_decode(r->jpeg, r->payload, fr->payload_size, out, why, sizeof(why)) < 0)
			return dao_error_set(err, -EINVAL, "frame %u of '%s' is corrupt: %s (%u bytes)",
					     frame, in->name, why, fr->payload_size);
	} else {
		dao_oni_color_convert_raw(in->pixel_format, r->payload, in->width, in->height, out);
	}
	out->timestamp_ns = fr->timestamp_us * 1000u;
	out->sequence = fr->number;
	return 0;
}

int dao_oni_reader_match_frame(const struct dao_oni_reader *r, uint32_t stream, uint32_t frame,
			       uint32_t other, uint32_t *match)
{
	if (!r || stream >= r->nnodes || other >= r->nnodes || !match ||
	    frame >= r->nodes[stream].nframes)
		return -EINVAL;
	const struct node *o = &r->nodes[other];
	if (!o->nframes)
		return -ENOENT;
	const uint64_t t = r->nodes[stream].frames[frame].timestamp_us;
	/* the first frame recorded after t (timestamps do not go back within a node) */
	uint32_t lo = 0, hi = o->nframes;
	while (lo < hi) {
		uint32_t mid = lo + (hi - lo) / 2;
		if (o->frames[mid].timestamp_us <= t)
			lo = mid + 1;
		else
			hi = mid;
	}
	if (lo == 0)
		*match = 0;
	else if (lo == o->nframes)
		*match = o->nframes - 1;
	else
		*match = o->frames[lo].timestamp_us - t < t - o->frames[lo - 1].timestamp_us
				 ? lo
				 : lo - 1;
	return 0;
}

const char *dao_oni_codec_name(enum dao_oni_codec codec)
{
	switch (codec) {
	case DAO_ONI_CODEC_NONE: return "none";
	case DAO_ONI_CODEC_16Z: return "16z";
	case DAO_ONI_CODEC_16ZT: return "16zt";
	case DAO_ONI_CODEC_JPEG: return "jpeg";
	case DAO_ONI_CODEC_8Z: return "8z";
	default: return "other";
	}
}

int dao_oni_codec_from_name(const char *name, enum dao_oni_codec *codec)
{
	static const struct {
		const char *name;
		enum dao_oni_codec codec;
	} names[] = {{"none", DAO_ONI_CODEC_NONE}, {"16z", DAO_ONI_CODEC_16Z},
		     {"16zp", DAO_ONI_CODEC_16Z},  {"16zt", DAO_ONI_CODEC_16ZT}};
	for (size_t i = 0; name && i < sizeof(names) / sizeof(names[0]); i++) {
		if (!strcasecmp(name, names[i].name)) {
			*codec = names[i].codec;
			return 0;
		}
	}
	return -EINVAL;
}
