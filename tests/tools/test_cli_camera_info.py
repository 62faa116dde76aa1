#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""ROS CameraInfo YAML as intrinsics file: files written by PyYAML
(python3-yaml, an independent writer) in camera_info_manager's layout, read
by `depthao process --intrinsics-file`, found as camera.yaml beside PNG
input, and by depthaod's [source] intrinsics_file.  The intrinsics used are
checked exactly through the point cloud (every vertex is the back-projection
through them); distortion warns and uses the projection matrix; hostile and
truncated files are errors naming the file and what is wrong.

usage: test_cli_camera_info.py DEPTHAO_CLI DEPTHAOD
"""

import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
try:
    import numpy as np
    import yaml
except ImportError as e:
    print("SKIP: %s (python3-numpy, python3-yaml)" % e)
    sys.exit(77)
from test_cli_cloud import read_ply, read_png16, write_png16  # noqa: E402

CLI, DAEMON = sys.argv[1], sys.argv[2]
W, H = 40, 30
UNIT = 0.001


def camera_info(k, d=(0.0, 0.0, 0.0, 0.0, 0.0), p=None, w=W, h=H, flow=None):
    """camera_info_manager's layout (camera_calibration_parsers writeCalibrationYml)."""
    fx, fy, cx, cy = k
    if p is None:
        p = (fx, fy, cx, cy)
    info = {
        "image_width": w, "image_height": h, "camera_name": "depth_camera",
        "camera_matrix": {"rows": 3, "cols": 3, "data": [fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0]},
        "distortion_model": "plumb_bob",
        "distortion_coefficients": {"rows": 1, "cols": len(d), "data": list(d)},
        "rectification_matrix": {"rows": 3, "cols": 3,
                                 "data": [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]},
        "projection_matrix": {"rows": 3, "cols": 4,
                              "data": [p[0], 0.0, p[2], 0.0, 0.0, p[1], p[3], 0.0,
                                       0.0, 0.0, 1.0, 0.0]},
    }
    return yaml.safe_dump(info, default_flow_style=flow, sort_keys=False)


def json_camera(fx, fy, cx, cy):
    """Open3D's PinholeCameraIntrinsic JSON (column-major K) for W x H."""
    return json.dumps({"width": W, "height": H,
                       "intrinsic_matrix": [fx, 0, 0, 0, fy, 0, cx, cy, 1]})


def run(args, expect=0, prog=None):
    p = subprocess.run([prog or CLI] + args, capture_output=True, text=True)
    if p.returncode != expect:
        sys.exit("FAIL: %s: exit %d (expected %d)\n%s" % (" ".join(args), p.returncode, expect,
                                                          p.stderr))
    return p.stderr


def check(cond, what):
    if not cond:
        sys.exit("FAIL: " + what)
    print("ok - " + what)


def cloud_intrinsics(ply, depth):
    """fx, fy, cx, cy that the cloud was back-projected with (least squares, exact data)."""
    v, _ = read_ply(ply)
    rows, cols = np.nonzero(depth)
    z = v["z"].astype(np.float64)
    # x / z = (u - cx) / fx: a line in u
    ax, bx = np.polyfit(cols, v["x"] / z, 1)
    ay, by = np.polyfit(rows, v["y"] / z, 1)
    return np.array([1 / ax, 1 / ay, -bx / ax, -by / ay])


with tempfile.TemporaryDirectory() as tmp:
    v, u = np.mgrid[0:H, 0:W]
    depth = np.round((1.0 + 0.01 * u + 0.02 * v) / UNIT).astype(np.uint16)
    depth[5:9, 10:20] = 700
    png = os.path.join(tmp, "d.png")
    write_png16(png, depth)
    k = (41.5, 43.25, 19.75, 14.5)

    for flow in (None, False):
        cam = os.path.join(tmp, "cam.yaml")
        open(cam, "w").write(camera_info(k, flow=flow))
        ply = os.path.join(tmp, "c.ply")
        err = run(["process", "--quiet", "--input", png, "--intrinsics-file", cam,
                   "--cloud-out", ply])
        got = cloud_intrinsics(ply, depth)
        check(np.abs(got - k).max() < 1e-3 and "warning" not in err,
              "CameraInfo YAML (%s style): K used, no warning (%s)" % (
                  "block" if flow is False else "flow lists", got.round(4)))
    ply2 = os.path.join(tmp, "c2.ply")
    run(["process", "--quiet", "--input", png, "--intrinsics=%r,%r,%r,%r" % k,
         "--cloud-out", ply2])
    check(open(ply, "rb").read() == open(ply2, "rb").read(),
          "the same cloud as --intrinsics with K's numbers, byte for byte")

    # distortion: a warning that depth must be rectified, the projection matrix's intrinsics
    cam = os.path.join(tmp, "dist.yml")
    p = (40.0, 42.0, 20.0, 15.0)
    open(cam, "w").write(camera_info(k, d=(-0.1, 0.02, 0.0, 0.001, 0.0), p=p))
    err = run(["process", "--input", png, "--intrinsics-file", cam, "--cloud-out", ply])
    got = cloud_intrinsics(ply, depth)
    check("warning" in err and "rectified" in err and "dist.yml" in err,
          "distortion: a warning that the depth must be rectified: " + err.strip().splitlines()[0])
    check(np.abs(got - p).max() < 1e-3, "distortion: the projection matrix's intrinsics (%s)"
          % got.round(4))

    # camera.yaml beside a directory of PNGs (no camera.json)
    d = os.path.join(tmp, "seq")
    os.mkdir(d)
    write_png16(os.path.join(d, "0.png"), depth)
    open(os.path.join(d, "camera.yaml"), "w").write(camera_info(k))
    err = run(["process", "--input", d, "--cloud-out", os.path.join(tmp, "seqc")])
    got = cloud_intrinsics(os.path.join(tmp, "seqc", "0.ply"), depth)
    check("camera.yaml" in err and np.abs(got - k).max() < 1e-3,
          "camera.yaml beside PNG input is used")

    # hostile and broken files: exit 1, the file named, what is wrong
    good = camera_info(k)
    bad = {
        "truncated.yaml": (good[:good.index("data") + 12], "not valid YAML"),
        "cut.yaml": (good[:good.index("camera_matrix")], "camera_matrix is missing"),
        "syntax.yaml": ("image_width: 40\nimage_height: [30\ncamera_matrix: x\n", "line"),
        "nokey.yaml": (good.replace("camera_matrix", "kamera_matrix"), "camera_matrix is"),
        "short.yaml": (good.replace("0.0, 0.0, 1.0]", "0.0, 1.0]", 1), "has 8 numbers"),
        "text.yaml": (good.replace("41.5", "fourty"), "not a finite number"),
        "nan.yaml": (good.replace("41.5", ".nan"), "not a finite number"),
        "size.yaml": (camera_info(k, w=64), "40x30"),
        "zero.yaml": (good.replace("image_width: 40", "image_width: 0"), "image_width"),
        "huge.yaml": (good.replace("image_width: 40", "image_width: 99999999999"), "image_width"),
        "fx.yaml": (good.replace("41.5", "-41.5"), "focal"),
        "list.yaml": ("- 1\n- 2\n", "not a ROS CameraInfo"),
        "empty.yaml": ("", "empty"),
        "lastrow.yaml": (good.replace("0.0, 0.0, 1.0]", "0.0, 0.0, 2.0]", 1), "last row"),
        "alias.yaml": ("a: &a [1, 2]\nimage_width: *a\nimage_height: 30\n", "image_width"),
        "big.yaml": ("# " + "x" * (2 << 20) + "\n" + good, "larger than"),
        "binary.yaml": ("\x00\xff\xfe garbage", "YAML"),
        # implausible intrinsics (issue 38): the value named, whatever the format
        "fxbig.yaml": (good.replace("41.5", "1.0e+308"), "fx=1e+308"),
        "fxtiny.yaml": (good.replace("41.5", "5.0e-324"), "fx=4.94066e-324"),
        "cxfar.yaml": (good.replace("19.75", "1.0e+9"), "cx=1e+09"),
        "cyfar.yaml": (good.replace("14.5", "-1.0e+9"), "cy=-1e+09"),
        "fxbig.json": (json_camera(1e308, 43.25, 19.75, 14.5), "fx=1e+308"),
        "cxfar.json": (json_camera(41.5, 43.25, 1e9, 14.5), "cx=1e+09"),
        "fyzero.json": (json_camera(41.5, 0, 19.75, 14.5), "fy=0"),
        # one document, one value: a second document, duplicate keys, trailing data
        "two.yaml": (good + "---\n" + camera_info((50.0, 50.0, 20.0, 15.0)),
                     "second YAML document"),
        "dup.yaml": ("image_width: 64\n" + good, "'image_width' appears twice"),
        "dupdata.yaml": (good.replace("rows: 3", "rows: 3\n  rows: 3", 1),
                         "'rows' appears twice"),
        "nul.json": (json_camera(41.5, 43.25, 19.75, 14.5) + "\x00garbage", "a NUL byte"),
        "trail.json": (json_camera(41.5, 43.25, 19.75, 14.5) + " {}", "data after the JSON"),
    }
    for name, (text, what) in bad.items():
        path = os.path.join(tmp, name)
        with open(path, "w", encoding="latin-1") as f:
            f.write(text)
        err = run(["process", "--input", png, "--intrinsics-file", path, "--ao-out",
                   os.path.join(tmp, "ao.png")], expect=1)
        check(name in err and what in err, "%s: %s" % (name, err.strip()))
    err = run(["process", "--input", png, "--intrinsics-file", os.path.join(tmp, "none.yaml"),
               "--ao-out", os.path.join(tmp, "ao.png")], expect=1)
    check("none.yaml" in err and "No such file" in err, "a missing file: " + err.strip())
    # a FIFO: refused at once, not read (it hung forever: issue 38); a directory too
    fifo = os.path.join(tmp, "fifo.yaml")
    os.mkfifo(fifo)
    for path, what in ((fifo, "is a FIFO (named pipe), not a regular file"),
                       (tmp, "is a directory, not a regular file")):
        p = subprocess.run([CLI, "process", "--input", png, "--intrinsics-file", path,
                            "--ao-out", os.path.join(tmp, "ao.png")], capture_output=True,
                           text=True, timeout=20)
        check(p.returncode == 1 and path in p.stderr and what in p.stderr,
              "intrinsics file that is not a file: %s" % p.stderr.strip())
    # a plausible camera at the edges of the rule still works (fields of view near
    # 179 degrees and a principal point an image size outside)
    edge = os.path.join(tmp, "edge.json")
    open(edge, "w").write(json_camera(W / 200.0 * 1.01, 30.0, -W + 0.5, 2 * H - 0.5))
    run(["process", "--quiet", "--input", png, "--intrinsics-file", edge, "--ao-out",
         os.path.join(tmp, "ao.png")])
    check(True, "intrinsics at the edges of the plausible range are accepted")

    # depthaod: [source] intrinsics_file
    cam = os.path.join(tmp, "cam.yaml")
    ini = os.path.join(tmp, "d.ini")
    sink = "[sink.a]\nuri = images:%s\n" % os.path.join(tmp, "sink")
    open(ini, "w").write("[source]\nuri = images:%s\nintrinsics_file = %s\n%s" % (d, cam, sink))
    run(["--check-config", ini], prog=DAEMON)
    check(True, "depthaod --check-config takes [source] intrinsics_file")
    open(ini, "w").write("[source]\nuri = images:%s\nintrinsics_file = %s\n%s" % (
        d, os.path.join(tmp, "short.yaml"), sink))
    err = run(["--check-config", ini], expect=2, prog=DAEMON)
    check("d.ini:3" in err and "short.yaml" in err and "has 8 numbers" in err,
          "depthaod: a bad intrinsics_file is a config error at its line: " + err.strip())
    err = run(["--check-config", "/dev/null", "--set", "source.uri=images:" + d, "--set",
               "source.intrinsics_file=" + os.path.join(tmp, "dist.yml"), "--sink",
               "a=images:" + os.path.join(tmp, "sink")], prog=DAEMON)
    check("rectified" in err, "depthaod: distortion is logged")
    # depthaod: a FIFO as configuration file or intrinsics_file is refused, not read
    p = subprocess.run([DAEMON, "--check-config", fifo], capture_output=True, text=True,
                       timeout=20)
    check(p.returncode == 2 and "configuration file" in p.stderr and "FIFO" in p.stderr,
          "depthaod: a FIFO configuration file: " + p.stderr.strip())
    p = subprocess.run([DAEMON, "--check-config", "/dev/null", "--set", "source.uri=images:" + d,
                        "--set", "source.intrinsics_file=" + fifo, "--sink",
                        "a=images:" + os.path.join(tmp, "sink")], capture_output=True,
                       text=True, timeout=20)
    check(p.returncode == 2 and "FIFO" in p.stderr,
          "depthaod: a FIFO intrinsics_file: " + p.stderr.strip())
    err = run(["--check-config", "/dev/null", "--set", "source.uri=images:" + d, "--set",
               "source.intrinsics_file=" + cam, "--set", "source.fov=60,45", "--sink",
               "a=images:" + os.path.join(tmp, "sink")], expect=2,
              prog=DAEMON)
    check("intrinsics_file alone" in err, "depthaod: intrinsics_file with fov is refused")
    # a run: the AO with the file's intrinsics = the CLI's with the same numbers
    out = os.path.join(tmp, "daod")
    run(["--source", "images:" + d, "--set", "source.intrinsics_file=" + cam,
         "--depth-temporal", "0", "--sink", "ao=images:" + out, "--stream", "ao=ao",
         "--stats-interval", "0"], prog=DAEMON)
    run(["process", "--quiet", "--input", d, "--intrinsics=%r,%r,%r,%r" % k,
         "--ao-out", os.path.join(tmp, "cliao")])
    check(np.array_equal(read_png16(os.path.join(out, "000000.png")),
                         read_png16(os.path.join(tmp, "cliao", "0.png"))),
          "depthaod with intrinsics_file: the same AO as depthao process --intrinsics")
print("PASS")
