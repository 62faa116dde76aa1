/* SPDX-License-Identifier: MIT */
#define _GNU_SOURCE /* struct ucred */
#include "control.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include "log.h"

#define MAX_CLIENTS 8
#define LINE_MAX_BYTES 4096
#define SNAPSHOT_TIMEOUT_MS 3000

struct client {
	int fd;
	char buf[LINE_MAX_BYTES];
	size_t len;
};

struct control {
	struct daemon *d;
	char path[108];
	int listen_fd, wake[2];
	pthread_t thread;
	struct client clients[MAX_CLIENTS];
	struct log_limit set_log;
};

static void reply(int fd, struct json_object *j)
{
	const char *s = json_object_to_json_string_ext(j, JSON_C_TO_STRING_PLAIN);
	size_t n = strlen(s);
	char *line = malloc(n + 2);
	if (line) {
		memcpy(line, s, n);
		line[n] = '\n';
		size_t off = 0;
		while (off < n + 1) {
			ssize_t w = send(fd, line + off, n + 1 - off, MSG_NOSIGNAL);
			if (w < 0 && errno == EINTR)
				continue;
			if (w <= 0)
				break;
			off += (size_t)w;
		}
		free(line);
	}
	json_object_put(j);
}

static struct json_object *error_reply(const char *fmt, const char *a)
{
	char m[512];
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

static struct json_object *handle(struct control *c, const char *line)
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
		} else if (daemon_snapshot(c->d, path, SNAPSHOT_TIMEOUT_MS, m, sizeof m) < 0) {
			res = error_reply("snapshot: %s", m);
		} else {
			res = ok_reply();
			json_object_object_add(res, "path", json_object_new_string(path));
		}
	} else {
		res = error_reply("unknown command '%s' (stats, get, set, pause, resume, snapshot)", cmd);
	}
	json_object_put(req);
	return res;
}

static int peer_is_us(int fd)
{
	struct ucred cr;
	socklen_t n = sizeof cr;
	return getsockopt(fd, SOL_SOCKET, SO_PEERCRED, &cr, &n) == 0 && cr.uid == getuid();
}

static void drop_client(struct client *cl)
{
	close(cl->fd);
	cl->fd = -1;
	cl->len = 0;
}

static void on_readable(struct control *c, struct client *cl)
{
	ssize_t n = recv(cl->fd, cl->buf + cl->len, sizeof cl->buf - cl->len, 0);
	if (n <= 0) {
		drop_client(cl);
		return;
	}
	cl->len += (size_t)n;
	char *nl;
	while ((nl = memchr(cl->buf, '\n', cl->len))) {
		*nl = '\0';
		reply(cl->fd, handle(c, cl->buf));
		size_t used = (size_t)(nl - cl->buf) + 1;
		memmove(cl->buf, cl->buf + used, cl->len - used);
		cl->len -= used;
	}
	if (cl->len == sizeof cl->buf) {
		reply(cl->fd, error_reply("%s", "line too long"));
		drop_client(cl);
	}
}

static void *control_main(void *arg)
{
	struct control *c = arg;
	for (;;) {
		struct pollfd p[2 + MAX_CLIENTS];
		int np = 2;
		p[0] = (struct pollfd){c->wake[0], POLLIN, 0};
		p[1] = (struct pollfd){c->listen_fd, POLLIN, 0};
		for (int i = 0; i < MAX_CLIENTS; i++)
			if (c->clients[i].fd >= 0)
				p[np++] = (struct pollfd){c->clients[i].fd, POLLIN, 0};
		if (poll(p, (nfds_t)np, -1) < 0) {
			if (errno == EINTR)
				continue;
			break;
		}
		if (p[0].revents)
			break;
		if (p[1].revents & POLLIN) {
			int fd = accept4(c->listen_fd, NULL, NULL, SOCK_CLOEXEC);
			if (fd >= 0) {
				int slot = -1;
				for (int i = 0; i < MAX_CLIENTS && slot < 0; i++)
					if (c->clients[i].fd < 0)
						slot = i;
				if (!peer_is_us(fd)) {
					log_warn("control: refused a connection from another user");
					close(fd);
				} else if (slot < 0) {
					reply(fd, error_reply("%s", "too many control connections"));
					close(fd);
				} else {
					c->clients[slot].fd = fd;
					c->clients[slot].len = 0;
				}
			}
		}
		for (int k = 2; k < np; k++) {
			if (!p[k].revents)
				continue;
			for (int i = 0; i < MAX_CLIENTS; i++)
				if (c->clients[i].fd == p[k].fd)
					on_readable(c, &c->clients[i]);
		}
	}
	return NULL;
}

int control_start(struct control **out, const char *path, struct daemon *d, char *msg, size_t len)
{
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
	c->set_log = (struct log_limit)LOG_LIMIT_INIT(10000, 5);
	snprintf(c->path, sizeof c->path, "%s", path);
	for (int i = 0; i < MAX_CLIENTS; i++)
		c->clients[i].fd = -1;
	c->listen_fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
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
	int r = bind(c->listen_fd, (struct sockaddr *)&addr, sizeof addr);
	umask(old);
	if (r < 0 || chmod(path, 0600) < 0 || listen(c->listen_fd, 4) < 0 || pipe(c->wake) < 0) {
		snprintf(msg, len, "control socket %s: %s", path, strerror(errno));
		close(c->listen_fd);
		free(c);
		return -errno;
	}
	if (pthread_create(&c->thread, NULL, control_main, c) != 0) {
		snprintf(msg, len, "cannot start the control thread");
		close(c->listen_fd);
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
	ssize_t w = write(c->wake[1], "x", 1);
	(void)w;
	pthread_join(c->thread, NULL);
	log_limit_flush(&c->set_log, LOG_INFO, "control: settings");
	for (int i = 0; i < MAX_CLIENTS; i++)
		if (c->clients[i].fd >= 0)
			close(c->clients[i].fd);
	close(c->listen_fd);
	close(c->wake[0]);
	close(c->wake[1]);
	unlink(c->path);
	free(c);
}
