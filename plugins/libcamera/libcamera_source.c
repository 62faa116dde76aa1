/* SPDX-License-Identifier: MIT */
/*
 * Source plugin "libcamera": depth from time-of-flight sensors that deliver
 * it through libcamera as a mono raw stream (R12, R10 or R8), counts times
 * a configured unit (dao_source_options.depth_unit, else 1 mm).
 *
 * URI: CAMERA_ID or "any", optionally "?size=WxH".  With no camera present
 * the error says "no cameras found".  libcamera gives no field of view:
 * the configuration does, or a default with a warning.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/plugin.h>

#include "lc_shim.h"

struct lc_source {
	struct lcs_camera *cam;
	float unit;
	unsigned w, h, bits;
	char text[160];
	uint64_t delivered;
};

static int lc_probe(const char *uri)
{
	(void)uri;
	return 0; /* only when named: libcamera:ID */
}

struct listing {
	dao_device_cb cb;
	void *user;
};

static void on_camera(void *user, const char *id, const char *model)
{
	struct listing *l = user;
	struct dao_device_entry e;
	memset(&e, 0, sizeof e);
	snprintf(e.uri, sizeof e.uri, "%.255s", id);
	snprintf(e.name, sizeof e.name, "%.127s", model);
	snprintf(e.detail, sizeof e.detail, "libcamera");
	l->cb(l->user, &e);
}

static int lc_list(dao_device_cb cb, void *user, struct dao_error *err)
{
	char msg[256];
	struct listing l = {cb, user};
	int n = lcs_list(on_camera, &l, msg, sizeof msg);
	return n < 0 ? dao_error_set(err, n, "%s", msg) : n;
}

static int lc_open(const char *uri, const struct dao_source_options *o, void **state,
		   struct dao_error *err)
{
	static const char *const known[] = {"size", NULL};
	char id[256], msg[256], tail;
	unsigned w = 0, h = 0;
	snprintf(id, sizeof id, "%s", uri);
	size_t at = dao_uri_path_len(id, known);
	struct dao_options *opts;
	int r = dao_options_parse(&opts, "libcamera", id[at] ? id + at + 1 : NULL, known, err);
	if (r < 0)
		return r;
	const char *size = dao_options_value(opts, "size");
	if (size && (sscanf(size, "%ux%u%c", &w, &h, &tail) != 2 || !w || !h))
		r = dao_error_set(err, -EINVAL, "libcamera: 'size' must be WxH, got '%.40s'", size);
	dao_options_free(opts);
	if (r < 0)
		return r;
	id[at] = '\0';
	struct lc_source *s = calloc(1, sizeof(*s));
	if (!s)
		return dao_error_set(err, -ENOMEM, "out of memory");
	s->unit = o->depth_unit > 0 ? o->depth_unit : 0.001f;
	if (!(s->cam = lcs_open(id, w, h, msg, sizeof msg))) {
		free(s);
		return dao_error_set(err, -ENODEV, "%s", msg);
	}
	lcs_describe(s->cam, &s->w, &s->h, &s->bits, s->text, sizeof s->text);
	*state = s;
	return 0;
}

static void lc_info(void *state, struct dao_source_info *in)
{
	struct lc_source *s = state;
	in->width = s->w;
	in->height = s->h;
	in->format = DAO_PIXFMT_DEPTH16;
	in->depth_unit = s->unit;
	in->frame_count = -1;
	in->live = 1;
	snprintf(in->description, sizeof in->description, "%.140s, %u-bit", s->text, s->bits);
}

static int lc_start(void *state, struct dao_error *err)
{
	char msg[256];
	int r = lcs_start(((struct lc_source *)state)->cam, msg, sizeof msg);
	return r < 0 ? dao_error_set(err, r, "%s", msg) : 0;
}

static int lc_read(void *state, struct dao_source_frame *f, int timeout_ms, struct dao_error *err)
{
	struct lc_source *s = state;
	const uint16_t *data;
	unsigned stride;
	uint64_t ts, seq;
	int r = lcs_read(s->cam, timeout_ms, &data, &stride, &ts, &seq);
	if (r == -ENODEV)
		return dao_error_set(err, -ENODEV, "libcamera: the camera was disconnected");
	if (r < 0)
		return r;
	f->depth = (struct dao_frame){.format = DAO_PIXFMT_DEPTH16, .width = s->w, .height = s->h,
			.stride = (int32_t)stride,
				      .data = (void *)data, .depth_unit = s->unit, .timestamp_ns = ts, .sequence = seq};
	f->color.format = DAO_PIXFMT_NONE;
	f->index = s->delivered++;
	return 0;
}

static void lc_stop(void *state)
{
	(void)state; /* the camera stops on close */
}

static void lc_close(void *state)
{
	struct lc_source *s = state;
	lcs_close(s->cam);
	free(s);
}

static const struct dao_source_ops lc_ops = {
	.version = DAO_SOURCE_OPS_VERSION,
	.probe = lc_probe,
	.list_devices = lc_list,
	.open = lc_open,
	.get_info = lc_info,
	.start = lc_start,
	.read = lc_read,
	.stop = lc_stop,
	.close = lc_close,
};

static const struct dao_plugin lc_plugin = {
	DAO_PLUGIN_HEADER,
	.name = "libcamera",
	.description = "time-of-flight depth through libcamera (mono raw R12/R10/R8 streams)",
	.source = &lc_ops,
};

DAO_PLUGIN_DEFINE(lc_plugin)
