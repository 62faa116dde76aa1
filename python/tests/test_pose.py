# SPDX-License-Identifier: MIT
"""The camera's motion and pose through the Python binding (issue #37, item 3):
AO.set_pose() feeding depth_temporal_motion="source", AO.motion, AO.pose (the pose
the library's track composes, dao_context_pose_track, as depthao process --pose-out
gives it), and a ROS
bag's tf read with depthao.open(..., poses=True).

The depth is ray-cast here, in numpy, from a camera moving inside a box-shaped room
(every plane a wall: all six degrees of freedom are pinned), so the true poses are
known exactly.
"""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))

import depthao  # noqa: E402

SOURCE_ROOT = os.environ.get("DAO_SOURCE_ROOT") or os.path.dirname(os.path.dirname(HERE))
ONI = os.path.join(SOURCE_ROOT, "recordings", "spheres-rolling.oni")

W, H, F = 320, 240, 200.0  # 77 x 62 degrees
CAM = depthao.Camera(F, F, (W - 1) / 2, (H - 1) / 2, W, H)
# the room (y down: the floor at y = 1) and a box standing on its floor
ROOM_LO, ROOM_HI = np.array([-1.5, -0.6, -1.0]), np.array([1.6, 1.0, 2.5])
BOX_LO, BOX_HI = np.array([0.5, 0.6, 1.2]), np.array([0.9, 1.0, 1.6])
BALL, BALL_R = np.array([0.1, 0.7, 1.5]), 0.3  # and a ball (the curved surface pins the turn)


def rot_y(deg):
    a = np.radians(deg)
    return np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])


def rot_x(deg):
    a = np.radians(deg)
    return np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])


def quat(r):
    """The unit quaternion (x, y, z, w), w >= 0, of a rotation matrix (not near a half turn)."""
    w = np.sqrt(max(0.0, 1.0 + np.trace(r))) / 2
    return np.array([(r[2, 1] - r[1, 2]) / (4 * w), (r[0, 2] - r[2, 0]) / (4 * w),
                     (r[1, 0] - r[0, 1]) / (4 * w), w])


def quat_matrix(q):
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def render(r, t):
    """Depth (float32 metres along the optical axis) of the room seen by a camera at
    pose (r, t): x_world = r x_camera + t."""
    v, u = np.mgrid[0:H, 0:W].astype(np.float64)
    d = np.stack([(u - CAM.cx) / F, (v - CAM.cy) / F, np.ones_like(u)], -1) @ r.T
    s = np.full((H, W), np.inf)
    with np.errstate(divide="ignore", invalid="ignore"):
        for axis in range(3):
            for wall in (ROOM_LO[axis], ROOM_HI[axis]):
                k = (wall - t[axis]) / d[..., axis]
                s = np.where((k > 0) & (k < s), k, s)
        # the box: where the ray enters its slabs (Kay and Kajiya)
        a, b = (BOX_LO - t) / d, (BOX_HI - t) / d
        near = np.minimum(a, b).max(-1)
        far = np.maximum(a, b).min(-1)
        s = np.where((far >= near) & (near > 0) & (near < s), near, s)
        # the ball: the nearer root of |t + k d - c|^2 = r^2
        oc = t - BALL
        qa, qb = (d * d).sum(-1), (d * oc).sum(-1)
        disc = qb * qb - qa * ((oc * oc).sum() - BALL_R ** 2)
        k = (-qb - np.sqrt(np.maximum(disc, 0))) / qa
        s = np.where((disc > 0) & (k > 0) & (k < s), k, s)
    return s.astype(np.float32)  # the ray's parameter along (x, y, 1) is z


def trajectory(n):
    """n poses: looking into a corner at the box, down at the floor; a pan of 1 degree
    a frame, a slide of 1 cm a frame and a slight tilt."""
    r0 = rot_y(30.0) @ rot_x(-25.0)
    t0 = np.array([0.2, 0.1, 0.3])
    return [(r0 @ rot_y(1.0 * k) @ rot_x(0.2 * k), t0 + np.array([0.01 * k, 0.0, 0.004 * k]))
            for k in range(n)]


def relative(pa, pb):
    """The pose of b in a's frame: (ra^T rb, ra^T (tb - ta))."""
    (ra, ta), (rb, tb) = pa, pb
    return ra.T @ rb, ra.T @ (tb - ta)


def test_set_pose_drives_source_motion():
    poses = trajectory(6)
    ao = depthao.AO(CAM, stream=True, depth_temporal_motion="source")
    assert ao.pose is None and ao.motion["state"] == "none"
    assert ao.pose_track["frames"] == 0 and not ao.pose_track["current"]
    for k, (r, t) in enumerate(poses):
        # the quaternion on even frames, the matrix on odd ones
        ao.set_pose(quat(r) if k % 2 == 0 else r, t)
        ao.process(render(r, t), frame_index=k)
        m = ao.motion
        if k == 0:
            assert m["state"] == "none"
        else:
            assert m["state"] == "applied" and m["origin"] == "source", m
            want_r, want_t = relative(poses[k - 1], poses[k])
            assert np.abs(m["rotation"] - want_r).max() < 1e-9
            assert np.abs(m["translation"] - want_t).max() < 1e-9
        q, tt = ao.pose
        want_r, want_t = relative(poses[0], poses[k])
        assert np.abs(quat_matrix(q) - want_r).max() < 1e-9, k
        assert np.abs(tt - want_t).max() < 1e-9, k
    # a frame without a pose: its motion is unknown, and so is the next one's
    last = ao.pose
    r, t = poses[-1]
    ao.set_pose(None)
    ao.process(render(r, t), frame_index=6)
    assert ao.motion["state"] == "none" and ao.pose is None
    ao.set_pose(r, t)
    ao.process(render(r, t), frame_index=7)
    assert ao.motion["state"] == "none" and ao.pose is None
    ao.set_pose(r, t)
    ao.process(render(r, t), frame_index=8)  # the same pose again: no motion
    assert ao.motion["state"] == "still"
    q, tt = ao.pose  # the pose kept through the frames without motion
    assert np.abs(q - last[0]).max() < 1e-12 and np.abs(tt - last[1]).max() < 1e-12
    track = ao.pose_track
    assert track["current"] and track["frame_index"] == 8 and track["frames"] == 9
    assert track["accepted"] == 6 and track["refused"] == 0  # frames 1-5 and 8
    assert np.abs(track["rotation"] - q).max() < 1e-15
    ao.set_pose(None)  # held: the track says from which frame
    ao.process(render(r, t), frame_index=9)
    track = ao.pose_track
    assert ao.pose is None and not track["current"] and track["frame_index"] == 8
    assert np.abs(track["translation"] - tt).max() < 1e-15
    ao.close()


def test_pose_from_icp_and_when_there_is_none():
    poses = trajectory(8)
    ao = depthao.AO(CAM, stream=True, depth_temporal_motion="icp")
    for k, (r, t) in enumerate(poses):
        ao.process(render(r, t), frame_index=k)
        assert ao.motion["origin"] == "depth"
    assert ao.motion["state"] == "applied"
    q, tt = ao.pose
    want_r, want_t = relative(poses[0], poses[-1])
    # ray-cast depth without noise: within a millimetre and 0.05 degrees after 7 frames
    # (0.12 mm and 0.01 degrees measured)
    angle = np.degrees(np.arccos(np.clip((np.trace(quat_matrix(q).T @ want_r) - 1) / 2, -1, 1)))
    assert np.linalg.norm(tt - want_t) < 0.001 and angle < 0.05, (tt, want_t, angle)
    assert np.linalg.norm(want_t) > 0.07  # the motion is far larger than the error allowed
    # reset(): the pose starts over at the next frame
    ao.reset()
    assert ao.pose is None
    ao.process(render(*poses[0]), frame_index=0)
    q, tt = ao.pose
    assert np.array_equal(q, [0, 0, 0, 1]) and np.array_equal(tt, [0, 0, 0])
    # the motion not followed: no pose
    ao.depth_temporal_motion = "off"
    ao.process(render(*poses[1]), frame_index=1)
    assert ao.pose is None and ao.motion["state"] == "none"
    # followed again: from that frame on, in its optical frame
    ao.depth_temporal_motion = "source"
    ao.set_pose(*poses[2])
    ao.process(render(*poses[2]), frame_index=2)
    q, tt = ao.pose
    assert np.array_equal(q, [0, 0, 0, 1]) and np.array_equal(tt, [0, 0, 0])
    ao.set_pose(*poses[3])
    ao.process(render(*poses[3]), frame_index=3)
    want_r, want_t = relative(poses[2], poses[3])
    assert np.abs(quat_matrix(ao.pose[0]) - want_r).max() < 1e-9
    ao.depth_temporal = 0  # the depth filter off: nothing follows the camera
    ao.process(render(*poses[4]), frame_index=4)
    assert ao.pose is None
    ao.close()


def test_origin_and_refused_frames():
    """The first followed frame is the origin even where it has a motion (the motion
    switched on mid-stream, the depth history kept); a refused motion (a jump beyond
    0.25 m) gives no pose, and the next frame's moves the pose held through it; the
    motion switched off and on between two frames starts the pose over."""
    poses = trajectory(6)
    ao = depthao.AO(CAM, stream=True)  # depth_temporal_motion off
    for k in (0, 1):
        ao.process(render(*poses[k]), frame_index=k)
        assert ao.pose is None
    ao.depth_temporal_motion = "icp"
    ao.process(render(*poses[2]), frame_index=2)
    assert ao.motion["state"] == "applied"  # the motion from frame 1, not followed then
    q, t = ao.pose
    assert np.array_equal(q, [0, 0, 0, 1]) and np.array_equal(t, [0, 0, 0])
    ao.process(render(*poses[3]), frame_index=3)
    want_r, want_t = relative(poses[2], poses[3])
    assert np.abs(ao.pose[1] - want_t).max() < 3e-4
    # source mode: a jump of 0.4 m is refused: no pose; then 1 cm on moves the held pose
    ao.update(depth_temporal_motion="off")
    ao.update(depth_temporal_motion="source")  # off and on between two frames: a new origin
    r, t0 = poses[4]
    ao.set_pose(r, t0)
    ao.process(render(r, t0), frame_index=4)
    q, t = ao.pose
    assert np.array_equal(q, [0, 0, 0, 1]) and np.array_equal(t, [0, 0, 0])
    t1 = t0 + np.array([0.4, 0.0, 0.0])
    ao.set_pose(r, t1)
    ao.process(render(r, t1), frame_index=5)
    assert ao.motion["state"] == "refused" and ao.motion["reason"] == 4
    assert ao.pose is None
    ao.set_pose(r, t1 + np.array([0.01, 0.0, 0.0]))
    ao.process(render(r, t1 + np.array([0.01, 0.0, 0.0])), frame_index=6)
    assert ao.motion["state"] == "applied"
    q, t = ao.pose
    assert np.abs(t - r.T @ np.array([0.01, 0.0, 0.0])).max() < 1e-9  # the jump lost
    ao.close()


def test_set_pose_errors():
    ao = depthao.AO(CAM, stream=True, depth_temporal_motion="source")
    for bad, match in (([0, 0, 0, 2], "norm"), ([0, 0, float("nan"), 1], "finite"),
                       (np.eye(3) * 2, "not a rotation"), (np.diag([1, 1, -1]), "not a rotation"),
                       ([1, 2, 3], "quaternion"), ("up", "quaternion")):
        with pytest.raises(ValueError, match=match):
            ao.set_pose(bad, [0, 0, 0])
    for bad in (None, [0, 0], "x", [[0, 0, 0]]):
        with pytest.raises(ValueError, match="translation must be 3 numbers"):
            ao.set_pose([0, 0, 0, 1], bad)
    with pytest.raises(ValueError, match="1e6|1e\\+06|beyond"):
        ao.set_pose([0, 0, 0, 1], [2e6, 0, 0])
    with pytest.raises(AttributeError):
        ao.pose = None
    # a pose refused in Python, like one refused by the library, leaves the next frame
    # without one (not the pose set before it)
    poses = trajectory(2)
    ao.set_pose(*poses[0])
    ao.process(render(*poses[0]), frame_index=0)
    ao.set_pose(*poses[1])
    with pytest.raises(ValueError):
        ao.set_pose(np.eye(3) * 2, poses[1][1])
    ao.process(render(*poses[1]), frame_index=1)
    assert ao.motion["state"] == "none" and ao.pose is None
    ao.close()
    with pytest.raises(ValueError, match="closed"):
        ao.set_pose([0, 0, 0, 1], [0, 0, 0])


def _plan(tmp_path, poses, gap):
    """A bag plan for tests/bag/make_tf_bag.py: the room's depth (uint16 mm), /tf
    odom -> camera_depth_optical_frame at each frame's stamp but `gap`."""
    frames, raw, tf = [], b"", []
    start = 1_700_000_000 * 10**9
    for k, (r, t) in enumerate(poses):
        ns = start + k * 33_333_333
        frames.append({"stamp_ns": str(ns)})
        raw += np.rint(render(r, t) * 1000).astype("<u2").tobytes()
        if k not in gap:
            tf.append([{"stamp_ns": str(ns), "parent": "odom",
                        "child": "camera_depth_optical_frame", "t": list(t),
                        "q": list(quat(r))}])
    plan = {"width": W, "height": H, "start_ns": str(start), "frame_id":
            "camera_depth_optical_frame", "K": [F, 0, CAM.cx, 0, F, CAM.cy, 0, 0, 1],
            "frames": frames, "tf_static_messages": [], "tf_messages": tf, "odometry": []}
    (tmp_path / "plan.json").write_text(json.dumps(plan))
    (tmp_path / "depth.raw").write_bytes(raw)


def test_source_poses_from_a_bag(tmp_path):
    """A ROS 1 bag (rosbag's own writer) with tf: open(..., poses=True) gives each
    frame's pose (None in a gap, saying why); fed to AO.set_pose, AO.pose is the
    camera's motion from the first frame."""
    poses = trajectory(6)
    _plan(tmp_path, poses, gap={3})
    bag = tmp_path / "tf.bag"
    make = os.path.join(SOURCE_ROOT, "tests", "bag", "make_tf_bag.py")
    py = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable
    p = subprocess.run([py, make, str(tmp_path), str(bag)], capture_output=True, text=True)
    if p.returncode == 77:
        pytest.skip(p.stdout.strip())
    assert p.returncode == 0, p.stdout + p.stderr
    uri = "%s?pose_frame=odom&pose_gap=0.02" % bag
    with depthao.open(uri, poses=True) as src:
        ao = depthao.AO(src.camera(), stream=True, depth_temporal_motion="source")
        got = []
        for index, depth, info in src:
            pose = info["pose"]
            if index == 3:
                assert pose is None and info["pose_missing"], info
            else:
                r, t = poses[index]
                assert np.abs(quat_matrix(pose[0]) - r).max() < 1e-6
                assert np.abs(pose[1] - t).max() < 1e-6
                assert info["pose_missing"] is None
            ao.set_pose(*pose) if pose is not None else ao.set_pose(None)
            ao.process(depth, unit=info["depth_unit"], frame_index=index)
            got.append(ao.pose)
        assert "odom" in src.pose_description, src.pose_description
    want_r, want_t = relative(poses[0], poses[2])
    assert np.abs(quat_matrix(got[2][0]) - want_r).max() < 1e-6
    assert np.abs(got[2][1] - want_t).max() < 1e-6
    assert got[3] is None and got[4] is None  # no pose, then no motion from it
    want_r, want_t = relative(poses[0], poses[5])
    # frames 3 and 4 lost their motion (taken as none): frame 5's pose lacks it
    w5 = relative(poses[4], poses[5])
    exp_r = relative(poses[0], poses[2])[0] @ w5[0]
    exp_t = relative(poses[0], poses[2])[0] @ w5[1] + relative(poses[0], poses[2])[1]
    assert np.abs(quat_matrix(got[5][0]) - exp_r).max() < 1e-6
    assert np.abs(got[5][1] - exp_t).max() < 1e-6
    assert np.abs(got[5][1] - want_t).max() > 0.01  # (the lost motion shows)
    ao.close()


def test_source_without_poses():
    with depthao.open(ONI, poses=True) as src:
        with pytest.raises(OSError, match="carries no camera poses"):
            next(src)
