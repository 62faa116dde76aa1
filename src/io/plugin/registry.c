/* SPDX-License-Identifier: MIT */
/*
 * The plugin registry: built-in plugins first, then modules from the search
 * path, first of a name wins.  Modules are opened RTLD_NODELETE so that a
 * library a plugin pulls in (OpenNI2 starts threads and registers handlers)
 * is never unmapped under its own feet when the registry is freed.
 */
#define _GNU_SOURCE /* RTLD_NODELETE, secure_getenv */
#include <depthao/depthao.h> /* dao_version */
#include <depthao/plugin.h>

#include <dirent.h>
#include <dlfcn.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error_internal.h"
#include "plugin/builtin.h"
#include "plugin/lookup.h"
#include "plugin/struct_sizes.h"

#ifndef DAO_PLUGIN_DIR
#define DAO_PLUGIN_DIR "/usr/local/lib/depthao/plugins"
#endif

struct entry {
	const struct dao_plugin *plugin;
	char *origin;
};

/* a module found but not loaded: "path: reason", and the plugin's name when the
 * descriptor was readable enough to trust it (NULL otherwise) */
struct skipped {
	char *line;
	char *name;
};

struct dao_plugins {
	struct entry *v;
	size_t n;
	struct skipped *skipped;
	size_t nskipped;
};

const char *dao_plugins_install_dir(void)
{
	return DAO_PLUGIN_DIR;
}

static int add_skipped_named(struct dao_plugins *p, const char *path, const char *name,
			     const char *why)
{
	struct skipped *s = realloc(p->skipped, (p->nskipped + 1) * sizeof(*s));
	if (!s)
		return -ENOMEM;
	p->skipped = s;
	s += p->nskipped;
	size_t len = strlen(path) + strlen(why) + 3;
	s->name = NULL;
	if (!(s->line = malloc(len)) || (name && !(s->name = strdup(name)))) {
		free(s->line);
		return -ENOMEM;
	}
	snprintf(s->line, len, "%s: %s", path, why);
	p->nskipped++;
	return 0;
}

static int add_skipped(struct dao_plugins *p, const char *path, const char *why)
{
	return add_skipped_named(p, path, NULL, why);
}

static int add(struct dao_plugins *p, const struct dao_plugin *pl, const char *origin)
{
	struct entry *v = realloc(p->v, (p->n + 1) * sizeof(*v));
	if (!v)
		return -ENOMEM;
	p->v = v;
	if (!(v[p->n].origin = strdup(origin)))
		return -ENOMEM;
	v[p->n].plugin = pl;
	p->n++;
	return 0;
}

static int valid_name(const char *s)
{
	if (!s || !*s)
		return 0;
	for (; *s; s++)
		if (!((*s >= 'a' && *s <= 'z') || (*s >= '0' && *s <= '9') || *s == '-' || *s == '_'))
			return 0;
	return 1;
}

/* "NAME(), NAME()" of the callbacks marked absent into `missing` ("" if none). */
static void list_missing(const char *const *names, const int *absent, size_t n, char *missing,
			 size_t len)
{
	size_t k = 0;
	missing[0] = '\0';
	for (size_t i = 0; i < n; i++)
		if (absent[i] && k < len)
			k += (size_t)snprintf(missing + k, len - k, "%s%s()", k ? ", " : "", names[i]);
}

/*
 * Why `pl` is refused for a callback the host calls without checking (the
 * ones plugin.h does not mark optional): "source 'x' has no read(); ..." into
 * `why`; 0 if it has them all.  A source's probe, list_devices, release, seek,
 * stop and frame_pose and a sink's probe, flush, attach_host and write_stream
 * are optional.
 */
static int lacks_callbacks(const struct dao_plugin *pl, char *why, size_t len)
{
	static const char *const src_names[] = {"open", "get_info", "start", "read", "close"};
	static const char *const sink_names[] = {"open", "negotiate", "write", "close"};
	const struct dao_source_ops *so = pl->source;
	const struct dao_sink_ops *si = pl->sink;
	char missing[80] = "";
	const char *role = "source", *all = "open, get_info, start, read and close";
	if (so) {
		const int absent[] = {!so->open, !so->get_info, !so->start, !so->read, !so->close};
		list_missing(src_names, absent, 5, missing, sizeof missing);
	}
	if (!missing[0] && si) {
		const int absent[] = {!si->open, !si->negotiate, !si->write, !si->close};
		list_missing(sink_names, absent, 4, missing, sizeof missing);
		role = "sink";
		all = "open, negotiate, write and close";
	}
	if (!missing[0])
		return 0;
	snprintf(why, len,
		 "%s '%s' has no %s; a %s plugin must implement %s: add %s and rebuild it "
		 "(docs/sources.md, \"Writing a plugin\")",
		 role, pl->name, missing, role, all, strchr(missing, ',') ? "them" : "it");
	return 1;
}

static int load_module(struct dao_plugins *p, const char *path)
{
	char why[320];
	void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
	if (!h) {
		const char *e = dlerror();
		return add_skipped(p, path, e ? e : "dlopen failed");
	}
	dao_plugin_entry_fn fn;
	void *sym = dlsym(h, DAO_PLUGIN_ENTRY_SYMBOL);
	memcpy(&fn, &sym, sizeof(fn));
	const struct dao_plugin *pl = fn ? fn() : NULL;
	if (!fn || !pl) {
		dlclose(h);
		return add_skipped(p, path, "not a depthao plugin (no " DAO_PLUGIN_ENTRY_SYMBOL ")");
	}
	if (pl->abi_version != DAO_PLUGIN_ABI_VERSION) {
		snprintf(why, sizeof(why),
			 "built for plugin ABI %u, this library (depthao %s) has %u; rebuild it "
			 "against this depthao's headers",
			 pl->abi_version, dao_version(), DAO_PLUGIN_ABI_VERSION);
		dlclose(h);
		return add_skipped(p, path, why);
	}
	/* the descriptor itself (its abi_version is at offset 0 in every ABI, the
	 * rest only in ABI 3 on) */
	if (pl->size < PLUGIN_SIZE_FIRST) {
		snprintf(why, sizeof(why),
			 "its struct dao_plugin says it is %u bytes, less than the %zu of the first "
			 "sized descriptor; begin it with DAO_PLUGIN_HEADER and rebuild it",
			 pl->size, (size_t)PLUGIN_SIZE_FIRST);
		dlclose(h);
		return add_skipped(p, path, why);
	}
	if (pl->version < PLUGIN_VERSION_FIRST || pl->version > DAO_PLUGIN_VERSION) {
		snprintf(why, sizeof(why),
			 "its struct dao_plugin has version %u, this library (depthao %s) knows "
			 "%u to %u; %s",
			 pl->version, dao_version(), PLUGIN_VERSION_FIRST, DAO_PLUGIN_VERSION,
			 pl->version > DAO_PLUGIN_VERSION
				 ? "update depthao, or rebuild the plugin against this one's headers"
				 : "begin it with DAO_PLUGIN_HEADER and rebuild it");
		dlclose(h);
		return add_skipped(p, path, why);
	}
	/* each interface by its own version: newer than ours is fine (we call
	 * what we know), older than the first versioned table is not */
	if ((pl->source && pl->source->version < SOURCE_OPS_VERSION_FIRST) ||
	    (pl->sink && pl->sink->version < SINK_OPS_VERSION_FIRST)) {
		snprintf(why, sizeof(why),
			 "its %s table has version 0; set .version = %s and rebuild it",
			 pl->source && pl->source->version < SOURCE_OPS_VERSION_FIRST ? "source"
										 : "sink",
			 pl->source && pl->source->version < SOURCE_OPS_VERSION_FIRST
				 ? "DAO_SOURCE_OPS_VERSION"
				 : "DAO_SINK_OPS_VERSION");
		dlclose(h);
		return add_skipped(p, path, why);
	}
	if (!valid_name(pl->name) || (!pl->source && !pl->sink)) {
		dlclose(h);
		return add_skipped(p, path, "bad plugin table (name must be [a-z0-9_-], and a source or sink)");
	}
	/* a callback the host calls unchecked would be a NULL call in the middle of a
	 * stream: refused here, where the module is named */
	if (lacks_callbacks(pl, why, sizeof(why))) {
		/* the name is the module's: copied before it is closed */
		const int r = add_skipped_named(p, path, pl->name, why);
		dlclose(h);
		return r;
	}
	if (dao_plugins_find(p, pl->name)) {
		snprintf(why, sizeof(why), "a plugin named '%s' is already loaded", pl->name);
		dlclose(h);
		return add_skipped(p, path, why);
	}
	return add(p, pl, path); /* the handle stays open for the process (RTLD_NODELETE) */
}

static int cmp_str(const void *a, const void *b)
{
	return strcmp(*(char *const *)a, *(char *const *)b);
}

static int scan_dir(struct dao_plugins *p, const char *dir)
{
	DIR *d = opendir(dir);
	if (!d)
		return 0; /* a missing directory is not an error */
	char **names = NULL;
	size_t n = 0;
	int ret = 0;
	struct dirent *e;
	while ((e = readdir(d))) {
		size_t len = strlen(e->d_name);
		if (len < 4 || strcmp(e->d_name + len - 3, ".so") != 0)
			continue;
		char **nn = realloc(names, (n + 1) * sizeof(*nn));
		if (!nn || !(nn[n] = malloc(strlen(dir) + len + 2))) {
			names = nn ? nn : names;
			ret = -ENOMEM;
			break;
		}
		names = nn;
		sprintf(names[n++], "%s/%s", dir, e->d_name);
	}
	closedir(d);
	if (n > 1) /* a directory without modules leaves names NULL: qsort(NULL) is UB */
		qsort(names, n, sizeof(*names), cmp_str); /* deterministic order */
	for (size_t i = 0; i < n; i++) {
		if (ret == 0)
			ret = load_module(p, names[i]);
		free(names[i]);
	}
	free(names);
	return ret;
}

static int scan_path(struct dao_plugins *p, const char *path)
{
	char *copy = strdup(path), *save = NULL;
	int ret = 0;
	if (!copy)
		return -ENOMEM;
	for (char *dir = strtok_r(copy, ":", &save); dir && ret == 0;
	     dir = strtok_r(NULL, ":", &save))
		ret = scan_dir(p, dir);
	free(copy);
	return ret;
}

int dao_plugins_load(struct dao_plugins **out, const char *path, struct dao_error *err)
{
	if (!out)
		return dao_error_set(err, -EINVAL, "dao_plugins_load: out is required");
	*out = NULL;
	struct dao_plugins *p = calloc(1, sizeof(*p));
	int ret = 0;
	if (!p)
		return dao_error_set(err, -ENOMEM, "out of memory loading plugins");
	for (const struct dao_plugin *const *b = dao_builtin_plugins; *b && ret == 0; b++)
		ret = add(p, *b, "built-in");
	if (ret == 0) {
		if (path) {
			ret = scan_path(p, path);
		} else {
			/* not in a set-user-ID or set-group-ID program: the caller's
			 * environment must not choose code that runs with its rights */
			const char *env = secure_getenv(DAO_PLUGIN_PATH_ENV);
			if (env && *env)
				ret = scan_path(p, env);
			if (ret == 0)
				ret = scan_dir(p, DAO_PLUGIN_DIR);
		}
	}
	if (ret < 0) {
		dao_plugins_free(p);
		return dao_error_set(err, ret, "loading plugins failed: %s", strerror(-ret));
	}
	*out = p;
	return 0;
}

void dao_plugins_free(struct dao_plugins *p)
{
	if (!p)
		return;
	for (size_t i = 0; i < p->n; i++)
		free(p->v[i].origin);
	for (size_t i = 0; i < p->nskipped; i++) {
		free(p->skipped[i].line);
		free(p->skipped[i].name);
	}
	free(p->v);
	free(p->skipped);
	free(p);
}

size_t dao_plugins_count(const struct dao_plugins *p)
{
	return p ? p->n : 0;
}

const struct dao_plugin *dao_plugins_get(const struct dao_plugins *p, size_t i)
{
	return p && i < p->n ? p->v[i].plugin : NULL;
}

const char *dao_plugins_origin(const struct dao_plugins *p, size_t i)
{
	return p && i < p->n ? p->v[i].origin : NULL;
}

const struct dao_plugin *dao_plugins_find(const struct dao_plugins *p, const char *name)
{
	for (size_t i = 0; p && name && i < p->n; i++)
		if (!strcmp(p->v[i].plugin->name, name))
			return p->v[i].plugin;
	return NULL;
}

size_t dao_plugins_skipped_count(const struct dao_plugins *p)
{
	return p ? p->nskipped : 0;
}

const char *dao_plugins_skipped(const struct dao_plugins *p, size_t i)
{
	return p && i < p->nskipped ? p->skipped[i].line : NULL;
}

const char *dao_plugins_skipped_reason(const struct dao_plugins *p, const char *name)
{
	for (size_t i = 0; p && name && i < p->nskipped; i++)
		if (p->skipped[i].name && !strcmp(p->skipped[i].name, name))
			return p->skipped[i].line;
	return NULL;
}
