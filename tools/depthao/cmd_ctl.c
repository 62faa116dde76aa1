/* SPDX-License-Identifier: MIT */
/* depthao ctl: one command to a running depthaod over its control socket. */
#include <errno.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <time.h>
#include <unistd.h>

#include <json-c/json.h>

#include "common/tool_clock.h"
#include "commands.h"

static void usage(FILE *out)
{
	fprintf(out,
		"usage: depthao ctl --socket PATH [--timeout S] COMMAND [ARGS]\n"
		"\n"
		"Talks to a running depthaod (its [daemon] socket or --socket).  Commands:\n"
		"  stats               counters, fps, latency per sink (JSON)\n"
		"  get [PARAM]         AO parameters (all, or one)\n"
		"  set PARAM VALUE     change an AO parameter of the running pipeline\n"
		"  pause | resume      stop / restart processing (live sources keep streaming)\n"
		"  snapshot FILE.png   write the next shaded frame (a relative FILE is taken\n"
		"                      from the current directory)\n"
		"Prints the daemon's JSON reply; exits 0 if it says ok, 1 if not, if the daemon\n"
		"cannot be reached or gives no reply within --timeout seconds (default 5).\n");
}

static long long now_ms(void)
{
	return (long long)(tool_mono_ns() / 1000000u);
}

/* Waits for `events` on fd until the deadline; 1 ready, 0 timed out, -1 error. */
static int wait_fd(int fd, short events, long long deadline)
{
	for (;;) {
		long long left = deadline - now_ms();
		if (left <= 0)
			return 0;
		struct pollfd p = {fd, events, 0};
		int r = poll(&p, 1, left > 1000000 ? 1000000 : (int)left);
		if (r < 0 && errno == EINTR)
			continue;
		return r < 0 ? -1 : r > 0;
	}
}

/* Connects (retrying while the daemon's backlog is full) by the deadline. */
static int connect_by(int fd, const struct sockaddr_un *addr, long long deadline)
{
	for (;;) {
		if (connect(fd, (const struct sockaddr *)addr, sizeof *addr) == 0)
			return 0;
		if (errno != EAGAIN && errno != EINTR)
			return -errno;
		if (now_ms() >= deadline)
			return -ETIMEDOUT;
		struct timespec d = {0, 10 * 1000 * 1000};
		nanosleep(&d, NULL);
	}
}

/* The options before the command; *next: the command's index.  -1 to go on, else the exit status. */
static int parse_options(int argc, char **argv, const char **sock, double *timeout_s, int *next)
{
	int i = 1;
	for (; i < argc && !strncmp(argv[i], "--", 2); i++) {
		if (!strcmp(argv[i], "--help")) {
			usage(stdout);
			return 0;
		}
		if (!strcmp(argv[i], "--socket") && i + 1 < argc) {
			*sock = argv[++i];
		} else if (!strcmp(argv[i], "--timeout") && i + 1 < argc) {
			char *end;
			*timeout_s = strtod(argv[++i], &end);
			if (*end || !(*timeout_s >= 0.01 && *timeout_s <= 86400))
				return usage_error("ctl", "--timeout '%s' must be seconds in 0.01..86400",
						   argv[i]);
		} else
			return usage_error("ctl", "unknown option '%s'", argv[i]);
	}
	if (!*sock)
		return usage_error("ctl", "--socket PATH is required");
	if (i >= argc)
		return usage_error("ctl", "no command given");
	*next = i;
	return -1;
}

/* The JSON request of the command cmd with its nargs arguments args: 0 or the exit status. */
static int build_request(const char *cmd, char **args, int nargs, struct json_object **out)
{
	struct json_object *req = json_object_new_object();
	json_object_object_add(req, "cmd", json_object_new_string(cmd));
	if (!strcmp(cmd, "get") && nargs <= 1) {
		if (nargs)
			json_object_object_add(req, "key", json_object_new_string(args[0]));
	} else if (!strcmp(cmd, "set") && nargs == 2) {
		json_object_object_add(req, "key", json_object_new_string(args[0]));
		json_object_object_add(req, "value", json_object_new_string(args[1]));
	} else if (!strcmp(cmd, "snapshot") && nargs == 1) {
		/* the daemon writes it: a relative path is made absolute here, where it was meant */
		char cwd[4096], abs[8192];
		const char *path = args[0];
		if (path[0] != '/') {
			if (!getcwd(cwd, sizeof cwd)) {
				fprintf(stderr, "depthao: ctl snapshot %s: cannot tell the current "
					"directory (%s); give an absolute path\n", path, strerror(errno));
				json_object_put(req);
				return 1;
			}
			snprintf(abs, sizeof abs, "%s/%s", strcmp(cwd, "/") ? cwd : "", path);
			path = abs;
		}
		json_object_object_add(req, "path", json_object_new_string(path));
	} else if ((!strcmp(cmd, "stats") || !strcmp(cmd, "pause") || !strcmp(cmd, "resume")) &&
		   nargs == 0) {
		/* no arguments */
	} else {
		json_object_put(req);
		return usage_error("ctl", "bad command or arguments: '%s'", cmd);
	}
	*out = req;
	return 0;
}

/* The request as one line on fd, by the deadline: 0 or the exit status. */
static int send_request(int fd, struct json_object *req, const char *sock, long long deadline)
{
	const char *text = json_object_to_json_string_ext(req, JSON_C_TO_STRING_PLAIN);
	char line[8192];
	size_t n = (size_t)snprintf(line, sizeof line, "%s\n", text), off = 0;
	if (n >= sizeof line) {
		fprintf(stderr, "depthao: the request is too long\n");
		return 1;
	}
	while (off < n) {
		ssize_t w = send(fd, line + off, n - off, MSG_NOSIGNAL);
		if (w > 0) {
			off += (size_t)w;
		} else if (w < 0 && (errno == EAGAIN || errno == EINTR)) {
			if (wait_fd(fd, POLLOUT, deadline) <= 0)
				break;
		} else {
			break;
		}
	}
	if (off < n) {
		fprintf(stderr, "depthao: cannot send to %s: %s\n", sock,
			now_ms() >= deadline ? "timed out" : strerror(errno));
		return 1;
	}
	return 0;
}

/* The reply's line, printed: 0 if it says ok, else 1. */
static int print_reply(int fd, const char *sock, double timeout_s, long long deadline)
{
	char buf[65536];
	size_t len = 0;
	int timed_out = 0;
	while (len < sizeof buf - 1 && !memchr(buf, '\n', len)) {
		int ready = wait_fd(fd, POLLIN, deadline);
		if (ready <= 0) {
			timed_out = ready == 0;
			break;
		}
		ssize_t k = read(fd, buf + len, sizeof buf - 1 - len);
		if (k < 0 && (errno == EAGAIN || errno == EINTR))
			continue;
		if (k <= 0)
			break;
		len += (size_t)k;
	}
	if (timed_out) {
		fprintf(stderr, "depthao: no reply from %s within %g s (is the daemon stuck? "
			"--timeout sets the wait)\n", sock, timeout_s);
		return 1;
	}
	buf[len] = '\0';
	struct json_object *res = json_tokener_parse(buf);
	struct json_object *ok;
	if (!res) {
		fprintf(stderr, "depthao: no reply from %s\n", sock);
		return 1;
	}
	printf("%s\n", json_object_to_json_string_ext(res, JSON_C_TO_STRING_PRETTY |
							     JSON_C_TO_STRING_NOSLASHESCAPE));
	int status = json_object_object_get_ex(res, "ok", &ok) && json_object_get_boolean(ok) ? 0 : 1;
	json_object_put(res);
	return status;
}

int cmd_ctl(int argc, char **argv)
{
	const char *sock = NULL;
	double timeout_s = 5;
	int i = 0;
	int status = parse_options(argc, argv, &sock, &timeout_s, &i);
	if (status >= 0)
		return status;
	struct json_object *req;
	if ((status = build_request(argv[i], argv + i + 1, argc - i - 1, &req)))
		return status;
	struct sockaddr_un addr = {.sun_family = AF_UNIX};
	if (strlen(sock) >= sizeof addr.sun_path) {
		json_object_put(req);
		return usage_error("ctl", "socket path '%s' is too long", sock);
	}
	memcpy(addr.sun_path, sock, strlen(sock) + 1);
	long long deadline = now_ms() + (long long)(timeout_s * 1000);
	int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
	int r = fd < 0 ? -errno : connect_by(fd, &addr, deadline);
	if (r < 0) {
		fprintf(stderr, "depthao: cannot connect to %s: %s (is depthaod running with this "
			"socket?)\n", sock, strerror(-r));
		json_object_put(req);
		if (fd >= 0)
			close(fd);
		return 1;
	}
	status = send_request(fd, req, sock, deadline);
	if (!status)
		status = print_reply(fd, sock, timeout_s, deadline);
	json_object_put(req);
	close(fd);
	return status;
}
