/* SPDX-License-Identifier: MIT */
/*
 * Logging to stderr with levels.  Under systemd (JOURNAL_STREAM set) lines
 * carry a "<N>" priority prefix and no timestamp, which journald reads; on a
 * terminal they carry a local timestamp.  Thread-safe (one write per line).
 */
#ifndef DAOD_LOG_H
#define DAOD_LOG_H

#include <stdint.h>

enum log_level { LOG_ERROR = 0, LOG_WARN, LOG_INFO, LOG_DEBUG };

void log_init(enum log_level level);
void log_set_level(enum log_level level);
/* "error", "warn", "info", "debug" -> level; -1 if unknown. */
int log_level_parse(const char *name);

void log_msg(enum log_level level, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/*
 * A rate limit for one kind of message that may repeat (a failing sink, a
 * flood of control requests): at most `burst` lines per `interval_ms`; the
 * lines in between are counted, and the next line logged says how many were
 * left out.  One thread uses a limiter at a time.
 */
struct log_limit {
	unsigned interval_ms, burst;
	uint64_t window_start_ns;   /* when the current window began (0 = none yet) */
	unsigned in_window;         /* lines logged in it */
	unsigned long long suppressed;
};

#define LOG_LIMIT_INIT(interval_ms, burst) {(interval_ms), (burst), 0, 0, 0}

/* Logs like log_msg, through the limit; returns 1 if the line was written. */
int log_limited(struct log_limit *l, enum log_level level, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));
/* Says "<what>: N more like this were not logged" if some were held back. */
void log_limit_flush(struct log_limit *l, enum log_level level, const char *what);

#define log_error(...) log_msg(LOG_ERROR, __VA_ARGS__)
#define log_warn(...) log_msg(LOG_WARN, __VA_ARGS__)
#define log_info(...) log_msg(LOG_INFO, __VA_ARGS__)
#define log_debug(...) log_msg(LOG_DEBUG, __VA_ARGS__)

#endif
