/* SPDX-License-Identifier: MIT */
/*
 * depthaod under systemd (Type=notify): readiness, status, reload and stop
 * notices and the watchdog, through libsystemd's sd_notify.  Without
 * $NOTIFY_SOCKET (not started by systemd) every call does nothing; built
 * without libsystemd (meson -Dsystemd=disabled, or libsystemd-dev absent)
 * too, and notify_init() says so in the log when systemd expects notices.
 *
 * When READY=1 is sent: once the pipeline threads run and the first attempt
 * to open the source has finished, whether it opened (frames flow) or failed
 * (it is retried in the background, and STATUS says "waiting for the
 * source").  A sensor that is missing at boot neither fails nor delays the
 * service; the status line shows it.
 *
 * The watchdog proves the processing thread alive: notify_watchdog() is
 * called from its loop, which comes round at least every 100 ms while it
 * waits for frames (or is paused) and once per frame otherwise; it sends
 * WATCHDOG=1 at most every WATCHDOG_USEC / 4.  A frame that takes longer
 * than WatchdogSec (a hung kernel, a deadlock, a sink that blocks a
 * lossless pipeline) stops the pings, and systemd restarts the service.
 */
#ifndef DAOD_NOTIFY_H
#define DAOD_NOTIFY_H

#include <stdint.h>

struct daemon;

/* Reads the environment systemd set ($NOTIFY_SOCKET, $WATCHDOG_USEC); once, before the threads. */
void notify_init(void);

/* "systemd notification: yes (libsystemd N)" or "...: no (built without libsystemd)". */
const char *notify_describe(void);

/* The watchdog interval systemd asked for, in microseconds; 0 = none. */
uint64_t notify_watchdog_usec(void);

/* From the processing loop: WATCHDOG=1, at most every quarter interval. */
void notify_watchdog(void);

/*
 * From the main loop, every few hundred ms: READY=1 once the pipeline is
 * running (see above), then STATUS=... with the frame rate, frame and drop
 * counts every 2 s.
 */
void notify_tick(struct daemon *d);

/* SIGHUP: RELOADING=1 before the reload, READY=1 after it. */
void notify_reloading(void);
void notify_reloaded(void);

/* STOPPING=1 with why, before the pipeline is stopped. */
void notify_stopping(const char *why);

#endif
