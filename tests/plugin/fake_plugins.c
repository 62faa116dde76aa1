/* SPDX-License-Identifier: MIT */
/*
 * Test modules for the registry, built from this one file with -DFAKE_KIND=n:
 *   1: a plugin built for another ABI version (must be skipped, with why)
 *   2: a module without the entry symbol (must be skipped)
 *   3: a valid sink-only plugin named "fakesink" (must load)
 *   4: a source "fakebig" whose URI "WxH" is the size it reports (pixel limits)
 */
#include <depthao/plugin.h>

#include <stdio.h>
#include <stdlib.h>

#define EXPORT __attribute__((visibility("default")))

#if FAKE_KIND == 1
static const struct dao_source_ops ops;
static const struct dao_plugin plugin = {DAO_PLUGIN_ABI_VERSION + 98, "wrongabi", "", &ops, 0};
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
#elif FAKE_KIND == 4
struct big {
	unsigned w, h;
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
}

static void big_close(void *state)
{
	free(state);
}

static const struct dao_source_ops ops = {.open = big_open, .get_info = big_info,
					  .close = big_close};
static const struct dao_plugin plugin = {DAO_PLUGIN_ABI_VERSION, "fakebig", "a test source", &ops,
					 0};
EXPORT const struct dao_plugin *dao_plugin_entry(void);
const struct dao_plugin *dao_plugin_entry(void)
{
	return &plugin;
}
#else
static int fake_probe(const char *uri)
{
	(void)uri;
	return 0;
}
static const struct dao_sink_ops ops = {.probe = fake_probe};
static const struct dao_plugin plugin = {DAO_PLUGIN_ABI_VERSION, "fakesink", "a test sink", 0,
					 &ops};
EXPORT const struct dao_plugin *dao_plugin_entry(void);
const struct dao_plugin *dao_plugin_entry(void)
{
	return &plugin;
}
#endif
