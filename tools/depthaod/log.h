/* SPDX-License-Identifier: MIT */
/*
 * Logging to stderr with levels.  Under systemd (JOURNAL_STREAM set) lines
 * carry a "<N>" priority prefix and no timestamp, which journald reads; on a
 * terminal they carry a local timestamp.  Thread-safe (one write per line).
 */
#ifndef DAOD_LOG_H
#define DAOD_LOG_H

enum log_level { LOG_ERROR = 0, LOG_WARN, LOG_INFO, LOG_DEBUG };

void log_init(enum log_level level);
void log_set_level(enum log_level level);
/* "error", "warn", "info", "debug" -> level; -1 if unknown. */
int log_level_parse(const char *name);

void log_msg(enum log_level level, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#define log_error(...) log_msg(LOG_ERROR, __VA_ARGS__)
#define log_warn(...) log_msg(LOG_WARN, __VA_ARGS__)
#define log_info(...) log_msg(LOG_INFO, __VA_ARGS__)
#define log_debug(...) log_msg(LOG_DEBUG, __VA_ARGS__)

#endif
