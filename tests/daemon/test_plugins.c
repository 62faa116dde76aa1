/* SPDX-License-Identifier: MIT */
/*
 * Plugins for the daemon tests, built from this file with -DTEST_PLUGIN=n:
 *   1: source "testsrc" - a live synthetic camera: "testsrc:fps=200,fail_after=20,w=64,h=48"
 *      delivers a moving box at `fps` and, after `fail_after` frames, reports the
 *      device as gone (-ENODEV) once per open, as an unplugged sensor would.
 *   2: sink "slowsink" - "slowsink:MS" takes MS milliseconds per frame.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <depthao/plugin.h>

#define EXPORT __attribute__((visibility("default")))

static void sleep_ms(long ms)
{
	struct timespec d = {ms / 1000, (ms % 1000) * 1000000};
	while (nanosleep(&d, &d) < 0 && errno == EINTR)
		;
}

static int no_probe(const char *uri)
{
	(void)uri;
	return 0;
}

#if TEST_PLUGIN == 1
struct src {
	unsigned w, h, fps, fail_after, delivered;
	uint16_t *pixels;
};

static int src_open(const char *uri, const struct dao_source_options *o, void **state,
		    struct dao_error *err)
{
	(void)o;
	struct src *s = calloc(1, sizeof(*s));
	if (!s)
		return -ENOMEM;
	s->w = 64;
	s->h = 48;
	s->fps = 100;
	char buf[256];
	snprintf(buf, sizeof buf, "%s", uri);
	for (char *tok = strtok(buf, ","); tok; tok = strtok(NULL, ",")) {
		unsigned v;
		if (sscanf(tok, "fps=%u", &v) == 1)
			s->fps = v;
		else if (sscanf(tok, "fail_after=%u", &v) == 1)
			s->fail_after = v;
		else if (sscanf(tok, "w=%u", &v) == 1)
			s->w = v;
		else if (sscanf(tok, "h=%u", &v) == 1)
			s->h = v;
	}
	s->pixels = malloc((size_t)s->w * s->h * 2);
	if (!s->pixels || !s->fps) {
		if (err)
			snprintf(err->message, sizeof err->message, "testsrc: bad options '%s'", uri);
		free(s->pixels);
		free(s);
		return -EINVAL;
	}
	*state = s;
	return 0;
}

static void src_info(void *state, struct dao_source_info *in)
{
	struct src *s = state;
	in->width = s->w;
	in->height = s->h;
	in->format = DAO_PIXFMT_DEPTH16;
	in->depth_unit = 0.001f;
	in->has_fov = 1;
	in->hfov = 1.0;
	in->vfov = 0.8;
	in->fps = s->fps;
	in->frame_count = -1;
	in->live = 1;
	snprintf(in->description, sizeof in->description, "testsrc %ux%u@%u", s->w, s->h, s->fps);
}

static int src_start(void *state, struct dao_error *err)
{
	(void)state;
	(void)err;
	return 0;
}

static int src_read(void *state, struct dao_source_frame *f, int timeout_ms, struct dao_error *err)
{
	struct src *s = state;
	(void)timeout_ms;
	if (s->fail_after && s->delivered >= s->fail_after) {
		if (err)
			snprintf(err->message, sizeof err->message, "testsrc: unplugged after %u frames",
				 s->delivered);
		return -ENODEV;
	}
	sleep_ms(1000 / s->fps);
	unsigned bx = s->delivered % (s->w / 2);
	for (unsigned y = 0; y < s->h; y++)
		for (unsigned x = 0; x < s->w; x++)
			s->pixels[y * s->w + x] =
				(uint16_t)(x >= bx && x < bx + s->w / 4 && y > s->h / 3 ? 900 : 1500);
	f->depth = (struct dao_frame){DAO_PIXFMT_DEPTH16, s->w, s->h, (int32_t)(2 * s->w), s->pixels,
				      0.001f, 0, s->delivered + 1};
	f->index = s->delivered++;
	return 0;
}

static void src_stop(void *state)
{
	(void)state;
}

static void src_close(void *state)
{
	struct src *s = state;
	free(s->pixels);
	free(s);
}

static const struct dao_source_ops ops = {
	.probe = no_probe, .open = src_open, .get_info = src_info, .start = src_start,
	.read = src_read, .stop = src_stop, .close = src_close,
};
static const struct dao_plugin plugin = {DAO_PLUGIN_ABI_VERSION, "testsrc", "test camera", &ops, 0};
#else
struct sink {
	long ms;
};

static int sink_open(const char *uri, void **state, struct dao_error *err)
{
	(void)err;
	struct sink *s = calloc(1, sizeof(*s));
	if (!s)
		return -ENOMEM;
	s->ms = atol(uri);
	*state = s;
	return 0;
}

static int sink_negotiate(void *state, struct dao_sink_format *fmt, struct dao_error *err)
{
	(void)state;
	(void)fmt;
	(void)err;
	return 0;
}

static int sink_write(void *state, const struct dao_frame *frame, struct dao_error *err)
{
	(void)frame;
	(void)err;
	sleep_ms(((struct sink *)state)->ms);
	return 0;
}

static int sink_flush(void *state, struct dao_error *err)
{
	(void)state;
	(void)err;
	return 0;
}

static int sink_close(void *state, struct dao_error *err)
{
	(void)err;
	free(state);
	return 0;
}

static const struct dao_sink_ops ops = {
	.probe = no_probe, .open = sink_open, .negotiate = sink_negotiate, .write = sink_write,
	.flush = sink_flush, .close = sink_close,
};
static const struct dao_plugin plugin = {DAO_PLUGIN_ABI_VERSION, "slowsink", "slow test sink", 0,
					 &ops};
#endif

EXPORT const struct dao_plugin *dao_plugin_entry(void);
const struct dao_plugin *dao_plugin_entry(void)
{
	return &plugin;
}
