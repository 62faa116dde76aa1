/* SPDX-License-Identifier: MIT */
/*
 * What the files of the http sink share: the sink's state (http_sink.c), its
 * routes (http_routes.c), the per-client MJPEG queues (mjpeg_client.c).
 */
#ifndef DAO_HTTP_SINK_H
#define DAO_HTTP_SINK_H

#include <pthread.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/types.h>

#include <depthao/plugin.h>

struct MHD_Connection;

/* The pictures the viewer offers: what ?stream= names. */
enum view_stream { VIEW_SHADED = 0, VIEW_AO, VIEW_OVERLAY, VIEW_DEPTH, VIEW_COUNT };

#define HTTP_LATENCY_RING 512
#define HTTP_MAX_BODY 8192          /* bytes of a POST body (413 above) */
#define HTTP_MAX_HEADERS 48         /* header lines of a request (431 above) */
#define HTTP_MEMORY_LIMIT 16384     /* per connection, the request line and headers included */
#define HTTP_DEFAULT_CLIENTS 32     /* concurrent connections (?max_clients=) */
#define HTTP_TOKEN_HEADER "X-Depthao-Token"
#define HTTP_DEFAULT_DEADLINE_MS 5000 /* a request's line, headers and body (?request_timeout=) */
#define HTTP_DEFAULT_PER_IP 16      /* connections from one address (?per_ip=) */
/* /snapshot.png: requests a second (and burst) per client address and for everyone;
   beyond them 429 with Retry-After */
#define HTTP_SNAPSHOT_RATE_CLIENT 5.0
#define HTTP_SNAPSHOT_BURST_CLIENT 10.0
#define HTTP_SNAPSHOT_RATE_ALL 20.0
#define HTTP_SNAPSHOT_BURST_ALL 40.0
/* a snapshot's PNG is encoded at most once a frame and this often (ms); the
   requests meanwhile share the last one */
#define HTTP_SNAPSHOT_MIN_INTERVAL_MS 200
#define HTTP_RATE_CLIENTS 64        /* client addresses with a bucket (the least recent goes) */

struct mjpeg_client;

/* The latest picture of one stream, and its JPEG (encoded once for every client). */
struct view_picture {
	uint8_t *rgb;                /* RGB24 or GRAY8 pixels, tightly packed */
	size_t rgb_cap;
	int gray;                    /* 1: GRAY8 */
	uint32_t width, height;
	uint64_t sequence;
	int valid;
	unsigned char *jpeg;         /* tjBufSize() bytes, reused */
	unsigned long jpeg_cap;
};

/* A PNG shared by the snapshot replies that send it: freed with the last of them. */
struct png_blob {
	atomic_int refs;
	size_t len;
	unsigned char data[];
};

struct rate_bucket {
	double tokens;
	uint64_t last_ns;            /* 0: unused */
};

struct rate_client {
	unsigned char key[16];       /* the address */
	struct rate_bucket b;
};

struct guard_conn;

struct http_sink {
	/* from the URI */
	char bind_host[64];
	int port;                    /* as bound (the port chosen by the kernel for 0) */
	int control;                 /* POST /api/params allowed to everyone */
	char token[128];             /* or to requests carrying it in HTTP_TOKEN_HEADER */
	int quality;                 /* JPEG 1..100 */
	unsigned max_clients;
	unsigned queue;              /* frames queued per stream client */
	unsigned per_ip;             /* connections from one address (0: no limit) */
	unsigned request_deadline_ms; /* for a request's line, headers and body */
	unsigned max_streams;        /* stream connections: the rest stay for the API */

	const struct dao_sink_host *host;
	struct MHD_Daemon *mhd;
	int listen_fd;
	void *tj;                    /* tjhandle: encodes in the writer thread only */
	enum view_stream primary;    /* the configured stream (negotiated) */
	uint32_t frames_seen;        /* of the configured stream, since open */
	atomic_int has_color;        /* an overlay frame came: the source has colour */
	atomic_int connections;      /* open now (max_clients at most) */

	pthread_mutex_t lock;        /* clients, pictures, the latency ring, counters */
	pthread_cond_t frame_cond;   /* a frame was queued for some client, or stopping */
	struct mjpeg_client *clients;
	unsigned nclients;
	unsigned wanted[VIEW_COUNT]; /* stream clients per stream */
	struct view_picture pic[VIEW_COUNT];
	int stopping;
	unsigned long long frames_sent, frames_dropped, clients_served;
	uint32_t lat_us[HTTP_LATENCY_RING];  /* capture -> the frame's last bytes to the socket */
	uint32_t send_us[HTTP_LATENCY_RING]; /* the sink got it -> its last bytes to the socket */
	unsigned lat_n, lat_pos;
	uint32_t lat_sorted[HTTP_LATENCY_RING]; /* /api/stats' copy */
	pthread_mutex_t stats_lock;  /* one /api/stats reply at a time: stats_text */
	char stats_text[65536];
	uint64_t encode_ns, encoded;

	/* /snapshot.png: the last PNG of each stream (s->lock), one encoder at a time */
	pthread_mutex_t snap_lock;
	struct png_blob *snap[VIEW_COUNT];
	uint64_t snap_seq[VIEW_COUNT], snap_ns[VIEW_COUNT];
	uint8_t *snap_rgb;           /* (snap_lock) the picture being encoded */
	size_t snap_rgb_cap;
	unsigned long long snap_encoded, snap_shared;

	/* http_guard.c (guard_lock): connections, their deadlines, rate limits */
	pthread_mutex_t guard_lock;
	pthread_cond_t guard_cond;
	pthread_t guard_thread;
	int guard_running, guard_quit;
	struct guard_conn *guard_conns;
	unsigned guard_streams;
	unsigned long long deadline_cuts, evicted, rate_limited, streams_refused;
	struct rate_bucket rate_all;
	struct rate_client rate_clients[HTTP_RATE_CLIENTS];
};

const char *view_stream_name(enum view_stream v);
/* "shaded", "ao", "overlay", "depth" -> 0 with *v; -1 for anything else */
int view_stream_parse(const char *name, enum view_stream *v);
/* Tells the host the streams the clients want now (with s->lock held). */
void http_update_wanted(struct http_sink *s);
/* Records one frame's latency and the sink's share of it (with s->lock held). */
void http_record_latency(struct http_sink *s, uint64_t capture_ns, uint64_t written_ns,
			 uint64_t now_ns);
uint64_t http_now_ns(void);

/* POST bodies are checked by json_strict_check (plugins/common/json_strict.h) nested
   at most this deep; json-c parses them with room for as much */
#define HTTP_JSON_MAX_DEPTH 32
/* json_echo.c: copies src into dst as valid UTF-8 (whole characters; a stray byte becomes the
   text \xHH) to be echoed in a JSON reply; returns the length written. */
size_t http_json_safe(char *dst, size_t cap, const char *src);

/* Drops one reference (NULL: nothing). */
void http_png_unref(struct png_blob *b);

/* http_guard.c: the connection slots (see there).  A connection opened (its record,
   the notify callback's socket context) and closed; its request is in (no deadline);
   its request is done (the next one's deadline starts); a stream slot (0: none
   left); the oldest connection still sending its request is cut to make room
   (-1: none). */
void *http_guard_opened(struct http_sink *s, struct MHD_Connection *conn);
int http_guard_closed(struct http_sink *s, void *rec); /* 1: it was released */
/* The connection stops counting against max_clients now (a refused stream, closed
   after its reply). */
void http_guard_release(struct http_sink *s, struct MHD_Connection *conn);
void http_guard_answered(struct http_sink *s, struct MHD_Connection *conn);
void http_guard_request_done(struct http_sink *s, struct MHD_Connection *conn);
int http_guard_stream_slot(struct http_sink *s, struct MHD_Connection *conn);
int http_guard_make_room(struct http_sink *s);
int http_guard_start(struct http_sink *s);
void http_guard_stop(struct http_sink *s);
/* A snapshot token for the client and for everyone: 1, or 0 with the seconds to wait. */
int http_rate_take(struct http_sink *s, struct MHD_Connection *conn, unsigned *retry_after);

/* http_routes.c: starts serving on the listening socket; 0 or < 0 with err */
int http_routes_start(struct http_sink *s, struct dao_error *err);
void http_routes_stop(struct http_sink *s);

/* mjpeg_client.c: a stream client with its own bounded queue (s->lock held for all) */
struct mjpeg_client *mjpeg_client_new(struct http_sink *s, enum view_stream v);
/* Unlinks and frees the client (its connection closed). */
void mjpeg_client_free(struct http_sink *s, struct mjpeg_client *c);
/* Queues one JPEG for every client of stream v; a full queue drops its oldest. */
void mjpeg_clients_push(struct http_sink *s, enum view_stream v, const unsigned char *jpeg,
			size_t len, uint64_t capture_ns, uint64_t written_ns);
/* The next bytes of the client's multipart stream (MHD's content reader; takes s->lock). */
ssize_t mjpeg_client_read(struct http_sink *s, struct mjpeg_client *c, char *buf, size_t max);

#endif
