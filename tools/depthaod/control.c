/* SPDX-License-Identifier: MIT */
#define _GNU_SOURCE /* struct ucred, accept4, pipe2 */
#include "common/tool_clock.h"
#include "control.h"

#include <errno.h>
#include <fcntl.h>
#include <grp.h>
#include <poll.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <time.h>
#include <unistd.h>

#include "log.h"

#ifndef SO_PEERGROUPS
#define SO_PEERGROUPS 59 /* Linux 4.13 */
#endif

#define MAX_CLIENTS 16
#define LINE_MAX_BYTES 4096
#define OUT_HIGH_WATER (64 * 1024)   /* unsent bytes at which a client's requests wait */
#define STALL_TIMEOUT_MS 5000        /* a client taking none of its replies this long is dropped */
#define SNAPSHOT_TIMEOUT_MS 3000
#define DEFAULT_GROUP "depthao"
#define MAX_PEER_GROUPS 256

struct client {
	int fd;                       /* -1 = free slot */
	pid_t pid;
	uid_t uid;
	char in[LINE_MAX_BYTES];
	size_t in_len;
	char *out;                    /* replies not yet sent: out[out_off..out_len) */
	size_t out_len, out_off, out_cap;
	uint64_t last_request_ns;     /* for the idle timeout and eviction */
	uint64_t stalled_since_ns;    /* output waiting and none taken since (0 = not stalled) */
	int eof;                      /* the client has sent all it will */
	int out_gone;                 /* it reads no more replies (they are dropped) */
	int closing;                  /* drop once the output is sent */
	int snapshot;                 /* waiting for a snapshot: its later requests wait too */
	uint64_t snapshot_deadline_ns;
	char snapshot_path[512];
};

struct control {
	struct daemon *d;
	char path[108];
	int listen_fd;
	int wake[2];                  /* 'q': stop; 's': a snapshot is done (non-blocking) */
	int have_group;
	gid_t gid;
	char group[64];
	uint64_t idle_ns;
	pthread_t thread;
	int snapshot_owner;           /* client slot waiting for the snapshot, -1 = none */
	struct client clients[MAX_CLIENTS];
	struct log_limit set_log, refused_log, evict_log, stall_log;
};

/* ---- replies ------------------------------------------------------------ */

static struct json_object *error_reply(const char *fmt, const char *a)
{
	char m[1024];
	snprintf(m, sizeof m, fmt, a);
	struct json_object *j = json_object_new_object();
	json_object_object_add(j, "ok", json_object_new_boolean(0));
	json_object_object_add(j, "error", json_object_new_string(m));
	return j;
}

static struct json_object *ok_reply(void)
{
	struct json_object *j = json_object_new_object();
	json_object_object_add(j, "ok", json_object_new_boolean(1));
	return j;
}

static void drop_client(struct control *c, struct client *cl)
{
	if (cl->snapshot) {
		daemon_snapshot_cancel(c->d);
		c->snapshot_owner = -1;
	}
	close(cl->fd);
	free(cl->out);
	memset(cl, 0, sizeof(*cl));
	cl->fd = -1;
}

/* Sends what the socket takes now; 0, or -1 if the client is gone (dropped). */
static int flush_out(struct control *c, struct client *cl)
{
	while (cl->out_off < cl->out_len) {
		ssize_t w = send(cl->fd, cl->out + cl->out_off, cl->out_len - cl->out_off,
				 MSG_NOSIGNAL | MSG_DONTWAIT);
		if (w < 0 && errno == EINTR)
			continue;
		if (w < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
			if (!cl->stalled_since_ns)
				cl->stalled_since_ns = tool_mono_ns();
			return 0;
		}
		if (w < 0 && (errno == EPIPE || errno == ECONNRESET)) {
			/* it hung up: what it asked before is still done, the replies go nowhere */
			cl->out_gone = 1;
			break;
		}
		if (w <= 0) {
			drop_client(c, cl);
			return -1;
		}
		cl->out_off += (size_t)w;
		cl->stalled_since_ns = 0;
	}
	cl->out_off = cl->out_len = 0;
	cl->stalled_since_ns = 0;
	if (cl->closing) {
		drop_client(c, cl);
		return -1;
	}
	return 0;
}

/* Queues one reply line (and frees j); sends what it can. */
static int reply(struct control *c, struct client *cl, struct json_object *j)
{
	if (cl->out_gone) {
		json_object_put(j);
		if (cl->closing) {
			drop_client(c, cl);
			return -1;
		}
		return 0;
	}
	const char *s = json_object_to_json_string_ext(j, JSON_C_TO_STRING_PLAIN);
	size_t n = strlen(s);
	if (cl->out_off) { /* what was sent makes room */
		memmove(cl->out, cl->out + cl->out_off, cl->out_len - cl->out_off);
		cl->out_len -= cl->out_off;
		cl->out_off = 0;
	}
	if (cl->out_len + n + 1 > cl->out_cap) {
		size_t cap = cl->out_cap ? cl->out_cap : 4096;
		while (cap < cl->out_len + n + 1)
			cap *= 2;
		char *p = realloc(cl->out, cap);
		if (!p) {
			json_object_put(j);
			log_error("control: out of memory for a reply; closing that connection");
			drop_client(c, cl);
			return -1;
		}
		cl->out = p;
		cl->out_cap = cap;
	}
	memcpy(cl->out + cl->out_len, s, n);
	cl->out[cl->out_len + n] = '\n';
	cl->out_len += n + 1;
	json_object_put(j);
	return flush_out(c, cl);
}

/* ---- requests ----------------------------------------------------------- */

static const char *str_field(struct json_object *req, const char *name)
{
	struct json_object *v;
	if (!json_object_object_get_ex(req, name, &v))
		return NULL;
	return json_object_get_string(v); /* numbers become text too */
}

static struct json_object *params_json(const struct dao_params *p, const char *only)
{
	struct json_object *o = json_object_new_object();
	size_t n;
	const struct dao_param_info *t = dao_param_table(&n);
	for (size_t i = 0; i < n; i++) {
		char v[64];
		if (only && dao_param_find(only) != &t[i])
			continue;
		if (dao_params_get(p, t[i].name, v, sizeof v, NULL) == 0)
			json_object_object_add(o, t[i].name, json_object_new_string(v));
	}
	return o;
}

/* The reply to one request line, or NULL when it comes later (a snapshot). */
static struct json_object *handle(struct control *c, struct client *cl, const char *line)
{
	struct json_object *req = json_tokener_parse(line);
	struct json_object *res;
	const char *cmd = req && json_object_is_type(req, json_type_object) ? str_field(req, "cmd") : NULL;
	if (!cmd) {
		res = error_reply("%s", "expected a JSON object with \"cmd\" (stats, get, set, pause, "
				  "resume, snapshot)");
	} else if (!strcmp(cmd, "stats")) {
		res = ok_reply();
		json_object_object_add(res, "stats", daemon_stats(c->d, 0));
	} else if (!strcmp(cmd, "get")) {
		const char *key = str_field(req, "key");
		struct dao_params p;
		daemon_get_params(c->d, &p);
		if (key && !dao_param_find(key)) {
			res = error_reply("unknown AO parameter '%s'", key);
		} else {
			res = ok_reply();
			json_object_object_add(res, "params", params_json(&p, key));
		}
	} else if (!strcmp(cmd, "set")) {
		const char *key = str_field(req, "key"), *value = str_field(req, "value");
		struct dao_params p;
		struct dao_error err = {0};
		daemon_get_params(c->d, &p);
		if (!key || !value) {
			res = error_reply("%s", "set needs \"key\" and \"value\"");
		} else if (dao_params_set(&p, key, value, &err) < 0 || dao_params_validate(&p, &err) < 0) {
			res = error_reply("%s", err.message);
		} else {
			daemon_set_params(c->d, &p);
			log_limited(&c->set_log, LOG_INFO, "control: %s = %s", key, value);
			res = ok_reply();
			json_object_object_add(res, "key", json_object_new_string(key));
			json_object_object_add(res, "value", json_object_new_string(value));
		}
	} else if (!strcmp(cmd, "pause") || !strcmp(cmd, "resume")) {
		int paused = cmd[0] == 'p';
		daemon_set_paused(c->d, paused);
		log_info("control: %s", paused ? "paused" : "resumed");
		res = ok_reply();
		json_object_object_add(res, "paused", json_object_new_boolean(paused));
	} else if (!strcmp(cmd, "snapshot")) {
		const char *path = str_field(req, "path");
		char m[256];
		if (!path || !*path) {
			res = error_reply("%s", "snapshot needs \"path\" (a .png file to write)");
		} else if (path[0] != '/') {
			res = error_reply("snapshot: '%s' is relative; the path must be absolute (the "
					  "daemon's working directory is not the client's; depthao ctl "
					  "makes a relative path absolute)", path);
		} else if (strlen(path) >= sizeof cl->snapshot_path) {
			res = error_reply("%s", "snapshot: the path is too long");
		} else if (daemon_snapshot_request(c->d, path, c->wake[1], m, sizeof m) < 0) {
			res = error_reply("snapshot: %s", m);
		} else {
			cl->snapshot = 1;
			cl->snapshot_deadline_ns = tool_mono_ns() + (uint64_t)SNAPSHOT_TIMEOUT_MS * 1000000u;
			snprintf(cl->snapshot_path, sizeof cl->snapshot_path, "%s", path);
			c->snapshot_owner = (int)(cl - c->clients);
			res = NULL;
		}
	} else {
		res = error_reply("unknown command '%s' (stats, get, set, pause, resume, snapshot)", cmd);
	}
	json_object_put(req);
	return res;
}

/* Answers the complete lines received, in order, while the client takes its replies. */
static void serve_lines(struct control *c, struct client *cl)
{
	char *nl;
	while (cl->fd >= 0 && !cl->snapshot && cl->out_len - cl->out_off < OUT_HIGH_WATER &&
	       (nl = memchr(cl->in, '\n', cl->in_len))) {
		*nl = '\0';
		struct json_object *res = handle(c, cl, cl->in);
		size_t used = (size_t)(nl - cl->in) + 1;
		memmove(cl->in, cl->in + used, cl->in_len - used);
		cl->in_len -= used;
		if (res && reply(c, cl, res) < 0)
			return;
	}
	if (cl->fd >= 0 && cl->eof && !cl->snapshot && !memchr(cl->in, '\n', cl->in_len) &&
	    cl->out_off == cl->out_len)
		drop_client(c, cl); /* said all it had to say and got every answer */
}

static void on_readable(struct control *c, struct client *cl)
{
	ssize_t n = recv(cl->fd, cl->in + cl->in_len, sizeof cl->in - cl->in_len, MSG_DONTWAIT);
	if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR))
		return;
	if (n < 0) {
		drop_client(c, cl);
		return;
	}
	if (n == 0) {
		cl->eof = 1;
	} else {
		cl->in_len += (size_t)n;
		cl->last_request_ns = tool_mono_ns();
	}
	serve_lines(c, cl);
	if (cl->fd >= 0 && cl->in_len == sizeof cl->in && !memchr(cl->in, '\n', cl->in_len)) {
		cl->in_len = 0;
		cl->closing = 1;
		reply(c, cl, error_reply("a request is longer than %s bytes; closing", "4095"));
	}
}

static void finish_snapshot(struct control *c, int timed_out)
{
	struct client *cl = &c->clients[c->snapshot_owner];
	char m[768] = "";
	int r = 1;
	if (timed_out) {
		if (daemon_snapshot_cancel(c->d))
			snprintf(m, sizeof m, "%s is still being written after %d ms (a FIFO whose "
				 "reader does not read, or a slow file system); the pipeline goes on",
				 cl->snapshot_path, SNAPSHOT_TIMEOUT_MS);
		else
			snprintf(m, sizeof m, "no frame within %d ms (the source is idle or slow)",
				 SNAPSHOT_TIMEOUT_MS);
	} else if ((r = daemon_snapshot_result(c->d, m, sizeof m)) == 1) {
		return; /* not yet */
	}
	c->snapshot_owner = -1;
	cl->snapshot = 0;
	struct json_object *res;
	if (timed_out || r < 0) {
		res = error_reply("snapshot: %s", m);
	} else {
		res = ok_reply();
		json_object_object_add(res, "path", json_object_new_string(cl->snapshot_path));
	}
	if (reply(c, cl, res) == 0)
		serve_lines(c, cl); /* what it asked meanwhile */
}

/* ---- connections -------------------------------------------------------- */

static int in_group(int fd, gid_t gid, gid_t primary)
{
	if (primary == gid)
		return 1;
	gid_t groups[MAX_PEER_GROUPS];
	socklen_t n = sizeof groups;
	if (getsockopt(fd, SOL_SOCKET, SO_PEERGROUPS, groups, &n) < 0)
		return 0;
	for (size_t i = 0; i < n / sizeof(gid_t); i++)
		if (groups[i] == gid)
			return 1;
	return 0;
}

static int peer_allowed(struct control *c, int fd, struct ucred *cr)
{
	socklen_t n = sizeof *cr;
	if (getsockopt(fd, SOL_SOCKET, SO_PEERCRED, cr, &n) < 0)
		return 0;
	return cr->uid == geteuid() || cr->uid == 0 ||
	       (c->have_group && in_group(fd, c->gid, cr->gid));
}

/* A free slot; when there is none, the longest-idle client (not awaiting a snapshot) makes room. */
static struct client *free_slot(struct control *c)
{
	struct client *idlest = NULL;
	for (int i = 0; i < MAX_CLIENTS; i++) {
		struct client *cl = &c->clients[i];
		if (cl->fd < 0)
			return cl;
		if (!cl->snapshot && (!idlest || cl->last_request_ns < idlest->last_request_ns))
			idlest = cl;
	}
	if (idlest) {
		log_limited(&c->evict_log, LOG_INFO, "control: %d connections open; the longest idle "
			    "(pid %d) is closed to make room", MAX_CLIENTS, (int)idlest->pid);
		drop_client(c, idlest);
	}
	return idlest;
}

static void on_accept(struct control *c)
{
	int fd = accept4(c->listen_fd, NULL, NULL, SOCK_CLOEXEC | SOCK_NONBLOCK);
	if (fd < 0)
		return;
	struct ucred cr = {0};
	if (!peer_allowed(c, fd, &cr)) {
		if (c->have_group)
			log_limited(&c->refused_log, LOG_WARN,
				    "control: refused uid %u (pid %d): only uid %u, root and group "
				    "%s may connect (the group is [daemon] socket_group)",
				    (unsigned)cr.uid, (int)cr.pid, (unsigned)geteuid(), c->group);
		else
			log_limited(&c->refused_log, LOG_WARN,
				    "control: refused uid %u (pid %d): only uid %u and root may "
				    "connect; set [daemon] socket_group to let a group in",
				    (unsigned)cr.uid, (int)cr.pid, (unsigned)geteuid());
		close(fd);
		return;
	}
	struct client *cl = free_slot(c);
	if (!cl) { /* every slot waits for a snapshot: cannot happen with one snapshot at a time */
		close(fd);
		return;
	}
	cl->fd = fd;
	cl->pid = cr.pid;
	cl->uid = cr.uid;
	cl->last_request_ns = tool_mono_ns();
}

/* Drops idle and stalled clients, times snapshots out; the poll timeout until the next such event. */
static int expire(struct control *c)
{
	uint64_t now = tool_mono_ns(), next = now + 1000000000u;
	for (int i = 0; i < MAX_CLIENTS; i++) {
		struct client *cl = &c->clients[i];
		if (cl->fd < 0)
			continue;
		if (cl->snapshot) {
			if (now >= cl->snapshot_deadline_ns)
				finish_snapshot(c, 1);
			else if (cl->snapshot_deadline_ns < next)
				next = cl->snapshot_deadline_ns;
			continue;
		}
		if (cl->fd < 0)
			continue;
		uint64_t stall_end = cl->stalled_since_ns + (uint64_t)STALL_TIMEOUT_MS * 1000000u;
		if (cl->stalled_since_ns && now >= stall_end) {
			log_limited(&c->stall_log, LOG_WARN, "control: a client (pid %d) took none of "
				    "its replies for %d s; disconnected", (int)cl->pid,
				    STALL_TIMEOUT_MS / 1000);
			drop_client(c, cl);
			continue;
		}
		uint64_t idle_end = cl->last_request_ns + c->idle_ns;
		if (!cl->stalled_since_ns && cl->out_off == cl->out_len && now >= idle_end) {
			log_debug("control: closing a connection idle for %llu s (pid %d)",
				  (unsigned long long)(c->idle_ns / 1000000000u), (int)cl->pid);
			drop_client(c, cl);
			continue;
		}
		if (cl->stalled_since_ns && stall_end < next)
			next = stall_end;
		if (idle_end < next)
			next = idle_end;
	}
	uint64_t ms = next > now ? (next - now) / 1000000u + 1 : 0;
	return (int)ms;
}

static void *control_main(void *arg)
{
	struct control *c = arg;
	for (;;) {
		struct pollfd p[2 + MAX_CLIENTS];
		int slot[2 + MAX_CLIENTS];
		int np = 2, timeout = expire(c);
		p[0] = (struct pollfd){c->wake[0], POLLIN, 0};
		p[1] = (struct pollfd){c->listen_fd, POLLIN, 0};
		for (int i = 0; i < MAX_CLIENTS; i++) {
			struct client *cl = &c->clients[i];
			if (cl->fd < 0)
				continue;
			short ev = 0;
			if (!cl->eof && !cl->snapshot && cl->out_len - cl->out_off < OUT_HIGH_WATER &&
			    cl->in_len < sizeof cl->in)
				ev |= POLLIN;
			if (cl->out_off < cl->out_len)
				ev |= POLLOUT;
			slot[np] = i;
			p[np++] = (struct pollfd){cl->fd, ev, 0};
		}
		if (poll(p, (nfds_t)np, timeout) < 0) {
			if (errno == EINTR)
				continue;
			log_error("control: poll: %s; the control socket stops", strerror(errno));
			break;
		}
		if (p[0].revents) {
			char b[64];
			ssize_t n = read(c->wake[0], b, sizeof b);
			if (n > 0 && memchr(b, 'q', (size_t)n))
				break;
			if (c->snapshot_owner >= 0)
				finish_snapshot(c, 0);
		}
		if (p[1].revents & POLLIN)
			on_accept(c);
		for (int k = 2; k < np; k++) {
			struct client *cl = &c->clients[slot[k]];
			if (cl->fd != p[k].fd || !p[k].revents)
				continue; /* dropped (or replaced) meanwhile */
			if ((p[k].revents & POLLOUT) && flush_out(c, cl) == 0 && cl->out_off == cl->out_len)
				serve_lines(c, cl); /* requests held back by the output */
			/* what a client sent before hanging up is read and done first (POLLIN comes
			 * with POLLHUP then); a hang-up with nothing left to read drops it */
			if (cl->fd == p[k].fd && (p[k].revents & POLLIN))
				on_readable(c, cl);
			else if (cl->fd == p[k].fd && (p[k].revents & (POLLHUP | POLLERR)))
				drop_client(c, cl);
		}
	}
	return NULL;
}

/* ---- start, stop -------------------------------------------------------- */

static int resolve_group(struct control *c, const char *group, char *msg, size_t len)
{
	const char *name = group && *group ? group : DEFAULT_GROUP;
	char buf[4096];
	struct group gr, *res = NULL;
	int r = getgrnam_r(name, &gr, buf, sizeof buf, &res);
	if (r == 0 && res) {
		c->have_group = 1;
		c->gid = res->gr_gid;
		snprintf(c->group, sizeof c->group, "%s", name);
		return 0;
	}
	if (group && *group) {
		snprintf(msg, len, "[daemon] socket_group: there is no group '%s'%s%s", group,
			 r ? ": " : "", r ? strerror(r) : "");
		return -ENOENT;
	}
	return 0; /* no default group: the socket stays the daemon's user's */
}

int control_start(struct control **out, const struct control_options *o, struct daemon *d,
		  char *msg, size_t len)
{
	const char *path = o->path;
	struct sockaddr_un addr = {.sun_family = AF_UNIX};
	if (strlen(path) >= sizeof addr.sun_path) {
		snprintf(msg, len, "control socket path '%s' is longer than %zu bytes", path,
			 sizeof addr.sun_path - 1);
		return -ENAMETOOLONG;
	}
	memcpy(addr.sun_path, path, strlen(path) + 1);
	struct control *c = calloc(1, sizeof(*c));
	if (!c) {
		snprintf(msg, len, "out of memory");
		return -ENOMEM;
	}
	c->d = d;
	c->snapshot_owner = -1;
	c->idle_ns = (uint64_t)(o->idle_timeout_s ? o->idle_timeout_s : 30) * 1000000000u;
	c->set_log = (struct log_limit)LOG_LIMIT_INIT(10000, 5);
	c->refused_log = (struct log_limit)LOG_LIMIT_INIT(60000, 5);
	c->evict_log = (struct log_limit)LOG_LIMIT_INIT(60000, 5);
	c->stall_log = (struct log_limit)LOG_LIMIT_INIT(60000, 5);
	snprintf(c->path, sizeof c->path, "%s", path);
	for (int i = 0; i < MAX_CLIENTS; i++)
		c->clients[i].fd = -1;
	c->wake[0] = c->wake[1] = -1;
	int r = resolve_group(c, o->group, msg, len);
	if (r < 0) {
		free(c);
		return r;
	}
	c->listen_fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
	struct stat st;
	if (lstat(path, &st) == 0) {
		/* a socket left by a daemon that died: remove it, unless someone answers */
		int probe = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
		int alive = connect(probe, (struct sockaddr *)&addr, sizeof addr) == 0;
		close(probe);
		if (alive || !S_ISSOCK(st.st_mode)) {
			snprintf(msg, len, "control socket %s: %s", path,
				 alive ? "another depthaod is listening there"
				       : "exists and is not a socket");
			close(c->listen_fd);
			free(c);
			return -EEXIST;
		}
		unlink(path);
	}
	mode_t old = umask(0077); /* the socket is created 0600 */
	int bound = bind(c->listen_fd, (struct sockaddr *)&addr, sizeof addr) == 0;
	umask(old);
	if (!bound || chmod(path, 0600) < 0 || listen(c->listen_fd, 16) < 0 || pipe2(c->wake, O_CLOEXEC | O_NONBLOCK) < 0) {
		r = -errno;
		snprintf(msg, len, "control socket %s: %s", path, strerror(errno));
		close(c->listen_fd);
		if (bound)
			unlink(path);
		free(c);
		return r;
	}
	if (c->have_group) {
		if (chown(path, (uid_t)-1, c->gid) == 0 && chmod(path, 0660) == 0)
			log_info("control socket %s: mode 0660, group %s", path, c->group);
		else
			log_warn("control socket %s: cannot give it to group %s (%s); only uid %u and "
				 "root may use it (run depthaod with that group, e.g. systemd's "
				 "SupplementaryGroups=%s)", path, c->group, strerror(errno),
				 (unsigned)geteuid(), c->group);
	}
	if (pthread_create(&c->thread, NULL, control_main, c) != 0) {
		snprintf(msg, len, "cannot start the control thread");
		close(c->listen_fd);
		close(c->wake[0]);
		close(c->wake[1]);
		unlink(path);
		free(c);
		return -EAGAIN;
	}
	*out = c;
	return 0;
}

void control_stop(struct control *c)
{
	if (!c)
		return;
	ssize_t w = write(c->wake[1], "q", 1);
	(void)w;
	pthread_join(c->thread, NULL);
	log_limit_flush(&c->set_log, LOG_INFO, "control: settings");
	log_limit_flush(&c->refused_log, LOG_WARN, "control: refused connections");
	for (int i = 0; i < MAX_CLIENTS; i++)
		if (c->clients[i].fd >= 0)
			drop_client(c, &c->clients[i]);
	close(c->listen_fd);
	close(c->wake[0]);
	close(c->wake[1]);
	unlink(c->path);
	free(c);
}
