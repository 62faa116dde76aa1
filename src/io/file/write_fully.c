/* SPDX-License-Identifier: MIT */
/* pwritev until everything is written (write_fully.h). */
#define _DEFAULT_SOURCE /* pwritev */
#include "file/write_fully.h"

#include <errno.h>
#include <sys/types.h>
#include <sys/uio.h>

int dao_io_write_fully(int fd, struct iovec *iov, int n, uint64_t at)
{
	for (;;) {
		while (n > 0 && iov->iov_len == 0) {
			iov++;
			n--;
		}
		if (n == 0)
			return 0;
		ssize_t k = pwritev(fd, iov, n, (off_t)at);
		if (k < 0 && errno == EINTR)
			continue;
		if (k < 0)
			return -errno;
		if (k == 0)
			return -EIO; /* a regular file takes something or says why not */
		at += (uint64_t)k;
		while (n > 0 && (size_t)k >= iov->iov_len) {
			k -= (ssize_t)iov->iov_len;
			iov++;
			n--;
		}
		if (n > 0) {
			iov->iov_base = (uint8_t *)iov->iov_base + k;
			iov->iov_len -= (size_t)k;
		}
	}
}
