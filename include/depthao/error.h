/* SPDX-License-Identifier: MIT */
/*
 * Error reporting.
 *
 * Every fallible libdepthao function returns 0 on success or a negative
 * errno-style code (-EINVAL, -ENOMEM, -EIO, ...).  Functions whose failure a
 * user can cause also take an optional `struct dao_error *`; when it is not
 * NULL it receives the code and a one-line message saying what was wrong and
 * what to do about it.
 */
#ifndef DEPTHAO_ERROR_H
#define DEPTHAO_ERROR_H

#include <depthao/api.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Size of struct dao_error's message buffer, NUL included. */
#define DAO_ERROR_MESSAGE_MAX 256

/* An error: the code every call returns, and a message saying what and where. */
struct dao_error {
	int code;                             /* negative errno, 0 = none */
	char message[DAO_ERROR_MESSAGE_MAX];  /* NUL-terminated, no newline */
};

/* A short description of a negative error code (never NULL). */
DAO_API const char *dao_strerror(int code);

/*
 * Fills `err` (when not NULL) with `code` and a printf-formatted message, as
 * the library does; returns `code`.  For plugins and programs that report
 * their own errors through a struct dao_error.
 */
DAO_API int dao_error_set(struct dao_error *err, int code, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));

/* Clears `err` (code 0, empty message); NULL-safe. */
DAO_API void dao_error_clear(struct dao_error *err);

#ifdef __cplusplus
}
#endif
#endif
