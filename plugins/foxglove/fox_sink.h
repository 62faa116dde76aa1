/* SPDX-License-Identifier: MIT */
/*
 * What the files of the foxglove sink share: the sink's state and its
 * messages (fox_sink.c: the frames made into Foxglove messages), the
 * WebSocket server (fox_server.c: libwebsockets, the protocol, the clients).
 *
 * Threads: the host's sink thread calls write_stream, builds each message once
 * and only queues references to it (fox_publish); one service thread owns every
 * socket and writes.  s->lock guards the client list, the queues, the message
 * pools and the counters; no socket call is made under it.
 */
#ifndef DAO_FOX_SINK_H
#define DAO_FOX_SINK_H

#include <pthread.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>

#include <depthao/plugin.h>

enum fox_channel { CH_AO = 0, CH_SHADED, CH_CALIB, CH_CLOUD, CH_TF, CH_COUNT };

#define FOX_DEFAULT_CLIENTS 16     /* ?max-clients= (1..256) */
#define FOX_DEFAULT_QUEUE 2        /* data messages queued per client (?queue= 1..16) */
#define FOX_QUEUE_MAX 16
#define FOX_CTL_MAX 32             /* JSON replies queued per client; more: it is closed */
#define FOX_MAX_IN 16384           /* bytes of one client message (1009 above) */
#define FOX_PENDING_MAX 16         /* connections not yet upgraded, all addresses */
#define FOX_PENDING_PER_ADDR 8     /* ... from one address */
#define FOX_HANDSHAKE_MS 3000      /* accept -> WebSocket established, a total deadline */
#define FOX_RATE_PER_S 20.0        /* client messages per second, sustained */
#define FOX_RATE_BURST 40.0        /* ... in a burst */
#define FOX_LATENCY_RING 1024
#define FOX_JSON_MAX_DEPTH 16      /* nested objects and arrays in a client message */
#define FOX_HEADER 13              /* Message Data: opcode, subscription id, timestamp */

/* One message, built once and shared by the clients' queues (refs under s->lock). */
struct fox_msg {
	struct fox_msg *next;      /* in a pool while unused */
	unsigned refs;
	int text;                  /* 1: a JSON text message; 0: Message Data */
	int channel;               /* enum fox_channel of Message Data */
	uint64_t capture_ns;       /* CLOCK_MONOTONIC of the frame's capture */
	uint64_t entered_ns;       /* ... of the frame's arrival in the sink */
	uint64_t published_ns;     /* ... of the message's queueing to the clients */
	size_t len;                /* bytes from LWS_PRE on (header and payload) */
	size_t cap;
	unsigned char *buf;        /* LWS_PRE + cap bytes */
};

struct fox_client;
struct fox_server;

struct fox_sink {
	/* from the URI */
	char bind_host[64];
	int port;                  /* as bound */
	int control;               /* everyone may set parameters */
	char token[128];           /* ... or clients connecting with ?token= */
	int quality;               /* JPEG 1..100 */
	unsigned max_clients;
	unsigned queue;
	unsigned cloud_step;       /* every n-th pixel in x and y becomes a point */

	const struct dao_sink_host *host;
	void *tj;                  /* tjhandle, the sink thread's */
	struct lws_context *ctx;
	struct fox_server *srv;    /* the service thread's own state */
	pthread_t thread;
	int thread_started;
	atomic_int stopping;

	uint64_t wall_offset_ns;    /* CLOCK_REALTIME - CLOCK_MONOTONIC at open */
	/* the camera, from negotiate */
	int has_camera;
	uint32_t width, height;
	double fx, fy, cx, cy;
	/* the point cloud's inputs, matched by frame sequence */
	uint16_t *depth, *ao;
	size_t depth_cap, ao_cap;
	uint64_t depth_seq, ao_seq, cloud_seq;
	int have_depth, have_ao;
	float depth_unit;
	unsigned char *jpeg;       /* the JPEG scratch buffer */
	unsigned long jpeg_cap;

	pthread_mutex_t lock;
	struct fox_client *clients;
	unsigned nclients;
	unsigned subscribers[CH_COUNT];
	unsigned wanted_mask;      /* last mask given to want_streams */
	struct fox_msg *pool[CH_COUNT];
	unsigned long long sent, dropped, clients_served, refused;
	uint64_t bytes_sent[CH_COUNT], msgs_built[CH_COUNT];
	uint32_t lat_us[FOX_LATENCY_RING]; /* capture -> the message's last byte to the kernel */
	uint32_t lat_sink_us[FOX_LATENCY_RING]; /* arrival in the sink -> ... */
	uint32_t lat_build_us[FOX_LATENCY_RING]; /* arrival -> queued (encoding, once) */
	unsigned lat_n, lat_pos;
	uint64_t entered_ns;       /* the frame being written arrived (the sink's thread) */
};

uint64_t fox_now_ns(void);
/* The message pool: a message of channel ch with room for `need` bytes (refs 0). */
struct fox_msg *fox_msg_get(struct fox_sink *s, int ch, size_t need);
/* Drops one reference (s->lock held); the last puts it back in its pool. */
void fox_msg_unref(struct fox_sink *s, struct fox_msg *m);
/* Queues m for every client subscribed to its channel (takes s->lock; wakes the server). */
void fox_publish(struct fox_sink *s, struct fox_msg *m);
/* Tells the host which streams the subscriptions need (s->lock held). */
void fox_update_wanted(struct fox_sink *s);

/* fox_server.c */
int fox_server_start(struct fox_sink *s, struct dao_error *err);
void fox_server_stop(struct fox_sink *s);
/* The median and 99th percentile latency in ms, and the count (s->lock held). */
void fox_latency(struct fox_sink *s, double *median, double *p99, unsigned *n);
/* The median and p99 in ms of the first n values of one of the rings (s->lock held). */
void fox_ring_stats(const uint32_t *ring, unsigned n, double *median, double *p99);

#endif
