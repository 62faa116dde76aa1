/* SPDX-License-Identifier: MIT */
/*
 * .oni writer: one depth node, laid out as OpenNI2's recorder lays it out
 * (node added, properties, state ready, data begin, frames, node removed,
 * seek table, end).  File format version 1.0.1.0 (64-bit positions).
 *
 * The file is written at its own name from the start and only ever grows by
 * whole records (a record that fails part-way is cut off again), so it can
 * be recovered up to its last complete frame at any moment.  Frames are
 * written with pwritev straight to the kernel (nothing waits in a user-space
 * buffer, so kill -9 loses nothing already accepted).  When a frame comes
 * DAO_ONI_SYNC_INTERVAL_MS or more after the last sync, the file is synced
 * (fdatasync), then the synced frame count and timestamps are written into
 * the node record, the data-begin record and the file header (those become
 * durable with the next sync): what they count is always on disk, so
 * OpenNI2, which trusts them, plays an unfinished file up to its last sync.
 * finish appends node-removed, seek table and end records and syncs twice
 * (tail, then header), so a power cut never leaves a header pointing at a
 * seek table that is not there.
 */
#define _DEFAULT_SOURCE /* pwritev */
#include <depthao/oni.h>

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/uio.h>
#include <time.h>
#include <unistd.h>

#include "core/clock.h"
#include "core/error_internal.h"
#include "core/math_util.h"
#include "core/sized.h"
#include "file/output_file_internal.h"
#include "file/write_fully.h"
#include "oni/codec_16z.h"
#include "oni/oni_format.h"

#define NODE_ID 1u
#define NODE_NAME "Depth1"

struct seek_entry {
	uint64_t timestamp_us, pos;
};

struct dao_oni_writer {
	int fd;
	char *path;
	struct dao_oni_writer_options o;
	float unit;
	uint32_t fourcc;
	uint64_t pos;               /* end of the last complete record */
	uint64_t node_added_pos, data_begin_pos, last_data_pos;
	uint16_t *pixels;           /* w*h, the frame in the file's unit */
	uint8_t *payload;
	size_t payload_cap;
	uint16_t *table_scratch;    /* 65536 entries, 16zT */
	struct seek_entry *seek;
	uint32_t nframes, seek_cap;
	uint32_t synced, syncs;     /* frames counted in the header; fdatasync calls */
	uint64_t first_ts, last_ts;
	uint64_t last_sync_ns;
	int failed;                 /* the error that ended the recording */
	char fail_msg[DAO_ERROR_MESSAGE_MAX]; /* ... and what was said about it */
};

/* Appends p[0..n) at w->pos (the preamble, record by record). */
static int put(struct dao_oni_writer *w, const void *p, size_t n)
{
	struct iovec v = {(void *)p, n};
	int r = dao_io_write_fully(w->fd, &v, 1, w->pos);
	if (r < 0)
		return r;
	w->pos += n;
	return 0;
}

static int patch(struct dao_oni_writer *w, uint64_t at, const uint8_t *p, size_t n)
{
	struct iovec v = {(void *)p, n};
	return dao_io_write_fully(w->fd, &v, 1, at);
}

/* Cuts off whatever a failed write left after the last complete record (best effort:
 * if this fails too, the reader drops the partial record). */
static void cut_partial(struct dao_oni_writer *w)
{
	int r = ftruncate(w->fd, (off_t)w->pos);
	(void)r;
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

/* The first struct dao_oni_writer_options that carried `size` (depthao 1.0). */
#define ONI_WRITER_OPTIONS_SIZE_FIRST DAO_END_OF(struct dao_oni_writer_options, overwrite)

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

/*
 * The frame count and timestamps in the node record, the data-begin record
 * and the file header (max timestamp); seek_pos 0 = no seek table.
 */
static int write_counts(struct dao_oni_writer *w, uint32_t frames, uint64_t seek_pos)
{
	uint8_t f[128], h[ONI_FILE_HEADER_SIZE];
	uint64_t first = frames ? w->first_ts : 0, last = frames ? w->last_ts : 0;
	size_t n = node_added_fields(w, f, frames, first, last, seek_pos);
	int r = patch(w, w->node_added_pos + ONI_RECORD_HEADER_SIZE, f, n);
	oni_wr32(f, frames);
	oni_wr64(f + 4, last);
	if (r == 0)
		r = patch(w, w->data_begin_pos + ONI_RECORD_HEADER_SIZE, f, 12);
	file_header(h, last);
	if (r == 0)
		r = patch(w, 0, h, ONI_FILE_HEADER_SIZE);
	return r;
}

static int write_preamble(struct dao_oni_writer *w)
{
	const struct dao_oni_writer_options *o = &w->o;
	uint8_t hdr[ONI_FILE_HEADER_SIZE], f[128], b[16];
	int r;

	/* counts and timestamps say "nothing synced yet" until the first sync */
	file_header(hdr, 0);
	if ((r = put(w, hdr, sizeof(hdr))) < 0)
		return r;
	w->node_added_pos = w->pos;
	size_t n = node_added_fields(w, f, 0, 0, 0, 0);
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
	oni_wr32(f, 0);
	oni_wr64(f + 4, 0);
	return put_record(w, ONI_REC_NODE_DATA_BEGIN, NODE_ID, f, 12);
}

static void writer_free(struct dao_oni_writer *w)
{
	if (w->fd >= 0)
		close(w->fd);
	free(w->path);
	free(w->pixels);
	free(w->payload);
	free(w->table_scratch);
	free(w->seek);
	free(w);
}

/* A new file's name must survive a power cut too: sync the directory it is in. */
static void sync_parent_dir(const char *path)
{
	const char *slash = strrchr(path, '/');
	char *dir = slash ? strndup(path, slash == path ? 1 : (size_t)(slash - path)) : strdup(".");
	int fd = dir ? open(dir, O_RDONLY | O_CLOEXEC) : -1;
	if (fd >= 0) {
		fsync(fd); /* best effort: some file systems refuse to sync directories */
		close(fd);
	}
	free(dir);
}

/* Creates the file (or truncates it with overwrite); regular files only. */
static int create_file(struct dao_oni_writer *w, const char *path, struct dao_error *err)
{
	struct stat st;
	int r;
	if (!strcmp(path, "-"))
		return dao_error_set(err, -EINVAL,
				     "oni writer: a recording cannot go to standard output ('-'): "
				     "its header and seek table are written last, in place; give a "
				     "file name (./- for one named '-')");
	if (stat(path, &st) == 0) {
		if (S_ISDIR(st.st_mode))
			return dao_error_set(err, -EISDIR,
					     "oni writer: %s is a directory; give the path of the .oni "
					     "file to write",
					     path);
		if (!S_ISREG(st.st_mode))
			return dao_error_set(err, -EINVAL,
					     "oni writer: %s is not a regular file (a device, FIFO or "
					     "socket); recordings are written to files",
					     path);
		if (!w->o.overwrite)
			return dao_error_set(err, -EEXIST,
					     "oni writer: %s exists; a recording never replaces a file "
					     "(pick another name, remove it, or ask to overwrite)",
					     path);
		if ((r = dao_output_file_check_replaceable(path, &st, err)) < 0)
			return r;
	}
	int flags = O_WRONLY | O_CREAT | O_CLOEXEC | (w->o.overwrite ? O_TRUNC : O_EXCL);
	w->fd = open(path, flags, 0666);
	if (w->fd < 0 && errno == EEXIST)
		return dao_error_set(err, -EEXIST,
				     "oni writer: %s exists; a recording never replaces a file (pick "
				     "another name, remove it, or ask to overwrite)",
				     path);
	if (w->fd < 0)
		return dao_error_set(err, -errno, "oni writer: cannot create %s: %s", path,
				     strerror(errno));
	if (fstat(w->fd, &st) != 0 || !S_ISREG(st.st_mode))
		return dao_error_set(err, -EINVAL, "oni writer: %s is not a regular file", path);
	sync_parent_dir(path);
	return 0;
}

int dao_oni_writer_open(const char *path, const struct dao_oni_writer_options *opts,
			struct dao_oni_writer **out, struct dao_error *err)
{
	struct dao_oni_writer *w;
	int r;

	if (!path || !opts || !out)
		return dao_error_set(err, -EINVAL, "dao_oni_writer_open: path, opts and out are required");
	*out = NULL;
	/* the caller's options, of its own size (core/sized.h) */
	struct dao_oni_writer_options o;
	if (dao_sized_copy_in(&o, sizeof o, opts, ONI_WRITER_OPTIONS_SIZE_FIRST) < 0)
		return dao_error_set(err, -EINVAL,
				     "oni writer: the options' size is %u, this library takes %zu "
				     "to %zu: start them from DAO_ONI_WRITER_OPTIONS_INIT",
				     opts->size, (size_t)ONI_WRITER_OPTIONS_SIZE_FIRST, sizeof o);
	opts = &o;
	if ((r = check_options(opts, err)) < 0)
		return r;
	w = calloc(1, sizeof(*w));
	if (!w)
		return dao_error_set(err, -ENOMEM, "out of memory");
	w->fd = -1;
	w->o = o;
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
	w->pixels = malloc(npix * sizeof(uint16_t));
	w->payload = malloc(w->payload_cap);
	if (opts->codec == DAO_ONI_CODEC_16ZT)
		w->table_scratch = malloc(65536 * sizeof(uint16_t));
	if (!w->path || !w->pixels || !w->payload ||
	    (opts->codec == DAO_ONI_CODEC_16ZT && !w->table_scratch)) {
		writer_free(w);
		return dao_error_set(err, -ENOMEM, "out of memory for a %ux%u recording",
				     opts->width, opts->height);
	}
	if ((r = create_file(w, path, err)) < 0) {
		writer_free(w);
		return r;
	}
	if ((r = write_preamble(w)) < 0) {
		dao_error_set(err, r, "oni writer: cannot write %s: %s", path, strerror(-r));
		close(w->fd);
		w->fd = -1;
		unlink(path);
		writer_free(w);
		return r;
	}
	w->last_sync_ns = dao_mono_ns();
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

/* -ENOENT if the file has no name any more: removed (or its directory) while written. */
static int check_linked(int fd)
{
	struct stat st;
	return fstat(fd, &st) == 0 && st.st_nlink == 0 ? -ENOENT : 0;
}

/*
 * fdatasync, then the frames it covers into the header (durable with the next
 * sync).  A file removed meanwhile is an error (-ENOENT): what is written into
 * it is lost with it, however well synced.
 */
static int writer_sync(struct dao_oni_writer *w)
{
	if (fdatasync(w->fd) != 0)
		return -errno;
	int r = check_linked(w->fd);
	if (r < 0)
		return r;
	w->syncs++;
	w->last_sync_ns = dao_mono_ns();
	if (w->synced == w->nframes)
		return 0;
	r = write_counts(w, w->nframes, 0);
	if (r == 0)
		w->synced = w->nframes;
	return r;
}

static int sync_due(const struct dao_oni_writer *w)
{
	return dao_mono_us_since(w->last_sync_ns) >= (int64_t)DAO_ONI_SYNC_INTERVAL_MS * 1000;
}

static const char *plural(uint32_t n)
{
	return n == 1 ? "" : "s";
}

/* Ends the recording after a failed write or sync: no more frames, the file keeps its own. */
static int fail(struct dao_oni_writer *w, int r, const char *what, struct dao_error *err)
{
	w->failed = r;
	cut_partial(w);
	if (r == -ENOENT)
		snprintf(w->fail_msg, sizeof w->fail_msg,
			 "%s was removed while being written (or its directory): its %u frame%s "
			 "went with it; the recording stops",
			 w->path, w->nframes, plural(w->nframes));
	else
		snprintf(w->fail_msg, sizeof w->fail_msg,
			 "cannot %s %s: %s; the recording stops and keeps its first %u frame%s",
			 what, w->path, strerror(-r), w->nframes, plural(w->nframes));
	return dao_error_set(err, r, "oni writer: %s", w->fail_msg);
}

/* What a call after the failure says. */
static int failed_before(const struct dao_oni_writer *w, struct dao_error *err)
{
	return dao_error_set(err, w->failed, "oni writer: an earlier write or sync failed: %s",
			     w->fail_msg);
}

int dao_oni_writer_write_depth(struct dao_oni_writer *w, const struct dao_frame *depth,
			       uint64_t timestamp_us, struct dao_error *err)
{
	int r;
	if (!w || !depth)
		return dao_error_set(err, -EINVAL, "oni writer: writer and frame are required");
	if (w->failed)
		return failed_before(w, err);
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
	record_header(h, ONI_REC_NEW_DATA, NODE_ID, ONI_RECORD_HEADER_SIZE + 12, (uint32_t)size,
		      w->last_data_pos);
	oni_wr64(h + ONI_RECORD_HEADER_SIZE, timestamp_us);
	oni_wr32(h + ONI_RECORD_HEADER_SIZE + 8, w->nframes + 1); /* frame numbers start at 1 */
	struct iovec v[2] = {{h, sizeof(h)}, {w->payload, (size_t)size}};
	if ((r = dao_io_write_fully(w->fd, v, 2, w->pos)) < 0)
		return fail(w, r, "write a frame to", err);
	w->seek[w->nframes].timestamp_us = timestamp_us;
	w->seek[w->nframes].pos = w->pos;
	w->last_data_pos = w->pos;
	w->pos += sizeof(h) + (size_t)size;
	if (w->nframes == 0)
		w->first_ts = timestamp_us;
	w->last_ts = timestamp_us;
	w->nframes++;
	/* a failed sync ends the recording, but this frame is in the file (handed to the
	 * kernel, as every frame before it): this write succeeded, the next call reports it */
	if (sync_due(w) && (r = writer_sync(w)) < 0)
		fail(w, r, "sync", NULL);
	return 0;
}

int dao_oni_writer_sync(struct dao_oni_writer *w, struct dao_error *err)
{
	if (!w)
		return dao_error_set(err, -EINVAL, "oni writer: NULL writer");
	if (w->failed)
		return failed_before(w, err);
	int r = writer_sync(w);
	return r < 0 ? fail(w, r, "sync", err) : 0;
}

int dao_oni_writer_get_status_sized(const struct dao_oni_writer *w,
				    struct dao_oni_writer_status *st, size_t size)
{
	struct dao_oni_writer_status now = {0};
	if (w) {
		now.frames = w->nframes;
		now.synced_frames = w->synced;
		now.syncs = w->syncs;
		now.bytes = w->pos;
		now.error = w->failed;
	}
	return dao_sized_copy_out(st, size, &now, sizeof now);
}

/*
 * Node removed, seek table and end record after the last frame; `with_table`
 * 0 writes only the end record (less room needed).  Returns the seek table's
 * position through *seek_pos (0 without one).
 */
static int write_tail(struct dao_oni_writer *w, int with_table, uint64_t *seek_pos)
{
	size_t n = 2 * ONI_RECORD_HEADER_SIZE +
		   (with_table ? ONI_RECORD_HEADER_SIZE + (w->nframes + 1) * ONI_SEEK_ENTRY_SIZE : 0);
	uint8_t *t = calloc(1, n), *p = t;
	if (!t)
		return -ENOMEM;
	*seek_pos = 0;
	record_header(p, ONI_REC_NODE_REMOVED, NODE_ID, ONI_RECORD_HEADER_SIZE, 0,
		      w->node_added_pos);
	p += ONI_RECORD_HEADER_SIZE;
	if (with_table) {
		*seek_pos = w->pos + ONI_RECORD_HEADER_SIZE;
		record_header(p, ONI_REC_SEEK_TABLE, NODE_ID, ONI_RECORD_HEADER_SIZE,
			      (w->nframes + 1) * ONI_SEEK_ENTRY_SIZE, 0);
		p += ONI_RECORD_HEADER_SIZE + ONI_SEEK_ENTRY_SIZE; /* entry 0: frames start at 1 */
		for (uint32_t i = 0; i < w->nframes; i++, p += ONI_SEEK_ENTRY_SIZE) {
			oni_wr64(p, w->seek[i].timestamp_us);
			oni_wr32(p + 8, 0); /* configuration id */
			oni_wr64(p + 12, w->seek[i].pos);
		}
	}
	record_header(p, ONI_REC_END, UINT32_MAX, ONI_RECORD_HEADER_SIZE, 0, 0);
	struct iovec v = {t, n};
	int r = dao_io_write_fully(w->fd, &v, 1, w->pos);
	free(t);
	if (r < 0)
		cut_partial(w);
	return r;
}

/* Closes the file and frees the writer; a file without frames is removed. */
static void writer_close(struct dao_oni_writer *w)
{
	if (w->fd >= 0) {
		close(w->fd);
		w->fd = -1;
		if (w->nframes == 0)
			unlink(w->path);
	}
	writer_free(w);
}

int dao_oni_writer_finish(struct dao_oni_writer *w, struct dao_error *err)
{
	int r;
	if (!w)
		return dao_error_set(err, -EINVAL, "oni writer: NULL writer");
	if (w->nframes == 0) {
		r = w->failed ? dao_error_set(err, w->failed,
					      "oni writer: writing %s failed (%s); nothing was recorded",
					      w->path, strerror(-w->failed))
			      : dao_error_set(err, -EINVAL,
					      "oni writer: no frames were written to %s; nothing to save",
					      w->path);
		writer_close(w);
		return r;
	}
	if (w->failed)
		cut_partial(w);
	/* the tail, synced before the header points at it; a full disk may have room for
	 * the end record alone, else the file stays unfinished with every frame counted */
	uint64_t seek_pos = 0;
	int tail = write_tail(w, 1, &seek_pos);
	if (tail < 0)
		tail = write_tail(w, 0, &seek_pos);
	if (tail == 0 && fdatasync(w->fd) != 0)
		tail = -errno;
	r = write_counts(w, w->nframes, tail == 0 ? seek_pos : 0);
	if (r == 0 && fdatasync(w->fd) != 0)
		r = -errno;
	if (close(w->fd) != 0 && r == 0 && errno != EINTR)
		r = -errno;
	w->fd = -1;
	if (tail < 0)
		r = dao_error_set(err, tail,
				  "oni writer: %s keeps %u frame%s but is not finalised: its end "
				  "could not be written (%s); depthao recovers it, OpenNI2 plays %s",
				  w->path, w->nframes, plural(w->nframes), strerror(-tail),
				  r == 0 ? "every frame" : "the frames synced before");
	else if (r < 0)
		r = dao_error_set(err, r, "oni writer: finishing %s failed: %s", w->path,
				  strerror(-r));
	writer_free(w);
	return r;
}

void dao_oni_writer_abort(struct dao_oni_writer *w)
{
	if (!w)
		return;
	if (w->fd >= 0 && w->nframes) {
		/* unfinished but whole: no partial record, every frame counted */
		if (w->failed)
			cut_partial(w);
		if (write_counts(w, w->nframes, 0) == 0 && fdatasync(w->fd) != 0)
			w->failed = -errno; /* nothing to report it to: abort has no result */
	}
	writer_close(w);
}
