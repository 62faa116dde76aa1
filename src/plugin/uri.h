/* SPDX-License-Identifier: MIT */
#ifndef DAO_PLUGIN_URI_H
#define DAO_PLUGIN_URI_H

#include <stddef.h>

/*
 * Length of a plugin prefix "name:" at the start of a URI: two or more of
 * [a-z0-9_-] then ':' (so "C:\x", "./a:b" or "/x:y" are not prefixes); 0 if none.
 */
static inline size_t dao_uri_prefix_len(const char *uri)
{
	size_t i = 0;
	while ((uri[i] >= 'a' && uri[i] <= 'z') || (uri[i] >= '0' && uri[i] <= '9') ||
	       uri[i] == '-' || uri[i] == '_')
		i++;
	return i > 1 && uri[i] == ':' ? i : 0;
}

#endif
