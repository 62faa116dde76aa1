/* SPDX-License-Identifier: MIT */
/*
 * Built-in source "images": one 16-bit depth PNG, or every *.png of a
 * directory in byte order of their names, as a recording of frame_count
 * frames (unit from the options, 0.001 by default; no field of view: PNG
 * files do not carry one).  Frames are decoded on read; all must have the
 * size of the first.  Real-time playback paces them as a recording at
 * 30 fps (frame i at i/30 s; with a step, every step-th of them).
 */
#include <depthao/plugin.h>
#include <depthao/png.h>

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <time.h>

#include "core/error_internal.h"
#include "plugin/builtin.h"
#include "plugin/playback.h"

#define IMAGES_REALTIME_FPS 30

struct images_source {
	char **paths;
	uint32_t count;
	float unit;
	uint64_t max_pixels;
	uint32_t width, height;
	struct dao_frame frame; /* the last frame read (owned) */
	struct dao_playback_cursor play;
	char description[160];
};

static int is_png_name(const char *name)
{
	size_t n = strlen(name);
	return n > 4 && !strcasecmp(name + n - 4, ".png");
}

static int is_dir(const char *path)
{
	struct stat st;
	return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

static int images_probe(const char *uri)
{
	return is_png_name(uri) || is_dir(uri) ? 30 : 0;
}

static int cmp_paths(const void *a, const void *b)
{
	return strcmp(*(char *const *)a, *(char *const *)b);
}

static void free_paths(struct images_source *s)
{
	for (uint32_t i = 0; i < s->count; i++)
		free(s->paths[i]);
	free(s->paths);
	s->paths = NULL;
	s->count = 0;
}

static int add_path(struct images_source *s, const char *dir, const char *name)
{
	char **p = realloc(s->paths, (s->count + 1) * sizeof(*p));
	if (!p)
		return -ENOMEM;
	s->paths = p;
	size_t len = (dir ? strlen(dir) + 1 : 0) + strlen(name) + 1;
	if (!(p[s->count] = malloc(len)))
		return -ENOMEM;
	if (dir)
		snprintf(p[s->count], len, "%s/%s", dir, name);
	else
		snprintf(p[s->count], len, "%s", name);
	s->count++;
	return 0;
}

static int list_dir(struct images_source *s, const char *dir, struct dao_error *err)
{
	DIR *d = opendir(dir);
	if (!d)
		return dao_error_set(err, -errno, "cannot open directory %s: %s", dir, strerror(errno));
	struct dirent *e;
	int r = 0;
	while (r == 0 && (e = readdir(d)))
		if (e->d_name[0] != '.' && is_png_name(e->d_name))
			r = add_path(s, dir, e->d_name);
	closedir(d);
	if (r < 0)
		return dao_error_set(err, r, "out of memory listing %s", dir);
	if (s->count == 0)
		return dao_error_set(err, -ENOENT, "no *.png files in %s", dir);
	qsort(s->paths, s->count, sizeof(*s->paths), cmp_paths);
	return 0;
}

static int read_frame(struct images_source *s, uint32_t i, struct dao_error *err)
{
	dao_frame_free(&s->frame);
	int r = dao_png_read_depth_limited(s->paths[i], s->unit, s->max_pixels, &s->frame, err);
	if (r < 0)
		return r;
	if (s->width && (s->frame.width != s->width || s->frame.height != s->height))
		return dao_error_set(err, -EINVAL, "%s is %ux%u, but the sequence is %ux%u",
				     s->paths[i], s->frame.width, s->frame.height, s->width,
				     s->height);
	s->frame.sequence = i + 1;
	s->frame.timestamp_ns = (uint64_t)i * 1000000000u / IMAGES_REALTIME_FPS;
	return 0;
}

int dao_images_source_open(const char *uri, const struct dao_source_options *opts,
			   uint64_t max_pixels, void **state, struct dao_error *err)
{
	struct images_source *s = calloc(1, sizeof(*s));
	int r;
	if (!s)
		return dao_error_set(err, -ENOMEM, "out of memory");
	s->max_pixels = max_pixels;
	s->unit = opts->depth_unit > 0 ? opts->depth_unit : 0.001f;
	if (!(opts->depth_unit >= 0 && opts->depth_unit <= 1)) {
		r = dao_error_set(err, -EINVAL, "images: depth unit %g is not in (0, 1] metres",
				  (double)opts->depth_unit);
		goto fail;
	}
	if (is_dir(uri))
		r = list_dir(s, uri, err);
	else if (is_png_name(uri))
		r = add_path(s, NULL, uri) < 0 ? dao_error_set(err, -ENOMEM, "out of memory") : 0;
	else
		r = dao_error_set(err, -EINVAL, "images: %s is neither a directory nor a .png file",
				  uri);
	if (r < 0)
		goto fail;
	if (opts->start_frame >= s->count) {
		r = dao_error_set(err, -EINVAL, "images: start frame %u is past the end (%u images)",
				  opts->start_frame, s->count);
		goto fail;
	}
	/* the first image fixes the size */
	if ((r = read_frame(s, 0, err)) < 0)
		goto fail;
	s->width = s->frame.width;
	s->height = s->frame.height;
	dao_frame_free(&s->frame);
	snprintf(s->description, sizeof(s->description), "%.100s: %u depth PNG%s, %ux%u", uri,
		 s->count, s->count == 1 ? "" : "s", s->width, s->height);
	dao_playback_init(&s->play, opts, s->count);
	*state = s;
	return 0;
fail:
	free_paths(s);
	dao_frame_free(&s->frame);
	free(s);
	return r;
}

static int images_open(const char *uri, const struct dao_source_options *opts, void **state,
		       struct dao_error *err)
{
	return dao_images_source_open(uri, opts, DAO_DEFAULT_MAX_PIXELS, state, err);
}

static void images_get_info(void *state, struct dao_source_info *in)
{
	struct images_source *s = state;
	in->width = s->width;
	in->height = s->height;
	in->format = DAO_PIXFMT_DEPTH16;
	in->depth_unit = s->unit;
	in->fps = 0;
	in->frame_count = s->count;
	snprintf(in->description, sizeof(in->description), "%s", s->description);
}

static int images_start(void *state, struct dao_error *err)
{
	struct images_source *s = state;
	(void)err;
	dao_playback_restart(&s->play);
	return 0;
}

static int images_read(void *state, struct dao_source_frame *f, int timeout_ms,
		       struct dao_error *err)
{
	struct images_source *s = state;
	uint64_t i;
	int r = dao_playback_next(&s->play, &i, err);
	if (r)
		return r;
	if ((r = read_frame(s, (uint32_t)i, err)) < 0) /* a bad image is skipped */
		return dao_playback_skip(&s->play, r, err);
	if ((r = dao_playback_pace(&s->play, s->frame.timestamp_ns / 1000, timeout_ms)) < 0)
		return r;
	f->depth = s->frame;
	f->color.format = DAO_PIXFMT_NONE;
	f->index = dao_playback_advance(&s->play);
	return 0;
}

static int images_seek(void *state, uint64_t index, struct dao_error *err)
{
	struct images_source *s = state;
	if (index >= s->count)
		return dao_error_set(err, -EINVAL, "seek to frame %llu: there are %u images",
				     (unsigned long long)index, s->count);
	dao_playback_seek(&s->play, index);
	return 0;
}

static void images_close(void *state)
{
	struct images_source *s = state;
	free_paths(s);
	dao_frame_free(&s->frame);
	free(s);
}

static const struct dao_source_ops images_source_ops = {
	.version = DAO_SOURCE_OPS_VERSION,
	.probe = images_probe,
	.open = images_open,
	.get_info = images_get_info,
	.start = images_start,
	.read = images_read,
	.seek = images_seek,
	.close = images_close,
};

const struct dao_plugin dao_builtin_images_plugin = {
	DAO_PLUGIN_HEADER,
	.name = "images",
	.description = "a 16-bit depth PNG or a directory of them (name order); "
		       "writes DIR/NNNNNN.png",
	.source = &images_source_ops,
	.sink = &dao_images_sink_ops,
};
