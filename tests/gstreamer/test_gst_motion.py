# SPDX-License-Identifier: MIT
"""The element's "depthao-motion" messages (issue #37, item 3: the camera's pose as an
output): a pan `depthao synth --trajectory` renders with its true poses, through
`pngdec ! depthao depth-temporal-motion=icp` under `gst-launch-1.0 -m`, posts one
message a frame, in order, with the buffer's timestamps; its motion estimate and pose are
the library's for the same frames (the Python binding over the same libdepthao, the
element's defaults), the pose within 2 mm and 0.06 degrees a frame of the truth, the
track's counts agree with the states; the GRAY8 AO and the AO over colour post the
same; none with post-messages=false, none while the motion is not followed (the
default).
usage: test_gst_motion.py DEPTHAO_CLI   (GST_PLUGIN_PATH, DEPTHAO_LIBRARY, DAO_SOURCE_ROOT
set; exit 77 without gst-launch-1.0 or numpy)"""
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

try:
    import numpy as np
except ImportError as e:
    print("SKIP: %s (python3-numpy)" % e)
    sys.exit(77)
from gst_checks import check, launch, require, status  # noqa: E402

require("gst-launch-1.0", "gst-inspect-1.0")
sys.path.insert(0, os.path.join(os.environ["DAO_SOURCE_ROOT"], "python"))
import depthao  # noqa: E402  (DEPTHAO_LIBRARY: the build's libdepthao)

N = 8

# the fields of a structure as gst_structure_to_string writes these: name=(type)value,
# a value plain, quoted, or a GstValueArray "< a, b >" of numbers (this structure's
# kinds only: no escaped quotes, no nested arrays)
FIELD = re.compile(r"([\w-]+)=\((\w+)\)(<[^>]*>|\"[^\"]*\"|[^,;]*)")


def value(kind, text):
    text = text.strip()
    if text.startswith("<"):
        return [float(v) for v in text.strip("<> ").split(",")]
    if kind in ("guint64", "int", "uint", "gint64"):
        return int(text)
    if kind == "boolean":
        return text in ("true", "TRUE", "1")
    return text.strip('"')


def messages(out):
    """The depthao-motion structures gst-launch -m printed, as dicts, in order."""
    found = []
    for line in out.splitlines():
        at = line.find("(element): depthao-motion, ")
        if at >= 0:
            body = line[at + len("(element): depthao-motion, "):]
            found.append({m.group(1): value(m.group(2), m.group(3))
                          for m in FIELD.finditer(body)})
    return found


def quat_matrix(q):
    """Row-major rotation matrix of a unit quaternion x, y, z, w."""
    x, y, z, w = q
    return np.array([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w),
                     2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
                     2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)])


def quat_angle_deg(a, b):
    d = abs(sum(x * y for x, y in zip(a, b)))
    return math.degrees(2.0 * math.acos(min(1.0, d)))


def main():
    cli = sys.argv[1]
    tmp = tempfile.mkdtemp(prefix="gst-motion-")
    try:
        run(cli, tmp)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    sys.exit(status())


def run(cli, tmp):
    p = subprocess.run(["gst-inspect-1.0", "depthao"], capture_output=True, text=True)
    check("post-messages" in p.stdout, "inspect: no post-messages property")

    p = subprocess.run([cli, "synth", "--scene", "boxes", "--trajectory", "pan-30", "--sensor",
                        "tof", "--frames", str(N), "--rays", "1", "--variant", "2", "--seed", "9",
                        "--out", tmp], capture_output=True, text=True)
    check(p.returncode == 0, "synth: %s" % p.stderr[-500:])
    if p.returncode:
        return
    seq = os.path.join(tmp, "boxes-pan-30-tof")
    truth = [[float(v) for v in line.split()] for line in open(os.path.join(seq, "poses.txt"))
             if not line.startswith("#")]
    cam = ["fx=525", "fy=525", "cx=319.5", "cy=239.5"]
    src = ["multifilesrc", "location=" + os.path.join(seq, "depth", "%04d.png"), "index=0",
           "stop-index=%d" % (N - 1), "caps=image/png,framerate=30/1", "!", "pngdec", "!"]

    p = launch("-m", *src, "depthao", *cam, "depth-temporal-motion=icp", "!", "fakesink")
    check(p.returncode == 0, "pipeline: %s" % p.stderr[-800:])
    got = messages(p.stdout)
    check(len(got) == N, "%d depthao-motion messages for %d frames" % (len(got), N))
    check([m.get("frame") for m in got] == list(range(len(got))),
          "frames out of order: %s" % [m.get("frame") for m in got])
    stamps = [m.get("timestamp") for m in got]
    check(all(b > a for a, b in zip(stamps, stamps[1:])) and
          all(m.get("running-time") == m.get("timestamp") for m in got),
          "timestamps: %s" % stamps)

    # the library on the same frames with the element's defaults
    ao = depthao.AO(depthao.Camera(525.0, 525.0, 319.5, 239.5, 640, 480), stream=True,
                    depth_temporal_motion="icp")
    accepted = refused = 0
    for i, m in enumerate(got[:N]):
        d = depthao.read_png_depth(os.path.join(seq, "depth", "%04d.png" % i))
        ao.process(d, unit=0.001, frame_index=i)
        mo, pose = ao.motion, ao.pose
        check(m["state"] == mo["state"], "frame %d: state %s, the library's %s"
              % (i, m["state"], mo["state"]))
        check(m["track-frames"] == i + 1, "frame %d: track-frames %s" % (i, m["track-frames"]))
        check(m["pose-frame"] == (i if m["pose-current"] else got[i - 1]["pose-frame"]),
              "frame %d: pose-frame %s" % (i, m["pose-frame"]))
        if i:
            accepted += m["state"] in ("applied", "still")
            refused += m["state"] == "refused"
        check(m["track-accepted"] == accepted and m["track-refused"] == refused,
              "frame %d: track counts %s / %s, the states say %d / %d"
              % (i, m["track-accepted"], m["track-refused"], accepted, refused))
        check(m["pose-current"] == (pose is not None),
              "frame %d: pose-current %s, the library's pose %s" % (i, m["pose-current"], pose))
        if pose is not None:
            check(np.allclose(m["pose-rotation"], pose[0], atol=1e-12) and
                  np.allclose(m["pose-translation"], pose[1], atol=1e-12),
                  "frame %d: pose %s %s, the library's %s" % (
                      i, m["pose-rotation"], m["pose-translation"], pose))
        check(np.allclose(quat_matrix(m["motion-rotation"]), np.ravel(mo["rotation"]),
                          atol=1e-9),
              "frame %d: motion rotation %s, the library's %s"
              % (i, m["motion-rotation"], mo["rotation"]))
        check(np.allclose(m["motion-translation"], mo["translation"], atol=1e-12),
              "frame %d: motion translation %s, the library's %s"
              % (i, m["motion-translation"], mo["translation"]))
        # against the truth, the camera in frame 0's optical frame: dead reckoning, so
        # the error grows from frame to frame (measured 0.65-1.5 mm and 0.02-0.04 deg a
        # frame on this pan; the bounds twice that)
        t = truth[i]
        err_mm = 1000.0 * math.dist(m["pose-translation"], t[1:4])
        err_deg = quat_angle_deg(m["pose-rotation"], t[4:8])
        check(err_mm <= 2.0 * i + 0.5 and err_deg <= 0.06 * i + 0.01,
              "frame %d: pose %.2f mm, %.3f deg from the truth" % (i, err_mm, err_deg))
        print("frame %d: %s, pose %.2f mm %.3f deg from the truth" % (
            i, m["state"], err_mm, err_deg))
    check(got and got[0]["state"] == "none" and got[0]["pose-rotation"] == [0, 0, 0, 1] and
          got[0]["pose-translation"] == [0, 0, 0], "frame 0 is not the origin: %s" % got[:1])
    check(accepted >= N - 2, "only %d of %d motions accepted on a clean pan" % (accepted, N - 1))

    # the other outputs post as the shaded one: the AO (GRAY8), and the AO over colour
    p = launch("-m", *src, "depthao", *cam, "depth-temporal-motion=icp", "!",
               "video/x-raw,format=GRAY8", "!", "fakesink")
    check(p.returncode == 0 and [m.get("frame") for m in messages(p.stdout)] == list(range(N)),
          "GRAY8 output: messages for frames %s" % [m.get("frame") for m in messages(p.stdout)])
    p = launch("-m", *src, "depthao", "name=d", *cam, "depth-temporal-motion=icp", "!",
               "video/x-raw,format=RGB", "!", "fakesink",
               "videotestsrc", "num-buffers=%d" % N, "!",
               "video/x-raw,format=RGB,width=640,height=480,framerate=30/1", "!", "d.color_sink")
    got_overlay = messages(p.stdout)
    check(p.returncode == 0 and [m.get("frame") for m in got_overlay] == list(range(N)),
          "AO over colour: messages for frames %s: %s" % (
              [m.get("frame") for m in got_overlay], p.stderr[-500:]))
    check([m.get("pose-translation") for m in got_overlay] ==
          [m.get("pose-translation") for m in got], "AO over colour: another pose")

    p = launch("-m", *src, "depthao", *cam, "depth-temporal-motion=icp", "post-messages=false",
               "!", "fakesink")
    check(p.returncode == 0 and not messages(p.stdout), "post-messages=false: %d messages"
          % len(messages(p.stdout)))
    p = launch("-m", *src, "depthao", *cam, "!", "fakesink")
    check(p.returncode == 0 and not messages(p.stdout), "motion not followed: %d messages"
          % len(messages(p.stdout)))


if __name__ == "__main__":
    main()
