/* SPDX-License-Identifier: MIT */
#include "v4l2_io.h"

#include <errno.h>

int v4l2_xioctl(const struct v4l2_io *io, int fd, unsigned long request, void *arg)
{
	int r;
	do
		r = io->ioctl(io->user, fd, request, arg);
	while (r < 0 && errno == EINTR);
	return r;
}
