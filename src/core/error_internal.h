/* SPDX-License-Identifier: MIT */
#ifndef DAO_CORE_ERROR_INTERNAL_H
#define DAO_CORE_ERROR_INTERNAL_H

#include <depthao/error.h>

/* Fills `err` (if not NULL) with code and printf-style message; returns code. */
int dao_error_set(struct dao_error *err, int code, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));

void dao_error_clear(struct dao_error *err);

#endif
