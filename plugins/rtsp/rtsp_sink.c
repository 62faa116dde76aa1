/* SPDX-License-Identifier: MIT */
/*
 * Sink plugin "rtsp": serves the stream (shaded RGB, or the 8-bit AO) over
 * RTSP with gst-rtsp-server, as Motion-JPEG over RTP (jpegenc ! rtpjpegpay,
 * both in gstreamer1.0-plugins-good; no H.264 encoder needed).
 *
 * URIs: "PORT/MOUNT" (rtsp:8554/depthao), "HOST:PORT/MOUNT" to bind one
 * address (IPv6 in brackets: [::1]:8554/depthao), or "//HOST:PORT/MOUNT" (so rtsp://0.0.0.0:8554/depthao works as
 * written), with options "?quality=N" (JPEG quality, 1..100, default 85) and
 * "transport=tcp|udp" joined by '&'.  The server listens from open on;
 * clients connect to rtsp://HOST:PORT/MOUNT.
 *
 * RTP goes over one lower transport, TCP by default (interleaved in the RTSP
 * connection: no loss of the many packets of a JPEG frame, through
 * firewalls); clients that ask for UDP first fall back to it (RTSP 461).
 * Mixing UDP and TCP clients on one shared media is what gst-rtsp-server
 * 1.22 handles badly (see rtsp_negotiate), so it is one or the other.
 *
 * The JPEGs are full-range BT.601 (JFIF, colorimetry 1:4:0:0), as decoders
 * read them.  One shared media serves every client (one encoder, whatever
 * the number of clients).  The media pipeline starts with the first client and stops when the last one leaves.
 * write() never waits: without a client the frame is dropped, and with
 * clients it goes into a leaky appsrc (two frames deep, the oldest dropped),
 * so clients coming, going or stalling never hold up the daemon's pipeline.
 * The server runs in its own thread with its own GMainContext.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gio/gio.h>
#include <gst/app/gstappsrc.h>
#include <gst/gst.h>
#include <gst/rtsp-server/rtsp-server.h>
#include <gst/video/video.h>

#include <depthao/plugin.h>


#define DEFAULT_QUALITY 85
#define APPSRC_NAME "depthao-src"

/*
 * What the server's callbacks share with the writer.  Reference counted
 * (g_atomic_rc_box): media signals may fire in the server's threads until
 * the media is gone, which can be after close().
 */
struct shared {
	GMutex lock;
	GstCaps *caps;          /* of the frames written */
	GstElement *appsrc;     /* of the prepared shared media (a ref), NULL without clients */
	GstRTSPMedia *media;    /* the media that appsrc belongs to (not a ref) */
	GstClockTime last_pts;  /* of the last frame pushed into appsrc */
};

struct rtsp_sink {
	char host[64], mount[128];
	int port, quality;
	GstRTSPLowerTrans transport; /* the one transport offered to clients */
	struct shared *sh;
	GstVideoInfo info;
	GstBufferPool *pool;    /* frames for appsrc, reused: no 1 MB allocation per frame */
	GMainContext *mctx;
	GMainLoop *loop;
	GThread *thread;
	GstRTSPServer *server;
	GSource *server_source, *cleanup_source;
};

static void shared_clear(gpointer data)
{
	struct shared *sh = data;
	gst_clear_caps(&sh->caps);
	gst_clear_object(&sh->appsrc);
	g_mutex_clear(&sh->lock);
}

static void shared_release(gpointer data, GClosure *closure)
{
	(void)closure;
	g_atomic_rc_box_release_full(data, shared_clear);
}

static int rtsp_probe(const char *uri)
{
	return !strncmp(uri, "rtsp://", 7) ? 100 : 0;
}

static const char *const rtsp_options[] = {"quality", "transport", NULL};

/* "quality=N&transport=tcp|udp" (the library's parser: errors name the key and the value) */
static int parse_options(struct rtsp_sink *s, const char *text, struct dao_error *err)
{
	static const char *const transports[] = {"tcp", "udp", NULL};
	struct dao_options *o;
	int r = dao_options_parse(&o, "rtsp", text, rtsp_options, err);
	if (r < 0)
		return r;
	int64_t quality = s->quality;
	int udp = 0;
	if ((r = dao_options_get_int(o, "quality", 1, 100, &quality, err)) >= 0 &&
	    (r = dao_options_get_enum(o, "transport", transports, &udp, err)) >= 0) {
		s->quality = (int)quality;
		s->transport = udp ? GST_RTSP_LOWER_TRANS_UDP : GST_RTSP_LOWER_TRANS_TCP;
	}
	dao_options_free(o);
	return r < 0 ? r : 0;
}

/* "PORT/MOUNT", "HOST:PORT/MOUNT", "//HOST:PORT/MOUNT", each with "?OPTION&OPTION" */
static int parse_uri(struct rtsp_sink *s, const char *uri, struct dao_error *err)
{
	char buf[512];
	if (g_strlcpy(buf, uri, sizeof buf) >= sizeof buf)
		return dao_error_set(err, -EINVAL, "rtsp: the URI is too long");
	char *p = buf;
	s->quality = DEFAULT_QUALITY;
	s->transport = GST_RTSP_LOWER_TRANS_TCP;
	size_t opts_at = dao_uri_path_len(buf, rtsp_options);
	int r;
	if (buf[opts_at] && (r = parse_options(s, buf + opts_at + 1, err)) < 0)
		return r;
	buf[opts_at] = '\0';
	if (!strncmp(p, "//", 2))
		p += 2;
	char *slash = strchr(p, '/');
	if (g_strlcpy(s->mount, slash && slash[1] ? slash : "/depthao", sizeof s->mount) >=
	    sizeof s->mount)
		return dao_error_set(err, -EINVAL, "rtsp: '%s': the mount path is too long", uri);
	if (slash)
		*slash = '\0';
	char *colon = strrchr(p, ':');
	g_strlcpy(s->host, "0.0.0.0", sizeof s->host);
	if (colon) {
		*colon = '\0';
		size_t n = strlen(p);
		if (n >= 2 && p[0] == '[' && p[n - 1] == ']') { /* [IPv6] */
			p[n - 1] = '\0';
			p++;
		}
		if (*p && g_strlcpy(s->host, p, sizeof s->host) >= sizeof s->host)
			return dao_error_set(err, -EINVAL, "rtsp: '%s': the address is too long", uri);
		p = colon + 1;
	}
	char *end;
	long port = strtol(p, &end, 10);
	if (!*p || *end || port < 1 || port > 65535)
		return dao_error_set(err, -EINVAL,
				    "rtsp: '%s' is not PORT/MOUNT or HOST:PORT/MOUNT with a port in "
				    "1..65535 (e.g. rtsp:8554/depthao)",
				    uri);
	s->port = (int)port;
	return 0;
}

static gboolean cleanup_sessions(gpointer data)
{
	struct rtsp_sink *s = data;
	GstRTSPSessionPool *pool = gst_rtsp_server_get_session_pool(s->server);
	gst_rtsp_session_pool_cleanup(pool); /* UDP clients that vanished without TEARDOWN */
	g_object_unref(pool);
	return G_SOURCE_CONTINUE;
}

static gpointer server_thread(gpointer data)
{
	struct rtsp_sink *s = data;
	g_main_context_push_thread_default(s->mctx);
	g_main_loop_run(s->loop);
	g_main_context_pop_thread_default(s->mctx);
	return NULL;
}

static int rtsp_open(const char *uri, void **state, struct dao_error *err)
{
	GError *gerr = NULL;
	struct rtsp_sink *s = calloc(1, sizeof(*s));
	if (!s)
		return dao_error_set(err, -ENOMEM, "out of memory");
	int r = parse_uri(s, uri, err);
	if (r < 0) {
		free(s);
		return r;
	}
	if (!gst_init_check(NULL, NULL, &gerr)) {
		r = dao_error_set(err, -ENOTSUP, "rtsp: GStreamer does not start: %s",
				 gerr ? gerr->message : "gst_init failed");
		g_clear_error(&gerr);
		free(s);
		return r;
	}
	static const char *const needed[] = {"appsrc", "videoconvert", "jpegenc", "rtpjpegpay"};
	for (size_t i = 0; i < G_N_ELEMENTS(needed); i++) {
		GstElementFactory *f = gst_element_factory_find(needed[i]);
		if (!f) {
			free(s);
			return dao_error_set(err, -ENOTSUP,
					    "rtsp: the GStreamer element '%s' is missing (install "
					    "gstreamer1.0-plugins-base and -good)",
					    needed[i]);
		}
		gst_object_unref(f);
	}
	s->sh = g_atomic_rc_box_new0(struct shared);
	g_mutex_init(&s->sh->lock);
	s->mctx = g_main_context_new();
	s->loop = g_main_loop_new(s->mctx, FALSE);
	s->server = gst_rtsp_server_new();
	char service[16];
	snprintf(service, sizeof service, "%d", s->port);
	gst_rtsp_server_set_address(s->server, s->host);
	gst_rtsp_server_set_service(s->server, service);
	/* bind now, so a port in use is an error of open (the daemon retries) */
	s->server_source = gst_rtsp_server_create_source(s->server, NULL, &gerr);
	if (!s->server_source) {
		r = gerr && g_error_matches(gerr, G_IO_ERROR, G_IO_ERROR_ADDRESS_IN_USE) ? -EADDRINUSE
											  : -EIO;
		dao_error_set(err, r, "rtsp: cannot listen on %s:%d: %s", s->host, s->port,
			     gerr ? gerr->message : "unknown error");
		g_clear_error(&gerr);
		g_object_unref(s->server);
		g_main_loop_unref(s->loop);
		g_main_context_unref(s->mctx);
		g_atomic_rc_box_release_full(s->sh, shared_clear);
		free(s);
		return r;
	}
	g_source_attach(s->server_source, s->mctx);
	s->cleanup_source = g_timeout_source_new_seconds(2);
	g_source_set_callback(s->cleanup_source, cleanup_sessions, s, NULL);
	g_source_attach(s->cleanup_source, s->mctx);
	s->thread = g_thread_new("rtsp-sink", server_thread, s);
	*state = s;
	return 0;
}

static void on_media_unprepared(GstRTSPMedia *media, gpointer data)
{
	struct shared *sh = data;
	g_mutex_lock(&sh->lock);
	if (sh->media == media) { /* the last client left: frames are dropped again */
		gst_clear_object(&sh->appsrc);
		sh->media = NULL;
	}
	g_mutex_unlock(&sh->lock);
}

/* A client asked for the stream and the shared media is being built. */
static void on_media_configure(GstRTSPMediaFactory *factory, GstRTSPMedia *media, gpointer data)
{
	struct shared *sh = data;
	(void)factory;
	GstElement *bin = gst_rtsp_media_get_element(media);
	GstElement *src = gst_bin_get_by_name_recurse_up(GST_BIN(bin), APPSRC_NAME);
	gst_object_unref(bin);
	if (!src)
		return;
	g_mutex_lock(&sh->lock);
	g_object_set(src, "caps", sh->caps, NULL);
	gst_object_replace((GstObject **)&sh->appsrc, GST_OBJECT(src));
	sh->media = media;
	sh->last_pts = 0;
	g_mutex_unlock(&sh->lock);
	gst_object_unref(src);
	g_signal_connect_data(media, "unprepared", G_CALLBACK(on_media_unprepared),
			      g_atomic_rc_box_acquire(sh), shared_release, 0);
}

static int rtsp_negotiate(void *state, struct dao_sink_format *fmt, struct dao_error *err)
{
	struct rtsp_sink *s = state;
	if (fmt->format == DAO_PIXFMT_GRAY16) {
		fmt->format = DAO_PIXFMT_GRAY8; /* 8-bit pictures only: subscribe to ao8 */
		return 0;
	}
	if (fmt->format != DAO_PIXFMT_RGB24 && fmt->format != DAO_PIXFMT_GRAY8)
		return dao_error_set(err, -ENOTSUP,
				    "rtsp: serves 8-bit JPEG pictures (the shaded, overlay or ao8 "
				    "stream), not %s frames%s",
				    fmt->format == DAO_PIXFMT_DEPTH16 ? "16-bit depth" : "these",
				    fmt->format == DAO_PIXFMT_DEPTH16
					    ? " (JPEG has no 16-bit grey: record the depth with an "
					      "images: or oni: sink, or send it to v4l2 as Y16)" : "");
	if (fmt->width > 2040 || fmt->height > 2040) /* RFC 2435: at most 255 x 8 pixels */
		return dao_error_set(err, -ENOTSUP,
				    "rtsp: %ux%u is too large for RTP/JPEG (2040x2040 at most)",
				    fmt->width, fmt->height);
	gint num = 0, den = 1;
	if (fmt->fps > 0)
		gst_util_double_to_fraction(fmt->fps, &num, &den);
	GstCaps *caps = gst_caps_new_simple(
		"video/x-raw", "format", G_TYPE_STRING,
		fmt->format == DAO_PIXFMT_RGB24 ? "RGB" : "GRAY8", "width", G_TYPE_INT,
		(int)fmt->width, "height", G_TYPE_INT, (int)fmt->height, "framerate",
		GST_TYPE_FRACTION, num, den, NULL);
	if (!gst_video_info_from_caps(&s->info, caps)) {
		gst_caps_unref(caps);
		return dao_error_set(err, -EINVAL, "rtsp: bad frame size %ux%u", fmt->width,
				    fmt->height);
	}
	if (s->pool) {
		gst_buffer_pool_set_active(s->pool, FALSE);
		gst_clear_object(&s->pool);
	}
	/* no upper bound: acquiring never waits; frames come back when the encoder is done */
	s->pool = gst_buffer_pool_new();
	GstStructure *conf = gst_buffer_pool_get_config(s->pool);
	gst_buffer_pool_config_set_params(conf, caps, (guint)GST_VIDEO_INFO_SIZE(&s->info), 2, 0);
	if (!gst_buffer_pool_set_config(s->pool, conf) || !gst_buffer_pool_set_active(s->pool, TRUE)) {
		gst_caps_unref(caps);
		gst_clear_object(&s->pool);
		return dao_error_set(err, -ENOMEM, "rtsp: cannot set up frame buffers of %ux%u",
				    fmt->width, fmt->height);
	}
	g_mutex_lock(&s->sh->lock);
	gst_caps_replace(&s->sh->caps, caps);
	g_mutex_unlock(&s->sh->lock);
	gst_caps_unref(caps);

	gchar *launch = g_strdup_printf(
		"( appsrc name=" APPSRC_NAME " is-live=true format=time "
		"block=false max-buffers=2 leaky-type=downstream "
		"! videoconvert ! video/x-raw,format=I420,colorimetry=1:4:0:0,chroma-site=jpeg "
		"! jpegenc quality=%d "
		"! rtpjpegpay name=pay0 pt=26 )",
		s->quality);
	GstRTSPMediaFactory *factory = gst_rtsp_media_factory_new();
	gst_rtsp_media_factory_set_launch(factory, launch);
	g_free(launch);
	gst_rtsp_media_factory_set_shared(factory, TRUE);
	/* one lower transport only: gst-rtsp-server 1.22 can deadlock a shared media
	   when a UDP and a TCP client start playing at the same moment (it relinks
	   the sender part through an idle probe while the first sink prerolls) */
	gst_rtsp_media_factory_set_protocols(factory, s->transport);
	gst_rtsp_media_factory_set_suspend_mode(factory, GST_RTSP_SUSPEND_MODE_NONE);
	g_signal_connect_data(factory, "media-configure", G_CALLBACK(on_media_configure),
			      g_atomic_rc_box_acquire(s->sh), shared_release, 0);
	GstRTSPMountPoints *mounts = gst_rtsp_server_get_mount_points(s->server);
	gst_rtsp_mount_points_add_factory(mounts, s->mount, factory); /* takes the factory */
	g_object_unref(mounts);
	return 0;
}

/*
 * The frame's timestamp: the media pipeline's running time now, once it plays.
 * (appsrc's do-timestamp reads the clock while the pipeline may not have its
 * base time yet; a frame then carried the clock's absolute time, hours ahead,
 * and the RTP sink waited that long on it: a client that got no frame at all,
 * about once in 50 connections.)  Before PLAYING, and should the clock step
 * back, the last timestamp again: frames never go back in time.
 */
static GstClockTime frame_time(struct shared *sh, GstElement *src)
{
	GstClockTime pts = GST_CLOCK_TIME_NONE;
	GstState state = GST_STATE_NULL;
	if (gst_element_get_state(src, &state, NULL, 0) != GST_STATE_CHANGE_FAILURE &&
	    state == GST_STATE_PLAYING) {
		GstClock *clock = gst_element_get_clock(src);
		if (clock) {
			const GstClockTime now = gst_clock_get_time(clock);
			const GstClockTime base = gst_element_get_base_time(src);
			if (GST_CLOCK_TIME_IS_VALID(now) && GST_CLOCK_TIME_IS_VALID(base) && now >= base)
				pts = now - base;
			gst_object_unref(clock);
		}
	}
	g_mutex_lock(&sh->lock);
	if (!GST_CLOCK_TIME_IS_VALID(pts) || pts < sh->last_pts)
		pts = sh->last_pts;
	sh->last_pts = pts;
	g_mutex_unlock(&sh->lock);
	return pts;
}

static int rtsp_write(void *state, const struct dao_frame *f, struct dao_error *err)
{
	struct rtsp_sink *s = state;
	(void)err;
	g_mutex_lock(&s->sh->lock);
	GstElement *src = s->sh->appsrc ? gst_object_ref(s->sh->appsrc) : NULL;
	g_mutex_unlock(&s->sh->lock);
	if (!src)
		return 0; /* nobody is watching */
	const gsize row = (gsize)f->width * (f->format == DAO_PIXFMT_RGB24 ? 3 : 1);
	const gsize stride = (gsize)GST_VIDEO_INFO_PLANE_STRIDE(&s->info, 0);
	GstBuffer *buf = NULL;
	if (gst_buffer_pool_acquire_buffer(s->pool, &buf, NULL) != GST_FLOW_OK)
		buf = NULL;
	GstMapInfo map;
	if (buf && gst_buffer_map(buf, &map, GST_MAP_WRITE)) {
		for (uint32_t y = 0; y < f->height; y++)
			memcpy(map.data + y * stride,
			       (const guint8 *)f->data + (gsize)y * (gsize)f->stride, row);
		gst_buffer_unmap(buf, &map);
		GST_BUFFER_OFFSET(buf) = f->sequence;
		GST_BUFFER_PTS(buf) = frame_time(s->sh, src);
		/* never blocks: a full queue drops its oldest frame; a media that is
		   shutting down answers FLUSHING, which is no error of this sink */
		gst_app_src_push_buffer(GST_APP_SRC(src), buf);
	} else if (buf) {
		gst_buffer_unref(buf);
	}
	gst_object_unref(src);
	return 0;
}

static GstRTSPFilterResult remove_client(GstRTSPServer *server, GstRTSPClient *client,
					 gpointer data)
{
	(void)server;
	(void)client;
	(void)data;
	return GST_RTSP_FILTER_REMOVE;
}

static GstRTSPFilterResult remove_session(GstRTSPSessionPool *pool, GstRTSPSession *session,
					  gpointer data)
{
	(void)pool;
	(void)session;
	(void)data;
	return GST_RTSP_FILTER_REMOVE;
}

/* In the server's thread: disconnect every client, stop listening, end the loop. */
static gboolean shutdown_server(gpointer data)
{
	struct rtsp_sink *s = data;
	GstRTSPMountPoints *mounts = gst_rtsp_server_get_mount_points(s->server);
	gst_rtsp_mount_points_remove_factory(mounts, s->mount);
	g_object_unref(mounts);
	g_source_destroy(s->server_source);
	g_source_destroy(s->cleanup_source);
	gst_rtsp_server_client_filter(s->server, remove_client, NULL);
	GstRTSPSessionPool *pool = gst_rtsp_server_get_session_pool(s->server);
	gst_rtsp_session_pool_filter(pool, remove_session, NULL);
	g_object_unref(pool);
	g_main_loop_quit(s->loop);
	return G_SOURCE_REMOVE;
}

static int rtsp_close(void *state, struct dao_error *err)
{
	struct rtsp_sink *s = state;
	(void)err;
	g_mutex_lock(&s->sh->lock);
	gst_clear_object(&s->sh->appsrc);
	s->sh->media = NULL;
	g_mutex_unlock(&s->sh->lock);
	GSource *idle = g_idle_source_new();
	g_source_set_callback(idle, shutdown_server, s, NULL);
	g_source_attach(idle, s->mctx);
	g_source_unref(idle);
	g_thread_join(s->thread);
	g_source_unref(s->server_source);
	g_source_unref(s->cleanup_source);
	g_object_unref(s->server);
	g_main_loop_unref(s->loop);
	g_main_context_unref(s->mctx);
	g_atomic_rc_box_release_full(s->sh, shared_clear);
	if (s->pool) { /* frames still in a media are freed when it lets them go */
		gst_buffer_pool_set_active(s->pool, FALSE);
		gst_object_unref(s->pool);
	}
	free(s);
	return 0;
}

static const struct dao_sink_ops rtsp_sink_ops = {
	.version = DAO_SINK_OPS_VERSION,
	.probe = rtsp_probe,
	.open = rtsp_open,
	.negotiate = rtsp_negotiate,
	.write = rtsp_write,
	.close = rtsp_close,
};

static const struct dao_plugin rtsp_plugin = {
	DAO_PLUGIN_HEADER,
	.name = "rtsp",
	.description = "RTSP server (gst-rtsp-server): the stream as Motion-JPEG over RTP, "
		       "rtsp:PORT/MOUNT",
	.sink = &rtsp_sink_ops,
};

DAO_PLUGIN_DEFINE(rtsp_plugin)
