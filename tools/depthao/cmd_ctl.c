/* SPDX-License-Identifier: MIT */
/* depthao ctl: one command to a running depthaod over its control socket. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <json-c/json.h>

#include "commands.h"

static void usage(FILE *out)
{
	fprintf(out,
		"usage: depthao ctl --socket PATH COMMAND [ARGS]\n"
		"\n"
		"Talks to a running depthaod (its [daemon] socket or --socket).  Commands:\n"
		"  stats               counters, fps, latency per sink (JSON)\n"
		"  get [PARAM]         AO parameters (all, or one)\n"
		"  set PARAM VALUE     change an AO parameter of the running pipeline\n"
		"  pause | resume      stop / restart processing (live sources keep streaming)\n"
		"  snapshot FILE.png   write the next shaded frame\n"
		"Prints the daemon's JSON reply; exits 0 if it says ok, 1 if not or unreachable.\n");
}

int cmd_ctl(int argc, char **argv)
{
	const char *sock = NULL;
	int i = 1;
	for (; i < argc && !strncmp(argv[i], "--", 2); i++) {
		if (!strcmp(argv[i], "--help")) {
			usage(stdout);
			return 0;
		}
		if (!strcmp(argv[i], "--socket") && i + 1 < argc)
			sock = argv[++i];
		else
			return usage_error("ctl", "unknown option '%s'", argv[i]);
	}
	if (!sock)
		return usage_error("ctl", "--socket PATH is required");
	if (i >= argc)
		return usage_error("ctl", "no command given");
	const char *cmd = argv[i++];
	int nargs = argc - i;
	struct json_object *req = json_object_new_object();
	json_object_object_add(req, "cmd", json_object_new_string(cmd));
	if (!strcmp(cmd, "get") && nargs <= 1) {
		if (nargs)
			json_object_object_add(req, "key", json_object_new_string(argv[i]));
	} else if (!strcmp(cmd, "set") && nargs == 2) {
		json_object_object_add(req, "key", json_object_new_string(argv[i]));
		json_object_object_add(req, "value", json_object_new_string(argv[i + 1]));
	} else if (!strcmp(cmd, "snapshot") && nargs == 1) {
		json_object_object_add(req, "path", json_object_new_string(argv[i]));
	} else if ((!strcmp(cmd, "stats") || !strcmp(cmd, "pause") || !strcmp(cmd, "resume")) &&
		   nargs == 0) {
		/* no arguments */
	} else {
		json_object_put(req);
		return usage_error("ctl", "bad command or arguments: '%s'", cmd);
	}
	struct sockaddr_un addr = {.sun_family = AF_UNIX};
	if (strlen(sock) >= sizeof addr.sun_path) {
		json_object_put(req);
		return usage_error("ctl", "socket path '%s' is too long", sock);
	}
	memcpy(addr.sun_path, sock, strlen(sock) + 1);
	int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
	if (fd < 0 || connect(fd, (struct sockaddr *)&addr, sizeof addr) < 0) {
		fprintf(stderr, "depthao: cannot connect to %s: %s (is depthaod running with this "
			"socket?)\n", sock, strerror(errno));
		json_object_put(req);
		if (fd >= 0)
			close(fd);
		return 1;
	}
	const char *line = json_object_to_json_string_ext(req, JSON_C_TO_STRING_PLAIN);
	int status = 1;
	if (dprintf(fd, "%s\n", line) < 0) {
		fprintf(stderr, "depthao: cannot send to %s: %s\n", sock, strerror(errno));
		goto out;
	}
	char buf[65536];
	size_t len = 0;
	while (len < sizeof buf - 1) {
		ssize_t n = read(fd, buf + len, sizeof buf - 1 - len);
		if (n <= 0)
			break;
		len += (size_t)n;
		if (memchr(buf, '\n', len))
			break;
	}
	buf[len] = '\0';
	struct json_object *res = json_tokener_parse(buf);
	struct json_object *ok;
	if (!res) {
		fprintf(stderr, "depthao: no reply from %s\n", sock);
		goto out;
	}
	printf("%s\n", json_object_to_json_string_ext(res, JSON_C_TO_STRING_PRETTY));
	status = json_object_object_get_ex(res, "ok", &ok) && json_object_get_boolean(ok) ? 0 : 1;
	json_object_put(res);
out:
	json_object_put(req);
	close(fd);
	return status;
}
