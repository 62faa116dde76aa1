/* SPDX-License-Identifier: MIT */
/*
 * Opening a sink by URI, and the thin wrapper around its vtable.  The
 * wrapper enforces the call order (negotiate before the first write; the
 * format is fixed once a frame was written) and that every frame has the
 * negotiated format and size, so sinks can trust what they receive.
 */
#include <depthao/plugin.h>

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error_internal.h"
#include "plugin/lookup.h"
#include "plugin/struct_sizes.h"

struct dao_sink {
	const struct dao_plugin *plugin;
	void *state;
	int negotiated;               /* fmt holds what the sink accepted */
	int written;                  /* a write was attempted: the format is fixed */
	struct dao_sink_format fmt;
	struct dao_sink_host host;    /* the caller's, completed to this library's size */
};

int dao_sink_open(const struct dao_plugins *p, const char *uri, struct dao_sink **out,
		  struct dao_error *err)
{
	const struct dao_plugin *pl = NULL;
	const char *rest = uri;

	if (!p || !uri || !out)
		return dao_error_set(err, -EINVAL, "dao_sink_open: plugins, uri and out are required");
	*out = NULL;
	int r = dao_plugin_lookup(p, uri, DAO_PLUGIN_SINK, &pl, &rest, err);
	if (r < 0)
		return r;
	/* open, negotiate, write and close are there: the registry refuses a sink
	 * without them (registry.c, lacks_callbacks) */
	const struct dao_sink_ops *ops = pl->sink;
	struct dao_sink *s = calloc(1, sizeof(*s));
	if (!s)
		return dao_error_set(err, -ENOMEM, "out of memory");
	s->plugin = pl;
	r = ops->open(rest, &s->state, err);
	if (r < 0) {
		free(s);
		return r;
	}
	*out = s;
	return 0;
}

void dao_sink_attach_host(struct dao_sink *s, const struct dao_sink_host *host)
{
	if (!s || !host || !s->plugin->sink->attach_host || host->size < SINK_HOST_SIZE_FIRST)
		return; /* a host without its size is not one this library can read */
	memset(&s->host, 0, sizeof(s->host));
	memcpy(&s->host, host, host->size < sizeof(s->host) ? host->size : sizeof(s->host));
	s->host.size = sizeof(s->host);
	s->plugin->sink->attach_host(s->state, &s->host);
}

const struct dao_plugin *dao_sink_plugin(const struct dao_sink *s)
{
	return s ? s->plugin : NULL;
}

int dao_sink_negotiate(struct dao_sink *s, struct dao_sink_format *fmt, struct dao_error *err)
{
	if (!s || !fmt)
		return dao_error_set(err, -EINVAL, "dao_sink_negotiate: sink and fmt are required");
	if (fmt->size < SINK_FORMAT_SIZE_FIRST)
		return dao_error_set(err, -EINVAL,
				     "struct dao_sink_format has size %u: initialise it with "
				     "DAO_SINK_FORMAT_INIT",
				     (unsigned)fmt->size);
	/* the plugin gets a complete struct of this library's size; the caller
	 * gets back what fits in its own */
	const uint32_t caller_size = fmt->size < sizeof(s->fmt) ? fmt->size : sizeof(s->fmt);
	struct dao_sink_format full = DAO_SINK_FORMAT_INIT;
	memcpy(&full, fmt, caller_size);
	full.size = sizeof(full);
	if (s->written)
		return dao_error_set(err, -EINVAL,
				     "sink '%s': the format cannot change after the first write; "
				     "close the sink and open a new one",
				     s->plugin->name);
	s->negotiated = 0; /* until the sink accepts the new format */
	if (dao_pixfmt_bytes_per_pixel(fmt->format) == 0)
		return dao_error_set(err, -EINVAL, "sink '%s': pixel format %d is not valid",
				     s->plugin->name, (int)fmt->format);
	if (fmt->width == 0 || fmt->height == 0 || fmt->width > DAO_MAX_DIMENSION ||
	    fmt->height > DAO_MAX_DIMENSION)
		return dao_error_set(err, -EINVAL, "sink '%s': size %ux%u is out of range (1..%d)",
				     s->plugin->name, fmt->width, fmt->height, DAO_MAX_DIMENSION);
	if (!isfinite(fmt->fps) || fmt->fps < 0)
		return dao_error_set(err, -EINVAL,
				     "sink '%s': frame rate %g is not valid (>= 0, 0 = unknown)",
				     s->plugin->name, fmt->fps);
	int r = s->plugin->sink->negotiate(s->state, &full, err);
	memcpy(fmt, &full, caller_size);
	fmt->size = caller_size;
	if (r < 0)
		return r;
	s->fmt = full;
	s->negotiated = 1;
	return 0;
}

int dao_sink_write(struct dao_sink *s, const struct dao_frame *frame, struct dao_error *err)
{
	int r;
	if (!s || !frame)
		return dao_error_set(err, -EINVAL, "dao_sink_write: sink and frame are required");
	if (!s->negotiated)
		return dao_error_set(err, -EINVAL,
				     "sink '%s': write before the format was negotiated "
				     "(call dao_sink_negotiate first)",
				     s->plugin->name);
	if ((r = dao_frame_check(frame, "sink input", 0, 0, err)) < 0)
		return r;
	if (frame->format != s->fmt.format || frame->width != s->fmt.width ||
	    frame->height != s->fmt.height)
		return dao_error_set(err, -EINVAL,
				     "sink '%s' was negotiated for %ux%u %s frames, this one is "
				     "%ux%u %s",
				     s->plugin->name, s->fmt.width, s->fmt.height,
				     dao_pixfmt_name(s->fmt.format), frame->width, frame->height,
				     dao_pixfmt_name(frame->format));
	s->written = 1;
	return s->plugin->sink->write(s->state, frame, err);
}

int dao_sink_write_stream(struct dao_sink *s, const struct dao_sink_frame_info *info,
			  const struct dao_frame *frame, struct dao_error *err)
{
	int r;
	if (!s || !info || !frame)
		return dao_error_set(err, -EINVAL,
				     "dao_sink_write_stream: sink, info and frame are required");
	if (info->size < SINK_FRAME_INFO_SIZE_FIRST)
		return dao_error_set(err, -EINVAL,
				     "struct dao_sink_frame_info has size %u: set .size = sizeof(struct "
				     "dao_sink_frame_info)",
				     (unsigned)info->size);
	if ((unsigned)info->stream >= DAO_STREAM_COUNT)
		return dao_error_set(err, -EINVAL, "sink '%s': stream %d is not valid",
				     s->plugin->name, (int)info->stream);
	if (!s->plugin->sink->write_stream)
		return dao_sink_write(s, frame, err);
	if (!s->negotiated)
		return dao_error_set(err, -EINVAL,
				     "sink '%s': write before the format was negotiated "
				     "(call dao_sink_negotiate first)",
				     s->plugin->name);
	if ((r = dao_frame_check(frame, "sink input", 0, 0, err)) < 0)
		return r;
	s->written = 1;
	/* the plugin gets a complete struct of this library's size */
	struct dao_sink_frame_info full;
	memset(&full, 0, sizeof(full));
	memcpy(&full, info, info->size < sizeof(full) ? info->size : sizeof(full));
	full.size = sizeof(full);
	return s->plugin->sink->write_stream(s->state, &full, frame, err);
}

int dao_sink_takes_streams(const struct dao_sink *s)
{
	return s && s->plugin->sink->write_stream != NULL;
}

int dao_sink_flush(struct dao_sink *s, struct dao_error *err)
{
	if (!s)
		return dao_error_set(err, -EINVAL, "dao_sink_flush: sink is required");
	if (!s->plugin->sink->flush)
		return 0;
	return s->plugin->sink->flush(s->state, err);
}

int dao_sink_close(struct dao_sink *s, struct dao_error *err)
{
	if (!s)
		return 0;
	int r = s->plugin->sink->close(s->state, err);
	free(s);
	return r;
}
