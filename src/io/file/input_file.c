/* SPDX-License-Identifier: MIT */
/*
 * Opening an input file: regular files only, checked on the open descriptor
 * before a byte is read (O_NONBLOCK: opening a FIFO without a writer would
 * block forever), the size limit from fstat.
 */
#include <depthao/output_file.h>

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error_internal.h"

static const char *kind(mode_t m)
{
	if (S_ISDIR(m))
		return "a directory";
	if (S_ISFIFO(m))
		return "a FIFO (named pipe)";
	if (S_ISCHR(m))
		return "a character device";
	if (S_ISBLK(m))
		return "a block device";
	if (S_ISSOCK(m))
		return "a socket";
	return "something else";
}

int dao_input_file_open(const char *path, const char *what, uint64_t max_size, uint64_t *size,
			struct dao_error *err)
{
	if (!path || !what)
		return dao_error_set(err, -EINVAL, "dao_input_file_open: path and what are required");
	int fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
	if (fd < 0) {
		int e = errno;
		return dao_error_set(err, -e, "cannot open %s '%s': %s", what, path, strerror(e));
	}
	struct stat st;
	int r = 0;
	if (fstat(fd, &st) != 0) {
		int e = errno;
		r = dao_error_set(err, -e, "cannot read %s '%s': %s", what, path, strerror(e));
	} else if (!S_ISREG(st.st_mode)) {
		r = dao_error_set(err, -EINVAL,
				  "%s '%s' is %s, not a regular file: depthao reads only "
				  "regular files; give the path of a file (copy a stream into "
				  "a file first)",
				  what, path, kind(st.st_mode));
	} else if (max_size && (uint64_t)st.st_size > max_size) {
		r = dao_error_set(err, -EFBIG,
				  "%s '%s' is %llu bytes, larger than the %llu a valid one can have: "
				  "refused unread; check that it is the right file",
				  what, path, (unsigned long long)st.st_size,
				  (unsigned long long)max_size);
	} else {
		int fl = fcntl(fd, F_GETFL);
		if (fl < 0 || fcntl(fd, F_SETFL, fl & ~O_NONBLOCK) < 0) {
			int e = errno;
			r = dao_error_set(err, -e, "cannot read %s '%s': %s", what, path,
					  strerror(e));
		}
	}
	if (r < 0) {
		close(fd);
		return r;
	}
	if (size)
		*size = (uint64_t)st.st_size;
	return fd;
}
