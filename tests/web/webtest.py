# SPDX-License-Identifier: MIT
"""Shared by the web suite: depthaod with an http sink on the bundled recording,
and small HTTP/MJPEG clients (python3's standard library only)."""
import http.client
import json
import os
import re
import signal
import socket
import subprocess
import sys
import tempfile
import time

SKIP = 77


def fail(msg):
    print("FAIL: " + msg, file=sys.stderr)
    sys.exit(1)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Daemon:
    """depthaod looping the recording in real time into sink web=http:PORT?OPTS."""

    def __init__(self, depthaod, plugin_dir, opts="", extra=(), source=None):
        root = os.environ.get("DAO_SOURCE_ROOT", ".")
        self.rec = source or os.path.join(root, "recordings", "spheres-rolling.oni")
        self.port = free_port()
        self.log = tempfile.NamedTemporaryFile(prefix="web-", suffix=".log", delete=False)
        uri = "http:%d%s" % (self.port, ("?" + opts) if opts else "")
        env = dict(os.environ, DEPTHAO_PLUGIN_PATH=plugin_dir)
        self.proc = subprocess.Popen([depthaod, "--source", self.rec, "--loop", "--sink",
                                      "web=" + uri, "--stats-interval", "0", *extra],
                                     stdout=self.log, stderr=subprocess.STDOUT, env=env)
        # the sink opens with the first frame: wait for its line (generous: a loaded host)
        deadline = time.monotonic() + 60
        while "the viewer is at" not in self.text():
            if self.proc.poll() is not None:
                fail("depthaod exited %d: %s" % (self.proc.returncode, self.text()))
            if time.monotonic() > deadline:
                self.proc.kill()  # never leave a daemon running behind a failed test
                self.proc.wait()
                fail("the http sink did not open in 60 s: " + self.text())
            time.sleep(0.1)

    def text(self):
        with open(self.log.name) as f:
            return f.read()

    def conn(self, timeout=30):
        return http.client.HTTPConnection("127.0.0.1", self.port, timeout=timeout)

    def request(self, method, path, body=None, headers=None):
        c = self.conn()
        c.request(method, path, body=body, headers=headers or {})
        r = c.getresponse()
        data = r.read()
        c.close()
        return r.status, dict((k.lower(), v) for k, v in r.getheaders()), data

    def json(self, method, path, body=None, headers=None):
        st, h, data = self.request(method, path, body, headers)
        try:
            return st, json.loads(data)
        except ValueError:
            fail("%s %s: %d, not JSON: %r" % (method, path, st, data[:200]))

    def stats(self):
        st, j = self.json("GET", "/api/stats")
        if st != 200:
            fail("/api/stats: %d" % st)
        return j

    def stop(self):
        """SIGTERM; returns the milliseconds until the process is gone."""
        t0 = time.monotonic()
        self.proc.send_signal(signal.SIGTERM)
        try:
            self.proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
            fail("depthaod did not stop in 20 s after SIGTERM: " + self.text())
        return (time.monotonic() - t0) * 1000.0

    def close(self):
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()
        os.unlink(self.log.name)


class MjpegReader:
    """A /stream.mjpg client on a raw socket: counts the complete JPEG parts it read
    (HTTP/1.0: the body is not chunked)."""

    def __init__(self, port, stream="shaded"):
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=30)
        self.sock.sendall(("GET /stream.mjpg?stream=%s HTTP/1.0\r\nHost: x\r\n\r\n" % stream).encode())
        self.buf = b""
        self.frames = 0
        self.bad = 0
        self.last = b""
        self.header = None

    def pump(self, seconds):
        """Reads for `seconds`; returns the frames read meanwhile."""
        n0 = self.frames
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            self.sock.settimeout(max(0.05, end - time.monotonic()))
            try:
                d = self.sock.recv(1 << 16)
            except socket.timeout:
                continue
            if not d:
                break
            self.buf += d
            self.parse()
        return self.frames - n0

    def parse(self):
        if self.header is None:
            i = self.buf.find(b"\r\n\r\n")
            if i < 0:
                return
            self.header = self.buf[:i].decode("latin-1")
            self.buf = self.buf[i + 4:]
        while True:
            m = re.search(rb"--depthaoframe\r\nContent-Type: image/jpeg\r\nContent-Length: (\d+)\r\n\r\n",
                          self.buf)
            if not m or len(self.buf) < m.end() + int(m.group(1)) + 2:
                return
            jpeg = self.buf[m.end():m.end() + int(m.group(1))]
            if jpeg[:2] != b"\xff\xd8" or jpeg[-2:] != b"\xff\xd9":
                self.bad += 1
            self.frames += 1
            self.last = jpeg
            self.buf = self.buf[m.end() + len(jpeg) + 2:]

    def close(self):
        self.sock.close()
