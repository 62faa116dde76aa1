/* SPDX-License-Identifier: MIT */
/*
 * Built-in sink "oni": records the depth stream as an .oni file through
 * depthao's own writer.  URI: "PATH" optionally followed by
 * "?codec=none|16z|16zt" (default 16zt, what OpenNI2 records) and
 * "&overwrite=true" (a '?' that is not followed by key=value is part of the
 * file name).
 *
 * Nothing is created before the format is known: the writer is opened by
 * negotiate and the file grows at its name (see dao_oni_writer_open: synced
 * every second, recoverable after a crash); close finalises it.  A
 * recording is never written over another: when PATH exists (an earlier
 * run, a daemon restarted after a crash, a reopen after an error), it goes
 * to PATH-1.oni, PATH-2.oni, ... instead, said in the host's log, unless
 * overwrite=true.  After a write error (a full disk) the file keeps the
 * frames before it and close still finalises them; flush syncs the file.
 * A recording without frames leaves no file at all.
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

#include "core/error_internal.h"
#include "core/math_util.h"
#include "plugin/builtin.h"
#include "plugin/recorder_sink.h"

#define ONI_SINK_DEFAULT_FPS 30
#define ONI_SINK_DEFAULT_HFOV_DEG 58.5
#define ONI_SINK_DEFAULT_VFOV_DEG 45.6
#define ONI_SINK_OPTIONS_HELP "?codec=none|16z|16zt&overwrite=true|false"

struct oni_sink {
	struct dao_recorder rec;       /* the path, the file written, the host */
	enum dao_oni_codec codec;
	int overwrite;
	struct dao_oni_writer *writer; /* from negotiate on */
	uint32_t fps;
	uint64_t nframes;
	uint64_t last_ts_us;
	struct dao_oni_writer_options *opts; /* during open_writer */
};

static const char *const oni_sink_options[] = {"codec", "overwrite", NULL};

static int oni_sink_probe(const char *uri)
{
	size_t n = dao_uri_path_len(uri, oni_sink_options);
	return n > 4 && !strncasecmp(uri + n - 4, ".oni", 4) ? 50 : 0;
}

/* "codec=X&overwrite=B" after the '?'. */
static int parse_options(struct oni_sink *s, const char *opts, struct dao_error *err)
{
	/* the codecs that record depth (16zp: another name of 16z) */
	static const char *const codecs[] = {"none", "16z", "16zp", "16zt", NULL};
	static const enum dao_oni_codec codec_of[] = {DAO_ONI_CODEC_NONE, DAO_ONI_CODEC_16Z,
						      DAO_ONI_CODEC_16Z, DAO_ONI_CODEC_16ZT};
	struct dao_options *o;
	int r = dao_options_parse(&o, "oni", opts, oni_sink_options, err);
	if (r < 0)
		return r;
	int codec;
	if ((r = dao_options_get_bool(o, "overwrite", &s->overwrite, err)) >= 0 &&
	    (r = dao_options_get_enum(o, "codec", codecs, &codec, err)) > 0)
		s->codec = codec_of[codec];
	dao_options_free(o);
	return r < 0 ? r : 0;
}

static int oni_sink_open(const char *uri, void **state, struct dao_error *err)
{
	size_t n = dao_uri_path_len(uri, oni_sink_options);
	struct oni_sink *s = calloc(1, sizeof(*s));
	if (!s)
		return dao_error_set(err, -ENOMEM, "out of memory");
	s->codec = DAO_ONI_CODEC_16ZT;
	int r = dao_recorder_init(&s->rec, "oni", uri, n, ONI_SINK_OPTIONS_HELP, err);
	if (r == 0 && uri[n] == '?')
		r = parse_options(s, uri + n + 1, err);
	if (r == 0)
		r = dao_recorder_check_dir(&s->rec, 1, err);
	if (r < 0) {
		dao_recorder_free(&s->rec);
		free(s);
		return r;
	}
	*state = s;
	return 0;
}

static void oni_sink_attach_host(void *state, const struct dao_sink_host *host)
{
	struct oni_sink *s = state;
	s->rec.host = *host;
}

static int open_at(void *ctx, const char *name, int overwrite, struct dao_error *err)
{
	struct oni_sink *s = ctx;
	s->opts->overwrite = overwrite;
	return dao_oni_writer_open(name, s->opts, &s->writer, err);
}

/* Opens the writer at the path, or at the first free numbered name beside it. */
static int open_writer(struct oni_sink *s, struct dao_oni_writer_options *o,
		       struct dao_error *err)
{
	s->opts = o;
	int r = dao_recorder_open_numbered(&s->rec, s->overwrite, open_at, s, err);
	s->opts = NULL;
	if (r < 0)
		s->writer = NULL;
	return r;
}

static int oni_sink_negotiate(void *state, struct dao_sink_format *fmt, struct dao_error *err)
{
	struct oni_sink *s = state;
	if (s->writer) { /* negotiated again before the first frame: start over */
		dao_oni_writer_abort(s->writer); /* no frames: the file goes */
		s->writer = NULL;
		s->nframes = 0;
		dao_recorder_forget_file(&s->rec);
	}
	if (fmt->format != DAO_PIXFMT_DEPTH16)
		return dao_error_set(err, -ENOTSUP,
				     "oni: the oni recorder records depth, not %s; subscribe it "
				     "to the depth stream",
				     dao_pixfmt_name(fmt->format));
	struct dao_oni_writer_options o = {
		.size = sizeof(struct dao_oni_writer_options),
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
	int r = open_writer(s, &o, err);
	if (r < 0)
		return r;
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
				      (unsigned long long)s->nframes, dao_recorder_file(&s->rec),
				      strerror(-r));
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
	struct oni_sink *s = state;
	/* frames are in the file as they are written; this puts them on the disk */
	return s->writer && s->nframes ? dao_oni_writer_sync(s->writer, err) : 0;
}

static int oni_sink_close(void *state, struct dao_error *err)
{
	struct oni_sink *s = state;
	int r = 0;
	if (s->writer && s->nframes == 0)
		dao_oni_writer_abort(s->writer); /* nothing to save: no file */
	else if (s->writer)
		r = dao_oni_writer_finish(s->writer, err); /* also after a failed write */
	dao_recorder_free(&s->rec);
	free(s);
	return r;
}

const struct dao_sink_ops dao_oni_sink_ops = {
	.version = DAO_SINK_OPS_VERSION,
	.probe = oni_sink_probe,
	.open = oni_sink_open,
	.negotiate = oni_sink_negotiate,
	.write = oni_sink_write,
	.flush = oni_sink_flush,
	.close = oni_sink_close,
	.attach_host = oni_sink_attach_host,
};
