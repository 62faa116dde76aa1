/* SPDX-License-Identifier: MIT */
#include "v4l2_io.h"

#include <errno.h>
#include <glob.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#include <libv4l2.h>

static int sys_open(void *user, const char *path, int flags)
{
	(void)user;
	return v4l2_open(path, flags);
}

static int sys_close(void *user, int fd)
{
	(void)user;
	return v4l2_close(fd);
}

static int sys_ioctl(void *user, int fd, unsigned long request, void *arg)
{
	(void)user;
	return v4l2_ioctl(fd, request, arg);
}

static void *sys_mmap(void *user, size_t length, int prot, int flags, int fd, int64_t offset)
{
	(void)user;
	return v4l2_mmap(NULL, length, prot, flags, fd, offset);
}

static int sys_munmap(void *user, void *addr, size_t length)
{
	(void)user;
	return v4l2_munmap(addr, length);
}

static int sys_poll(void *user, struct pollfd *fds, nfds_t n, int timeout_ms)
{
	(void)user;
	return poll(fds, n, timeout_ms);
}

static ssize_t sys_write(void *user, int fd, const void *buf, size_t n)
{
	(void)user;
	return v4l2_write(fd, buf, n);
}

static int sys_nodes(void *user, char (*names)[64], int max)
{
	(void)user;
	glob_t g;
	int n = 0;
	if (glob("/dev/video*", 0, NULL, &g) == 0) {
		for (size_t i = 0; i < g.gl_pathc && n < max; i++)
			if (strlen(g.gl_pathv[i]) < 64)
				strcpy(names[n++], g.gl_pathv[i]);
		globfree(&g);
	}
	return n;
}

static const struct v4l2_io system_io = {
	NULL, sys_open, sys_close, sys_ioctl, sys_mmap, sys_munmap, sys_poll, sys_write, sys_nodes,
};

const struct v4l2_io *v4l2_io_system(void)
{
	return &system_io;
}
