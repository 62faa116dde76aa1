/* SPDX-License-Identifier: MIT */
#include "common/tool_clock.h"
#include "log.h"

#include <stdarg.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static atomic_int g_level = LOG_INFO;
static int g_journal;

static const char *const names[] = {"error", "warn", "info", "debug"};
/* syslog priorities: err, warning, info, debug */
static const int priorities[] = {3, 4, 6, 7};

void log_init(enum log_level level)
{
	atomic_store(&g_level, (int)level);
	g_journal = getenv("JOURNAL_STREAM") != NULL;
}

void log_set_level(enum log_level level)
{
	atomic_store(&g_level, (int)level);
}

int log_level_parse(const char *name)
{
	for (int i = 0; i < 4; i++)
		if (!strcmp(name, names[i]))
			return i;
	return -1;
}

static void vlog(enum log_level level, const char *suffix, const char *fmt, va_list ap)
{
	char line[1024];
	size_t n;
	if (g_journal) {
		n = (size_t)snprintf(line, sizeof line, "<%d>", priorities[level]);
	} else {
		struct timespec ts;
		struct tm tm;
		clock_gettime(CLOCK_REALTIME, &ts);
		localtime_r(&ts.tv_sec, &tm);
		n = strftime(line, sizeof line, "%H:%M:%S", &tm);
		n += (size_t)snprintf(line + n, sizeof line - n, ".%03ld %-5s ", ts.tv_nsec / 1000000,
				      names[level]);
	}
	int k = vsnprintf(line + n, sizeof line - n - 1, fmt, ap);
	n = k < 0 ? n : n + (size_t)k;
	if (n > sizeof line - 2)
		n = sizeof line - 2;
	if (suffix && *suffix) {
		k = snprintf(line + n, sizeof line - n - 1, "%s", suffix);
		n = k < 0 ? n : n + (size_t)k;
		if (n > sizeof line - 2)
			n = sizeof line - 2;
	}
	line[n++] = '\n';
	ssize_t w = write(STDERR_FILENO, line, n);
	(void)w;
}

void log_msg(enum log_level level, const char *fmt, ...)
{
	if ((int)level > atomic_load(&g_level))
		return;
	va_list ap;
	va_start(ap, fmt);
	vlog(level, NULL, fmt, ap);
	va_end(ap);
}

int log_limited(struct log_limit *l, enum log_level level, const char *fmt, ...)
{
	uint64_t now = tool_mono_ns();
	if (!l->window_start_ns || now - l->window_start_ns >= (uint64_t)l->interval_ms * 1000000u) {
		l->window_start_ns = now;
		l->in_window = 0;
	}
	if (l->in_window >= l->burst) {
		l->suppressed++;
		return 0;
	}
	l->in_window++;
	if ((int)level > atomic_load(&g_level)) {
		l->suppressed = 0;
		return 0;
	}
	char suffix[96] = "";
	if (l->suppressed)
		snprintf(suffix, sizeof suffix, " (%llu more like this not logged)",
			 l->suppressed);
	l->suppressed = 0;
	va_list ap;
	va_start(ap, fmt);
	vlog(level, suffix, fmt, ap);
	va_end(ap);
	return 1;
}

void log_limit_flush(struct log_limit *l, enum log_level level, const char *what)
{
	if (l->suppressed)
		log_msg(level, "%s: %llu more like this not logged", what, l->suppressed);
	l->suppressed = 0;
}
