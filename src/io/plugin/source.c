/* SPDX-License-Identifier: MIT */
/* Opening a source by URI, and the thin wrapper around its vtable. */
#include <depthao/plugin.h>

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error_internal.h"
#include "plugin/builtin.h"
#include "plugin/lookup.h"
#include "plugin/struct_sizes.h"

struct dao_source {
	const struct dao_plugin *plugin;
	void *state;
	int started;
};

/* The plugin's open; the built-in file sources check the limit themselves, before allocating. */
static int open_state(const struct dao_plugin *pl, const char *rest,
		      const struct dao_source_options *opts, uint64_t max_pixels, void **state,
		      struct dao_error *err)
{
	if (pl == &dao_builtin_images_plugin)
		return dao_images_source_open(rest, opts, max_pixels, state, err);
	if (pl == &dao_builtin_oni_plugin)
		return dao_oni_source_open(rest, opts, max_pixels, state, err);
	if (pl == &dao_builtin_bag_plugin)
		return dao_bag_source_open(rest, opts, max_pixels, state, err);
	if (pl == &dao_builtin_mcap_plugin)
		return dao_mcap_source_open(rest, opts, max_pixels, state, err);
	if (pl == &dao_builtin_db3_plugin)
		return dao_db3_source_open(rest, opts, max_pixels, state, err);
	int r = pl->source->open(rest, opts, state, err);
	if (r < 0)
		return r;
	struct dao_source_info in;
	memset(&in, 0, sizeof(in));
	in.size = sizeof(in);
	pl->source->get_info(*state, &in);
	if ((uint64_t)in.width * in.height > max_pixels) {
		r = dao_error_set(err, -EFBIG,
				  "source '%s' delivers %ux%u depth images (%llu pixels), more than "
				  "the limit of %llu pixels",
				  pl->name, in.width, in.height,
				  (unsigned long long)in.width * in.height,
				  (unsigned long long)max_pixels);
		pl->source->close(*state);
		*state = NULL;
	}
	return r;
}

int dao_source_open(const struct dao_plugins *p, const char *uri,
		    const struct dao_source_options *opts, struct dao_source **out,
		    struct dao_error *err)
{
	return dao_source_open_limited(p, uri, opts, DAO_DEFAULT_MAX_PIXELS, out, err);
}

int dao_source_open_limited(const struct dao_plugins *p, const char *uri,
			    const struct dao_source_options *opts, uint64_t max_pixels,
			    struct dao_source **out, struct dao_error *err)
{
	struct dao_source_options full = DAO_SOURCE_OPTIONS_INIT;
	const struct dao_plugin *pl = NULL;
	const char *rest = uri;

	if (!p || !uri || !out)
		return dao_error_set(err, -EINVAL, "dao_source_open: plugins, uri and out are required");
	*out = NULL;
	if (opts) {
		/* the caller's struct may be older (shorter) than this library's: the
		 * plugin gets a complete one, the missing fields at their defaults */
		if (opts->size < SOURCE_OPTIONS_SIZE_FIRST)
			return dao_error_set(err, -EINVAL,
					     "struct dao_source_options has size %u: initialise it "
					     "with DAO_SOURCE_OPTIONS_INIT",
					     (unsigned)opts->size);
		memcpy(&full, opts, opts->size < sizeof(full) ? opts->size : sizeof(full));
		full.size = sizeof(full);
	}
	opts = &full;
	int r = dao_plugin_lookup(p, uri, DAO_PLUGIN_SOURCE, &pl, &rest, err);
	if (r < 0)
		return r;
	struct dao_source *s = calloc(1, sizeof(*s));
	if (!s)
		return dao_error_set(err, -ENOMEM, "out of memory");
	s->plugin = pl;
	r = open_state(pl, rest, opts, max_pixels ? max_pixels : DAO_DEFAULT_MAX_PIXELS,
		       &s->state, err);
	if (r < 0) {
		free(s);
		return r;
	}
	*out = s;
	return 0;
}

const struct dao_plugin *dao_source_plugin(const struct dao_source *s)
{
	return s ? s->plugin : NULL;
}

int dao_source_get_info_sized(const struct dao_source *s, struct dao_source_info *info,
			      size_t size)
{
	if (!s || !info || size < SOURCE_INFO_SIZE_FIRST)
		return -EINVAL;
	struct dao_source_info full;
	memset(&full, 0, sizeof(full));
	full.size = sizeof(full);
	s->plugin->source->get_info(s->state, &full);
	if (size > sizeof(full))
		size = sizeof(full);
	memcpy(info, &full, size);
	info->size = (uint32_t)size;
	return 0;
}

/* open, get_info, start, read and close of a source's table are there: the registry
 * refuses a source without them (registry.c, lacks_callbacks) */

int dao_source_start(struct dao_source *s, struct dao_error *err)
{
	if (!s)
		return dao_error_set(err, -EINVAL, "dao_source_start: no source (open one with "
				     "dao_source_open first)");
	if (s->started)
		return 0;
	int r = s->plugin->source->start(s->state, err);
	if (r == 0)
		s->started = 1;
	return r;
}

int dao_source_read(struct dao_source *s, struct dao_source_frame *f, int timeout_ms,
		    struct dao_error *err)
{
	if (!s || !f)
		return dao_error_set(err, -EINVAL, "dao_source_read: source and frame are required");
	if (!s->started)
		return dao_error_set(err, -EINVAL, "read from a source that was not started");
	memset(f, 0, sizeof(*f));
	return s->plugin->source->read(s->state, f, timeout_ms, err);
}

void dao_source_release(struct dao_source *s, struct dao_source_frame *f)
{
	if (s->plugin->source->release)
		s->plugin->source->release(s->state, f);
}

int dao_source_seek(struct dao_source *s, uint64_t index, struct dao_error *err)
{
	if (!s->plugin->source->seek)
		return dao_error_set(err, -ENOTSUP, "source '%s' cannot seek", s->plugin->name);
	return s->plugin->source->seek(s->state, index, err);
}

int dao_source_frame_pose_sized(struct dao_source *s, const struct dao_source_frame *frame,
				struct dao_source_pose *pose, size_t size, struct dao_error *err)
{
	const struct dao_source_ops *ops = s ? s->plugin->source : NULL;
	if (!s || !frame || !pose)
		return dao_error_set(err, -EINVAL, "dao_source_frame_pose: NULL argument");
	if (size < offsetof(struct dao_source_pose, description))
		return dao_error_set(err, -EINVAL, "dao_source_frame_pose: a struct of %zu bytes is "
				     "smaller than the first layout (DAO_SOURCE_POSE_INIT)", size);
	if (ops->version < 2 || !ops->frame_pose)
		return dao_error_set(err, -ENOTSUP, "source '%s' carries no camera poses",
				     s->plugin->name);
	struct dao_source_pose full = DAO_SOURCE_POSE_INIT;
	int r = ops->frame_pose(s->state, frame, &full, err);
	if (r < 0)
		return r;
	full.size = (uint32_t)(size < sizeof(full) ? size : sizeof(full));
	memcpy(pose, &full, full.size);
	return 0;
}

void dao_source_close(struct dao_source *s)
{
	if (!s)
		return;
	if (s->started && s->plugin->source->stop)
		s->plugin->source->stop(s->state);
	s->plugin->source->close(s->state);
	free(s);
}
