/* SPDX-License-Identifier: MIT */
/*
 * The system calls the V4L2 plugin makes, behind a table: the plugin uses
 * libv4l2's (v4l2_open, v4l2_ioctl, v4l2_mmap, ...), the tests an emulated
 * device that follows the V4L2 specification's state machine.  Calls
 * return what the system calls return (-1 and errno on failure).
 */
#ifndef DAO_V4L2_IO_H
#define DAO_V4L2_IO_H

#include <poll.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/types.h>

struct v4l2_io {
	void *user;
	int (*open)(void *user, const char *path, int flags);
	int (*close)(void *user, int fd);
	int (*ioctl)(void *user, int fd, unsigned long request, void *arg);
	void *(*mmap)(void *user, size_t length, int prot, int flags, int fd, int64_t offset);
	int (*munmap)(void *user, void *addr, size_t length);
	int (*poll)(void *user, struct pollfd *fds, nfds_t n, int timeout_ms);
	ssize_t (*write)(void *user, int fd, const void *buf, size_t n);
	/* device nodes to look at when listing ("/dev/video0", ...): up to max into names */
	int (*nodes)(void *user, char (*names)[64], int max);
};

/* The real thing, through libv4l2. */
const struct v4l2_io *v4l2_io_system(void);

/* ioctl that retries on EINTR. */
int v4l2_xioctl(const struct v4l2_io *io, int fd, unsigned long request, void *arg);

#endif
