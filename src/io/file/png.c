/* SPDX-License-Identifier: MIT */
/*
 * PNG reading and writing through libpng, with errors a user can act on and
 * atomic writes (temporary file + rename; FIFOs and character devices are
 * written straight into, see depthao/output_file.h).
 */
#include <errno.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <png.h>
#include <zlib.h>

#include <depthao/png.h>

#include "core/error_internal.h"
#include "file/output_file_internal.h"

struct png_err_ctx {
	char message[160];
};


static void on_png_error(png_structp png, png_const_charp msg)
{
	struct png_err_ctx *e = png_get_error_ptr(png);
	snprintf(e->message, sizeof e->message, "%s", msg);
	png_longjmp(png, 1);
}

static void on_png_warning(png_structp png, png_const_charp msg)
{
	(void)png;
	(void)msg; /* warnings (e.g. unknown chunks) do not stop reading */
}

static int open_error(struct dao_error *err, const char *path, const char *verb)
{
	int e = errno;
	return dao_error_set(err, -e, "cannot %s '%s': %s", verb, path, strerror(e));
}

/*
 * Everything libpng may longjmp across lives in one heap block whose address
 * is fixed before setjmp, so no automatic variable changes between setjmp and
 * longjmp (C11 7.13.2.1).
 */
struct read_state {
	FILE *fp;
	png_structp png;
	png_infop info;
	png_bytep *rows;
	struct dao_frame frame;
	uint64_t max_pixels;
	struct png_err_ctx pe;
};

/* Releases everything in `st`, and `st` itself. */
static void read_cleanup(struct read_state *st)
{
	if (st->png)
		png_destroy_read_struct(&st->png, st->info ? &st->info : NULL, NULL);
	if (st->fp)
		fclose(st->fp);
	free(st->rows);
	dao_frame_free(&st->frame);
	free(st);
}

/* Picks the frame format for a PNG layout and sets up libpng's conversions. */
static int choose_format(png_structp png, int depth, int color, enum dao_pixfmt *fmt)
{
	if (color == PNG_COLOR_TYPE_GRAY && depth == 16) {
		*fmt = DAO_PIXFMT_GRAY16;
		const uint16_t one = 1;
		if (*(const unsigned char *)&one == 1)
			png_set_swap(png); /* big-endian on disk -> little-endian host */
		return 0;
	}
	if (color == PNG_COLOR_TYPE_GRAY && depth <= 8) {
		*fmt = DAO_PIXFMT_GRAY8;
		if (depth < 8)
			png_set_expand_gray_1_2_4_to_8(png);
		return 0;
	}
	if (depth <= 8 && (color == PNG_COLOR_TYPE_RGB || color == PNG_COLOR_TYPE_PALETTE ||
			   color == PNG_COLOR_TYPE_RGB_ALPHA || color == PNG_COLOR_TYPE_GRAY_ALPHA)) {
		*fmt = DAO_PIXFMT_RGB24;
		if (color == PNG_COLOR_TYPE_PALETTE)
			png_set_palette_to_rgb(png);
		if (color == PNG_COLOR_TYPE_GRAY_ALPHA)
			png_set_gray_to_rgb(png);
		if (color & PNG_COLOR_MASK_ALPHA)
			png_set_strip_alpha(png);
		return 0;
	}
	return -1;
}

int dao_png_read_limited(const char *path, uint64_t max_pixels, struct dao_frame *out,
			 struct dao_error *err)
{
	if (!path || !out)
		return dao_error_set(err, -EINVAL, "PNG read: path or output frame is NULL");
	memset(out, 0, sizeof *out);
	struct read_state *const st = calloc(1, sizeof *st);
	if (!st)
		return dao_error_set(err, -ENOMEM, "out of memory reading '%s'", path);
	st->max_pixels = max_pixels ? max_pixels : DAO_DEFAULT_MAX_PIXELS;
	int fd = dao_input_file_open(path, "PNG file", 0, NULL, err);
	if (fd < 0) {
		free(st);
		return fd;
	}
	if (!(st->fp = fdopen(fd, "rb"))) {
		int r = open_error(err, path, "read");
		close(fd);
		free(st);
		return r;
	}
	unsigned char sig[8];
	if (fread(sig, 1, sizeof sig, st->fp) != sizeof sig || png_sig_cmp(sig, 0, sizeof sig)) {
		read_cleanup(st);
		return dao_error_set(err, -EINVAL, "'%s' is not a PNG file (bad signature)", path);
	}
	st->png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &st->pe, on_png_error, on_png_warning);
	if (st->png)
		st->info = png_create_info_struct(st->png);
	if (!st->png || !st->info) {
		read_cleanup(st);
		return dao_error_set(err, -ENOMEM, "out of memory reading '%s'", path);
	}
	if (setjmp(png_jmpbuf(st->png))) {
		int r = dao_error_set(err, -EINVAL, "'%s' is corrupt or truncated: %s", path,
				      st->pe.message[0] ? st->pe.message : "libpng error");
		read_cleanup(st);
		return r;
	}
	png_init_io(st->png, st->fp);
	png_set_sig_bytes(st->png, sizeof sig);
	png_set_user_limits(st->png, DAO_MAX_DIMENSION, DAO_MAX_DIMENSION);
	png_read_info(st->png, st->info);

	png_uint_32 w, h;
	int depth, color;
	png_get_IHDR(st->png, st->info, &w, &h, &depth, &color, NULL, NULL, NULL);
	if ((uint64_t)w * h > st->max_pixels) { /* before anything of the image's size exists */
		int r = dao_error_set(err, -EFBIG,
				      "'%s' is %ux%u (%llu pixels), more than the limit of %llu "
				      "pixels for decoded images",
				      path, (unsigned)w, (unsigned)h, (unsigned long long)w * h,
				      (unsigned long long)st->max_pixels);
		read_cleanup(st);
		return r;
	}
	enum dao_pixfmt fmt;
	if (choose_format(st->png, depth, color, &fmt)) {
		read_cleanup(st);
		return dao_error_set(err, -EINVAL,
				     "'%s': %d-bit PNGs of colour type %d are not supported "
				     "(use 8-bit gray/RGB or 16-bit gray)", path, depth, color);
	}
	png_read_update_info(st->png, st->info);
	int r = dao_frame_alloc(&st->frame, fmt, w, h, err);
	if (!r && !(st->rows = malloc(h * sizeof *st->rows)))
		r = dao_error_set(err, -ENOMEM, "out of memory reading '%s'", path);
	if (r) {
		read_cleanup(st);
		return r;
	}
	for (png_uint_32 y = 0; y < h; y++)
		st->rows[y] = (png_bytep)st->frame.data + (size_t)y * st->frame.stride;
	png_read_image(st->png, st->rows);
	png_read_end(st->png, NULL);
	*out = st->frame;
	st->frame.data = NULL; /* now the caller's */
	read_cleanup(st);
	return 0;
}

int dao_png_read(const char *path, struct dao_frame *out, struct dao_error *err)
{
	return dao_png_read_limited(path, DAO_DEFAULT_MAX_PIXELS, out, err);
}

int dao_png_read_depth_limited(const char *path, float depth_unit, uint64_t max_pixels,
			       struct dao_frame *out, struct dao_error *err)
{
	if (!(depth_unit > 0.0f) || depth_unit > 1.0f)
		return dao_error_set(err, -EINVAL,
				     "depth unit %g must be in (0, 1] metres per count",
				     (double)depth_unit);
	int r = dao_png_read_limited(path, max_pixels, out, err);
	if (r)
		return r;
	if (out->format != DAO_PIXFMT_GRAY16) {
		const char *what = out->format == DAO_PIXFMT_GRAY8 ? "8-bit gray" : "8-bit colour";
		dao_frame_free(out);
		return dao_error_set(err, -EINVAL,
				     "'%s' is %s, but a depth image must be a single-channel 16-bit PNG",
				     path, what);
	}
	out->format = DAO_PIXFMT_DEPTH16;
	out->depth_unit = depth_unit;
	return 0;
}

int dao_png_read_depth(const char *path, float depth_unit, struct dao_frame *out,
		       struct dao_error *err)
{
	return dao_png_read_depth_limited(path, depth_unit, DAO_DEFAULT_MAX_PIXELS, out, err);
}

struct write_state {
	int compression, color, depth;
	FILE *fp;
	png_structp png;
	png_infop info;
	png_bytep *rows;
	struct dao_output_file out; /* a temporary file renamed into place, or a stream */
	struct png_err_ctx pe;
};

/* Releases everything in `st` (removing the temporary file unless committed), and `st`. */
static void write_cleanup(struct write_state *st)
{
	if (st->png)
		png_destroy_write_struct(&st->png, st->info ? &st->info : NULL);
	if (st->fp)
		fclose(st->fp);
	else if (st->out.fd >= 0)
		close(st->out.fd);
	dao_output_file_abandon(&st->out);
	free(st->rows);
	free(st);
}

static int png_layout(enum dao_pixfmt format, int *color, int *depth)
{
	switch (format) {
	case DAO_PIXFMT_GRAY8: *color = PNG_COLOR_TYPE_GRAY; *depth = 8; return 0;
	case DAO_PIXFMT_GRAY16:
	case DAO_PIXFMT_DEPTH16: *color = PNG_COLOR_TYPE_GRAY; *depth = 16; return 0;
	case DAO_PIXFMT_RGB24: *color = PNG_COLOR_TYPE_RGB; *depth = 8; return 0;
	default: return -1;
	}
}

/*
 * The encoder settings of a compression level (see png.h and
 * docs/perf/png-output.md for the measurements behind them): one filter for every row instead of
 * libpng's adaptive choice, which tries all five per row and cost more time
 * than the deflate itself at level 1; at level 1 zlib's run-length matching
 * for gray images (AO maps: runs of equal bytes, noise between them that
 * longer matches do not find; twice as fast for 16 bits and no larger), but
 * not for RGB, where it made files 50 % larger, nor for depth (DEPTH16: smooth
 * surfaces, which the Up filter leaves as small repeating differences that longer
 * matches find: 2.6x faster and 4.6x smaller on clean depth, 1.1x and 1.6x on
 * noisy depth without it; docs/perf/png-output.md, "Depth").
 */
static void set_compression(png_structp png, int compression, int color, enum dao_pixfmt format)
{
	png_set_compression_level(png, compression);
	png_set_filter(png, PNG_FILTER_TYPE_BASE, compression ? PNG_FILTER_UP : PNG_FILTER_NONE);
	if (compression == 1 && color == PNG_COLOR_TYPE_GRAY && format != DAO_PIXFMT_DEPTH16)
		png_set_compression_strategy(png, Z_RLE);
}

int dao_png_write(const char *path, const struct dao_frame *f, struct dao_error *err)
{
	return dao_png_write_compressed(path, f, DAO_PNG_COMPRESSION_DEFAULT, err);
}

/* Checks the compression and the frame, and finds its PNG layout; 0 or -EINVAL. */
static int check_write(const char *what, const struct dao_frame *f, int compression, int *color,
		       int *depth, struct dao_error *err)
{
	if (compression < 0 || compression > 9)
		return dao_error_set(err, -EINVAL,
				     "PNG compression %d for %s is not in 0..9 (0 = none, 1 = "
				     "fastest, 9 = smallest)", compression, what);
	int r = dao_frame_check(f, "PNG output", 0, 0, err);
	if (r)
		return r;
	if (png_layout(f->format, color, depth))
		return dao_error_set(err, -EINVAL, "cannot write %s frames as PNG %s",
				     dao_pixfmt_name(f->format), what);
	return 0;
}

/*
 * The header and every row of `f` into st->png, whose output is set; 0, or
 * -1 after a libpng error (st->pe.message says which).  The setjmp is here,
 * with nothing in this frame that changes after it.
 */
static int encode_image(struct write_state *st, const struct dao_frame *f)
{
	if (setjmp(png_jmpbuf(st->png)))
		return -1;
	png_set_IHDR(st->png, st->info, f->width, f->height, st->depth, st->color,
		     PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
	set_compression(st->png, st->compression, st->color, f->format);
	png_write_info(st->png, st->info);
	const uint16_t one = 1;
	if (st->depth == 16 && *(const unsigned char *)&one == 1)
		png_set_swap(st->png); /* little-endian host -> big-endian on disk */
	for (uint32_t y = 0; y < f->height; y++)
		st->rows[y] = (png_bytep)f->data + (size_t)y * f->stride;
	png_write_image(st->png, st->rows);
	png_write_end(st->png, NULL);
	return 0;
}

/*
 * A write_state for `f` (checked: check_write()) with its rows and the
 * libpng structs; NULL when out of memory.
 */
static struct write_state *write_state_new(const struct dao_frame *f, int compression, int color,
					   int depth)
{
	struct write_state *st = calloc(1, sizeof *st);
	if (!st)
		return NULL;
	st->out.fd = -1;
	st->compression = compression;
	st->color = color;
	st->depth = depth;
	if ((st->rows = malloc(f->height * sizeof *st->rows)) &&
	    (st->png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &st->pe, on_png_error,
					       on_png_warning)) &&
	    (st->info = png_create_info_struct(st->png)))
		return st;
	write_cleanup(st);
	return NULL;
}

int dao_png_write_compressed(const char *path, const struct dao_frame *f, int compression,
			     struct dao_error *err)
{
	if (!path || !*path)
		return dao_error_set(err, -EINVAL, "PNG write: no output path");
	char what[64];
	snprintf(what, sizeof what, "'%.60s'", path);
	int color = 0, depth = 0;
	int r = check_write(what, f, compression, &color, &depth, err);
	if (r)
		return r;
	struct write_state *const st = write_state_new(f, compression, color, depth);
	if (!st)
		return dao_error_set(err, -ENOMEM, "out of memory writing '%s'", path);
	if ((r = dao_output_file_begin(&st->out, path, err)) < 0) {
		write_cleanup(st);
		return r;
	}
	if (!(st->fp = fdopen(st->out.fd, "wb"))) {
		r = dao_error_set(err, -errno, "cannot write '%s': %s", path, strerror(errno));
		write_cleanup(st);
		return r;
	}
	png_init_io(st->png, st->fp);
	if (encode_image(st, f) < 0) {
		/* a failed fwrite (a full disk) left its errno; libpng only says "Write Error" */
		int e = st->fp && ferror(st->fp) && errno ? errno : EIO;
		if (e != EIO)
			r = dao_error_set(err, -e, "cannot write '%s': %s", path, strerror(e));
		else
			r = dao_error_set(err, -EIO, "cannot write '%s': %s", path,
					  st->pe.message[0] ? st->pe.message : "libpng error");
		write_cleanup(st);
		return r;
	}

	/* flush and close before the rename, so a full disk shows up here */
	FILE *fp = st->fp;
	st->fp = NULL;
	if (fflush(fp) != 0 || ferror(fp)) {
		int e = errno ? errno : EIO;
		fclose(fp);
		st->out.fd = -1;
		write_cleanup(st);
		return dao_error_set(err, -e, "cannot write '%s': %s", path, strerror(e));
	}
	int closed = fclose(fp);
	int e = errno;
	st->out.fd = -1;
	if (closed != 0) {
		write_cleanup(st);
		return dao_error_set(err, -e, "cannot write '%s': %s", path, strerror(e));
	}
	r = dao_output_file_finish(&st->out, path, err);
	write_cleanup(st);
	return r;
}

/* The growing buffer of dao_png_encode(). */
struct mem_out {
	unsigned char *data;
	size_t len, cap;
	int failed;
};

static void mem_append(png_structp png, png_bytep data, png_size_t len)
{
	struct mem_out *m = png_get_io_ptr(png);
	if (m->failed)
		return;
	if (len > m->cap - m->len) {
		size_t cap = (m->cap ? m->cap * 2 : 65536) + len;
		unsigned char *d = realloc(m->data, cap);
		if (!d) {
			m->failed = 1;
			return;
		}
		m->data = d;
		m->cap = cap;
	}
	memcpy(m->data + m->len, data, len);
	m->len += len;
}

static void mem_flush(png_structp png)
{
	(void)png;
}

int dao_png_encode(const struct dao_frame *f, int compression, void **data, size_t *size,
		   struct dao_error *err)
{
	if (!data || !size)
		return dao_error_set(err, -EINVAL, "PNG encode: no place for the result");
	*data = NULL;
	*size = 0;
	int color = 0, depth = 0;
	int r = check_write("in memory", f, compression, &color, &depth, err);
	if (r)
		return r;
	struct write_state *const st = write_state_new(f, compression, color, depth);
	struct mem_out *const m = calloc(1, sizeof *m);
	if (!st || !m) {
		if (st)
			write_cleanup(st);
		free(m);
		return dao_error_set(err, -ENOMEM, "out of memory encoding a PNG");
	}
	png_set_write_fn(st->png, m, mem_append, mem_flush);
	if (encode_image(st, f) < 0) {
		r = dao_error_set(err, -EIO, "cannot encode a PNG: %s",
				  st->pe.message[0] ? st->pe.message : "libpng error");
		write_cleanup(st);
		free(m->data);
		free(m);
		return r;
	}
	write_cleanup(st);
	if (m->failed) {
		free(m->data);
		free(m);
		return dao_error_set(err, -ENOMEM, "out of memory encoding a PNG");
	}
	*data = m->data;
	*size = m->len;
	free(m);
	return 0;
}
