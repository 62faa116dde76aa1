#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Camera poses from a recording's tf, odometry or Foxglove transforms (issue #37, item 3).

A synth --trajectory sequence (640x480, structured light) is written as a ROS 1 bag by
rosbag (make_tf_bag.py), and as MCAP and a rosbag2 .db3 by @mcap/core and sql.js with
CDR from @foxglove/rosmsg2-serialization (make_tf_mcap.js), with a tf tree around the
camera: map -> odom (static, not the identity), odom -> base_link (dynamic), base_link ->
camera_link (static: a mount with a tilt and an offset), camera_link ->
camera_depth_optical_frame (static: ROS's optical rotation).  The depth images carry
header.frame_id camera_depth_optical_frame.  Variants (each in every format):

  pan    pan-30, /tf at the frames' stamps, /tf_static in two messages; one transform
         with a quaternion of norm 1.5 (skipped, a warning) and one of norm 1 + 4e-4
         (normalised)
  slide  sideways (0.5 m/s, level), /tf 12 ms after each frame's stamp (and one before
         the first): every pose is interpolated (exact for a linear path)
  odom   pan-30 as nav_msgs/Odometry on /odom (odom -> base_link) and /tf_static; no /tf
         (the fixed frame is the odometry's, odom)
  gap    pan-30 with /tf at frames 0, 1 and 5 only
  split  pan-30 without the mount (base_link -> camera_link) in /tf_static
  bare   odometry whose child base_link has no static transform to the camera
  imu    pan-30 as sensor_msgs/Imu on /camera/imu (200 Hz, angular velocity only; the
         IMU's frame mounted on camera_link by /tf_static), no /tf
  imuq   the same with the IMU's orientation (an AHRS's: from a tilted world frame)
  imubare  imu without the IMU's mount: its frame taken for the optical frame (a warning)
  imunoframe  imu with frame_id "/": no frame, taken for the optical frame (a warning)
  imugap   imu with 30 ms between two messages, between frames 2 and 3, read with pose_gap=0.01:
           frame 3 has no pose, and the turn in the gap is lost after it (and after a seek
           back to frame 0, the same)
  imugap2  the same with 60 ms around frame 3: frame 3 has none, frame 4 has one
  (pan-30 turns at a constant rate, where the side a rate multiplies on does not matter:
  test imu-track checks that on an axis that turns)

Checks, through the public API (source_poses.c: dao_source_frame_pose):
1. pan: every frame's pose in map is map->odom x the truth of poses.txt within 1e-6,
   the skipped transform warned once; slide with pose_frame=odom: the truth itself
   within 1e-6 (interpolated); odom: the truth (odom is the odometry's root);
2. gap with pose_gap=0.1: frames 2-4 have none, with a message naming the transform and
   the times; bare: base_link's pose and a warning;
   imu, imuq: every frame's rotation is the IMU's (its rates integrated from its first
   message, or its orientation) after the mount, within 1e-6, no translation, and the
   warning that an IMU has no translation; imubare, imunoframe: the IMU's rotation and a
   warning; imugap: no pose for frame 3;
3. depthao process --depth-temporal-motion source on each recording gives the filtered
   depth of depthao process --poses poses.txt on the PNG frames (--algorithm none
   --depth-out; at most 1 count apart on at most 0.05 % of the pixels), and differs from
   the filter without motion; so does source with the IMU of imu and imuq (pan-30 turns
   about the optical centre: the rotation is all its motion), and source+icp from the IMU
   gives the poses (--pose-out) of source+icp from the true poses within 1e-6;
4. error paths: split with --pose-frame map (not connected, the frames listed); a
   missing --pose-topic; a recording without /tf; PNG input with --pose-frame; an .oni;
   imu with --pose-frame.

5. depthaod with depth-temporal-motion source (manual playback, the filtered-depth
   stream) gives process' filtered depth on each recording; on an .oni it says once that
   the source has no poses and runs on.

Foxglove (make_fg_tf_mcap.js: @mcap/core, protobufjs with @foxglove/schemas' .proto, or
JSON): the same plans as MCAP files of foxglove.RawImage depth (frame_id the optical
frame), foxglove.CameraCalibration, /tf as foxglove.FrameTransform and /tf_static as
foxglove.FrameTransforms, in protobuf (format fgproto) and JSON (fgjson); pan, slide, gap
and split go through 1-5 (no odometry: Foxglove has none), and process on pan must give
the filtered depth of the ROS 2 MCAP to the pixel.  Foxglove-only variants:

  fgstatic   the static transforms on /mount (not .../tf_static): map -> odom stamped 0,
             the mount and the optical rotation each once: static all the same
  fgtopic    a decoy odom -> base_link on /tf_decoy at the frames' stamps: pose_topic=/tf
             reads the truth, without it the decoy wins
  fgnan      a /tf transform with w NaN (skipped, the warning says why)
  fgcut      a /tf message cut short (skipped, the warning says which)
  fgnochild  the mount without child_frame_id: skipped; with --pose-frame map the error
             says the depth frame is not connected and why
  fgenc      /tf in the message encoding cbor (fgproto), or JSON messages under a protobuf
             schema (fgjson): refused, saying what was found and what is read

Foxglove's ROS 2 messages (make_tf_mcap.js with plan fg_cdr: foxglove_msgs/msg/FrameTransform
on /tf, FrameTransforms on /tf_static, in CDR by @foxglove/rosmsg2-serialization with the .msg
@foxglove/schemas generates, beside sensor_msgs/msg/Image depth): as MCAP (fgcdr) and .db3
(fgdb3), through the same checks as fgproto and fgjson (a transform left without
child_frame_id is written with an empty one; fgenc is /tf in message encoding cbor).

The camera's poses as Foxglove PoseInFrame(s) (pose_topic=/camera_pose, pan's poses in odom
and /tf_static) in fgproto, fgjson, fgcdr and fgdb3:

  fgpose     PoseInFrame: the truth in odom (the pose's frame_id), and with
             pose_frame=map map -> odom x the truth; process gives the filtered depth of the
             ROS 2 MCAP's odometry to the pixel; refused without pose_topic
  fgposes    PosesInFrame of one pose, one more message with w NaN (skipped, warned)
  fgposecut  PoseInFrame, one message cut short (skipped, warned)
  fgposes2   PosesInFrame, one message of two poses: refused, saying why and what to do
  fgposeenc  /camera_pose in the message encoding cbor: refused

usage: test_cli_tf_poses.py DEPTHAO SOURCE_POSES MAKE_TF_BAG MAKE_TF_MCAP NODE DEPTHAOD
                            MAKE_FG_TF_MCAP
"""
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np
from PIL import Image

DEPTHAO, SOURCE_POSES, MAKE_BAG, MAKE_MCAP, NODE, DEPTHAOD, MAKE_FG = sys.argv[1:8]
FG_FORMATS = {"fgproto": "protobuf", "fgjson": "json", "fgcdr": "cdr", "fgdb3": "cdr"}
FG_SCHEMA = {"protobuf": "foxglove.", "json": "foxglove.", "cdr": "foxglove_msgs/msg/"}
POSE_TOPIC = "/camera_pose"
FG_SHARED = ("pan", "slide", "gap", "split")  # the plans written in the Foxglove formats too
START_NS = 1700000000 * 10**9
FRAME_ID = "camera_depth_optical_frame"
FAILURES = []


def fail(msg):
    print("FAIL: " + msg)
    FAILURES.append(msg)


# rigid transforms: (q = [x, y, z, w], t = [x, y, z]), p_parent = R(q) p_child + t
def qmul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return [aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz]


def qrot(q, v):
    p = qmul(qmul(q, [v[0], v[1], v[2], 0.0]), [-q[0], -q[1], -q[2], q[3]])
    return p[:3]


def compose(a, b):
    return (qmul(a[0], b[0]), [x + y for x, y in zip(qrot(a[0], b[1]), a[1])])


def inverse(a):
    qi = [-a[0][0], -a[0][1], -a[0][2], a[0][3]]
    return (qi, [-x for x in qrot(qi, a[1])])


def axis_angle(axis, deg):
    s = math.sin(math.radians(deg) / 2)
    n = math.sqrt(sum(x * x for x in axis))
    return [axis[0] / n * s, axis[1] / n * s, axis[2] / n * s, math.cos(math.radians(deg) / 2)]


MAP_ODOM = (axis_angle([0, 0, 1], 30), [1.0, 2.0, 0.5])
IMU_TOPIC = "/camera/imu"
IMU_FRAME = "camera_imu_optical_frame"
IMU_MOUNT = (axis_angle([1, 0, 0], 90), [0.01, -0.02, 0.03])  # camera_link -> the IMU's frame
AHRS = axis_angle([0.3, -0.5, 0.8], 40)  # the imuq orientation's world -> the IMU at its start
MOUNT = (axis_angle([0, 1, 0], 10), [0.2, 0.05, 0.4])     # base_link -> camera_link
OPTICAL = ([-0.5, 0.5, -0.5, 0.5], [0.0, 0.0, 0.0])       # camera_link -> optical
CAM = compose(MOUNT, OPTICAL)                              # base_link -> optical


def tf(stamp_ns, parent, child, tr):
    return {"stamp_ns": str(stamp_ns), "parent": parent, "child": child, "q": list(tr[0]),
            "t": list(tr[1])}


def run(args, **kw):
    return subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)


def synth(work, trajectory):
    out = os.path.join(work, "synth")
    r = run([DEPTHAO, "synth", "--scene", "boxes", "--trajectory", trajectory, "--frames", "6",
             "--rays", "4", "--sensor", "structured-light", "--out", out])
    if r.returncode:
        sys.exit("synth failed: " + r.stderr)
    seq = os.path.join(out, "boxes-%s-structured-light" % trajectory)
    poses = []
    for line in open(os.path.join(seq, "poses.txt")):
        if line.startswith("#"):
            continue
        v = [float(x) for x in line.split()]
        poses.append((v[4:8], v[1:4]))
    return seq, poses


def stamp(i):
    return START_NS + round(i * 1e9 / 30)


def plan_dir(work, name, seq, plan):
    d = os.path.join(work, "plan-" + name)
    os.makedirs(d, exist_ok=True)
    cam = json.load(open(os.path.join(seq, "depth", "camera.json")))
    names = sorted(os.listdir(os.path.join(seq, "depth")))
    frames = [n for n in names if n.endswith(".png")]
    with open(os.path.join(d, "depth.raw"), "wb") as f:
        for n in frames:
            f.write(np.asarray(Image.open(os.path.join(seq, "depth", n))).astype("<u2").tobytes())
    m = cam["intrinsic_matrix"]  # column-major
    plan.update({"width": cam["width"], "height": cam["height"], "frame_id": FRAME_ID,
                 "K": [m[0], m[3], m[6], m[1], m[4], m[7], m[2], m[5], m[8]],
                 "start_ns": str(START_NS),
                 "frames": [{"stamp_ns": str(stamp(i))} for i in range(len(frames))]})
    for k in ("tf_messages", "tf_static_messages", "odometry"):
        plan.setdefault(k, [])
    plan.setdefault("odometry_topic", "/odom")
    json.dump(plan, open(os.path.join(d, "plan.json"), "w"), indent=1)
    return d


def statics(mount=True):
    first = [tf(START_NS, "map", "odom", MAP_ODOM)] + \
        ([tf(START_NS, "base_link", "camera_link", MOUNT)] if mount else [])
    return [first, [tf(START_NS, "camera_link", FRAME_ID, OPTICAL)]]


def rotvec(q):
    """The rotation vector (axis times angle) of a unit quaternion."""
    x, y, z, w = q if q[3] >= 0 else [-v for v in q]
    n = math.sqrt(x * x + y * y + z * z)
    if n < 1e-15:
        return [2 * x, 2 * y, 2 * z]
    a = 2 * math.atan2(n, w)
    return [x / n * a, y / n * a, z / n * a]


def quat_exp(v):
    """The unit quaternion of a rotation vector."""
    a = math.sqrt(sum(x * x for x in v))
    if a < 1e-15:
        return [0.0, 0.0, 0.0, 1.0]
    k = math.sin(a / 2) / a
    return [v[0] * k, v[1] * k, v[2] * k, math.cos(a / 2)]


def base(pose):
    return compose(pose, inverse(CAM))  # odom -> base_link for a camera pose in odom


def plans(work):
    seq_pan, pan = synth(work, "pan-30")
    seq_slide, slide = synth(work, "sideways")
    out = {}
    msgs = [[tf(stamp(i), "odom", "base_link", base(p))] for i, p in enumerate(pan)]
    msgs[3][0]["q"] = [x * (1 + 4e-4) for x in msgs[3][0]["q"]]
    bad = tf(stamp(1) + 10**7, "odom", "base_link", base(pan[1]))
    bad["q"] = [x * 1.5 for x in bad["q"]]
    msgs.insert(2, [bad])
    out["pan"] = (seq_pan, pan, plan_dir(work, "pan", seq_pan,
                                         {"tf_messages": msgs, "tf_static_messages": statics()}))
    # sideways: linear in time; samples 12 ms after each frame, and one before the first
    v = [(b - a) * 30 for a, b in zip(slide[0][1], slide[1][1])]
    for i, p in enumerate(slide):
        want = [a + x * i / 30 for a, x in zip(slide[0][1], v)]
        if max(abs(a - b) for a, b in zip(want, p[1])) > 1e-8 or p[0] != slide[0][0]:
            sys.exit("the sideways trajectory is not linear at frame %d" % i)
    def at(t_s):
        return (slide[0][0], [a + x * t_s for a, x in zip(slide[0][1], v)])
    smsgs = [[tf(stamp(i) + 12 * 10**6, "odom", "base_link", base(at(i / 30 + 0.012)))]
             for i in range(-1, len(slide))]
    out["slide"] = (seq_slide, slide, plan_dir(work, "slide", seq_slide,
                                               {"tf_messages": smsgs,
                                                "tf_static_messages": statics()}))
    odo = [tf(stamp(i), "odom", "base_link", base(p)) for i, p in enumerate(pan)]
    out["odom"] = (seq_pan, pan, plan_dir(work, "odom", seq_pan,
                                          {"odometry": odo, "tf_static_messages": statics()}))
    out["gap"] = (seq_pan, pan, plan_dir(work, "gap", seq_pan, {
        "tf_messages": [m for i, m in enumerate(msgs) if m[0] is not bad and
                        int(m[0]["stamp_ns"]) in (stamp(0), stamp(1), stamp(5))],
        "tf_static_messages": statics()}))
    out["split"] = (seq_pan, pan, plan_dir(work, "split", seq_pan, {
        "tf_messages": [m for m in msgs if m[0] is not bad],
        "tf_static_messages": statics(mount=False)}))
    out["bare"] = (seq_pan, pan, plan_dir(work, "bare", seq_pan, {"odometry": odo}))
    # Foxglove only (plan["fg"] and the transforms' "fg": make_fg_tf_mcap.js)
    clean = [m for m in msgs if m[0] is not bad]
    st = statics()
    st[0][0] = dict(st[0][0], fg="stamp0")
    out["fgstatic"] = (seq_pan, pan, plan_dir(work, "fgstatic", seq_pan, {
        "tf_messages": clean, "tf_static_messages": st, "fg": {"static_topic": "/mount"}}))
    decoy = [{"topic": "/tf_decoy", "stamp_ns": str(stamp(i)), "transforms": [
        tf(stamp(i), "odom", "base_link", ([0.0, 0.0, 0.0, 1.0], [0.0, 0.0, 0.0]))]}
        for i in range(len(pan))]
    out["fgtopic"] = (seq_pan, pan, plan_dir(work, "fgtopic", seq_pan, {
        "tf_messages": clean, "tf_static_messages": statics(), "fg": {"extra": decoy}}))
    for name, damage in (("fgnan", "nan"), ("fgcut", "truncate")):
        hurt = dict(tf(stamp(1) + 10**7, "odom", "base_link", base(pan[1])), fg=damage)
        out[name] = (seq_pan, pan, plan_dir(work, name, seq_pan, {
            "tf_messages": clean[:2] + [[hurt]] + clean[2:], "tf_static_messages": statics()}))
    st = statics()
    st[0][1] = dict(st[0][1], fg="nochild")
    out["fgnochild"] = (seq_pan, pan, plan_dir(work, "fgnochild", seq_pan, {
        "tf_messages": clean, "tf_static_messages": st}))
    out["fgenc"] = (seq_pan, pan, plan_dir(work, "fgenc", seq_pan, {
        "tf_messages": clean, "tf_static_messages": statics()}))
    pose_plans(work, out, seq_pan, pan)
    imu_plans(work, out, seq_pan, pan)
    return out


def imu_plans(work, out, seq, pan):
    """The imu* plans: pan-30's rotation as an IMU at 200 Hz from 20 ms before the first
    frame to 20 ms after the last; the expected poses in out[name][1]."""
    inv = lambda q: [-q[0], -q[1], -q[2], q[3]]
    rates = [[x * 30 for x in rotvec(qmul(inv(a[0]), b[0]))] for a, b in zip(pan, pan[1:])]
    if max(abs(a - b) for r in rates for a, b in zip(r, rates[0])) > 1e-9:
        sys.exit("pan-30 does not turn at a constant rate: %s" % rates)
    mount_opt = compose(inverse(IMU_MOUNT), OPTICAL)  # the optical frame in the IMU's
    w_imu = qrot(mount_opt[0], rates[0])
    t0 = stamp(0) - 20 * 10**6
    n = (stamp(len(pan) - 1) + 20 * 10**6 - t0) // (5 * 10**6) + 1
    track = lambda ns: quat_exp([x * (ns - t0) * 1e-9 for x in w_imu])
    # imunoframe: frame_id "/" (no frame); imugap: no messages between 70 and 100 ms
    # after frame 0, between frames 2 and 3 (read with pose_gap=0.01, a gap); imugap2:
    # none between 70 and 130 ms, around frame 3
    gaps = {"imugap": (stamp(2) + 4 * 10**6, stamp(3) - 4 * 10**6),
            "imugap2": (stamp(2) + 4 * 10**6, stamp(4) - 4 * 10**6)}
    for name, orientation, mounted, frame in (("imu", False, True, IMU_FRAME),
                                              ("imuq", True, True, IMU_FRAME),
                                              ("imubare", False, False, IMU_FRAME),
                                              ("imunoframe", False, True, "/"),
                                              ("imugap", False, True, IMU_FRAME),
                                              ("imugap2", False, True, IMU_FRAME)):
        stamps = [t0 + k * 5 * 10**6 for k in range(n)]
        gap = gaps.get(name, (0, 0))
        stamps = [t for t in stamps if not gap[0] < t < gap[1]]
        msgs = [dict({"stamp_ns": str(t), "w": w_imu},
                     **({"q": qmul(AHRS, track(t))} if orientation else {})) for t in stamps]
        st = statics() + ([[tf(START_NS, "camera_link", IMU_FRAME, IMU_MOUNT)]] if mounted else [])
        start = AHRS if orientation else [0.0, 0.0, 0.0, 1.0]
        axes = mount_opt[0] if mounted and frame != "/" else [0, 0, 0, 1]
        # after a gap the integration goes on from where it stopped: the turn in it is lost
        lost = lambda ns: 0 if name not in gaps or ns < gap[1] else \
            min(t for t in stamps if t > gap[0]) - max(t for t in stamps if t < gap[0])
        want = [(qmul(qmul(start, track(stamp(i) - lost(stamp(i)))), axes), [0.0, 0.0, 0.0])
                for i in range(len(pan))]
        out[name] = (seq, want, plan_dir(work, name, seq, {
            "tf_static_messages": st,
            "imu": {"topic": IMU_TOPIC, "frame": frame, "messages": msgs}}))


def pose_plans(work, out, seq, pan):
    """The fgpose* plans: pan's camera poses in odom as PoseInFrame(s) on POSE_TOPIC."""
    def msg(ns, p, fg=None, n=1):
        return {"stamp_ns": str(ns), "frame": "odom",
                "poses": [dict({"q": list(p[0]), "t": list(p[1])}, **({"fg": fg} if fg else {}))] * n}
    good = [msg(stamp(i), p) for i, p in enumerate(pan)]
    hurt = {"fgposes": "nan", "fgposecut": "truncate"}
    for name, kind in (("fgpose", "PoseInFrame"), ("fgposes", "PosesInFrame"),
                       ("fgposecut", "PoseInFrame"), ("fgposes2", "PosesInFrame"),
                       ("fgposeenc", "PoseInFrame")):
        msgs = list(good)
        if name in hurt:
            msgs.insert(2, msg(stamp(1) + 10**7, pan[1], hurt[name]))
        if name == "fgposes2":
            msgs[3] = msg(stamp(3), pan[3], n=2)
        plan = {"tf_static_messages": statics(), "poses": {"topic": POSE_TOPIC, "type": kind,
                                                           "messages": msgs}}
        out[name] = (seq, pan, plan_dir(work, name, seq, plan))


def write_recordings(work, plans_):
    """{format: {variant: path}}; a format whose writer is missing is left out (noted)."""
    recs = {"bag": {}, "mcap": {}, "db3": {}}
    ros_plans = {k: v for k, v in plans_.items() if not k.startswith("fg")}
    for name, (_, _, d) in ros_plans.items():
        path = os.path.join(work, name + ".bag")
        r = run(["/usr/bin/python3", MAKE_BAG, d, path])
        if r.returncode == 77:
            print("note: no ROS 1 bags: " + r.stdout.strip())
            recs.pop("bag", None)
            break
        if r.returncode:
            sys.exit("make_tf_bag.py failed: " + r.stdout + r.stderr)
        recs["bag"][name] = path
    if not shutil.which(NODE):
        print("note: no MCAP, .db3 or Foxglove MCAP: node is not installed")
        recs.pop("mcap")
        recs.pop("db3")
        return recs
    for name, (_, _, d) in ros_plans.items():
        m, b = os.path.join(work, name + ".mcap"), os.path.join(work, name + ".db3")
        r = run([NODE, MAKE_MCAP, d, m, b])
        if r.returncode == 77:
            print("note: no MCAP, .db3 or Foxglove MCAP: " + r.stdout.strip())
            recs.pop("mcap")
            recs.pop("db3")
            return recs
        if r.returncode:
            sys.exit("make_tf_mcap.js failed: " + r.stdout + r.stderr)
        recs["mcap"][name], recs["db3"][name] = m, b
    for fmt, encoding in FG_FORMATS.items():
        recs[fmt] = {}
        for name, (_, _, d) in plans_.items():
            if name not in FG_SHARED and not name.startswith("fg"):
                continue
            if fmt == "fgdb3":  # written with fgcdr's MCAP
                recs[fmt][name] = os.path.join(work, "%s-fgcdr.db3" % name)
                continue
            d = fg_plan(work, name, d, encoding)
            path = os.path.join(work, "%s-%s.mcap" % (name, fmt))
            r = run([NODE, MAKE_MCAP, d, path, path[:-5] + ".db3"] if encoding == "cdr" else
                    [NODE, MAKE_FG, d, path, encoding])
            if r.returncode:
                sys.exit("make_tf_mcap.js or make_fg_tf_mcap.js failed: " + r.stdout + r.stderr)
            recs[fmt][name] = path
    return recs


def fg_plan(work, name, d, encoding):
    """The plan of d for a Foxglove file in encoding: fgenc and fgposeenc with another
    encoding for /tf or the pose topic (this file's bytes under another name), CDR with
    fg_cdr (Foxglove's ROS 2 messages)."""
    plan = json.load(open(os.path.join(d, "plan.json")))
    topic = POSE_TOPIC if name == "fgposeenc" else "/tf"
    plan.setdefault("fg", {})
    if name in ("fgenc", "fgposeenc"):
        plan["fg"]["encoding"] = {"topic": topic, "message": "json" if encoding == "json" else "cbor",
                                  "schema": "ros2msg" if encoding == "cdr" else "protobuf"}
    plan["fg_cdr"] = encoding == "cdr"
    out = os.path.join(work, "plan-%s-%s" % (name, encoding))
    os.makedirs(out, exist_ok=True)
    json.dump(plan, open(os.path.join(out, "plan.json"), "w"))
    if not os.path.exists(os.path.join(out, "depth.raw")):
        os.symlink(os.path.join(d, "depth.raw"), os.path.join(out, "depth.raw"))
    return out


def source_poses(uri, again=False):
    """(exit status, {frame: (q, t) or the gap's message}, {description, warning, error});
    with again, a seek back and every frame once more: a list of two such frame maps."""
    r = run([SOURCE_POSES, uri] + (["again"] if again else []))
    if again:
        passes = r.stdout.split("again\n")
        got = [parse_poses(p.splitlines()) for p in passes]
        return r.returncode, [g[0] for g in got], got[0][1]
    frames, info = parse_poses(r.stdout.splitlines())
    return r.returncode, frames, info


def parse_poses(lines):
    frames = {}
    info = {"description": [], "warning": [], "error": []}
    for line in lines:
        w = line.split(" ", 3)
        if w[0] in info:
            info[w[0]].append(line.split(" ", 1)[1])
        elif w[2] == "pose":
            v = [float(x) for x in line.split()[3:]]
            frames[int(w[0])] = (v[3:7], v[0:3])
        else:
            frames[int(w[0])] = w[3]
    return frames, info


def close(a, b, tol=1e-6):
    dq = min(max(abs(x - y) for x, y in zip(a[0], b[0])),
             max(abs(x + y) for x, y in zip(a[0], b[0])))
    return dq <= tol and max(abs(x - y) for x, y in zip(a[1], b[1])) <= tol


def check_truth(fmt, name, uri, want, gaps=(), warning=None):
    rc, frames, info = source_poses(uri)
    if rc:
        return fail("%s %s: source_poses failed: %s" % (fmt, name, info["error"]))
    worst = 0.0
    for i, w in enumerate(want):
        got = frames.get(i)
        if i in gaps:
            if not isinstance(got, str) or "no transform 'odom' -> 'base_link'" not in got:
                fail("%s %s: frame %d should have no pose: %s" % (fmt, name, i, got))
            continue
        if not isinstance(got, tuple) or not close(got, w):
            fail("%s %s: frame %d: %s, want %s" % (fmt, name, i, got, w))
            continue
        worst = max(worst, max(abs(x - y) for x, y in zip(got[1], w[1])))
    if warning and not any(warning in x for x in info["warning"]):
        fail("%s %s: no warning '%s': %s" % (fmt, name, warning, info["warning"]))
    if not warning and info["warning"]:
        fail("%s %s: a warning: %s" % (fmt, name, info["warning"]))
    if len(info["warning"]) > 1:
        fail("%s %s: the warning more than once" % (fmt, name))
    print("%s %s: %d frames, largest translation difference %.2e m; %s" %
          (fmt, name, len(want), worst, info["description"]))


def check_sources(recs, plans_):
    for fmt, paths in recs.items():
        pan = plans_["pan"][1]
        check_truth(fmt, "pan", paths["pan"], [compose(MAP_ODOM, p) for p in pan],
                    warning="skipped as malformed")
        check_truth(fmt, "slide", paths["slide"] + "?pose_frame=odom", plans_["slide"][1])
        check_truth(fmt, "gap", paths["gap"] + "?pose_gap=0.1",
                    [compose(MAP_ODOM, p) for p in pan], gaps=(2, 3, 4))
        if "odom" not in paths:  # Foxglove: no odometry
            continue
        check_truth(fmt, "odom", paths["odom"] + "?pose_topic=/odom", pan)
        check_truth(fmt, "bare", paths["bare"] + "?pose_topic=/odom", [base(p) for p in pan],
                    warning="the odometry's pose is taken as the camera's")
        sel = "?pose_topic=" + IMU_TOPIC
        note = "%s is an IMU: a rotation (%s), no translation; source+icp finds the translation"
        check_truth(fmt, "imu", paths["imu"] + sel, plans_["imu"][1],
                    warning=note % (IMU_TOPIC, "its rates integrated"))
        check_truth(fmt, "imuq", paths["imuq"] + sel, plans_["imuq"][1],
                    warning=note % (IMU_TOPIC, "its orientation"))
        axes = "no transform from the IMU's '%s' to '%s': its axes taken for the optical frame's; "
        check_truth(fmt, "imubare", paths["imubare"] + sel, plans_["imubare"][1],
                    warning=axes % (IMU_FRAME, FRAME_ID) +
                    note % (IMU_TOPIC, "its rates integrated"))
        check_truth(fmt, "imunoframe", paths["imunoframe"] + sel, plans_["imunoframe"][1],
                    warning=axes % ("(no frame_id)", FRAME_ID) +
                    note % (IMU_TOPIC, "its rates integrated"))
        check_imu_gap(fmt, "imugap", paths["imugap"] + sel + "&pose_gap=0.01",
                      plans_["imugap"][1], 3, "the IMU's messages have a gap")
        check_imu_gap(fmt, "imugap2", paths["imugap2"] + sel + "&pose_gap=0.01",
                      plans_["imugap2"][1], 3, "farther apart than 0.010 s")


def check_imu_gap(fmt, name, uri, want, hole, why):
    """imugap: frame 3, the first after the IMU's gap, has no pose (its turn in the gap is
    unknown); imugap2: frame 3, inside the gap, has none, and frame 4 after it has one (the
    frame before it had none: no motion to get wrong); the others are the truth, also
    after a seek back to frame 0."""
    rc, passes, info = source_poses(uri, again=True)
    if rc or len(passes) != 2:
        return fail("%s %s: source_poses failed: %s" % (fmt, name, info["error"]))
    for k, frames in enumerate(passes):
        for i, w in enumerate(want):
            got = frames.get(i)
            if i == hole:
                if not isinstance(got, str) or why not in got:
                    fail("%s %s: pass %d: frame %d should have no pose: %s" %
                         (fmt, name, k, i, got))
            elif not isinstance(got, tuple) or not close(got, w):
                fail("%s %s: pass %d: frame %d: %s, want %s" % (fmt, name, k, i, got, w))
    print("%s %s: frame %d without a pose, the others the truth, twice (a seek back)" %
          (fmt, name, hole))


def depth_out(work, tag, args):
    out = os.path.join(work, "out-" + tag)
    r = run([DEPTHAO, "process", "--algorithm", "none", "--depth-temporal", "0.8",
             "--noise-interval", "15", "--depth-out", out] + args)
    if r.returncode:
        fail("process %s: exit %d: %s" % (tag, r.returncode, r.stderr))
        return None, r.stderr
    return [np.asarray(Image.open(os.path.join(out, n))).astype(np.int32)
            for n in sorted(os.listdir(out))], r.stderr


def references(work, plans_):
    """pan's filtered depth with --poses poses.txt and without motion, from its PNGs."""
    seq = plans_["pan"][0]
    ref, _ = depth_out(work, "png", ["--input", os.path.join(seq, "depth"), "--poses",
                                     os.path.join(seq, "poses.txt")])
    still, _ = depth_out(work, "png-still", ["--input", os.path.join(seq, "depth")])
    return ref, still


def differences(got, want, still):
    """The largest difference in counts, the largest share of pixels that differ in a
    frame, and the pixels that differ from the filter without motion."""
    diff = [np.abs(a - b) for a, b in zip(got, want)]
    return (max(int(d.max()) for d in diff), max(float((d > 0).mean()) for d in diff),
            sum(int((a != b).sum()) for a, b in zip(got, still)))


def check_process(work, recs, plans_, ref, still):
    seq = plans_["pan"][0]
    if ref is None or still is None:
        return
    outs = {}
    for fmt, paths in recs.items():
        for mode in ("source", "source+icp"):
            got, err = depth_out(work, fmt + mode, ["--input", paths["pan"],
                                                    "--depth-temporal-motion", mode, "--quiet"])
            if got is None:
                continue
            outs[fmt, mode] = got
            ros2 = outs.get(("mcap", mode))
            if fmt in FG_FORMATS and ros2 is not None:
                n = sum(int((a != b).sum()) for a, b in zip(got, ros2))
                print("%s %s: %d pixels of the filtered depth differ from the ROS 2 MCAP's" %
                      (fmt, mode, n))
                if n or len(got) != len(ros2):
                    fail("%s %s: %d pixels differ from the ROS 2 MCAP's (%d frames, %d)" %
                         (fmt, mode, n, len(got), len(ros2)))
            if mode == "source":
                want = ref
            else:
                want, _ = depth_out(work, "png-" + mode, [
                    "--input", os.path.join(seq, "depth"), "--poses",
                    os.path.join(seq, "poses.txt"), "--depth-temporal-motion", mode])
            if want is None or len(got) != len(want):
                fail("%s %s: %s frames" % (fmt, mode, len(got)))
                continue
            big, share, moved = differences(got, want, still)
            print("%s %s: filtered depth against --poses: largest difference %d counts, "
                  "%.4f %% of the pixels differ; %d pixels differ from the filter without "
                  "motion" % (fmt, mode, big, 100 * share, moved))
            if big > 1 or share > 5e-4:
                fail("%s %s: the filtered depth differs from --poses' (%d counts, %.4f %%)" %
                     (fmt, mode, big, 100 * share))
            if moved == 0:
                fail("%s %s: the same as without motion" % (fmt, mode))
            if "skipped as malformed" not in err:
                fail("%s %s: no warning of the skipped transform: %s" % (fmt, mode, err))


def pose_rows(path):
    """A --pose-out file's poses (tx ty tz qx qy qz qw a frame), the quaternions with w >= 0."""
    rows = [[float(x) for x in line.split()[1:]] for line in open(path) if line[0] != "#"]
    return [r[:3] + ([-x for x in r[3:]] if r[6] < 0 else r[3:]) for r in rows]


def pose_distance(a, b):
    return max(abs(x - y) for ra, rb in zip(a, b) for x, y in zip(ra, rb)) \
        if len(a) == len(b) else float("inf")


def imu_seed_reference(work, seq):
    """--pose-out of source+icp seeded with the truth's rotations (pan-30 has no translation:
    an IMU's seed exactly), and of icp alone, from the PNG frames."""
    out = {}
    for tag, args in (("truth", ["--poses", os.path.join(seq, "poses.txt"),
                                 "--depth-temporal-motion", "source+icp"]),
                      ("icp", ["--depth-temporal-motion", "icp"])):
        path = os.path.join(work, "imu-ref-%s.txt" % tag)
        got, _ = depth_out(work, "png-imu-" + tag, ["--input", os.path.join(seq, "depth"),
                                                    "--pose-out", path] + args)
        out[tag] = pose_rows(path) if got is not None else None
    return out


def check_imu_process(work, recs, plans_, ref, still):
    """process with source on an IMU's rotation (the imu plans are pan's frames) against
    process --poses: pan-30's motion is its rotation alone; source+icp from the IMU estimates
    what source+icp from the true poses does (--pose-out)."""
    if ref is None or still is None:
        return
    seeds = imu_seed_reference(work, plans_["pan"][0])
    for fmt, paths in recs.items():
        if "imu" not in paths:
            continue
        for name, mode in (("imu", "source"), ("imuq", "source"), ("imu", "source+icp")):
            pose_out = os.path.join(work, "poses-%s-%s-%s.txt" % (fmt, name, mode))
            got, err = depth_out(work, "%s-%s-%s" % (fmt, name, mode), [
                "--input", paths[name], "--depth-temporal-motion", mode, "--pose-topic",
                IMU_TOPIC, "--pose-out", pose_out])
            if got is None:
                continue
            if len(got) != len(ref):
                fail("%s %s %s: %d frames" % (fmt, name, mode, len(got)))
                continue
            big, share, moved = differences(got, ref, still)
            if moved == 0:
                fail("%s %s %s: the same as without motion" % (fmt, name, mode))
            if "is an IMU" not in err:
                fail("%s %s %s: no word that an IMU has no translation: %s" %
                     (fmt, name, mode, err))
            if mode != "source":
                d, d_icp = (pose_distance(pose_rows(pose_out), seeds[k]) if seeds[k] else None
                            for k in ("truth", "icp"))
                print("%s %s %s: poses %.2e from source+icp seeded by the truth, %.2e from icp "
                      "alone" % (fmt, name, mode, d, d_icp))
                if d is None or not d <= 1e-6:
                    fail("%s %s %s: the poses are %s from those seeded by the truth" %
                         (fmt, name, mode, d))
                continue
            print("%s %s source: filtered depth against --poses: largest difference %d counts, "
                  "%.4f %% of the pixels differ" % (fmt, name, big, 100 * share))
            if big > 1 or share > 5e-4:
                fail("%s %s: the filtered depth differs from --poses' (%d counts, %.4f %%)" %
                     (fmt, name, big, 100 * share))
        expect_fail(fmt + " imu --pose-frame", ["--input", paths["imu"], "--depth-temporal-motion",
                                                "source", "--pose-topic", IMU_TOPIC,
                                                "--pose-frame", "map"],
                    "an IMU's rotation has no frame of the tf to be in")


def daemon_depth(work, tag, source):
    out = os.path.join(work, "daemon-" + tag)
    r = run([DEPTHAOD, "--source", source, "--playback", "manual", "--sink", "d=images:" + out,
             "--stream", "d=filtered-depth", "--depth-temporal", "0.8", "--noise-interval", "15",
             "--depth-temporal-motion", "source", "--algorithm", "none", "--stats-interval",
             "0"], timeout=120)
    if r.returncode or not os.path.isdir(out):
        fail("depthaod %s: exit %d: %s" % (tag, r.returncode, r.stderr))
        return None, r.stderr
    return [np.asarray(Image.open(os.path.join(out, n))).astype(np.int32)
            for n in sorted(os.listdir(out))], r.stderr


def check_daemon(work, recs):
    for fmt, paths in recs.items():
        want, _ = depth_out(work, fmt + "-d", ["--input", paths["pan"], "--depth-temporal-motion",
                                               "source", "--quiet"])
        got, err = daemon_depth(work, fmt, paths["pan"])
        if want is None or got is None:
            continue
        if len(got) != len(want) or any((a != b).any() for a, b in zip(got, want)):
            fail("depthaod %s: the filtered depth differs from process' (%d frames)" %
                 (fmt, len(got)))
        else:
            print("depthaod %s: %d frames, the filtered depth of process" % (fmt, len(got)))
        if "skipped as malformed" not in err:
            fail("depthaod %s: no warning of the skipped transform: %s" % (fmt, err))


def expect_fail(tag, args, want, status=1):
    r = run([DEPTHAO, "process", "--algorithm", "none", "--depth-out",
             os.path.join(tempfile.gettempdir(), "unused")] + args)
    wants = want if isinstance(want, list) else [want]
    if r.returncode != status or any(w not in r.stderr for w in wants):
        fail("%s: exit %d, want %d and '%s': %s" % (tag, r.returncode, status, want, r.stderr))


def check_errors(work, recs, plans_):
    for fmt, paths in recs.items():
        expect_fail(fmt + " split", ["--input", paths["split"], "--depth-temporal-motion",
                                     "source", "--pose-frame", "map"],
                    ["the depth frame '%s' is not connected to 'map' in /tf" % FRAME_ID,
                     "frames seen: 'map', 'odom', 'camera_link', '%s', 'base_link'" % FRAME_ID])
        expect_fail(fmt + " no topic", ["--input", paths["pan"], "--depth-temporal-motion",
                                        "source", "--pose-topic", "/nope"],
                    ["no nav_msgs/Odometry, Foxglove PoseInFrame(s) or sensor_msgs/Imu "
                     "topic '/nope' (pose_topic), nor transforms; odometry, pose and IMU "
                     "topics: none; transform topics: /tf", "/tf_static"])
        if "odom" in paths:
            expect_fail(fmt + " no tf", ["--input", paths["odom"], "--depth-temporal-motion",
                                         "source"],
                        "no tf topic (tf2_msgs/TFMessage, foxglove.FrameTransform(s)) for the "
                        "camera's poses, only /tf_static; name a nav_msgs/Odometry")
        r = run([DEPTHAO, "process", "--algorithm", "none", "--depth-out",
                 os.path.join(work, "gapout"), "--input", paths["gap"],
                 "--depth-temporal-motion", "source", "--pose-gap", "0.1"])
        if r.returncode or "no camera pose for 3 of 6 frames" not in r.stderr or \
                "farther apart than 0.100 s" not in r.stderr:
            fail("%s gap: exit %d: %s" % (fmt, r.returncode, r.stderr))
    seq = plans_["pan"][0]
    expect_fail("png --pose-frame", ["--input", os.path.join(seq, "depth"), "--depth-temporal",
                                     "0.8", "--pose-frame", "odom"],
                "--pose-frame, --pose-topic and --pose-gap say how a ROS or Foxglove "
                "recording's", 2)
    oni = os.path.join(work, "oni")
    r = run([DEPTHAO, "synth", "--scene", "plane", "--frames", "2", "--rays", "4", "--oni",
             "none", "--out", oni])
    onis = [os.path.join(oni, n) for n in os.listdir(oni) if n.endswith(".oni")]
    if r.returncode or not onis:
        return fail("synth --oni: " + r.stderr)
    expect_fail("oni", ["--input", onis[0], "--depth-temporal-motion", "source"],
                "source 'oni' carries no camera poses")
    got, err = daemon_depth(work, "oni", onis[0])
    if got is None or err.count("carries no camera poses") != 1:
        fail("depthaod on an .oni with source motion: %s" % err)


def check_foxglove(recs, plans_):
    pan = plans_["pan"][1]
    truth = [compose(MAP_ODOM, p) for p in pan]
    for fmt, encoding in FG_FORMATS.items():
        paths = recs.get(fmt)
        if not paths:
            continue
        check_truth(fmt, "fgstatic", paths["fgstatic"], truth)
        check_truth(fmt, "fgtopic", paths["fgtopic"] + "?pose_topic=/tf", truth)
        rc, frames, info = source_poses(paths["fgtopic"])
        wrong = sum(1 for i, w in enumerate(truth)
                    if isinstance(frames.get(i), tuple) and not close(frames[i], w))
        print("%s fgtopic without pose_topic: %d of %d poses are the decoy's" %
              (fmt, wrong, len(truth)))
        if rc or wrong != len(truth):
            fail("%s fgtopic: without pose_topic the decoy should win: %d of %d (%s)" %
                 (fmt, wrong, len(truth), info["error"]))
        what = "not a %sFrameTransform (%s)" % (FG_SCHEMA[encoding], encoding)
        check_truth(fmt, "fgnan", paths["fgnan"], truth,
                    warning="1 transforms or messages of /tf_static, /tf skipped as malformed "
                    "(the first: message 2 of '/tf': a rotation that is not a finite number)")
        check_truth(fmt, "fgcut", paths["fgcut"], truth,
                    warning="skipped as malformed (the first: message 2 of '/tf': " + what + ")")
        expect_fail(fmt + " fgnochild", ["--input", paths["fgnochild"], "--depth-temporal-motion",
                                         "source", "--pose-frame", "map"],
                    ["the depth frame '%s' is not connected to 'map' in /tf_static, /tf "
                     "(1 skipped as malformed, the first: message 0 of '/tf_static': a frame "
                     "name that is empty" % FRAME_ID])
        expect_fail(fmt + " fgenc", ["--input", paths["fgenc"], "--depth-temporal-motion",
                                     "source"],
                    ["topic '/tf' is %sFrameTransform in message encoding %s" %
                     (FG_SCHEMA[encoding], wrong_encoding(fmt, encoding)), REFUSED])
        check_foxglove_poses(fmt, encoding, paths, recs, pan)


REFUSED = "read are protobuf, json (jsonschema) and, for foxglove_msgs/msg/*, cdr"


def wrong_encoding(fmt, encoding):
    """What fg_plan wrote for fgenc and fgposeenc: the encodings, as the error names them."""
    return {"protobuf": "'cbor' (schema encoding 'protobuf')",
            "json": "'json' (schema encoding 'protobuf')",
            "cdr": "'cbor' (schema encoding '%s')" % ("" if fmt == "fgdb3" else "ros2msg")}[encoding]


def check_foxglove_poses(fmt, encoding, paths, recs, pan):
    """The camera's poses as PoseInFrame(s) (pose_plans)."""
    sel = "?pose_topic=" + POSE_TOPIC
    check_truth(fmt, "fgpose", paths["fgpose"] + sel, pan)
    check_truth(fmt, "fgpose map", paths["fgpose"] + sel + "&pose_frame=map",
                [compose(MAP_ODOM, p) for p in pan])
    kind = FG_SCHEMA[encoding]
    check_truth(fmt, "fgposes", paths["fgposes"] + sel, pan,
                warning="1 transforms or messages of %s, /tf_static skipped as malformed (the "
                "first: message 2 of '%s': a rotation that is not a finite number)" %
                (POSE_TOPIC, POSE_TOPIC))
    check_truth(fmt, "fgposecut", paths["fgposecut"] + sel, pan,
                warning="(the first: message 2 of '%s': not a %sPoseInFrame (%s))" %
                (POSE_TOPIC, kind, encoding))
    topic = ["--depth-temporal-motion", "source", "--pose-topic", POSE_TOPIC]
    expect_fail(fmt + " fgposes2", ["--input", paths["fgposes2"]] + topic,
                "message 3 of '%s' (%sPosesInFrame) has not exactly one pose: which is the "
                "camera's is unknown; record it alone, or name another pose_topic" %
                (POSE_TOPIC, kind))
    expect_fail(fmt + " fgposeenc", ["--input", paths["fgposeenc"]] + topic,
                ["topic '%s' is %sPoseInFrame in message encoding %s" %
                 (POSE_TOPIC, kind, wrong_encoding(fmt, encoding)), REFUSED])
    expect_fail(fmt + " fgpose without --pose-topic", ["--input", paths["fgpose"],
                                                       "--depth-temporal-motion", "source"],
                "for the camera's poses, only /tf_static; name a nav_msgs/Odometry, "
                "PoseInFrame(s) or sensor_msgs/Imu topic (pose_topic), or use motion icp or off")


def check_pose_process(work, recs):
    """process on PoseInFrame poses against process on the ROS 2 MCAP's odometry."""
    if "mcap" not in recs:
        return
    motion = ["--depth-temporal-motion", "source", "--quiet", "--pose-topic"]
    want, _ = depth_out(work, "mcap-odom", ["--input", recs["mcap"]["odom"]] + motion + ["/odom"])
    for fmt in FG_FORMATS:
        got, _ = depth_out(work, fmt + "-pose", ["--input", recs[fmt]["fgpose"]] + motion +
                           [POSE_TOPIC])
        if got is None or want is None:
            continue
        n = sum(int((a != b).sum()) for a, b in zip(got, want))
        print("%s fgpose source: %d pixels of the filtered depth differ from the ROS 2 MCAP's "
              "odometry's" % (fmt, n))
        if n or len(got) != len(want):
            fail("%s fgpose: %d pixels differ from the odometry's (%d frames, %d)" %
                 (fmt, n, len(got), len(want)))


def main():
    work = tempfile.mkdtemp(prefix="dao-tf-poses-")
    try:
        plans_ = plans(work)
        recs = write_recordings(work, plans_)
        if not recs:
            print("SKIP: neither rosbag nor node's @mcap/core is there to write recordings")
            sys.exit(77)
        check_sources(recs, plans_)
        ref, still = references(work, plans_)
        check_process(work, recs, plans_, ref, still)
        check_imu_process(work, recs, plans_, ref, still)
        check_errors(work, recs, plans_)
        check_foxglove(recs, plans_)
        check_pose_process(work, recs)
        check_daemon(work, recs)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    if FAILURES:
        sys.exit("%d failures" % len(FAILURES))
    print("ok")


if __name__ == "__main__":
    main()
