/* SPDX-License-Identifier: MIT */
#include "common/tool_clock.h"
#include "notify.h"

#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include <json-c/json.h>

#include "daemon.h"
#include "log.h"

#if DAOD_HAVE_SYSTEMD
#include <systemd/sd-daemon.h>
#endif

#define STATUS_PERIOD_NS 2000000000ull

static int g_active;                  /* NOTIFY_SOCKET is set */
static uint64_t g_watchdog_usec;      /* 0 = no watchdog */
static atomic_ullong g_last_ping_ns;
static int g_ready;
static uint64_t g_last_status_ns, g_last_processed, g_last_failures;

#if DAOD_HAVE_SYSTEMD
static void notify_send(const char *text)
{
	if (!g_active)
		return;
	int r = sd_notify(0, text);
	if (r < 0)
		log_debug("sd_notify: %d", r);
}

void notify_init(void)
{
	g_active = getenv("NOTIFY_SOCKET") != NULL;
	uint64_t usec = 0;
	if (g_active && sd_watchdog_enabled(0, &usec) > 0) /* WATCHDOG_PID, if set, is ours */
		g_watchdog_usec = usec;
	if (g_watchdog_usec)
		log_info("systemd watchdog: every %.1f s from the processing thread",
			 (double)g_watchdog_usec / 4e6);
}

const char *notify_describe(void)
{
	return "systemd notification: yes (sd_notify: readiness, status, watchdog)";
}
#else
static void notify_send(const char *text)
{
	(void)text;
}

void notify_init(void)
{
	if (getenv("NOTIFY_SOCKET"))
		log_warn("systemd expects notifications ($NOTIFY_SOCKET is set), but this depthaod "
			 "was built without libsystemd: no readiness or watchdog (use Type=simple "
			 "and no WatchdogSec=, or rebuild with libsystemd-dev)");
}

const char *notify_describe(void)
{
	return "systemd notification: no (built without libsystemd)";
}
#endif

uint64_t notify_watchdog_usec(void)
{
	return g_watchdog_usec;
}

void notify_watchdog(void)
{
	if (!g_watchdog_usec)
		return;
	uint64_t t = tool_mono_ns();
	if (t - atomic_load(&g_last_ping_ns) < g_watchdog_usec * 1000u / 4)
		return;
	atomic_store(&g_last_ping_ns, t);
	notify_send("WATCHDOG=1");
}

static long long stat_int(struct json_object *j, const char *key)
{
	struct json_object *v;
	return json_object_object_get_ex(j, key, &v) ? json_object_get_int64(v) : 0;
}

/* STATUS=... from the counters: what the pipeline does now. */
static void send_status(struct daemon *d, const char *prefix, uint64_t t)
{
	struct json_object *j = daemon_stats(d, 0);
	long long processed = stat_int(j, "frames_processed");
	long long dropped = stat_int(j, "frames_dropped_in");
	long long opens = stat_int(j, "source_opens"), failures = stat_int(j, "source_failures");
	struct json_object *v;
	int paused = json_object_object_get_ex(j, "paused", &v) && json_object_get_boolean(v);
	json_object_put(j);
	double fps = g_last_status_ns && t > g_last_status_ns
			     ? (double)((uint64_t)processed - g_last_processed) * 1e9 /
				       (double)(t - g_last_status_ns)
			     : 0;
	char text[256];
	if (paused)
		snprintf(text, sizeof text, "%sSTATUS=paused; %lld frames processed", prefix,
			 processed);
	else if ((uint64_t)failures > g_last_failures && (!opens || fps == 0))
		snprintf(text, sizeof text,
			 "%sSTATUS=waiting for the source (%lld failed opens, retrying; see the log)",
			 prefix, failures);
	else if (!g_last_status_ns)
		snprintf(text, sizeof text, "%sSTATUS=running; %lld frames processed", prefix,
			 processed);
	else
		snprintf(text, sizeof text,
			 "%sSTATUS=%.1f fps; %lld frames processed, %lld dropped at the input", prefix,
			 fps, processed, dropped);
	notify_send(text);
	g_last_status_ns = t;
	g_last_processed = (uint64_t)processed;
	g_last_failures = (uint64_t)failures;
}

void notify_tick(struct daemon *d)
{
	if (!g_active)
		return;
	uint64_t t = tool_mono_ns();
	if (!g_ready) {
		struct json_object *j = daemon_stats(d, 0);
		int tried = stat_int(j, "source_opens") + stat_int(j, "source_failures") > 0;
		json_object_put(j);
		if (!tried)
			return;
		g_ready = 1;
		send_status(d, "READY=1\n", t);
		return;
	}
	if (t - g_last_status_ns >= STATUS_PERIOD_NS)
		send_status(d, "", t);
}

void notify_reloading(void)
{
	char text[96];
	snprintf(text, sizeof text, "RELOADING=1\nSTATUS=reloading [ao]\nMONOTONIC_USEC=%llu",
		 (unsigned long long)(tool_mono_ns() / 1000u));
	notify_send(text);
}

void notify_reloaded(void)
{
	notify_send("READY=1\nSTATUS=reloaded [ao]");
}

void notify_stopping(const char *why)
{
	char text[160];
	snprintf(text, sizeof text, "STOPPING=1\nSTATUS=stopping: %s", why);
	notify_send(text);
}
