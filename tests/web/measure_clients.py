#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""How the http sink scales with stream clients (not a test: numbers for docs/viewer.md).
depthaod loops the bundled recording in real time (640x480, 30 fps) into an http sink;
for 0, 1 and N clients of the shaded stream it reports, over WINDOW seconds, the
daemon's CPU time per second (utime + stime from /proc), frames processed, the frames
each client got and the sink's latency (capture -> last bytes handed to the socket).
usage: measure_clients.py DEPTHAOD PLUGIN_DIR [N=10] [WINDOW=10] [depthaod options...]"""
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from webtest import Daemon, MjpegReader  # noqa: E402


def cpu_s(pid):
    with open("/proc/%d/stat" % pid) as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def sink_cpu_s(pid):
    """CPU seconds of the sink's threads: its writer (sink:web) and libmicrohttpd's
    (schedstat: nanoseconds on a CPU; threads that ended are not counted)."""
    total = 0
    for tid in os.listdir("/proc/%d/task" % pid):
        try:
            with open("/proc/%d/task/%s/comm" % (pid, tid)) as f:
                comm = f.read().strip()
            if comm == "sink:web" or comm.startswith("MHD"):
                with open("/proc/%d/task/%s/schedstat" % (pid, tid)) as f:
                    total += int(f.read().split()[0])
        except OSError:
            pass
    return total / 1e9


def main():
    depthaod, plugins = sys.argv[1], sys.argv[2]
    n = int(sys.argv[3]) if len(sys.argv) > 3 else 10
    window = float(sys.argv[4]) if len(sys.argv) > 4 else 10.0
    d = Daemon(depthaod, plugins, "", extra=sys.argv[5:])
    try:
        time.sleep(2)
        for k in (0, 1, n):
            readers = [MjpegReader(d.port) for _ in range(k)]
            for r in readers:
                r.pump(0.2)
            s0, c0, t0 = d.stats(), cpu_s(d.proc.pid), time.monotonic()
            k0 = sink_cpu_s(d.proc.pid)
            counts = [0] * k
            end = t0 + window
            while time.monotonic() < end:
                if readers:
                    for i, r in enumerate(readers):
                        counts[i] += r.pump(0.02)
                else:
                    time.sleep(0.1)
            s1, c1, t1 = d.stats(), cpu_s(d.proc.pid), time.monotonic()
            k1 = sink_cpu_s(d.proc.pid)
            for r in readers:
                r.close()
            secs = t1 - t0
            proc = s1["daemon"]["frames_processed"] - s0["daemon"]["frames_processed"]
            h = s1["http"]
            sink_ms = (k1 - k0) / max(1, proc) * 1000
            print("%2d clients: the sink's threads %.2f ms CPU per frame (%.1f %% of a core at "
                  "30 fps); the daemon %.1f %% of a core, "
                  "%.1f fps processed, per client %s fps, "
                  "latency median %.1f ms p99 %.1f ms (of it in the sink: median %.1f ms p99 %.1f ms), "
                  "encode %.2f ms" %
                  (k, sink_ms, sink_ms * 30 / 10, 100 * (c1 - c0) / secs, proc / secs,
                   "/".join("%.1f" % (c / secs) for c in counts) or "-",
                   h["latency_ms_median"], h["latency_ms_p99"], h["sink_ms_median"],
                   h["sink_ms_p99"], h["encode_ms_mean"]))
            time.sleep(1.5)
    finally:
        d.stop()
        d.close()


main()
