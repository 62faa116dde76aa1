/* SPDX-License-Identifier: MIT */
/*
 * Sink plugin "foxglove": the running pipeline live in Foxglove, over the
 * Foxglove WebSocket protocol (subprotocol foxglove.websocket.v1, served with
 * libwebsockets by fox_server.c).
 *
 * URIs: "PORT" or "HOST:PORT" ("[V6]:PORT"), the host 127.0.0.1 unless given
 * (every interface only when asked: 0.0.0.0 or [::]), with options after '?':
 *   control=true     every client may change the AO parameters
 *   token=SECRET     ... or clients that connect with ws://HOST:PORT/?token=SECRET
 *   max-clients=N    WebSocket clients at once (1..256, default 16)
 *   queue=N          messages queued per client and channel set (1..16, default 2);
 *                    a client that does not keep up loses its oldest
 *   quality=1..100   JPEG quality of the shaded image (default 80)
 *   cloud-step=N     every N-th pixel in x and y becomes a point (1..16, default 4)
 * Without control or token the parameters are read-only.
 *
 * Channels (protobuf, the schemas of proto/foxglove/schemas.proto):
 *   /depthao/ao           foxglove.RawImage mono16 (the AO, visibility x 65535)
 *   /depthao/shaded       foxglove.CompressedImage jpeg
 *   /depthao/calibration  foxglove.CameraCalibration (with every AO frame)
 *   /depthao/cloud        foxglove.PointCloud x, y, z (m, float32) and ao (0..1)
 *   /depthao/tf           foxglove.FrameTransform: the camera's pose (frame "depthao", the
 *                         images' and the cloud's) in "depthao_odom" (the first frame's
 *                         optical frame), with each AO frame where the host tracks it
 *                         (depth-temporal-motion not off)
 * Each message is built once per frame, and only for a channel somebody is
 * subscribed to; the streams it needs are asked of the host (want_streams).
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <libwebsockets.h>
#include <turbojpeg.h>

#include <depthao/camera.h>

#include "fox_proto.h"
#include "fox_sink.h"

#define DEFAULT_QUALITY 80
#define DEFAULT_CLOUD_STEP 4
#define FRAME_ID "depthao"
#define POSE_FRAME_ID "depthao_odom"

uint64_t fox_now_ns(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

/* The wall-clock time of a CLOCK_MONOTONIC instant (message timestamps), with the
 * clocks' offset taken once at open: the messages of one frame share a timestamp. */
static uint64_t wall_ns(const struct fox_sink *s, uint64_t mono_ns)
{
	return mono_ns + s->wall_offset_ns;
}

static uint64_t wall_offset(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_REALTIME, &ts);
	const uint64_t now = (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
	const uint64_t mono = fox_now_ns();
	return now > mono ? now - mono : 0;
}

struct fox_msg *fox_msg_get(struct fox_sink *s, int ch, size_t need)
{
	pthread_mutex_lock(&s->lock);
	struct fox_msg **pp = &s->pool[ch], *m = NULL;
	for (; *pp; pp = &(*pp)->next)
		if ((*pp)->cap >= need) {
			m = *pp;
			*pp = m->next;
			break;
		}
	if (!m && s->pool[ch]) { /* grow the first unused one rather than keep both */
		m = s->pool[ch];
		s->pool[ch] = m->next;
	}
	pthread_mutex_unlock(&s->lock);
	if (!m && !(m = calloc(1, sizeof(*m))))
		return NULL;
	if (m->cap < need) {
		unsigned char *b = realloc(m->buf, LWS_PRE + need);
		if (!b) {
			free(m->buf);
			free(m);
			return NULL;
		}
		m->buf = b;
		m->cap = need;
	}
	m->next = NULL;
	m->refs = 0;
	m->text = 0;
	m->channel = ch;
	m->len = 0;
	return m;
}

void fox_msg_unref(struct fox_sink *s, struct fox_msg *m)
{
	if (--m->refs)
		return;
	if (m->text) { /* replies are made for one client: not pooled */
		free(m->buf);
		free(m);
		return;
	}
	m->next = s->pool[m->channel];
	s->pool[m->channel] = m;
}

void fox_update_wanted(struct fox_sink *s)
{
	unsigned mask = 0;
	if (s->subscribers[CH_AO] || s->subscribers[CH_CALIB] || s->subscribers[CH_TF])
		mask |= 1u << DAO_STREAM_AO;
	if (s->subscribers[CH_SHADED])
		mask |= 1u << DAO_STREAM_SHADED;
	if (s->subscribers[CH_CLOUD])
		mask |= 1u << DAO_STREAM_AO | 1u << DAO_STREAM_DEPTH;
	if (mask != s->wanted_mask && s->host && s->host->want_streams) {
		s->host->want_streams(s->host->user, mask);
		s->wanted_mask = mask;
	}
}

static int fox_probe(const char *uri)
{
	(void)uri;
	return 0; /* only by name: foxglove:PORT */
}

static const char *const fox_options[] = {"control", "token", "max-clients", "queue", "quality",
					  "cloud-step", NULL};

static int parse_options(struct fox_sink *s, const char *text, struct dao_error *err)
{
	struct dao_options *o;
	int r = dao_options_parse(&o, "foxglove", text, fox_options, err);
	if (r < 0)
		return r;
	int64_t clients = s->max_clients, queue = s->queue, quality = s->quality,
		step = s->cloud_step;
	if ((r = dao_options_get_bool(o, "control", &s->control, err)) >= 0 &&
	    (r = dao_options_get_string(o, "token", s->token, sizeof s->token, err)) >= 0 &&
	    (r = dao_options_get_int(o, "max-clients", 1, 256, &clients, err)) >= 0 &&
	    (r = dao_options_get_int(o, "queue", 1, FOX_QUEUE_MAX, &queue, err)) >= 0 &&
	    (r = dao_options_get_int(o, "quality", 1, 100, &quality, err)) >= 0 &&
	    (r = dao_options_get_int(o, "cloud-step", 1, 16, &step, err)) >= 0) {
		s->max_clients = (unsigned)clients;
		s->queue = (unsigned)queue;
		s->quality = (int)quality;
		s->cloud_step = (unsigned)step;
	}
	dao_options_free(o);
	return r < 0 ? r : 0;
}

/* "PORT", "HOST:PORT", "[V6]:PORT", each with "?OPTION&OPTION" */
static int parse_uri(struct fox_sink *s, const char *uri, struct dao_error *err)
{
	char buf[512];
	if (snprintf(buf, sizeof buf, "%s", uri) >= (int)sizeof buf)
		return dao_error_set(err, -EINVAL, "foxglove: the URI is too long");
	s->max_clients = FOX_DEFAULT_CLIENTS;
	s->queue = FOX_DEFAULT_QUEUE;
	s->quality = DEFAULT_QUALITY;
	s->cloud_step = DEFAULT_CLOUD_STEP;
	snprintf(s->bind_host, sizeof s->bind_host, "127.0.0.1");
	size_t opts_at = dao_uri_path_len(buf, fox_options);
	int r;
	if (buf[opts_at] && (r = parse_options(s, buf + opts_at + 1, err)) < 0)
		return r;
	buf[opts_at] = '\0';
	char *p = buf;
	char *colon = strrchr(p, ':');
	if (colon && (p[0] != '[' || colon > strchr(p, ']'))) {
		*colon = '\0';
		size_t n = strlen(p);
		if (n >= 2 && p[0] == '[' && p[n - 1] == ']') {
			p[n - 1] = '\0';
			p++;
		}
		if (!*p || strlen(p) >= sizeof s->bind_host)
			return dao_error_set(err, -EINVAL,
					    "foxglove: '%s': the address is empty or too long", uri);
		snprintf(s->bind_host, sizeof s->bind_host, "%s", p);
		p = colon + 1;
	}
	char *end;
	long port = strtol(p, &end, 10);
	if (!*p || *end || port < 0 || port > 65535)
		return dao_error_set(err, -EINVAL,
				    "foxglove: '%s' is not PORT or HOST:PORT with a port in 0..65535 "
				    "(e.g. foxglove:8765 for 127.0.0.1, foxglove:0.0.0.0:8765 for every "
				    "interface)",
				    uri);
	s->port = (int)port;
	return 0;
}

static void free_state(struct fox_sink *s)
{
	for (int ch = 0; ch < CH_COUNT; ch++)
		while (s->pool[ch]) {
			struct fox_msg *m = s->pool[ch];
			s->pool[ch] = m->next;
			free(m->buf);
			free(m);
		}
	if (s->tj)
		tjDestroy(s->tj);
	tjFree(s->jpeg);
	free(s->depth);
	free(s->ao);
	pthread_mutex_destroy(&s->lock);
	free(s);
}

static int fox_open(const char *uri, void **state, struct dao_error *err)
{
	struct fox_sink *s = calloc(1, sizeof(*s));
	if (!s)
		return dao_error_set(err, -ENOMEM, "out of memory");
	pthread_mutex_init(&s->lock, NULL);
	s->wall_offset_ns = wall_offset();
	int r = parse_uri(s, uri, err);
	if (r == 0 && !(s->tj = tjInitCompress()))
		r = dao_error_set(err, -ENOMEM, "foxglove: the JPEG encoder does not start: %s",
				 tjGetErrorStr());
	if (r == 0)
		r = fox_server_start(s, err);
	if (r < 0) {
		free_state(s);
		return r;
	}
	*state = s;
	return 0;
}

static void fox_attach_host(void *state, const struct dao_sink_host *host)
{
	struct fox_sink *s = state;
	pthread_mutex_lock(&s->lock);
	s->host = host;
	s->wanted_mask = ~0u; /* tell the host once, whatever it assumed */
	fox_update_wanted(s);
	pthread_mutex_unlock(&s->lock);
	if (host && host->log) {
		char line[300];
		int v6 = strchr(s->bind_host, ':') != NULL;
		snprintf(line, sizeof line,
			 "foxglove: open ws://%s%s%s:%d in Foxglove (%s)", v6 ? "[" : "", s->bind_host,
			 v6 ? "]" : "", s->port,
			 s->control ? "parameters can be changed"
			 : s->token[0] ? "parameters can be changed with ?token="
				       : "parameters read-only");
		host->log(host->user, DAO_LOG_INFO, line);
	}
}

static int fox_negotiate(void *state, struct dao_sink_format *fmt, struct dao_error *err)
{
	struct fox_sink *s = state;
	if (fmt->format != DAO_PIXFMT_RGB24 && fmt->format != DAO_PIXFMT_GRAY16 &&
	    fmt->format != DAO_PIXFMT_GRAY8 && fmt->format != DAO_PIXFMT_DEPTH16)
		return dao_error_set(err, -ENOTSUP,
				    "foxglove: takes the shaded, ao, ao8 or depth stream, not %s frames",
				    dao_pixfmt_name(fmt->format));
	struct dao_camera cam;
	s->has_camera = fmt->has_fov &&
			dao_camera_from_fov(&cam, fmt->width, fmt->height, fmt->hfov, fmt->vfov,
					    NULL) == 0;
	if (s->has_camera) {
		s->width = fmt->width;
		s->height = fmt->height;
		s->fx = cam.fx;
		s->fy = cam.fy;
		s->cx = cam.cx;
		s->cy = cam.cy;
	}
	return 0;
}

/* Fills the Message Data header of m (the subscription id is set per client). */
static void data_header(const struct fox_sink *s, struct fox_msg *m, uint64_t capture_ns)
{
	unsigned char *h = m->buf + LWS_PRE;
	const uint64_t ts = wall_ns(s, capture_ns);
	h[0] = 0x01;
	memset(h + 1, 0, 4);
	m->entered_ns = s->entered_ns;
	for (int i = 0; i < 8; i++)
		h[5 + i] = (unsigned char)(ts >> (8 * i));
	m->capture_ns = capture_ns;
}

/* foxglove.RawImage mono16 of the AO */
static int publish_ao(struct fox_sink *s, const struct dao_frame *f, uint64_t cap)
{
	const uint64_t ts = wall_ns(s, cap);
	const size_t row = (size_t)f->width * 2, data = row * f->height;
	const size_t len = fox_pb_time_size(ts) + fox_pb_len_size(sizeof FRAME_ID - 1) + 5 + 5 +
			   fox_pb_len_size(6) + 5 + fox_pb_len_size(data);
	struct fox_msg *m = fox_msg_get(s, CH_AO, FOX_HEADER + len);
	if (!m)
		return -ENOMEM;
	data_header(s, m, cap);
	uint8_t *p = m->buf + LWS_PRE + FOX_HEADER;
	p = fox_pb_time(p, 1, ts);
	p = fox_pb_string(p, 7, FRAME_ID);
	p = fox_pb_fixed32(p, 2, f->width);
	p = fox_pb_fixed32(p, 3, f->height);
	p = fox_pb_string(p, 4, "mono16");
	p = fox_pb_fixed32(p, 5, (uint32_t)row);
	p = fox_pb_len(p, 6, data);
	for (uint32_t y = 0; y < f->height; y++, p += row)
		memcpy(p, (const uint8_t *)f->data + (size_t)y * (size_t)f->stride, row);
	m->len = (size_t)(p - (m->buf + LWS_PRE));
	fox_publish(s, m);
	return 0;
}

/* foxglove.CompressedImage jpeg of the shaded picture */
static int publish_shaded(struct fox_sink *s, const struct dao_frame *f, uint64_t cap,
			  struct dao_error *err)
{
	const unsigned long need = tjBufSize((int)f->width, (int)f->height, TJSAMP_420);
	if (s->jpeg_cap < need) {
		tjFree(s->jpeg);
		s->jpeg = tjAlloc((int)need);
		s->jpeg_cap = s->jpeg ? need : 0;
		if (!s->jpeg)
			return -ENOMEM;
	}
	unsigned char *jpeg = s->jpeg;
	unsigned long jlen = s->jpeg_cap;
	if (tjCompress2(s->tj, f->data, (int)f->width, (int)f->stride, (int)f->height, TJPF_RGB,
			&jpeg, &jlen, TJSAMP_420, s->quality, TJFLAG_NOREALLOC | TJFLAG_FASTDCT) < 0)
		return dao_error_set(err, -EIO, "foxglove: JPEG encoding failed: %s",
				    tjGetErrorStr());
	const uint64_t ts = wall_ns(s, cap);
	const size_t len = fox_pb_time_size(ts) + fox_pb_len_size(sizeof FRAME_ID - 1) +
			   fox_pb_len_size(jlen) + fox_pb_len_size(4);
	struct fox_msg *m = fox_msg_get(s, CH_SHADED, FOX_HEADER + len);
	if (!m)
		return -ENOMEM;
	data_header(s, m, cap);
	uint8_t *p = m->buf + LWS_PRE + FOX_HEADER;
	p = fox_pb_time(p, 1, ts);
	p = fox_pb_string(p, 4, FRAME_ID);
	p = fox_pb_bytes(p, 2, jpeg, jlen);
	p = fox_pb_string(p, 3, "jpeg");
	m->len = (size_t)(p - (m->buf + LWS_PRE));
	fox_publish(s, m);
	return 0;
}

/* foxglove.CameraCalibration: the pinhole camera the AO was computed with */
static int publish_calibration(struct fox_sink *s, uint64_t cap)
{
	const uint64_t ts = wall_ns(s, cap);
	const double K[9] = {s->fx, 0, s->cx, 0, s->fy, s->cy, 0, 0, 1};
	const double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
	const double P[12] = {s->fx, 0, s->cx, 0, 0, s->fy, s->cy, 0, 0, 0, 1, 0};
	const double D[5] = {0};
	/* repeated doubles, packed: tag, length, 8 bytes each */
	const size_t len = fox_pb_time_size(ts) + fox_pb_len_size(sizeof FRAME_ID - 1) + 5 + 5 +
			   fox_pb_len_size(9) + fox_pb_len_size(5 * 8) + fox_pb_len_size(9 * 8) * 2 +
			   fox_pb_len_size(12 * 8);
	struct fox_msg *m = fox_msg_get(s, CH_CALIB, FOX_HEADER + len);
	if (!m)
		return -ENOMEM;
	data_header(s, m, cap);
	uint8_t *p = m->buf + LWS_PRE + FOX_HEADER;
	p = fox_pb_time(p, 1, ts);
	p = fox_pb_string(p, 9, FRAME_ID);
	p = fox_pb_fixed32(p, 2, s->width);
	p = fox_pb_fixed32(p, 3, s->height);
	p = fox_pb_string(p, 4, "plumb_bob");
	const struct { unsigned field; const double *v; size_t n; } rep[] = {
		{5, D, 5}, {6, K, 9}, {7, R, 9}, {8, P, 12}};
	for (size_t i = 0; i < 4; i++) {
		p = fox_pb_len(p, rep[i].field, rep[i].n * 8);
		for (size_t k = 0; k < rep[i].n; k++) {
			uint64_t v;
			memcpy(&v, &rep[i].v[k], 8);
			for (int b = 0; b < 8; b++)
				*p++ = (uint8_t)(v >> (8 * b));
		}
	}
	m->len = (size_t)(p - (m->buf + LWS_PRE));
	fox_publish(s, m);
	return 0;
}

/* foxglove.FrameTransform: the camera (FRAME_ID) in POSE_FRAME_ID */
static int publish_tf(struct fox_sink *s, const struct dao_sink_frame_info *info, uint64_t cap)
{
	const uint64_t ts = wall_ns(s, cap);
	const size_t vec = 3 * 9, quat = 4 * 9; /* doubles: a tag and 8 bytes each */
	const size_t len = fox_pb_time_size(ts) + fox_pb_len_size(sizeof POSE_FRAME_ID - 1) +
			   fox_pb_len_size(sizeof FRAME_ID - 1) + fox_pb_len_size(vec) +
			   fox_pb_len_size(quat);
	struct fox_msg *m = fox_msg_get(s, CH_TF, FOX_HEADER + len);
	if (!m)
		return -ENOMEM;
	data_header(s, m, cap);
	uint8_t *p = m->buf + LWS_PRE + FOX_HEADER;
	p = fox_pb_time(p, 1, ts);
	p = fox_pb_string(p, 2, POSE_FRAME_ID);
	p = fox_pb_string(p, 3, FRAME_ID);
	p = fox_pb_len(p, 4, vec);
	for (unsigned i = 0; i < 3; i++)
		p = fox_pb_double(p, i + 1, info->pose_translation[i]);
	p = fox_pb_len(p, 5, quat);
	for (unsigned i = 0; i < 4; i++)
		p = fox_pb_double(p, i + 1, info->pose_rotation[i]);
	m->len = (size_t)(p - (m->buf + LWS_PRE));
	fox_publish(s, m);
	return 0;
}

static size_t field_size(const char *name)
{
	return fox_pb_len_size(fox_pb_len_size(strlen(name)) + 5 + 2);
}

static uint8_t *field(uint8_t *p, const char *name, uint32_t offset)
{
	p = fox_pb_len(p, 5, fox_pb_len_size(strlen(name)) + 5 + 2);
	p = fox_pb_string(p, 1, name);
	p = fox_pb_fixed32(p, 2, offset);
	p = fox_pb_tag(p, 3, PB_VARINT);
	*p++ = 7; /* FLOAT32 */
	return p;
}

/* foxglove.PointCloud of the depth and AO of one frame: x, y, z, ao (float32 each) */
static int publish_cloud(struct fox_sink *s, uint64_t cap)
{
	const uint32_t w = s->width, h = s->height, st = s->cloud_step;
	const size_t max_points = (size_t)((w + st - 1) / st) * ((h + st - 1) / st);
	const uint64_t ts = wall_ns(s, cap);
	/* the pose: identity (position 0, orientation w = 1) */
	const size_t pose = fox_pb_len_size(0) + fox_pb_len_size(9);
	const size_t len_max = fox_pb_time_size(ts) + fox_pb_len_size(sizeof FRAME_ID - 1) +
			       fox_pb_len_size(pose) + 5 + field_size("x") * 3 + field_size("ao") +
			       fox_pb_len_size(max_points * 16);
	struct fox_msg *m = fox_msg_get(s, CH_CLOUD, FOX_HEADER + len_max);
	if (!m)
		return -ENOMEM;
	data_header(s, m, cap);
	uint8_t *p = m->buf + LWS_PRE + FOX_HEADER;
	p = fox_pb_time(p, 1, ts);
	p = fox_pb_string(p, 2, FRAME_ID);
	p = fox_pb_len(p, 3, pose);
	p = fox_pb_len(p, 1, 0);
	p = fox_pb_len(p, 2, 9);
	p = fox_pb_double(p, 4, 1.0);
	p = fox_pb_fixed32(p, 4, 16);
	p = field(p, "x", 0);
	p = field(p, "y", 4);
	p = field(p, "z", 8);
	p = field(p, "ao", 12);
	/* the data's length is known only after the points: write them after room for
	 * the longest length, then move them down to their place */
	uint8_t *tag = p;
	uint8_t *pts = tag + 1 + fox_pb_varint_size(max_points * 16);
	uint8_t *q = pts;
	const float unit = s->depth_unit > 0 ? s->depth_unit : 0.001f;
	for (uint32_t y = 0; y < h; y += st)
		for (uint32_t x = 0; x < w; x += st) {
			const uint16_t d = s->depth[(size_t)y * w + x];
			if (!d)
				continue;
			const float z = (float)d * unit;
			const float v[4] = {(float)(((double)x - s->cx) * z / s->fx),
					    (float)(((double)y - s->cy) * z / s->fy), z,
					    (float)s->ao[(size_t)y * w + x] / 65535.0f};
			memcpy(q, v, sizeof v);
			q += sizeof v;
		}
	const size_t n = (size_t)(q - pts);
	p = fox_pb_len(tag, 6, n);
	memmove(p, pts, n);
	m->len = (size_t)(p + n - (m->buf + LWS_PRE));
	fox_publish(s, m);
	return 0;
}

/* Keeps a tightly packed copy of a 16-bit frame in *buf. */
static int keep16(uint16_t **buf, size_t *cap, const struct dao_frame *f)
{
	const size_t n = (size_t)f->width * f->height;
	if (*cap < n) {
		uint16_t *b = realloc(*buf, n * 2);
		if (!b)
			return -ENOMEM;
		*buf = b;
		*cap = n;
	}
	for (uint32_t y = 0; y < f->height; y++)
		memcpy(*buf + (size_t)y * f->width, (const uint8_t *)f->data + (size_t)y * (size_t)f->stride,
		       (size_t)f->width * 2);
	return 0;
}

static int fox_write_stream(void *state, const struct dao_sink_frame_info *info,
			    const struct dao_frame *f, struct dao_error *err)
{
	struct fox_sink *s = state;
	s->entered_ns = fox_now_ns();
	const uint64_t cap = DAO_STRUCT_HAS(struct dao_sink_frame_info, info, capture_ns) &&
				     info->capture_ns ? info->capture_ns : fox_now_ns();
	pthread_mutex_lock(&s->lock);
	unsigned subs[CH_COUNT];
	memcpy(subs, s->subscribers, sizeof subs);
	pthread_mutex_unlock(&s->lock);
	const int cam_ok = s->has_camera && f->width == s->width && f->height == s->height;
	int r = 0;
	switch (info->stream) {
	case DAO_STREAM_AO:
		if (f->format != DAO_PIXFMT_GRAY16)
			break;
		if (subs[CH_AO])
			r = publish_ao(s, f, cap);
		if (r == 0 && subs[CH_CALIB] && cam_ok)
			r = publish_calibration(s, cap);
		if (r == 0 && subs[CH_TF] &&
		    DAO_STRUCT_HAS(struct dao_sink_frame_info, info, pose_translation) &&
		    info->has_pose)
			r = publish_tf(s, info, cap);
		if (r == 0 && subs[CH_CLOUD] && cam_ok) {
			r = keep16(&s->ao, &s->ao_cap, f);
			s->ao_seq = f->sequence;
			s->have_ao = r == 0;
		}
		break;
	case DAO_STREAM_SHADED:
		if (f->format == DAO_PIXFMT_RGB24 && subs[CH_SHADED])
			r = publish_shaded(s, f, cap, err);
		break;
	case DAO_STREAM_DEPTH:
		if (f->format == DAO_PIXFMT_DEPTH16 && subs[CH_CLOUD] && cam_ok) {
			r = keep16(&s->depth, &s->depth_cap, f);
			s->depth_seq = f->sequence;
			s->depth_unit = f->depth_unit;
			s->have_depth = r == 0;
		}
		break;
	default:
		break;
	}
	/* the depth and the AO of one frame, in whichever order they came */
	if (r == 0 && s->have_ao && s->have_depth && s->ao_seq == s->depth_seq &&
	    (s->cloud_seq != s->ao_seq + 1)) {
		s->cloud_seq = s->ao_seq + 1;
		r = publish_cloud(s, cap);
	}
	if (r == -ENOMEM)
		return dao_error_set(err, r, "foxglove: out of memory for a %ux%u frame", f->width,
				    f->height);
	return r;
}

static int fox_write(void *state, const struct dao_frame *f, struct dao_error *err)
{
	const struct dao_sink_frame_info info = {
		.size = sizeof(struct dao_sink_frame_info),
		.stream = f->format == DAO_PIXFMT_GRAY16    ? DAO_STREAM_AO
			  : f->format == DAO_PIXFMT_DEPTH16 ? DAO_STREAM_DEPTH
			  : f->format == DAO_PIXFMT_RGB24   ? DAO_STREAM_SHADED
							    : DAO_STREAM_AO8,
	};
	return fox_write_stream(state, &info, f, err);
}

static int fox_close(void *state, struct dao_error *err)
{
	struct fox_sink *s = state;
	(void)err;
	fox_server_stop(s);
	if (s->host && s->host->log) {
		double med, p99, in_med, in_p99, b_med, b_p99;
		unsigned n;
		char line[512];
		pthread_mutex_lock(&s->lock);
		fox_latency(s, &med, &p99, &n);
		fox_ring_stats(s->lat_sink_us, n, &in_med, &in_p99);
		fox_ring_stats(s->lat_build_us, n, &b_med, &b_p99);
		snprintf(line, sizeof line,
			 "foxglove: %llu clients served, %llu messages sent, %llu dropped (slow "
			 "clients), %llu connections refused; latency capture -> socket median "
			 "%.2f ms, p99 %.2f ms (%u messages); of it in the sink median %.2f ms, "
			 "p99 %.2f ms; building the message median %.2f ms, p99 %.2f ms",
			 s->clients_served, s->sent, s->dropped, s->refused, med, p99, n, in_med,
			 in_p99, b_med, b_p99);
		pthread_mutex_unlock(&s->lock);
		s->host->log(s->host->user, DAO_LOG_INFO, line);
	}
	free_state(s);
	return 0;
}

static const struct dao_sink_ops fox_sink_ops = {
	.version = DAO_SINK_OPS_VERSION,
	.probe = fox_probe,
	.open = fox_open,
	.negotiate = fox_negotiate,
	.write = fox_write,
	.close = fox_close,
	.attach_host = fox_attach_host,
	.write_stream = fox_write_stream,
};

static const struct dao_plugin fox_plugin = {
	DAO_PLUGIN_HEADER,
	.name = "foxglove",
	.description = "Foxglove WebSocket server (libwebsockets): the AO, the shaded image, the "
		       "calibration, the AO point cloud and the camera's pose live in Foxglove, the "
		       "AO parameters as its parameters, foxglove:[HOST:]PORT",
	.sink = &fox_sink_ops,
};

DAO_PLUGIN_DEFINE(fox_plugin)
