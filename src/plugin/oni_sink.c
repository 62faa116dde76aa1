/* SPDX-License-Identifier: MIT */
/*
 * Built-in sink "oni": records the depth stream as an .oni file through
 * depthao's own writer.  URI: "PATH" optionally followed by
 * "?codec=none|16z|16zt" (default 16zt, what OpenNI2 records; a '?' that
 * is not followed by key=value is part of the file name).
 *
 * Nothing is created before the format is known: the writer is opened by
 * negotiate, writes under a temporary name beside PATH and renames it into
 * place at close.  A recording without frames leaves no file at all.
 *
 * What goes into the file:
 *   - depth unit 0.0001 m -> pixel format "100 um", anything else "1 mm"
 *     (the writer converts counts when a frame's unit differs);
 *   - max depth 65535 counts, so far pixels are never an error;
 *   - the frame rate rounded to an integer 1..1000 (30 if unknown);
 *   - the field of view, or, when the source does not know it, the
 *     PrimeSense/Kinect default of 58.5 x 45.6 degrees (OpenNI2 players
 *     need one; it is what a file from such a camera would say);
 *   - timestamps from frame->timestamp_ns; frames without one (0) get
 *     sequence * 1e6 / fps microseconds; a timestamp that goes backwards is
 *     clamped to the previous one (the format requires them monotonic).
 */
#include <depthao/oni.h>
#include <depthao/plugin.h>

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error_internal.h"
#include "core/math_util.h"
#include "plugin/builtin.h"

#define ONI_SINK_DEFAULT_FPS 30
#define ONI_SINK_DEFAULT_HFOV_DEG 58.5
#define ONI_SINK_DEFAULT_VFOV_DEG 45.6
#define ONI_SINK_OPTIONS_HELP "?codec=none|16z|16zt"

struct oni_sink {
	char *path;
	enum dao_oni_codec codec;
	struct dao_oni_writer *writer; /* from negotiate on */
	uint32_t fps;
	uint64_t nframes;
	uint64_t last_ts_us;
};

/* Length of the path part of a URI: up to the last '?' if options ("k=v") follow. */
static size_t path_len(const char *uri)
{
	const char *q = strrchr(uri, '?');
	return q && strchr(q, '=') ? (size_t)(q - uri) : strlen(uri);
}

static int oni_sink_probe(const char *uri)
{
	size_t n = path_len(uri);
	return n > 4 && !strncasecmp(uri + n - 4, ".oni", 4) ? 50 : 0;
}

/* "codec=X[&...]" after the '?'. */
static int parse_options(struct oni_sink *s, const char *uri, const char *opts,
			 struct dao_error *err)
{
	char *copy = strdup(opts), *save = NULL;
	int r = 0;
	if (!copy)
		return dao_error_set(err, -ENOMEM, "out of memory");
	for (char *kv = strtok_r(copy, "&", &save); kv && r == 0; kv = strtok_r(NULL, "&", &save)) {
		char *v = strchr(kv, '=');
		if (v)
			*v++ = '\0';
		if (strcmp(kv, "codec") != 0) {
			r = dao_error_set(err, -EINVAL,
					  "oni: unknown option '%s' in '%s'; the recorder takes "
					  ONI_SINK_OPTIONS_HELP,
					  kv, uri);
		} else if (!v || dao_oni_codec_from_name(v, &s->codec) < 0 ||
			   (s->codec != DAO_ONI_CODEC_NONE && s->codec != DAO_ONI_CODEC_16Z &&
			    s->codec != DAO_ONI_CODEC_16ZT)) {
			r = dao_error_set(err, -EINVAL,
					  "oni: codec '%s' in '%s' cannot record depth; use none, "
					  "16z or 16zt",
					  v ? v : "", uri);
		}
	}
	free(copy);
	return r;
}

/* The directory a file would go to must exist and be writable. */
static int check_dir(const char *path, struct dao_error *err)
{
	struct stat st;
	if (stat(path, &st) == 0 && S_ISDIR(st.st_mode))
		return dao_error_set(err, -EISDIR,
				     "oni: %s is a directory; give the path of the .oni file "
				     "to write",
				     path);
	const char *slash = strrchr(path, '/');
	char *dir = slash ? strndup(path, slash == path ? 1 : (size_t)(slash - path)) : strdup(".");
	if (!dir)
		return dao_error_set(err, -ENOMEM, "out of memory");
	int r = 0;
	if (access(dir, W_OK | X_OK) != 0)
		r = dao_error_set(err, -errno, "oni: cannot record to %s: directory %s: %s", path,
				  dir, strerror(errno));
	free(dir);
	return r;
}

static int oni_sink_open(const char *uri, void **state, struct dao_error *err)
{
	int r;
	size_t n = path_len(uri);
	if (n == 0)
		return dao_error_set(err, -EINVAL,
				     "oni: no output file given; use oni:PATH.oni" ONI_SINK_OPTIONS_HELP);
	struct oni_sink *s = calloc(1, sizeof(*s));
	if (!s || !(s->path = strndup(uri, n))) {
		free(s);
		return dao_error_set(err, -ENOMEM, "out of memory");
	}
	s->codec = DAO_ONI_CODEC_16ZT;
	if (uri[n] == '?' && (r = parse_options(s, uri, uri + n + 1, err)) < 0)
		goto fail;
	if ((r = check_dir(s->path, err)) < 0)
		goto fail;
	*state = s;
	return 0;
fail:
	free(s->path);
	free(s);
	return r;
}

static int oni_sink_negotiate(void *state, struct dao_sink_format *fmt, struct dao_error *err)
{
	struct oni_sink *s = state;
	if (s->writer) { /* negotiated again before the first frame: start over */
		dao_oni_writer_abort(s->writer);
		s->writer = NULL;
		s->nframes = 0;
	}
	if (fmt->format != DAO_PIXFMT_DEPTH16)
		return dao_error_set(err, -ENOTSUP,
				     "oni: the oni recorder records depth, not %s; subscribe it "
				     "to the depth stream",
				     dao_pixfmt_name(fmt->format));
	struct dao_oni_writer_options o = {
		.width = fmt->width,
		.height = fmt->height,
		.codec = s->codec,
		.pixel_format = fabsf(fmt->depth_unit - 0.0001f) < 1e-7f ? DAO_ONI_PIXEL_DEPTH_100_UM
									  : DAO_ONI_PIXEL_DEPTH_1_MM,
		.max_depth = 65535,
		.mirrored = fmt->mirrored != 0,
	};
	double fps = fmt->fps > 0 ? floor(fmt->fps + 0.5) : ONI_SINK_DEFAULT_FPS;
	o.fps = fps < 1 ? 1 : fps > 1000 ? 1000 : (uint32_t)fps;
	if (fmt->has_fov) {
		o.hfov = fmt->hfov;
		o.vfov = fmt->vfov;
	} else {
		o.hfov = ONI_SINK_DEFAULT_HFOV_DEG * DAO_PI / 180;
		o.vfov = ONI_SINK_DEFAULT_VFOV_DEG * DAO_PI / 180;
	}
	int r = dao_oni_writer_open(s->path, &o, &s->writer, err);
	if (r < 0) {
		s->writer = NULL;
		return r;
	}
	s->fps = o.fps;
	return 0;
}

static int oni_sink_write(void *state, const struct dao_frame *frame, struct dao_error *err)
{
	struct oni_sink *s = state;
	struct dao_error e;
	if (!s->writer)
		return dao_error_set(err, -EINVAL, "oni: write before negotiate");
	uint64_t ts = frame->timestamp_ns ? frame->timestamp_ns / 1000
					  : frame->sequence * 1000000 / s->fps;
	if (s->nframes && ts < s->last_ts_us)
		ts = s->last_ts_us;
	dao_error_clear(&e);
	int r = dao_oni_writer_write_depth(s->writer, frame, ts, &e);
	if (r < 0) {
		if (e.code != r) /* the writer returned without a message */
			dao_error_set(&e, r, "oni: writing frame %llu to %s failed: %s",
				      (unsigned long long)s->nframes, s->path, strerror(-r));
		if (err)
			*err = e;
		return r;
	}
	s->nframes++;
	s->last_ts_us = ts;
	return 0;
}

static int oni_sink_flush(void *state, struct dao_error *err)
{
	(void)state;
	(void)err;
	return 0; /* the writer flushes (and syncs) every frame */
}

static int oni_sink_close(void *state, struct dao_error *err)
{
	struct oni_sink *s = state;
	int r = 0;
	if (s->writer && s->nframes == 0)
		dao_oni_writer_abort(s->writer); /* nothing to save: no file */
	else if (s->writer)
		r = dao_oni_writer_finish(s->writer, err);
	free(s->path);
	free(s);
	return r;
}

const struct dao_sink_ops dao_oni_sink_ops = {
	.probe = oni_sink_probe,
	.open = oni_sink_open,
	.negotiate = oni_sink_negotiate,
	.write = oni_sink_write,
	.flush = oni_sink_flush,
	.close = oni_sink_close,
};
