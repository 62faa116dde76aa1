/* SPDX-License-Identifier: MIT */
/* The plumbing the recording sinks share (recorder_sink.h). */
#include "plugin/recorder_sink.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error_internal.h"
#include "plugin/output_path.h"

int dao_recorder_init(struct dao_recorder *r, const char *scheme, const char *uri, size_t n,
		      const char *help, struct dao_error *err)
{
	memset(r, 0, sizeof *r);
	r->scheme = scheme;
	if (n == 0)
		return dao_error_set(err, -EINVAL, "%s: no output file given; use %s:PATH.%s%s",
				     scheme, scheme, scheme, help);
	if (!(r->path = strndup(uri, n)))
		return dao_error_set(err, -ENOMEM, "out of memory");
	return 0;
}

void dao_recorder_free(struct dao_recorder *r)
{
	free(r->file);
	free(r->path);
	r->file = r->path = NULL;
}

int dao_recorder_check_dir(const struct dao_recorder *r, int regular_only,
			   struct dao_error *err)
{
	struct stat st;
	const char *path = r->path;
	if (stat(path, &st) == 0 && S_ISDIR(st.st_mode))
		return dao_error_set(err, -EISDIR,
				     "%s: %s is a directory; give the path of the .%s file to write",
				     r->scheme, path, r->scheme);
	if (regular_only && stat(path, &st) == 0 && !S_ISREG(st.st_mode))
		return dao_error_set(err, -EINVAL,
				     "%s: %s is not a regular file (a device, FIFO or socket); "
				     "the recorder writes .%s files",
				     r->scheme, path, r->scheme);
	const char *slash = strrchr(path, '/');
	char *dir = slash ? strndup(path, slash == path ? 1 : (size_t)(slash - path)) : strdup(".");
	if (!dir)
		return dao_error_set(err, -ENOMEM, "out of memory");
	int rc = 0;
	if (access(dir, W_OK | X_OK) != 0)
		rc = dao_error_set(err, -errno, "%s: cannot record to %s: directory %s: %s",
				   r->scheme, path, dir, strerror(errno));
	free(dir);
	return rc;
}

void dao_recorder_note(const struct dao_recorder *r, int level, const char *fmt, ...)
{
	char msg[DAO_ERROR_MESSAGE_MAX + 256];
	va_list ap;
	if (!r->host.log)
		return;
	va_start(ap, fmt);
	vsnprintf(msg, sizeof(msg), fmt, ap);
	va_end(ap);
	r->host.log(r->host.user, level, msg);
}

int dao_recorder_open_numbered(struct dao_recorder *r, int overwrite, dao_recorder_open_fn open,
			       void *ctx, struct dao_error *err)
{
	char *name = NULL;
	int rc = open(ctx, r->path, overwrite, err);
	for (unsigned k = 1; rc == -EEXIST && k <= DAO_OUTPUT_NUMBERED_MAX; k++) {
		struct stat st;
		if (!(name = dao_output_numbered(r->path, k)))
			return dao_error_set(err, -ENOMEM, "out of memory");
		rc = lstat(name, &st) == 0 ? -EEXIST : open(ctx, name, 0, err);
		if (rc == 0)
			break;
		free(name);
		name = NULL;
	}
	if (rc == -EEXIST)
		return dao_error_set(err, rc,
				     "%s: %s and its numbered names up to -%u exist; a recording "
				     "never replaces a file (add ?overwrite=true to replace it)",
				     r->scheme, r->path, DAO_OUTPUT_NUMBERED_MAX);
	if (rc < 0)
		return rc;
	if (name) {
		dao_recorder_note(r, DAO_LOG_INFO,
				  "%s: %s exists; recording to %s instead (a recording never "
				  "replaces a file; add ?overwrite=true to replace it)",
				  r->scheme, r->path, name);
		free(r->file);
		r->file = name;
	}
	return 0;
}

const char *dao_recorder_file(const struct dao_recorder *r)
{
	return r->file ? r->file : r->path;
}

void dao_recorder_forget_file(struct dao_recorder *r)
{
	free(r->file);
	r->file = NULL;
}
