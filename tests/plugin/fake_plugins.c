/* SPDX-License-Identifier: MIT */
/*
 * Test modules for the registry, built from this one file with -DFAKE_KIND=n:
 *   1: a plugin built for another ABI version (must be skipped, with why)
 *   2: a module without the entry symbol (must be skipped)
 *   3: a valid sink-only plugin named "fakesink" (must load)
 */
#include <depthao/plugin.h>

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
