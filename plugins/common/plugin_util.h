/* SPDX-License-Identifier: MIT */
/* Small helpers every plugin needs (plugins see only the public API). */
#ifndef DAO_PLUGIN_UTIL_H
#define DAO_PLUGIN_UTIL_H

#include <stdarg.h>
#include <stdio.h>

#include <depthao/error.h>

/* Fills `err` (if not NULL) like the library does; returns `code`. */
__attribute__((format(printf, 3, 4))) static inline int
plugin_error(struct dao_error *err, int code, const char *fmt, ...)
{
	if (err) {
		va_list ap;
		va_start(ap, fmt);
		err->code = code;
		vsnprintf(err->message, sizeof(err->message), fmt, ap);
		va_end(ap);
	}
	return code;
}

#endif
