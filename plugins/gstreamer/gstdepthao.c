/* SPDX-License-Identifier: MIT */
/*
 * GStreamer element "depthao": 16-bit depth in, ambient occlusion, the
 * occlusion-shaded image or AO over colour out, through libdepthao (one
 * dao_context per negotiated size and camera).
 *
 *   sink:       video/x-raw GRAY16_LE or GRAY16_BE (depth counts, metres =
 *               count * depth-unit; pngdec gives GRAY16_BE)
 *   color_sink: (request pad) video/x-raw RGB, the colour camera's frames
 *   src:  GRAY8 / GRAY16_LE  the AO (visibility * 255 / round(visibility * 65535))
 *         RGB / RGBA / BGRx  the shaded image (dao_context_shade), or with a
 *                            linked color_sink the colour darkened by the AO
 *                            (dao_overlay)
 *   depth_src: (request pad) GRAY16_LE, the filtered depth of each frame
 *               (dao_context_get_depth) in counts of depth-unit, 0 = no depth
 *   bus:  element messages "depthao-motion" (post-messages) while the camera's
 *         motion is followed (depth-temporal-motion): the motion estimate and
 *         the camera's pose of each frame (post_motion)
 *
 * depth_src is an optional output, so a request pad (as tee's src_%u or the
 * colour input here): requested by name (d.depth_src), it gets the input's
 * size and framerate, each input buffer's timestamps, the input's segment,
 * and EOS and flushes.  While it is not linked nothing is computed for it; a
 * branch that is not linked (or has ended) does not stop the AO output.
 *
 * AO over colour: each depth buffer is paired with the colour buffer whose
 * running time is nearest to its own (the earlier one on a tie; without
 * timestamps, one colour buffer per depth buffer in order); the depth
 * thread waits for the colour buffer that decides it, up to COLOR_QUEUE
 * colour buffers are held.  The two inputs must come from separate
 * streaming threads (two sources, or queues after a tee), as for any
 * element with two sink pads.  Colour of another size with the depth's
 * aspect ratio is scaled to the depth's size; another aspect ratio is an
 * element error.  The pad is given only when asked for by name
 * (d.color_sink): a colour stream linked to the element without a pad name
 * is refused as before (it would take the colour pad and leave the depth
 * unlinked).  A requested color_sink that is not linked when the
 * element starts is an error (the overlay would never come), and so is a
 * colour stream that ends before its first frame.
 *
 * The camera comes from fx/fy/cx/cy, else hfov-deg/vfov-deg (degrees, like
 * depthao's --fov; the radian properties hfov/vfov are deprecated), else a
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
 * marked DISCONT, as after a new context (another frame size or new
 * intrinsics; new caps of the same size and camera keep it).
 */
#include <math.h>
#include <string.h>

#include <gst/gst.h>
#include <gst/video/gstvideofilter.h>
#include <gst/video/video.h>

#include <depthao/context.h>
#include <depthao/overlay.h>
#include <depthao/params.h>
#include <depthao/pose.h>

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
#define SINK_FORMATS "{ GRAY16_LE, GRAY16_BE }"
/* colour buffers held while the depth they pair with is awaited */
#define COLOR_QUEUE 4
#define RAD_PER_DEG (G_PI / 180.0)

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
	double hfov, vfov;     /* radians, 0 = unset (properties hfov-deg, vfov-deg) */
	gboolean radians_warned; /* the deprecated radian properties were used */
	enum dao_quality quality;
	struct dao_params params; /* what the AO properties say */
	guint8 *explicit_set;     /* per table entry: set by the user (survives a preset) */
	gboolean params_dirty;    /* params changed since the context last got them */
	gboolean camera_dirty;    /* an intrinsics property changed */
	gboolean reset_pending;   /* a flush: the temporal histories start over */
	gboolean post_messages;   /* "depthao-motion" element messages while the motion is followed */

	/* streaming thread */
	struct dao_context *ctx;
	struct dao_camera cam;
	guint64 frame_index;
	gchar *last_error;  /* the setup error posted last (not posted again on retries) */
	guint8 *scratch;    /* shaded RGB24 before repacking (RGBA, BGRx) */
	gsize scratch_size;
	gboolean swap_in;   /* the depth's byte order is not the host's */
	guint16 *swapped;   /* the depth in host order when swap_in */
	guint16 *ao16;      /* AO over colour: the AO before it is laid over */

	/* colour input (request pad color_sink), under color_lock */
	GstPad *color_pad;
	GMutex color_lock;
	GCond color_cond;
	GstBuffer *color_q[COLOR_QUEUE];
	GstClockTime color_rt[COLOR_QUEUE]; /* running times */
	guint color_n;
	GstVideoInfo color_info;
	gboolean color_info_set;
	GstSegment color_segment;
	gboolean color_eos, color_flushing, depth_flushing;

	/* filtered-depth output (request pad depth_src); the pad under the object
	 * lock, the rest in the streaming thread */
	GstPad *depth_pad;
	gboolean depth_started;      /* stream-start sent */
	gboolean depth_caps_pending; /* the input's caps changed: new caps to send */
	gboolean depth_seg_pending;  /* a new segment to send */
	GstVideoInfo depth_info;     /* GRAY16_LE of the input's size */
	GstBufferPool *depth_pool;
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
	PROP_HFOV_DEG,
	PROP_VFOV_DEG,
	PROP_QUALITY,
	PROP_POST_MESSAGES,
	PROP_PARAM_FIRST, /* + index in the library's parameter table */
};

/* The library's table, and the GEnum type of each enum parameter (0 otherwise). */
static const struct dao_param_info *param_table;
static size_t param_count;
static GType *param_enum_types;

static GstStaticPadTemplate sink_template = GST_STATIC_PAD_TEMPLATE(
	"sink", GST_PAD_SINK, GST_PAD_ALWAYS,
	GST_STATIC_CAPS("video/x-raw, format = (string) " SINK_FORMATS ", "
			"width = (int) [ 1, 16384 ], height = (int) [ 1, 16384 ], "
			"framerate = (fraction) [ 0, MAX ]"));

static GstStaticPadTemplate color_template = GST_STATIC_PAD_TEMPLATE(
	"color_sink", GST_PAD_SINK, GST_PAD_REQUEST,
	GST_STATIC_CAPS("video/x-raw, format = (string) RGB, "
			"width = (int) [ 1, 16384 ], height = (int) [ 1, 16384 ], "
			"framerate = (fraction) [ 0, MAX ]"));

static GstStaticPadTemplate depth_template = GST_STATIC_PAD_TEMPLATE(
	"depth_src", GST_PAD_SRC, GST_PAD_REQUEST,
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
	case PROP_VFOV:
		if (!self->radians_warned)
			GST_WARNING_OBJECT(self, "the properties hfov and vfov (radians) are "
					   "deprecated: use hfov-deg and vfov-deg (degrees)");
		self->radians_warned = TRUE;
		*(id == PROP_HFOV ? &self->hfov : &self->vfov) = g_value_get_double(value);
		self->camera_dirty = TRUE;
		break;
	case PROP_HFOV_DEG:
	case PROP_VFOV_DEG:
		/* as depthao process --fov H,V turns degrees into radians */
		*(id == PROP_HFOV_DEG ? &self->hfov : &self->vfov) =
			g_value_get_double(value) * RAD_PER_DEG;
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
	case PROP_POST_MESSAGES:
		self->post_messages = g_value_get_boolean(value);
		break;
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
	case PROP_HFOV_DEG:
		g_value_set_double(value, self->hfov / RAD_PER_DEG);
		break;
	case PROP_VFOV_DEG:
		g_value_set_double(value, self->vfov / RAD_PER_DEG);
		break;
	case PROP_QUALITY:
		g_value_set_enum(value, (gint)self->quality);
		break;
	case PROP_POST_MESSAGES:
		g_value_set_boolean(value, self->post_messages);
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
	GstDepthao *self = GST_DEPTHAO(bt);
	GstCaps *res = gst_caps_new_empty();
	GValue formats = G_VALUE_INIT;
	/* with colour linked, the output is AO over colour: the RGB formats */
	GST_OBJECT_LOCK(self);
	const size_t nout = self->color_pad ? 3 : G_N_ELEMENTS(src_preference);
	GST_OBJECT_UNLOCK(self);
	if (direction == GST_PAD_SINK) { /* depth in -> every output format */
		gst_value_list_init(&formats, nout);
		for (size_t i = 0; i < nout; i++) {
			GValue f = G_VALUE_INIT;
			g_value_init(&f, G_TYPE_STRING);
			g_value_set_static_string(&f, gst_video_format_to_string(src_preference[i]));
			gst_value_list_append_and_take_value(&formats, &f);
		}
	} else {
		static const char *const in_formats[] = {"GRAY16_LE", "GRAY16_BE"};
		gst_value_list_init(&formats, 2);
		for (size_t i = 0; i < G_N_ELEMENTS(in_formats); i++) {
			GValue f = G_VALUE_INIT;
			g_value_init(&f, G_TYPE_STRING);
			g_value_set_static_string(&f, in_formats[i]);
			gst_value_list_append_and_take_value(&formats, &f);
		}
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
				   "no camera given (fx/fy/cx/cy or hfov-deg/vfov-deg): assuming a %.1f "
				   "x %.1f degree field of view",
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
	GstVideoFormat inf = GST_VIDEO_INFO_FORMAT(in_info);
	if (inf != GST_VIDEO_FORMAT_GRAY16_LE && inf != GST_VIDEO_FORMAT_GRAY16_BE) {
		GST_ELEMENT_ERROR(self, CORE, NEGOTIATION,
				  ("depthao takes 16-bit depth (GRAY16_LE or GRAY16_BE), not %s",
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
	self->swap_in = (inf == GST_VIDEO_FORMAT_GRAY16_BE) != (G_BYTE_ORDER == G_BIG_ENDIAN);
	g_clear_pointer(&self->swapped, g_free);
	if (self->swap_in)
		self->swapped = g_new(guint16, (gsize)w * h);
	g_clear_pointer(&self->ao16, g_free);
	if (self->color_pad)
		self->ao16 = g_new(guint16, (gsize)w * h);
	/* the filtered depth: GRAY16_LE of the input's size, rate and aspect */
	gst_video_info_set_format(&self->depth_info, GST_VIDEO_FORMAT_GRAY16_LE, w, h);
	GST_VIDEO_INFO_FPS_N(&self->depth_info) = GST_VIDEO_INFO_FPS_N(in_info);
	GST_VIDEO_INFO_FPS_D(&self->depth_info) = GST_VIDEO_INFO_FPS_D(in_info);
	GST_VIDEO_INFO_PAR_N(&self->depth_info) = GST_VIDEO_INFO_PAR_N(in_info);
	GST_VIDEO_INFO_PAR_D(&self->depth_info) = GST_VIDEO_INFO_PAR_D(in_info);
	self->depth_caps_pending = TRUE;
	GST_INFO_OBJECT(self, "%ux%u %s depth%s", w, h, gst_video_format_to_string(inf),
			self->color_pad ? ", AO over colour" : "");
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

/* The input frame as the library's depth frame (host-order samples). */
static struct dao_frame depth_of(GstDepthao *self, GstVideoFrame *in, float unit)
{
	const uint32_t w = (uint32_t)GST_VIDEO_FRAME_WIDTH(in);
	const uint32_t h = (uint32_t)GST_VIDEO_FRAME_HEIGHT(in);
	struct dao_frame depth = {
		.size = DAO_FRAME_SIZE,
		.format = DAO_PIXFMT_DEPTH16,
		.width = w,
		.height = h,
		.stride = GST_VIDEO_FRAME_PLANE_STRIDE(in, 0),
		.data = GST_VIDEO_FRAME_PLANE_DATA(in, 0),
		.depth_unit = unit,
		.timestamp_ns = GST_BUFFER_PTS_IS_VALID(in->buffer) ? GST_BUFFER_PTS(in->buffer) : 0,
		.sequence = self->frame_index,
	};
	if (self->swap_in) { /* GRAY16_BE on a little-endian host (or LE on a big one) */
		for (uint32_t y = 0; y < h; y++) {
			const guint8 *s = (const guint8 *)depth.data + (gsize)y * (gsize)depth.stride;
			guint16 *d = self->swapped + (gsize)y * w;
			for (uint32_t x = 0; x < w; x++) {
				guint16 v;
				memcpy(&v, s + 2 * (gsize)x, 2);
				d[x] = GUINT16_SWAP_LE_BE(v);
			}
		}
		depth.data = self->swapped;
		depth.stride = (int32_t)(w * 2);
	}
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
		struct dao_frame ao = {.size = DAO_FRAME_SIZE, .width = w, .height = h, .stride = os,
				       .data = od};
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
	struct dao_frame rgb = {.size = DAO_FRAME_SIZE, .format = DAO_PIXFMT_RGB24, .width = w,
				.height = h};
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

/* ---- the camera's motion (element messages) ------------------------------ */

static const char *const motion_state_names[] = {"none", "refused", "still", "applied"};

/* n doubles as a GstValueArray field ("< a, b, c >") */
static void set_doubles(GstStructure *s, const char *field, const double *v, guint n)
{
	GValue arr = G_VALUE_INIT, d = G_VALUE_INIT;
	gst_value_array_init(&arr, n);
	g_value_init(&d, G_TYPE_DOUBLE);
	for (guint i = 0; i < n; i++) {
		g_value_set_double(&d, v[i]);
		gst_value_array_append_value(&arr, &d);
	}
	g_value_unset(&d);
	gst_structure_take_value(s, field, &arr);
}

/*
 * After a frame: while the context follows the camera's motion (its pose
 * track runs) and post-messages is on, an element message "depthao-motion"
 * with the buffer's times (as the level element gives them), the motion
 * estimate (dao_context_motion: state, reason, this frame to the last as a
 * quaternion x, y, z, w and metres) and the camera's pose
 * (dao_context_pose_track: this frame's optical frame to the track's first,
 * with pose-current FALSE where it was held from an earlier frame).
 */
static void post_motion(GstDepthao *self, GstBaseTransform *bt, GstBuffer *buf,
			guint64 frame_index)
{
	GST_OBJECT_LOCK(self);
	const gboolean post = self->post_messages;
	GST_OBJECT_UNLOCK(self);
	if (!post)
		return;
	struct dao_pose_track pt = DAO_POSE_TRACK_INIT;
	dao_context_pose_track(self->ctx, &pt);
	if (pt.frames == 0) /* the motion not followed */
		return;
	struct dao_motion_info mi = DAO_MOTION_INFO_INIT;
	dao_context_motion(self->ctx, &mi);
	const GstClockTime pts = GST_BUFFER_PTS(buf);
	GstClockTime st = GST_CLOCK_TIME_NONE, rt = GST_CLOCK_TIME_NONE;
	if (GST_CLOCK_TIME_IS_VALID(pts)) {
		st = gst_segment_to_stream_time(&bt->segment, GST_FORMAT_TIME, pts);
		rt = gst_segment_to_running_time(&bt->segment, GST_FORMAT_TIME, pts);
	}
	const int state = mi.state >= 0 && mi.state <= 3 ? mi.state : 0;
	double mq[4], pq[4];
	dao_pose_matrix_to_quat(mi.rotation, mq);
	dao_pose_matrix_to_quat(pt.rotation, pq);
	GstStructure *s = gst_structure_new(
		"depthao-motion", "timestamp", G_TYPE_UINT64, (guint64)pts, "stream-time",
		G_TYPE_UINT64, (guint64)st, "running-time", G_TYPE_UINT64, (guint64)rt, "duration",
		G_TYPE_UINT64, (guint64)GST_BUFFER_DURATION(buf), "frame", G_TYPE_UINT64,
		frame_index, "state", G_TYPE_STRING, motion_state_names[state], "reason",
		G_TYPE_INT, mi.reason, "pose-current", G_TYPE_BOOLEAN, pt.current ? TRUE : FALSE,
		"pose-frame", G_TYPE_UINT64, (guint64)pt.frame_index,
		"track-frames", G_TYPE_UINT64, (guint64)pt.frames, "track-accepted", G_TYPE_UINT64,
		(guint64)pt.accepted, "track-refused", G_TYPE_UINT64, (guint64)pt.refused, NULL);
	set_doubles(s, "motion-rotation", mq, 4);
	set_doubles(s, "motion-translation", mi.translation, 3);
	set_doubles(s, "pose-rotation", pq, 4);
	set_doubles(s, "pose-translation", pt.translation, 3);
	gst_element_post_message(GST_ELEMENT(self), gst_message_new_element(GST_OBJECT(self), s));
}

/* ---- filtered depth (depth_src) ----------------------------------------- */

/* stream-start, caps (and a buffer pool for them), segment: those not sent yet */
static gboolean depth_events(GstDepthao *self, GstBaseTransform *bt, GstPad *pad)
{
	if (!self->depth_started) {
		gchar *id = gst_pad_create_stream_id(pad, GST_ELEMENT(self), "depth");
		gst_pad_push_event(pad, gst_event_new_stream_start(id));
		g_free(id);
		self->depth_started = TRUE;
	}
	if (self->depth_caps_pending) {
		GstCaps *caps = gst_video_info_to_caps(&self->depth_info);
		gboolean ok = gst_pad_push_event(pad, gst_event_new_caps(gst_caps_ref(caps)));
		if (self->depth_pool) {
			gst_buffer_pool_set_active(self->depth_pool, FALSE);
			gst_clear_object(&self->depth_pool);
		}
		GstBufferPool *pool = gst_video_buffer_pool_new();
		GstStructure *config = gst_buffer_pool_get_config(pool);
		gst_buffer_pool_config_set_params(config, caps, (guint)self->depth_info.size, 2, 0);
		if (gst_buffer_pool_set_config(pool, config) && gst_buffer_pool_set_active(pool, TRUE))
			self->depth_pool = pool;
		else
			gst_object_unref(pool);
		gst_caps_unref(caps);
		if (!ok || !self->depth_pool)
			return FALSE;
		self->depth_caps_pending = FALSE;
	}
	if (self->depth_seg_pending) {
		gst_pad_push_event(pad, gst_event_new_segment(&bt->segment));
		self->depth_seg_pending = FALSE;
	}
	return TRUE;
}

/* The filtered depth of the frame just processed, out of depth_src in counts of
 * `unit` with the input buffer's timestamps; nothing when the pad is not linked.
 * Only errors of that branch (not-negotiated, error) stop the element. */
static GstFlowReturn push_depth(GstDepthao *self, GstBaseTransform *bt, GstBuffer *inbuf,
				float unit)
{
	GST_OBJECT_LOCK(self);
	GstPad *pad = self->depth_pad ? gst_object_ref(self->depth_pad) : NULL;
	GST_OBJECT_UNLOCK(self);
	if (!pad)
		return GST_FLOW_OK;
	GstFlowReturn ret = GST_FLOW_OK;
	GstBuffer *buf = NULL;
	GstVideoFrame vf;
	struct dao_error err = {0};
	if (!gst_pad_is_linked(pad))
		goto out;
	if (!depth_events(self, bt, pad)) {
		ret = GST_FLOW_NOT_NEGOTIATED;
		GST_ELEMENT_ERROR(self, CORE, NEGOTIATION,
				  ("depthao: downstream of depth_src does not take %ux%u GRAY16_LE",
				   GST_VIDEO_INFO_WIDTH(&self->depth_info),
				   GST_VIDEO_INFO_HEIGHT(&self->depth_info)), (NULL));
		goto out;
	}
	if ((ret = gst_buffer_pool_acquire_buffer(self->depth_pool, &buf, NULL)) != GST_FLOW_OK)
		goto out;
	if (!gst_video_frame_map(&vf, &self->depth_info, buf, GST_MAP_WRITE)) {
		ret = GST_FLOW_ERROR;
		goto out;
	}
	struct dao_frame d = {
		.size = DAO_FRAME_SIZE, .format = DAO_PIXFMT_DEPTH16,
		.width = (uint32_t)GST_VIDEO_FRAME_WIDTH(&vf),
		.height = (uint32_t)GST_VIDEO_FRAME_HEIGHT(&vf),
		.stride = GST_VIDEO_FRAME_PLANE_STRIDE(&vf, 0),
		.data = GST_VIDEO_FRAME_PLANE_DATA(&vf, 0), .depth_unit = unit,
	};
	int r = dao_context_get_depth(self->ctx, &d, &err);
#if G_BYTE_ORDER == G_BIG_ENDIAN
	for (uint32_t y = 0; r == 0 && y < d.height; y++) {
		guint16 *row = (guint16 *)((guint8 *)d.data + (gsize)y * (gsize)d.stride);
		for (uint32_t x = 0; x < d.width; x++)
			row[x] = GUINT16_TO_LE(row[x]);
	}
#endif
	gst_video_frame_unmap(&vf);
	if (r < 0) {
		GST_ELEMENT_ERROR(self, STREAM, FAILED, ("depthao: depth_src: %s", err.message),
				  (NULL));
		ret = GST_FLOW_ERROR;
		goto out;
	}
	gst_buffer_copy_into(buf, inbuf, GST_BUFFER_COPY_TIMESTAMPS, 0, (gsize)-1);
	if (GST_BUFFER_FLAG_IS_SET(inbuf, GST_BUFFER_FLAG_DISCONT))
		GST_BUFFER_FLAG_SET(buf, GST_BUFFER_FLAG_DISCONT);
	ret = gst_pad_push(pad, buf);
	buf = NULL;
	/* a branch that is unlinked, flushing or at its end leaves the AO alone */
	if (ret == GST_FLOW_NOT_LINKED || ret == GST_FLOW_FLUSHING || ret == GST_FLOW_EOS)
		ret = GST_FLOW_OK;
out:
	if (buf)
		gst_buffer_unref(buf);
	gst_object_unref(pad);
	return ret;
}

/* The depth input's EOS and flushes go out of depth_src too; a new segment at the
 * next buffer. */
static void depth_sink_event(GstDepthao *self, GstEvent *event)
{
	GstEventType t = GST_EVENT_TYPE(event);
	if (t == GST_EVENT_SEGMENT || t == GST_EVENT_FLUSH_STOP) {
		self->depth_seg_pending = TRUE;
		if (t == GST_EVENT_SEGMENT)
			return;
	}
	if (t != GST_EVENT_EOS && t != GST_EVENT_FLUSH_START && t != GST_EVENT_FLUSH_STOP)
		return;
	GST_OBJECT_LOCK(self);
	GstPad *pad = self->depth_pad ? gst_object_ref(self->depth_pad) : NULL;
	GST_OBJECT_UNLOCK(self);
	if (!pad)
		return;
	if (t == GST_EVENT_EOS && !self->depth_started && gst_pad_is_linked(pad)) {
		gchar *id = gst_pad_create_stream_id(pad, GST_ELEMENT(self), "depth");
		gst_pad_push_event(pad, gst_event_new_stream_start(id));
		g_free(id);
		self->depth_started = TRUE;
	}
	if (self->depth_started)
		gst_pad_push_event(pad, gst_event_ref(event));
	gst_object_unref(pad);
}

/* ---- colour ------------------------------------------------------------ */

static void color_pop(GstDepthao *self)
{
	gst_buffer_unref(self->color_q[0]);
	memmove(self->color_q, self->color_q + 1, (self->color_n - 1) * sizeof(self->color_q[0]));
	memmove(self->color_rt, self->color_rt + 1, (self->color_n - 1) * sizeof(self->color_rt[0]));
	self->color_n--;
	g_cond_broadcast(&self->color_cond);
}

static void color_clear(GstDepthao *self)
{
	while (self->color_n)
		color_pop(self);
}

/*
 * The colour buffer for a depth buffer at running time t (a reference, with
 * its video info in *info), waiting for the colour that decides it.  NULL
 * with *ret FLUSHING while flushing, or ERROR (posted) when the colour
 * stream ended before its first frame.
 */
static GstBuffer *color_for(GstDepthao *self, GstClockTime t, GstVideoInfo *info,
			    GstFlowReturn *ret)
{
	GstBuffer *buf = NULL;
	g_mutex_lock(&self->color_lock);
	for (;;) {
		if (self->depth_flushing || self->color_flushing) {
			*ret = GST_FLOW_FLUSHING;
			g_mutex_unlock(&self->color_lock);
			return NULL;
		}
		/* a colour buffer with a later one not after t is never the nearest */
		while (GST_CLOCK_TIME_IS_VALID(t) && self->color_n >= 2 &&
		       GST_CLOCK_TIME_IS_VALID(self->color_rt[1]) && self->color_rt[1] <= t)
			color_pop(self);
		GstClockTime last = self->color_n ? self->color_rt[self->color_n - 1] : 0;
		if (self->color_n && (!GST_CLOCK_TIME_IS_VALID(t) || !GST_CLOCK_TIME_IS_VALID(last) ||
				      last >= t))
			break; /* colour at or after t: the nearest is known */
		if (self->color_eos)
			break; /* no more colour: the last one is the nearest */
		g_cond_wait(&self->color_cond, &self->color_lock);
	}
	if (self->color_n == 0) {
		g_mutex_unlock(&self->color_lock);
		GST_ELEMENT_ERROR(self, STREAM, FAILED,
				  ("depthao: the colour stream (color_sink) ended before its first "
				   "frame, so there is no colour to lay the AO over"),
				  (NULL));
		*ret = GST_FLOW_ERROR;
		return NULL;
	}
	guint i = 0;
	if (GST_CLOCK_TIME_IS_VALID(t) && GST_CLOCK_TIME_IS_VALID(self->color_rt[0])) {
		if (self->color_n >= 2 && self->color_rt[0] < t && self->color_rt[1] > t &&
		    self->color_rt[1] - t < t - self->color_rt[0])
			i = 1;
		buf = gst_buffer_ref(self->color_q[i]);
		*info = self->color_info;
	} else { /* no timestamps: one colour buffer per depth buffer, in order */
		buf = gst_buffer_ref(self->color_q[0]);
		*info = self->color_info;
		color_pop(self);
	}
	g_mutex_unlock(&self->color_lock);
	return buf;
}

/* AO over the colour paired with this depth buffer into `out` (RGB, RGBA, BGRx). */
static GstFlowReturn render_overlay(GstDepthao *self, GstBaseTransform *bt,
				    const struct dao_frame *depth, GstVideoFrame *out,
				    struct dao_error *err)
{
	const uint32_t w = depth->width, h = depth->height;
	GstClockTime pts = GST_BUFFER_PTS(out->buffer);
	GstClockTime t = GST_CLOCK_TIME_IS_VALID(pts)
				 ? gst_segment_to_running_time(&bt->segment, GST_FORMAT_TIME, pts)
				 : GST_CLOCK_TIME_NONE;
	GstVideoInfo cinfo;
	GstFlowReturn ret = GST_FLOW_OK;
	GstBuffer *cbuf = color_for(self, t, &cinfo, &ret);
	if (!cbuf)
		return ret;
	GstVideoFrame cf;
	if (!gst_video_frame_map(&cf, &cinfo, cbuf, GST_MAP_READ)) {
		gst_buffer_unref(cbuf);
		GST_ELEMENT_ERROR(self, STREAM, FAILED, ("depthao: cannot map a colour buffer"),
				  (NULL));
		return GST_FLOW_ERROR;
	}
	struct dao_frame color = {
		.size = DAO_FRAME_SIZE,
		.format = DAO_PIXFMT_RGB24,
		.width = (uint32_t)GST_VIDEO_FRAME_WIDTH(&cf),
		.height = (uint32_t)GST_VIDEO_FRAME_HEIGHT(&cf),
		.stride = GST_VIDEO_FRAME_PLANE_STRIDE(&cf, 0),
		.data = GST_VIDEO_FRAME_PLANE_DATA(&cf, 0),
	};
	struct dao_frame ao = {.size = DAO_FRAME_SIZE, .format = DAO_PIXFMT_GRAY16, .width = w,
			       .height = h, .stride = (int32_t)(w * 2), .data = self->ao16};
	GstVideoFormat of = GST_VIDEO_FRAME_FORMAT(out);
	struct dao_frame rgb = {.size = DAO_FRAME_SIZE, .format = DAO_PIXFMT_RGB24, .width = w,
				.height = h};
	if (of == GST_VIDEO_FORMAT_RGB) {
		rgb.stride = GST_VIDEO_FRAME_PLANE_STRIDE(out, 0);
		rgb.data = GST_VIDEO_FRAME_PLANE_DATA(out, 0);
	} else {
		rgb.stride = (int32_t)(w * 3);
		rgb.data = self->scratch;
	}
	int r = dao_context_process(self->ctx, depth, NULL, self->frame_index, &ao, err);
	if (r == 0)
		r = dao_overlay(&color, &ao, &rgb, err);
	gst_video_frame_unmap(&cf);
	gst_buffer_unref(cbuf);
	if (r < 0)
		return GST_FLOW_ERROR;
	if (of != GST_VIDEO_FORMAT_RGB)
		repack_rgb(self->scratch, w, h, GST_VIDEO_FRAME_PLANE_DATA(out, 0),
			   GST_VIDEO_FRAME_PLANE_STRIDE(out, 0), of == GST_VIDEO_FORMAT_BGRx);
	return GST_FLOW_OK;
}

static GstFlowReturn color_chain(GstPad *pad, GstObject *parent, GstBuffer *buf)
{
	GstDepthao *self = GST_DEPTHAO(parent);
	(void)pad;
	g_mutex_lock(&self->color_lock);
	GstClockTime pts = GST_BUFFER_PTS(buf);
	GstClockTime rt = GST_CLOCK_TIME_IS_VALID(pts)
				  ? gst_segment_to_running_time(&self->color_segment, GST_FORMAT_TIME,
								pts)
				  : GST_CLOCK_TIME_NONE;
	while (self->color_n == COLOR_QUEUE && !self->color_flushing)
		g_cond_wait(&self->color_cond, &self->color_lock);
	if (self->color_flushing) {
		g_mutex_unlock(&self->color_lock);
		gst_buffer_unref(buf);
		return GST_FLOW_FLUSHING;
	}
	self->color_q[self->color_n] = buf;
	self->color_rt[self->color_n++] = rt;
	g_cond_broadcast(&self->color_cond);
	g_mutex_unlock(&self->color_lock);
	return GST_FLOW_OK;
}

/* The colour pad's events stay here: its caps, segment, flushes and EOS. */
static gboolean color_event(GstPad *pad, GstObject *parent, GstEvent *event)
{
	GstDepthao *self = GST_DEPTHAO(parent);
	gboolean ok = TRUE;
	(void)pad;
	g_mutex_lock(&self->color_lock);
	switch (GST_EVENT_TYPE(event)) {
	case GST_EVENT_CAPS: {
		GstCaps *caps;
		gst_event_parse_caps(event, &caps);
		ok = gst_video_info_from_caps(&self->color_info, caps);
		self->color_info_set = ok;
		break;
	}
	case GST_EVENT_SEGMENT:
		gst_event_copy_segment(event, &self->color_segment);
		break;
	case GST_EVENT_FLUSH_START:
		self->color_flushing = TRUE;
		g_cond_broadcast(&self->color_cond);
		break;
	case GST_EVENT_FLUSH_STOP:
		color_clear(self);
		self->color_flushing = FALSE;
		self->color_eos = FALSE;
		gst_segment_init(&self->color_segment, GST_FORMAT_TIME);
		break;
	case GST_EVENT_EOS:
		self->color_eos = TRUE;
		g_cond_broadcast(&self->color_cond);
		break;
	default:
		break;
	}
	g_mutex_unlock(&self->color_lock);
	gst_event_unref(event);
	return ok;
}

static gboolean color_query(GstPad *pad, GstObject *parent, GstQuery *query)
{
	switch (GST_QUERY_TYPE(query)) {
	case GST_QUERY_ALLOCATION:
		return FALSE; /* upstream allocates as it likes */
	case GST_QUERY_CAPS: {
		GstCaps *filter, *caps = gst_pad_get_pad_template_caps(pad);
		gst_query_parse_caps(query, &filter);
		if (filter) {
			GstCaps *tmp = gst_caps_intersect_full(filter, caps, GST_CAPS_INTERSECT_FIRST);
			gst_caps_unref(caps);
			caps = tmp;
		}
		gst_query_set_caps_result(query, caps);
		gst_caps_unref(caps);
		return TRUE;
	}
	default:
		return gst_pad_query_default(pad, parent, query);
	}
}

/* depth_src: its caps fixed once known, queries and upstream events as the
 * default handlers do (through the depth input) */
static GstPad *request_depth_pad(GstDepthao *self, GstPadTemplate *templ)
{
	GST_OBJECT_LOCK(self);
	if (self->depth_pad) {
		GST_OBJECT_UNLOCK(self);
		GST_WARNING_OBJECT(self, "depthao has one depth_src pad");
		return NULL;
	}
	GstPad *pad = gst_pad_new_from_template(templ, "depth_src");
	gst_pad_use_fixed_caps(pad);
	self->depth_pad = pad;
	self->depth_started = FALSE;
	self->depth_caps_pending = TRUE;
	self->depth_seg_pending = TRUE;
	GST_OBJECT_UNLOCK(self);
	gst_element_add_pad(GST_ELEMENT(self), pad);
	return pad;
}

static GstPad *gst_depthao_request_new_pad(GstElement *element, GstPadTemplate *templ,
					   const gchar *name, const GstCaps *caps)
{
	GstDepthao *self = GST_DEPTHAO(element);
	(void)caps;
	if (!strcmp(GST_PAD_TEMPLATE_NAME_TEMPLATE(templ), "depth_src"))
		return request_depth_pad(self, templ);
	/* only by name (d.color_sink): linking colour caps to the element without naming
	 * a pad would otherwise take this pad and leave the depth input unlinked */
	if (!name || strcmp(name, "color_sink") != 0) {
		GST_DEBUG_OBJECT(self, "color_sink is requested by its name only");
		return NULL;
	}
	GST_OBJECT_LOCK(self);
	if (self->color_pad) {
		GST_OBJECT_UNLOCK(self);
		GST_WARNING_OBJECT(self, "depthao has one color_sink pad");
		return NULL;
	}
	GstPad *pad = gst_pad_new_from_template(templ, "color_sink");
	gst_pad_set_chain_function(pad, color_chain);
	gst_pad_set_event_function(pad, color_event);
	gst_pad_set_query_function(pad, color_query);
	self->color_pad = pad;
	GST_OBJECT_UNLOCK(self);
	gst_element_add_pad(element, pad);
	/* the output formats change: the RGB ones only */
	gst_base_transform_reconfigure_src(GST_BASE_TRANSFORM(self));
	return pad;
}

static void gst_depthao_release_pad(GstElement *element, GstPad *pad)
{
	GstDepthao *self = GST_DEPTHAO(element);
	GST_OBJECT_LOCK(self);
	gboolean color = self->color_pad == pad;
	if (color)
		self->color_pad = NULL;
	if (self->depth_pad == pad)
		self->depth_pad = NULL;
	GST_OBJECT_UNLOCK(self);
	gst_element_remove_pad(element, pad);
	if (color)
		gst_base_transform_reconfigure_src(GST_BASE_TRANSFORM(self));
}

static GstStateChangeReturn gst_depthao_change_state(GstElement *element, GstStateChange t)
{
	GstDepthao *self = GST_DEPTHAO(element);
	if (t == GST_STATE_CHANGE_READY_TO_PAUSED) {
		GST_OBJECT_LOCK(self);
		gboolean unlinked = self->color_pad && !gst_pad_is_linked(self->color_pad);
		GST_OBJECT_UNLOCK(self);
		if (unlinked) {
			GST_ELEMENT_ERROR(self, CORE, PAD,
					  ("depthao: the color_sink pad was requested but nothing is "
					   "linked to it, so the AO over colour would never come: link "
					   "the colour stream to it (depth-only input: do not request "
					   "color_sink)"),
					  (NULL));
			return GST_STATE_CHANGE_FAILURE;
		}
		g_mutex_lock(&self->color_lock);
		color_clear(self);
		self->color_eos = self->color_flushing = self->depth_flushing = FALSE;
		gst_segment_init(&self->color_segment, GST_FORMAT_TIME);
		g_mutex_unlock(&self->color_lock);
		self->depth_started = FALSE;
		self->depth_caps_pending = self->depth_seg_pending = TRUE;
	} else if (t == GST_STATE_CHANGE_PAUSED_TO_READY) {
		/* a depth thread waiting for colour, a colour thread for room: both go */
		g_mutex_lock(&self->color_lock);
		self->color_flushing = self->depth_flushing = TRUE;
		g_cond_broadcast(&self->color_cond);
		g_mutex_unlock(&self->color_lock);
	}
	GstStateChangeReturn ret =
		GST_ELEMENT_CLASS(gst_depthao_parent_class)->change_state(element, t);
	if (t == GST_STATE_CHANGE_PAUSED_TO_READY) {
		g_mutex_lock(&self->color_lock);
		color_clear(self);
		g_mutex_unlock(&self->color_lock);
	}
	return ret;
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
	GST_OBJECT_LOCK(self);
	const gboolean with_color = self->color_pad != NULL;
	GST_OBJECT_UNLOCK(self);
	if (with_color) { /* colour linked: AO over colour */
		GstVideoFormat of = GST_VIDEO_FRAME_FORMAT(out);
		if (of != GST_VIDEO_FORMAT_RGB && of != GST_VIDEO_FORMAT_RGBA &&
		    of != GST_VIDEO_FORMAT_BGRx) {
			/* negotiated before color_sink was requested, downstream kept its caps */
			GST_ELEMENT_ERROR(self, CORE, NEGOTIATION,
					  ("depthao: AO over colour needs RGB, RGBA or BGRx output, "
					   "the output is %s", gst_video_format_to_string(of)),
					  (NULL));
			return GST_FLOW_NOT_NEGOTIATED;
		}
		if (!self->ao16) /* color_sink requested after the caps were set */
			self->ao16 = g_new(guint16, (gsize)depth.width * depth.height);
		GstFlowReturn ret = render_overlay(self, GST_BASE_TRANSFORM(filter), &depth, out, &err);
		if (ret == GST_FLOW_ERROR && err.message[0])
			GST_ELEMENT_ERROR(self, STREAM, FAILED, ("depthao: %s", err.message),
					  ("frame %" G_GUINT64_FORMAT, self->frame_index));
		if (ret == GST_FLOW_OK) {
			post_motion(self, GST_BASE_TRANSFORM(filter), in->buffer, self->frame_index);
			self->frame_index++;
			ret = push_depth(self, GST_BASE_TRANSFORM(filter), in->buffer, unit);
		}
		return ret;
	}
	if (render(self, &depth, out, &err) < 0) {
		GST_ELEMENT_ERROR(self, STREAM, FAILED, ("depthao: %s", err.message),
				  ("frame %" G_GUINT64_FORMAT, self->frame_index));
		return GST_FLOW_ERROR;
	}
	post_motion(self, GST_BASE_TRANSFORM(filter), in->buffer, self->frame_index);
	self->frame_index++;
	return push_depth(self, GST_BASE_TRANSFORM(filter), in->buffer, unit);
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
	GstDepthao *self = GST_DEPTHAO(bt);
	if (GST_EVENT_TYPE(event) == GST_EVENT_FLUSH_STOP) {
		GST_OBJECT_LOCK(self);
		self->reset_pending = TRUE;
		GST_OBJECT_UNLOCK(self);
	}
	/* a depth thread waiting for colour lets go on a flush */
	if (GST_EVENT_TYPE(event) == GST_EVENT_FLUSH_START ||
	    GST_EVENT_TYPE(event) == GST_EVENT_FLUSH_STOP) {
		g_mutex_lock(&self->color_lock);
		self->depth_flushing = GST_EVENT_TYPE(event) == GST_EVENT_FLUSH_START;
		g_cond_broadcast(&self->color_cond);
		g_mutex_unlock(&self->color_lock);
	}
	depth_sink_event(self, event);
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
	g_clear_pointer(&self->swapped, g_free);
	g_clear_pointer(&self->ao16, g_free);
	if (self->depth_pool) {
		gst_buffer_pool_set_active(self->depth_pool, FALSE);
		gst_clear_object(&self->depth_pool);
	}
	self->depth_caps_pending = TRUE;
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
	g_mutex_clear(&self->color_lock);
	g_cond_clear(&self->color_cond);
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
	self->post_messages = TRUE;
	g_mutex_init(&self->color_lock);
	g_cond_init(&self->color_cond);
	gst_segment_init(&self->color_segment, GST_FORMAT_TIME);
}

static void install_double_flags(GObjectClass *oc, guint id, const char *name, const char *blurb,
				 double min, double max, double def, GParamFlags extra)
{
	g_object_class_install_property(
		oc, id,
		g_param_spec_double(name, name, blurb, min, max, def,
				    G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS |
					    GST_PARAM_CONTROLLABLE | GST_PARAM_MUTABLE_PLAYING |
					    extra));
}

static void install_double(GObjectClass *oc, guint id, const char *name, const char *blurb,
			   double min, double max, double def)
{
	install_double_flags(oc, id, name, blurb, min, max, def, 0);
}

/* Every AO parameter of the library, from its table, as a property (after the
 * element's own, whose names win). */
static void install_param_properties(GObjectClass *oc)
{
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
	install_double(oc, PROP_HFOV_DEG, "hfov-deg",
		       "horizontal field of view in degrees, as depthao's --fov, used without "
		       "fx/fy (0 = from vfov-deg, or 58.5)",
		       0, 179, 0);
	install_double(oc, PROP_VFOV_DEG, "vfov-deg",
		       "vertical field of view in degrees, as depthao's --fov, used without "
		       "fx/fy (0 = from hfov-deg, or 45.6)",
		       0, 179, 0);
	install_double_flags(oc, PROP_HFOV, "hfov",
			     "DEPRECATED, use hfov-deg: horizontal field of view in radians "
			     "(the same setting as hfov-deg)",
			     0, 3.1, 0, G_PARAM_DEPRECATED);
	install_double_flags(oc, PROP_VFOV, "vfov",
			     "DEPRECATED, use vfov-deg: vertical field of view in radians "
			     "(the same setting as vfov-deg)",
			     0, 3.1, 0, G_PARAM_DEPRECATED);
	g_object_class_install_property(
		oc, PROP_QUALITY,
		g_param_spec_enum("quality", "quality",
				  "AO preset; parameters set explicitly stay as set",
				  gst_depthao_quality_get_type(), DAO_QUALITY_DEFAULT,
				  G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS |
					  GST_PARAM_MUTABLE_PLAYING));
	g_object_class_install_property(
		oc, PROP_POST_MESSAGES,
		g_param_spec_boolean("post-messages", "post-messages",
				     "post a \"depthao-motion\" element message for every frame "
				     "while the camera's motion is followed (depth-temporal > 0, "
				     "depth-temporal-motion not off): the motion estimate and the "
				     "camera's pose",
				     TRUE,
				     G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS |
					     GST_PARAM_MUTABLE_PLAYING));

	install_param_properties(oc);

	gst_element_class_set_static_metadata(
		ec, "Depth ambient occlusion", "Filter/Effect/Video",
		"Ambient occlusion (GRAY8, GRAY16_LE), the occlusion-shaded image, or with colour "
		"on color_sink the AO over colour (RGB, RGBA, BGRx) from 16-bit depth (GRAY16_LE, "
		"GRAY16_BE), with libdepthao; the filtered depth (GRAY16_LE) on depth_src",
		"depthao");
	gst_element_class_add_static_pad_template(ec, &sink_template);
	gst_element_class_add_static_pad_template(ec, &src_template);
	gst_element_class_add_static_pad_template(ec, &color_template);
	gst_element_class_add_static_pad_template(ec, &depth_template);
	ec->request_new_pad = gst_depthao_request_new_pad;
	ec->release_pad = gst_depthao_release_pad;
	ec->change_state = gst_depthao_change_state;

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
