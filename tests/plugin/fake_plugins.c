/* SPDX-License-Identifier: MIT */
/*
 * Test modules for the registry, built from this one file with -DFAKE_KIND=n:
 *   1: a plugin built for another ABI version (must be skipped, with why)
 *   2: a module without the entry symbol (must be skipped)
 *   3: a valid sink-only plugin named "fakesink" (must load; it takes and drops frames)
 *   4: a source "fakebig" whose URI "WxH" is the size it reports (pixel limits), a flat
 *      wall at 1 m; it has the required callbacks only (no probe, release, seek, stop:
 *      must load and stream)
 *   5: a source "noversion" whose ops table lacks its version (must be skipped)
 *   6: a sink "newersink" built for a newer sink interface and a larger
 *      struct dao_sink_format than this library's (must load and work: it
 *      reads only what DAO_STRUCT_HAS says is there)
 *   7: a sink "smalldesc" whose descriptor says it is smaller than the first
 *      sized one (must be skipped, with what to do)
 *   8: a sink "futuredesc" whose descriptor has a version newer than this
 *      library's (must be skipped, with what to do)
 *   9: a source "nostart", fakebig without start and read (must be skipped, with
 *      the callbacks it lacks)
 *  10: a sink "nowrite", fakesink without write (must be skipped, likewise)
 */
#include <depthao/plugin.h>

#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

#define EXPORT __attribute__((visibility("default")))

#if FAKE_KIND == 1
static const struct dao_source_ops ops;
static const struct dao_plugin plugin = {.abi_version = DAO_PLUGIN_ABI_VERSION + 98,
					 .name = "wrongabi", .description = "", .source = &ops};
EXPORT const struct dao_plugin *dao_plugin_entry(void);
const struct dao_plugin *dao_plugin_entry(void)
{
	return &plugin;
}
#elif FAKE_KIND == 2
EXPORT int not_a_plugin(void);
int not_a_plugin(void)
{
	return 0;
}
#elif FAKE_KIND == 4 || FAKE_KIND == 9
struct big {
	unsigned w, h;
	uint16_t *wall; /* allocated by start: open may be asked for more than fits */
	uint64_t n;
};

static int big_open(const char *uri, const struct dao_source_options *o, void **state,
		    struct dao_error *err)
{
	(void)o;
	(void)err;
	struct big *b = calloc(1, sizeof(*b));
	if (!b)
		return -12;
	if (sscanf(uri, "%ux%u", &b->w, &b->h) != 2) {
		free(b);
		return -22;
	}
	*state = b;
	return 0;
}

static void big_info(void *state, struct dao_source_info *in)
{
	const struct big *b = state;
	in->width = b->w;
	in->height = b->h;
	in->format = DAO_PIXFMT_DEPTH16;
	in->depth_unit = 0.001f;
	in->frame_count = -1;
	in->live = 1;
	snprintf(in->description, sizeof in->description, "a flat wall, %ux%u", b->w, b->h);
}

static void big_close(void *state)
{
	struct big *b = state;
	free(b->wall);
	free(b);
}

#if FAKE_KIND == 4
static int big_start(void *state, struct dao_error *err)
{
	(void)err;
	struct big *b = state;
	if (!b->wall && !(b->wall = malloc(sizeof(uint16_t) * b->w * b->h)))
		return -12;
	for (size_t i = 0; i < (size_t)b->w * b->h; i++)
		b->wall[i] = 1000;
	return 0;
}

static int big_read(void *state, struct dao_source_frame *frame, int timeout_ms,
		    struct dao_error *err)
{
	(void)timeout_ms;
	(void)err;
	struct big *b = state;
	frame->depth = (struct dao_frame){.format = DAO_PIXFMT_DEPTH16, .width = b->w,
					  .height = b->h, .stride = 2 * b->w, .data = b->wall,
					  .depth_unit = 0.001f, .sequence = b->n};
	frame->color.format = DAO_PIXFMT_NONE;
	frame->index = b->n++;
	return 0;
}

static const struct dao_source_ops ops = {.version = DAO_SOURCE_OPS_VERSION, .open = big_open,
					  .get_info = big_info, .start = big_start,
					  .read = big_read, .close = big_close};
static const struct dao_plugin plugin = {DAO_PLUGIN_HEADER, .name = "fakebig",
					 .description = "a test source", .source = &ops};
#else
static const struct dao_source_ops ops = {.version = DAO_SOURCE_OPS_VERSION, .open = big_open,
					  .get_info = big_info, .close = big_close};
static const struct dao_plugin plugin = {DAO_PLUGIN_HEADER, .name = "nostart",
					 .description = "a test source without start and read",
					 .source = &ops};
#endif
EXPORT const struct dao_plugin *dao_plugin_entry(void);
const struct dao_plugin *dao_plugin_entry(void)
{
	return &plugin;
}
#elif FAKE_KIND == 5
static const struct dao_source_ops ops = {.open = NULL}; /* .version left 0 */
static const struct dao_plugin plugin = {DAO_PLUGIN_HEADER, .name = "noversion", .description = "",
					 .source = &ops};
DAO_PLUGIN_DEFINE(plugin)
#elif FAKE_KIND == 6
/* The struct a future depthao might hand over: today's, then a new field. */
struct future_format {
	struct dao_sink_format now;
	double gamma; /* "since" a later layout */
};

static int ns_open(const char *uri, void **state, struct dao_error *err)
{
	(void)uri;
	(void)err;
	*state = calloc(1, sizeof(int));
	return *state ? 0 : -12;
}

static int ns_negotiate(void *state, struct dao_sink_format *fmt, struct dao_error *err)
{
	(void)state;
	(void)err;
	/* the new field only where the host's struct has it */
	if (fmt->size >= offsetof(struct future_format, gamma) + sizeof(double))
		return -22; /* this library's struct never has it */
	fmt->format = DAO_PIXFMT_GRAY8; /* take GRAY8 only */
	return 0;
}

static int ns_write(void *state, const struct dao_frame *frame, struct dao_error *err)
{
	(void)frame;
	(void)err;
	++*(int *)state;
	return 0;
}

static int ns_close(void *state, struct dao_error *err)
{
	(void)err;
	int n = *(int *)state;
	free(state);
	return n == 1 ? 0 : -5; /* exactly the one frame the test writes */
}

static const struct dao_sink_ops ops = {.version = DAO_SINK_OPS_VERSION + 5, .open = ns_open,
					.negotiate = ns_negotiate, .write = ns_write,
					.close = ns_close};
static const struct dao_plugin plugin = {DAO_PLUGIN_HEADER, .name = "newersink", .description = "",
					 .sink = &ops};
DAO_PLUGIN_DEFINE(plugin)
#elif FAKE_KIND == 7 || FAKE_KIND == 8
static const struct dao_sink_ops ops = {.version = DAO_SINK_OPS_VERSION};
static const struct dao_plugin plugin = {
	.abi_version = DAO_PLUGIN_ABI_VERSION,
#if FAKE_KIND == 7
	.size = 8, /* a descriptor ending after abi_version and size */
	.version = DAO_PLUGIN_VERSION,
	.name = "smalldesc",
#else
	.size = sizeof(struct dao_plugin),
	.version = DAO_PLUGIN_VERSION + 1,
	.name = "futuredesc",
#endif
	.description = "",
	.sink = &ops,
};
DAO_PLUGIN_DEFINE(plugin)
#else /* 3, 10 */
static int fake_probe(const char *uri)
{
	(void)uri;
	return 0;
}

static int fake_open(const char *uri, void **state, struct dao_error *err)
{
	(void)uri;
	(void)err;
	*state = NULL;
	return 0;
}

static int fake_negotiate(void *state, struct dao_sink_format *fmt, struct dao_error *err)
{
	(void)state;
	(void)fmt;
	(void)err;
	return 0;
}

#if FAKE_KIND == 3
static int fake_write(void *state, const struct dao_frame *frame, struct dao_error *err)
{
	(void)state;
	(void)frame;
	(void)err;
	return 0;
}
#endif

static int fake_close(void *state, struct dao_error *err)
{
	(void)state;
	(void)err;
	return 0;
}

static const struct dao_sink_ops ops = {.version = DAO_SINK_OPS_VERSION, .probe = fake_probe,
					.open = fake_open, .negotiate = fake_negotiate,
#if FAKE_KIND == 3
					.write = fake_write,
#endif
					.close = fake_close};
#if FAKE_KIND == 3
static const struct dao_plugin plugin = {DAO_PLUGIN_HEADER, .name = "fakesink",
					 .description = "a test sink", .sink = &ops};
#else
static const struct dao_plugin plugin = {DAO_PLUGIN_HEADER, .name = "nowrite",
					 .description = "a test sink without write", .sink = &ops};
#endif
EXPORT const struct dao_plugin *dao_plugin_entry(void);
const struct dao_plugin *dao_plugin_entry(void)
{
	return &plugin;
}
#endif
