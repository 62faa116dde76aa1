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

/* The pictures the viewer offers: what ?stream= names. */
enum view_stream { VIEW_SHADED = 0, VIEW_AO, VIEW_OVERLAY, VIEW_DEPTH, VIEW_COUNT };

#define HTTP_LATENCY_RING 512
#define HTTP_MAX_BODY 8192          /* bytes of a POST body (413 above) */
#define HTTP_MAX_HEADERS 48         /* header lines of a request (431 above) */
#define HTTP_MEMORY_LIMIT 16384     /* per connection, the request line and headers included */
#define HTTP_DEFAULT_CLIENTS 32     /* concurrent connections (?max_clients=) */
#define HTTP_TOKEN_HEADER "X-Depthao-Token"

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

struct http_sink {
	/* from the URI */
	char bind_host[64];
	int port;                    /* as bound (the port chosen by the kernel for 0) */
	int control;                 /* POST /api/params allowed to everyone */
	char token[128];             /* or to requests carrying it in HTTP_TOKEN_HEADER */
	int quality;                 /* JPEG 1..100 */
	unsigned max_clients;
	unsigned queue;              /* frames queued per stream client */

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
