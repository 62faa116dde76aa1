#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""depthao process --cloud-out: the PLY files read back by a small numpy parser
of the PLY format written here (independent of the writer) and by Open3D
(python3-open3d; that part is skipped with a message when it is absent).

A depth PNG of known counts (written by this script with zlib, not by the
library) goes in; every vertex must be the back-projection of its pixel, in
row order, exactly the pixels with depth, with the AO of the --ao-out PNG as
its colour and scalar.

usage: test_cli_cloud.py DEPTHAO_CLI
"""

import os
import struct
import subprocess
import sys
import tempfile
import zlib

try:
    import numpy as np
except ImportError:
    print("SKIP: numpy is not installed (python3-numpy)")
    sys.exit(77)

CLI = None
ROOT = os.environ.get("DAO_SOURCE_ROOT", os.path.join(os.path.dirname(__file__), "..", ".."))
FX, FY, CX, CY = 61.0, 58.5, 30.25, 22.75
UNIT = 0.0005
W, H = 64, 48


def write_png16(path, img):
    """A 16-bit grey PNG, filter None on every row (RFC 2083)."""
    def chunk(kind, data):
        c = struct.pack(">I", len(data)) + kind + data
        return c + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    raw = b"".join(b"\0" + row.astype(">u2").tobytes() for row in img)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", img.shape[1], img.shape[0], 16, 0, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw)))
        f.write(chunk(b"IEND", b""))


def read_png16(path):
    """The 16-bit grey PNG the library wrote (filters None, Sub, Up, Average, Paeth)."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    pos, idat = 8, b""
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, colour = struct.unpack(">IIBB", body[:10])
            assert (depth, colour) == (16, 0), (depth, colour)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw = zlib.decompress(idat)
    bpp, stride = 2, 2 * w
    out = np.zeros((h, stride), np.int64)
    prev = np.zeros(stride, np.int64)
    for y in range(h):
        ft = raw[y * (stride + 1)]
        line = np.frombuffer(raw, np.uint8, stride, y * (stride + 1) + 1).astype(np.int64)
        cur = np.zeros(stride, np.int64)
        for i in range(stride):
            a = cur[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
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
        out[y] = cur
        prev = cur
    return (out[:, 0::2] << 8 | out[:, 1::2]).astype(np.uint16)


PLY_TYPES = {"char": "i1", "uchar": "u1", "short": "<i2", "ushort": "<u2", "int": "<i4",
             "uint": "<u4", "float": "<f4", "double": "<f8"}


def read_ply(path):
    """Vertices of a binary little-endian PLY as a numpy structured array."""
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    lines = data[:end].decode("ascii").splitlines()
    assert lines[0] == "ply", lines[0]
    assert "format binary_little_endian 1.0" in lines, lines
    count, fields, elements = None, [], 0
    for ln in lines:
        t = ln.split()
        if t[0] == "element":
            elements += 1
            assert t[1] == "vertex", ln
            count = int(t[2])
        elif t[0] == "property":
            fields.append((t[2], PLY_TYPES[t[1]]))
    assert elements == 1
    dt = np.dtype(fields)
    assert len(data) - end == count * dt.itemsize, \
        "%d bytes after the header, %d vertices of %d" % (len(data) - end, count, dt.itemsize)
    return np.frombuffer(data, dt, count, end), [f[0] for f in fields]


def run(*args, expect=0):
    p = subprocess.run([CLI, "process", "--quiet"] + list(args), capture_output=True, text=True)
    if p.returncode != expect:
        sys.exit("FAIL: depthao process %s: exit %d (expected %d)\n%s" % (
            " ".join(args), p.returncode, expect, p.stderr))
    return p.stderr


def check(cond, what):
    if not cond:
        sys.exit("FAIL: " + what)
    print("ok - " + what)


def scene():
    """A tilted plane with a box in front and holes, in counts of UNIT."""
    v, u = np.mgrid[0:H, 0:W]
    z = 1.2 + 0.01 * u + 0.004 * v
    z[10:25, 20:40] = 0.8
    d = np.round(z / UNIT).astype(np.uint16)
    d[30:34, 5:15] = 0
    d[::7, ::5] = 0
    return d


def main():
    with tempfile.TemporaryDirectory() as tmp:
        depth = scene()
        png = os.path.join(tmp, "d.png")
        write_png16(png, depth)
        ply = os.path.join(tmp, "cloud.ply")
        aopng = os.path.join(tmp, "ao.png")
        intr = "--intrinsics=%r,%r,%r,%r" % (FX, FY, CX, CY)
        run("--input", png, intr, "--depth-unit", str(UNIT), "--ao-out", aopng, "--cloud-out", ply)

        v, names = read_ply(ply)
        check(names == ["x", "y", "z", "red", "green", "blue", "scalar_ao"],
              "PLY properties x y z red green blue scalar_ao (%s)" % " ".join(names))
        rows, cols = np.nonzero(depth)
        check(len(v) == len(rows) == int(np.count_nonzero(depth)),
              "one vertex per pixel with depth: %d of %d pixels" % (len(v), depth.size))
        z = depth[rows, cols] * np.float64(np.float32(UNIT))
        want = np.stack([(cols - CX) / FX * z, (rows - CY) / FY * z, z], axis=1)
        got = np.stack([v["x"], v["y"], v["z"]], axis=1).astype(np.float64)
        err = np.abs(got - want).max()
        check(err <= 1e-6, "x y z = back-projection of the depth, row order (max error %.2g m)" % err)
        ao16 = read_png16(aopng)
        vis = ao16[rows, cols] / 65535.0
        err = np.abs(v["scalar_ao"] - vis).max()
        check(err <= 1e-6, "scalar_ao = the AO PNG's visibility (max error %.2g)" % err)
        check(vis.min() < 0.97 and len(np.unique(vis)) > 50,
              "the scene has occlusion (AO down to %.3f)" % vis.min())
        grey = np.round(v["scalar_ao"].astype(np.float64) * 255)
        check(np.array_equal(v["red"], grey) and np.array_equal(v["green"], grey) and
              np.array_equal(v["blue"], grey), "colour = grey round(visibility x 255)")

        try:
            import open3d as o3d
        except ImportError:
            print("SKIP (part): Open3D is not installed (python3-open3d); read back with numpy only")
            o3d = None
        if o3d is not None:
            pc = o3d.io.read_point_cloud(ply)
            pts = np.asarray(pc.points)
            check(pts.shape == (len(v), 3), "Open3D reads %d points" % len(pts))
            check(np.abs(pts - want).max() <= 1e-6, "Open3D: the same coordinates")
            cols3 = np.asarray(pc.colors)
            check(pc.has_colors() and np.abs(cols3 - grey[:, None] / 255).max() <= 1e-6,
                  "Open3D: the AO as colour")

        # a directory of PNGs: one NAME.ply per file; one .ply for several frames is an error
        d2 = os.path.join(tmp, "seq")
        os.mkdir(d2)
        write_png16(os.path.join(d2, "a.png"), depth)
        write_png16(os.path.join(d2, "b.png"), np.where(depth > 0, depth // 2, 0).astype(np.uint16))
        out = os.path.join(tmp, "clouds")
        run("--input", d2, intr, "--depth-unit", str(UNIT), "--cloud-out", out)
        check(sorted(os.listdir(out)) == ["a.ply", "b.ply"], "a directory: a.ply, b.ply and nothing "
              "else (%s)" % sorted(os.listdir(out)))
        vb, _ = read_ply(os.path.join(out, "b.ply"))
        check(np.abs(vb["z"] * 2 - v["z"]).max() < UNIT, "b.ply holds the second frame")
        msg = run("--input", d2, intr, "--cloud-out", os.path.join(tmp, "one.ply"), expect=2)
        check("give a directory" in msg and not os.path.exists(os.path.join(tmp, "one.ply")),
              "several PNGs into one FILE.ply: usage error naming a directory, nothing written")

        # a recording: 000000.ply ...; FILE.ply with --frames 1 only
        oni = os.path.join(ROOT, "recordings", "spheres-rolling.oni")
        out = os.path.join(tmp, "rec")
        run("--input", oni, "--frames", "2", "--cloud-out", out)
        check(sorted(os.listdir(out)) == ["000000.ply", "000001.ply"],
              "a recording: 000000.ply, 000001.ply")
        msg = run("--input", oni, "--cloud-out", os.path.join(tmp, "rec.ply"), expect=2)
        check("--frames 1" in msg, "a recording into one FILE.ply: usage error suggesting --frames 1")
        run("--input", oni, "--frames", "1", "--start", "1", "--cloud-out",
            os.path.join(tmp, "rec.ply"))
        v1, _ = read_ply(os.path.join(tmp, "rec.ply"))
        v0, _ = read_ply(os.path.join(out, "000001.ply"))
        check(np.array_equal(v0[["x", "y", "z"]], v1[["x", "y", "z"]]),
              "--start 1 --frames 1 into FILE.ply = frame 1 of the directory run")

        # a pipe (/dev/stdout): written straight into, the same bytes as the file
        p = subprocess.run([CLI, "process", "--quiet", "--input", png, intr, "--depth-unit",
                            str(UNIT), "--cloud-out", "/dev/stdout"], capture_output=True)
        check(p.returncode == 0 and p.stdout == open(ply, "rb").read(),
              "--cloud-out /dev/stdout on a pipe: the same %d bytes as the file"
              % len(p.stdout))

        # written whole: a directory named FILE.ply is refused
        os.mkdir(os.path.join(tmp, "dir.ply"))
        msg = run("--input", png, intr, "--cloud-out", os.path.join(tmp, "dir.ply"), expect=1)
        check("dir.ply" in msg, "a directory named FILE.ply: an error naming it")
        leftovers = [n for n in os.listdir(tmp) if n.startswith(".")]
        check(not leftovers, "no temporary files left (%s)" % leftovers)
    print("PASS")


if __name__ == "__main__":
    CLI = sys.argv[1]
    main()
