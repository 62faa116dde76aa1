#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The viewer in a real browser: headless Chromium driven through chromedriver's
WebDriver HTTP API (python3's urllib only).  The live image changes between
screenshots; moving the shade-power slider changes /api/params and darkens the
picture; 10 concurrent stream clients each get frames while the page watches.
Skips (77) without chromium and chromedriver.
usage: test_web_browser.py DEPTHAOD PLUGIN_DIR [SCREENSHOT.png]"""
import base64
import json
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request
import zlib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from webtest import SKIP, Daemon, MjpegReader, fail, free_port  # noqa: E402

ELEMENT = "element-6066-11e4-a52e-4f735466cecf"  # W3C WebDriver element key


def find_browser():
    chrome = next((shutil.which(n) for n in ("chromium", "chromium-browser", "google-chrome")
                   if shutil.which(n)), None)
    driver = shutil.which("chromedriver")
    if not chrome or not driver:
        print("SKIP: chromium and chromedriver are needed (Debian: apt-get install chromium "
              "chromium-driver)")
        sys.exit(SKIP)
    return chrome, driver


class WebDriver:
    def __init__(self, chrome, driver):
        self.port = free_port()
        self.profile = tempfile.mkdtemp(prefix="web-chrome-")
        self.proc = subprocess.Popen([driver, "--port=%d" % self.port],
                                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        self.base = "http://127.0.0.1:%d" % self.port
        deadline = time.monotonic() + 60
        while True:
            try:
                self.call("GET", "/status")
                break
            except (urllib.error.URLError, ConnectionError):
                if time.monotonic() > deadline:
                    fail("chromedriver did not answer in 60 s")
                time.sleep(0.2)
        caps = {"capabilities": {"alwaysMatch": {"browserName": "chrome", "goog:chromeOptions": {
            "binary": chrome,
            "args": ["--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                     "--window-size=1100,900", "--user-data-dir=" + self.profile,
                     "--no-first-run", "--disable-extensions"]}}}}
        self.sid = self.call("POST", "/session", caps)["sessionId"]

    def call(self, method, path, body=None, timeout=120):
        data = json.dumps(body).encode() if body is not None else None
        req = urllib.request.Request(self.base + path, data=data, method=method,
                                     headers={"Content-Type": "application/json"})
        try:
            with urllib.request.urlopen(req, timeout=timeout) as r:
                return json.loads(r.read())["value"]
        except urllib.error.HTTPError as e:
            fail("WebDriver %s %s: %d %s" % (method, path, e.code, e.read()[:500]))

    def s(self, method, path, body=None):
        return self.call(method, "/session/%s%s" % (self.sid, path), body)

    def js(self, script, *args):
        return self.s("POST", "/execute/sync", {"script": script, "args": list(args)})

    def element(self, css):
        v = self.s("POST", "/element", {"using": "css selector", "value": css})
        if not isinstance(v, dict) or ELEMENT not in v:
            fail("WebDriver: no element %s: %r" % (css, v))
        return v[ELEMENT]

    def shot(self, eid):
        return base64.b64decode(self.s("GET", "/element/%s/screenshot" % eid))

    def close(self):
        try:
            self.call("DELETE", "/session/%s" % self.sid, timeout=30)
        except Exception:  # noqa: BLE001 (the driver goes anyway)
            pass
        self.proc.terminate()
        self.proc.wait()
        shutil.rmtree(self.profile, ignore_errors=True)


def png_pixels(png):
    """(width, height, rows of RGB bytes) of an 8-bit RGB or RGBA PNG (what Chromium writes)."""
    if png[:8] != b"\x89PNG\r\n\x1a\n":
        fail("not a PNG screenshot")
    pos, idat, w = 8, b"", 0
    while pos < len(png):
        n, kind = struct.unpack(">I4s", png[pos:pos + 8])
        data = png[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, ctype = struct.unpack(">IIBB", data[:10])
            if depth != 8 or ctype not in (2, 6):
                fail("screenshot PNG depth %d type %d" % (depth, ctype))
            bpp = 3 if ctype == 2 else 4
        elif kind == b"IDAT":
            idat += data
        pos += 12 + n
    raw = zlib.decompress(idat)
    stride = w * bpp
    rows, prev = [], bytearray(stride)
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):  # PNG filters (RFC 2083, 6.2-6.6)
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], prev[i - bpp] if i >= bpp else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    return w, h, bpp, rows


def stats_of(png, step=4):
    """Mean brightness and the sampled pixels (every step-th pixel, each way)."""
    w, h, bpp, rows = png_pixels(png)
    px = [sum(rows[y][x * bpp:x * bpp + 3]) / 3 for y in range(0, h, step) for x in range(0, w, step)]
    return sum(px) / len(px), px


def diff(a, b):
    return sum(abs(x - y) for x, y in zip(a, b)) / max(1, len(a))


def wait_image(wd, timeout=60):
    """The <img> shows a decoded frame (naturalWidth > 0)."""
    end = time.monotonic() + timeout
    while not wd.js("return document.getElementById('live').naturalWidth"):
        if time.monotonic() > end:
            fail("the live image shows no frame after %d s" % timeout)
        time.sleep(0.2)


def main():
    depthaod, plugins = sys.argv[1], sys.argv[2]
    out_png = sys.argv[3] if len(sys.argv) > 3 else None
    chrome, driver = find_browser()
    d = Daemon(depthaod, plugins, "control=true")
    wd = None
    try:
        wd = WebDriver(chrome, driver)
        wd.s("POST", "/url", {"url": "http://127.0.0.1:%d/" % d.port})
        wait_image(wd)
        # the sliders come from the parameter table
        names = wd.js("return [...document.querySelectorAll('#params [name]')].map(e => e.name)")
        for need in ("radius", "slices", "steps", "thickness", "algorithm", "denoise", "shade-power"):
            if need not in names:
                fail("the page has no control for %s (it has %r)" % (need, names))
        opts = wd.js("return [...document.getElementById('stream').options].map(o => o.value)")
        if opts != ["shaded", "ao", "depth"]:
            fail("stream choices %r" % opts)
        # statistics are shown, and refresh
        end = time.monotonic() + 30
        while "fps" not in (wd.js("return document.getElementById('stats').textContent") or ""):
            if time.monotonic() > end:
                fail("no statistics on the page")
            time.sleep(0.3)
        # the camera's motion is shown once it is followed
        def stats():
            return wd.js("return document.getElementById('stats').textContent") or ""
        if "camera motion" in stats():
            fail("camera motion shown while it is not followed: %r" % stats())
        st, _, body = d.request("POST", "/api/params", json.dumps({"depth-temporal-motion": "icp"}),
                                {"Content-Type": "application/json"})
        if st != 200:
            fail("setting depth-temporal-motion: %d %s" % (st, body[:200]))
        end = time.monotonic() + 30
        while not any(s in stats() for s in ("stillcamera motion", "appliedcamera motion")):
            if time.monotonic() > end:
                fail("no camera motion on the page with depth-temporal-motion icp: %r" % stats())
            time.sleep(0.3)
        print("motion followed: %r" % stats())
        # ... and gone again once it is switched off
        st, _, body = d.request("POST", "/api/params", json.dumps({"depth-temporal-motion": "off"}),
                                {"Content-Type": "application/json"})
        if st != 200:
            fail("setting depth-temporal-motion off: %d %s" % (st, body[:200]))
        end = time.monotonic() + 30
        while "camera motion" in stats():
            if time.monotonic() > end:
                fail("camera motion still shown with depth-temporal-motion off: %r" % stats())
            time.sleep(0.3)
        # live: the picture changes between screenshots (the spheres roll)
        img = wd.element("#live")
        shots = []
        for _ in range(3):
            shots.append(stats_of(wd.shot(img)))
            time.sleep(1.0)
        natural = max(diff(shots[i][1], shots[i + 1][1]) for i in range(2))
        wobble = max(s[0] for s in shots) - min(s[0] for s in shots)
        if natural < 0.5:
            fail("the live image did not change between screenshots (mean difference %.2f)" % natural)
        if out_png:
            with open(out_png, "wb") as f:
                f.write(base64.b64decode(wd.s("GET", "/screenshot")))
        # a slider moved with the pointer: shade-power near its top darkens the picture
        before = float(next(p["value"] for p in d.json("GET", "/api/params")[1]["params"]
                            if p["name"] == "shade-power"))
        slider = wd.element('#params input[name="shade-power"]')
        wd.js("arguments[0].scrollIntoView({block: 'center'})", {ELEMENT: slider})
        width = wd.js("return arguments[0].getBoundingClientRect().width", {ELEMENT: slider})
        wd.s("POST", "/actions", {"actions": [{"type": "pointer", "id": "mouse",
                                               "parameters": {"pointerType": "mouse"}, "actions": [
            {"type": "pointerMove", "origin": {ELEMENT: slider}, "x": int(width * 0.42), "y": 0},
            {"type": "pointerDown", "button": 0}, {"type": "pointerUp", "button": 0}]}]})
        end = time.monotonic() + 30
        while True:
            after = float(next(p["value"] for p in d.json("GET", "/api/params")[1]["params"]
                               if p["name"] == "shade-power"))
            if after > before + 3:
                break
            if time.monotonic() > end:
                fail("moving the slider did not change shade-power (%.2f -> %.2f)" % (before, after))
            time.sleep(0.2)
        wd.js("window.scrollTo(0, 0)")
        dark = None
        end = time.monotonic() + 30
        while True:
            time.sleep(1.0)
            dark = stats_of(wd.shot(img))
            drop = shots[-1][0] - dark[0]
            # the rolling spheres change the mean brightness by `wobble` by themselves
            # (measured 0.1-1); shade-power 1 -> 7.5 lowers it by about 44 of 255
            if drop > max(10.0, 3 * wobble):
                break
            if time.monotonic() > end:
                fail("shade-power %.2f -> %.2f did not darken the picture: brightness %.1f -> "
                     "%.1f (it varies by %.2f by itself)" %
                     (before, after, shots[-1][0], dark[0], wobble))
        print("live: frames differ by %.2f, brightness by %.2f; shade-power %.2f -> %.2f: "
              "brightness %.1f -> %.1f" % (natural, wobble, before, after, shots[-1][0], dark[0]))
        # 10 concurrent stream clients each get frames, the page's among the watchers
        readers = [MjpegReader(d.port, ("shaded", "ao", "depth")[i % 3]) for i in range(10)]
        counts = [0] * 10
        end = time.monotonic() + 8
        while time.monotonic() < end:
            for i, r in enumerate(readers):
                counts[i] += r.pump(0.05)
        clients = d.stats()["http"]["clients"]
        for r in readers:
            r.close()
        print("10 clients: frames %r; clients counted %d" % (counts, clients))
        if min(counts) < 5 or any(r.bad for r in readers):
            fail("10 concurrent clients: frames %r (%d bad)" % (counts, sum(r.bad for r in readers)))
        if clients < 11:
            fail("%d clients counted with the page and 10 readers" % clients)
        # a phone's screen: nothing wider than the window, the picture across it
        wd.s("POST", "/window/rect", {"width": 390, "height": 844})
        end = time.monotonic() + 30
        while True:
            m = wd.js("const e = document.documentElement;"
                      "return [e.scrollWidth, e.clientWidth,"
                      "        document.getElementById('live').getBoundingClientRect().width]")
            if m[1] < 500 and m[0] <= m[1] and m[2] >= 0.85 * m[1]:
                break
            if time.monotonic() > end:
                fail("on a 390 px wide window: page %d px wide in %d, picture %d px" % tuple(m))
            time.sleep(0.3)
        print("phone: page %d px in a %d px window, picture %d px" % tuple(m))
        print("ok")
    finally:
        if wd:
            wd.close()
        d.stop()
        d.close()


main()
