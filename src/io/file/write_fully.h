/* SPDX-License-Identifier: MIT */
#ifndef DAO_IO_FILE_WRITE_FULLY_H
#define DAO_IO_FILE_WRITE_FULLY_H

#include <stdint.h>
#include <sys/uio.h>

/*
 * Writes all of iov[0..n) at offset `at` (pwritev): short writes continue,
 * EINTR retries.  0, or -errno (-EIO where a write took nothing).  iov is
 * consumed (its entries advanced past what was written).  The recorders'
 * (.oni, MCAP) one way to put bytes in their files.
 */
int dao_io_write_fully(int fd, struct iovec *iov, int n, uint64_t at);

#endif
