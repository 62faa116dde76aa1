/* SPDX-License-Identifier: MIT */
/*
 * Built-in sink "images": every frame as DIR/NNNNNN.png, NNNNNN the frame's
 * sequence number zero-padded to six digits (more digits past 999999).
 * GRAY8 and RGB24 are 8-bit PNGs, GRAY16 and DEPTH16 16-bit grey (depth in
 * counts, the unit is not stored: read them back with the same unit).  The
 * directory is created, with missing parents, when the sink is opened.
 * dao_png_write() writes a temporary file and renames it, so a reader of the
 * directory never sees a half-written image.
 */
#include <depthao/plugin.h>
#include <depthao/png.h>

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/error_internal.h"
#include "plugin/builtin.h"

struct images_sink {
	char *dir;
	char *path; /* dir + "/" + name, reused for every frame */
	size_t path_cap;
};

static int is_dir(const char *path)
{
	struct stat st;
	return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

static int images_sink_probe(const char *uri)
{
	/* an existing directory; anything else only as "images:DIR" */
	return is_dir(uri) ? 20 : 0;
}

/* mkdir -p: creates `path` and its missing parents. */
static int make_dirs(char *path, struct dao_error *err)
{
	for (char *p = path + 1;; p++) {
		if (*p != '/' && *p != '\0')
			continue;
		char c = *p;
		*p = '\0';
		int r = mkdir(path, 0777) == 0 || errno == EEXIST ? 0 : -errno;
		if (r < 0) {
			dao_error_set(err, r, "images: cannot create directory %s: %s", path,
				      strerror(-r));
			*p = c;
			return r;
		}
		*p = c;
		if (c == '\0')
			return 0;
	}
}

static int images_sink_open(const char *uri, void **state, struct dao_error *err)
{
	struct stat st;
	int r;
	if (!*uri)
		return dao_error_set(err, -EINVAL,
				     "images: no output directory given; use images:DIR");
	struct images_sink *s = calloc(1, sizeof(*s));
	if (!s || !(s->dir = strdup(uri))) {
		free(s);
		return dao_error_set(err, -ENOMEM, "out of memory");
	}
	size_t n = strlen(s->dir);
	while (n > 1 && s->dir[n - 1] == '/') /* "out/" -> "out", "/" stays */
		s->dir[--n] = '\0';
	if (stat(s->dir, &st) == 0) {
		if (!S_ISDIR(st.st_mode)) {
			r = dao_error_set(err, -ENOTDIR,
					  "images: %s exists and is not a directory; give a "
					  "directory (new or existing) for the PNG files",
					  s->dir);
			goto fail;
		}
	} else if ((r = make_dirs(s->dir, err)) < 0) {
		goto fail;
	}
	s->path_cap = n + 32; /* "/" + up to 20 digits + ".png" */
	if (!(s->path = malloc(s->path_cap))) {
		r = dao_error_set(err, -ENOMEM, "out of memory");
		goto fail;
	}
	*state = s;
	return 0;
fail:
	free(s->dir);
	free(s);
	return r;
}

static int images_sink_negotiate(void *state, struct dao_sink_format *fmt,
				 struct dao_error *err)
{
	(void)state;
	switch (fmt->format) {
	case DAO_PIXFMT_GRAY8:
	case DAO_PIXFMT_GRAY16:
	case DAO_PIXFMT_RGB24:
	case DAO_PIXFMT_DEPTH16:
		return 0;
	case DAO_PIXFMT_GRAY_F32:
		fmt->format = DAO_PIXFMT_GRAY16;
		return 0;
	case DAO_PIXFMT_DEPTH_F32:
		fmt->format = DAO_PIXFMT_DEPTH16;
		return 0;
	case DAO_PIXFMT_NORMAL_F32:
		fmt->format = DAO_PIXFMT_RGB24;
		return 0;
	default:
		return dao_error_set(err, -ENOTSUP,
				     "images: cannot write %s frames; it takes gray8, gray16, "
				     "rgb24 and depth16",
				     dao_pixfmt_name(fmt->format));
	}
}

static int images_sink_write(void *state, const struct dao_frame *frame, struct dao_error *err)
{
	struct images_sink *s = state;
	snprintf(s->path, s->path_cap, "%s/%06llu.png", s->dir,
		 (unsigned long long)frame->sequence);
	return dao_png_write(s->path, frame, err);
}

static int images_sink_flush(void *state, struct dao_error *err)
{
	(void)state;
	(void)err;
	return 0; /* every image is complete (renamed into place) when write returns */
}

static int images_sink_close(void *state, struct dao_error *err)
{
	struct images_sink *s = state;
	(void)err;
	free(s->path);
	free(s->dir);
	free(s);
	return 0;
}

const struct dao_sink_ops dao_images_sink_ops = {
	.probe = images_sink_probe,
	.open = images_sink_open,
	.negotiate = images_sink_negotiate,
	.write = images_sink_write,
	.flush = images_sink_flush,
	.close = images_sink_close,
};
