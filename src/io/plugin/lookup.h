/* SPDX-License-Identifier: MIT */
/* Which plugin opens a URI: the one it names, or the one whose probe wants it most. */
#ifndef DAO_PLUGIN_LOOKUP_H
#define DAO_PLUGIN_LOOKUP_H

#include <depthao/plugin.h>

enum dao_plugin_role {
	DAO_PLUGIN_SOURCE,
	DAO_PLUGIN_SINK,
};

/*
 * The plugin that opens `uri` as a source or a sink: the one named by its
 * prefix ("NAME:rest"), else the one whose probe scores the URI highest;
 * *rest is what follows the prefix (or the whole URI).  0, or -ENOENT with a
 * message that lists the plugins of that role.
 */
int dao_plugin_lookup(const struct dao_plugins *p, const char *uri, enum dao_plugin_role role,
		      const struct dao_plugin **out, const char **rest, struct dao_error *err);

/*
 * The module called `name` that was found but not loaded (a required callback
 * missing): its "path: reason" as dao_plugins_skipped() gives it, or NULL.
 */
const char *dao_plugins_skipped_reason(const struct dao_plugins *p, const char *name);

#endif
