/* SPDX-License-Identifier: MIT */
#ifndef DAO_PLUGIN_BUILTIN_H
#define DAO_PLUGIN_BUILTIN_H

#include <depthao/plugin.h>

/* NULL-terminated: the plugins compiled into the library. */
extern const struct dao_plugin *const dao_builtin_plugins[];

extern const struct dao_plugin dao_builtin_oni_plugin;
extern const struct dao_plugin dao_builtin_images_plugin;

#endif
