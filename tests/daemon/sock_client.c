/* SPDX-License-Identifier: MIT */
/*
 * sock_client: clients of depthaod's control socket that misbehave on purpose,
 * for the daemon tests.
 *   sock_client ask SOCK TIMEOUT_MS LINE   send LINE, print the reply line;
 *                                          exit 0, 2 = no reply in time, 1 = refused/closed
 *   sock_client many SOCK N LINE           send LINE N times, read the N replies; print how
 *                                          many said "ok":true
 *   sock_client idle SOCK N SECONDS        hold N connections that say nothing; print
 *                                          "all closed" once the daemon closed them all
 *   sock_client flood SOCK SECONDS         send requests and never read a reply; hold on
 *   sock_client hold SOCK LINE SECONDS     send LINE, then hold without reading
 *   sock_client listen SOCK SECONDS        a socket that takes connections and never answers
 *   sock_client fire SOCK LINE...          send the LINEs in one go and close at once, without
 *                                          waiting for replies
 * The holding modes print "ready" on stdout once their connections are made (and, for
 * flood, once the daemon stopped taking requests), then sleep.
 */
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <time.h>
#include <unistd.h>

static int connect_to(const char *path)
{
	struct sockaddr_un a = {.sun_family = AF_UNIX};
	snprintf(a.sun_path, sizeof a.sun_path, "%s", path);
	int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
	if (fd < 0 || connect(fd, (struct sockaddr *)&a, sizeof a) < 0) {
		fprintf(stderr, "sock_client: connect %s: %s\n", path, strerror(errno));
		exit(1);
	}
	return fd;
}

static long long now_ms(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return (long long)t.tv_sec * 1000 + t.tv_nsec / 1000000;
}

static void send_line(int fd, const char *line)
{
	char buf[4200];
	int n = snprintf(buf, sizeof buf, "%s\n", line);
	if (send(fd, buf, (size_t)n, MSG_NOSIGNAL) != n) {
		fprintf(stderr, "sock_client: send: %s\n", strerror(errno));
		exit(1);
	}
}

static void ready_then_sleep(int seconds)
{
	printf("ready\n");
	fflush(stdout);
	sleep((unsigned)seconds);
}

static int ask(const char *path, int timeout_ms, const char *line)
{
	int fd = connect_to(path);
	long long t0 = now_ms();
	send_line(fd, line);
	char buf[1 << 16];
	size_t len = 0;
	for (;;) {
		int left = (int)(t0 + timeout_ms - now_ms());
		struct pollfd p = {fd, POLLIN, 0};
		if (left <= 0 || poll(&p, 1, left) == 0) {
			fprintf(stderr, "sock_client: no reply within %d ms\n", timeout_ms);
			return 2;
		}
		ssize_t n = recv(fd, buf + len, sizeof buf - 1 - len, 0);
		if (n <= 0) {
			fprintf(stderr, "sock_client: connection closed without a reply\n");
			return 1;
		}
		len += (size_t)n;
		buf[len] = '\0';
		char *nl = strchr(buf, '\n');
		if (nl) {
			*nl = '\0';
			printf("%s\n", buf);
			fprintf(stderr, "sock_client: reply after %lld ms\n", now_ms() - t0);
			return 0;
		}
	}
}

static int many(const char *path, int n, const char *line)
{
	int fd = connect_to(path);
	int sent = 0, replies = 0, ok = 0;
	char buf[1 << 16];
	size_t len = 0;
	while (replies < n) {
		struct pollfd p = {fd, (short)(POLLIN | (sent < n ? POLLOUT : 0)), 0};
		if (poll(&p, 1, 10000) <= 0) {
			fprintf(stderr, "sock_client: many: stuck after %d replies\n", replies);
			return 2;
		}
		if ((p.revents & POLLOUT) && sent < n) {
			send_line(fd, line);
			sent++;
		}
		if (p.revents & (POLLIN | POLLHUP)) {
			ssize_t k = recv(fd, buf + len, sizeof buf - 1 - len, 0);
			if (k <= 0) {
				fprintf(stderr, "sock_client: many: closed after %d replies\n", replies);
				return 1;
			}
			len += (size_t)k;
			buf[len] = '\0';
			char *nl;
			while ((nl = memchr(buf, '\n', len))) {
				*nl = '\0';
				replies++;
				ok += strstr(buf, "\"ok\":true") != NULL;
				len -= (size_t)(nl + 1 - buf);
				memmove(buf, nl + 1, len);
				buf[len] = '\0';
			}
		}
	}
	printf("%d\n", ok);
	return 0;
}

static int idle(const char *path, int n, int seconds)
{
	struct pollfd p[64];
	if (n > 64)
		n = 64;
	for (int i = 0; i < n; i++)
		p[i] = (struct pollfd){connect_to(path), POLLIN, 0};
	printf("ready\n");
	fflush(stdout);
	long long end = now_ms() + seconds * 1000LL;
	int open = n;
	while (open && now_ms() < end) {
		if (poll(p, (nfds_t)n, 100) <= 0)
			continue;
		for (int i = 0; i < n; i++) {
			char b[256];
			if (p[i].fd >= 0 && p[i].revents && recv(p[i].fd, b, sizeof b, MSG_DONTWAIT) <= 0) {
				close(p[i].fd);
				p[i].fd = -1;
				open--;
			}
		}
	}
	if (!open)
		printf("all closed\n");
	return 0;
}

static int flood(const char *path, int seconds)
{
	int fd = connect_to(path);
	fcntl(fd, F_SETFL, O_NONBLOCK);
	static const char req[] = "{\"cmd\":\"stats\"}\n";
	long long sent = 0, stalled_since = now_ms();
	/* until the daemon has stopped taking requests for a second (both buffers full) */
	while (now_ms() - stalled_since < 1000) {
		ssize_t n = send(fd, req, sizeof req - 1, MSG_NOSIGNAL);
		if (n > 0) {
			sent += n;
			stalled_since = now_ms();
		} else if (n < 0 && errno != EAGAIN) {
			fprintf(stderr, "sock_client: flood: %s after %lld bytes\n", strerror(errno), sent);
			break;
		} else {
			struct timespec ms = {0, 1000000};
			nanosleep(&ms, NULL);
		}
	}
	fprintf(stderr, "sock_client: flood: %lld bytes of requests sent\n", sent);
	ready_then_sleep(seconds);
	return 0;
}

static int listen_only(const char *path, int seconds)
{
	struct sockaddr_un a = {.sun_family = AF_UNIX};
	snprintf(a.sun_path, sizeof a.sun_path, "%s", path);
	int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
	if (fd < 0 || bind(fd, (struct sockaddr *)&a, sizeof a) < 0 || listen(fd, 8) < 0) {
		fprintf(stderr, "sock_client: listen %s: %s\n", path, strerror(errno));
		return 1;
	}
	ready_then_sleep(seconds);
	unlink(path);
	return 0;
}

static int fire(const char *path, int n, char **lines)
{
	char buf[8192];
	size_t len = 0;
	for (int i = 0; i < n; i++)
		len += (size_t)snprintf(buf + len, sizeof buf - len, "%s\n", lines[i]);
	int fd = connect_to(path);
	if (send(fd, buf, len, MSG_NOSIGNAL) != (ssize_t)len) {
		fprintf(stderr, "sock_client: fire: send: %s\n", strerror(errno));
		return 1;
	}
	close(fd);
	return 0;
}

int main(int argc, char **argv)
{
	if (argc >= 5 && !strcmp(argv[1], "ask"))
		return ask(argv[2], atoi(argv[3]), argv[4]);
	if (argc >= 5 && !strcmp(argv[1], "many"))
		return many(argv[2], atoi(argv[3]), argv[4]);
	if (argc >= 5 && !strcmp(argv[1], "idle"))
		return idle(argv[2], atoi(argv[3]), atoi(argv[4]));
	if (argc >= 4 && !strcmp(argv[1], "flood"))
		return flood(argv[2], atoi(argv[3]));
	if (argc >= 5 && !strcmp(argv[1], "hold")) {
		send_line(connect_to(argv[2]), argv[3]);
		ready_then_sleep(atoi(argv[4]));
		return 0;
	}
	if (argc >= 4 && !strcmp(argv[1], "fire"))
		return fire(argv[2], argc - 3, argv + 3);
	if (argc >= 4 && !strcmp(argv[1], "listen"))
		return listen_only(argv[2], atoi(argv[3]));
	fprintf(stderr, "usage: sock_client ask|many|idle|flood|hold|listen|fire SOCK ... (see the source)\n");
	return 64;
}
