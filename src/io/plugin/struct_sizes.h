/* SPDX-License-Identifier: MIT */
/*
 * The first layouts of the plugin interface's structs that carried `size`
 * (plugin ABI 2): the smallest a caller or plugin may hand over.  They never
 * change once released; fields added later lie beyond them (plugin.h).
 */
#ifndef DAO_PLUGIN_STRUCT_SIZES_H
#define DAO_PLUGIN_STRUCT_SIZES_H

#include <stddef.h>

#include <depthao/plugin.h>

#include "core/sized.h" /* DAO_END_OF */

#define SOURCE_INFO_SIZE_FIRST DAO_END_OF(struct dao_source_info, cy)
#define SOURCE_OPTIONS_SIZE_FIRST DAO_END_OF(struct dao_source_options, depth_unit)
#define SINK_FORMAT_SIZE_FIRST DAO_END_OF(struct dao_sink_format, reserved)
#define SINK_HOST_SIZE_FIRST DAO_END_OF(struct dao_sink_host, want_streams)
#define SINK_FRAME_INFO_SIZE_FIRST DAO_END_OF(struct dao_sink_frame_info, capture_ns)

/* The first descriptor that carried `size` and `version` (plugin ABI 3). */
#define PLUGIN_SIZE_FIRST DAO_END_OF(struct dao_plugin, sink)
#define PLUGIN_VERSION_FIRST 1

/* The first ops tables carried `version` 1; 0 is a table that forgot it. */
#define SOURCE_OPS_VERSION_FIRST 1
#define SINK_OPS_VERSION_FIRST 1

#endif
