/* SPDX-License-Identifier: MIT */
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "core/error_internal.h"
#include "plugin/lookup.h"

static int has_role(const struct dao_plugin *pl, enum dao_plugin_role role)
{
	return role == DAO_PLUGIN_SOURCE ? pl->source != NULL : pl->sink != NULL;
}

static int probe(const struct dao_plugin *pl, enum dao_plugin_role role, const char *uri)
{
	if (role == DAO_PLUGIN_SOURCE)
		return pl->source && pl->source->probe ? pl->source->probe(uri) : 0;
	return pl->sink && pl->sink->probe ? pl->sink->probe(uri) : 0;
}

/* "name1, name2" of the plugins in that role ("none"), and how many failed to load. */
static void list_role(const struct dao_plugins *p, enum dao_plugin_role role, char *buf,
		      size_t cap)
{
	size_t len = 0;
	buf[0] = '\0';
	for (size_t i = 0; i < dao_plugins_count(p); i++) {
		const struct dao_plugin *pl = dao_plugins_get(p, i);
		if (!has_role(pl, role))
			continue;
		int k = snprintf(buf + len, cap - len, "%s%s", len ? ", " : "", pl->name);
		if (k < 0 || (size_t)k >= cap - len)
			break;
		len += (size_t)k;
	}
	if (len == 0)
		snprintf(buf, cap, "none");
	len = strlen(buf);
	size_t ns = dao_plugins_skipped_count(p);
	if (ns && len + 32 < cap)
		snprintf(buf + len, cap - len, "; %zu plugin(s) failed to load, see 'depthao devices'",
			 ns);
}

int dao_plugin_lookup(const struct dao_plugins *p, const char *uri, enum dao_plugin_role role,
		      const struct dao_plugin **out, const char **rest, struct dao_error *err)
{
	const char *what = role == DAO_PLUGIN_SOURCE ? "source" : "sink";
	char names[200];
	*out = NULL;
	*rest = uri;
	size_t n = dao_uri_prefix_len(uri);
	if (n) {
		char name[64];
		snprintf(name, sizeof(name), "%.*s", (int)(n < 63 ? n : 63), uri);
		const struct dao_plugin *pl = dao_plugins_find(p, name);
		const char *skipped = pl ? NULL : dao_plugins_skipped_reason(p, name);
		if (skipped)
			return dao_error_set(err, -ENOENT, "no %s plugin '%s': %s", what, name,
					     skipped);
		if (!pl || !has_role(pl, role)) {
			list_role(p, role, names, sizeof(names));
			return dao_error_set(err, -ENOENT, "no %s plugin '%s' for '%s'; available: %s",
					     what, name, uri, names);
		}
		*out = pl;
		*rest = uri + n + 1;
		return 0;
	}
	int best = 0;
	for (size_t i = 0; i < dao_plugins_count(p); i++) {
		const struct dao_plugin *c = dao_plugins_get(p, i);
		int score = probe(c, role, uri);
		if (score > best) {
			best = score;
			*out = c;
		}
	}
	if (!*out) {
		list_role(p, role, names, sizeof(names));
		return dao_error_set(err, -ENOENT,
				     "no %s recognises '%s'; name one as NAME:URI (available: %s)", what,
				     uri, names);
	}
	return 0;
}
