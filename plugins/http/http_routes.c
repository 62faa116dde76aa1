/* SPDX-License-Identifier: MIT */
/*
 * The viewer's routes, and nothing else: /, /stream.mjpg, /api/params,
 * /api/stats, /snapshot.png.  Anything else is 404, another method 405, a
 * body over HTTP_MAX_BODY 413, more than HTTP_MAX_HEADERS header lines 431;
 * libmicrohttpd bounds the request line and headers (HTTP_MEMORY_LIMIT) and the
 * connections per address (per_ip); beyond max_clients a new connection takes the
 * slot of the oldest one still sending its request, or is closed (accept_policy,
 * http_guard.c, which also cuts a request past its deadline).  libmicrohttpd's own messages stay off:
 * a viewer closing its tab would log a failed send every time.
 */
#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#include <json-c/json.h>
#include <microhttpd.h>

#include <depthao/params.h>
#include <depthao/png.h>

#include "http_sink.h"
#include "json_strict.h"
#include "viewer_page.h"

/* A request's state between the calls of the access handler (POST bodies). */
struct request {
	char body[HTTP_MAX_BODY + 1];
	size_t len;
	int too_large;
};

static enum MHD_Result reply(struct MHD_Connection *conn, unsigned status, const char *type,
			     const void *data, size_t len, enum MHD_ResponseMemoryMode mode)
{
	struct MHD_Response *r = MHD_create_response_from_buffer(len, (void *)data, mode);
	if (!r)
		return MHD_NO;
	MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, type);
	MHD_add_response_header(r, MHD_HTTP_HEADER_CACHE_CONTROL, "no-store");
	MHD_add_response_header(r, "X-Content-Type-Options", "nosniff");
	enum MHD_Result ret = MHD_queue_response(conn, status, r);
	MHD_destroy_response(r);
	return ret;
}

static enum MHD_Result reply_json(struct MHD_Connection *conn, unsigned status,
				  struct json_object *j)
{
	const char *t = json_object_to_json_string_ext(j, JSON_C_TO_STRING_PLAIN);
	enum MHD_Result r = reply(conn, status, "application/json", t, strlen(t),
				  MHD_RESPMEM_MUST_COPY);
	json_object_put(j);
	return r;
}

static enum MHD_Result reply_error(struct MHD_Connection *conn, unsigned status, const char *msg)
{
	char safe[1024]; /* what the message echoes may be any bytes: sent as valid UTF-8 */
	http_json_safe(safe, sizeof safe, msg);
	struct json_object *j = json_object_new_object();
	json_object_object_add(j, "error", json_object_new_string(safe));
	return reply_json(conn, status, j);
}

static const char *const param_types[] = {"float", "int", "enum", "color"};

/* The host, once attached (the server answers from open on, before attach_host). */
static const struct dao_sink_host *host_of(struct http_sink *s)
{
	pthread_mutex_lock(&s->lock);
	const struct dao_sink_host *h = s->host;
	pthread_mutex_unlock(&s->lock);
	return h;
}

static struct json_object *params_json(struct http_sink *s, int control)
{
	const struct dao_sink_host *host = host_of(s);
	struct json_object *list = json_object_new_array();
	size_t n;
	const struct dao_param_info *t = dao_param_table(&n);
	for (size_t i = 0; i < n; i++) {
		char v[64];
		if (!host || !host->get_param || host->get_param(host->user, t[i].name, v, sizeof v) < 0)
			continue;
		struct json_object *o = json_object_new_object();
		json_object_object_add(o, "name", json_object_new_string(t[i].name));
		json_object_object_add(o, "value", json_object_new_string(v));
		json_object_object_add(o, "type", json_object_new_string(param_types[t[i].type]));
		if (t[i].type == DAO_PARAM_FLOAT || t[i].type == DAO_PARAM_INT) {
			json_object_object_add(o, "min", json_object_new_double(t[i].min));
			json_object_object_add(o, "max", json_object_new_double(t[i].max));
		}
		if (t[i].type == DAO_PARAM_ENUM) {
			struct json_object *e = json_object_new_array();
			for (const char *const *k = t[i].enum_names; k && *k; k++)
				json_object_array_add(e, json_object_new_string(*k));
			json_object_object_add(o, "options", e);
		}
		if (t[i].unit)
			json_object_object_add(o, "unit", json_object_new_string(t[i].unit));
		json_object_object_add(o, "help", json_object_new_string(t[i].help));
		json_object_object_add(o, "runtime",
				       json_object_new_boolean(!!(t[i].flags & DAO_PARAM_RUNTIME)));
		json_object_array_add(list, o);
	}
	struct json_object *j = json_object_new_object();
	json_object_object_add(j, "control", json_object_new_boolean(control));
	json_object_object_add(j, "params", list);
	return j;
}

/* Compares without stopping at the first difference (the token is a secret). */
static int same_secret(const char *a, const char *b)
{
	size_t la = strlen(a), lb = strlen(b);
	unsigned char d = la != lb;
	for (size_t i = 0; i < la; i++)
		d |= (unsigned char)(a[i] ^ b[i % (lb ? lb : 1)]);
	return d == 0;
}

static int may_control(struct http_sink *s, struct MHD_Connection *conn)
{
	if (s->control)
		return 1;
	const char *tok = MHD_lookup_connection_value(conn, MHD_HEADER_KIND, HTTP_TOKEN_HEADER);
	return s->token[0] && tok && same_secret(tok, s->token);
}

/* POST /api/params: a JSON object of changes, applied all together or not at all. */
static enum MHD_Result post_params(struct http_sink *s, struct MHD_Connection *conn,
				   struct request *rq)
{
	if (!may_control(s, conn))
		return reply_error(conn, MHD_HTTP_FORBIDDEN,
				   "the viewer is read-only: start the sink with ?control=true, or "
				   "give it ?token=SECRET and send the header " HTTP_TOKEN_HEADER);
	rq->body[rq->len] = '\0';
	char why[256];
	if (json_strict_check(rq->body, rq->len, HTTP_JSON_MAX_DEPTH, why, sizeof why) < 0) {
		char msg[320];
		snprintf(msg, sizeof msg, "not accepted as a JSON object of parameter changes: %s", why);
		return reply_error(conn, MHD_HTTP_BAD_REQUEST, msg);
	}
	struct json_tokener *tk = json_tokener_new_ex(HTTP_JSON_MAX_DEPTH + 2);
	struct json_object *j = tk ? json_tokener_parse_ex(tk, rq->body, (int)rq->len) : NULL;
	int complete = tk && json_tokener_get_error(tk) == json_tokener_success &&
		       tk->char_offset == (int)rq->len;
	json_tokener_free(tk);
	if (!j || !complete || !json_object_is_type(j, json_type_object)) {
		json_object_put(j);
		return reply_error(conn, MHD_HTTP_BAD_REQUEST,
				   "expected one JSON object of parameter changes, e.g. "
				   "{\"radius\": 0.5, \"algorithm\": \"gtao\"}");
	}
	const char *names[128], *values[128];
	size_t n = 0;
	char msg[512] = "";
	json_object_object_foreach(j, key, val)
	{
		if (n == 128) {
			snprintf(msg, sizeof msg, "too many changes in one request (128 at most)");
			break;
		}
		if (!dao_param_find(key)) {
			snprintf(msg, sizeof msg, "unknown AO parameter '%.100s'", key);
			break;
		}
		if (!json_object_is_type(val, json_type_string) &&
		    !json_object_is_type(val, json_type_int) &&
		    !json_object_is_type(val, json_type_double)) {
			snprintf(msg, sizeof msg, "%.100s: the value must be a number or a string", key);
			break;
		}
		names[n] = key;
		values[n++] = json_object_get_string(val);
	}
	const struct dao_sink_host *host = host_of(s);
	if (!msg[0] && (!host || !host->set_params))
		snprintf(msg, sizeof msg, "this host does not take parameter changes");
	if (!msg[0] && host->set_params(host->user, names, values, n, msg, sizeof msg) < 0 &&
	    !msg[0])
		snprintf(msg, sizeof msg, "the changes were refused");
	json_object_put(j);
	if (msg[0])
		return reply_error(conn, MHD_HTTP_BAD_REQUEST, msg);
	return reply_json(conn, MHD_HTTP_OK, params_json(s, 1));
}

static int cmp_u32(const void *a, const void *b)
{
	uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
	return x < y ? -1 : x > y;
}

static enum MHD_Result get_stats(struct http_sink *s, struct MHD_Connection *conn)
{
	uint32_t *lat = s->lat_sorted; /* under s->lock */
	struct json_object *h = json_object_new_object();
	pthread_mutex_lock(&s->lock);
	unsigned n = s->lat_n;
	memcpy(lat, s->lat_us, n * sizeof s->lat_us[0]);
	qsort(lat, n, sizeof s->lat_us[0], cmp_u32);
	json_object_object_add(h, "clients", json_object_new_int((int)s->nclients));
	json_object_object_add(h, "clients_served", json_object_new_int64((int64_t)s->clients_served));
	json_object_object_add(h, "frames_sent", json_object_new_int64((int64_t)s->frames_sent));
	json_object_object_add(h, "frames_dropped", json_object_new_int64((int64_t)s->frames_dropped));
	json_object_object_add(h, "latency_ms_median", json_object_new_double(n ? lat[n / 2] / 1000.0 : 0));
	json_object_object_add(h, "latency_ms_p99",
			       json_object_new_double(n ? lat[((size_t)n * 99 + 99) / 100 - 1] / 1000.0 : 0));
	memcpy(lat, s->send_us, n * sizeof s->send_us[0]);
	qsort(lat, n, sizeof s->send_us[0], cmp_u32);
	json_object_object_add(h, "sink_ms_median", json_object_new_double(n ? lat[n / 2] / 1000.0 : 0));
	json_object_object_add(h, "sink_ms_p99",
			       json_object_new_double(n ? lat[((size_t)n * 99 + 99) / 100 - 1] / 1000.0 : 0));
	json_object_object_add(h, "snapshots_encoded", json_object_new_int64((int64_t)s->snap_encoded));
	json_object_object_add(h, "snapshots_shared", json_object_new_int64((int64_t)s->snap_shared));
	json_object_object_add(h, "streams_refused", json_object_new_int64((int64_t)s->streams_refused));
	json_object_object_add(h, "encode_ms_mean",
			       json_object_new_double(s->encoded ? (double)s->encode_ns / 1e6 / (double)s->encoded : 0));
	pthread_mutex_unlock(&s->lock);
	pthread_mutex_lock(&s->guard_lock);
	json_object_object_add(h, "requests_cut_at_deadline", json_object_new_int64((int64_t)s->deadline_cuts));
	json_object_object_add(h, "requests_cut_for_room", json_object_new_int64((int64_t)s->evicted));
	json_object_object_add(h, "rate_limited", json_object_new_int64((int64_t)s->rate_limited));
	pthread_mutex_unlock(&s->guard_lock);
	struct json_object *streams = json_object_new_array();
	for (int v = 0; v < VIEW_COUNT; v++)
		if (v != VIEW_OVERLAY || atomic_load(&s->has_color))
			json_object_array_add(streams, json_object_new_string(view_stream_name(v)));
	json_object_object_add(h, "streams", streams);
	json_object_object_add(h, "control", json_object_new_boolean(may_control(s, conn)));
	struct json_object *j = json_object_new_object();
	pthread_mutex_lock(&s->stats_lock); /* one stats reply at a time: stats_text */
	struct json_object *dj = NULL;
	const struct dao_sink_host *host = host_of(s);
	if (host && host->stats_json &&
	    host->stats_json(host->user, s->stats_text, sizeof s->stats_text) >= 0)
		dj = json_tokener_parse(s->stats_text);
	pthread_mutex_unlock(&s->stats_lock);
	json_object_object_add(j, "daemon", dj ? dj : json_object_new_object());
	json_object_object_add(j, "http", h);
	return reply_json(conn, MHD_HTTP_OK, j);
}

void http_png_unref(struct png_blob *b)
{
	if (b && atomic_fetch_sub(&b->refs, 1) == 1)
		free(b);
}

static void png_reply_done(void *data)
{
	http_png_unref((struct png_blob *)((unsigned char *)data - offsetof(struct png_blob, data)));
}

/* The stream's last PNG with a reference taken, if it is of the current frame or
   young enough to share (s->lock held). */
static struct png_blob *fresh_png(struct http_sink *s, enum view_stream v, uint64_t now)
{
	struct png_blob *b = s->snap[v];
	if (b && (s->snap_seq[v] == s->pic[v].sequence ||
		  now - s->snap_ns[v] < (uint64_t)HTTP_SNAPSHOT_MIN_INTERVAL_MS * 1000000u)) {
		atomic_fetch_add(&b->refs, 1);
		return b;
	}
	return NULL;
}

/* A new PNG of stream v's picture (snap_lock held: one encoder at a time). */
static struct png_blob *encode_png(struct http_sink *s, enum view_stream v)
{
	pthread_mutex_lock(&s->lock);
	struct view_picture *p = &s->pic[v];
	const size_t bytes = (size_t)p->width * p->height * (p->gray ? 1 : 3);
	if (s->snap_rgb_cap < bytes) {
		uint8_t *d = realloc(s->snap_rgb, bytes);
		if (!d) {
			pthread_mutex_unlock(&s->lock);
			return NULL;
		}
		s->snap_rgb = d;
		s->snap_rgb_cap = bytes;
	}
	memcpy(s->snap_rgb, p->rgb, bytes);
	const uint32_t w = p->width, h = p->height;
	const int gray = p->gray;
	const uint64_t seq = p->sequence;
	pthread_mutex_unlock(&s->lock);
	/* the library's writer at its default (its fastest) level: a snapshot is for looking at */
	const struct dao_frame f = {
		.format = gray ? DAO_PIXFMT_GRAY8 : DAO_PIXFMT_RGB24, .width = w, .height = h,
		.stride = (int32_t)(w * (gray ? 1 : 3)), .data = s->snap_rgb,
	};
	void *png = NULL;
	size_t len = 0;
	if (dao_png_encode(&f, DAO_PNG_COMPRESSION_DEFAULT, &png, &len, NULL) < 0)
		return NULL;
	struct png_blob *b = malloc(sizeof(*b) + len);
	if (b) {
		atomic_init(&b->refs, 2); /* the cache's and the caller's */
		b->len = len;
		memcpy(b->data, png, len);
	}
	free(png);
	if (!b)
		return NULL;
	pthread_mutex_lock(&s->lock);
	http_png_unref(s->snap[v]);
	s->snap[v] = b;
	s->snap_seq[v] = seq;
	s->snap_ns[v] = http_now_ns();
	s->snap_encoded++;
	pthread_mutex_unlock(&s->lock);
	return b;
}

static enum MHD_Result reply_busy(struct MHD_Connection *conn, unsigned status, unsigned retry,
				  int close, const char *msg)
{
	char safe[256], t[320], ra[16];
	http_json_safe(safe, sizeof safe, msg);
	struct json_object *j = json_object_new_object();
	json_object_object_add(j, "error", json_object_new_string(safe));
	snprintf(t, sizeof t, "%s", json_object_to_json_string_ext(j, JSON_C_TO_STRING_PLAIN));
	json_object_put(j);
	struct MHD_Response *r = MHD_create_response_from_buffer(strlen(t), t, MHD_RESPMEM_MUST_COPY);
	if (!r)
		return MHD_NO;
	snprintf(ra, sizeof ra, "%u", retry);
	MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, "application/json");
	MHD_add_response_header(r, MHD_HTTP_HEADER_CACHE_CONTROL, "no-store");
	MHD_add_response_header(r, MHD_HTTP_HEADER_RETRY_AFTER, ra);
	if (close)
		MHD_add_response_header(r, MHD_HTTP_HEADER_CONNECTION, "close");
	enum MHD_Result ret = MHD_queue_response(conn, status, r);
	MHD_destroy_response(r);
	return ret;
}

/*
 * The snapshot: rate-limited (per address and for everyone: 429 with Retry-After),
 * then the stream's last PNG when it is of the current frame or younger than
 * HTTP_SNAPSHOT_MIN_INTERVAL_MS, else one new PNG that the requests waiting
 * meanwhile share.  Never encoded per request; the writer is never waited on
 * beyond the copy of the picture.
 */
static enum MHD_Result get_snapshot(struct http_sink *s, struct MHD_Connection *conn,
				    enum view_stream v)
{
	unsigned retry;
	if (!http_rate_take(s, conn, &retry))
		return reply_busy(conn, MHD_HTTP_TOO_MANY_REQUESTS, retry, 0,
				  "too many snapshots: try again after Retry-After seconds");
	pthread_mutex_lock(&s->lock);
	const int valid = s->pic[v].valid;
	struct png_blob *b = valid ? fresh_png(s, v, http_now_ns()) : NULL;
	if (b)
		s->snap_shared++;
	pthread_mutex_unlock(&s->lock);
	if (!valid)
		return reply_error(conn, MHD_HTTP_SERVICE_UNAVAILABLE,
				   "no frame of that stream yet: try again, or watch it first");
	if (!b) {
		pthread_mutex_lock(&s->snap_lock);
		pthread_mutex_lock(&s->lock); /* another request may have encoded it meanwhile */
		b = fresh_png(s, v, http_now_ns());
		if (b)
			s->snap_shared++;
		pthread_mutex_unlock(&s->lock);
		if (!b)
			b = encode_png(s, v);
		pthread_mutex_unlock(&s->snap_lock);
	}
	if (!b)
		return reply_error(conn, MHD_HTTP_INTERNAL_SERVER_ERROR, "cannot encode the PNG");
	struct MHD_Response *r =
		MHD_create_response_from_buffer_with_free_callback(b->len, b->data, png_reply_done);
	if (!r) {
		http_png_unref(b);
		return MHD_NO;
	}
	MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, "image/png");
	MHD_add_response_header(r, MHD_HTTP_HEADER_CACHE_CONTROL, "no-store");
	enum MHD_Result ret = MHD_queue_response(conn, MHD_HTTP_OK, r);
	MHD_destroy_response(r);
	return ret;
}

struct stream_ctx {
	struct http_sink *s;
	struct mjpeg_client *c;
};

static ssize_t stream_read(void *cls, uint64_t pos, char *buf, size_t max)
{
	struct stream_ctx *x = cls;
	(void)pos;
	return mjpeg_client_read(x->s, x->c, buf, max);
}

/* The connection ended: the client and its queue go at once. */
static void stream_free(void *cls)
{
	struct stream_ctx *x = cls;
	pthread_mutex_lock(&x->s->lock);
	mjpeg_client_free(x->s, x->c);
	pthread_mutex_unlock(&x->s->lock);
	free(x);
}

static enum MHD_Result get_stream(struct http_sink *s, struct MHD_Connection *conn,
				  enum view_stream v)
{
	if (!http_guard_stream_slot(s, conn)) {
		pthread_mutex_lock(&s->lock);
		s->streams_refused++;
		pthread_mutex_unlock(&s->lock);
		/* its slot is free before the reply leaves (the connection closes after it):
		   a request right after it is let in, not cut for want of a slot */
		http_guard_release(s, conn);
		return reply_busy(conn, MHD_HTTP_SERVICE_UNAVAILABLE, 2, 1,
				  "every stream slot is taken (the rest are kept for the page and "
				  "the API): try again later");
	}
	struct stream_ctx *x = malloc(sizeof(*x));
	if (!x)
		return MHD_NO;
	x->s = s;
	pthread_mutex_lock(&s->lock);
	x->c = mjpeg_client_new(s, v);
	pthread_mutex_unlock(&s->lock);
	if (!x->c) {
		free(x);
		return MHD_NO;
	}
	struct MHD_Response *r =
		MHD_create_response_from_callback(MHD_SIZE_UNKNOWN, 32 * 1024, stream_read, x, stream_free);
	if (!r) {
		stream_free(x);
		return MHD_NO;
	}
	MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE,
				"multipart/x-mixed-replace; boundary=depthaoframe");
	MHD_add_response_header(r, MHD_HTTP_HEADER_CACHE_CONTROL, "no-store");
	enum MHD_Result ret = MHD_queue_response(conn, MHD_HTTP_OK, r);
	MHD_destroy_response(r);
	return ret;
}

static enum MHD_Result count_header(void *cls, enum MHD_ValueKind kind, const char *key,
				    const char *value)
{
	(void)kind;
	(void)key;
	(void)value;
	(*(unsigned *)cls)++;
	return MHD_YES;
}

/* ?stream=NAME (default: the configured stream); -1 when it names none */
static int stream_arg(struct http_sink *s, struct MHD_Connection *conn, enum view_stream *v)
{
	const char *name = MHD_lookup_connection_value(conn, MHD_GET_ARGUMENT_KIND, "stream");
	if (!name) {
		pthread_mutex_lock(&s->lock);
		*v = s->primary;
		pthread_mutex_unlock(&s->lock);
		return 0;
	}
	if (view_stream_parse(name, v) < 0)
		return -1;
	return 0;
}

static enum MHD_Result route(void *cls, struct MHD_Connection *conn, const char *url,
			     const char *method, const char *version, const char *upload,
			     size_t *upload_size, void **con_cls)
{
	struct http_sink *s = cls;
	(void)version;
	const int get = !strcmp(method, MHD_HTTP_METHOD_GET) || !strcmp(method, MHD_HTTP_METHOD_HEAD);
	const int post = !strcmp(method, MHD_HTTP_METHOD_POST);
	struct request *rq = *con_cls;
	if (!rq) { /* the first call: the headers are in */
		unsigned headers = 0;
		MHD_get_connection_values(conn, MHD_HEADER_KIND, count_header, &headers);
		if (headers > HTTP_MAX_HEADERS)
			return reply_error(conn, MHD_HTTP_REQUEST_HEADER_FIELDS_TOO_LARGE,
					   "too many header lines");
		if (post && !strcmp(url, "/api/params")) {
			const char *cl = MHD_lookup_connection_value(conn, MHD_HEADER_KIND,
								     MHD_HTTP_HEADER_CONTENT_LENGTH);
			if (cl && strtoull(cl, NULL, 10) > HTTP_MAX_BODY)
				return reply_error(conn, MHD_HTTP_CONTENT_TOO_LARGE,
						   "the body is too large (8 KiB at most)");
			if (!(rq = calloc(1, sizeof(*rq))))
				return MHD_NO;
			*con_cls = rq;
			return MHD_YES;
		}
		/* other requests have no body: answered now (a body is refused below) */
	} else if (*upload_size) { /* a POST body arrives in pieces */
		if (rq->len + *upload_size > HTTP_MAX_BODY)
			rq->too_large = 1;
		else
			memcpy(rq->body + rq->len, upload, *upload_size);
		if (!rq->too_large)
			rq->len += *upload_size;
		*upload_size = 0;
		return MHD_YES;
	} else { /* the whole body is in */
		if (rq->too_large)
			return reply_error(conn, MHD_HTTP_CONTENT_TOO_LARGE,
					   "the body is too large (8 KiB at most)");
		return post_params(s, conn, rq);
	}
	if (upload && *upload_size)
		return reply_error(conn, MHD_HTTP_BAD_REQUEST, "this route takes no body");
	const char *allow = "GET, HEAD";
	if (!strcmp(url, "/") || !strcmp(url, "/index.html")) {
		if (get)
			return reply(conn, MHD_HTTP_OK, "text/html; charset=utf-8", viewer_html,
				     sizeof viewer_html - 1, MHD_RESPMEM_PERSISTENT);
	} else if (!strcmp(url, "/stream.mjpg") || !strcmp(url, "/snapshot.png")) {
		enum view_stream v;
		if (get && stream_arg(s, conn, &v) < 0)
			return reply_error(conn, MHD_HTTP_BAD_REQUEST,
					   "unknown stream (streams: shaded, ao, overlay, depth)");
		if (get && v == VIEW_OVERLAY && !atomic_load(&s->has_color))
			return reply_error(conn, MHD_HTTP_BAD_REQUEST,
					   "the overlay needs a source with colour; this one has none");
		if (get)
			return url[1] == 's' && url[2] == 't' ? get_stream(s, conn, v)
							     : get_snapshot(s, conn, v);
	} else if (!strcmp(url, "/api/stats")) {
		if (get)
			return get_stats(s, conn);
	} else if (!strcmp(url, "/api/params")) {
		if (get)
			return reply_json(conn, MHD_HTTP_OK, params_json(s, may_control(s, conn)));
		allow = "GET, HEAD, POST";
	} else {
		return reply_error(conn, MHD_HTTP_NOT_FOUND,
				   "no such page (/, /stream.mjpg, /snapshot.png, /api/params, "
				   "/api/stats)");
	}
	char msg[160];
	char m[64];
	http_json_safe(m, 21, method);
	snprintf(msg, sizeof msg, "method %s is not allowed here (allowed: %s)", m, allow);
	struct json_object *j = json_object_new_object();
	json_object_object_add(j, "error", json_object_new_string(msg));
	const char *t = json_object_to_json_string_ext(j, JSON_C_TO_STRING_PLAIN);
	struct MHD_Response *r = MHD_create_response_from_buffer(strlen(t), (void *)t,
								 MHD_RESPMEM_MUST_COPY);
	json_object_put(j);
	if (!r)
		return MHD_NO;
	MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, "application/json");
	MHD_add_response_header(r, MHD_HTTP_HEADER_ALLOW, allow);
	enum MHD_Result ret = MHD_queue_response(conn, MHD_HTTP_METHOD_NOT_ALLOWED, r);
	MHD_destroy_response(r);
	return ret;
}

/* The request's deadline ends when it is answered: the first call for requests
   without a body, the last for a POST (the body in). */
static enum MHD_Result handle(void *cls, struct MHD_Connection *conn, const char *url,
			      const char *method, const char *version, const char *upload,
			      size_t *upload_size, void **con_cls)
{
	struct http_sink *s = cls;
	const int had = *con_cls != NULL, chunk = *upload_size != 0;
	enum MHD_Result r = route(cls, conn, url, method, version, upload, upload_size, con_cls);
	if (!*con_cls || (had && !chunk)) /* replied now, or the last call of a POST */
		http_guard_answered(s, conn);
	return r;
}

static void request_done(void *cls, struct MHD_Connection *conn, void **con_cls,
			 enum MHD_RequestTerminationCode code)
{
	(void)code;
	http_guard_request_done(cls, conn);
	free(*con_cls);
	*con_cls = NULL;
}

/* Counts the open connections (libmicrohttpd's threads call this). */
static void on_connection(void *cls, struct MHD_Connection *conn, void **socket_context,
			  enum MHD_ConnectionNotificationCode code)
{
	struct http_sink *s = cls;
	if (code == MHD_CONNECTION_NOTIFY_STARTED) {
		atomic_fetch_add(&s->connections, 1);
		*socket_context = http_guard_opened(s, conn);
	} else if (code == MHD_CONNECTION_NOTIFY_CLOSED) {
		if (!http_guard_closed(s, *socket_context))
			atomic_fetch_sub(&s->connections, 1);
		*socket_context = NULL;
	}
}

/*
 * At max_clients a new connection takes the slot of the oldest one still sending
 * its request (cut: it goes in a moment, hence MHD's limit a little above ours);
 * when every connection has its request in (streams, replies on their way), the
 * new one is closed at once.  (libmicrohttpd's own limit stops accepting instead:
 * a client waited in the listen backlog, a request for /api/stats hung for as
 * long as the streams lasted.)
 */
#define EVICTING_SLOTS 16

static enum MHD_Result accept_policy(void *cls, const struct sockaddr *addr, socklen_t addrlen)
{
	struct http_sink *s = cls;
	(void)addr;
	(void)addrlen;
	const int open = atomic_load(&s->connections);
	if (open < (int)s->max_clients)
		return MHD_YES;
	if (open >= (int)s->max_clients + EVICTING_SLOTS)
		return MHD_NO;
	return http_guard_make_room(s) == 0 ? MHD_YES : MHD_NO;
}

#define SERVER_NICE 10 /* the server's threads: this much nicer than the pipeline's */

static void *start_server(void *arg)
{
	struct http_sink *s = arg;
	/* on Linux, PRIO_PROCESS 0 is the calling thread alone (nice is per thread).
	   Relative to the daemon's own niceness: one started nice 10 (a loaded host's test
	   run, or Nice= in its unit) had its server threads at the pipeline's priority, and
	   a snapshot flood then cost it a quarter of its input frames */
	errno = 0;
	int nice = getpriority(PRIO_PROCESS, 0);
	if (nice == -1 && errno)
		nice = 0;
	setpriority(PRIO_PROCESS, 0, nice + SERVER_NICE > 19 ? 19 : nice + SERVER_NICE);
	/* libmicrohttpd's per-address limit counts against max_clients only below it */
	const unsigned per_ip = s->per_ip && s->per_ip < s->max_clients ? s->per_ip : 0;
	s->mhd = MHD_start_daemon(
		MHD_USE_THREAD_PER_CONNECTION | MHD_USE_INTERNAL_POLLING_THREAD | MHD_USE_ITC,
		0, accept_policy, s, handle, s, MHD_OPTION_LISTEN_SOCKET, s->listen_fd,
		MHD_OPTION_NOTIFY_CONNECTION, on_connection, s,
		MHD_OPTION_CONNECTION_LIMIT, s->max_clients + EVICTING_SLOTS,
		MHD_OPTION_PER_IP_CONNECTION_LIMIT, per_ip, MHD_OPTION_CONNECTION_MEMORY_LIMIT,
		(size_t)HTTP_MEMORY_LIMIT, MHD_OPTION_CONNECTION_TIMEOUT, 30u,
		MHD_OPTION_NOTIFY_COMPLETED, request_done, s,
		MHD_OPTION_END);
	return NULL;
}

int http_routes_start(struct http_sink *s, struct dao_error *err)
{
	int gr = http_guard_start(s);
	if (gr < 0) {
		if (err) {
			err->code = gr;
			snprintf(err->message, sizeof err->message,
				 "http: the connection watchdog does not start: %s", strerror(-gr));
		}
		return gr;
	}
	/* started from a thread of lower priority: libmicrohttpd's threads, and every
	   connection's thread, inherit it (Linux: nice is per thread and inherited), so a
	   flood of requests takes the CPU the pipeline leaves, not the pipeline's */
	pthread_t t;
	if (pthread_create(&t, NULL, start_server, s) == 0)
		pthread_join(t, NULL);
	if (!s->mhd) {
		http_guard_stop(s);
		if (err) {
			err->code = -EIO;
			snprintf(err->message, sizeof err->message,
				 "http: the server does not start on %s:%d", s->bind_host, s->port);
		}
		return -EIO;
	}
	return 0;
}

void http_routes_stop(struct http_sink *s)
{
	if (!s->mhd)
		return;
	/* the listening socket is ours again (closed here, not by MHD), then every
	   connection ends: readers waiting for a frame see s->stopping */
	MHD_quiesce_daemon(s->mhd);
	MHD_stop_daemon(s->mhd);
	s->mhd = NULL;
	http_guard_stop(s);
	close(s->listen_fd);
	s->listen_fd = -1;
}
