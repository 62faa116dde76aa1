/* SPDX-License-Identifier: MIT */
#include "plugin/builtin.h"

const struct dao_plugin *const dao_builtin_plugins[] = {
	&dao_builtin_oni_plugin,
	&dao_builtin_images_plugin,
	&dao_builtin_y4m_plugin,
	&dao_builtin_bag_plugin,
	&dao_builtin_mcap_plugin,
	&dao_builtin_db3_plugin,
	NULL,
};
