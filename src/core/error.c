/* SPDX-License-Identifier: MIT */
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include <depthao/error.h>

#include "core/error_internal.h"

const char *dao_strerror(int code)
{
	switch (code) {
	case 0: return "success";
	case -EINVAL: return "invalid argument";
	case -ENOMEM: return "out of memory";
	case -ENOENT: return "no such file or directory";
	case -EACCES: return "permission denied";
	case -EIO: return "input/output error";
	case -EAGAIN: return "try again";
	case -EDOM: return "outside the domain";
	case -ENODEV: return "no such device";
	case -ENOSPC: return "no space left on device";
	case -EOVERFLOW: return "value too large";
	case -ENOTSUP: return "not supported";
	case -ENXIO: return "no such device or address (no reader on a FIFO)";
	case -EPIPE: return "broken pipe (the reader went away)";
	case -ENOTDIR: return "not a directory";
	case -EISDIR: return "is a directory";
	case -ERANGE: return "value out of range";
	case -EEXIST: return "already exists";
	case -ETIMEDOUT: return "timed out";
	case -EBUSY: return "busy";
	case -ENODATA: return "no data";
	case -EFBIG: return "file too large";
	default: return "unknown error";
	}
}

int dao_error_set(struct dao_error *err, int code, const char *fmt, ...)
{
	if (err) {
		va_list ap;
		err->code = code;
		va_start(ap, fmt);
		vsnprintf(err->message, sizeof err->message, fmt, ap);
		va_end(ap);
	}
	return code;
}

void dao_error_clear(struct dao_error *err)
{
	if (err) {
		err->code = 0;
		err->message[0] = '\0';
	}
}
