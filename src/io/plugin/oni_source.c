/* SPDX-License-Identifier: MIT */
/*
 * Built-in source "oni": .oni recordings through depthao's own reader, no
 * OpenNI needed.  Manual playback hands out every frame once; real-time
 * playback sleeps until each frame's recorded time has come (relative to
 * the first frame delivered); loop wraps to the first frame (or start_frame).
 * A recording that was never finished (its writer crashed) plays up to its
 * last complete frame; the reader's warning says so (info.warning).
 * With want_color, each depth frame comes with the colour frame recorded
 * nearest in time to it (dao_oni_reader_match_frame), decoded to RGB24.
 */
#include <depthao/oni.h>
#include <depthao/plugin.h>

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>

#include "core/error_internal.h"
#include "plugin/builtin.h"
#include "plugin/playback.h"

struct oni_source {
	struct dao_oni_reader *reader;
	int stream;
	struct dao_oni_stream_info info;
	char path_tail[96];
	struct dao_frame depth;
	int color_stream;           /* -1: no colour delivered */
	struct dao_oni_stream_info color_info;
	struct dao_frame color;
	char color_note[256];       /* why a recording's colour is not delivered */
	struct dao_playback_cursor play;
};

static int oni_probe(const char *uri)
{
	size_t n = strlen(uri);
	return n > 4 && !strcasecmp(uri + n - 4, ".oni") ? 60 : 0;
}

/* The colour stream, when the recording has one that can be decoded. */
static int open_color(struct oni_source *s, struct dao_error *err)
{
	struct dao_error e;
	int c = dao_oni_reader_color_stream(s->reader, &e);
	if (c < 0)
		return 0; /* depth only */
	if (dao_oni_reader_color_usable(s->reader, (uint32_t)c, &e) < 0) {
		snprintf(s->color_note, sizeof(s->color_note), "no colour: %.240s", e.message);
		return 0;
	}
	const struct dao_oni_stream_info *ci = dao_oni_reader_stream(s->reader, (uint32_t)c);
	if (ci->frame_count == 0) {
		snprintf(s->color_note, sizeof(s->color_note),
			 "no colour: the colour stream '%s' has no frames", ci->name);
		return 0;
	}
	int r = dao_frame_alloc(&s->color, DAO_PIXFMT_RGB24, ci->width, ci->height, err);
	if (r < 0)
		return r;
	s->color_info = *ci;
	s->color_stream = c;
	return 0;
}

int dao_oni_source_open(const char *uri, const struct dao_source_options *opts,
			uint64_t max_pixels, void **state, struct dao_error *err)
{
	struct oni_source *s = calloc(1, sizeof(*s));
	int r;
	if (!s)
		return dao_error_set(err, -ENOMEM, "out of memory");
	if ((r = dao_oni_reader_open_limited(uri, max_pixels, &s->reader, err)) < 0)
		goto fail;
	if ((r = dao_oni_reader_depth_stream(s->reader, err)) < 0) {
		r = dao_error_set(err, -EINVAL, "%s: the recording has no depth stream", uri);
		goto fail;
	}
	s->stream = r;
	s->info = *dao_oni_reader_stream(s->reader, (uint32_t)s->stream);
	if (s->info.frame_count == 0) {
		r = dao_error_set(err, -EINVAL, "%s: the depth stream '%s' has no frames", uri,
				  s->info.name);
		goto fail;
	}
	if (s->info.depth_unit == 0.0f) {
		r = dao_error_set(err, -EINVAL,
				  "%s: depth pixel format %d is not metric (1 mm or 100 um)", uri,
				  s->info.pixel_format);
		goto fail;
	}
	if (opts->start_frame >= s->info.frame_count) {
		r = dao_error_set(err, -EINVAL,
				  "%s: start frame %u is past the end (the recording has %u frames)",
				  uri, opts->start_frame, s->info.frame_count);
		goto fail;
	}
	if ((r = dao_frame_alloc(&s->depth, DAO_PIXFMT_DEPTH16, s->info.width, s->info.height,
				 err)) < 0)
		goto fail;
	s->color_stream = -1;
	if (opts->want_color && (r = open_color(s, err)) < 0)
		goto fail;
	const char *base = strrchr(uri, '/');
	snprintf(s->path_tail, sizeof(s->path_tail), "%s", base ? base + 1 : uri);
	dao_playback_init(&s->play, opts, s->info.frame_count);
	*state = s;
	return 0;
fail:
	dao_frame_free(&s->depth);
	dao_frame_free(&s->color);
	dao_oni_reader_close(s->reader);
	free(s);
	return r;
}

static int oni_open(const char *uri, const struct dao_source_options *opts, void **state,
		    struct dao_error *err)
{
	return dao_oni_source_open(uri, opts, DAO_DEFAULT_MAX_PIXELS, state, err);
}

static void oni_get_info(void *state, struct dao_source_info *in)
{
	struct oni_source *s = state;
	in->width = s->info.width;
	in->height = s->info.height;
	in->format = DAO_PIXFMT_DEPTH16;
	in->depth_unit = s->info.depth_unit;
	in->has_fov = s->info.has_fov;
	in->hfov = s->info.hfov;
	in->vfov = s->info.vfov;
	in->fps = s->info.fps;
	in->frame_count = s->info.frame_count;
	in->live = 0;
	in->mirrored = s->info.mirrored;
	in->registered = s->info.registered;
	in->has_color = s->color_stream >= 0;
	if (in->has_color) {
		in->color_width = s->color_info.width;
		in->color_height = s->color_info.height;
		snprintf(in->description, sizeof(in->description),
			 "%.60s: %.30s %ux%u@%u %s + %.20s %ux%u %s, %u frames", s->path_tail,
			 s->info.name, s->info.width, s->info.height, s->info.fps,
			 s->info.codec_fourcc, s->color_info.name, s->color_info.width,
			 s->color_info.height, s->color_info.codec_fourcc, s->info.frame_count);
	} else {
		snprintf(in->description, sizeof(in->description),
			 "%.60s: %.40s %ux%u@%u %s, %u frames", s->path_tail, s->info.name,
			 s->info.width, s->info.height, s->info.fps, s->info.codec_fourcc,
			 s->info.frame_count);
	}
	const char *w = dao_oni_reader_warning(s->reader); /* an unfinished recording */
	if (w)
		snprintf(in->warning, sizeof(in->warning), "%s", w);
	else if (s->color_note[0])
		snprintf(in->warning, sizeof(in->warning), "%.250s", s->color_note);
}

static int oni_start(void *state, struct dao_error *err)
{
	struct oni_source *s = state;
	dao_playback_restart(&s->play);
	return 0;
}

static int oni_read(void *state, struct dao_source_frame *f, int timeout_ms,
		    struct dao_error *err)
{
	struct oni_source *s = state;
	uint64_t i;
	int r = dao_playback_next(&s->play, &i, err);
	if (r)
		return r;
	if ((r = dao_oni_reader_read_depth(s->reader, (uint32_t)s->stream, (uint32_t)i, &s->depth,
					   err)) < 0)
		return dao_playback_skip(&s->play, r, err);
	if ((r = dao_playback_pace(&s->play, s->depth.timestamp_ns / 1000, timeout_ms)) < 0)
		return r;
	f->color.format = DAO_PIXFMT_NONE;
	if (s->color_stream >= 0) {
		uint32_t c;
		if (dao_oni_reader_match_frame(s->reader, (uint32_t)s->stream, (uint32_t)i,
					       (uint32_t)s->color_stream, &c) < 0)
			r = dao_error_set(err, -EINVAL, "no colour frame");
		else
			r = dao_oni_reader_read_color(s->reader, (uint32_t)s->color_stream, c,
						      &s->color, err);
		if (r < 0) /* skipped like a corrupt depth frame */
			return dao_playback_skip(&s->play, r, err);
		f->color = s->color;
	}
	f->depth = s->depth;
	f->index = dao_playback_advance(&s->play);
	return 0;
}

static int oni_seek(void *state, uint64_t index, struct dao_error *err)
{
	struct oni_source *s = state;
	if (index >= s->info.frame_count)
		return dao_error_set(err, -EINVAL, "seek to frame %llu: the recording has %u frames",
				     (unsigned long long)index, s->info.frame_count);
	dao_playback_seek(&s->play, index);
	return 0;
}

static void oni_close(void *state)
{
	struct oni_source *s = state;
	dao_frame_free(&s->depth);
	dao_frame_free(&s->color);
	dao_oni_reader_close(s->reader);
	free(s);
}

static const struct dao_source_ops oni_source_ops = {
	.version = DAO_SOURCE_OPS_VERSION,
	.probe = oni_probe,
	.open = oni_open,
	.get_info = oni_get_info,
	.start = oni_start,
	.read = oni_read,
	.seek = oni_seek,
	.close = oni_close,
};

const struct dao_plugin dao_builtin_oni_plugin = {
	DAO_PLUGIN_HEADER,
	.name = "oni",
	.description = ".oni recordings (depth: NONE, 16zP, 16zT; colour: JPEG, RGB, YUV) "
		       "through depthao's own reader and writer",
	.source = &oni_source_ops,
	.sink = &dao_oni_sink_ops,
};
