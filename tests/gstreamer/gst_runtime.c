/* SPDX-License-Identifier: MIT */
/*
 * Property changes on a playing depthao element reach the next frame.
 *
 *   gst_runtime DEPTH.png OUTDIR
 *
 * Pushes the depth image four times through
 *   appsrc ! depthao fx=525 fy=525 cx=319.5 cy=239.5 ! GRAY16_LE ! appsink
 * one frame at a time, changing properties in between, and writes each AO
 * frame as OUTDIR/fN.raw (GRAY16_LE) for the script to compare with
 * `depthao process --frame-index N ...`:
 *   f0: the defaults
 *   f1: radius = 0.25
 *   f2: quality = high (radius stays 0.25: it was set explicitly)
 *   f3: depth-min = 30 > depth-max: rejected with a warning on the bus, the
 *       f2 settings stay
 * Exit 0 when the pipeline ran and the properties read back as set.
 */
#include <stdio.h>
#include <string.h>

#include <gst/app/gstappsink.h>
#include <gst/app/gstappsrc.h>
#include <gst/gst.h>
#include <gst/video/video.h>

#include <depthao/frame.h>
#include <depthao/params.h>
#include <depthao/png.h>

static int failures;

#define CHECK(cond, ...)                                                                     \
	do {                                                                                 \
		if (!(cond)) {                                                               \
			printf("FAIL: " __VA_ARGS__);                                        \
			printf("\n");                                                        \
			failures++;                                                          \
		}                                                                            \
	} while (0)

static GstBuffer *depth_buffer(const struct dao_frame *d, const GstVideoInfo *info)
{
	GstBuffer *buf = gst_buffer_new_allocate(NULL, GST_VIDEO_INFO_SIZE(info), NULL);
	GstMapInfo map;
	gst_buffer_map(buf, &map, GST_MAP_WRITE);
	for (uint32_t y = 0; y < d->height; y++) {
		guint16 *row = (guint16 *)(map.data + y * (gsize)GST_VIDEO_INFO_PLANE_STRIDE(info, 0));
		const guint16 *src = (const guint16 *)((const guint8 *)d->data + y * (gsize)d->stride);
		for (uint32_t x = 0; x < d->width; x++)
			row[x] = GUINT16_TO_LE(src[x]);
	}
	gst_buffer_unmap(buf, &map);
	return buf;
}

/* Pushes frame n and writes what comes out to OUTDIR/fN.raw (tightly packed). */
static int run_frame(GstElement *src, GstElement *sink, const struct dao_frame *d,
		     const GstVideoInfo *info, int n, const char *outdir)
{
	GstBuffer *buf = depth_buffer(d, info);
	GST_BUFFER_PTS(buf) = gst_util_uint64_scale_int(GST_SECOND, n, 30);
	GST_BUFFER_DURATION(buf) = GST_SECOND / 30;
	if (gst_app_src_push_buffer(GST_APP_SRC(src), buf) != GST_FLOW_OK) {
		printf("FAIL: frame %d: push refused\n", n);
		return -1;
	}
	GstSample *s = gst_app_sink_try_pull_sample(GST_APP_SINK(sink), 30 * GST_SECOND);
	if (!s) {
		printf("FAIL: frame %d: no output\n", n);
		return -1;
	}
	GstVideoInfo oi;
	gst_video_info_from_caps(&oi, gst_sample_get_caps(s));
	CHECK(GST_VIDEO_INFO_FORMAT(&oi) == GST_VIDEO_FORMAT_GRAY16_LE, "frame %d: output %s", n,
	      gst_video_format_to_string(GST_VIDEO_INFO_FORMAT(&oi)));
	GstMapInfo map;
	GstBuffer *ob = gst_sample_get_buffer(s);
	gst_buffer_map(ob, &map, GST_MAP_READ);
	char path[4096];
	snprintf(path, sizeof path, "%s/f%d.raw", outdir, n);
	FILE *f = fopen(path, "wb");
	int r = f ? 0 : -1;
	for (uint32_t y = 0; f && y < d->height; y++)
		if (fwrite(map.data + y * (gsize)GST_VIDEO_INFO_PLANE_STRIDE(&oi, 0), 2, d->width, f) !=
		    d->width)
			r = -1;
	if (f && fclose(f) != 0)
		r = -1;
	if (r < 0)
		printf("FAIL: cannot write %s\n", path);
	gst_buffer_unmap(ob, &map);
	gst_sample_unref(s);
	return r;
}

static int count_warnings(GstBus *bus, GstElement *from)
{
	int n = 0;
	GstMessage *m;
	while ((m = gst_bus_pop_filtered(bus, GST_MESSAGE_WARNING | GST_MESSAGE_ERROR))) {
		GError *e = NULL;
		gchar *dbg = NULL;
		if (GST_MESSAGE_TYPE(m) == GST_MESSAGE_ERROR) {
			gst_message_parse_error(m, &e, &dbg);
			printf("FAIL: error from %s: %s\n", GST_OBJECT_NAME(GST_MESSAGE_SRC(m)),
			       e->message);
			failures++;
		} else {
			gst_message_parse_warning(m, &e, &dbg);
			printf("warning from %s: %s\n", GST_OBJECT_NAME(GST_MESSAGE_SRC(m)), e->message);
			n += GST_MESSAGE_SRC(m) == GST_OBJECT(from);
		}
		g_clear_error(&e);
		g_free(dbg);
		gst_message_unref(m);
	}
	return n;
}

int main(int argc, char **argv)
{
	if (argc != 3) {
		fprintf(stderr, "usage: %s DEPTH.png OUTDIR\n", argv[0]);
		return 2;
	}
	gst_init(NULL, NULL);
	struct dao_frame d;
	struct dao_error err;
	if (dao_png_read_depth(argv[1], 0.001f, &d, &err) < 0) {
		fprintf(stderr, "%s\n", err.message);
		return 2;
	}
	GError *gerr = NULL;
	GstElement *pipe = gst_parse_launch(
		"appsrc name=src format=time ! depthao name=ao fx=525 fy=525 cx=319.5 cy=239.5 "
		"! video/x-raw,format=GRAY16_LE ! appsink name=sink sync=false",
		&gerr);
	if (!pipe) {
		fprintf(stderr, "pipeline: %s\n", gerr->message);
		return 2;
	}
	GstElement *src = gst_bin_get_by_name(GST_BIN(pipe), "src");
	GstElement *ao = gst_bin_get_by_name(GST_BIN(pipe), "ao");
	GstElement *sink = gst_bin_get_by_name(GST_BIN(pipe), "sink");
	GstVideoInfo info;
	gst_video_info_set_format(&info, GST_VIDEO_FORMAT_GRAY16_LE, d.width, d.height);
	GST_VIDEO_INFO_FPS_N(&info) = 30;
	GST_VIDEO_INFO_FPS_D(&info) = 1;
	GstCaps *caps = gst_video_info_to_caps(&info);
	g_object_set(src, "caps", caps, NULL);
	gst_caps_unref(caps);
	GstBus *bus = gst_element_get_bus(pipe);
	gst_element_set_state(pipe, GST_STATE_PLAYING);

	int ok = run_frame(src, sink, &d, &info, 0, argv[2]) == 0;
	g_object_set(ao, "radius", 0.25, NULL);
	ok = ok && run_frame(src, sink, &d, &info, 1, argv[2]) == 0;
	gst_util_set_object_arg(G_OBJECT(ao), "quality", "high");
	ok = ok && run_frame(src, sink, &d, &info, 2, argv[2]) == 0;
	CHECK(count_warnings(bus, ao) == 0, "warnings before the bad setting");
	g_object_set(ao, "depth-min", 30.0, NULL);
	ok = ok && run_frame(src, sink, &d, &info, 3, argv[2]) == 0;
	CHECK(count_warnings(bus, ao) == 1, "depth-min > depth-max gave no warning");
	CHECK(ok, "the frames did not all come through");

	double radius = 0, dmin = 0;
	int slices = 0;
	gchar *quality = NULL;
	g_object_get(ao, "radius", &radius, "depth-min", &dmin, "slices", &slices, NULL);
	GValue v = G_VALUE_INIT;
	g_object_get_property(G_OBJECT(ao), "quality", &v);
	GEnumClass *ec = g_type_class_ref(G_VALUE_TYPE(&v));
	GEnumValue *ev = g_enum_get_value(ec, g_value_get_enum(&v));
	quality = g_strdup(ev ? ev->value_nick : "?");
	g_type_class_unref(ec);
	g_value_unset(&v);
	CHECK(radius == 0.25, "radius reads back as %.17g", radius);
	CHECK(dmin == 30.0, "depth-min reads back as %.17g", dmin);
	struct dao_params high;
	dao_params_init(&high, DAO_QUALITY_HIGH);
	CHECK(slices == high.slices, "slices %d after quality=high (%d expected)", slices,
	      high.slices);
	CHECK(!strcmp(quality, "high"), "quality reads back as %s", quality);
	g_free(quality);

	gst_app_src_end_of_stream(GST_APP_SRC(src));
	gst_element_set_state(pipe, GST_STATE_NULL);
	gst_object_unref(bus);
	gst_object_unref(src);
	gst_object_unref(ao);
	gst_object_unref(sink);
	gst_object_unref(pipe);
	dao_frame_free(&d);
	if (failures) {
		printf("%d failure(s)\n", failures);
		return 1;
	}
	printf("4 frames with property changes in between\n");
	return 0;
}
