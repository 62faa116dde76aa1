#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""depthaod under systemd's notification protocol, without systemd (issue #16, item 13).

The test binds the unix datagram socket that $NOTIFY_SOCKET names, as systemd does, and
runs depthaod with $WATCHDOG_USEC (and $WATCHDOG_PID = its own pid, through exec):
  - a live source: READY=1, STATUS=... with the frame rate, WATCHDOG=1 at least every
    WATCHDOG_USEC (also while paused, i.e. idle), RELOADING=1 then READY=1 on SIGHUP,
    STOPPING=1 on SIGTERM;
  - a source that cannot be opened: READY=1 with a status saying so, pings go on;
  - a pipeline stuck inside a frame (manual playback into a sink that blocks): the pings
    stop, so systemd would restart the service;
  - a source whose read never returns (a hung driver): the pings stop too;
  - $WATCHDOG_PID naming another process: no pings.
usage: test_daemon_notify.py DEPTHAOD DEPTHAO JSON_GET PNG_INFO TEST_PLUGIN_DIR
"""
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

DAEMON, DEPTHAO, _, _, PLUGINS = sys.argv[1:6]
ROOT = os.environ["DAO_SOURCE_ROOT"]
REC = os.path.join(ROOT, "recordings", "spheres-rolling.oni")
failures = []


def fail(msg):
    print("FAIL: " + msg)
    failures.append(msg)


class Listener:
    """The notification socket: every datagram with the time it arrived."""

    def __init__(self, path):
        self.sock = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
        self.sock.bind(path)
        self.path = path
        self.msgs = []  # (monotonic seconds, {key: value})

    def pump(self, seconds):
        end = time.monotonic() + seconds
        while True:
            left = end - time.monotonic()
            if left <= 0:
                return
            self.sock.settimeout(left)
            try:
                data = self.sock.recv(4096)
            except socket.timeout:
                return
            fields = dict(line.split("=", 1) for line in data.decode().split("\n") if "=" in line)
            self.msgs.append((time.monotonic(), fields))

    def wait_for(self, key, value=None, seconds=10.0, since=0.0):
        """The first message since `since` with key (= value): its time, or None."""
        end = time.monotonic() + seconds
        while True:
            for t, m in self.msgs:
                if t >= since and key in m and (value is None or m[key] == value):
                    return t
            if time.monotonic() >= end:
                return None
            self.pump(min(0.2, end - time.monotonic()))

    def times(self, key, since=0.0):
        return [t for t, m in self.msgs if t >= since and key in m]

    def statuses(self, since=0.0):
        return [m["STATUS"] for t, m in self.msgs if t >= since and "STATUS" in m]

    def close(self):
        self.sock.close()


def start(work, listener, args, watchdog_usec, pid_is_self=True, env_extra=None):
    env = dict(os.environ, NOTIFY_SOCKET=listener.path, WATCHDOG_USEC=str(watchdog_usec),
               DEPTHAO_PLUGIN_PATH=PLUGINS)
    env.update(env_extra or {})
    log = open(os.path.join(work, "log"), "ab")
    # WATCHDOG_PID as systemd sets it: the pid of the service process (the shell's pid,
    # which exec hands to depthaod), or another one
    pid = '$$' if pid_is_self else '1'
    cmd = ["sh", "-c", 'WATCHDOG_PID=%s exec "$0" "$@"' % pid, DAEMON] + args
    return subprocess.Popen(cmd, env=env, stderr=log, stdout=subprocess.DEVNULL)


def stop(proc, listener):
    proc.send_signal(signal.SIGTERM)
    t0 = time.monotonic()
    while proc.poll() is None and time.monotonic() - t0 < 5:
        listener.pump(0.1)
    if proc.poll() is None:
        proc.kill()
        proc.wait()
        fail("depthaod did not stop within 5 s of SIGTERM")
    listener.pump(0.2)
    return proc.returncode


def max_gap(times):
    return max((b - a for a, b in zip(times, times[1:])), default=float("inf"))


def healthy(work):
    """A live 30 fps source: readiness, status, steady pings (also paused), reload, stop."""
    lis = Listener(os.path.join(work, "notify-healthy"))
    ini = os.path.join(work, "d.ini")
    with open(ini, "w") as f:
        f.write("[source]\nuri = testsrc:fps=30\n[sink.null]\nuri = y4m:/dev/null\n"
                "[ao]\nradius = 0.3\n[daemon]\nstats_interval = 0\n")
    sock = os.path.join(work, "ctl.sock")
    wd = 3000000  # 3 s: pings every 0.75 s
    proc = start(work, lis, ["-c", ini, "--socket", sock], wd)
    t_ready = lis.wait_for("READY", "1")
    if t_ready is None:
        fail("no READY=1 within 10 s: %s" % lis.msgs)
        stop(proc, lis)
        return
    # two status periods: a status with the frame rate, and pings
    lis.pump(5.0)
    fps = [s for s in lis.statuses() if "fps" in s]
    if not fps:
        fail("no STATUS with the frame rate: %s" % lis.statuses())
    else:
        print("status: %s" % fps[-1])
        rate = float(fps[-1].split(" fps")[0])
        if not 5 <= rate <= 40:
            fail("status frame rate %.1f for a 30 fps source" % rate)
    pings = lis.times("WATCHDOG", since=t_ready)
    print("%d pings in %.1f s after READY, largest gap %.2f s" %
          (len(pings), time.monotonic() - t_ready, max_gap(pings)))
    if len(pings) < 4:
        fail("only %d WATCHDOG=1 in 5 s with WATCHDOG_USEC=3 s" % len(pings))
    elif max_gap(pings) >= wd / 1e6:
        fail("a gap of %.2f s between pings, WATCHDOG_USEC is %.1f s" % (max_gap(pings), wd / 1e6))
    # paused: the processing thread idles and still proves it is alive
    subprocess.run([DEPTHAO, "ctl", "--socket", sock, "pause"], check=True,
                   stdout=subprocess.DEVNULL)
    t_pause = time.monotonic()
    lis.pump(3.0)
    paused = lis.times("WATCHDOG", since=t_pause)
    if len(paused) < 2 or max_gap([t_pause] + paused + [time.monotonic()]) >= wd / 1e6:
        fail("pings while paused: %d, largest gap %.2f s" % (len(paused), max_gap(paused)))
    if not any(s.startswith("paused") for s in lis.statuses(since=t_pause)):
        fail("no paused status: %s" % lis.statuses(since=t_pause))
    subprocess.run([DEPTHAO, "ctl", "--socket", sock, "resume"], check=True,
                   stdout=subprocess.DEVNULL)
    # SIGHUP: RELOADING=1 (with the monotonic time) and READY=1 again
    t_hup = time.monotonic()
    proc.send_signal(signal.SIGHUP)
    t_rel = lis.wait_for("RELOADING", "1", since=t_hup)
    t_re = lis.wait_for("READY", "1", since=t_hup)
    if t_rel is None or t_re is None or t_re < t_rel:
        fail("SIGHUP: RELOADING=1 then READY=1 expected: %s" % lis.msgs[-5:])
    elif not any("MONOTONIC_USEC" in m for t, m in lis.msgs if t >= t_hup):
        fail("RELOADING=1 without MONOTONIC_USEC")
    t_term = time.monotonic()
    code = stop(proc, lis)
    if code != 0:
        fail("exit status %d after SIGTERM" % code)
    if lis.wait_for("STOPPING", "1", seconds=0.5, since=t_term) is None:
        fail("no STOPPING=1 after SIGTERM: %s" % lis.msgs[-3:])
    lis.close()


def missing_source(work):
    """READY=1 although the camera is not there (it is retried); the status says so; pings go on."""
    lis = Listener(os.path.join(work, "notify-missing"))
    proc = start(work, lis, ["--source", "testsrc:absent=1",
                             "--sink", "y4m:/dev/null", "--set", "source.retry_initial_ms=50",
                             "--set", "source.retry_max_ms=200", "--stats-interval", "0"],
                 2000000)
    t_ready = lis.wait_for("READY", "1")
    if t_ready is None:
        fail("missing source: no READY=1: %s" % lis.msgs)
    else:
        lis.pump(4.0)
        st = lis.statuses()
        if not st or not st[0].startswith("waiting for the source"):
            fail("missing source: status %s" % st)
        pings = lis.times("WATCHDOG", since=t_ready)
        if len(pings) < 4 or max_gap(pings) >= 2.0:
            fail("missing source: %d pings, largest gap %.2f s" % (len(pings), max_gap(pings)))
    stop(proc, lis)
    lis.close()


def stuck(work):
    """Manual playback into a sink that blocks: the processing thread waits inside a frame
    for that sink, so its pings stop; systemd would kill and restart the service."""
    lis = Listener(os.path.join(work, "notify-stuck"))
    proc = start(work, lis, ["--source", REC, "--playback", "manual", "--loop",
                             "--sink", "stuck=slowsink:600000", "--set", "sink.stuck.queue=1",
                             "--stats-interval", "0"], 1000000)
    if lis.wait_for("READY", "1") is None:
        fail("stuck: no READY=1: %s" % lis.msgs)
    # wait until the pings have stopped for 3 x WATCHDOG_USEC (at most 20 s)
    end = time.monotonic() + 20
    quiet = 0.0
    while time.monotonic() < end:
        lis.pump(0.25)
        pings = lis.times("WATCHDOG")
        quiet = time.monotonic() - (pings[-1] if pings else 0)
        if pings and quiet >= 3.0:
            break
    pings = lis.times("WATCHDOG")
    print("stuck: %d pings, then none for %.1f s" % (len(pings), quiet))
    if not pings:
        fail("stuck: no pings at all before the pipeline got stuck")
    elif quiet < 3.0:
        fail("stuck: pings go on (last %.1f s ago) while the pipeline is stuck" % quiet)
    if proc.poll() is not None:
        fail("stuck: the daemon exited by itself (%d)" % proc.returncode)
    stop(proc, lis)  # exits 1: the stuck sink misses the stop deadline
    lis.close()


def hung_source(work):
    """A camera whose read never returns (a hung driver): the processing thread idles
    and would go on pinging; the pings stop, so systemd restarts the service."""
    lis = Listener(os.path.join(work, "notify-hung"))
    proc = start(work, lis, ["--source", "testsrc:fps=30,hang_after=10", "--sink", "y4m:/dev/null",
                             "--stats-interval", "0"], 1000000)
    if lis.wait_for("READY", "1") is None:
        fail("hung source: no READY=1: %s" % lis.msgs)
    end = time.monotonic() + 20
    quiet = 0.0
    while time.monotonic() < end:
        lis.pump(0.25)
        pings = lis.times("WATCHDOG")
        quiet = time.monotonic() - (pings[-1] if pings else 0)
        if pings and quiet >= 3.0:
            break
    pings = lis.times("WATCHDOG")
    print("hung source: %d pings, then none for %.1f s" % (len(pings), quiet))
    if not pings:
        fail("hung source: no pings at all before the source hung")
    elif quiet < 3.0:
        fail("hung source: pings go on (last %.1f s ago) while the source's read hangs" % quiet)
    stop(proc, lis)  # the read is abandoned at the stop deadline
    with open(os.path.join(work, "log")) as f:
        if "watchdog pings stop so that systemd restarts" not in f.read():
            fail("hung source: the log does not say why the pings stopped")
    lis.close()


def other_pid(work):
    """WATCHDOG_PID names another process: the watchdog is not ours, no pings."""
    lis = Listener(os.path.join(work, "notify-otherpid"))
    proc = start(work, lis, ["--source", "testsrc:fps=30", "--sink", "y4m:/dev/null",
                             "--stats-interval", "0"], 500000, pid_is_self=False)
    if lis.wait_for("READY", "1") is None:
        fail("other pid: no READY=1")
    lis.pump(1.5)
    if lis.times("WATCHDOG"):
        fail("other pid: %d pings for a watchdog of another process" % len(lis.times("WATCHDOG")))
    stop(proc, lis)
    lis.close()


def main():
    # meson says whether libsystemd was found; then depthaod must notify (not skip)
    if os.environ.get("DAO_HAVE_SYSTEMD") == "0":
        print("SKIP: built without libsystemd (meson -Dsystemd, libsystemd-dev)")
        sys.exit(77)
    version = subprocess.run([DAEMON, "--version"], capture_output=True, text=True).stdout
    if "systemd notification: yes" not in version:
        fail("built with libsystemd, but --version says: %s" % version.strip())
    work = tempfile.mkdtemp(prefix="daod-notify.")
    try:
        healthy(work)
        missing_source(work)
        stuck(work)
        hung_source(work)
        other_pid(work)
        if failures:
            with open(os.path.join(work, "log")) as f:
                print("depthaod's log:\n" + f.read()[-3000:])
    finally:
        shutil.rmtree(work, ignore_errors=True)
    if failures:
        print("%d failure(s)" % len(failures))
        sys.exit(1)
    print("all passed")


if __name__ == "__main__":
    main()
