/* SPDX-License-Identifier: MIT */
/*
 * GStreamer element "depthao": 16-bit depth in, ambient occlusion or the
 * occlusion-shaded image out, through libdepthao (one dao_context per
 * negotiated size and camera).
 *
 *   sink: video/x-raw GRAY16_LE (depth counts, metres = count * depth-unit)
 *   src:  GRAY8 / GRAY16_LE  the AO (visibility * 255 / round(visibility * 65535))
 *         RGB / RGBA / BGRx  the shaded image (dao_context_shade)
 *
 * The camera comes from fx/fy/cx/cy, else hfov/vfov (radians), else a
 * 58.5 x 45.6 degree field of view (with a warning).  Every AO parameter of
 * the library's table (dao_param_table) is a controllable property generated
 * at class_init: float -> double, int -> int, enum -> a registered GEnum,
 * colour -> uint 0xRRGGBB.  Property changes are applied by the streaming
 * thread before the next frame (dao_context_set_params), so the context is
 * only ever used by one thread.  The noise pattern's frame_index counts the
 * frames since the element started (the first frame is 0, as in
 * `depthao process`).
 *
 * Buffers are a stream of consecutive frames, so the temporal depth filter is
 * on by default (dao_params_stream_defaults: depth-temporal 0.8; the
 * property depth-temporal=0 turns it off, as a preset loaded by quality=
 * does not); its history starts over after a flush (a seek) and at a buffer
 * marked DISCONT, as after a new context (new caps or intrinsics).
 */
#include <math.h>
#include <string.h>

#include <gst/gst.h>
#include <gst/video/gstvideofilter.h>
#include <gst/video/video.h>

#include <depthao/context.h>
#include <depthao/params.h>

#ifndef PACKAGE
#define PACKAGE "depthao"
#endif
#ifndef VERSION
#define VERSION "0.0.0"
#endif

GST_DEBUG_CATEGORY_STATIC(gst_depthao_debug);
#define GST_CAT_DEFAULT gst_depthao_debug

#define DEFAULT_DEPTH_UNIT 0.001
#define DEFAULT_HFOV_DEG 58.5
#define DEFAULT_VFOV_DEG 45.6
#define SRC_FORMATS "{ RGB, BGRx, RGBA, GRAY8, GRAY16_LE }"

/* preferred output when downstream takes several: the shaded image first */
static const GstVideoFormat src_preference[] = {GST_VIDEO_FORMAT_RGB, GST_VIDEO_FORMAT_BGRx,
						GST_VIDEO_FORMAT_RGBA, GST_VIDEO_FORMAT_GRAY8,
						GST_VIDEO_FORMAT_GRAY16_LE};

#define GST_TYPE_DEPTHAO (gst_depthao_get_type())
G_DECLARE_FINAL_TYPE(GstDepthao, gst_depthao, GST, DEPTHAO, GstVideoFilter)

struct _GstDepthao {
	GstVideoFilter parent;

	/* properties, under the object lock */
	double depth_unit;
	double fx, fy, cx, cy; /* fx/fy 0 = unset; cx/cy < 0 = image centre */
	double hfov, vfov;     /* radians, 0 = unset */
	enum dao_quality quality;
	struct dao_params params; /* what the AO properties say */
	guint8 *explicit_set;     /* per table entry: set by the user (survives a preset) */
	gboolean params_dirty;    /* params changed since the context last got them */
	gboolean camera_dirty;    /* an intrinsics property changed */
	gboolean reset_pending;   /* a flush: the temporal histories start over */

	/* streaming thread */
	struct dao_context *ctx;
	struct dao_camera cam;
	guint64 frame_index;
	gchar *last_error;  /* the setup error posted last (not posted again on retries) */
	guint8 *scratch;    /* shaded RGB24 before repacking (RGBA, BGRx) */
	gsize scratch_size;
#if G_BYTE_ORDER == G_BIG_ENDIAN
	guint16 *swapped; /* GRAY16_LE depth in host order */
	gsize swapped_size;
#endif
};

G_DEFINE_TYPE(GstDepthao, gst_depthao, GST_TYPE_VIDEO_FILTER)

enum {
	PROP_0,
	PROP_DEPTH_UNIT,
	PROP_FX,
	PROP_FY,
	PROP_CX,
	PROP_CY,
	PROP_HFOV,
	PROP_VFOV,
	PROP_QUALITY,
	PROP_PARAM_FIRST, /* + index in the library's parameter table */
};

/* The library's table, and the GEnum type of each enum parameter (0 otherwise). */
static const struct dao_param_info *param_table;
static size_t param_count;
static GType *param_enum_types;

static GstStaticPadTemplate sink_template = GST_STATIC_PAD_TEMPLATE(
	"sink", GST_PAD_SINK, GST_PAD_ALWAYS,
	GST_STATIC_CAPS("video/x-raw, format = (string) GRAY16_LE, "
			"width = (int) [ 1, 16384 ], height = (int) [ 1, 16384 ], "
			"framerate = (fraction) [ 0, MAX ]"));

static GstStaticPadTemplate src_template = GST_STATIC_PAD_TEMPLATE(
	"src", GST_PAD_SRC, GST_PAD_ALWAYS,
	GST_STATIC_CAPS("video/x-raw, format = (string) " SRC_FORMATS ", "
			"width = (int) [ 1, 16384 ], height = (int) [ 1, 16384 ], "
			"framerate = (fraction) [ 0, MAX ]"));

/* ---- the quality preset as a GEnum ------------------------------------ */

static GType gst_depthao_quality_get_type(void)
{
	static GType type;
	static const GEnumValue values[] = {
		{DAO_QUALITY_LOW, "fewest samples", "low"},
		{DAO_QUALITY_MEDIUM, "the library's default", "medium"},
		{DAO_QUALITY_HIGH, "more slices and steps", "high"},
		{DAO_QUALITY_ULTRA, "most samples, bilateral denoise", "ultra"},
		{0, NULL, NULL},
	};
	if (g_once_init_enter(&type)) {
		GType t = g_enum_register_static("GstDepthaoQuality", values);
		g_once_init_leave(&type, t);
	}
	return type;
}

/* "denoise" -> "GstDepthaoDenoise", "foo-bar" -> "GstDepthaoFooBar" */
static GType register_param_enum(const struct dao_param_info *pi)
{
	GString *tn = g_string_new("GstDepthao");
	gboolean up = TRUE;
	for (const char *c = pi->name; *c; c++) {
		if (*c == '-' || *c == '_') {
			up = TRUE;
			continue;
		}
		g_string_append_c(tn, up ? g_ascii_toupper(*c) : *c);
		up = FALSE;
	}
	GType t = g_type_from_name(tn->str);
	if (!t) {
		guint n = 0;
		while (pi->enum_names[n])
			n++;
		/* registered types live for the process: never freed */
		GEnumValue *v = g_new0(GEnumValue, n + 1);
		for (guint i = 0; i < n; i++) {
			v[i].value = (gint)i;
			v[i].value_name = pi->enum_names[i];
			v[i].value_nick = pi->enum_names[i];
		}
		t = g_enum_register_static(g_intern_string(tn->str), v);
	}
	g_string_free(tn, TRUE);
	return t;
}

/* ---- parameter fields by table entry ---------------------------------- */

static void *param_field(struct dao_params *p, const struct dao_param_info *pi)
{
	return (char *)p + pi->offset;
}

static size_t param_size(const struct dao_param_info *pi)
{
	return pi->type == DAO_PARAM_FLOAT ? sizeof(float)
	       : pi->type == DAO_PARAM_COLOR ? sizeof(uint32_t)
					     : sizeof(int);
}

/* A float field as the double a user would have typed (0.3f -> 0.3, not 0.30000001). */
static double float_to_double(float f)
{
	static const char *const formats[] = {"%.6g", "%.7g", "%.8g", "%.9g"};
	char buf[G_ASCII_DTOSTR_BUF_SIZE];
	if (!isfinite(f))
		return (double)f;
	for (size_t i = 0; i < G_N_ELEMENTS(formats); i++) {
		double d = g_ascii_strtod(g_ascii_formatd(buf, sizeof buf, formats[i], (double)f), NULL);
		if ((float)d == f)
			return d;
	}
	return (double)f;
}

static void param_to_value(const struct dao_params *p, const struct dao_param_info *pi,
			   GValue *v)
{
	const void *f = (const char *)p + pi->offset;
	float fv;
	int iv;
	uint32_t uv;
	switch (pi->type) {
	case DAO_PARAM_FLOAT:
		memcpy(&fv, f, sizeof fv);
		g_value_set_double(v, float_to_double(fv));
		break;
	case DAO_PARAM_INT:
		memcpy(&iv, f, sizeof iv);
		g_value_set_int(v, iv);
		break;
	case DAO_PARAM_ENUM:
		memcpy(&iv, f, sizeof iv);
		g_value_set_enum(v, iv);
		break;
	case DAO_PARAM_COLOR:
		memcpy(&uv, f, sizeof uv);
		g_value_set_uint(v, uv);
		break;
	}
}

static void param_from_value(struct dao_params *p, const struct dao_param_info *pi,
			     const GValue *v)
{
	void *f = param_field(p, pi);
	float fv;
	int iv;
	uint32_t uv;
	switch (pi->type) {
	case DAO_PARAM_FLOAT:
		fv = (float)g_value_get_double(v);
		memcpy(f, &fv, sizeof fv);
		break;
	case DAO_PARAM_INT:
		iv = g_value_get_int(v);
		memcpy(f, &iv, sizeof iv);
		break;
	case DAO_PARAM_ENUM:
		iv = g_value_get_enum(v);
		memcpy(f, &iv, sizeof iv);
		break;
	case DAO_PARAM_COLOR:
		uv = g_value_get_uint(v);
		memcpy(f, &uv, sizeof uv);
		break;
	}
}

static GParamSpec *param_spec(const struct dao_param_info *pi, GType enum_type,
			      const struct dao_params *defaults)
{
	const GParamFlags flags = G_PARAM_READWRITE | G_PARAM_STATIC_NAME | G_PARAM_STATIC_NICK |
				  GST_PARAM_CONTROLLABLE | GST_PARAM_MUTABLE_PLAYING;
	gchar *blurb = pi->unit ? g_strdup_printf("%s (%s)", pi->help, pi->unit)
				: g_strdup(pi->help);
	GValue def = G_VALUE_INIT;
	GParamSpec *ps = NULL;
	switch (pi->type) {
	case DAO_PARAM_FLOAT:
		g_value_init(&def, G_TYPE_DOUBLE);
		param_to_value(defaults, pi, &def);
		ps = g_param_spec_double(pi->name, pi->name, blurb, pi->min, pi->max,
					 CLAMP(g_value_get_double(&def), pi->min, pi->max), flags);
		break;
	case DAO_PARAM_INT:
		g_value_init(&def, G_TYPE_INT);
		param_to_value(defaults, pi, &def);
		ps = g_param_spec_int(pi->name, pi->name, blurb, (gint)pi->min, (gint)pi->max,
				      CLAMP(g_value_get_int(&def), (gint)pi->min, (gint)pi->max),
				      flags);
		break;
	case DAO_PARAM_ENUM:
		g_value_init(&def, enum_type);
		param_to_value(defaults, pi, &def);
		ps = g_param_spec_enum(pi->name, pi->name, blurb, enum_type, g_value_get_enum(&def),
				       flags);
		break;
	case DAO_PARAM_COLOR:
		g_value_init(&def, G_TYPE_UINT);
		param_to_value(defaults, pi, &def);
		ps = g_param_spec_uint(pi->name, pi->name, blurb, 0, 0xffffff, g_value_get_uint(&def),
				       flags);
		break;
	}
	g_value_unset(&def);
	g_free(blurb); /* without G_PARAM_STATIC_BLURB the spec keeps its own copy */
	return ps;
}

/* ---- properties -------------------------------------------------------- */

static void gst_depthao_set_property(GObject *object, guint id, const GValue *value,
				     GParamSpec *pspec)
{
	GstDepthao *self = GST_DEPTHAO(object);
	GST_OBJECT_LOCK(self);
	switch (id) {
	case PROP_DEPTH_UNIT:
		self->depth_unit = g_value_get_double(value);
		break;
	case PROP_FX:
		self->fx = g_value_get_double(value);
		self->camera_dirty = TRUE;
		break;
	case PROP_FY:
		self->fy = g_value_get_double(value);
		self->camera_dirty = TRUE;
		break;
	case PROP_CX:
		self->cx = g_value_get_double(value);
		self->camera_dirty = TRUE;
		break;
	case PROP_CY:
		self->cy = g_value_get_double(value);
		self->camera_dirty = TRUE;
		break;
	case PROP_HFOV:
		self->hfov = g_value_get_double(value);
		self->camera_dirty = TRUE;
		break;
	case PROP_VFOV:
		self->vfov = g_value_get_double(value);
		self->camera_dirty = TRUE;
		break;
	case PROP_QUALITY: {
		/* the preset, then every parameter the user set explicitly on top */
		struct dao_params p;
		self->quality = (enum dao_quality)g_value_get_enum(value);
		dao_params_init(&p, self->quality);
		dao_params_stream_defaults(&p);
		for (size_t i = 0; i < param_count; i++)
			if (self->explicit_set[i]) {
				memcpy(param_field(&p, &param_table[i]),
				       param_field(&self->params, &param_table[i]),
				       param_size(&param_table[i]));
			}
		self->params = p;
		self->params_dirty = TRUE;
		break;
	}
	default:
		if (id >= PROP_PARAM_FIRST && id - PROP_PARAM_FIRST < param_count) {
			size_t i = id - PROP_PARAM_FIRST;
			param_from_value(&self->params, &param_table[i], value);
			self->explicit_set[i] = 1;
			self->params_dirty = TRUE;
		} else {
			G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
		}
		break;
	}
	GST_OBJECT_UNLOCK(self);
}

static void gst_depthao_get_property(GObject *object, guint id, GValue *value, GParamSpec *pspec)
{
	GstDepthao *self = GST_DEPTHAO(object);
	GST_OBJECT_LOCK(self);
	switch (id) {
	case PROP_DEPTH_UNIT:
		g_value_set_double(value, self->depth_unit);
		break;
	case PROP_FX:
		g_value_set_double(value, self->fx);
		break;
	case PROP_FY:
		g_value_set_double(value, self->fy);
		break;
	case PROP_CX:
		g_value_set_double(value, self->cx);
		break;
	case PROP_CY:
		g_value_set_double(value, self->cy);
		break;
	case PROP_HFOV:
		g_value_set_double(value, self->hfov);
		break;
	case PROP_VFOV:
		g_value_set_double(value, self->vfov);
		break;
	case PROP_QUALITY:
		g_value_set_enum(value, (gint)self->quality);
		break;
	default:
		if (id >= PROP_PARAM_FIRST && id - PROP_PARAM_FIRST < param_count)
			param_to_value(&self->params, &param_table[id - PROP_PARAM_FIRST], value);
		else
			G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
		break;
	}
	GST_OBJECT_UNLOCK(self);
}

/* ---- caps -------------------------------------------------------------- */

static GstCaps *gst_depthao_transform_caps(GstBaseTransform *bt, GstPadDirection direction,
					   GstCaps *caps, GstCaps *filter)
{
	GstCaps *res = gst_caps_new_empty();
	GValue formats = G_VALUE_INIT;
	if (direction == GST_PAD_SINK) { /* depth in -> every output format */
		gst_value_list_init(&formats, G_N_ELEMENTS(src_preference));
		for (size_t i = 0; i < G_N_ELEMENTS(src_preference); i++) {
			GValue f = G_VALUE_INIT;
			g_value_init(&f, G_TYPE_STRING);
			g_value_set_static_string(&f, gst_video_format_to_string(src_preference[i]));
			gst_value_list_append_and_take_value(&formats, &f);
		}
	} else {
		g_value_init(&formats, G_TYPE_STRING);
		g_value_set_static_string(&formats, "GRAY16_LE");
	}
	for (guint i = 0; i < gst_caps_get_size(caps); i++) {
		GstStructure *s = gst_structure_copy(gst_caps_get_structure(caps, i));
		GstCapsFeatures *f = gst_caps_get_features(caps, i);
		gst_structure_set_value(s, "format", &formats);
		gst_structure_remove_fields(s, "colorimetry", "chroma-site", NULL);
		gst_caps_append_structure_full(res, s, f ? gst_caps_features_copy(f) : NULL);
	}
	g_value_unset(&formats);
	if (filter) {
		GstCaps *tmp = gst_caps_intersect_full(filter, res, GST_CAPS_INTERSECT_FIRST);
		gst_caps_unref(res);
		res = tmp;
	}
	GST_DEBUG_OBJECT(bt, "%s %" GST_PTR_FORMAT " -> %" GST_PTR_FORMAT,
			 direction == GST_PAD_SINK ? "sink" : "src", caps, res);
	return res;
}

/* Of the formats downstream takes, the shaded image first, then the AO. */
static GstCaps *gst_depthao_fixate_caps(GstBaseTransform *bt, GstPadDirection direction,
					GstCaps *caps, GstCaps *othercaps)
{
	(void)caps;
	if (direction == GST_PAD_SINK) {
		for (size_t i = 0; i < G_N_ELEMENTS(src_preference); i++) {
			GstCaps *want = gst_caps_new_simple(
				"video/x-raw", "format", G_TYPE_STRING,
				gst_video_format_to_string(src_preference[i]), NULL);
			GstCaps *tmp = gst_caps_intersect(othercaps, want);
			gst_caps_unref(want);
			if (!gst_caps_is_empty(tmp)) {
				gst_caps_unref(othercaps);
				othercaps = tmp;
				break;
			}
			gst_caps_unref(tmp);
		}
	}
	othercaps = gst_caps_fixate(othercaps);
	GST_DEBUG_OBJECT(bt, "fixated to %" GST_PTR_FORMAT, othercaps);
	return othercaps;
}

/* ---- the context ------------------------------------------------------- */

/* Builds the camera from the properties (object lock held). */
static int make_camera(GstDepthao *self, uint32_t w, uint32_t h, struct dao_camera *cam,
		       struct dao_error *err)
{
	if (self->fx > 0 || self->fy > 0) {
		double fx = self->fx > 0 ? self->fx : self->fy, fy = self->fy > 0 ? self->fy : self->fx;
		double cx = self->cx >= 0 ? self->cx : (w - 1) / 2.0;
		double cy = self->cy >= 0 ? self->cy : (h - 1) / 2.0;
		return dao_camera_from_intrinsics(cam, w, h, fx, fy, cx, cy, err);
	}
	double hfov = self->hfov, vfov = self->vfov;
	if (hfov <= 0 && vfov <= 0) {
		hfov = DEFAULT_HFOV_DEG * (G_PI / 180.0);
		vfov = DEFAULT_VFOV_DEG * (G_PI / 180.0);
		GST_WARNING_OBJECT(self,
				   "no camera given (fx/fy/cx/cy or hfov/vfov): assuming a %.1f x %.1f "
				   "degree field of view",
				   DEFAULT_HFOV_DEG, DEFAULT_VFOV_DEG);
	} else if (vfov <= 0) { /* square pixels */
		vfov = 2.0 * atan(tan(hfov / 2.0) * h / w);
	} else if (hfov <= 0) {
		hfov = 2.0 * atan(tan(vfov / 2.0) * w / h);
	}
	return dao_camera_from_fov(cam, w, h, hfov, vfov, err);
}

static gboolean same_camera(const struct dao_camera *a, const struct dao_camera *b)
{
	return a->width == b->width && a->height == b->height && a->fx == b->fx && a->fy == b->fy &&
	       a->cx == b->cx && a->cy == b->cy;
}

/* Upstream retries the caps after a failure: post each setup error once. */
static gboolean new_setup_error(GstDepthao *self, const char *message)
{
	if (self->last_error && !strcmp(self->last_error, message))
		return FALSE;
	g_free(self->last_error);
	self->last_error = g_strdup(message);
	return TRUE;
}

/*
 * (Re)creates the context for a w x h stream, or gives it the current
 * parameters.  Posts an element error and returns FALSE when the camera or
 * the parameters are rejected.
 */
static gboolean setup_context(GstDepthao *self, uint32_t w, uint32_t h)
{
	struct dao_error err = {0};
	struct dao_camera cam;
	struct dao_params p;
	GST_OBJECT_LOCK(self);
	int r = make_camera(self, w, h, &cam, &err);
	p = self->params;
	self->params_dirty = FALSE;
	self->camera_dirty = FALSE;
	GST_OBJECT_UNLOCK(self);
	if (r < 0) {
		if (new_setup_error(self, err.message))
			GST_ELEMENT_ERROR(self, LIBRARY, SETTINGS,
					  ("Bad camera for depthao: %s", err.message),
					  ("%ux%u frames", w, h));
		return FALSE;
	}
	if (self->ctx && same_camera(&cam, &self->cam)) {
		r = dao_context_set_params(self->ctx, &p, &err);
	} else {
		dao_context_destroy(self->ctx);
		self->ctx = NULL;
		r = dao_context_create(&self->ctx, &cam, &p, &err);
		if (r == 0)
			self->cam = cam;
	}
	if (r < 0) {
		if (new_setup_error(self, err.message))
			GST_ELEMENT_ERROR(self, LIBRARY, SETTINGS,
					  ("depthao could not set up ambient occlusion: %s",
					   err.message),
					  ("camera %ux%u fx=%g fy=%g cx=%g cy=%g", w, h, cam.fx,
					   cam.fy, cam.cx, cam.cy));
		return FALSE;
	}
	g_clear_pointer(&self->last_error, g_free);
	GST_INFO_OBJECT(self, "context for %ux%u, fx=%g fy=%g cx=%g cy=%g", w, h, cam.fx, cam.fy,
			cam.cx, cam.cy);
	return TRUE;
}

static gboolean gst_depthao_set_info(GstVideoFilter *filter, GstCaps *incaps,
				     GstVideoInfo *in_info, GstCaps *outcaps,
				     GstVideoInfo *out_info)
{
	GstDepthao *self = GST_DEPTHAO(filter);
	GstVideoFormat of = GST_VIDEO_INFO_FORMAT(out_info);
	(void)incaps;
	(void)outcaps;
	if (GST_VIDEO_INFO_FORMAT(in_info) != GST_VIDEO_FORMAT_GRAY16_LE) {
		GST_ELEMENT_ERROR(self, CORE, NEGOTIATION,
				  ("depthao takes 16-bit depth (GRAY16_LE), not %s",
				   gst_video_format_to_string(GST_VIDEO_INFO_FORMAT(in_info))),
				  (NULL));
		return FALSE;
	}
	if (GST_VIDEO_INFO_WIDTH(in_info) != GST_VIDEO_INFO_WIDTH(out_info) ||
	    GST_VIDEO_INFO_HEIGHT(in_info) != GST_VIDEO_INFO_HEIGHT(out_info)) {
		GST_ELEMENT_ERROR(self, CORE, NEGOTIATION,
				  ("depthao does not scale: input %dx%d, output %dx%d",
				   GST_VIDEO_INFO_WIDTH(in_info), GST_VIDEO_INFO_HEIGHT(in_info),
				   GST_VIDEO_INFO_WIDTH(out_info), GST_VIDEO_INFO_HEIGHT(out_info)),
				  (NULL));
		return FALSE;
	}
	uint32_t w = (uint32_t)GST_VIDEO_INFO_WIDTH(in_info);
	uint32_t h = (uint32_t)GST_VIDEO_INFO_HEIGHT(in_info);
	if (!setup_context(self, w, h))
		return FALSE;
	g_free(self->scratch);
	self->scratch = NULL;
	self->scratch_size = 0;
	if (of == GST_VIDEO_FORMAT_RGBA || of == GST_VIDEO_FORMAT_BGRx) {
		self->scratch_size = (gsize)w * h * 3;
		self->scratch = g_malloc(self->scratch_size);
	}
#if G_BYTE_ORDER == G_BIG_ENDIAN
	g_free(self->swapped);
	self->swapped_size = (gsize)w * h;
	self->swapped = g_new(guint16, self->swapped_size);
#endif
	return TRUE;
}

/* ---- frames ------------------------------------------------------------ */

static void gst_depthao_before_transform(GstBaseTransform *bt, GstBuffer *buf)
{
	GstClockTime ts = GST_BUFFER_PTS(buf);
	if (!GST_CLOCK_TIME_IS_VALID(ts))
		return;
	GstClockTime st = gst_segment_to_stream_time(&bt->segment, GST_FORMAT_TIME, ts);
	if (GST_CLOCK_TIME_IS_VALID(st))
		gst_object_sync_values(GST_OBJECT(bt), st); /* controlled properties */
}

/* RGB24 rows -> RGBA (alpha 255) or BGRx */
static void repack_rgb(const guint8 *rgb, uint32_t w, uint32_t h, guint8 *out, gint stride,
		       gboolean bgrx)
{
	for (uint32_t y = 0; y < h; y++) {
		const guint8 *s = rgb + (gsize)y * w * 3;
		guint8 *d = out + (gsize)y * (gsize)stride;
		for (uint32_t x = 0; x < w; x++, s += 3, d += 4) {
			d[0] = bgrx ? s[2] : s[0];
			d[1] = s[1];
			d[2] = bgrx ? s[0] : s[2];
			d[3] = 255;
		}
	}
}

/*
 * What changed since the last frame (properties, a flush or a discontinuity):
 * a new context for new intrinsics, new parameters, or a reset of the
 * histories.  The depth unit in *unit.  FALSE if no context could be made.
 */
static gboolean apply_pending(GstDepthao *self, GstBuffer *buf, uint32_t w, uint32_t h,
			      float *unit)
{
	struct dao_error err = {0};
	GST_OBJECT_LOCK(self);
	gboolean camera_dirty = self->camera_dirty, params_dirty = self->params_dirty;
	gboolean reset = self->reset_pending || GST_BUFFER_FLAG_IS_SET(buf, GST_BUFFER_FLAG_DISCONT);
	struct dao_params p = self->params;
	self->params_dirty = FALSE;
	self->reset_pending = FALSE;
	*unit = (float)self->depth_unit;
	GST_OBJECT_UNLOCK(self);
	if (camera_dirty || !self->ctx) { /* intrinsics changed while playing: a new context */
		if (!setup_context(self, w, h))
			return FALSE;
	} else if (params_dirty && dao_context_set_params(self->ctx, &p, &err) < 0) {
		GST_ELEMENT_WARNING(self, LIBRARY, SETTINGS,
				    ("depthao kept its previous AO parameters: %s", err.message),
				    (NULL));
	}
	if (reset)
		dao_context_reset(self->ctx);
	return TRUE;
}

/* The input frame as the library's depth frame (little-endian samples). */
static struct dao_frame depth_of(GstDepthao *self, GstVideoFrame *in, float unit)
{
	const uint32_t w = (uint32_t)GST_VIDEO_FRAME_WIDTH(in);
	const uint32_t h = (uint32_t)GST_VIDEO_FRAME_HEIGHT(in);
	struct dao_frame depth = {
		.format = DAO_PIXFMT_DEPTH16,
		.width = w,
		.height = h,
		.stride = GST_VIDEO_FRAME_PLANE_STRIDE(in, 0),
		.data = GST_VIDEO_FRAME_PLANE_DATA(in, 0),
		.depth_unit = unit,
		.timestamp_ns = GST_BUFFER_PTS_IS_VALID(in->buffer) ? GST_BUFFER_PTS(in->buffer) : 0,
		.sequence = self->frame_index,
	};
#if G_BYTE_ORDER == G_BIG_ENDIAN
	for (uint32_t y = 0; y < h; y++) {
		const guint16 *s = (const guint16 *)((const guint8 *)depth.data +
						     (gsize)y * (gsize)depth.stride);
		for (uint32_t x = 0; x < w; x++)
			self->swapped[(gsize)y * w + x] = GUINT16_FROM_LE(s[x]);
	}
	depth.data = self->swapped;
	depth.stride = (int32_t)(w * 2);
#endif
	return depth;
}

/* The AO (GRAY8, GRAY16_LE) or the shaded image (RGB, RGBA, BGRx) of `depth` into `out`. */
static int render(GstDepthao *self, const struct dao_frame *depth, GstVideoFrame *out,
		  struct dao_error *err)
{
	const uint32_t w = depth->width, h = depth->height;
	GstVideoFormat of = GST_VIDEO_FRAME_FORMAT(out);
	guint8 *od = GST_VIDEO_FRAME_PLANE_DATA(out, 0);
	gint os = GST_VIDEO_FRAME_PLANE_STRIDE(out, 0);
	int r;
	if (of == GST_VIDEO_FORMAT_GRAY8 || of == GST_VIDEO_FORMAT_GRAY16_LE) {
		struct dao_frame ao = {.width = w, .height = h, .stride = os, .data = od};
		ao.format = of == GST_VIDEO_FORMAT_GRAY8 ? DAO_PIXFMT_GRAY8 : DAO_PIXFMT_GRAY16;
		r = dao_context_process(self->ctx, depth, NULL, self->frame_index, &ao, err);
#if G_BYTE_ORDER == G_BIG_ENDIAN
		if (r == 0 && of == GST_VIDEO_FORMAT_GRAY16_LE)
			for (uint32_t y = 0; y < h; y++) {
				guint16 *row = (guint16 *)(od + (gsize)y * (gsize)os);
				for (uint32_t x = 0; x < w; x++)
					row[x] = GUINT16_TO_LE(row[x]);
			}
#endif
		return r;
	}
	struct dao_frame rgb = {.format = DAO_PIXFMT_RGB24, .width = w, .height = h};
	if (of == GST_VIDEO_FORMAT_RGB) {
		rgb.stride = os;
		rgb.data = od;
	} else {
		rgb.stride = (int32_t)(w * 3);
		rgb.data = self->scratch;
	}
	r = dao_context_process(self->ctx, depth, NULL, self->frame_index, NULL, err);
	if (r == 0)
		r = dao_context_shade(self->ctx, &rgb, err);
	if (r == 0 && of != GST_VIDEO_FORMAT_RGB)
		repack_rgb(self->scratch, w, h, od, os, of == GST_VIDEO_FORMAT_BGRx);
	return r;
}

static GstFlowReturn gst_depthao_transform_frame(GstVideoFilter *filter, GstVideoFrame *in,
						 GstVideoFrame *out)
{
	GstDepthao *self = GST_DEPTHAO(filter);
	struct dao_error err = {0};
	float unit;
	if (!apply_pending(self, in->buffer, (uint32_t)GST_VIDEO_FRAME_WIDTH(in),
			   (uint32_t)GST_VIDEO_FRAME_HEIGHT(in), &unit))
		return GST_FLOW_ERROR;
	const struct dao_frame depth = depth_of(self, in, unit);
	if (render(self, &depth, out, &err) < 0) {
		GST_ELEMENT_ERROR(self, STREAM, FAILED, ("depthao: %s", err.message),
				  ("frame %" G_GUINT64_FORMAT, self->frame_index));
		return GST_FLOW_ERROR;
	}
	self->frame_index++;
	return GST_FLOW_OK;
}

/* ---- life cycle --------------------------------------------------------- */

static gboolean gst_depthao_start(GstBaseTransform *bt)
{
	GST_DEPTHAO(bt)->frame_index = 0;
	return TRUE;
}

/* A flush (a seek): the next frame does not follow the last one. */
static gboolean gst_depthao_sink_event(GstBaseTransform *bt, GstEvent *event)
{
	if (GST_EVENT_TYPE(event) == GST_EVENT_FLUSH_STOP) {
		GstDepthao *self = GST_DEPTHAO(bt);
		GST_OBJECT_LOCK(self);
		self->reset_pending = TRUE;
		GST_OBJECT_UNLOCK(self);
	}
	return GST_BASE_TRANSFORM_CLASS(gst_depthao_parent_class)->sink_event(bt, event);
}

static void release_stream(GstDepthao *self)
{
	dao_context_destroy(self->ctx);
	self->ctx = NULL;
	memset(&self->cam, 0, sizeof self->cam);
	g_clear_pointer(&self->last_error, g_free);
	g_free(self->scratch);
	self->scratch = NULL;
	self->scratch_size = 0;
#if G_BYTE_ORDER == G_BIG_ENDIAN
	g_free(self->swapped);
	self->swapped = NULL;
	self->swapped_size = 0;
#endif
}

static gboolean gst_depthao_stop(GstBaseTransform *bt)
{
	release_stream(GST_DEPTHAO(bt));
	return TRUE;
}

static void gst_depthao_finalize(GObject *object)
{
	GstDepthao *self = GST_DEPTHAO(object);
	release_stream(self);
	g_free(self->explicit_set);
	G_OBJECT_CLASS(gst_depthao_parent_class)->finalize(object);
}

static void gst_depthao_init(GstDepthao *self)
{
	self->depth_unit = DEFAULT_DEPTH_UNIT;
	self->cx = self->cy = -1;
	self->quality = DAO_QUALITY_DEFAULT;
	dao_params_init(&self->params, DAO_QUALITY_DEFAULT);
	dao_params_stream_defaults(&self->params);
	self->explicit_set = g_new0(guint8, param_count ? param_count : 1);
}

static void install_double(GObjectClass *oc, guint id, const char *name, const char *blurb,
			   double min, double max, double def)
{
	g_object_class_install_property(
		oc, id,
		g_param_spec_double(name, name, blurb, min, max, def,
				    G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS |
					    GST_PARAM_CONTROLLABLE | GST_PARAM_MUTABLE_PLAYING));
}

static void gst_depthao_class_init(GstDepthaoClass *klass)
{
	GObjectClass *oc = G_OBJECT_CLASS(klass);
	GstElementClass *ec = GST_ELEMENT_CLASS(klass);
	GstBaseTransformClass *bc = GST_BASE_TRANSFORM_CLASS(klass);
	GstVideoFilterClass *vc = GST_VIDEO_FILTER_CLASS(klass);

	oc->set_property = gst_depthao_set_property;
	oc->get_property = gst_depthao_get_property;
	oc->finalize = gst_depthao_finalize;

	install_double(oc, PROP_DEPTH_UNIT, "depth-unit", "metres per depth count (0.001 = mm)",
		       1e-7, 1.0, DEFAULT_DEPTH_UNIT);
	install_double(oc, PROP_FX, "fx", "focal length x in pixels (0 = from fy, hfov or default)",
		       0, 1e6, 0);
	install_double(oc, PROP_FY, "fy", "focal length y in pixels (0 = from fx, vfov or default)",
		       0, 1e6, 0);
	install_double(oc, PROP_CX, "cx", "principal point x in pixels (-1 = image centre)", -1,
		       1e6, -1);
	install_double(oc, PROP_CY, "cy", "principal point y in pixels (-1 = image centre)", -1,
		       1e6, -1);
	install_double(oc, PROP_HFOV,
		       "hfov", "horizontal field of view in radians, used without fx/fy "
			       "(0 = from vfov, or 58.5 degrees)",
		       0, 3.1, 0);
	install_double(oc, PROP_VFOV,
		       "vfov", "vertical field of view in radians, used without fx/fy "
			       "(0 = from hfov, or 45.6 degrees)",
		       0, 3.1, 0);
	g_object_class_install_property(
		oc, PROP_QUALITY,
		g_param_spec_enum("quality", "quality",
				  "AO preset; parameters set explicitly stay as set",
				  gst_depthao_quality_get_type(), DAO_QUALITY_DEFAULT,
				  G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS |
					  GST_PARAM_MUTABLE_PLAYING));

	/* every AO parameter of the library, from its table */
	struct dao_params defaults;
	dao_params_init(&defaults, DAO_QUALITY_DEFAULT);
	dao_params_stream_defaults(&defaults);
	param_table = dao_param_table(&param_count);
	param_enum_types = g_new0(GType, param_count ? param_count : 1);
	for (size_t i = 0; i < param_count; i++) {
		const struct dao_param_info *pi = &param_table[i];
		if (!g_param_spec_is_valid_name(pi->name) ||
		    g_object_class_find_property(oc, pi->name)) {
			GST_WARNING("AO parameter '%s' left out: its name clashes with a property",
				    pi->name);
			continue;
		}
		if (pi->type == DAO_PARAM_ENUM)
			param_enum_types[i] = register_param_enum(pi);
		GParamSpec *ps = param_spec(pi, param_enum_types[i], &defaults);
		if (ps)
			g_object_class_install_property(oc, (guint)(PROP_PARAM_FIRST + i), ps);
	}

	gst_element_class_set_static_metadata(
		ec, "Depth ambient occlusion", "Filter/Effect/Video",
		"Ambient occlusion (GRAY8, GRAY16_LE) or the occlusion-shaded image (RGB, RGBA, "
		"BGRx) from 16-bit depth (GRAY16_LE), with libdepthao",
		"depthao");
	gst_element_class_add_static_pad_template(ec, &sink_template);
	gst_element_class_add_static_pad_template(ec, &src_template);

	bc->transform_caps = gst_depthao_transform_caps;
	bc->fixate_caps = gst_depthao_fixate_caps;
	bc->before_transform = gst_depthao_before_transform;
	bc->start = gst_depthao_start;
	bc->sink_event = gst_depthao_sink_event;
	bc->stop = gst_depthao_stop;
	bc->passthrough_on_same_caps = FALSE;
	vc->set_info = gst_depthao_set_info;
	vc->transform_frame = gst_depthao_transform_frame;

	gst_type_mark_as_plugin_api(gst_depthao_quality_get_type(), 0);
	for (size_t i = 0; i < param_count; i++)
		if (param_enum_types[i])
			gst_type_mark_as_plugin_api(param_enum_types[i], 0);
}

static gboolean plugin_init(GstPlugin *plugin)
{
	GST_DEBUG_CATEGORY_INIT(gst_depthao_debug, "depthao", 0, "depthao ambient occlusion");
	return gst_element_register(plugin, "depthao", GST_RANK_NONE, GST_TYPE_DEPTHAO);
}

GST_PLUGIN_DEFINE(GST_VERSION_MAJOR, GST_VERSION_MINOR, depthao,
		  "Ambient occlusion from depth cameras (libdepthao)", plugin_init, VERSION,
		  "MIT/X11", "depthao", "depthao")
