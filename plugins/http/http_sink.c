/* SPDX-License-Identifier: MIT */
/*
 * Sink plugin "http": a browser viewer of the running pipeline, served by
 * libmicrohttpd.  One page (/) shows the live picture of a chosen stream
 * (Motion-JPEG, /stream.mjpg), sliders for the AO parameters (/api/params)
 * and the statistics (/api/stats); /snapshot.png is the current frame.
 *
 * URIs: "PORT", "HOST:PORT" or "//HOST:PORT" (IPv6 in brackets), the host
 * 127.0.0.1 unless given (every interface only when asked: 0.0.0.0 or [::]),
 * with options joined by '&' after '?':
 *   control=true     anyone who reaches the port may change parameters
 *   token=SECRET     ... or requests with the header X-Depthao-Token: SECRET
 *   quality=1..100   JPEG quality (default 80)
 *   max_clients=N    concurrent connections (1..1024, default 32)
 *   queue=1..8       frames queued per stream client (default 2)
 *   per_ip=N         connections from one address (1..1024, default 16; 0 = no limit)
 *   request_timeout=S  seconds for a whole request: line, headers, body (1..60, default 5)
 * Without control or token the viewer is read-only.
 *
 * The sink takes every frame through write_stream: the configured stream
 * and those the connected clients watch (want_streams).  Each picture is
 * encoded once (libturbojpeg) and copied into every client's own queue
 * (mjpeg_client.c); the connections are served by libmicrohttpd's threads,
 * one per connection, so a slow client waits in its own thread only.
 */
#include <errno.h>
#include <netdb.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <turbojpeg.h>

#include "http_sink.h"

#define DEFAULT_QUALITY 80
#define DEFAULT_QUEUE 2
/* frames during which the overlay is asked for, to learn whether the source has colour */
#define COLOR_PROBE_FRAMES 30
#define SEND_BUFFER (128 * 1024) /* bytes (Linux doubles it) */

static const char *const view_names[VIEW_COUNT] = {"shaded", "ao", "overlay", "depth"};

const char *view_stream_name(enum view_stream v)
{
	return (unsigned)v < VIEW_COUNT ? view_names[v] : "?";
}

int view_stream_parse(const char *name, enum view_stream *v)
{
	for (int i = 0; i < VIEW_COUNT; i++)
		if (!strcmp(name, view_names[i])) {
			*v = (enum view_stream)i;
			return 0;
		}
	return -1;
}

static const enum dao_stream view_to_stream[VIEW_COUNT] = {
	[VIEW_SHADED] = DAO_STREAM_SHADED, [VIEW_AO] = DAO_STREAM_AO8,
	[VIEW_OVERLAY] = DAO_STREAM_OVERLAY, [VIEW_DEPTH] = DAO_STREAM_DEPTH,
};

uint64_t http_now_ns(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

static uint32_t micros(uint64_t from, uint64_t to)
{
	uint64_t us = to > from ? (to - from) / 1000u : 0;
	return us > UINT32_MAX ? UINT32_MAX : (uint32_t)us;
}

void http_record_latency(struct http_sink *s, uint64_t capture_ns, uint64_t written_ns,
			 uint64_t now_ns)
{
	s->lat_us[s->lat_pos] = micros(capture_ns, now_ns);
	s->send_us[s->lat_pos] = micros(written_ns, now_ns);
	s->lat_pos = (s->lat_pos + 1) % HTTP_LATENCY_RING;
	if (s->lat_n < HTTP_LATENCY_RING)
		s->lat_n++;
}

void http_update_wanted(struct http_sink *s)
{
	unsigned mask = 0;
	for (int v = 0; v < VIEW_COUNT; v++)
		if (s->wanted[v])
			mask |= 1u << view_to_stream[v];
	if (s->frames_seen < COLOR_PROBE_FRAMES)
		mask |= 1u << DAO_STREAM_OVERLAY;
	if (s->host && s->host->want_streams)
		s->host->want_streams(s->host->user, mask);
}

static int http_probe(const char *uri)
{
	(void)uri;
	return 0; /* only by name: http:PORT */
}

static int parse_uint(const char *v, long lo, long hi, long *out)
{
	char *end;
	long n = strtol(v, &end, 10);
	if (!*v || *end || n < lo || n > hi)
		return -1;
	*out = n;
	return 0;
}

static const char *const http_options[] = {"control", "token", "quality", "max_clients", "queue",
					   "per_ip", "request_timeout", NULL};

/* The options after the '?' (the library's parser: errors name the key and the value). */
static int parse_options(struct http_sink *s, const char *text, struct dao_error *err)
{
	struct dao_options *o;
	int r = dao_options_parse(&o, "http", text, http_options, err);
	if (r < 0)
		return r;
	int64_t quality = s->quality, clients = s->max_clients, queue = s->queue;
	int64_t per_ip = s->per_ip, deadline = s->request_deadline_ms / 1000;
	if ((r = dao_options_get_bool(o, "control", &s->control, err)) >= 0 &&
	    (r = dao_options_get_string(o, "token", s->token, sizeof s->token, err)) >= 0 &&
	    (r = dao_options_get_int(o, "quality", 1, 100, &quality, err)) >= 0 &&
	    (r = dao_options_get_int(o, "max_clients", 1, 1024, &clients, err)) >= 0 &&
	    (r = dao_options_get_int(o, "queue", 1, 8, &queue, err)) >= 0 &&
	    (r = dao_options_get_int(o, "per_ip", 0, 1024, &per_ip, err)) >= 0 &&
	    (r = dao_options_get_int(o, "request_timeout", 1, 60, &deadline, err)) >= 0) {
		s->per_ip = (unsigned)per_ip;
		s->request_deadline_ms = (unsigned)deadline * 1000u;
		s->quality = (int)quality;
		s->max_clients = (unsigned)clients;
		s->queue = (unsigned)queue;
	}
	dao_options_free(o);
	return r < 0 ? r : 0;
}

/* "PORT", "HOST:PORT", "//HOST:PORT", "[V6]:PORT", each with "?OPTION&OPTION" */
static int parse_uri(struct http_sink *s, const char *uri, struct dao_error *err)
{
	char buf[512];
	if (snprintf(buf, sizeof buf, "%s", uri) >= (int)sizeof buf)
		return dao_error_set(err, -EINVAL, "http: the URI is too long");
	s->quality = DEFAULT_QUALITY;
	s->max_clients = HTTP_DEFAULT_CLIENTS;
	s->queue = DEFAULT_QUEUE;
	s->per_ip = HTTP_DEFAULT_PER_IP;
	s->request_deadline_ms = HTTP_DEFAULT_DEADLINE_MS;
	snprintf(s->bind_host, sizeof s->bind_host, "127.0.0.1");
	char *p = buf;
	size_t opts_at = dao_uri_path_len(buf, http_options);
	int r;
	if (buf[opts_at] && (r = parse_options(s, buf + opts_at + 1, err)) < 0)
		return r;
	buf[opts_at] = '\0';
	if (!strncmp(p, "//", 2))
		p += 2;
	size_t len = strlen(p);
	if (len && p[len - 1] == '/')
		p[--len] = '\0';
	char *colon = strrchr(p, ':');
	if (colon && (p[0] != '[' || colon > strchr(p, ']'))) {
		*colon = '\0';
		size_t n = strlen(p);
		if (n >= 2 && p[0] == '[' && p[n - 1] == ']') {
			p[n - 1] = '\0';
			p++;
		}
		if (!*p || strlen(p) >= sizeof s->bind_host)
			return dao_error_set(err, -EINVAL, "http: '%s': the address is empty or too long",
					    uri);
		snprintf(s->bind_host, sizeof s->bind_host, "%s", p);
		p = colon + 1;
	}
	long port;
	if (parse_uint(p, 0, 65535, &port) < 0)
		return dao_error_set(err, -EINVAL,
				    "http: '%s' is not PORT or HOST:PORT with a port in 0..65535 (e.g. "
				    "http:8080 for 127.0.0.1, http:0.0.0.0:8080 for every interface)",
				    uri);
	s->port = (int)port;
	/* a quarter of the slots (one at least, from two on) never go to streams: the
	   page, its statistics and parameters stay reachable while streams take the rest */
	const unsigned api = s->max_clients >= 4 ? s->max_clients / 4 : s->max_clients >= 2 ? 1 : 0;
	s->max_streams = s->max_clients - api;
	return 0;
}

/* Binds and listens now, so that a port in use is an error of open (the daemon retries). */
static int listen_on(struct http_sink *s, struct dao_error *err)
{
	struct addrinfo hints = {.ai_family = AF_UNSPEC, .ai_socktype = SOCK_STREAM,
				 .ai_flags = AI_PASSIVE | AI_NUMERICSERV};
	struct addrinfo *ai = NULL;
	char port[16];
	snprintf(port, sizeof port, "%d", s->port);
	int r = getaddrinfo(s->bind_host, port, &hints, &ai);
	if (r != 0)
		return dao_error_set(err, -EINVAL, "http: '%s' is not an address of this machine: %s",
				    s->bind_host, gai_strerror(r));
	int fd = socket(ai->ai_family, SOCK_STREAM | SOCK_CLOEXEC, 0);
	int one = 1;
	/* the connections inherit a modest send buffer: a client that stops reading
	   holds a few frames in the kernel, not a hundred, and its own queue (where
	   frames are dropped, counted) fills soon */
	int sndbuf = SEND_BUFFER;
	if (fd >= 0)
		setsockopt(fd, SOL_SOCKET, SO_SNDBUF, &sndbuf, sizeof sndbuf);
	if (fd < 0 || setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one) < 0 ||
	    bind(fd, ai->ai_addr, ai->ai_addrlen) < 0 || listen(fd, 64) < 0) {
		r = -errno;
		if (fd >= 0)
			close(fd);
		freeaddrinfo(ai);
		return dao_error_set(err, r, "http: cannot listen on %s:%d: %s%s", s->bind_host, s->port,
				    strerror(-r),
				    r == -EADDRINUSE ? " (another program has the port: pick another)"
						     : "");
	}
	freeaddrinfo(ai);
	struct sockaddr_storage sa;
	socklen_t salen = sizeof sa;
	if (getsockname(fd, (struct sockaddr *)&sa, &salen) == 0 && s->port == 0) {
		char h[64], sv[16];
		if (getnameinfo((struct sockaddr *)&sa, salen, h, sizeof h, sv, sizeof sv,
				NI_NUMERICHOST | NI_NUMERICSERV) == 0)
			s->port = atoi(sv);
	}
	s->listen_fd = fd;
	return 0;
}

static void free_state(struct http_sink *s)
{
	for (int v = 0; v < VIEW_COUNT; v++) {
		free(s->pic[v].rgb);
		tjFree(s->pic[v].jpeg);
		http_png_unref(s->snap[v]);
	}
	free(s->snap_rgb);
	if (s->tj)
		tjDestroy(s->tj);
	pthread_mutex_destroy(&s->lock);
	pthread_mutex_destroy(&s->stats_lock);
	pthread_mutex_destroy(&s->snap_lock);
	pthread_mutex_destroy(&s->guard_lock);
	pthread_cond_destroy(&s->frame_cond);
	free(s);
}

static int http_open(const char *uri, void **state, struct dao_error *err)
{
	struct http_sink *s = calloc(1, sizeof(*s));
	if (!s)
		return dao_error_set(err, -ENOMEM, "out of memory");
	s->listen_fd = -1;
	pthread_mutex_init(&s->lock, NULL);
	pthread_mutex_init(&s->stats_lock, NULL);
	pthread_mutex_init(&s->snap_lock, NULL);
	pthread_mutex_init(&s->guard_lock, NULL);
	pthread_condattr_t ca;
	pthread_condattr_init(&ca);
	pthread_condattr_setclock(&ca, CLOCK_MONOTONIC);
	pthread_cond_init(&s->frame_cond, &ca);
	pthread_condattr_destroy(&ca);
	int r = parse_uri(s, uri, err);
	if (r == 0 && !(s->tj = tjInitCompress()))
		r = dao_error_set(err, -ENOMEM, "http: the JPEG encoder does not start: %s",
				 tjGetErrorStr());
	if (r == 0)
		r = listen_on(s, err);
	if (r == 0)
		r = http_routes_start(s, err); /* owns listen_fd from here */
	if (r < 0) {
		if (s->listen_fd >= 0 && !s->mhd)
			close(s->listen_fd);
		free_state(s);
		return r;
	}
	*state = s;
	return 0;
}

static void http_attach_host(void *state, const struct dao_sink_host *host)
{
	struct http_sink *s = state;
	pthread_mutex_lock(&s->lock);
	s->host = host;
	http_update_wanted(s);
	pthread_mutex_unlock(&s->lock);
	if (host && host->log) {
		char line[256];
		int v6 = strchr(s->bind_host, ':') != NULL;
		snprintf(line, sizeof line, "http: the viewer is at http://%s%s%s:%d/ (%s)",
			 v6 ? "[" : "", s->bind_host, v6 ? "]" : "", s->port,
			 s->control ? "parameters can be changed"
			 : s->token[0] ? "parameters can be changed with the token"
				       : "read-only");
		host->log(host->user, DAO_LOG_INFO, line);
	}
}

static int http_negotiate(void *state, struct dao_sink_format *fmt, struct dao_error *err)
{
	(void)state;
	if (fmt->format == DAO_PIXFMT_GRAY16) {
		fmt->format = DAO_PIXFMT_GRAY8; /* the viewer shows 8-bit pictures: the ao8 stream */
		return 0;
	}
	if (fmt->format != DAO_PIXFMT_RGB24 && fmt->format != DAO_PIXFMT_GRAY8 &&
	    fmt->format != DAO_PIXFMT_DEPTH16)
		return dao_error_set(err, -ENOTSUP,
				    "http: shows the shaded, overlay, ao8 or depth stream, not %s frames",
				    dao_pixfmt_name(fmt->format));
	return 0;
}

/* A blue-cyan-green-yellow-red ramp for depth, 0 = near. */
static void ramp(unsigned i, uint8_t rgb[3])
{
	const float t = (float)i / 255.0f;
	float r = 1.5f - 4.0f * (t > 0.75f ? t - 0.75f : 0.75f - t);
	float g = 1.5f - 4.0f * (t > 0.5f ? t - 0.5f : 0.5f - t);
	float b = 1.5f - 4.0f * (t > 0.25f ? t - 0.25f : 0.25f - t);
	rgb[0] = (uint8_t)(255.0f * (r < 0 ? 0 : r > 1 ? 1 : r));
	rgb[1] = (uint8_t)(255.0f * (g < 0 ? 0 : g > 1 ? 1 : g));
	rgb[2] = (uint8_t)(255.0f * (b < 0 ? 0 : b > 1 ? 1 : b));
}

/* DEPTH16 to RGB over the frame's own depth range; no data is black. */
static void colormap_depth(const struct dao_frame *f, uint8_t *out)
{
	uint16_t lo = UINT16_MAX, hi = 0;
	for (uint32_t y = 0; y < f->height; y++) {
		const uint16_t *row = (const uint16_t *)((const uint8_t *)f->data + (size_t)y * (size_t)f->stride);
		for (uint32_t x = 0; x < f->width; x++)
			if (row[x]) {
				lo = row[x] < lo ? row[x] : lo;
				hi = row[x] > hi ? row[x] : hi;
			}
	}
	const uint32_t span = hi > lo ? (uint32_t)(hi - lo) : 1;
	for (uint32_t y = 0; y < f->height; y++) {
		const uint16_t *row = (const uint16_t *)((const uint8_t *)f->data + (size_t)y * (size_t)f->stride);
		uint8_t *o = out + (size_t)y * f->width * 3;
		for (uint32_t x = 0; x < f->width; x++, o += 3) {
			if (!row[x]) {
				o[0] = o[1] = o[2] = 0;
				continue;
			}
			ramp((uint32_t)(row[x] - lo) * 255u / span, o);
		}
	}
}

/* The frame as the picture of stream v (pixels copied, or the depth colormapped). */
static int keep_picture(struct http_sink *s, enum view_stream v, const struct dao_frame *f)
{
	struct view_picture *p = &s->pic[v];
	const int gray = f->format == DAO_PIXFMT_GRAY8;
	const size_t row = (size_t)f->width * (gray ? 1 : 3);
	const size_t need = row * f->height;
	if (p->rgb_cap < need) {
		uint8_t *d = realloc(p->rgb, need);
		if (!d)
			return -ENOMEM;
		p->rgb = d;
		p->rgb_cap = need;
	}
	const unsigned long jcap = tjBufSize((int)f->width, (int)f->height,
					     gray ? TJSAMP_GRAY : TJSAMP_420);
	if (p->jpeg_cap < jcap) {
		tjFree(p->jpeg);
		p->jpeg = tjAlloc((int)jcap);
		p->jpeg_cap = p->jpeg ? jcap : 0;
		if (!p->jpeg)
			return -ENOMEM;
	}
	if (f->format == DAO_PIXFMT_DEPTH16) {
		colormap_depth(f, p->rgb);
	} else {
		for (uint32_t y = 0; y < f->height; y++)
			memcpy(p->rgb + (size_t)y * row,
			       (const uint8_t *)f->data + (size_t)y * (size_t)f->stride, row);
	}
	p->gray = gray;
	p->width = f->width;
	p->height = f->height;
	p->sequence = f->sequence;
	p->valid = 1;
	return 0;
}

static int http_write_stream(void *state, const struct dao_sink_frame_info *info,
			     const struct dao_frame *f, struct dao_error *err)
{
	struct http_sink *s = state;
	const uint64_t t_in = http_now_ns();
	enum view_stream v;
	switch (info->stream) {
	case DAO_STREAM_SHADED: v = VIEW_SHADED; break;
	case DAO_STREAM_AO8: v = VIEW_AO; break;
	case DAO_STREAM_OVERLAY: v = VIEW_OVERLAY; break;
	case DAO_STREAM_DEPTH: v = VIEW_DEPTH; break;
	default: return 0; /* the 16-bit AO: the viewer shows ao8 */
	}
	const int ok = (v == VIEW_DEPTH && f->format == DAO_PIXFMT_DEPTH16) ||
		       (v == VIEW_AO && f->format == DAO_PIXFMT_GRAY8) ||
		       ((v == VIEW_SHADED || v == VIEW_OVERLAY) && f->format == DAO_PIXFMT_RGB24);
	if (!ok)
		return dao_error_set(err, -EINVAL, "http: a %s frame for the %s stream",
				    dao_pixfmt_name(f->format), view_stream_name(v));
	pthread_mutex_lock(&s->lock);
	if (!s->frames_seen++)
		s->primary = v; /* the configured stream comes first */
	if (s->frames_seen == COLOR_PROBE_FRAMES)
		http_update_wanted(s); /* stop asking for the overlay nobody watches */
	if (v == VIEW_OVERLAY)
		atomic_store(&s->has_color, 1);
	const unsigned watchers = s->wanted[v];
	int r = 0;
	if (watchers || v == s->primary)
		r = keep_picture(s, v, f); /* under the lock: /snapshot.png reads it */
	pthread_mutex_unlock(&s->lock);
	if (r < 0)
		return dao_error_set(err, r, "http: out of memory for %ux%u pictures", f->width,
				    f->height);
	if (!watchers)
		return 0;
	/* only this thread changes the pictures: encoding needs no lock */
	struct view_picture *p = &s->pic[v];
	unsigned char *jpeg = p->jpeg;
	unsigned long jlen = p->jpeg_cap;
	const uint64_t t0 = http_now_ns();
	if (tjCompress2(s->tj, p->rgb, (int)p->width, 0, (int)p->height,
			p->gray ? TJPF_GRAY : TJPF_RGB, &jpeg, &jlen,
			p->gray ? TJSAMP_GRAY : TJSAMP_420, s->quality,
			TJFLAG_NOREALLOC | TJFLAG_FASTDCT) < 0)
		return dao_error_set(err, -EIO, "http: JPEG encoding failed: %s", tjGetErrorStr());
	pthread_mutex_lock(&s->lock);
	s->encode_ns += http_now_ns() - t0;
	s->encoded++;
	mjpeg_clients_push(s, v, jpeg, jlen, info->capture_ns ? info->capture_ns : t_in, t_in);
	pthread_mutex_unlock(&s->lock);
	return 0;
}

static int http_write(void *state, const struct dao_frame *f, struct dao_error *err)
{
	struct http_sink *s = state;
	const struct dao_sink_frame_info info = {
		.size = sizeof(struct dao_sink_frame_info),
		.stream = f->format == DAO_PIXFMT_GRAY8	    ? DAO_STREAM_AO8
			  : f->format == DAO_PIXFMT_DEPTH16 ? DAO_STREAM_DEPTH
							    : DAO_STREAM_SHADED,
		.capture_ns = 0,
	};
	return http_write_stream(s, &info, f, err);
}

static int http_close(void *state, struct dao_error *err)
{
	struct http_sink *s = state;
	(void)err;
	pthread_mutex_lock(&s->lock);
	s->stopping = 1;
	pthread_cond_broadcast(&s->frame_cond);
	pthread_mutex_unlock(&s->lock);
	http_routes_stop(s); /* every connection ends; their clients are freed */
	free_state(s);
	return 0;
}

static const struct dao_sink_ops http_sink_ops = {
	.version = DAO_SINK_OPS_VERSION,
	.probe = http_probe,
	.open = http_open,
	.negotiate = http_negotiate,
	.write = http_write,
	.close = http_close,
	.attach_host = http_attach_host,
	.write_stream = http_write_stream,
};

static const struct dao_plugin http_plugin = {
	DAO_PLUGIN_HEADER,
	.name = "http",
	.description = "browser viewer (libmicrohttpd): live Motion-JPEG, AO parameter sliders and "
		       "statistics, http:[HOST:]PORT",
	.sink = &http_sink_ops,
};

DAO_PLUGIN_DEFINE(http_plugin)
