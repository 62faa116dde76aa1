/* SPDX-License-Identifier: MIT */
/*
 * What holds the sink's connection slots against slow and greedy clients:
 * - a deadline for a whole request (its line, headers and body) counted from
 *   the connection's start or the end of its previous request: libmicrohttpd's
 *   timeout counts only idle time, so a client sending a byte now and then
 *   would keep its slot for ever.  A watchdog thread shuts the socket of a
 *   request past the deadline down (libmicrohttpd's own thread then sees the
 *   end of the connection and closes it as usual);
 * - when every slot is taken, a new connection takes the slot of the oldest
 *   connection still sending its request (a client whose request is complete
 *   arrives in one packet; only a slow one is still sending);
 * - token buckets per client address and for everyone (the snapshot's rate).
 * The per-address connection limit is libmicrohttpd's (http_routes.c).
 */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <time.h>

#include <microhttpd.h>

#include "http_sink.h"

struct guard_conn {
	struct guard_conn *next, *prev;
	int fd;
	struct sockaddr_storage peer;
	socklen_t peerlen;
	uint64_t since_ns;           /* its request started (at the latest) */
	int answered;                /* its request is in: no deadline (streams, replies) */
	int stream;                  /* a /stream.mjpg connection */
	int cut;                     /* shut down by us: it goes soon */
	int released;                /* no longer counted in s->connections */
};

/* Shuts the connection's socket down if it is still the one we saw open (the
   descriptor may have been closed and reused meanwhile: the peer tells). */
static void cut(struct http_sink *s, struct guard_conn *c, unsigned long long *counter)
{
	struct sockaddr_storage sa;
	socklen_t len = sizeof sa;
	c->cut = 1;
	if (getpeername(c->fd, (struct sockaddr *)&sa, &len) < 0 || len != c->peerlen ||
	    memcmp(&sa, &c->peer, len))
		return;
	shutdown(c->fd, SHUT_RDWR);
	(*counter)++;
	(void)s;
}

void *http_guard_opened(struct http_sink *s, struct MHD_Connection *conn)
{
	struct guard_conn *c = calloc(1, sizeof(*c));
	if (!c)
		return NULL;
	const union MHD_ConnectionInfo *ci =
		MHD_get_connection_info(conn, MHD_CONNECTION_INFO_CONNECTION_FD);
	c->fd = ci ? ci->connect_fd : -1;
	c->peerlen = sizeof c->peer;
	if (c->fd < 0 || getpeername(c->fd, (struct sockaddr *)&c->peer, &c->peerlen) < 0)
		c->peerlen = 0; /* never cut: nothing to check it against */
	c->since_ns = http_now_ns();
	pthread_mutex_lock(&s->guard_lock);
	c->next = s->guard_conns;
	if (c->next)
		c->next->prev = c;
	s->guard_conns = c;
	pthread_mutex_unlock(&s->guard_lock);
	return c;
}

static struct guard_conn *rec_of(struct MHD_Connection *conn)
{
	const union MHD_ConnectionInfo *ci =
		MHD_get_connection_info(conn, MHD_CONNECTION_INFO_SOCKET_CONTEXT);
	return ci ? ci->socket_context : NULL;
}

int http_guard_closed(struct http_sink *s, void *rec)
{
	struct guard_conn *c = rec;
	if (!c)
		return 0;
	pthread_mutex_lock(&s->guard_lock);
	const int released = c->released;
	if (c->prev)
		c->prev->next = c->next;
	else
		s->guard_conns = c->next;
	if (c->next)
		c->next->prev = c->prev;
	if (c->stream)
		s->guard_streams--;
	pthread_mutex_unlock(&s->guard_lock);
	free(c);
	return released;
}

void http_guard_release(struct http_sink *s, struct MHD_Connection *conn)
{
	struct guard_conn *c = rec_of(conn);
	if (!c)
		return;
	pthread_mutex_lock(&s->guard_lock);
	if (!c->released) {
		c->released = 1;
		atomic_fetch_sub(&s->connections, 1);
	}
	pthread_mutex_unlock(&s->guard_lock);
}

void http_guard_answered(struct http_sink *s, struct MHD_Connection *conn)
{
	struct guard_conn *c = rec_of(conn);
	if (!c)
		return;
	pthread_mutex_lock(&s->guard_lock);
	c->answered = 1;
	pthread_mutex_unlock(&s->guard_lock);
}

void http_guard_request_done(struct http_sink *s, struct MHD_Connection *conn)
{
	struct guard_conn *c = rec_of(conn);
	if (!c)
		return;
	pthread_mutex_lock(&s->guard_lock);
	c->answered = 0; /* the next request on this connection has its own deadline */
	c->since_ns = http_now_ns();
	pthread_mutex_unlock(&s->guard_lock);
}

int http_guard_stream_slot(struct http_sink *s, struct MHD_Connection *conn)
{
	struct guard_conn *c = rec_of(conn);
	int ok = 0;
	pthread_mutex_lock(&s->guard_lock);
	if (s->guard_streams < s->max_streams) {
		s->guard_streams++;
		ok = 1;
		if (c) {
			c->stream = 1;
			c->answered = 1;
		} else {
			s->guard_streams--; /* cannot be given back: not counted */
		}
	}
	pthread_mutex_unlock(&s->guard_lock);
	return ok;
}

int http_guard_make_room(struct http_sink *s)
{
	struct guard_conn *oldest = NULL;
	pthread_mutex_lock(&s->guard_lock);
	for (struct guard_conn *c = s->guard_conns; c; c = c->next)
		if (!c->answered && !c->cut && c->peerlen && (!oldest || c->since_ns < oldest->since_ns))
			oldest = c;
	if (oldest)
		cut(s, oldest, &s->evicted);
	pthread_mutex_unlock(&s->guard_lock);
	return oldest ? 0 : -1;
}

static void *watchdog(void *arg)
{
	struct http_sink *s = arg;
	pthread_mutex_lock(&s->guard_lock);
	while (!s->guard_quit) {
		const uint64_t now = http_now_ns();
		const uint64_t limit = (uint64_t)s->request_deadline_ms * 1000000u;
		for (struct guard_conn *c = s->guard_conns; c; c = c->next)
			if (!c->answered && !c->cut && c->peerlen && now - c->since_ns > limit)
				cut(s, c, &s->deadline_cuts);
		struct timespec ts;
		clock_gettime(CLOCK_MONOTONIC, &ts);
		ts.tv_nsec += 100000000L; /* a request is cut within 0.1 s of its deadline */
		if (ts.tv_nsec >= 1000000000L) {
			ts.tv_sec++;
			ts.tv_nsec -= 1000000000L;
		}
		pthread_cond_timedwait(&s->guard_cond, &s->guard_lock, &ts);
	}
	pthread_mutex_unlock(&s->guard_lock);
	return NULL;
}

int http_guard_start(struct http_sink *s)
{
	pthread_condattr_t ca;
	pthread_condattr_init(&ca);
	pthread_condattr_setclock(&ca, CLOCK_MONOTONIC);
	pthread_cond_init(&s->guard_cond, &ca);
	pthread_condattr_destroy(&ca);
	int r = pthread_create(&s->guard_thread, NULL, watchdog, s);
	if (r) {
		pthread_cond_destroy(&s->guard_cond);
		return -r;
	}
	s->guard_running = 1;
	return 0;
}

void http_guard_stop(struct http_sink *s)
{
	if (!s->guard_running)
		return;
	pthread_mutex_lock(&s->guard_lock);
	s->guard_quit = 1;
	pthread_cond_signal(&s->guard_cond);
	pthread_mutex_unlock(&s->guard_lock);
	pthread_join(s->guard_thread, NULL);
	pthread_cond_destroy(&s->guard_cond);
	s->guard_running = 0;
}

/* ---- rate limits: token buckets ---- */

static int take_token(struct rate_bucket *b, double rate, double burst, uint64_t now,
		      double *wait_s)
{
	if (!b->last_ns)
		b->tokens = burst;
	else
		b->tokens += (double)(now - b->last_ns) / 1e9 * rate;
	if (b->tokens > burst)
		b->tokens = burst;
	b->last_ns = now;
	if (b->tokens >= 1.0) {
		b->tokens -= 1.0;
		return 1;
	}
	*wait_s = (1.0 - b->tokens) / rate;
	return 0;
}

/* The client's address as a key (the port left out). */
static size_t addr_key(const struct sockaddr *sa, unsigned char key[16])
{
	memset(key, 0, 16);
	if (sa && sa->sa_family == AF_INET) {
		memcpy(key, &((const struct sockaddr_in *)sa)->sin_addr, 4);
		return 4;
	}
	if (sa && sa->sa_family == AF_INET6) {
		memcpy(key, &((const struct sockaddr_in6 *)sa)->sin6_addr, 16);
		return 16;
	}
	return 0;
}

int http_rate_take(struct http_sink *s, struct MHD_Connection *conn, unsigned *retry_after)
{
	const union MHD_ConnectionInfo *ci =
		MHD_get_connection_info(conn, MHD_CONNECTION_INFO_CLIENT_ADDRESS);
	unsigned char key[16];
	addr_key(ci ? ci->client_addr : NULL, key);
	const uint64_t now = http_now_ns();
	double wait = 0;
	int ok;
	pthread_mutex_lock(&s->guard_lock);
	/* the client's bucket: found, or the least recently used one taken over */
	struct rate_client *rc = NULL, *lru = &s->rate_clients[0];
	for (unsigned i = 0; i < HTTP_RATE_CLIENTS; i++) {
		struct rate_client *e = &s->rate_clients[i];
		if (e->b.last_ns && !memcmp(e->key, key, 16)) {
			rc = e;
			break;
		}
		if (e->b.last_ns < lru->b.last_ns)
			lru = e;
	}
	if (!rc) {
		rc = lru;
		memcpy(rc->key, key, 16);
		rc->b.last_ns = 0;
	}
	/* the client's own bucket first: a greedy client does not use up everyone's */
	ok = take_token(&rc->b, HTTP_SNAPSHOT_RATE_CLIENT, HTTP_SNAPSHOT_BURST_CLIENT, now, &wait) &&
	     take_token(&s->rate_all, HTTP_SNAPSHOT_RATE_ALL, HTTP_SNAPSHOT_BURST_ALL, now, &wait);
	if (!ok)
		s->rate_limited++;
	pthread_mutex_unlock(&s->guard_lock);
	*retry_after = ok ? 0 : (unsigned)wait + 1;
	return ok;
}
