/* SPDX-License-Identifier: MIT */
#ifndef DAO_PLUGIN_BUILTIN_H
#define DAO_PLUGIN_BUILTIN_H

#include <depthao/plugin.h>

/* NULL-terminated: the plugins compiled into the library. */
extern const struct dao_plugin *const dao_builtin_plugins[];

extern const struct dao_plugin dao_builtin_oni_plugin;
extern const struct dao_plugin dao_builtin_images_plugin;
extern const struct dao_plugin dao_builtin_y4m_plugin;
extern const struct dao_plugin dao_builtin_bag_plugin;
extern const struct dao_plugin dao_builtin_mcap_plugin;
extern const struct dao_plugin dao_builtin_db3_plugin;

/*
 * The built-in file sources' open with a pixel limit (width x height of the
 * depth images, > 0), checked before anything of an image's size is
 * allocated; their ops->open uses DAO_DEFAULT_MAX_PIXELS.
 */
int dao_images_source_open(const char *uri, const struct dao_source_options *opts,
			   uint64_t max_pixels, void **state, struct dao_error *err);
int dao_oni_source_open(const char *uri, const struct dao_source_options *opts,
			uint64_t max_pixels, void **state, struct dao_error *err);
int dao_bag_source_open(const char *uri, const struct dao_source_options *opts,
			uint64_t max_pixels, void **state, struct dao_error *err);
int dao_mcap_source_open(const char *uri, const struct dao_source_options *opts,
			 uint64_t max_pixels, void **state, struct dao_error *err);
int dao_db3_source_open(const char *uri, const struct dao_source_options *opts,
			uint64_t max_pixels, void **state, struct dao_error *err);

/* Sinks of the plugins above whose source lives in another file. */
extern const struct dao_sink_ops dao_images_sink_ops; /* images_sink.c */
extern const struct dao_sink_ops dao_oni_sink_ops;    /* oni_sink.c */
extern const struct dao_sink_ops dao_mcap_sink_ops;   /* mcap_sink.c */

#endif
