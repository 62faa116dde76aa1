/* SPDX-License-Identifier: MIT */
/*
 * One client of /stream.mjpg: its own bounded queue of complete multipart
 * parts.  The writer copies each JPEG into every client's queue; a client
 * whose queue is full loses its oldest part (counted as its drop), so a slow
 * client never holds up the writer or the others.  Buffers grow to the
 * largest part seen and are reused: steady state allocates nothing.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <microhttpd.h>

#include "http_sink.h"

#define BOUNDARY "depthaoframe"
#define MAX_QUEUE 8

struct part {
	char *data;
	size_t len, cap;
	uint64_t capture_ns, written_ns;
};

struct mjpeg_client {
	struct mjpeg_client *next;
	enum view_stream stream;
	struct part q[MAX_QUEUE];    /* ring: head, count */
	unsigned head, count, depth;
	struct part out;             /* the part being sent */
	size_t out_off;
	unsigned long long sent, dropped;
};

struct mjpeg_client *mjpeg_client_new(struct http_sink *s, enum view_stream v)
{
	struct mjpeg_client *c = calloc(1, sizeof(*c));
	if (!c)
		return NULL;
	c->stream = v;
	c->depth = s->queue < 1 ? 1 : s->queue > MAX_QUEUE ? MAX_QUEUE : s->queue;
	c->next = s->clients;
	s->clients = c;
	s->nclients++;
	s->wanted[v]++;
	s->clients_served++;
	http_update_wanted(s);
	return c;
}

void mjpeg_client_free(struct http_sink *s, struct mjpeg_client *c)
{
	for (struct mjpeg_client **p = &s->clients; *p; p = &(*p)->next) {
		if (*p == c) {
			*p = c->next;
			break;
		}
	}
	s->nclients--;
	s->wanted[c->stream]--;
	s->frames_dropped += c->count; /* what it never got */
	http_update_wanted(s);
	for (unsigned i = 0; i < MAX_QUEUE; i++)
		free(c->q[i].data);
	free(c->out.data);
	free(c);
}

static int part_fill(struct part *p, const unsigned char *jpeg, size_t len, uint64_t capture_ns,
		     uint64_t written_ns)
{
	char head[128];
	int n = snprintf(head, sizeof head,
			 "--" BOUNDARY "\r\nContent-Type: image/jpeg\r\nContent-Length: %zu\r\n\r\n",
			 len);
	size_t need = (size_t)n + len + 2;
	if (p->cap < need) {
		char *d = realloc(p->data, need);
		if (!d)
			return -ENOMEM;
		p->data = d;
		p->cap = need;
	}
	memcpy(p->data, head, (size_t)n);
	memcpy(p->data + n, jpeg, len);
	memcpy(p->data + n + len, "\r\n", 2);
	p->len = need;
	p->capture_ns = capture_ns;
	p->written_ns = written_ns;
	return 0;
}

void mjpeg_clients_push(struct http_sink *s, enum view_stream v, const unsigned char *jpeg,
			size_t len, uint64_t capture_ns, uint64_t written_ns)
{
	int any = 0;
	for (struct mjpeg_client *c = s->clients; c; c = c->next) {
		if (c->stream != v)
			continue;
		if (c->count == c->depth) { /* full: this client loses its oldest part */
			c->head = (c->head + 1) % c->depth;
			c->count--;
			c->dropped++;
			s->frames_dropped++;
		}
		struct part *p = &c->q[(c->head + c->count) % c->depth];
		if (part_fill(p, jpeg, len, capture_ns, written_ns) < 0) {
			c->dropped++;
			s->frames_dropped++;
			continue;
		}
		c->count++;
		any = 1;
	}
	if (any)
		pthread_cond_broadcast(&s->frame_cond);
}

ssize_t mjpeg_client_read(struct http_sink *s, struct mjpeg_client *c, char *buf, size_t max)
{
	pthread_mutex_lock(&s->lock);
	while (c->out_off == c->out.len) {
		if (s->stopping) {
			pthread_mutex_unlock(&s->lock);
			return MHD_CONTENT_READER_END_OF_STREAM;
		}
		if (c->count) { /* the oldest queued part becomes the one to send (buffers swap) */
			struct part t = c->out;
			c->out = c->q[c->head];
			c->q[c->head] = t;
			c->q[c->head].len = 0;
			c->head = (c->head + 1) % c->depth;
			c->count--;
			c->out_off = 0;
			break;
		}
		/* the connection's own thread waits here; 200 ms at most, to see a stop */
		struct timespec ts;
		clock_gettime(CLOCK_MONOTONIC, &ts);
		ts.tv_nsec += 200000000L;
		if (ts.tv_nsec >= 1000000000L) {
			ts.tv_sec++;
			ts.tv_nsec -= 1000000000L;
		}
		pthread_cond_timedwait(&s->frame_cond, &s->lock, &ts);
	}
	size_t n = c->out.len - c->out_off;
	if (n > max)
		n = max;
	memcpy(buf, c->out.data + c->out_off, n);
	c->out_off += n;
	if (c->out_off == c->out.len) {
		/* its last bytes go to the connection now: the earlier ones are on the socket */
		c->sent++;
		s->frames_sent++;
		http_record_latency(s, c->out.capture_ns, c->out.written_ns, http_now_ns());
	}
	pthread_mutex_unlock(&s->lock);
	return (ssize_t)n;
}
