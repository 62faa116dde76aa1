/* SPDX-License-Identifier: MIT */
/*
 * The foxglove sink's WebSocket server: libwebsockets with one service
 * thread, subprotocol foxglove.websocket.v1 only.  What a client can do is
 * bounded from its first byte:
 *  - FOX_PENDING_MAX connections may be in their handshake (FOX_PENDING_PER_ADDR
 *    from one address), each for FOX_HANDSHAKE_MS in total however it trickles
 *    (a deadline, not an idle timeout); a newcomer when they are all taken cuts
 *    the oldest of the address holding the most (pending_evict); then max-clients
 *    established clients (more are refused at the handshake);
 *  - a message is at most FOX_MAX_IN bytes (1009 above), strict JSON (json_strict.h,
 *    nested at most FOX_JSON_MAX_DEPTH),
 *    and FOX_RATE_PER_S of them a second (burst FOX_RATE_BURST); beyond, they are
 *    dropped with one status a second;
 *  - replies queue up to FOX_CTL_MAX; a client that asks more than it reads is
 *    closed.  Frames queue `queue` deep per channel and the oldest is dropped.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/socket.h>

#include <json-c/json.h>
#include <libwebsockets.h>

#include <depthao/params.h>

#include "fox_sink.h"
#include "json_strict.h"
#include "schemas_fds.h"

#define SUBPROTOCOL "foxglove.websocket.v1"
#define MAX_PARAMS 128
#define TICK_US (200 * 1000)
#define FOX_PIECE (64 * 1024) /* a message goes out in WebSocket fragments of this */
#define PARAM_POLL_NS 1000000000ull

static const char *const topics[CH_COUNT] = {"/depthao/ao", "/depthao/shaded",
					     "/depthao/calibration", "/depthao/cloud",
					     "/depthao/tf"};
static const char *const schema_names[CH_COUNT] = {"foxglove.RawImage", "foxglove.CompressedImage",
						   "foxglove.CameraCalibration",
						   "foxglove.PointCloud", "foxglove.FrameTransform"};

struct fox_client {
	struct fox_client *next;
	struct lws *wsi;
	int control;
	int subscribed[CH_COUNT];
	uint32_t sub_id[CH_COUNT];
	struct fox_msg *q[CH_COUNT][FOX_QUEUE_MAX]; /* per channel, oldest first */
	unsigned q_n[CH_COUNT];
	struct fox_msg *ctl[FOX_CTL_MAX];
	unsigned ctl_head, ctl_n;
	int overflow;              /* its replies overflowed: closed */
	unsigned char param_sub[MAX_PARAMS];
	/* the service thread's alone */
	unsigned char in[FOX_MAX_IN];
	size_t in_len;
	int in_too_big;
	double tokens;
	uint64_t tokens_at, limit_noted_at;
	int inflight;              /* lws holds the rest of a message */
	uint64_t inflight_cap, inflight_entered, inflight_published;
	struct fox_msg *cur;       /* being sent in fragments (a reference) */
	size_t cur_off;            /* bytes of it sent */
	int cur_ch;
};

struct pending {
	struct lws *wsi;
	uint64_t deadline;
	struct sockaddr_storage addr;
	socklen_t alen;
};

struct fox_server {
	struct fox_sink *s;
	lws_sorted_usec_list_t tick;
	struct pending pending[FOX_PENDING_MAX];
	unsigned npending;
	char last[MAX_PARAMS][64]; /* the parameter values last told to subscribers */
	int have_last;
	uint64_t polled_at;
	char *advertise;           /* the advertise message, built once */
};

/* What lws keeps per connection. */
struct pss {
	struct fox_client *c;
	int control;               /* decided at the handshake (?token=) */
};

/* ---- queues (s->lock held) ---------------------------------------------- */

static int queued(const struct fox_client *c)
{
	if (c->ctl_n)
		return 1;
	for (int ch = 0; ch < CH_COUNT; ch++)
		if (c->q_n[ch])
			return 1;
	return 0;
}

void fox_publish(struct fox_sink *s, struct fox_msg *m)
{
	pthread_mutex_lock(&s->lock);
	m->refs = 1; /* ours until the loop is done */
	m->published_ns = fox_now_ns();
	const int ch = m->channel;
	for (struct fox_client *c = s->clients; c; c = c->next) {
		if (!c->subscribed[ch])
			continue;
		if (c->q_n[ch] == s->queue) { /* drop the oldest */
			fox_msg_unref(s, c->q[ch][0]);
			memmove(c->q[ch], c->q[ch] + 1, (s->queue - 1) * sizeof c->q[ch][0]);
			c->q_n[ch]--;
			s->dropped++;
		}
		c->q[ch][c->q_n[ch]++] = m;
		m->refs++;
	}
	s->msgs_built[ch]++;
	fox_msg_unref(s, m);
	pthread_mutex_unlock(&s->lock);
	if (s->ctx)
		lws_cancel_service(s->ctx); /* the service thread asks for writable sockets */
}

/* A JSON reply for one client; the client is marked for closing if it does not read them. */
static void send_json(struct fox_sink *s, struct fox_client *c, struct json_object *j)
{
	const char *t = json_object_to_json_string_ext(j, JSON_C_TO_STRING_PLAIN |
							  JSON_C_TO_STRING_NOSLASHESCAPE);
	const size_t len = strlen(t);
	struct fox_msg *m = calloc(1, sizeof(*m));
	unsigned char *b = m ? malloc(LWS_PRE + len) : NULL;
	if (!b) {
		free(m);
		json_object_put(j);
		return;
	}
	memcpy(b + LWS_PRE, t, len);
	json_object_put(j);
	m->buf = b;
	m->cap = m->len = len;
	m->text = 1;
	m->refs = 1;
	pthread_mutex_lock(&s->lock);
	if (c->ctl_n == FOX_CTL_MAX) {
		c->overflow = 1;
		fox_msg_unref(s, m);
	} else {
		c->ctl[(c->ctl_head + c->ctl_n++) % FOX_CTL_MAX] = m;
	}
	pthread_mutex_unlock(&s->lock);
	lws_callback_on_writable(c->wsi);
}

/* Copies at most cap-1 bytes of valid UTF-8 `src` without cutting a character. */
static void clip_utf8(char *dst, size_t cap, const char *src)
{
	size_t n = strlen(src);
	if (n >= cap) {
		n = cap - 1;
		while (n && ((unsigned char)src[n] & 0xc0) == 0x80)
			n--;
	}
	memcpy(dst, src, n);
	dst[n] = '\0';
}

/* level 0 info, 1 warning, 2 error; `id` echoes a request's id (NULL: none) */
static void send_status(struct fox_sink *s, struct fox_client *c, int level, const char *msg,
			const char *id)
{
	struct json_object *j = json_object_new_object();
	json_object_object_add(j, "op", json_object_new_string("status"));
	json_object_object_add(j, "level", json_object_new_int(level));
	json_object_object_add(j, "message", json_object_new_string(msg));
	if (id)
		json_object_object_add(j, "id", json_object_new_string(id));
	send_json(s, c, j);
}

/* ---- parameters ---------------------------------------------------------- */

static size_t param_count(void)
{
	size_t n;
	dao_param_table(&n);
	return n < MAX_PARAMS ? n : MAX_PARAMS;
}

static int param_index(const char *name)
{
	size_t n;
	const struct dao_param_info *t = dao_param_table(&n);
	const struct dao_param_info *p = dao_param_find(name);
	if (!p)
		return -1;
	size_t i = (size_t)(p - t);
	return i < MAX_PARAMS ? (int)i : -1;
}

static const struct dao_sink_host *host_of(struct fox_sink *s)
{
	pthread_mutex_lock(&s->lock);
	const struct dao_sink_host *h = s->host;
	pthread_mutex_unlock(&s->lock);
	return h;
}

/* {name, value[, type]} of parameter i from its text; NULL when the host has none */
static struct json_object *param_json(size_t i, const char *text)
{
	size_t n;
	const struct dao_param_info *t = dao_param_table(&n);
	struct json_object *o = json_object_new_object();
	json_object_object_add(o, "name", json_object_new_string(t[i].name));
	if (t[i].type == DAO_PARAM_FLOAT) {
		json_object_object_add(o, "value", json_object_new_double(strtod(text, NULL)));
		json_object_object_add(o, "type", json_object_new_string("float64"));
	} else if (t[i].type == DAO_PARAM_INT) {
		json_object_object_add(o, "value", json_object_new_int64(strtoll(text, NULL, 10)));
	} else {
		json_object_object_add(o, "value", json_object_new_string(text));
	}
	return o;
}

static int get_param(struct fox_sink *s, size_t i, char *v, size_t len)
{
	size_t n;
	const struct dao_param_info *t = dao_param_table(&n);
	const struct dao_sink_host *h = host_of(s);
	if (!h || !h->get_param)
		return -ENOTSUP;
	return h->get_param(h->user, t[i].name, v, len);
}

/* parameterValues of the parameters flagged in `which` (all when NULL) */
static void send_values(struct fox_sink *s, struct fox_client *c, const unsigned char *which,
			const char *id)
{
	struct json_object *list = json_object_new_array();
	for (size_t i = 0; i < param_count(); i++) {
		char v[64];
		if ((which && !which[i]) || get_param(s, i, v, sizeof v) < 0)
			continue;
		json_object_array_add(list, param_json(i, v));
	}
	struct json_object *j = json_object_new_object();
	json_object_object_add(j, "op", json_object_new_string("parameterValues"));
	json_object_object_add(j, "parameters", list);
	if (id)
		json_object_object_add(j, "id", json_object_new_string(id));
	send_json(s, c, j);
}

/* Tells the subscribers what changed since the last look (the service thread). */
static void poll_params(struct fox_server *srv)
{
	struct fox_sink *s = srv->s;
	unsigned char changed[MAX_PARAMS] = {0};
	int any = 0;
	for (size_t i = 0; i < param_count(); i++) {
		char v[64];
		if (get_param(s, i, v, sizeof v) < 0)
			continue;
		if (srv->have_last && strcmp(v, srv->last[i]))
			changed[i] = 1, any = 1;
		snprintf(srv->last[i], sizeof srv->last[i], "%s", v);
	}
	srv->have_last = 1;
	srv->polled_at = fox_now_ns();
	if (!any)
		return;
	/* the service thread alone changes the client list's membership */
	for (struct fox_client *c = s->clients; c; c = c->next) {
		unsigned char which[MAX_PARAMS];
		int mine = 0;
		for (size_t i = 0; i < MAX_PARAMS; i++)
			mine |= (which[i] = (unsigned char)(changed[i] && c->param_sub[i]));
		if (mine)
			send_values(s, c, which, NULL);
	}
}

/* ---- client requests ------------------------------------------------------ */

static const char *string_of(struct json_object *o, const char *key)
{
	struct json_object *v;
	return json_object_object_get_ex(o, key, &v) && json_object_is_type(v, json_type_string)
		       ? json_object_get_string(v)
		       : NULL;
}

/* An integer-valued JSON number in [0, max], or -1. */
static int64_t uint_of(struct json_object *v, int64_t max)
{
	if (json_object_is_type(v, json_type_int)) {
		int64_t n = json_object_get_int64(v);
		return n >= 0 && n <= max ? n : -1;
	}
	if (json_object_is_type(v, json_type_double)) {
		double d = json_object_get_double(v);
		return d >= 0 && d <= (double)max && d == floor(d) ? (int64_t)d : -1;
	}
	return -1;
}

static struct json_object *array_of(struct json_object *o, const char *key)
{
	struct json_object *v;
	return json_object_object_get_ex(o, key, &v) && json_object_is_type(v, json_type_array) ? v
												  : NULL;
}

static void on_subscribe(struct fox_sink *s, struct fox_client *c, struct json_object *j)
{
	struct json_object *subs = array_of(j, "subscriptions");
	if (!subs)
		return send_status(s, c, 2, "subscribe: expected \"subscriptions\": [{id, channelId}]",
				   NULL);
	for (size_t k = 0; k < json_object_array_length(subs); k++) {
		struct json_object *e = json_object_array_get_idx(subs, k), *id, *ch;
		int64_t sid = -1, cid = -1;
		if (json_object_is_type(e, json_type_object) &&
		    json_object_object_get_ex(e, "id", &id) && json_object_object_get_ex(e, "channelId", &ch)) {
			sid = uint_of(id, UINT32_MAX);
			cid = uint_of(ch, CH_COUNT);
		}
		if (sid < 0 || cid < 1) {
			send_status(s, c, 2, "subscribe: each subscription needs an id (0..2^32-1) and "
					     "the channelId of an advertised channel", NULL);
			continue;
		}
		const int chn = (int)cid - 1;
		int clash = c->subscribed[chn];
		for (int i = 0; i < CH_COUNT; i++)
			clash |= c->subscribed[i] && c->sub_id[i] == (uint32_t)sid;
		if (clash) {
			send_status(s, c, 2, "subscribe: that channel or subscription id is already "
					     "subscribed", NULL);
			continue;
		}
		pthread_mutex_lock(&s->lock);
		c->subscribed[chn] = 1;
		c->sub_id[chn] = (uint32_t)sid;
		s->subscribers[chn]++;
		fox_update_wanted(s);
		pthread_mutex_unlock(&s->lock);
	}
}

/* Drops channel ch's subscription and its queued frames (s->lock held). */
static void drop_subscription(struct fox_sink *s, struct fox_client *c, int ch)
{
	if (!c->subscribed[ch])
		return;
	c->subscribed[ch] = 0;
	s->subscribers[ch]--;
	for (unsigned k = 0; k < c->q_n[ch]; k++)
		fox_msg_unref(s, c->q[ch][k]);
	c->q_n[ch] = 0;
}

static void on_unsubscribe(struct fox_sink *s, struct fox_client *c, struct json_object *j)
{
	struct json_object *ids = array_of(j, "subscriptionIds");
	if (!ids)
		return send_status(s, c, 2, "unsubscribe: expected \"subscriptionIds\": [...]", NULL);
	pthread_mutex_lock(&s->lock);
	for (size_t k = 0; k < json_object_array_length(ids); k++) {
		int64_t sid = uint_of(json_object_array_get_idx(ids, k), UINT32_MAX);
		for (int ch = 0; ch < CH_COUNT; ch++)
			if (sid >= 0 && c->subscribed[ch] && c->sub_id[ch] == (uint32_t)sid)
				drop_subscription(s, c, ch);
	}
	fox_update_wanted(s);
	pthread_mutex_unlock(&s->lock);
}

/* parameterNames: the flags of the names given (all when empty); -1 if one is unknown */
static int names_of(struct fox_sink *s, struct fox_client *c, struct json_object *j,
		    unsigned char *which, const char *what)
{
	struct json_object *names = array_of(j, "parameterNames");
	size_t n = names ? json_object_array_length(names) : 0;
	memset(which, n ? 0 : 1, MAX_PARAMS);
	for (size_t k = 0; k < n; k++) {
		struct json_object *e = json_object_array_get_idx(names, k);
		int i = json_object_is_type(e, json_type_string) ? param_index(json_object_get_string(e))
								  : -1;
		if (i < 0) {
			char msg[200], name[80] = "";
			if (json_object_is_type(e, json_type_string))
				clip_utf8(name, sizeof name, json_object_get_string(e));
			snprintf(msg, sizeof msg, "%s: no AO parameter '%s'", what, name);
			send_status(s, c, 2, msg, string_of(j, "id"));
			return -1;
		}
		which[i] = 1;
	}
	return 0;
}

static void on_set_parameters(struct fox_sink *s, struct fox_client *c, struct json_object *j)
{
	const char *id = string_of(j, "id");
	struct json_object *list = array_of(j, "parameters");
	if (!c->control) {
		send_status(s, c, 2,
			    "setParameters refused: the parameters are read-only (start the sink with "
			    "?control=true, or give it ?token=SECRET and connect with "
			    "ws://HOST:PORT/?token=SECRET)",
			    id);
		if (id)
			send_values(s, c, NULL, id);
		return;
	}
	const char *names[MAX_PARAMS], *values[MAX_PARAMS];
	char text[MAX_PARAMS][32];
	unsigned char which[MAX_PARAMS] = {0};
	size_t n = list ? json_object_array_length(list) : 0;
	char msg[512] = "";
	if (!list)
		snprintf(msg, sizeof msg, "setParameters: expected \"parameters\": [{name, value}]");
	if (n > MAX_PARAMS)
		snprintf(msg, sizeof msg, "setParameters: too many parameters (%d at most)", MAX_PARAMS);
	for (size_t k = 0; !msg[0] && k < n; k++) {
		struct json_object *e = json_object_array_get_idx(list, k), *v = NULL;
		const char *name = json_object_is_type(e, json_type_object) ? string_of(e, "name") : NULL;
		int i = name ? param_index(name) : -1;
		if (i < 0) {
			char nm[80] = "";
			if (name)
				clip_utf8(nm, sizeof nm, name);
			snprintf(msg, sizeof msg, "setParameters: no AO parameter '%s'", nm);
			break;
		}
		json_object_object_get_ex(e, "value", &v);
		if (json_object_is_type(v, json_type_string)) {
			values[k] = json_object_get_string(v);
		} else if (json_object_is_type(v, json_type_int) ||
			   json_object_is_type(v, json_type_double)) {
			double d = json_object_get_double(v);
			snprintf(text[k], sizeof text[k], "%.17g", d);
			values[k] = text[k];
		} else {
			snprintf(msg, sizeof msg, "setParameters: %s: the value must be a number or a "
						  "string", name);
			break;
		}
		names[k] = name;
		which[i] = 1;
	}
	const struct dao_sink_host *h = host_of(s);
	if (!msg[0] && (!h || !h->set_params))
		snprintf(msg, sizeof msg, "setParameters: this host does not take parameter changes");
	if (!msg[0] && h->set_params(h->user, names, values, n, msg, sizeof msg) < 0 && !msg[0])
		snprintf(msg, sizeof msg, "setParameters: the changes were refused");
	if (msg[0]) {
		char clipped[400];
		clip_utf8(clipped, sizeof clipped, msg);
		send_status(s, c, 2, clipped, id);
	}
	if (id && msg[0]) {
		send_values(s, c, NULL, id); /* nothing changed: the values as they are */
	} else if (id) {
		/* the values as set (the pipeline takes them with its next frame) */
		struct json_object *vals = json_object_new_array();
		for (size_t k = 0; k < n; k++)
			json_object_array_add(vals, param_json((size_t)param_index(names[k]), values[k]));
		struct json_object *r = json_object_new_object();
		json_object_object_add(r, "op", json_object_new_string("parameterValues"));
		json_object_object_add(r, "parameters", vals);
		json_object_object_add(r, "id", json_object_new_string(id));
		send_json(s, c, r);
	}
	(void)which;
}

static void handle_text(struct fox_sink *s, struct fox_client *c, const char *text, size_t len)
{
	char why[160];
	char what[128];
	if (json_strict_check(text, len, FOX_JSON_MAX_DEPTH, what, sizeof what) < 0) {
		snprintf(why, sizeof why, "not strict JSON: %s", what);
		return send_status(s, c, 2, why, NULL);
	}
	struct json_tokener *tk = json_tokener_new_ex(FOX_JSON_MAX_DEPTH + 2);
	struct json_object *j = tk ? json_tokener_parse_ex(tk, text, (int)len) : NULL;
	json_tokener_free(tk);
	const char *op = j && json_object_is_type(j, json_type_object) ? string_of(j, "op") : NULL;
	if (!op)
		send_status(s, c, 2, "expected a JSON object with an \"op\"", NULL);
	else if (!strcmp(op, "subscribe"))
		on_subscribe(s, c, j);
	else if (!strcmp(op, "unsubscribe"))
		on_unsubscribe(s, c, j);
	else if (!strcmp(op, "getParameters")) {
		unsigned char which[MAX_PARAMS];
		if (names_of(s, c, j, which, "getParameters") == 0)
			send_values(s, c, which, string_of(j, "id"));
	} else if (!strcmp(op, "setParameters"))
		on_set_parameters(s, c, j);
	else if (!strcmp(op, "subscribeParameterUpdates") ||
		 !strcmp(op, "unsubscribeParameterUpdates")) {
		unsigned char which[MAX_PARAMS];
		const int on = op[0] == 's';
		if (names_of(s, c, j, which, op) == 0) {
			for (size_t i = 0; i < MAX_PARAMS; i++)
				if (which[i])
					c->param_sub[i] = (unsigned char)on;
			if (on && !s->srv->have_last)
				poll_params(s->srv);
		}
	} else {
		char msg[120], o[48];
		clip_utf8(o, sizeof o, op);
		snprintf(msg, sizeof msg, "unsupported op '%s'", o);
		send_status(s, c, 2, msg, NULL);
	}
	json_object_put(j);
}

/* The client's allowance of messages (a token bucket); 0 when over it. */
static int within_rate(struct fox_sink *s, struct fox_client *c)
{
	const uint64_t now = fox_now_ns();
	c->tokens += (double)(now - c->tokens_at) / 1e9 * FOX_RATE_PER_S;
	if (c->tokens > FOX_RATE_BURST)
		c->tokens = FOX_RATE_BURST;
	c->tokens_at = now;
	if (c->tokens >= 1.0) {
		c->tokens -= 1.0;
		return 1;
	}
	if (now - c->limit_noted_at >= 1000000000ull) {
		c->limit_noted_at = now;
		send_status(s, c, 1, "too many requests: messages are dropped (20 a second at most)",
			    NULL);
	}
	return 0;
}

/* ---- connections ---------------------------------------------------------- */

static int same_addr(const struct sockaddr_storage *a, const struct sockaddr_storage *b)
{
	if (a->ss_family != b->ss_family)
		return 0;
	if (a->ss_family == AF_INET)
		return !memcmp(&((const struct sockaddr_in *)a)->sin_addr,
			       &((const struct sockaddr_in *)b)->sin_addr, sizeof(struct in_addr));
	if (a->ss_family == AF_INET6)
		return !memcmp(&((const struct sockaddr_in6 *)a)->sin6_addr,
			       &((const struct sockaddr_in6 *)b)->sin6_addr, sizeof(struct in6_addr));
	return 0;
}

static void pending_remove(struct fox_server *srv, struct lws *wsi)
{
	for (unsigned i = 0; i < srv->npending; i++)
		if (srv->pending[i].wsi == wsi) {
			srv->pending[i] = srv->pending[--srv->npending];
			return;
		}
}

/*
 * Room for a newcomer when every handshake slot is taken: the oldest connection of
 * the address holding the most slots is cut.  Connections that trickle their upgrade
 * request (slowloris) thus never lock a newcomer out, even before their deadline;
 * and a client that owns one slot is cut last, however many addresses an attacker
 * uses (each holds at most FOX_PENDING_PER_ADDR).
 */
static void pending_evict(struct fox_server *srv)
{
	unsigned victim = 0, most = 0;
	for (unsigned i = 0; i < srv->npending; i++) {
		unsigned n = 0;
		for (unsigned k = 0; k < srv->npending; k++)
			n += same_addr(&srv->pending[i].addr, &srv->pending[k].addr);
		if (n > most || (n == most && srv->pending[i].deadline < srv->pending[victim].deadline)) {
			most = n;
			victim = i;
		}
	}
	if (!srv->npending)
		return;
	lws_set_timeout(srv->pending[victim].wsi, PENDING_TIMEOUT_HOLDING_AH, LWS_TO_KILL_ASYNC);
	srv->pending[victim] = srv->pending[--srv->npending];
}

/* Same-time comparison of a secret. */
static int same_secret(const char *a, const char *b)
{
	size_t la = strlen(a), lb = strlen(b);
	unsigned char d = la != lb;
	for (size_t i = 0; i < la; i++)
		d |= (unsigned char)(a[i] ^ b[i % (lb ? lb : 1)]);
	return d == 0;
}

/* The handshake: the subprotocol, a free slot, and ?token= for control. */
static int filter_handshake(struct fox_sink *s, struct lws *wsi, struct pss *pss)
{
	char proto[256] = "";
	if (lws_hdr_total_length(wsi, WSI_TOKEN_PROTOCOL) >= (int)sizeof proto ||
	    lws_hdr_copy(wsi, proto, sizeof proto, WSI_TOKEN_PROTOCOL) < 0)
		return -1;
	int found = 0;
	for (char *save = NULL, *t = strtok_r(proto, ", ", &save); t; t = strtok_r(NULL, ", ", &save))
		found |= !strcmp(t, SUBPROTOCOL);
	if (!found)
		return -1;
	pthread_mutex_lock(&s->lock);
	const int full = s->nclients >= s->max_clients;
	if (full)
		s->refused++;
	pthread_mutex_unlock(&s->lock);
	if (full)
		return -1;
	char tok[160];
	pss->control = s->control;
	/* the query's arguments, one fragment each ("token=SECRET") */
	for (int i = 0; !pss->control && s->token[0]; i++) {
		if (lws_hdr_copy_fragment(wsi, tok, sizeof tok, WSI_TOKEN_HTTP_URI_ARGS, i) < 0)
			break;
		if (!strncmp(tok, "token=", 6))
			pss->control = same_secret(tok + 6, s->token);
	}
	return 0;
}

static void greet(struct fox_sink *s, struct fox_client *c)
{
	struct json_object *j = json_object_new_object();
	struct json_object *caps = json_object_new_array();
	json_object_array_add(caps, json_object_new_string("parameters"));
	json_object_array_add(caps, json_object_new_string("parametersSubscribe"));
	json_object_object_add(j, "op", json_object_new_string("serverInfo"));
	json_object_object_add(j, "name", json_object_new_string("depthao"));
	json_object_object_add(j, "capabilities", caps);
	struct json_object *meta = json_object_new_object();
	json_object_object_add(meta, "control", json_object_new_string(c->control ? "true" : "false"));
	json_object_object_add(j, "metadata", meta);
	send_json(s, c, j);
	send_json(s, c, json_tokener_parse(s->srv->advertise));
	if (!c->control)
		send_status(s, c, 0,
			    "the AO parameters are read-only on this connection (connect with "
			    "?token=SECRET, or start the sink with ?control=true)",
			    NULL);
}

static int established(struct fox_sink *s, struct lws *wsi, struct pss *pss)
{
	pending_remove(s->srv, wsi);
	struct fox_client *c = calloc(1, sizeof(*c));
	if (!c)
		return -1;
	c->wsi = wsi;
	c->control = pss->control;
	c->tokens = FOX_RATE_BURST;
	c->tokens_at = fox_now_ns();
	pss->c = c;
	pthread_mutex_lock(&s->lock);
	c->next = s->clients;
	s->clients = c;
	s->nclients++;
	s->clients_served++;
	pthread_mutex_unlock(&s->lock);
	greet(s, c);
	return 0;
}

static void closed(struct fox_sink *s, struct pss *pss)
{
	struct fox_client *c = pss->c;
	if (!c)
		return;
	pss->c = NULL;
	pthread_mutex_lock(&s->lock);
	for (struct fox_client **pp = &s->clients; *pp; pp = &(*pp)->next)
		if (*pp == c) {
			*pp = c->next;
			break;
		}
	s->nclients--;
	for (int ch = 0; ch < CH_COUNT; ch++)
		drop_subscription(s, c, ch);
	for (unsigned k = 0; k < c->ctl_n; k++)
		fox_msg_unref(s, c->ctl[(c->ctl_head + k) % FOX_CTL_MAX]);
	if (c->cur)
		fox_msg_unref(s, c->cur);
	fox_update_wanted(s);
	pthread_mutex_unlock(&s->lock);
	free(c);
}

static uint32_t us_between(uint64_t from, uint64_t to)
{
	const uint64_t us = to > from ? (to - from) / 1000u : 0;
	return us > UINT32_MAX ? UINT32_MAX : (uint32_t)us;
}

/* capture -> socket, and where it went: arrival in the sink -> socket, of which the
 * message's building (docs/perf/foxlat.md) */
static void record_latency(struct fox_sink *s, uint64_t capture_ns, uint64_t entered_ns,
			   uint64_t published_ns)
{
	const uint64_t now = fox_now_ns();
	s->lat_us[s->lat_pos] = us_between(capture_ns, now);
	s->lat_sink_us[s->lat_pos] = us_between(entered_ns, now);
	s->lat_build_us[s->lat_pos] = us_between(entered_ns, published_ns);
	s->lat_pos = (s->lat_pos + 1) % FOX_LATENCY_RING;
	if (s->lat_n < FOX_LATENCY_RING)
		s->lat_n++;
}

static int older_or_smaller(const struct fox_msg *a, const struct fox_msg *b)
{
	return a->capture_ns < b->capture_ns || (a->capture_ns == b->capture_ns && a->len < b->len);
}

/* The next message for c (s->lock held): a reply first, else the oldest frame of any
 * channel; of one frame's messages the smallest first, else a slow client always starts
 * with the 614 KB AO and drops the shaded JPEG waiting behind it (docs/perf/foxlat.md). */
static struct fox_msg *next_msg(struct fox_client *c, int *chp)
{
	struct fox_msg *m = NULL;
	int ch = -1;
	if (c->ctl_n) {
		m = c->ctl[c->ctl_head];
		c->ctl_head = (c->ctl_head + 1) % FOX_CTL_MAX;
		c->ctl_n--;
	} else {
		for (int k = 0; k < CH_COUNT; k++)
			if (c->q_n[k] && (ch < 0 || older_or_smaller(c->q[k][0], c->q[ch][0])))
				ch = k;
		if (ch >= 0) {
			m = c->q[ch][0];
			memmove(c->q[ch], c->q[ch] + 1, (c->q_n[ch] - 1) * sizeof c->q[ch][0]);
			c->q_n[ch]--;
		}
	}
	*chp = ch;
	return m;
}

/* The next fragment of c->cur, at most FOX_PIECE bytes: a large message goes out as the
 * socket takes it, instead of lws copying what the kernel did not take into a buffer of
 * its own (a 614 KB copy per client and frame when a client reads slowly). lws puts
 * the fragment's header in the LWS_PRE bytes before it: message data that other clients
 * still send, kept and put back (only this thread touches a message being sent). */
static int write_piece(struct fox_client *c)
{
	struct fox_msg *m = c->cur;
	const size_t off = c->cur_off, left = m->len - off;
	const size_t n = left > FOX_PIECE ? FOX_PIECE : left;
	int flags = off ? LWS_WRITE_CONTINUATION : m->text ? LWS_WRITE_TEXT : LWS_WRITE_BINARY;
	if (n < left)
		flags |= LWS_WRITE_NO_FIN;
	unsigned char *p = m->buf + LWS_PRE + off;
	unsigned char keep[LWS_PRE];
	if (off)
		memcpy(keep, p - LWS_PRE, LWS_PRE);
	const int r = lws_write(c->wsi, p, n, (enum lws_write_protocol)flags);
	if (off)
		memcpy(p - LWS_PRE, keep, LWS_PRE);
	c->cur_off += n;
	return r;
}

/* One fragment of one message to the client. */
static int writeable(struct fox_sink *s, struct fox_client *c)
{
	pthread_mutex_lock(&s->lock);
	if (c->inflight) { /* lws has sent the rest of the last one */
		c->inflight = 0;
		record_latency(s, c->inflight_cap, c->inflight_entered, c->inflight_published);
	}
	if (c->overflow) {
		pthread_mutex_unlock(&s->lock);
		lws_close_reason(c->wsi, LWS_CLOSE_STATUS_POLICY_VIOLATION,
				 (unsigned char *)"replies not read", 16);
		return -1;
	}
	if (!c->cur) {
		c->cur = next_msg(c, &c->cur_ch);
		c->cur_off = 0;
	}
	struct fox_msg *m = c->cur;
	const int ch = c->cur_ch;
	pthread_mutex_unlock(&s->lock);
	if (!m)
		return 0;
	if (!m->text && !c->cur_off) { /* the subscription id is the client's own */
		for (int i = 0; i < 4; i++)
			m->buf[LWS_PRE + 1 + i] = (unsigned char)(c->sub_id[ch] >> (8 * i));
	}
	const int n = write_piece(c);
	const int done = c->cur_off >= m->len;
	pthread_mutex_lock(&s->lock);
	if (n >= 0 && done && !m->text) {
		s->sent++;
		s->bytes_sent[ch] += m->len;
		if (lws_partial_buffered(c->wsi)) {
			c->inflight = 1;
			c->inflight_cap = m->capture_ns;
			c->inflight_entered = m->entered_ns;
			c->inflight_published = m->published_ns;
		} else {
			record_latency(s, m->capture_ns, m->entered_ns, m->published_ns);
		}
	}
	if (done || n < 0) {
		fox_msg_unref(s, m);
		c->cur = NULL;
	}
	const int more = c->cur || queued(c) || c->inflight;
	pthread_mutex_unlock(&s->lock);
	if (n < 0)
		return -1;
	if (more)
		lws_callback_on_writable(c->wsi);
	return 0;
}

static int receive(struct fox_sink *s, struct lws *wsi, struct fox_client *c, const void *in,
		   size_t len)
{
	if (c->in_len + len > FOX_MAX_IN)
		c->in_too_big = 1;
	else
		memcpy(c->in + c->in_len, in, len);
	c->in_len += len;
	if (!lws_is_final_fragment(wsi) || lws_remaining_packet_payload(wsi))
		return 0;
	const size_t n = c->in_len;
	const int binary = lws_frame_is_binary(wsi);
	c->in_len = 0;
	if (c->in_too_big) {
		lws_close_reason(wsi, LWS_CLOSE_STATUS_MESSAGE_TOO_LARGE,
				 (unsigned char *)"message too large", 17);
		return -1;
	}
	if (!within_rate(s, c))
		return 0;
	if (binary) {
		send_status(s, c, 2, "binary client messages are not supported (no clientPublish or "
				     "services)", NULL);
		return 0;
	}
	handle_text(s, c, (const char *)c->in, n);
	return 0;
}

static void tick(lws_sorted_usec_list_t *sul)
{
	struct fox_server *srv = lws_container_of(sul, struct fox_server, tick);
	const uint64_t now = fox_now_ns();
	for (unsigned i = 0; i < srv->npending; i++)
		if (now >= srv->pending[i].deadline) /* killed on the next service pass */
			lws_set_timeout(srv->pending[i].wsi, PENDING_TIMEOUT_HOLDING_AH,
					LWS_TO_KILL_ASYNC);
	int subs = 0;
	for (struct fox_client *c = srv->s->clients; c && !subs; c = c->next)
		for (size_t i = 0; i < MAX_PARAMS && !subs; i++)
			subs = c->param_sub[i];
	if (subs && now - srv->polled_at >= PARAM_POLL_NS)
		poll_params(srv);
	lws_sul_schedule(srv->s->ctx, 0, &srv->tick, tick, TICK_US);
}

static int callback(struct lws *wsi, enum lws_callback_reasons reason, void *user, void *in,
		    size_t len)
{
	struct lws_context *ctx = lws_get_context(wsi);
	struct fox_sink *s = ctx ? lws_context_user(ctx) : NULL;
	struct pss *pss = user;
	if (!s)
		return 0;
	struct fox_server *srv = s->srv;
	switch (reason) {
	case LWS_CALLBACK_FILTER_NETWORK_CONNECTION: {
		const struct lws_filter_network_conn_args *a = user;
		unsigned same = 0;
		for (unsigned i = 0; a && i < srv->npending; i++)
			same += same_addr(&srv->pending[i].addr, &a->cli_addr);
		if (!atomic_load(&s->stopping) && same < FOX_PENDING_PER_ADDR &&
		    srv->npending >= FOX_PENDING_MAX)
			pending_evict(srv);
		if (atomic_load(&s->stopping) || srv->npending >= FOX_PENDING_MAX ||
		    same >= FOX_PENDING_PER_ADDR) {
			pthread_mutex_lock(&s->lock);
			s->refused++;
			pthread_mutex_unlock(&s->lock);
			return -1;
		}
		return 0;
	}
	case LWS_CALLBACK_SERVER_NEW_CLIENT_INSTANTIATED:
		if (srv->npending < FOX_PENDING_MAX) {
			struct pending *p = &srv->pending[srv->npending++];
			memset(p, 0, sizeof *p);
			p->wsi = wsi;
			p->deadline = fox_now_ns() + FOX_HANDSHAKE_MS * 1000000ull;
			p->alen = sizeof p->addr;
			getpeername(lws_get_socket_fd(wsi), (struct sockaddr *)&p->addr, &p->alen);
		}
		return 0;
	case LWS_CALLBACK_WSI_DESTROY:
		pending_remove(srv, wsi);
		return 0;
	case LWS_CALLBACK_FILTER_PROTOCOL_CONNECTION:
		return filter_handshake(s, wsi, pss);
	case LWS_CALLBACK_ESTABLISHED:
		return established(s, wsi, pss);
	case LWS_CALLBACK_CLOSED:
		closed(s, pss);
		return 0;
	case LWS_CALLBACK_RECEIVE:
		return pss && pss->c ? receive(s, wsi, pss->c, in, len) : -1;
	case LWS_CALLBACK_SERVER_WRITEABLE:
		return pss && pss->c ? writeable(s, pss->c) : 0;
	case LWS_CALLBACK_EVENT_WAIT_CANCELLED:
		pthread_mutex_lock(&s->lock);
		for (struct fox_client *c = s->clients; c; c = c->next)
			if (queued(c) && !c->inflight)
				lws_callback_on_writable(c->wsi);
		pthread_mutex_unlock(&s->lock);
		return 0;
	case LWS_CALLBACK_HTTP: /* a plain HTTP request: this port speaks WebSocket only */
		lws_return_http_status(wsi, HTTP_STATUS_NOT_FOUND,
				       "a Foxglove WebSocket server: open ws://HOST:PORT in Foxglove");
		return -1;
	default:
		return 0;
	}
}

static const struct lws_protocols protocols[] = {
	{SUBPROTOCOL, callback, sizeof(struct pss), FOX_MAX_IN, 0, NULL, 0},
	{NULL, NULL, 0, 0, 0, NULL, 0},
};

static void *service(void *arg)
{
	struct fox_sink *s = arg;
	prctl(PR_SET_NAME, "fox:lws", 0, 0, 0); /* its CPU, per thread: docs/perf/foxlat.md */
	while (!atomic_load(&s->stopping))
		if (lws_service(s->ctx, 0) < 0)
			break;
	return NULL;
}

void fox_latency(struct fox_sink *s, double *median, double *p99, unsigned *n)
{
	*n = s->lat_n;
	fox_ring_stats(s->lat_us, *n, median, p99);
}

void fox_ring_stats(const uint32_t *ring, unsigned n, double *median, double *p99)
{
	uint32_t sorted[FOX_LATENCY_RING];
	memcpy(sorted, ring, n * sizeof sorted[0]);
	/* insertion sort: at most FOX_LATENCY_RING values, once at the end */
	for (unsigned i = 1; i < n; i++) {
		uint32_t v = sorted[i];
		unsigned k = i;
		for (; k && sorted[k - 1] > v; k--)
			sorted[k] = sorted[k - 1];
		sorted[k] = v;
	}
	*median = n ? sorted[n / 2] / 1000.0 : 0;
	*p99 = n ? sorted[((size_t)n * 99 + 99) / 100 - 1] / 1000.0 : 0;
}

static char *advertise_text(void)
{
	struct json_object *list = json_object_new_array();
	for (int ch = 0; ch < CH_COUNT; ch++) {
		struct json_object *o = json_object_new_object();
		json_object_object_add(o, "id", json_object_new_int(ch + 1));
		json_object_object_add(o, "topic", json_object_new_string(topics[ch]));
		json_object_object_add(o, "encoding", json_object_new_string("protobuf"));
		json_object_object_add(o, "schemaName", json_object_new_string(schema_names[ch]));
		json_object_object_add(o, "schema", json_object_new_string(foxglove_schemas_b64));
		json_object_object_add(o, "schemaEncoding", json_object_new_string("protobuf"));
		json_object_array_add(list, o);
	}
	struct json_object *j = json_object_new_object();
	json_object_object_add(j, "op", json_object_new_string("advertise"));
	json_object_object_add(j, "channels", list);
	char *t = strdup(json_object_to_json_string_ext(j, JSON_C_TO_STRING_PLAIN |
							       JSON_C_TO_STRING_NOSLASHESCAPE));
	json_object_put(j);
	return t;
}

int fox_server_start(struct fox_sink *s, struct dao_error *err)
{
	struct fox_server *srv = calloc(1, sizeof(*srv));
	if (!srv || !(srv->advertise = advertise_text())) {
		free(srv);
		return dao_error_set(err, -ENOMEM, "out of memory");
	}
	srv->s = s;
	s->srv = srv;
	lws_set_log_level(0, NULL); /* its messages would flood the log; errors come as ours */
	struct lws_context_creation_info info;
	memset(&info, 0, sizeof info);
	info.port = s->port;
	info.iface = s->bind_host;
	info.protocols = protocols;
	info.user = s;
	info.gid = -1;
	info.uid = -1;
	info.options = LWS_SERVER_OPTION_FAIL_UPON_UNABLE_TO_BIND |
		       LWS_SERVER_OPTION_DISABLE_OS_CA_CERTS;
	if (!strchr(s->bind_host, ':'))
		info.options |= LWS_SERVER_OPTION_DISABLE_IPV6;
	info.timeout_secs = FOX_HANDSHAKE_MS / 1000;
	info.timeout_secs_ah_idle = FOX_HANDSHAKE_MS / 1000;
	info.fd_limit_per_thread = 1 + FOX_PENDING_MAX + s->max_clients + 16;
	s->ctx = lws_create_context(&info);
	if (!s->ctx) {
		free(srv->advertise);
		free(srv);
		s->srv = NULL;
		return dao_error_set(err, -EADDRINUSE,
				    "foxglove: cannot listen on %s:%d (the port is taken or the address "
				    "is not this machine's: pick another)",
				    s->bind_host, s->port);
	}
	struct lws_vhost *vh = lws_get_vhost_by_name(s->ctx, "default");
	if (vh && s->port == 0)
		s->port = lws_get_vhost_listen_port(vh);
	lws_sul_schedule(s->ctx, 0, &srv->tick, tick, TICK_US);
	if (pthread_create(&s->thread, NULL, service, s) != 0) {
		lws_context_destroy(s->ctx);
		s->ctx = NULL;
		free(srv->advertise);
		free(srv);
		s->srv = NULL;
		return dao_error_set(err, -EAGAIN, "foxglove: cannot start the server thread");
	}
	s->thread_started = 1;
	return 0;
}

void fox_server_stop(struct fox_sink *s)
{
	if (!s->ctx)
		return;
	atomic_store(&s->stopping, 1);
	lws_cancel_service(s->ctx);
	if (s->thread_started)
		pthread_join(s->thread, NULL);
	lws_context_destroy(s->ctx); /* closes every connection; CLOSED frees the clients */
	s->ctx = NULL;
	free(s->srv->advertise);
	free(s->srv);
	s->srv = NULL;
}
