/* SPDX-License-Identifier: MIT */
/*
 * Built-in sink "images": every frame as DIR/NNNNNN.png, NNNNNN the frame's
 * sequence number zero-padded to six digits (more digits past 999999).
 * GRAY8 and RGB24 are 8-bit PNGs, GRAY16 and DEPTH16 16-bit grey (depth in
 * counts, the unit is not stored: read them back with the same unit).  The
 * directory is created, with missing parents, when the sink is opened.
 * dao_png_write() writes a temporary file and renames it, so a reader of the
 * directory never sees a half-written image.
 *
 * Options after the directory, "DIR?compression=N&keep=N" (a '?' not
 * followed by key=value is part of the name):
 *   compression=0..9  zlib level (default DAO_PNG_COMPRESSION_DEFAULT, 1)
 *   keep=N            at most N of the sink's files in DIR: once a new one
 *                     is written the oldest are removed.  The sink's files
 *                     are the regular files whose name is exactly what it
 *                     would write ("%06llu.png" of a number); nothing else
 *                     in DIR is touched.  Those already there when the sink
 *                     opens (an earlier run) count, oldest by modification
 *                     time, and go first.
 */
#include <depthao/plugin.h>
#include <depthao/png.h>

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error_internal.h"
#include "plugin/builtin.h"
#include "plugin/keep_list.h"

#define IMAGES_SINK_OPTIONS_HELP "?compression=0..9&keep=N"
#define IMAGES_SINK_MAX_KEEP 10000000

struct images_sink {
	char *dir;
	char *path; /* dir + "/" + name, reused for every frame */
	char *old;  /* the same for the file being removed */
	size_t path_cap;
	int compression;
	uint32_t keep;           /* 0 = keep everything */
	struct keep_list files;  /* with keep: the sink's files in DIR, oldest first */
};

static const char *const images_options[] = {"compression", "keep", NULL};

/* "compression=N&keep=N" in any order; 0 or -EINVAL with a message. */
static int parse_options(struct images_sink *s, const char *opts, struct dao_error *err)
{
	struct dao_options *o;
	int r = dao_options_parse(&o, "images", opts, images_options, err);
	if (r < 0)
		return r;
	int64_t level, keep;
	if ((r = dao_options_get_int(o, "compression", 0, 9, &level, err)) > 0)
		s->compression = (int)level; /* 0 = none, 1 = fastest, the default; 9 = smallest */
	if (r >= 0 && (r = dao_options_get_int(o, "keep", 1, IMAGES_SINK_MAX_KEEP, &keep, err)) > 0)
		s->keep = (uint32_t)keep;
	dao_options_free(o);
	return r < 0 ? r : 0;
}

/* The number of a name the sink writes ("%06llu.png"), or -1 for any other name. */
static int own_number(const char *name, uint64_t *num)
{
	size_t digits = strspn(name, "0123456789");
	if (digits < 6 || digits > 20 || strcmp(name + digits, ".png"))
		return -1;
	char *end;
	errno = 0;
	unsigned long long n = strtoull(name, &end, 10);
	char again[32];
	snprintf(again, sizeof again, "%06llu.png", n);
	if (errno || strcmp(again, name))
		return -1; /* "0000012.png", or out of range */
	*num = n;
	return 0;
}

struct found {
	uint64_t num;
	int64_t mtime_ns;
};

static int by_age(const void *a, const void *b)
{
	const struct found *x = a, *y = b;
	if (x->mtime_ns != y->mtime_ns)
		return x->mtime_ns < y->mtime_ns ? -1 : 1;
	return x->num < y->num ? -1 : x->num > y->num;
}

/* Removes the oldest of the sink's files until at most `keep` are left. */
static int trim_files(struct images_sink *s, struct dao_error *err)
{
	uint64_t num;
	while (keep_list_count(&s->files) > s->keep && keep_list_pop_oldest(&s->files, &num)) {
		snprintf(s->old, s->path_cap, "%s/%06llu.png", s->dir, (unsigned long long)num);
		if (unlink(s->old) < 0 && errno != ENOENT)
			return dao_error_set(err, -errno,
					     "images: cannot remove %s to keep %u files: %s", s->old,
					     s->keep, strerror(errno));
	}
	return 0;
}

/* The sink's files already in DIR, oldest first, then trimmed to `keep`. */
static int scan_files(struct images_sink *s, struct dao_error *err)
{
	DIR *d = opendir(s->dir);
	if (!d)
		return dao_error_set(err, -errno, "images: cannot list %s: %s", s->dir,
				     strerror(errno));
	struct found *list = NULL;
	size_t n = 0, cap = 0;
	struct dirent *e;
	int r = 0;
	while ((e = readdir(d))) {
		struct stat st;
		uint64_t num;
		if (own_number(e->d_name, &num) < 0)
			continue;
		snprintf(s->old, s->path_cap, "%s/%s", s->dir, e->d_name);
		if (lstat(s->old, &st) < 0 || !S_ISREG(st.st_mode))
			continue; /* gone meanwhile, or a link or directory: not the sink's */
		if (n == cap) {
			cap = cap ? 2 * cap : 256;
			struct found *l = realloc(list, cap * sizeof(*l));
			if (!l) {
				r = dao_error_set(err, -ENOMEM, "out of memory");
				break;
			}
			list = l;
		}
		list[n].num = num;
		list[n].mtime_ns = (int64_t)st.st_mtim.tv_sec * 1000000000 + st.st_mtim.tv_nsec;
		n++;
	}
	closedir(d);
	if (r == 0) {
		if (n)
			qsort(list, n, sizeof(*list), by_age);
		for (size_t i = 0; i < n && r == 0; i++)
			if (keep_list_touch(&s->files, list[i].num) < 0)
				r = dao_error_set(err, -ENOMEM, "out of memory");
	}
	free(list);
	return r < 0 ? r : trim_files(s, err);
}

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

static void free_sink(struct images_sink *s)
{
	keep_list_free(&s->files);
	free(s->path);
	free(s->old);
	free(s->dir);
	free(s);
}

static int images_sink_open(const char *uri, void **state, struct dao_error *err)
{
	struct stat st;
	int r;
	size_t n = dao_uri_path_len(uri, images_options);
	if (n == 0)
		return dao_error_set(err, -EINVAL,
				     "images: no output directory given; use images:DIR"
				     IMAGES_SINK_OPTIONS_HELP);
	struct images_sink *s = calloc(1, sizeof(*s));
	if (!s || !(s->dir = strndup(uri, n))) {
		free(s);
		return dao_error_set(err, -ENOMEM, "out of memory");
	}
	s->compression = DAO_PNG_COMPRESSION_DEFAULT;
	keep_list_init(&s->files);
	if (!strcmp(s->dir, "-")) {
		r = dao_error_set(err, -EINVAL,
				  "images: '-' (standard output) cannot hold a directory of PNG "
				  "files; give a directory (./- for one named '-')");
		goto fail;
	}
	if (uri[n] == '?' && (r = parse_options(s, uri + n + 1, err)) < 0)
		goto fail;
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
	s->path_cap = n + 300; /* "/" + a file name (up to 255 bytes when scanning) */
	if (!(s->path = malloc(s->path_cap)) || !(s->old = malloc(s->path_cap))) {
		r = dao_error_set(err, -ENOMEM, "out of memory");
		goto fail;
	}
	if (s->keep && (r = scan_files(s, err)) < 0)
		goto fail;
	*state = s;
	return 0;
fail:
	free_sink(s);
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
	int r = dao_png_write_compressed(s->path, frame, s->compression, err);
	if (r < 0 || !s->keep)
		return r;
	if (keep_list_touch(&s->files, frame->sequence) < 0)
		return dao_error_set(err, -ENOMEM, "images: out of memory tracking the files to keep");
	return trim_files(s, err);
}

static int images_sink_flush(void *state, struct dao_error *err)
{
	(void)state;
	(void)err;
	return 0; /* every image is complete (renamed into place) when write returns */
}

static int images_sink_close(void *state, struct dao_error *err)
{
	(void)err;
	free_sink(state);
	return 0;
}

const struct dao_sink_ops dao_images_sink_ops = {
	.version = DAO_SINK_OPS_VERSION,
	.probe = images_sink_probe,
	.open = images_sink_open,
	.negotiate = images_sink_negotiate,
	.write = images_sink_write,
	.flush = images_sink_flush,
	.close = images_sink_close,
};
