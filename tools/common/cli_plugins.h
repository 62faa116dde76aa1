/* SPDX-License-Identifier: MIT */
#ifndef DAO_TOOLS_CLI_PLUGINS_H
#define DAO_TOOLS_CLI_PLUGINS_H

#include <depthao/plugin.h>

/*
 * Loads the plugins for the command line: $DEPTHAO_PLUGIN_PATH and the
 * install directory, or, when this depthao runs from its build tree and the
 * variable is unset, the plugins built beside it (so build/tools/depthao/depthao
 * finds the plugins in build/plugins without any setup).
 */
int cli_plugins_load(struct dao_plugins **out, struct dao_error *err);

#endif
