#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""depthao synth --trajectory and depthao eval --sequence (issue #37).

1. A pan of 30 deg/s written by synth: the files beside the frames, the poses
   read back here (quaternions, independent of the writer) turning 1 degree a
   frame at 30 fps, the family mark of an odd variant, the usage errors.
2. A hand-made 64x48 sequence written here (zlib PNGs): a flat wall (AO 1)
   with a truth of 0.5 on the left half and 1 on the right, and a true depth
   with a step sweeping 10 columns a frame: the MAE (0.25), the trail band's
   pixels (10 x 48, then 20 x 48) and its MAE (0.5), the static pixels and
   the flicker (0), the still camera, are known answers.
3. The real Kinect recording in ../shared/data (skipped without it): no truth,
   flicker and change are printed.
4. depthao process --pose-out on a synthetic pan and a sideways move: the
   estimated poses against the true poses.txt (timestamps equal, within
   0.05 degrees and 3 mm on every frame, and the camera seen to move);
   eval --sequence --picture: the strip's size read from its header; the same
   poses, filtered depth and AO on 1 and 2 threads.

usage: test_cli_motion.py DEPTHAO_CLI
"""

import json
import math
import os
import re
import struct
import sys
import tempfile
import zlib

from cli_run import check, run

W, H = 64, 48


def write_png16(path, rows):
    """A 16-bit grey PNG, filter None on every row (RFC 2083)."""
    def chunk(kind, data):
        c = struct.pack(">I", len(data)) + kind + data
        return c + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    raw = b"".join(b"\0" + struct.pack(">%dH" % len(r), *r) for r in rows)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", len(rows[0]), len(rows), 16, 0, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw)))
        f.write(chunk(b"IEND", b""))


def quat_angle(a, b):
    """Angle between the rotations of two unit quaternions (x, y, z, w)."""
    d = abs(sum(x * y for x, y in zip(a, b)))
    return 2.0 * math.acos(min(1.0, d))


def synth_pan(cli, tmp):
    out = os.path.join(tmp, "s")
    run(cli, "synth", "--scene", "thin-pole", "--trajectory", "pan-30", "--frames", "3",
        "--rays", "1", "--out", out)
    base = os.path.join(out, "thin-pole-pan-30")
    for sub in ("depth", "ao_gt", "depth_gt"):
        names = sorted(n for n in os.listdir(os.path.join(base, sub)) if n.endswith(".png"))
        check(names == ["0000.png", "0001.png", "0002.png"], "%s/: %s" % (sub, names))
    cam = json.load(open(os.path.join(base, "depth", "camera.json")))
    check(cam.get("trajectory") == "pan-30" and cam.get("set") == "tune" and cam.get("fps") == 30,
          "camera.json: %s" % cam)
    poses = [list(map(float, l.split())) for l in open(os.path.join(base, "poses.txt"))
             if l.strip() and not l.startswith("#")]
    check(len(poses) == 3 and all(len(p) == 8 for p in poses), "poses.txt: %s" % poses)
    check(poses[0][1:] == [0, 0, 0, 0, 0, 0, 1], "pose 0 is not the identity: %s" % poses[0])
    for a, b in zip(poses, poses[1:]):
        dt = b[0] - a[0]
        rate = math.degrees(quat_angle(a[4:], b[4:])) / dt
        check(abs(dt - 1 / 30) < 2e-6 and abs(rate - 30.0) < 0.01, "pan rate %.4f deg/s" % rate)
        check(max(abs(x) for x in b[1:4]) < 1e-9, "a pan moved the camera: %s" % b)
    # eval --sequence on it: a moving camera, trails measured, flicker followed over the poses
    text = run(cli, "eval", "--sequence", base, "--quality", "low")
    check("camera: moves" in text, text)
    m = re.search(r"flicker \(tracked over the true poses, (\d+) surface points", text)
    # 2 degrees of pan: most of the first frame stays in view
    check(m and int(m.group(1)) > 640 * 480 // 2, text)
    # without depth_gt/, a moving camera's flicker cannot be measured
    os.rename(os.path.join(base, "depth_gt"), os.path.join(base, "depth_gt.off"))
    text = run(cli, "eval", "--sequence", base, "--quality", "low")
    check("flicker: - (the camera moves" in text and "trail band: no" in text, text)
    check(re.search(r"mean MAE: off 0\.\d+, depth 0\.\d+, depth\+AO 0\.\d+", text), text)
    # the held-out family: odd variants
    run(cli, "synth", "--scene", "thin-pole", "--trajectory", "still", "--frames", "2",
        "--rays", "1", "--variant", "1", "--out", out)
    cam = json.load(open(os.path.join(out, "thin-pole-still", "depth", "camera.json")))
    check(cam.get("set") == "heldout", "variant 1 is not marked held out: %s" % cam)
    err = run(cli, "synth", "--scene", "thin-pole", "--trajectory", "fly", "--out", out, expect=2)
    check("unknown trajectory 'fly'" in err, err)
    err = run(cli, "synth", "--scene", "thin-pole", "--moving", "--out", out, expect=2)
    check("--moving needs --trajectory" in err, err)
    err = run(cli, "eval", "--sequence", os.path.join(tmp, "nothing"), expect=1)
    check("nothing" in err, err)


def hand_made(cli, tmp):
    base = os.path.join(tmp, "hand")
    for sub in ("depth", "ao_gt", "depth_gt"):
        os.makedirs(os.path.join(base, sub))
    with open(os.path.join(base, "depth", "camera.json"), "w") as f:
        json.dump({"width": W, "height": H,
                   "intrinsic_matrix": [52.5, 0, 0, 0, 52.5, 0, 31.5, 23.5, 1]}, f)
    gt = [[32768 if x < W // 2 else 65535 for x in range(W)] for _ in range(H)]
    wall = [[2000] * W for _ in range(H)]
    with open(os.path.join(base, "poses.txt"), "w") as f:
        f.write("# timestamp tx ty tz qx qy qz qw\n")
        for k in range(3):
            name = "%04d.png" % k
            write_png16(os.path.join(base, "depth", name), wall)
            write_png16(os.path.join(base, "ao_gt", name), gt)
            step = [[1000 if x < 10 * k else 2000 for x in range(W)] for _ in range(H)]
            write_png16(os.path.join(base, "depth_gt", name), step)
            f.write("%.6f 0 0 0 0 0 0 1\n" % (k / 30))
    text = run(cli, "eval", "--sequence", base)
    check("3 frames, 64x48, truth: yes, trail band: yes, camera: still" in text, text)
    m = re.search(r"mean MAE: off ([\d.]+), depth ([\d.]+), depth\+AO ([\d.]+)", text)
    check(m and all(abs(float(v) - 0.25) < 0.005 for v in m.groups()), "MAE: " + text)
    m = re.search(r"trail MAE \((\d+) px\): off ([\d.]+), depth ([\d.]+), depth\+AO ([\d.]+)", text)
    check(m and int(m.group(1)) == 10 * H + 20 * H, "trail band: " + text)
    check(all(abs(float(v) - 0.5) < 0.005 for v in m.groups()[1:]), "trail MAE: " + text)
    m = re.search(r"flicker \(tracked over the true poses, (\d+) surface points seen in every "
                  r"frame\): off ([\d.]+), depth ([\d.]+), depth\+AO ([\d.]+)", text)
    check(m and int(m.group(1)) == (W - 20) * H, "static pixels: " + text)
    check(all(float(v) < 1e-3 for v in m.groups()[1:]), "flicker of a still wall: " + text)
    check("frames worse than off (by > 1e-05): depth 0, depth+AO 0, depth+ICP 0, "
          "depth+AO+ICP 0 (of 3)" in text, text)
    m = re.search(r"mean MAE: off [\d.]+, depth [\d.]+, depth\+AO [\d.]+, depth\+ICP ([\d.]+), "
                  r"depth\+AO\+ICP ([\d.]+)", text)
    check(m and all(abs(float(v) - 0.25) < 0.005 for v in m.groups()), "ICP columns: " + text)
    # a poses.txt that is not one
    with open(os.path.join(base, "poses.txt"), "w") as f:
        f.write("0 0 0 0 0 0 0 3\n")
    err = run(cli, "eval", "--sequence", base, expect=1)
    check("poses.txt:1: the quaternion" in err, err)
    # without poses: per-pixel flicker on the pixels whose true depth stays
    os.remove(os.path.join(base, "poses.txt"))
    text = run(cli, "eval", "--sequence", base)
    m = re.search(r"flicker \((\d+) static px\): off ([\d.]+)", text)
    check(m and int(m.group(1)) == (W - 20) * H and float(m.group(2)) < 1e-3, text)


def real_recording(cli):
    oni = os.path.join(os.environ.get("DAO_SHARED_DATA", "../shared/data"), "oni", "3DJ_test.oni")
    if not os.path.exists(oni):
        print("skip: %s not found" % oni)
        return
    text = run(cli, "eval", "--sequence", oni, "--frames", "4", "--quality", "low")
    check("truth: no" in text and "mean MAE" not in text, text)
    check(re.search(r"flicker \(\d+ static px\): off [\d.]+", text), text)
    check(re.search(r"change \(mean \|AO_k - AO_k-1\|\): off 0\.\d+", text), text)


def read_poses(path):
    return [list(map(float, l.split())) for l in open(path)
            if l.strip() and not l.startswith("#")]


def threads_identical(cli, tmp, base):
    """The estimate (its steps on the pool) and the history's reprojection on 1 and 2
    threads: the same poses (as written), filtered depth and AO, to the byte."""
    outs = []
    for th in ("1", "2"):
        d = os.path.join(tmp, "threads" + th)
        run(cli, "process", "--input", os.path.join(base, "depth"), "--depth-temporal", "0.8",
            "--depth-temporal-motion", "icp", "--threads", th, "--pose-out", d + ".txt",
            "--depth-out", os.path.join(d, "depth") + "/", "--ao-out", os.path.join(d, "ao") + "/",
            "--quiet")
        files = {}
        for sub in ("depth", "ao"):
            for name in sorted(os.listdir(os.path.join(d, sub))):
                with open(os.path.join(d, sub, name), "rb") as f:
                    files[sub + "/" + name] = f.read()
        with open(d + ".txt") as f:
            files["poses"] = f.read()
        outs.append(files)
    check(len(outs[0]) == 9, "threads: %d outputs, not 4 + 4 + poses" % len(outs[0]))
    check(outs[0].keys() == outs[1].keys(), "1 and 2 threads wrote different files: %s, %s"
          % (sorted(outs[0]), sorted(outs[1])))
    differ = sorted(k for k in outs[0] if outs[0][k] != outs[1].get(k))
    check(not differ, "1 and 2 threads differ: %s" % differ)


def pose_out(cli, tmp):
    out = os.path.join(tmp, "p")
    for traj, moved in (("pan-30", 2.9), ("sideways", 0.045)):
        run(cli, "synth", "--scene", "boxes", "--trajectory", traj, "--frames", "4", "--rays", "1",
            "--out", out)
        base = os.path.join(out, "boxes-" + traj)
        est_path = os.path.join(tmp, traj + ".txt")
        run(cli, "process", "--input", os.path.join(base, "depth"), "--depth-temporal", "0.8",
            "--depth-temporal-motion", "icp", "--pose-out", est_path, "--quiet")
        truth, est = read_poses(os.path.join(base, "poses.txt")), read_poses(est_path)
        check(len(est) == 4 and all(len(p) == 8 for p in est), "%s: %s" % (est_path, est))
        for t, e in zip(truth, est):
            deg = math.degrees(quat_angle(t[4:], e[4:]))
            mm = 1e3 * math.dist(t[1:4], e[1:4])
            check(abs(t[0] - e[0]) < 2e-6 and deg < 0.05 and mm < 3.0,
                  "%s: pose %s against the truth %s (%.4f deg, %.3f mm)" % (traj, e, t, deg, mm))
        # the camera moved: an identity written every frame would fail
        last = est[-1]
        check(math.degrees(quat_angle([0, 0, 0, 1], last[4:])) > moved
              if traj.startswith("pan") else math.dist([0, 0, 0], last[1:4]) > moved,
              "%s: the estimate did not move: %s" % (traj, last))
        if traj == "pan-30":
            threads_identical(cli, tmp, base)
            pic = os.path.join(tmp, "strip.png")
            text = run(cli, "eval", "--sequence", base, "--quality", "low", "--picture", pic,
                       "--picture-frame", "2")
            check("picture: %s (frame 2: truth, off, depth+AO, depth+AO+ICP" % pic in text, text)
            with open(pic, "rb") as f:
                head = f.read(24)
            check(struct.unpack(">II", head[16:24]) == (4 * 320, 2 * 240), "strip size")
            err = run(cli, "eval", "--sequence", base, "--picture", pic, "--picture-frame", "4",
                      expect=2)
            check("--picture-frame 4: the sequence has 4 frames" in err, err)
    err = run(cli, "process", "--input", os.path.join(out, "boxes-pan-30", "depth"),
              "--pose-out", os.path.join(tmp, "x.txt"), expect=2)
    check("give --depth-temporal-motion icp (or --poses FILE) and the temporal depth filter" in err, err)


def main():
    cli = sys.argv[1]
    with tempfile.TemporaryDirectory() as tmp:
        hand_made(cli, tmp)
        synth_pan(cli, tmp)
        real_recording(cli)
        pose_out(cli, tmp)
    print("ok")


main()
