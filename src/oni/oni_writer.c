/* SPDX-License-Identifier: MIT */
/*
 * .oni writer: one depth node, laid out as OpenNI2's recorder lays it out
 * (node added, properties, state ready, data begin, frames, node removed,
 * seek table, end), with the node record, data-begin record and file header
 * patched on finish so that frame count, timestamps and the seek table
 * position are right.  File format version 1.0.1.0 (64-bit positions).
 */
#include <depthao/oni.h>

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/error_internal.h"
#include "core/file_mode.h"
#include "core/math_util.h"
#include "oni/codec_16z.h"
#include "oni/oni_format.h"

#define NODE_ID 1u
#define NODE_NAME "Depth1"

struct seek_entry {
	uint64_t timestamp_us, pos;
};

struct dao_oni_writer {
	FILE *f;
	char *path, *tmp_path;
	struct dao_oni_writer_options o;
	float unit;
	uint32_t fourcc;
	uint64_t pos;               /* bytes written so far */
	uint64_t node_added_pos, data_begin_pos, last_data_pos;
	uint16_t *pixels;           /* w*h, the frame in the file's unit */
	uint8_t *payload;
	size_t payload_cap;
	uint16_t *table_scratch;    /* 65536 entries, 16zT */
	struct seek_entry *seek;
	uint32_t nframes, seek_cap;
	uint64_t first_ts, last_ts;
	int failed;                 /* a write failed: the file is unusable */
};

static int put(struct dao_oni_writer *w, const void *p, size_t n)
{
	if (n && fwrite(p, 1, n, w->f) != n)
		return -(errno ? errno : EIO);
	w->pos += n;
	return 0;
}

static void record_header(uint8_t *h, uint32_t type, uint32_t node, uint32_t fields,
			  uint32_t payload, uint64_t undo)
{
	oni_wr32(h, ONI_RECORD_MAGIC);
	oni_wr32(h + 4, type);
	oni_wr32(h + 8, node);
	oni_wr32(h + 12, fields);
	oni_wr32(h + 16, payload);
	oni_wr64(h + 20, undo);
}

/* A record whose fields are `fields` (after the header) and no payload. */
static int put_record(struct dao_oni_writer *w, uint32_t type, uint32_t node,
		      const uint8_t *fields, size_t n)
{
	uint8_t h[ONI_RECORD_HEADER_SIZE];
	record_header(h, type, node, (uint32_t)(ONI_RECORD_HEADER_SIZE + n), 0, 0);
	int r = put(w, h, sizeof(h));
	return r < 0 ? r : put(w, fields, n);
}

static size_t put_string(uint8_t *f, const char *s)
{
	uint32_t n = (uint32_t)strlen(s) + 1;
	oni_wr32(f, n);
	memcpy(f + 4, s, n);
	return 4 + n;
}

static int put_property(struct dao_oni_writer *w, uint32_t type, const char *name,
			const void *data, uint32_t size)
{
	uint8_t f[128];
	size_t n = put_string(f, name);
	oni_wr32(f + n, size);
	memcpy(f + n + 4, data, size);
	return put_record(w, type, NODE_ID, f, n + 4 + size);
}

static int put_int(struct dao_oni_writer *w, const char *name, uint64_t v)
{
	uint8_t b[8];
	oni_wr64(b, v);
	return put_property(w, ONI_REC_INT_PROPERTY, name, b, 8);
}

static size_t node_added_fields(const struct dao_oni_writer *w, uint8_t *f, uint32_t frames,
				uint64_t min_ts, uint64_t max_ts, uint64_t seek_pos)
{
	size_t n = put_string(f, NODE_NAME);
	oni_wr32(f + n, ONI_NODE_TYPE_DEPTH);
	oni_wr32(f + n + 4, w->fourcc);
	oni_wr32(f + n + 8, frames);
	oni_wr64(f + n + 12, min_ts);
	oni_wr64(f + n + 20, max_ts);
	oni_wr64(f + n + 28, seek_pos);
	return n + 36;
}

static void file_header(uint8_t *h, uint64_t max_ts)
{
	memcpy(h, "NI10", 4);
	h[4] = 1; /* version 1.0.1.0 */
	h[5] = 0;
	oni_wr16(h + 6, 1);
	oni_wr32(h + 8, 0);
	oni_wr64(h + 12, max_ts);
	oni_wr32(h + 20, NODE_ID);
}

static int check_options(const struct dao_oni_writer_options *o, struct dao_error *err)
{
	if (o->width == 0 || o->height == 0 || o->width > DAO_MAX_DIMENSION ||
	    o->height > DAO_MAX_DIMENSION)
		return dao_error_set(err, -EINVAL, "oni writer: size %ux%u is out of range (1..%d)",
				     o->width, o->height, DAO_MAX_DIMENSION);
	if (o->fps < 1 || o->fps > 1000)
		return dao_error_set(err, -EINVAL, "oni writer: fps %u is out of range (1..1000)",
				     o->fps);
	if (o->codec != DAO_ONI_CODEC_NONE && o->codec != DAO_ONI_CODEC_16Z &&
	    o->codec != DAO_ONI_CODEC_16ZT)
		return dao_error_set(err, -EINVAL,
				     "oni writer: codec must be none, 16z or 16zt for depth");
	if (o->pixel_format != DAO_ONI_PIXEL_DEPTH_1_MM &&
	    o->pixel_format != DAO_ONI_PIXEL_DEPTH_100_UM)
		return dao_error_set(err, -EINVAL,
				     "oni writer: pixel format %d is not a depth format (use "
				     "100 for 1 mm or 101 for 100 um)",
				     o->pixel_format);
	if (!(o->hfov > 0 && o->hfov < DAO_PI) || !(o->vfov > 0 && o->vfov < DAO_PI))
		return dao_error_set(err, -EINVAL,
				     "oni writer: field of view %g x %g rad is not in (0, pi)",
				     o->hfov, o->vfov);
	if (o->max_depth > 65535)
		return dao_error_set(err, -EINVAL, "oni writer: max_depth %u exceeds 65535",
				     o->max_depth);
	return 0;
}

static int write_preamble(struct dao_oni_writer *w)
{
	const struct dao_oni_writer_options *o = &w->o;
	uint8_t hdr[ONI_FILE_HEADER_SIZE], f[128], b[16];
	int r;

	file_header(hdr, UINT64_MAX);
	if ((r = put(w, hdr, sizeof(hdr))) < 0)
		return r;
	w->node_added_pos = w->pos;
	size_t n = node_added_fields(w, f, UINT32_MAX, 0, UINT64_MAX, 0);
	if ((r = put_record(w, ONI_REC_NODE_ADDED, NODE_ID, f, n)) < 0)
		return r;
	/* the properties OpenNI2's player needs (map mode, cropping, max depth for 16zT) */
	if ((r = put_int(w, "oniRequiredFrameSize", 2ull * o->width * o->height)) < 0 ||
	    (r = put_int(w, "xnIsGenerating", 1)) < 0 ||
	    (r = put_int(w, "xnDeviceMaxDepth", o->max_depth)) < 0 ||
	    (r = put_int(w, "oniPixelFormat", (uint64_t)o->pixel_format)) < 0 ||
	    (r = put_int(w, "xnBytesPerPixel", 2)) < 0)
		return r;
	oni_wr32(b, o->width);
	oni_wr32(b + 4, o->height);
	oni_wr32(b + 8, o->fps);
	if ((r = put_property(w, ONI_REC_GENERAL_PROPERTY, "xnMapOutputMode", b, 12)) < 0)
		return r;
	memset(b, 0, sizeof(b)); /* cropping disabled */
	if ((r = put_property(w, ONI_REC_GENERAL_PROPERTY, "xnCropping", b, 12)) < 0)
		return r;
	uint64_t hf, vf;
	memcpy(&hf, &o->hfov, 8);
	memcpy(&vf, &o->vfov, 8);
	oni_wr64(b, hf);
	oni_wr64(b + 8, vf);
	if ((r = put_property(w, ONI_REC_GENERAL_PROPERTY, "xnFOV", b, 16)) < 0 ||
	    (r = put_int(w, "xnMirror", o->mirrored ? 1 : 0)) < 0)
		return r;
	if ((r = put_record(w, ONI_REC_NODE_STATE_READY, NODE_ID, NULL, 0)) < 0)
		return r;
	w->data_begin_pos = w->pos;
	oni_wr32(f, UINT32_MAX);
	oni_wr64(f + 4, UINT64_MAX);
	return put_record(w, ONI_REC_NODE_DATA_BEGIN, NODE_ID, f, 12);
}

static void writer_free(struct dao_oni_writer *w)
{
	if (w->f)
		fclose(w->f);
	free(w->path);
	free(w->tmp_path);
	free(w->pixels);
	free(w->payload);
	free(w->table_scratch);
	free(w->seek);
	free(w);
}

int dao_oni_writer_open(const char *path, const struct dao_oni_writer_options *opts,
			struct dao_oni_writer **out, struct dao_error *err)
{
	struct dao_oni_writer *w;
	int r;

	if (!path || !opts || !out)
		return dao_error_set(err, -EINVAL, "dao_oni_writer_open: path, opts and out are required");
	*out = NULL;
	if ((r = check_options(opts, err)) < 0)
		return r;
	w = calloc(1, sizeof(*w));
	if (!w)
		return dao_error_set(err, -ENOMEM, "out of memory");
	w->o = *opts;
	if (w->o.max_depth == 0)
		w->o.max_depth = opts->pixel_format == DAO_ONI_PIXEL_DEPTH_1_MM ? 10000 : 65535;
	w->unit = opts->pixel_format == DAO_ONI_PIXEL_DEPTH_1_MM ? 0.001f : 0.0001f;
	w->fourcc = opts->codec == DAO_ONI_CODEC_NONE  ? ONI_CODEC_NONE
		    : opts->codec == DAO_ONI_CODEC_16Z ? ONI_CODEC_16Z
						       : ONI_CODEC_16ZT;
	size_t npix = (size_t)opts->width * opts->height;
	w->payload_cap = opts->codec == DAO_ONI_CODEC_NONE
				 ? 2 * npix
				 : dao_16z_bound(npix, opts->codec == DAO_ONI_CODEC_16ZT);
	w->path = strdup(path);
	w->tmp_path = malloc(strlen(path) + 8);
	w->pixels = malloc(npix * sizeof(uint16_t));
	w->payload = malloc(w->payload_cap);
	if (opts->codec == DAO_ONI_CODEC_16ZT)
		w->table_scratch = malloc(65536 * sizeof(uint16_t));
	if (!w->path || !w->tmp_path || !w->pixels || !w->payload ||
	    (opts->codec == DAO_ONI_CODEC_16ZT && !w->table_scratch)) {
		writer_free(w);
		return dao_error_set(err, -ENOMEM, "out of memory for a %ux%u recording",
				     opts->width, opts->height);
	}
	sprintf(w->tmp_path, "%s.XXXXXX", path);
	int fd = mkstemp(w->tmp_path);
	if (fd < 0) {
		r = dao_error_set(err, -errno, "cannot create a file beside %s: %s", path,
				  strerror(errno));
		free(w->tmp_path);
		w->tmp_path = NULL;
		writer_free(w);
		return r;
	}
	w->f = fdopen(fd, "wb");
	if (!w->f) {
		close(fd);
		r = -errno;
	} else {
		r = write_preamble(w);
	}
	if (r < 0) {
		dao_error_set(err, r, "cannot write %s: %s", w->tmp_path, strerror(-r));
		dao_oni_writer_abort(w);
		return r;
	}
	*out = w;
	return 0;
}

/* Copies (and converts, if the units differ) a frame into w->pixels. */
static int take_frame(struct dao_oni_writer *w, const struct dao_frame *d, struct dao_error *err)
{
	const uint32_t W = w->o.width, H = w->o.height;
	double scale = 1.0;
	int convert = 0;

	if (!(d->depth_unit > 0) || !isfinite(d->depth_unit))
		return dao_error_set(err, -EINVAL, "oni writer: the frame's depth unit %g is not > 0",
				     (double)d->depth_unit);
	if (fabsf(d->depth_unit - w->unit) > 1e-6f * w->unit) {
		convert = 1;
		scale = (double)d->depth_unit / w->unit;
	}
	for (uint32_t y = 0; y < H; y++) {
		uint16_t *dst = w->pixels + (size_t)y * W;
		/* rows may be unaligned (odd strides are valid): copy, then convert in place */
		memcpy(dst, (const uint8_t *)d->data + (size_t)y * (size_t)d->stride,
		       (size_t)W * sizeof(uint16_t));
		for (uint32_t x = 0; x < W; x++) {
			double v = convert ? floor(dst[x] * scale + 0.5) : dst[x];
			if (v > w->o.max_depth)
				return dao_error_set(err, -ERANGE,
						     "oni writer: frame %u pixel (%u, %u) is %.0f counts "
						     "(%.4f m), above the recording's max depth %u",
						     w->nframes, x, y, v, v * w->unit, w->o.max_depth);
			dst[x] = (uint16_t)v;
		}
	}
	return 0;
}

int dao_oni_writer_write_depth(struct dao_oni_writer *w, const struct dao_frame *depth,
			       uint64_t timestamp_us, struct dao_error *err)
{
	int r;
	if (!w || !depth)
		return dao_error_set(err, -EINVAL, "oni writer: writer and frame are required");
	if (w->failed)
		return dao_error_set(err, w->failed,
				     "oni writer: an earlier write to %s failed (%s); the recording "
				     "cannot continue",
				     w->tmp_path, strerror(-w->failed));
	if ((r = dao_frame_check(depth, "oni writer input", w->o.width, w->o.height, err)) < 0)
		return r;
	if (depth->format != DAO_PIXFMT_DEPTH16)
		return dao_error_set(err, -EINVAL, "oni writer: frames must be depth16, not %s",
				     dao_pixfmt_name(depth->format));
	if (w->nframes && timestamp_us < w->last_ts)
		return dao_error_set(err, -EINVAL,
				     "oni writer: timestamp %llu us goes back from %llu us",
				     (unsigned long long)timestamp_us,
				     (unsigned long long)w->last_ts);
	if (w->nframes == UINT32_MAX - 1)
		return dao_error_set(err, -EFBIG, "oni writer: too many frames");
	if ((r = take_frame(w, depth, err)) < 0)
		return r;

	size_t npix = (size_t)w->o.width * w->o.height;
	long size;
	if (w->o.codec == DAO_ONI_CODEC_NONE) {
		for (size_t i = 0; i < npix; i++)
			oni_wr16(w->payload + 2 * i, w->pixels[i]);
		size = (long)(2 * npix);
	} else if (w->o.codec == DAO_ONI_CODEC_16Z) {
		size = dao_16z_encode(w->pixels, npix, w->payload, w->payload_cap);
	} else {
		size = dao_16zt_encode(w->pixels, npix, w->payload, w->payload_cap,
				       w->table_scratch);
	}
	if (size == -ERANGE)
		return dao_error_set(err, -ERANGE,
				     "oni writer: frame %u cannot be coded as %s (16z holds "
				     "counts below 32768, 16zT at most 32768 distinct values); "
				     "use the codec none",
				     w->nframes, dao_oni_codec_name(w->o.codec));
	if (size < 0)
		return dao_error_set(err, (int)size, "oni writer: encoding frame %u failed",
				     w->nframes);

	if (w->nframes == w->seek_cap) {
		uint32_t cap = w->seek_cap ? 2 * w->seek_cap : 256;
		struct seek_entry *s = realloc(w->seek, cap * sizeof(*s));
		if (!s)
			return dao_error_set(err, -ENOMEM, "out of memory");
		w->seek = s;
		w->seek_cap = cap;
	}
	uint8_t h[ONI_RECORD_HEADER_SIZE + 12];
	uint64_t pos = w->pos;
	record_header(h, ONI_REC_NEW_DATA, NODE_ID, ONI_RECORD_HEADER_SIZE + 12, (uint32_t)size,
		      w->last_data_pos);
	oni_wr64(h + ONI_RECORD_HEADER_SIZE, timestamp_us);
	oni_wr32(h + ONI_RECORD_HEADER_SIZE + 8, w->nframes + 1); /* frame numbers start at 1 */
	if ((r = put(w, h, sizeof(h))) < 0 || (r = put(w, w->payload, (size_t)size)) < 0) {
		w->failed = r; /* a partial record is in the file: no more frames, no finish */
		return dao_error_set(err, r, "cannot write %s: %s", w->tmp_path, strerror(-r));
	}
	w->seek[w->nframes].timestamp_us = timestamp_us;
	w->seek[w->nframes].pos = pos;
	w->last_data_pos = pos;
	if (w->nframes == 0)
		w->first_ts = timestamp_us;
	w->last_ts = timestamp_us;
	w->nframes++;
	return 0;
}

static int patch(struct dao_oni_writer *w, uint64_t at, const uint8_t *p, size_t n)
{
	if (fseeko(w->f, (off_t)at, SEEK_SET) < 0 || fwrite(p, 1, n, w->f) != n)
		return -(errno ? errno : EIO);
	return 0;
}

static int write_tail(struct dao_oni_writer *w)
{
	uint8_t h[ONI_RECORD_HEADER_SIZE], f[128], e[ONI_SEEK_ENTRY_SIZE];
	int r;

	record_header(h, ONI_REC_NODE_REMOVED, NODE_ID, ONI_RECORD_HEADER_SIZE, 0,
		      w->node_added_pos);
	if ((r = put(w, h, sizeof(h))) < 0)
		return r;
	uint64_t seek_pos = w->pos;
	record_header(h, ONI_REC_SEEK_TABLE, NODE_ID, ONI_RECORD_HEADER_SIZE,
		      (w->nframes + 1) * ONI_SEEK_ENTRY_SIZE, 0);
	if ((r = put(w, h, sizeof(h))) < 0)
		return r;
	memset(e, 0, sizeof(e)); /* entry 0: frame numbers start at 1 */
	if ((r = put(w, e, sizeof(e))) < 0)
		return r;
	for (uint32_t i = 0; i < w->nframes; i++) {
		oni_wr64(e, w->seek[i].timestamp_us);
		oni_wr32(e + 8, 0); /* configuration id */
		oni_wr64(e + 12, w->seek[i].pos);
		if ((r = put(w, e, sizeof(e))) < 0)
			return r;
	}
	record_header(h, ONI_REC_END, UINT32_MAX, ONI_RECORD_HEADER_SIZE, 0, 0);
	if ((r = put(w, h, sizeof(h))) < 0)
		return r;

	/* patch the node record, data-begin record and header now that all is known */
	size_t n = node_added_fields(w, f, w->nframes, w->first_ts, w->last_ts, seek_pos);
	if ((r = patch(w, w->node_added_pos + ONI_RECORD_HEADER_SIZE, f, n)) < 0)
		return r;
	oni_wr32(f, w->nframes);
	oni_wr64(f + 4, w->last_ts);
	if ((r = patch(w, w->data_begin_pos + ONI_RECORD_HEADER_SIZE, f, 12)) < 0)
		return r;
	file_header(h, w->last_ts);
	if ((r = patch(w, 0, h, ONI_FILE_HEADER_SIZE)) < 0)
		return r;
	if (fflush(w->f) != 0 || fsync(fileno(w->f)) != 0)
		return -(errno ? errno : EIO);
	return 0;
}

int dao_oni_writer_finish(struct dao_oni_writer *w, struct dao_error *err)
{
	int r;
	if (!w)
		return dao_error_set(err, -EINVAL, "oni writer: NULL writer");
	if (w->failed) {
		r = dao_error_set(err, w->failed,
				  "oni writer: an earlier write failed (%s); %s was not saved",
				  strerror(-w->failed), w->path);
		dao_oni_writer_abort(w);
		return r;
	}
	if (w->nframes == 0) {
		r = dao_error_set(err, -EINVAL,
				  "oni writer: no frames were written to %s; nothing to save",
				  w->path);
		dao_oni_writer_abort(w);
		return r;
	}
	if ((r = write_tail(w)) < 0) {
		dao_error_set(err, r, "cannot write %s: %s", w->tmp_path, strerror(-r));
		dao_oni_writer_abort(w);
		return r;
	}
	if (fclose(w->f) != 0) {
		w->f = NULL;
		r = dao_error_set(err, -(errno ? errno : EIO), "cannot write %s: %s", w->tmp_path,
				  strerror(errno));
		dao_oni_writer_abort(w);
		return r;
	}
	w->f = NULL;
	dao_file_mode_default(w->tmp_path);
	if (rename(w->tmp_path, w->path) != 0) {
		r = dao_error_set(err, -errno, "cannot rename %s to %s: %s", w->tmp_path, w->path,
				  strerror(errno));
		dao_oni_writer_abort(w);
		return r;
	}
	free(w->tmp_path);
	w->tmp_path = NULL;
	writer_free(w);
	return 0;
}

void dao_oni_writer_abort(struct dao_oni_writer *w)
{
	if (!w)
		return;
	if (w->f) {
		fclose(w->f);
		w->f = NULL;
	}
	if (w->tmp_path)
		unlink(w->tmp_path);
	writer_free(w);
}
