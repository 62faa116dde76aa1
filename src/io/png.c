/* SPDX-License-Identifier: MIT */
/*
 * PNG reading and writing through libpng, with errors a user can act on and
 * atomic writes (temporary file + rename).
 */
#include <errno.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <png.h>

#include <depthao/png.h>

#include "core/error_internal.h"

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

/* State shared across the setjmp boundary: volatile-free by keeping it in a struct. */
struct read_state {
	FILE *fp;
	png_structp png;
	png_infop info;
	png_bytep *rows;
	struct dao_frame frame;
};

/* Releases everything in `st`, and `st` itself. */
static void read_cleanup(struct read_state *st)
{
	if (st->png)
		png_destroy_read_struct(&st->png, st->info ? &st->info : NULL, NULL);
	if (st->fp)
		fclose(st->fp);
	free(st->rows);
	free(st);
}

int dao_png_read(const char *path, struct dao_frame *out, struct dao_error *err)
{
	if (!path || !out)
		return dao_error_set(err, -EINVAL, "PNG read: path or output frame is NULL");
	memset(out, 0, sizeof *out);
	/* everything libpng may longjmp across lives on the heap, set before setjmp */
	struct read_state *const sp = calloc(1, sizeof *sp);
	if (!sp)
		return dao_error_set(err, -ENOMEM, "out of memory reading '%s'", path);
	struct read_state *const stp = sp;
#define st (*sp)
	struct png_err_ctx pe = { "" };
	st.fp = fopen(path, "rb");
	if (!st.fp) {
		free(sp);
		return open_error(err, path, "open");
	}

	unsigned char sig[8];
	size_t got = fread(sig, 1, sizeof sig, st.fp);
	if (got != sizeof sig || png_sig_cmp(sig, 0, sizeof sig)) {
		read_cleanup(sp);
		return dao_error_set(err, -EINVAL, "'%s' is not a PNG file (bad signature)", path);
	}
	st.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &pe, on_png_error, on_png_warning);
	if (st.png)
		st.info = png_create_info_struct(st.png);
	if (!st.png || !st.info) {
		read_cleanup(&st);
		return dao_error_set(err, -ENOMEM, "out of memory reading '%s'", path);
	}
	if (setjmp(png_jmpbuf(st.png))) {
		dao_frame_free(&stp->frame);
		read_cleanup(stp);
		return dao_error_set(err, -EINVAL, "'%s' is corrupt or truncated: %s", path,
				     pe.message[0] ? pe.message : "libpng error");
	}
	png_init_io(st.png, st.fp);
	png_set_sig_bytes(st.png, sizeof sig);
	png_set_user_limits(st.png, DAO_MAX_DIMENSION, DAO_MAX_DIMENSION);
	png_read_info(st.png, st.info);

	png_uint_32 w, h;
	int depth, color;
	png_get_IHDR(st.png, st.info, &w, &h, &depth, &color, NULL, NULL, NULL);
	enum dao_pixfmt fmt;
	if (color == PNG_COLOR_TYPE_GRAY && depth == 16) {
		fmt = DAO_PIXFMT_GRAY16;
		png_set_swap(st.png); /* big-endian on disk -> host order (little-endian hosts) */
	} else if (color == PNG_COLOR_TYPE_GRAY && depth <= 8) {
		fmt = DAO_PIXFMT_GRAY8;
		if (depth < 8)
			png_set_expand_gray_1_2_4_to_8(st.png);
	} else if (depth <= 8 && (color == PNG_COLOR_TYPE_RGB || color == PNG_COLOR_TYPE_PALETTE ||
				  color == PNG_COLOR_TYPE_RGB_ALPHA ||
				  color == PNG_COLOR_TYPE_GRAY_ALPHA)) {
		fmt = DAO_PIXFMT_RGB24;
		if (color == PNG_COLOR_TYPE_PALETTE)
			png_set_palette_to_rgb(st.png);
		if (color == PNG_COLOR_TYPE_GRAY_ALPHA)
			png_set_gray_to_rgb(st.png);
		if (color & PNG_COLOR_MASK_ALPHA)
			png_set_strip_alpha(st.png);
		png_set_strip_16(st.png);
	} else {
		read_cleanup(&st);
		return dao_error_set(err, -EINVAL,
				     "'%s': %d-bit PNGs of colour type %d are not supported "
				     "(use 8-bit gray/RGB or 16-bit gray)", path, depth, color);
	}
	/* png_set_swap is a no-op need on big-endian hosts: undo it there */
	{
		const uint16_t one = 1;
		if (fmt == DAO_PIXFMT_GRAY16 && *(const unsigned char *)&one == 0)
			png_set_swap(st.png);
	}
	png_read_update_info(st.png, st.info);

	int r = dao_frame_alloc(&st.frame, fmt, w, h, err);
	if (r) {
		read_cleanup(&st);
		return r;
	}
	st.rows = malloc(h * sizeof *st.rows);
	if (!st.rows) {
		dao_frame_free(&st.frame);
		read_cleanup(&st);
		return dao_error_set(err, -ENOMEM, "out of memory reading '%s'", path);
	}
	for (png_uint_32 y = 0; y < h; y++)
		st.rows[y] = (png_bytep)st.frame.data + (size_t)y * st.frame.stride;
	png_read_image(st.png, st.rows);
	png_read_end(st.png, NULL);
	*out = st.frame;
	st.frame.data = NULL;
	read_cleanup(&st);
	return 0;
#undef st
}

int dao_png_read_depth(const char *path, float depth_unit, struct dao_frame *out,
		       struct dao_error *err)
{
	if (!(depth_unit > 0.0f) || depth_unit > 1.0f)
		return dao_error_set(err, -EINVAL,
				     "depth unit %g must be in (0, 1] metres per count",
				     (double)depth_unit);
	int r = dao_png_read(path, out, err);
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

struct write_state {
	FILE *fp;
	png_structp png;
	png_infop info;
	png_bytep *rows;
};

int dao_png_write(const char *path, const struct dao_frame *f, struct dao_error *err)
{
	if (!path || !*path)
		return dao_error_set(err, -EINVAL, "PNG write: no output path");
	int r = dao_frame_check(f, "PNG output", 0, 0, err);
	if (r)
		return r;
	int color, depth;
	switch (f->format) {
	case DAO_PIXFMT_GRAY8: color = PNG_COLOR_TYPE_GRAY; depth = 8; break;
	case DAO_PIXFMT_GRAY16:
	case DAO_PIXFMT_DEPTH16: color = PNG_COLOR_TYPE_GRAY; depth = 16; break;
	case DAO_PIXFMT_RGB24: color = PNG_COLOR_TYPE_RGB; depth = 8; break;
	default:
		return dao_error_set(err, -EINVAL, "cannot write %s frames as PNG '%s'",
				     dao_pixfmt_name(f->format), path);
	}

	size_t plen = strlen(path);
	char *tmp = malloc(plen + 16);
	if (!tmp)
		return dao_error_set(err, -ENOMEM, "out of memory writing '%s'", path);
	snprintf(tmp, plen + 16, "%s.tmp-XXXXXX", path);
	int fd = mkstemp(tmp);
	if (fd < 0) {
		int e = errno;
		free(tmp);
		return dao_error_set(err, -e, "cannot create '%s': %s", path, strerror(e));
	}
	struct png_err_ctx pe = { "" };
	struct write_state *const stp = calloc(1, sizeof *stp);
	FILE *fp = stp ? fdopen(fd, "wb") : NULL;
	if (!fp) {
		int e = stp ? errno : ENOMEM;
		close(fd);
		unlink(tmp);
		free(tmp);
		free(stp);
		return dao_error_set(err, -e, "cannot write '%s': %s", path, strerror(e));
	}
#define st (*stp)
	st.fp = fp;
	st.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &pe, on_png_error, on_png_warning);
	if (st.png)
		st.info = png_create_info_struct(st.png);
	st.rows = malloc(f->height * sizeof *st.rows);
	char *const tmpv = tmp;
	if (!st.png || !st.info || !st.rows) {
		r = dao_error_set(err, -ENOMEM, "out of memory writing '%s'", path);
		goto fail;
	}
	if (setjmp(png_jmpbuf(st.png))) {
		r = dao_error_set(err, -EIO, "cannot write '%s': %s", path,
				  pe.message[0] ? pe.message : "libpng error");
		goto fail;
	}
	png_init_io(st.png, st.fp);
	png_set_IHDR(st.png, st.info, f->width, f->height, depth, color, PNG_INTERLACE_NONE,
		     PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
	png_set_compression_level(st.png, 6);
	png_write_info(st.png, st.info);
	if (depth == 16) {
		const uint16_t one = 1;
		if (*(const unsigned char *)&one == 1)
			png_set_swap(st.png); /* host little-endian -> big-endian on disk */
	}
	for (uint32_t y = 0; y < f->height; y++)
		st.rows[y] = (png_bytep)f->data + (size_t)y * f->stride;
	png_write_image(st.png, st.rows);
	png_write_end(st.png, NULL);
	png_destroy_write_struct(&st.png, &st.info);
	free(st.rows);
	st.rows = NULL;
	if (fflush(st.fp) != 0 || ferror(st.fp)) {
		int e = errno ? errno : EIO;
		r = dao_error_set(err, -e, "cannot write '%s': %s", path, strerror(e));
		goto fail;
	}
	if (fclose(st.fp) != 0) {
		int e = errno;
		st.fp = NULL;
		r = dao_error_set(err, -e, "cannot write '%s': %s", path, strerror(e));
		goto fail;
	}
	st.fp = NULL;
	/* mkstemp creates 0600; give the file the usual permissions */
	{
		mode_t mask = umask(0);
		umask(mask);
		chmod(tmp, 0666 & ~mask);
	}
	if (rename(tmp, path) != 0) {
		int e = errno;
		r = dao_error_set(err, -e, "cannot move the written PNG into place as '%s': %s", path,
				  strerror(e));
		goto fail;
	}
	free(tmp);
	free(stp);
	return 0;
#undef st

fail:
	if (stp->png)
		png_destroy_write_struct(&stp->png, stp->info ? &stp->info : NULL);
	if (stp->fp)
		fclose(stp->fp);
	free(stp->rows);
	free(stp);
	unlink(tmpv);
	free(tmpv);
	return r;
}
