#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""depthao process --depth-out: the filtered depth as 16-bit PNGs.

The PNGs are read back by PIL and by the PNG parser of test_cli_cloud.py (both
independent of the library's writer) and compared with the counts
dao_context_get_depth() gives for the same input (tests/tools/filtered_depth.c):
equal to the count; the input's unit kept (also a non-millimetre one, and
--depth-out-unit); 0 where the input has no depth; --algorithm none gives the
AO path's depth; directories and recordings numbered like --ao-out; the output
path rules (-, read-only files, missing directories); --cloud-depth.

usage: test_cli_depth_out.py DEPTHAO_CLI FILTERED_DEPTH_HELPER
"""

import os
import shutil
import stat
import subprocess
import sys
import tempfile

try:
    import numpy as np
    from PIL import Image
except ImportError:
    print("SKIP: numpy or PIL is not installed (python3-numpy, python3-pil)")
    sys.exit(77)

import test_cli_cloud as cc

ROOT = os.environ.get("DAO_SOURCE_ROOT", os.path.join(os.path.dirname(__file__), "..", ".."))
NOISY = os.path.join(ROOT, "recordings", "spheres-noisy")
ONI = os.path.join(ROOT, "recordings", "spheres-rolling.oni")
K = "525,525,319.5,239.5"
CLI = HELPER = None


def run(*args, expect=0, stdout=None):
    p = subprocess.run([CLI, "process", "--quiet"] + list(args), stdout=stdout,
                       stderr=subprocess.PIPE, text=stdout is None)
    err = p.stderr if isinstance(p.stderr, str) else p.stderr.decode()
    if p.returncode != expect:
        sys.exit("FAIL: depthao process %s: exit %d (expected %d)\n%s" % (
            " ".join(args), p.returncode, expect, err))
    return err


check = cc.check


def read_pil(path, second_reader=False):
    """The PNG by PIL; with second_reader also by test_cli_cloud's parser (slow: pure Python)."""
    im = Image.open(path)
    check(im.mode in ("I;16", "I;16B", "I"), "%s is a 16-bit grey PNG (PIL mode %s)" % (
        os.path.basename(path), im.mode))
    a = np.array(im).astype(np.int64)
    if second_reader:
        b = cc.read_png16(path).astype(np.int64)
        check(np.array_equal(a, b), "%s: PIL and the test's own PNG parser agree" %
              os.path.basename(path))
    return a


def library_depth(png, unit, algorithm, tmp):
    raw = os.path.join(tmp, "lib.raw")
    subprocess.run([HELPER, png, str(unit), K, algorithm, raw], check=True)
    data = open(raw, "rb").read()
    head, body = data.split(b"\n", 1)
    w, h = map(int, head.split())
    return np.frombuffer(body, "<u2").reshape(h, w).astype(np.int64)


def test_png_file(tmp):
    src = os.path.join(NOISY, "0000.png")
    raw = read_pil(src)
    for unit in ("0.001", "0.0005"):
        out = os.path.join(tmp, "d%s.png" % unit)
        run("--input", src, "--intrinsics", K, "--depth-unit", unit, "--depth-out", out)
        got = read_pil(out, second_reader=unit == "0.001")
        want = library_depth(src, unit, "gtao", tmp)
        check(np.array_equal(got, want),
              "unit %s: the PNG holds dao_context_get_depth's counts (%d pixels with depth)"
              % (unit, int((want > 0).sum())))
        check(not got[raw == 0].any(), "unit %s: 0 where the input has no depth" % unit)
        both = (raw > 0) & (got > 0)
        d = got[both] - raw[both]
        check(abs(d.mean()) < 2 and np.percentile(np.abs(d), 99) < 60,
              "unit %s: the input's unit kept (mean difference %.2f counts, 99th percentile "
              "|difference| %.0f)" % (unit, d.mean(), np.percentile(np.abs(d), 99)))
    # filters off: the input's counts come back unchanged
    out = os.path.join(tmp, "plain.png")
    run("--input", src, "--intrinsics", K, "--prefilter", "none", "--depth-max", "60",
        "--depth-min", "0", "--depth-out", out)
    check(np.array_equal(read_pil(out), raw), "prefilter none: the input's counts exactly")
    # another unit for the output
    half = os.path.join(tmp, "half.png")
    run("--input", src, "--intrinsics", K, "--depth-unit", "0.0005", "--depth-out-unit", "0.001",
        "--depth-out", half)
    got, mm = read_pil(half), read_pil(os.path.join(tmp, "d0.001.png"))
    # the same depth: counts of 0.5 mm read as mm are halved (within the rounding)
    both = (mm > 0) & (got > 0)
    d = got[both] * 2 - raw[both]
    check(np.percentile(np.abs(d), 99) < 60 and abs(d.mean()) < 3,
          "--depth-out-unit 0.001 of 0.5 mm input: half the counts (mean %.2f)" % d.mean())
    # depth only equals the AO path's depth, and writes nothing else
    none = os.path.join(tmp, "none.png")
    run("--input", src, "--intrinsics", K, "--algorithm", "none", "--depth-out", none)
    check(np.array_equal(read_pil(none), read_pil(os.path.join(tmp, "d0.001.png"))),
          "--algorithm none: the same depth as the AO path")
    check(np.array_equal(read_pil(none), library_depth(src, "0.001", "none", tmp)),
          "--algorithm none: dao_context_get_depth's counts")


def test_dir_and_recording(tmp):
    d = os.path.join(tmp, "dir")
    run("--input", NOISY, "--intrinsics", K, "--algorithm", "none", "--depth-out", d)
    names = sorted(n for n in os.listdir(NOISY) if n.endswith(".png"))
    check(sorted(os.listdir(d)) == names, "a directory of PNGs: the same names (%s)" % names)
    check(np.array_equal(read_pil(os.path.join(d, names[1])),
                         library_depth(os.path.join(NOISY, names[1]), "0.001", "none", tmp)),
          "a directory of PNGs: each file its own filtered depth")
    if not os.path.exists(ONI):
        print("skip - %s is not there" % ONI)
        return
    a, b, r = (os.path.join(tmp, x) for x in ("oni_ao", "oni_none", "oni_raw"))
    run("--input", ONI, "--frames", "3", "--depth-out", a, "--ao-out", os.path.join(tmp, "ao"))
    run("--input", ONI, "--frames", "3", "--algorithm", "none", "--depth-out", b)
    run("--input", ONI, "--frames", "3", "--algorithm", "none", "--prefilter", "none",
        "--depth-temporal", "0", "--depth-min", "0", "--depth-max", "60", "--depth-out", r)
    want = ["%06d.png" % i for i in range(3)]
    check(sorted(os.listdir(a)) == want and sorted(os.listdir(b)) == want,
          "a recording: numbered like --ao-out (%s)" % want)
    for n in want:
        fa, fb, fr = (read_pil(os.path.join(x, n)) for x in (a, b, r))
        check(np.array_equal(fa, fb), "%s: --algorithm none equals the AO path's depth (temporal "
              "filter on)" % n)
        check(not fa[fr == 0].any(), "%s: 0 where the recording has no depth" % n)
        both = (fr > 0) & (fa > 0)
        check(abs((fa[both] - fr[both]).mean()) < 2, "%s: the recording's unit kept" % n)
    # --mcap-out ?filtered_depth=true: the same depth on /depthao/depth_filtered (16UC1),
    # read back by the mcap source with the filters off
    mc = os.path.join(tmp, "fd.mcap")
    run("--input", ONI, "--frames", "3", "--mcap-out", mc + "?filtered_depth=true")
    back = os.path.join(tmp, "mcap_back")
    run("--input", mc + "?topic=/depthao/depth_filtered", "--algorithm", "none", "--prefilter",
        "none", "--depth-temporal", "0", "--depth-min", "0", "--depth-max", "60",
        "--depth-out", back)
    check(sorted(os.listdir(back)) == want, "--mcap-out ?filtered_depth=true: every frame")
    for n in want:
        check(np.array_equal(read_pil(os.path.join(back, n)), read_pil(os.path.join(a, n))),
              "%s: the MCAP topic holds --depth-out's counts" % n)


def test_mcap_metres(tmp):
    """--mcap-out ?filtered_depth=true of 0.5 mm input: 32FC1 metres (16UC1 is mm in ROS),
    read back in 0.5 mm counts by the mcap source: --depth-out's counts."""
    d = os.path.join(tmp, "half_dir")
    mc = os.path.join(tmp, "half.mcap")
    run("--input", NOISY, "--intrinsics", K, "--depth-unit", "0.0005", "--depth-out", d,
        "--mcap-out", mc + "?filtered_depth=true")
    back = os.path.join(tmp, "half_back")
    run("--input", mc + "?topic=/depthao/depth_filtered", "--intrinsics", K, "--algorithm", "none",
        "--prefilter", "none", "--depth-temporal", "0", "--depth-min", "0", "--depth-max", "60",
        "--depth-out-unit", "0.0005", "--depth-out", back)
    got = sorted(os.listdir(back))
    check(len(got) == 4, "a 0.5 mm recording to MCAP: 4 frames (%s)" % got)
    names = sorted(n for n in os.listdir(NOISY) if n.endswith(".png"))
    for g, n in zip(got, names):
        check(np.array_equal(read_pil(os.path.join(back, g)), read_pil(os.path.join(d, n))),
              "%s: 32FC1 metres on the topic, the counts of --depth-out in 0.5 mm" % n)


def test_bags(tmp):
    """Bags (tests/bag/make_bags.py, rosbag's writer): 32FC1 metres are written in mm (or
    --depth-out-unit), NaN as 0; a RealSense bag keeps its 0.1 mm counts."""
    make = os.path.join(ROOT, "tests", "bag", "make_bags.py")
    bags = os.path.join(tmp, "bags")
    p = subprocess.run([sys.executable, make, bags], capture_output=True, text=True)
    if p.returncode == 77:
        print("skip - bags: %s" % p.stdout.strip())
        return
    check(p.returncode == 0, "make_bags.py wrote the test bags")
    v, u = np.mgrid[0:48, 0:64]
    plain = ["--algorithm", "none", "--prefilter", "none", "--depth-temporal", "0",
             "--depth-min", "0", "--depth-max", "60"]
    for bag, unit_args, scale in (("f32_be.bag", [], 1), ("f32_be.bag",
                                  ["--depth-out-unit", "0.0005"], 2), ("realsense.bag", [], 1)):
        out = os.path.join(tmp, "bag_%s_%d" % (bag, scale))
        run("--input", os.path.join(bags, bag), "--frames", "2", *plain, *unit_args,
            "--depth-out", out)
        for i in range(2):
            want = np.where(u == v, 0, 500 + 7 * u + 13 * v + 100 * i) * scale
            got = read_pil(os.path.join(out, "%06d.png" % i))
            check(np.array_equal(got, want), "%s%s frame %d: the counts of the bag%s, 0 where "
                  "it has none" % (bag, " " + " ".join(unit_args) if unit_args else "", i,
                                   " in %s mm" % (1 / scale) if bag.startswith("f32") else " (0.1 mm)"))


def test_cloud_depth(tmp):
    src = os.path.join(NOISY, "0000.png")
    raw = read_pil(src)
    filt = library_depth(src, "0.001", "gtao", tmp)
    for mode, depth in (("raw", raw), ("filtered", filt)):
        ply = os.path.join(tmp, "c_%s.ply" % mode)
        args = ["--input", src, "--intrinsics", K, "--cloud-out", ply]
        if mode == "filtered":
            args += ["--cloud-depth", "filtered"]
        run(*args)
        v, _ = cc.read_ply(ply)
        z = depth[depth > 0] * 0.001
        check(len(v) == len(z) and np.allclose(v["z"], z, atol=0.00051, rtol=0),
              "--cloud-depth %s: one vertex per pixel of that depth, at its z (%d)" % (mode, len(v)))
    check(not np.array_equal(raw, filt), "(the filtered and raw depth differ)")


def test_errors(tmp):
    src = os.path.join(NOISY, "0000.png")
    err = run("--input", NOISY, "--intrinsics", K, "--depth-out", "-", expect=1)
    check("give a directory" in err, "- for a directory of PNGs: an error saying what to do")
    p = subprocess.run([CLI, "process", "--quiet", "--input", src, "--intrinsics", K,
                        "--depth-out", "-"], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    check(p.returncode == 0 and p.stdout[:8] == b"\x89PNG\r\n\x1a\n",
          "- for one file: the PNG on standard output")
    ro = os.path.join(tmp, "ro.png")
    with open(ro, "wb") as f:
        f.write(b"keep")
    os.chmod(ro, stat.S_IRUSR)
    err = run("--input", src, "--intrinsics", K, "--depth-out", ro, expect=1)
    check("chmod" in err and open(ro, "rb").read() == b"keep",
          "a write-protected file: refused, saying chmod u+w, and kept")
    err = run("--input", src, "--intrinsics", K, "--depth-out",
              os.path.join(tmp, "missing", "x.png"), expect=1)
    check("missing" in err, "a missing directory: an error naming the path")
    link = os.path.join(tmp, "dangling.png")
    os.symlink(os.path.join(tmp, "nothing-there"), link)
    run("--input", src, "--intrinsics", K, "--depth-out", link, expect=1)
    check(not os.path.exists(os.path.join(tmp, "nothing-there")),
          "a dangling symlink: an error, nothing created")
    for bad in (["--depth-out-unit", "0"], ["--depth-out-unit", "nan"], ["--cloud-depth", "x"]):
        run("--input", src, "--depth-out", os.path.join(tmp, "u.png"), *bad, expect=2)
    check(True, "--depth-out-unit 0 or nan, --cloud-depth x: usage errors")
    err = run("--input", src, "--algorithm", "none", "--shaded-out", os.path.join(tmp, "s.png"),
              expect=2)
    check("--depth-out" in err, "--algorithm none with --shaded-out: a usage error")


def main():
    tmp = tempfile.mkdtemp(prefix="dao-depth-out-")
    try:
        test_png_file(tmp)
        test_dir_and_recording(tmp)
        test_bags(tmp)
        test_mcap_metres(tmp)
        test_cloud_depth(tmp)
        test_errors(tmp)
    finally:
        for dirpath, _, files in os.walk(tmp):
            for f in files:
                p = os.path.join(dirpath, f)
                if not os.path.islink(p):
                    os.chmod(p, stat.S_IRUSR | stat.S_IWUSR)
        shutil.rmtree(tmp)
    print("PASS")


if __name__ == "__main__":
    CLI, HELPER = sys.argv[1], sys.argv[2]
    main()
