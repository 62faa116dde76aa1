/* SPDX-License-Identifier: MIT */
/*
 * Plugins for the daemon tests, built from this file with -DTEST_PLUGIN=n:
 *   1: source "testsrc" - a live synthetic camera: "testsrc:fps=200,fail_after=20,w=64,h=48"
 *      delivers a moving box at `fps` and, after `fail_after` frames, reports the
 *      device as gone (-ENODEV) once per open, as an unplugged sensor would;
 *      "stall_after=N" delivers N frames, then none (-EAGAIN after each timeout),
 *      as a camera whose stream stops without an error; "absent=1" fails every open
 *      with -ENODEV, as a camera that is not plugged in; "resize_after=N,w2=W,h2=H"
 *      switches to W x H frames after N (a camera whose mode changed); "hang_after=N"
 *      delivers N frames, then its read never returns (a hung driver).
 *   2: sink "slowsink" - "slowsink:MS[,fail=E][,after=N][,open_fail=E][,out=FILE]" takes
 *      MS milliseconds per frame; its writes fail with errno E (a number or a name:
 *      ENOSPC, EIO, EPIPE, ...) after N good ones of each open; open_fail=E makes every
 *      open fail; out=FILE appends "OPEN" at each open and the sequence number of each
 *      frame it reports written, so a test can compare the daemon's counters with
 *      what the sink took.
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
	unsigned w, h, fps, fail_after, stall_after, delivered;
	unsigned resize_after, w2, h2, hang_after;
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
	char *save = NULL; /* strtok_r: the daemon opens its source and sinks in parallel threads */
	for (char *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
		unsigned v;
		if (sscanf(tok, "fps=%u", &v) == 1)
			s->fps = v;
		else if (sscanf(tok, "fail_after=%u", &v) == 1)
			s->fail_after = v;
		else if (sscanf(tok, "absent=%u", &v) == 1 && v) {
			if (err)
				snprintf(err->message, sizeof err->message, "testsrc: no camera plugged in");
			free(s);
			return -ENODEV;
		} else if (sscanf(tok, "stall_after=%u", &v) == 1)
			s->stall_after = v;
		else if (sscanf(tok, "w=%u", &v) == 1)
			s->w = v;
		else if (sscanf(tok, "h=%u", &v) == 1)
			s->h = v;
		else if (sscanf(tok, "resize_after=%u", &v) == 1)
			s->resize_after = v;
		else if (sscanf(tok, "hang_after=%u", &v) == 1)
			s->hang_after = v;
		else if (sscanf(tok, "w2=%u", &v) == 1)
			s->w2 = v;
		else if (sscanf(tok, "h2=%u", &v) == 1)
			s->h2 = v;
	}
	if (!s->w2 || !s->h2) {
		s->w2 = s->w;
		s->h2 = s->h;
	}
	size_t big = (size_t)(s->w > s->w2 ? s->w : s->w2) * (s->h > s->h2 ? s->h : s->h2);
	s->pixels = malloc(big * 2);
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
	if (s->fail_after && s->delivered >= s->fail_after) {
		if (err)
			snprintf(err->message, sizeof err->message, "testsrc: unplugged after %u frames",
				 s->delivered);
		return -ENODEV;
	}
	if (s->hang_after && s->delivered >= s->hang_after)
		sleep_ms(3600000); /* whatever the timeout: the daemon abandons it at stop */
	if (s->stall_after && s->delivered >= s->stall_after) {
		sleep_ms(timeout_ms > 0 ? timeout_ms : 10);
		return -EAGAIN;
	}
	sleep_ms(1000 / s->fps);
	if (s->resize_after && s->delivered == s->resize_after) {
		s->w = s->w2;
		s->h = s->h2;
	}
	unsigned bx = s->delivered % (s->w / 2);
	for (unsigned y = 0; y < s->h; y++)
		for (unsigned x = 0; x < s->w; x++)
			s->pixels[y * s->w + x] =
				(uint16_t)(x >= bx && x < bx + s->w / 4 && y > s->h / 3 ? 900 : 1500);
	f->depth = (struct dao_frame){.format = DAO_PIXFMT_DEPTH16, .width = s->w, .height = s->h,
			.stride = (int32_t)(2 * s->w), .data = s->pixels,
				      .depth_unit = 0.001f, .sequence = s->delivered + 1};
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
	.version = DAO_SOURCE_OPS_VERSION,
	.probe = no_probe, .open = src_open, .get_info = src_info, .start = src_start,
	.read = src_read, .stop = src_stop, .close = src_close,
};
static const struct dao_plugin plugin = {DAO_PLUGIN_HEADER, .name = "testsrc",
					 .description = "test camera", .source = &ops};
#else
struct sink {
	long ms;
	int fail, open_fail;
	unsigned after, written;
	char out[400];
};

static int errno_of(const char *v)
{
	static const struct {
		const char *name;
		int code;
	} names[] = {{"ENOSPC", ENOSPC}, {"EDQUOT", EDQUOT}, {"EFBIG", EFBIG}, {"EROFS", EROFS},
		     {"EPIPE", EPIPE},   {"EIO", EIO},       {"EACCES", EACCES}, {"ENOENT", ENOENT}};
	for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
		if (!strcmp(v, names[i].name))
			return names[i].code;
	return atoi(v);
}

static void note(const struct sink *s, const char *fmt, unsigned long long v)
{
	if (!s->out[0])
		return;
	FILE *f = fopen(s->out, "a");
	if (f) {
		fprintf(f, fmt, v);
		fclose(f);
	}
}

static int sink_open(const char *uri, void **state, struct dao_error *err)
{
	struct sink *s = calloc(1, sizeof(*s));
	if (!s)
		return -ENOMEM;
	char buf[512];
	snprintf(buf, sizeof buf, "%s", uri);
	s->ms = atol(buf);
	char *save = NULL; /* strtok_r: the daemon opens its source and sinks in parallel threads */
	for (char *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
		if (!strncmp(tok, "fail=", 5))
			s->fail = errno_of(tok + 5);
		else if (!strncmp(tok, "open_fail=", 10))
			s->open_fail = errno_of(tok + 10);
		else if (!strncmp(tok, "after=", 6))
			s->after = (unsigned)atoi(tok + 6);
		else if (!strncmp(tok, "out=", 4))
			snprintf(s->out, sizeof s->out, "%s", tok + 4);
	}
	if (s->open_fail) {
		int e = s->open_fail;
		if (err)
			snprintf(err->message, sizeof err->message, "slowsink: cannot open: %s",
				 strerror(e));
		free(s);
		return -e;
	}
	note(s, "OPEN\n", 0);
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
	struct sink *s = state;
	sleep_ms(s->ms);
	if (s->fail && s->written >= s->after) {
		if (err)
			snprintf(err->message, sizeof err->message, "slowsink: write failed: %s",
				 strerror(s->fail));
		return -s->fail;
	}
	s->written++;
	note(s, "%llu\n", (unsigned long long)frame->sequence);
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
	.version = DAO_SINK_OPS_VERSION,
	.probe = no_probe, .open = sink_open, .negotiate = sink_negotiate, .write = sink_write,
	.flush = sink_flush, .close = sink_close,
};
static const struct dao_plugin plugin = {DAO_PLUGIN_HEADER, .name = "slowsink",
					 .description = "slow test sink", .sink = &ops};
#endif

EXPORT const struct dao_plugin *dao_plugin_entry(void);
const struct dao_plugin *dao_plugin_entry(void)
{
	return &plugin;
}
