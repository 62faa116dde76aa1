/* SPDX-License-Identifier: MIT */
#define _XOPEN_SOURCE 700 /* realpath */
#include <depthao/output_file.h>

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error_internal.h"
#include "core/file_mode.h"
#include "file/output_file_internal.h"

static void release(struct dao_output_file *o)
{
	free(o->tmp);
	free(o->target);
	o->tmp = o->target = NULL;
	o->fd = -1;
}

/* FIFOs and character devices: straight into them, never created or truncated. */
static int open_stream(struct dao_output_file *o, const char *path, int fifo,
		       struct dao_error *err)
{
	/* non-blocking first: a FIFO nobody reads is ENXIO instead of a hang */
	o->fd = open(path, O_WRONLY | O_CLOEXEC | (fifo ? O_NONBLOCK : 0));
	if (o->fd < 0) {
		int e = errno;
		if (e == ENXIO && fifo)
			return dao_error_set(err, -e,
					     "no reader on FIFO '%s'; start the reader first", path);
		return dao_error_set(err, -e, "cannot open '%s' for writing: %s", path,
				     strerror(e));
	}
	int fl = fifo ? fcntl(o->fd, F_GETFL) : 0;
	if (fifo && (fl < 0 || fcntl(o->fd, F_SETFL, fl & ~O_NONBLOCK) < 0)) {
		int e = errno;
		close(o->fd);
		o->fd = -1;
		return dao_error_set(err, -e, "cannot write '%s': %s", path, strerror(e));
	}
	return 0;
}

/* "-": standard output, written straight into like a FIFO (never a terminal). */
static int open_stdout(struct dao_output_file *o, struct dao_error *err)
{
	if (isatty(STDOUT_FILENO))
		return dao_error_set(err, -EINVAL, "will not write binary data to the terminal "
				     "('-' is standard output): redirect it to a file or a pipe, "
				     "or give a file name");
	o->fd = fcntl(STDOUT_FILENO, F_DUPFD_CLOEXEC, 3);
	if (o->fd < 0) {
		int e = errno;
		return dao_error_set(err, -e, "cannot write to standard output ('-'): %s",
				     strerror(e));
	}
	return 0;
}

/* A regular file is replaced only if it could be written in place: not
 * write-protected (no w bit at all, even for root, as rm -i asks) and
 * writable by this user. */
int dao_output_file_check_replaceable(const char *path, const struct stat *st,
				      struct dao_error *err)
{
	if ((st->st_mode & 0222) && access(path, W_OK) == 0)
		return 0;
	return dao_error_set(err, -EACCES,
			     "'%s' is write-protected (mode %04o, owner uid %u): depthao does not "
			     "replace a file that could not be written; make it writable "
			     "(chmod u+w) or remove it first, or give another name",
			     path, (unsigned)(st->st_mode & 07777), (unsigned)st->st_uid);
}

int dao_output_file_begin(struct dao_output_file *o, const char *path, struct dao_error *err)
{
	struct stat st, lst;
	o->fd = -1;
	o->tmp = o->target = NULL;
	if (!strcmp(path, "-"))
		return open_stdout(o, err);
	int have = stat(path, &st) == 0;
	if (!have && lstat(path, &lst) == 0 && S_ISLNK(lst.st_mode))
		return dao_error_set(err, -ENOENT,
				     "'%s' is a symlink to something that does not exist: depthao "
				     "writes through symlinks only to existing files; remove the "
				     "link or create its target first", path);
	if (have && S_ISDIR(st.st_mode))
		return dao_error_set(err, -EISDIR, "cannot write '%s': it is a directory; give a file "
				     "name", path);
	if (have && (S_ISFIFO(st.st_mode) || S_ISCHR(st.st_mode)))
		return open_stream(o, path, S_ISFIFO(st.st_mode), err);
	if (have && !S_ISREG(st.st_mode))
		return dao_error_set(err, -EINVAL,
				     "cannot write '%s': it is a %s, not a file, FIFO or character "
				     "device",
				     path, S_ISBLK(st.st_mode) ? "block device" : "socket");
	int r;
	if (have && (r = dao_output_file_check_replaceable(path, &st, err)) < 0)
		return r;
	/* a symlink to a file: replace the file it points to, keep the link */
	if (have && lstat(path, &lst) == 0 && S_ISLNK(lst.st_mode))
		o->target = realpath(path, NULL);
	else
		o->target = strdup(path);
	size_t n = o->target ? strlen(o->target) + 16 : 0;
	if (!o->target || !(o->tmp = malloc(n))) {
		release(o);
		return dao_error_set(err, -ENOMEM, "out of memory writing '%s'", path);
	}
	snprintf(o->tmp, n, "%s.tmp-XXXXXX", o->target);
	o->fd = mkstemp(o->tmp);
	if (o->fd >= 0)
		fcntl(o->fd, F_SETFD, FD_CLOEXEC);
	if (o->fd < 0) {
		int e = errno;
		release(o);
		return dao_error_set(err, -e, "cannot create '%s': %s", path, strerror(e));
	}
	return 0;
}

int dao_output_file_finish(struct dao_output_file *o, const char *path, struct dao_error *err)
{
	int r = 0;
	if (o->tmp) {
		dao_file_mode_default(o->tmp);
		if (rename(o->tmp, o->target) != 0) {
			int e = errno;
			unlink(o->tmp);
			r = dao_error_set(err, -e, "cannot move the written file into place as '%s': %s",
					  path, strerror(e));
		}
	}
	release(o);
	return r;
}

void dao_output_file_abandon(struct dao_output_file *o)
{
	if (o->tmp)
		unlink(o->tmp);
	release(o);
}

/* The public, opaque handle: the same struct on the heap, with the path its
 * messages name. */
int dao_output_file_open(struct dao_output_file **out, const char *path, struct dao_error *err)
{
	*out = NULL;
	struct dao_output_file *o = calloc(1, sizeof *o);
	if (!o || !(o->path = strdup(path))) {
		free(o);
		return dao_error_set(err, -ENOMEM, "out of memory writing '%s'", path);
	}
	int r = dao_output_file_begin(o, path, err);
	if (r < 0) {
		free(o->path);
		free(o);
		return r;
	}
	*out = o;
	return 0;
}

int dao_output_file_fd(const struct dao_output_file *o)
{
	return o ? o->fd : -1;
}

int dao_output_file_commit(struct dao_output_file *o, struct dao_error *err)
{
	if (!o)
		return dao_error_set(err, -EINVAL, "no output file to commit");
	int r = dao_output_file_finish(o, o->path, err);
	free(o->path);
	free(o);
	return r;
}

void dao_output_file_discard(struct dao_output_file *o)
{
	if (!o)
		return;
	dao_output_file_abandon(o);
	free(o->path);
	free(o);
}
