#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""depthao process --poses (issue #37, item 3): the camera's poses from a TUM file.

A 64x48 sequence made here: a camera panning 2 degrees a frame before a slanted
wall with a box, ray-cast per pixel, with a structured-light-like noise
(0.0015 z^2 m, rounded to mm), its true poses in a TUM file (in a world frame
that is not the first camera's).  With the temporal depth filter:

1. the true poses (source) bring the filtered depth closer to the truth than
   the filter without motion;
2. a poses file with no pose at the frames' times gives the output of the
   filter without motion, byte for byte (and a warning);
3. frames named by their timestamps (the TUM benchmark's naming) with the
   poses at other times: interpolated, as good as the exact poses within 5 %;
4. bad files and option misuse fail with messages.

usage: test_cli_poses.py DEPTHAO_CLI
"""

import json
import math
import os
import random
import struct
import subprocess
import sys
import tempfile
import zlib

W, H, F = 64, 48, 60.0
CX, CY = (W - 1) / 2, (H - 1) / 2
FRAMES = 8


def write_png16(path, rows):
    def chunk(kind, data):
        c = struct.pack(">I", len(data)) + kind + data
        return c + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    raw = b"".join(b"\0" + struct.pack(">%dH" % len(r), *r) for r in rows)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", len(rows[0]), len(rows), 16, 0, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw)))
        f.write(chunk(b"IEND", b""))


def read_png16(path):
    """A 16-bit grey PNG (filters None, Sub, Up, Average, Paeth) as rows of ints."""
    data = open(path, "rb").read()
    pos, idat = 8, b""
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, colour = struct.unpack(">IIBB", body[:10])
            assert (depth, colour) == (16, 0)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw, stride, rows, prev = zlib.decompress(idat), 2 * w, [], [0] * (2 * w)
    for y in range(h):
        ft, line = raw[y * (stride + 1)], raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)]
        cur = [0] * stride
        for i in range(stride):
            a = cur[i - 2] if i >= 2 else 0
            b, c = prev[i], prev[i - 2] if i >= 2 else 0
            if ft == 0:
                p = 0
            elif ft == 1:
                p = a
            elif ft == 2:
                p = b
            elif ft == 3:
                p = (a + b) // 2
            else:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                p = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
            cur[i] = (line[i] + p) & 0xFF
        rows.append([cur[2 * i] << 8 | cur[2 * i + 1] for i in range(w)])
        prev = cur
    return rows


def yaw(deg):
    a = math.radians(deg)
    return [[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]]


def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def quat(r):
    """x, y, z, w of a rotation matrix (its trace is large here: small angles)."""
    w = math.sqrt(max(0.0, 1 + r[0][0] + r[1][1] + r[2][2])) / 2
    return [(r[2][1] - r[1][2]) / (4 * w), (r[0][2] - r[2][0]) / (4 * w),
            (r[1][0] - r[0][1]) / (4 * w), w]


def render(r, t, rng):
    """True and noisy depth (mm) seen by the camera (R, t), camera to world."""
    truth, noisy = [], []
    for v in range(H):
        tr, nr = [], []
        for u in range(W):
            d = [(u - CX) / F, (v - CY) / F, 1.0]
            dw = [sum(r[i][k] * d[k] for k in range(3)) for i in range(3)]
            best = math.inf
            # the wall: z = 3 + 0.4 x (world)
            den = dw[2] - 0.4 * dw[0]
            if abs(den) > 1e-9:
                lam = (3 + 0.4 * t[0] - t[2]) / den
                if lam > 0:
                    best = lam
            # the box [-0.3, 0.3] x [-0.2, 1] x [1.6, 2.0]
            lo, hi, tmin, tmax = [-0.3, -0.2, 1.6], [0.3, 1.0, 2.0], 0.0, math.inf
            for i in range(3):
                if abs(dw[i]) < 1e-12:
                    if not lo[i] <= t[i] <= hi[i]:
                        tmax = -1
                    continue
                a, b = (lo[i] - t[i]) / dw[i], (hi[i] - t[i]) / dw[i]
                tmin, tmax = max(tmin, min(a, b)), min(tmax, max(a, b))
            if tmin <= tmax and tmin > 0:
                best = min(best, tmin)
            z = best  # d has z = 1: the distance along it is the depth
            tr.append(int(round(z * 1000)) if z < 10 else 0)
            nr.append(int(round((z + rng.gauss(0, 0.0015 * z * z)) * 1000)) if z < 10 else 0)
        truth.append(tr)
        noisy.append(nr)
    return truth, noisy


def make_sequence(tmp, named_by_time):
    """depth/ (and truth/) of the pan, poses.txt; returns the directory."""
    root = os.path.join(tmp, "timed" if named_by_time else "seq")
    os.makedirs(os.path.join(root, "depth"))
    os.makedirs(os.path.join(root, "truth"))
    rng = random.Random(37)
    g = yaw(25.0)  # the file's world: turned 25 degrees and moved from the first camera's
    gt = [1.5, -0.2, 4.0]
    lines = ["# timestamp tx ty tz qx qy qz qw"]
    for k in range(FRAMES):
        r = yaw(-7.0 + 2.0 * k)
        t = [0.01 * k, 0.0, 0.0]
        truth, noisy = render(r, t, rng)
        ts = (1000.0 if named_by_time else 0.0) + k / 30.0  # index-named: index / fps
        name = "%.6f.png" % ts if named_by_time else "%04d.png" % k
        write_png16(os.path.join(root, "depth", name), noisy)
        write_png16(os.path.join(root, "truth", name), truth)
        rw = matmul(g, r)
        tw = [gt[i] + sum(g[i][j] * t[j] for j in range(3)) for i in range(3)]
        q = quat(rw)
        if named_by_time:  # poses at other times: halfway to the next frame, and before
            if k == 0:
                continue
            rp, tp = matmul(g, yaw(-7.0 + 2.0 * (k - 0.5))), [0.01 * (k - 0.5), 0, 0]
            tw = [gt[i] + sum(g[i][j] * tp[j] for j in range(3)) for i in range(3)]
            q, ts = quat(rp), ts - 0.5 / 30.0
        lines.append("%.6f %.9f %.9f %.9f %.12f %.12f %.12f %.12f" % (ts, *tw, *q))
    if named_by_time:  # one past the last frame, so that every frame but the first is bracketed
        rp, tp = matmul(g, yaw(-7.0 + 2.0 * FRAMES - 1.0)), [0.01 * (FRAMES - 0.5), 0, 0]
        tw = [gt[i] + sum(g[i][j] * tp[j] for j in range(3)) for i in range(3)]
        lines.append("%.6f %.9f %.9f %.9f %.12f %.12f %.12f %.12f"
                     % (1000.0 + (FRAMES - 0.5) / 30.0, *tw, *quat(rp)))
    with open(os.path.join(root, "poses.txt"), "w") as f:
        f.write("\n".join(lines) + "\n")
    with open(os.path.join(root, "depth", "camera.json"), "w") as f:
        json.dump({"width": W, "height": H, "fps": 30.0,
                   "intrinsic_matrix": [F, 0, 0, 0, F, 0, CX, CY, 1]}, f)
    return root


def run(cli, *args, expect=0):
    p = subprocess.run([cli, *args], capture_output=True, text=True)
    if p.returncode != expect:
        sys.exit("FAIL: depthao %s: exit %d (expected %d)\n%s" % (" ".join(args), p.returncode,
                                                                  expect, p.stderr))
    return p.stderr


def check(cond, what):
    if not cond:
        sys.exit("FAIL: " + what)
    print("ok: " + what)


def process(cli, root, out, *extra, expect=0):
    return run(cli, "process", "--input", os.path.join(root, "depth"), "--depth-out", out,
               "--algorithm", "none", "--prefilter", "none", "--depth-temporal", "0.8",
               "--quiet", *extra, expect=expect)


def mae(root, out, first=3):
    """Mean |filtered - true| / true (mm) over frames first.. where both have depth."""
    s = n = 0
    names = sorted(x for x in os.listdir(os.path.join(root, "truth")) if x.endswith(".png"))
    for name in names[first:]:
        a, b = read_png16(os.path.join(out, name)), read_png16(os.path.join(root, "truth", name))
        for ra, rb in zip(a, b):
            for x, y in zip(ra, rb):
                if x and y:
                    s, n = s + abs(x - y) / y, n + 1
    return s / n


def main():
    cli = sys.argv[1]
    with tempfile.TemporaryDirectory() as tmp:
        seq = make_sequence(tmp, False)
        off, src = os.path.join(tmp, "off"), os.path.join(tmp, "src")
        process(cli, seq, off)
        err = process(cli, seq, src, "--poses", os.path.join(seq, "poses.txt"))
        check(err == "", "the true poses: no warning (%r)" % err)
        m_off, m_src = mae(seq, off), mae(seq, src)
        print("relative depth MAE, frames 3-7: filter %.5f, filter + true poses %.5f"
              % (m_off, m_src))
        check(m_src < 0.8 * m_off, "the true poses bring the depth closer to the truth")

        # no pose at the frames' times: the filter without motion, byte for byte
        far = os.path.join(tmp, "far.txt")
        with open(far, "w") as f:
            f.write("500.0 0 0 0 0 0 0 1\n501.0 0 0 0 0 0 0 1\n")
        none = os.path.join(tmp, "none")
        err = process(cli, seq, none, "--poses", far)
        check("no pose for 8 of 8 frames" in err, "a warning names the frames without a pose")
        same = all(open(os.path.join(none, x), "rb").read() == open(os.path.join(off, x), "rb").read()
                   for x in os.listdir(off))
        check(same, "without poses the output is the filter's without motion, byte for byte")

        # frames named by time, poses between them: interpolated
        timed = make_sequence(tmp, True)
        tsrc = os.path.join(tmp, "tsrc")
        err = process(cli, timed, tsrc, "--poses", os.path.join(timed, "poses.txt"))
        m_t = mae(timed, tsrc)
        print("frames named by time, interpolated poses: relative depth MAE %.5f" % m_t)
        check("no pose for 1 of 8 frames" in err, "all but the first frame bracketed (%r)" % err)
        check(m_t < 1.05 * m_src, "interpolated poses as good as exact ones")

        # errors
        bad = os.path.join(tmp, "bad.txt")
        cases = [("1.0 0 0 0 0 0 0 1\n0.5 0 0 0 0 0 0 1\n", "bad.txt:2: timestamp 0.500000 does not follow"),
                 ("1.0 0 0 0 0 0 0 2\n", "norm 2"),
                 ("1.0 0 0 0 0 0 1\n", "number 8 is missing"),
                 ("1.0 0 0 0 nan 0 0 1\n", "not finite"),
                 ("# nothing\n", "no poses")]
        for text, want in cases:
            with open(bad, "w") as f:
                f.write(text)
            err = process(cli, seq, os.path.join(tmp, "x"), "--poses", bad, expect=1)
            check(want in err, "bad poses file: %r in %r" % (want, err.strip()))
        err = run(cli, "process", "--input", os.path.join(seq, "depth"), "--depth-out",
                  os.path.join(tmp, "x"), "--poses", os.path.join(seq, "poses.txt"), expect=2)
        check("--depth-temporal" in err, "--poses without the temporal filter: %r" % err.strip())
        err = process(cli, seq, os.path.join(tmp, "x"), "--poses", os.path.join(tmp, "missing"),
                      expect=1)
        check("--poses: cannot open" in err, "a missing poses file: %r" % err.strip())


if __name__ == "__main__":
    main()
