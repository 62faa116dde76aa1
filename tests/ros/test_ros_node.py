#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""depthao_node against a real roscore started here.

usage: test_ros_node.py DEPTHAO_NODE DEPTHAO_CLI LAUNCH_FILE

A roscore on a free port with its own ROS_HOME and ROS_LOG_DIR; two nodes: /a
(16UC1 in, mono16 AO; started by roslaunch with depthao.launch, the build tree as the
ROS package, a YAML file of AO parameters), /b (32FC1 big-endian in, 32FC1 AO) and
/c (a's input read as counts of 0.1 mm, the low preset), b and c started directly.  Bags written here by
rosbag's Python writer (depth + camera_info per frame) are played into them with
`rosbag play`; the AO and shaded images they publish must equal `depthao process` on
the same bags (mono16 and rgb8 bit for bit, 32FC1 rounded to 16 bits as the library
rounds: bit for bit),
with the inputs' stamps and frame ids, one output per input.  Then dynamic_reconfigure
changes /a's parameters (a value out of range is refused with a message), a wrong
encoding and a camera info of another size are logged as errors naming what is wrong,
and the bag played again (time goes back: the temporal filter starts over) equals
`depthao process` with the new parameters; played with a camera info that has
distortion, `depthao process` with the intrinsics of its P (the rectified image's).  Parameters refused at start stop the node.
The filtered depth (issue #36): depth_filtered/image of a (16UC1) and b (32FC1, NaN = no
depth) equals the library's filtered depth of the same frames (the Python binding over the
build's libdepthao, in a child process), with its camera_info; its compressedDepth topic
(a: 16UC1 PNG, b: 32FC1 RVL, c: 16UC1 RVL), decoded here by a decoder written from the
format's description (ConfigHeader, PNG through PIL, RVL), gives the same depth (32FC1:
the quantised inverse depth recomputed here, and within its step of the depth).
Poses from tf (issue #37): node d (`~pose_frame world`, depth_temporal_motion source) on a
bag of a camera moving through a static scene (its depth ray-cast here from the poses, tf a
moving /tf and a latched /tf_static) gives what `depthao process --pose-frame world` gives
on the same bag, and not what motion off gives; node e (`~pose_frame nowhere`) logs why its
frames have no pose and gives what motion off gives; d's camera_pose (geometry_msgs/
PoseStamped in depthao_odom) is the true pose of each frame's optical frame in the first's
(from the bag's tf, within 1e-9) and `depthao process --pose-out`'s to its printed digits;
e's is the first frame's origin only (no motion after it).
Exits 77 when ROS (roscore, rosbag, rospy, the node) is absent.  Every process
started here is killed on every exit path.
"""
import atexit
import os
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import threading
import time
import zlib
import io

W, H, FRAMES = 80, 60, 6
K = [70.0, 0.0, 39.5, 0.0, 71.0, 29.25, 0.0, 0.0, 1.0]
# the distorted camera info's P: the rectified image's camera, fx 52 fy 53.5 cx 38 cy 28
P_RECT = [52.0, 0.0, 38.0, 0.0, 0.0, 53.5, 28.0, 0.0, 0.0, 0.0, 1.0, 0.0]
TIMEOUT = 120.0  # s: generous, the host may run seven builds at once
procs = []
# processes roslaunch (roscore is one) starts in sessions of their own: the master, rosout,
# launched nodes; (pid, what its command line holds), killed should roslaunch not stop them
launched = []


def skip(msg):
    print("skip: " + msg)
    sys.exit(77)


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


if len(sys.argv) != 4:
    sys.exit(__doc__)
NODE, CLI, LAUNCH = sys.argv[1:4]
if not NODE or not os.path.exists(NODE):
    skip("depthao_node was not built: meson feature 'ros' needs libroscpp-dev, "
         "libimage-transport-dev, libsensor-msgs-dev, libdynamic-reconfigure-config-init-mutex-dev")
for tool in ("roscore", "rosbag", "roslaunch"):
    if not shutil.which(tool):
        skip("%s not found (Debian: ros-core)" % tool)
try:
    import genpy
    import numpy as np
    import rosbag
    import rosgraph
    import rospy
    import dynamic_reconfigure.client
    from sensor_msgs.msg import CameraInfo, CompressedImage, Image
except ImportError as e:
    skip("ROS Python modules missing (python3-rospy, python3-rosbag, python3-sensor-msgs, "
         "python3-dynamic-reconfigure): %s" % e)

WORK = tempfile.mkdtemp(prefix="dao-ros-")


def kill_all():
    for p in procs:
        if p.poll() is None:
            try:
                os.killpg(p.pid, signal.SIGTERM)
            except ProcessLookupError:
                continue
    deadline = time.monotonic() + 10
    for p in procs:
        try:
            p.wait(max(0.1, deadline - time.monotonic()))
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait()
    for pid, word in launched:
        try:
            with open("/proc/%d/cmdline" % pid, "rb") as f:
                if word.encode() in f.read():
                    os.kill(pid, signal.SIGKILL)
        except (OSError, ProcessLookupError):
            pass
    if not os.environ.get("DAO_KEEP_WORK"):
        shutil.rmtree(WORK, ignore_errors=True)


atexit.register(kill_all)
# meson test stops a test that runs out of time with SIGTERM: clean up then too
signal.signal(signal.SIGTERM, lambda *a: sys.exit(1))


def start(args, log):
    # a process group of its own: roscore's rosmaster and rosout go with it
    p = subprocess.Popen(args, stdout=open(log, "wb"), stderr=subprocess.STDOUT,
                         start_new_session=True)
    procs.append(p)
    return p


def wait_for(what, cond, timeout=TIMEOUT):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if cond():
            return
        time.sleep(0.05)
    fail("timed out after %.0f s waiting for %s" % (timeout, what))


def free_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def note_pid(master, node, word):
    """Remembers the pid of a node roslaunch started, to kill it if roslaunch cannot."""
    import xmlrpc.client
    code, _, pid = xmlrpc.client.ServerProxy(master.lookupNode(node)).getPid("/dao_test")
    if code == 1:
        launched.append((pid, word))


def start_roscore():
    """roscore on a free port; another port if it lost a race for this one."""
    for attempt in range(3):
        port = free_port()
        os.environ["ROS_MASTER_URI"] = "http://127.0.0.1:%d" % port
        log = os.path.join(WORK, "roscore-%d.log" % attempt)
        p = start(["roscore", "-p", str(port)], log)
        master = rosgraph.Master("/dao_test_probe")
        deadline = time.monotonic() + TIMEOUT
        while time.monotonic() < deadline and p.poll() is None:
            try:
                # rosout too (it subscribes /rosout): the nodes' logs go through it
                if any(t == "/rosout" for t, _ in master.getSystemState()[1]):
                    note_pid(master, "/rosout", "rosout")
                    launched.append((master.getPid(), "rosmaster"))
                    return
            except (OSError, rosgraph.MasterException):
                pass
            time.sleep(0.1)
        print("roscore on port %d did not come up:\n%s" % (port, open(log).read()))
    fail("roscore did not start")


# ---------------------------------------------------------------- the bags
def depth_m(x, y, i):
    """A tilted wall with a box in front of it moving one pixel a frame; holes; +-2 mm
    of noise changing from frame to frame (the temporal depth filter matters)."""
    if (x * 7 + y * 3 + i) % 37 == 0:
        return 0.0
    noise = ((x * 7919 + y * 104729 + i * 15485863) % 5 - 2) * 0.001
    if 20 + i <= x < 46 + i and 15 <= y < 42:
        return 1.7 + 0.004 * (x - 20 - i) + noise
    return 2.0 + 0.01 * y + 0.002 * x + noise


def stamp(i):
    return genpy.Time(200 + i, 10000000 * i)


def info_msg(i, width=W, height=H, distorted=False):
    c = CameraInfo()
    c.header.stamp = stamp(i)
    c.header.frame_id = "cam_depth_optical"
    c.width, c.height = width, height
    c.distortion_model = "plumb_bob"
    c.D = [-0.12, 0.03, 0.001, 0.0, 0.0] if distorted else [0.0] * 5
    c.K = K
    c.R = [1.0, 0, 0, 0, 1.0, 0, 0, 0, 1.0]
    c.P = P_RECT if distorted else K[:3] + [0.0] + K[3:6] + [0.0] + K[6:] + [0.0]
    return c


def image_msg(i, encoding, data, step, big_endian=0):
    m = Image()
    m.header.seq = i
    m.header.stamp = stamp(i)
    m.header.frame_id = "cam_depth_optical"
    m.width, m.height = W, H
    m.encoding, m.is_bigendian, m.step, m.data = encoding, big_endian, step, data
    return m


def d16(i):
    counts = [int(round(depth_m(x, y, i) * 1000)) for y in range(H) for x in range(W)]
    return image_msg(i, "16UC1", struct.pack("<%dH" % (W * H), *counts), 2 * W)


def f32_be(i):
    v = [depth_m(x, y, i) or float("nan") for y in range(H) for x in range(W)]
    return image_msg(i, "32FC1", struct.pack(">%df" % (W * H), *v), 4 * W, 1)


def write_bag(path, topic, make, distorted=False):
    with rosbag.Bag(path, "w") as b:
        for i in range(FRAMES):
            t = stamp(i) + genpy.Duration(0, 2000000)
            b.write(topic + "/camera_info", info_msg(i, distorted=distorted), t)
            b.write(topic + "/image", make(i), t)


# ---------------------------------------------------------------- a moving camera
CAM_LINK_TO_OPTICAL = (-0.5, 0.5, -0.5, 0.5)  # REP 103: optical z forward = the link's x


def quat_mul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz)


def quat_matrix(q):
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def link_pose(i):
    """cam_link in world at frame i: 1 cm a frame to the left (world +y), turning 0.6
    degrees a frame about world z, 1 cm up/down."""
    a = np.radians(0.6 * i) / 2
    return (0.0, 0.0, float(np.sin(a)), float(np.cos(a))), (0.0, 0.01 * i, 0.005 * (i % 2))


def moving_depth(i):
    """16-bit depth (mm) of a static room seen from link_pose(i): a wall 2.5 m ahead
    (world x = 2.5) leaning back, a box face at x = 1.8; holes and +-2 mm noise."""
    q, t = link_pose(i)
    R = quat_matrix(quat_mul(q, CAM_LINK_TO_OPTICAL))
    u, v = np.meshgrid(np.arange(W, dtype=np.float64), np.arange(H, dtype=np.float64))
    rays = np.stack([(u - K[2]) / K[0], (v - K[5]) / K[4], np.ones_like(u)], -1) @ R.T
    o = np.array(t)
    # wall: x - 0.1 z = 2.5; a ray o + s r (s the optical depth, since r's optical z is 1)
    s_wall = (2.5 - o[0] + 0.1 * o[2]) / (rays[..., 0] - 0.1 * rays[..., 2])
    s_box = (1.8 - o[0]) / rays[..., 0]
    hit = o + s_box[..., None] * rays
    on_box = (np.abs(hit[..., 1] - 0.05) < 0.35) & (hit[..., 2] > -0.3) & (hit[..., 2] < 0.25)
    s = np.where(on_box, s_box, s_wall)
    y, x = np.mgrid[0:H, 0:W]
    noise = ((x * 7919 + y * 104729 + i * 15485863) % 5 - 2) * 0.001
    mm = np.rint((s + noise) * 1000.0).astype(np.uint16)
    mm[(x * 7 + y * 3 + i) % 37 == 0] = 0
    return image_msg(i, "16UC1", mm.tobytes(), 2 * W)


SEP = "=" * 80 + "\n"
POSE_STAMPED = ("std_msgs/Header header\ngeometry_msgs/Pose pose\n" + SEP +
                "MSG: std_msgs/Header\nuint32 seq\ntime stamp\nstring frame_id\n" + SEP +
                "MSG: geometry_msgs/Pose\ngeometry_msgs/Point position\n"
                "geometry_msgs/Quaternion orientation\n" + SEP +
                "MSG: geometry_msgs/Point\nfloat64 x\nfloat64 y\nfloat64 z\n" + SEP +
                "MSG: geometry_msgs/Quaternion\nfloat64 x\nfloat64 y\nfloat64 z\nfloat64 w\n")


def write_moving_bag(path):
    sys.path.insert(0, os.path.join(os.environ["DAO_SOURCE_ROOT"], "tests", "bag"))
    import make_tf_bag
    from genpy.dynamic import generate_dynamic
    types = generate_dynamic("tf2_msgs/TFMessage", make_tf_bag.TF_MESSAGE)

    def tf(parent, child, q, t, when):
        m = types["tf2_msgs/TFMessage"]()
        m.transforms = [make_tf_bag.transform(types, {
            "stamp_ns": when.to_nsec(), "parent": parent, "child": child, "q": q, "t": t})]
        return m

    with rosbag.Bag(path, "w") as b:
        static = tf("cam_link", "cam_depth_optical", CAM_LINK_TO_OPTICAL, (0.0, 0.0, 0.0),
                    stamp(0))
        # latched, as tf2_ros' static broadcaster publishes it (rosbag play keeps that)
        b.write("/tf_static", static, stamp(0), connection_header={
            "topic": "/tf_static", "type": static._type, "md5sum": static._md5sum,
            "message_definition": static._full_text, "latching": "1"})
        for i in range(FRAMES):
            q, t = link_pose(i)
            b.write("/tf", tf("world", "cam_link", q, t, stamp(i)),
                    stamp(i) + genpy.Duration(0, 1000000))
            t = stamp(i) + genpy.Duration(0, 2000000)
            b.write("/mov/depth/camera_info", info_msg(i), t)
            b.write("/mov/depth/image", moving_depth(i), t)


def read_png(path):
    """depthao process' PNGs (16-bit gray, 8-bit RGB), read here: a reader independent of
    the library (and no libdepthao in this process, which may be a sanitizer build)."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        fail("%s is not a PNG" % path)
    pos, idat = 8, b""
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b"IHDR":
            w, h, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
    if (depth, ctype) not in ((16, 0), (8, 2)) or interlace:
        fail("%s: PNG of depth %d colour type %d interlace %d" % (path, depth, ctype, interlace))
    bpp = 2 if ctype == 0 else 3
    stride = w * bpp
    raw = zlib.decompress(idat)
    out = bytearray(h * stride)
    prev = bytearray(stride)
    for y in range(h):  # the five filters of the PNG specification, section 9
        kind = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            b = prev[x]
            c = prev[x - bpp] if x >= bpp else 0
            if kind == 1:
                line[x] = (line[x] + a) & 255
            elif kind == 2:
                line[x] = (line[x] + b) & 255
            elif kind == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif kind == 4:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                pred = a if pa <= pb and pa <= pc else b if pb <= pc else c
                line[x] = (line[x] + pred) & 255
        out[y * stride:(y + 1) * stride] = line
        prev = line
    if ctype == 0:
        return np.frombuffer(bytes(out), dtype=">u2").reshape(h, w).astype(np.uint16)
    return np.frombuffer(bytes(out), dtype=np.uint8).reshape(h, w, 3)


# ---------------------------------------------------------------- outputs
class Collector:
    def __init__(self, topic, kind=None):
        self.msgs = []
        self.lock = threading.Lock()
        self.sub = rospy.Subscriber(topic, kind or Image, self.cb, queue_size=None)
        self.topic = topic

    def cb(self, m):
        with self.lock:
            self.msgs.append(m)

    def count(self):
        with self.lock:
            return len(self.msgs)


def as_array(m):
    dt = {"mono16": "<u2", "32FC1": "<f4", "rgb8": "u1"}[m.encoding]
    a = np.frombuffer(m.data, dtype=dt)
    a = a.reshape(m.height, m.width, 3) if m.encoding == "rgb8" else a.reshape(m.height, m.width)
    return a


def cli(*args):
    r = subprocess.run([CLI, "process", "--quiet"] + list(args), capture_output=True, text=True)
    if r.returncode:
        fail("depthao process %s: %s" % (" ".join(args), r.stderr))


def check_run(name, col, bag, frames, encoding, opts, first):
    """The messages col.msgs[first:first+frames] against depthao process on bag."""
    out = os.path.join(WORK, "%s-%d" % (name, first))
    cli("--input", bag, "--ao-out", out + "/ao", "--shaded-out", out + "/sh", *opts)
    with col["ao"].lock:
        msgs = col["ao"].msgs[first:first + frames]
    for i, m in enumerate(msgs):
        if (m.header.stamp, m.header.frame_id) != (stamp(i), "cam_depth_optical"):
            fail("%s frame %d: header %s %r, the input had %s 'cam_depth_optical'"
                 % (name, i, m.header.stamp, m.header.frame_id, stamp(i)))
        if (m.encoding, m.width, m.height, m.is_bigendian) != (encoding, W, H, 0):
            fail("%s frame %d: %s %dx%d big-endian %d" % (name, i, m.encoding, m.width,
                                                          m.height, m.is_bigendian))
        ref = read_png(os.path.join(out, "ao", "%06d.png" % i))
        got = as_array(m)
        if encoding == "mono16":
            if not np.array_equal(got, ref):
                fail("%s frame %d: AO differs from depthao process in %d pixels (max %d)"
                     % (name, i, np.count_nonzero(got != ref),
                        np.abs(got.astype(int) - ref).max()))
        else:
            # the PNG holds round-half-even(v x 65535) of the same float visibility,
            # the product taken in float32 as the library does: equal, bit for bit
            if got.dtype != np.float32 or got.min() < 0.0 or got.max() > 1.0:
                fail("%s frame %d: 32FC1 visibility outside [0, 1]: %g..%g"
                     % (name, i, got.min(), got.max()))
            q = np.rint(got * np.float32(65535.0))
            if not np.array_equal(q, ref):
                fail("%s frame %d: 32FC1 AO x 65535 differs from depthao process in %d pixels "
                     "(max %.3f)" % (name, i, np.count_nonzero(q != ref),
                                     np.abs(got.astype(np.float64) * 65535.0 - ref).max()))
        if np.all(ref == ref.flat[0]):
            fail("%s frame %d: the AO is flat: the scene tests nothing" % (name, i))
    if "sh" in col:
        with col["sh"].lock:
            shaded = col["sh"].msgs[first:first + frames]
        for i, m in enumerate(shaded):
            ref = read_png(os.path.join(out, "sh", "%06d.png" % i))
            if m.encoding != "rgb8" or m.header.stamp != stamp(i) or \
                    not np.array_equal(as_array(m), ref):
                fail("%s frame %d: the shaded image (%s) differs from depthao process"
                     % (name, i, m.encoding))
    print("%s: %d frames equal to depthao process %s" % (name, frames, " ".join(opts)))


# ---------------------------------------------------------------- filtered depth
REFERENCE = r"""
import os, sys
import numpy as np
sys.path.insert(0, os.path.join(os.environ["DAO_SOURCE_ROOT"], "python"))
import depthao
frames, unit, quality, out = sys.argv[1], float(sys.argv[2]), sys.argv[3], sys.argv[4]
K = [float(v) for v in sys.argv[5].split(",")]
d = np.load(frames)
ao = depthao.AO(depthao.Camera(K[0], K[4], K[2], K[5], d.shape[2], d.shape[1]),
                quality=quality, stream=True)
res = []
for i in range(d.shape[0]):
    ao.process(d[i], unit=unit, frame_index=i)
    res.append(ao.filtered_depth() if d.dtype == np.float32 else ao.filtered_depth(unit))
np.save(out, np.stack(res))
"""


def reference_depth(name, frames, unit, quality="default"):
    """The library's filtered depth of frames (the node's settings: stream, index i)."""
    src, out = os.path.join(WORK, name + "-in.npy"), os.path.join(WORK, name + "-ref.npy")
    np.save(src, frames)
    env = dict(os.environ, ASAN_OPTIONS="detect_leaks=0")
    # a sanitizer build's library loads into python only after its runtimes
    lib = os.environ.get("DEPTHAO_LIBRARY", "")
    ldd = subprocess.run(["ldd", lib], capture_output=True, text=True).stdout if lib else ""
    pre = [w for line in ldd.splitlines() for w in line.split()
           if w.startswith("/") and ("libasan" in w or "libubsan" in w)]
    if pre:
        env["LD_PRELOAD"] = " ".join(pre)
    r = subprocess.run([sys.executable, "-c", REFERENCE, src, repr(unit), quality, out,
                        ",".join(repr(k) for k in K)], capture_output=True, text=True, env=env)
    if r.returncode:
        fail("the reference filtered depth (Python binding): %s" % r.stderr[-1500:])
    return np.load(out)


def rvl_decode(data, n):
    """RVL (Wilson 2017) as compressed_depth_image_transport stores it: little-endian
    32-bit words read from their top nibble; numbers of 3-bit groups, least significant
    first, bit 4 = more; zero runs, non-zero runs, zig-zag deltas."""
    words = struct.unpack("<%dI" % (len(data) // 4), data[:len(data) // 4 * 4])
    state = {"w": 0, "left": 0, "at": 0}

    def number():
        v, shift = 0, 0
        while True:
            if not state["left"]:
                if state["at"] == len(words):
                    fail("RVL data ends early")
                state["w"], state["left"] = words[state["at"]], 8
                state["at"] += 1
            nib = state["w"] >> 28
            state["w"] = (state["w"] << 4) & 0xFFFFFFFF
            state["left"] -= 1
            v |= (nib & 7) << shift
            shift += 3
            if not nib & 8:
                return v

    out, prev = [], 0
    while len(out) < n:
        out.extend([0] * number())
        for _ in range(number()):
            z = number()
            prev = (prev + ((z >> 1) ^ -(z & 1))) & 0xFFFF
            out.append(prev)
    if len(out) != n or state["at"] != len(words):
        fail("RVL: %d values (expected %d), %d of %d words read" % (len(out), n, state["at"],
                                                                      len(words)))
    return np.array(out, dtype=np.uint16).reshape(H, W)


def decode_compressed_depth(m):
    """(encoding, codec, A, B, 16-bit values) of a compressedDepth CompressedImage."""
    enc, _, rest = m.format.partition(";")
    codec = rest.strip().split(" ")[1]
    data = bytes(m.data)
    fmt, qa, qb = struct.unpack("<iff", data[:12])
    if fmt != 0:
        fail("compressedDepth header format %d, not 0 (inverse depth)" % fmt)
    if codec == "png":
        try:
            from PIL import Image as PILImage
            img = PILImage.open(io.BytesIO(data[12:]))
            if img.mode not in ("I;16", "I;16B", "I"):
                fail("compressedDepth PNG of mode %s" % img.mode)
            v = np.asarray(img).astype(np.uint16)
        except ImportError:
            path = os.path.join(WORK, "cdepth.png")
            with open(path, "wb") as f:
                f.write(data[12:])
            v = read_png(path)
    else:
        cols, rows = struct.unpack("<II", data[12:20])
        if (cols, rows) != (W, H):
            fail("RVL image of %dx%d" % (cols, rows))
        v = rvl_decode(data[20:], W * H)
    return enc, codec, qa, qb, v


def check_depth(name, col, ref, enc, codec):
    """depth_filtered/image, camera_info and compressedDepth of one node, first FRAMES."""
    with col["depth"].lock, col["cdepth"].lock:
        imgs, cds = col["depth"].msgs[:FRAMES], col["cdepth"].msgs[:FRAMES]
    infos = col["info"].msgs[:FRAMES] if "info" in col else None
    if len(imgs) < FRAMES or len(cds) < FRAMES:
        fail("%s: %d filtered depth images, %d compressed" % (name, len(imgs), len(cds)))
    for i in range(FRAMES):
        m = imgs[i]
        if (m.encoding, m.width, m.height, m.is_bigendian, m.header.stamp) != \
                (enc, W, H, 0, stamp(i)):
            fail("%s frame %d: %s %dx%d be %d stamp %s" % (name, i, m.encoding, m.width,
                                                            m.height, m.is_bigendian,
                                                            m.header.stamp))
        got = np.frombuffer(m.data, "<u2" if enc == "16UC1" else "<f4").reshape(H, W)
        if enc == "16UC1":
            same = np.array_equal(got, ref[i])
        else:
            same = np.array_equal(np.isnan(got), ref[i] == 0) and \
                np.array_equal(got[ref[i] > 0], ref[i][ref[i] > 0])
        if not same:
            fail("%s frame %d: the filtered depth differs from the library's" % (name, i))
        if np.count_nonzero(ref[i]) < W * H // 2:
            fail("%s frame %d: the reference has little depth: tests nothing" % (name, i))
        if infos is not None and (infos[i].header.stamp != stamp(i) or list(infos[i].K) != K
                                  or infos[i].header.frame_id != m.header.frame_id):
            fail("%s frame %d: camera_info %s" % (name, i, infos[i]))
        c = cds[i]
        if c.format != "%s; compressedDepth %s" % (enc, codec) or c.header.stamp != stamp(i):
            fail("%s frame %d: compressedDepth format '%s'" % (name, i, c.format))
        _, _, qa, qb, v = decode_compressed_depth(c)
        if enc == "16UC1":
            if (qa, qb) != (0.0, 0.0) or not np.array_equal(v, ref[i]):
                fail("%s frame %d: compressedDepth %s gives other counts (A %g B %g)"
                     % (name, i, codec, qa, qb))
            continue
        # 32FC1: the publisher's defaults depth_max 10, depth_quantization 100
        a32 = np.float32(100.0 * 101.0)
        b32 = np.float32(1.0) - a32 / np.float32(10.0)
        if (qa, qb) != (float(a32), float(b32)):
            fail("%s: compressedDepth A %r B %r" % (name, qa, qb))
        z = ref[i]
        with np.errstate(divide="ignore"):
            want = np.where((z > 0) & (z < 10), a32 / z + b32, 0).astype(np.float32)
        want = np.minimum(want, 65535).astype(np.uint16)
        back = np.where(v > 0, a32 / (v.astype(np.float32) - b32), 0)
        step = z * z / a32 * 1.001 + 1e-6
        if not np.array_equal(v, want) or np.any(np.abs(back - z)[z > 0] > step[z > 0]):
            fail("%s frame %d: compressedDepth 32FC1 %s: %d values differ, max depth error "
                 "%g m" % (name, i, codec, np.count_nonzero(v != want),
                           np.abs(back - z)[z > 0].max()))
    print("%s: %d filtered depth frames (%s) equal to the library's, compressedDepth %s "
          "decoded to the same" % (name, FRAMES, enc, codec))


def play(*bags):
    r = subprocess.run(["rosbag", "play", "--wait-for-subscribers", "-q"] + list(bags),
                       capture_output=True, text=True, timeout=TIMEOUT)
    if r.returncode:
        fail("rosbag play: %s%s" % (r.stdout, r.stderr))


def log_of(name):
    with open(os.path.join(WORK, name + ".log"), errors="replace") as f:
        return f.read()


def expect_refused(tag, cases):
    """Each (args, words): the node started with args stops with status 1 and its log (TAG.log)
    has words.  Private parameters stay on the server: a node name each."""
    for k, (bad, words) in enumerate(cases):
        p = start([NODE, "__name:=%s%d" % (tag, k)] + bad, os.path.join(WORK, tag + ".log"))
        try:
            st = p.wait(TIMEOUT)
        except subprocess.TimeoutExpired:
            fail("the node did not stop on %s" % bad)
        if st != 1 or words not in log_of(tag):
            fail("%s: exit %s, log: %s" % (bad, st, log_of(tag)))


def main():
    os.environ["ROS_HOME"] = os.path.join(WORK, "ros_home")
    os.environ["ROS_LOG_DIR"] = os.path.join(WORK, "ros_log")
    os.environ["ROS_HOSTNAME"] = "localhost"
    os.environ.pop("ROS_IP", None)
    os.environ.pop("ROS_NAMESPACE", None)
    os.environ["ROSCONSOLE_FORMAT"] = "[${severity}] ${message}"
    bag_a, bag_b = os.path.join(WORK, "a.bag"), os.path.join(WORK, "b.bag")
    write_bag(bag_a, "/cam/depth", d16)
    write_bag(bag_b, "/cam32/depth", f32_be)
    start_roscore()

    # parameters refused at start: an error naming them, exit status 1
    expect_refused("bad", ((["_radius:=-1"], "radius"),
                           (["_ao_encoding:=rgb8"], "mono16 or 32FC1"),
                           (["_prefilter:=blur"], "blur")))

    # node a through roslaunch: the package 'depthao' is the build directory (package.xml
    # beside the node); AO parameters from a YAML file
    yaml = os.path.join(WORK, "a.yaml")
    with open(yaml, "w") as f:
        f.write("occlusion_color: '203040'\nradiuss: 1\n")
    env = dict(os.environ, ROS_PACKAGE_PATH=os.path.dirname(os.path.abspath(NODE)))
    node_a = subprocess.Popen(["roslaunch", "--wait", LAUNCH, "ns:=a", "depth:=/cam/depth/image",
                               "queue_size:=50", "params:=" + yaml],
                              stdout=open(os.path.join(WORK, "a.log"), "wb"),
                              stderr=subprocess.STDOUT, start_new_session=True, env=env)
    procs.append(node_a)
    master = rosgraph.Master("/dao_test_probe")
    master.setParam("/b/depth_filtered/image/compressedDepth/format", "rvl")
    master.setParam("/c/depth_filtered/image/compressedDepth/format", "rvl")
    master.setParam("/c/depth_filtered/image/compressedDepth/png_level", 3)
    node_b = start([NODE, "__ns:=/b", "__name:=depthao", "depth/image:=/cam32/depth/image",
                    "_queue_size:=50", "_ao_encoding:=32FC1"], os.path.join(WORK, "b.log"))
    # node c: a's input with counts of 0.1 mm and the low preset
    node_c = start([NODE, "__ns:=/c", "__name:=depthao", "depth/image:=/cam/depth/image",
                    "_queue_size:=50", "_depth_unit:=0.0001", "_quality:=low"],
                   os.path.join(WORK, "c.log"))
    rospy.init_node("dao_test", anonymous=True, disable_signals=True)
    col_a = {"ao": Collector("/a/ao/image"), "sh": Collector("/a/shaded/image")}
    col_b = {"ao": Collector("/b/ao/image")}
    col_c = {"ao": Collector("/c/ao/image")}
    depth_cols = {}
    for n in "abc":
        depth_cols[n] = {"depth": Collector("/%s/depth_filtered/image" % n),
                         "cdepth": Collector("/%s/depth_filtered/image/compressedDepth" % n,
                                             CompressedImage)}
    depth_cols["a"]["info"] = Collector("/a/depth_filtered/camera_info", CameraInfo)
    for c in list(col_a.values()) + list(col_b.values()) + list(col_c.values()) + \
            [c for d in depth_cols.values() for c in d.values()]:
        wait_for("%s to be published" % c.topic, lambda: c.sub.get_num_connections() > 0)
    note_pid(rosgraph.Master("/dao_test_probe"), "/a/depthao", "depthao_node")
    if rospy.get_param("/a/depthao/occlusion_color") != "203040":
        fail("the parameters file was not applied: %s" % rospy.get_param("/a/depthao"))
    if "~radiuss is not a parameter of depthao_node" not in log_of("a"):
        fail("a misspelt parameter was not reported: %s" % log_of("a"))

    play(bag_a, bag_b)
    wait_for("%d AO frames of each node" % FRAMES, lambda: col_a["ao"].count() >= FRAMES and
             col_a["sh"].count() >= FRAMES and col_b["ao"].count() >= FRAMES and
             col_c["ao"].count() >= FRAMES)
    check_run("a", col_a, bag_a, FRAMES, "mono16", ["--occlusion-color", "203040"], 0)
    check_run("b", col_b, bag_b, FRAMES, "32FC1", [], 0)
    check_run("c", col_c, bag_a, FRAMES, "mono16", ["--depth-unit", "0.0001", "--quality", "low"], 0)
    wait_for("the filtered depth", lambda: all(
        c.count() >= FRAMES for d in depth_cols.values() for c in d.values()))
    counts = np.stack([np.frombuffer(d16(i).data, "<u2").reshape(H, W) for i in range(FRAMES)])
    metres = np.stack([np.frombuffer(f32_be(i).data, ">f4").reshape(H, W).astype(np.float32)
                       for i in range(FRAMES)])
    check_depth("a", depth_cols["a"], reference_depth("a", counts, 0.001), "16UC1", "png")
    check_depth("b", depth_cols["b"], reference_depth("b", metres, 0.0), "32FC1", "rvl")
    check_depth("c", depth_cols["c"], reference_depth("c", counts, 0.0001, "low"), "16UC1", "rvl")

    # dynamic_reconfigure: names for enums, ranges checked, the parameter server follows
    client = dynamic_reconfigure.client.Client("/a/depthao", timeout=TIMEOUT)
    cfg = client.update_configuration({"radius": 0.25, "prefilter": "none", "slices": 3})
    if (cfg["radius"], cfg["prefilter"], cfg["slices"]) != (0.25, 0, 3):
        fail("reconfigure: %s" % cfg)
    cfg = client.update_configuration({"radius": 500.0})
    if cfg["radius"] != 0.25:
        fail("radius 500 (out of range) was not refused: %s" % cfg["radius"])
    wait_for("the refusal in the log", lambda: "radius: 500 is out of range [0.01, 100] m; "
             "radius keeps its value" in log_of("a"))
    if rospy.get_param("/a/depthao/radius") != 0.25 or \
            rospy.get_param("/a/depthao/prefilter") != 0:
        fail("parameter server: %s" % rospy.get_param("/a/depthao"))

    # errors a publisher can cause: logged with what is wrong, the node goes on
    pub = rospy.Publisher("/cam/depth/image", Image, queue_size=10)
    pub_info = rospy.Publisher("/cam/depth/camera_info", CameraInfo, queue_size=10)
    # a and c both subscribe to /cam/depth: one connection may be c's alone, and a message
    # published then never reaches a (seen once at load 11), so wait for both
    wait_for("nodes a and c to subscribe", lambda: pub.get_num_connections() >= 2 and
             pub_info.get_num_connections() >= 2)
    rgb = image_msg(50, "rgb8", bytes(3 * W * H), 3 * W)
    pub_info.publish(info_msg(50))
    pub.publish(rgb)
    wait_for("the encoding error", lambda: "depth image encoding 'rgb8' is not accepted: "
             "depthao takes 16UC1 or mono16 (counts of depth_unit metres) or 32FC1 (metres)"
             in log_of("a"))
    small = d16(51)
    pub_info.publish(info_msg(51, W // 2, H // 2))
    pub.publish(small)
    wait_for("the size error", lambda: "the camera info is for 40x30, the depth image is 80x60"
             in log_of("a"))
    if node_a.poll() is not None:
        fail("node a stopped: %s" % log_of("a"))
    if col_a["ao"].count() != FRAMES:
        fail("%d AO frames after the errors, expected %d" % (col_a["ao"].count(), FRAMES))
    pub.unregister()
    pub_info.unregister()

    # the bag again: stamps go back, the histories start over; indices go on at FRAMES
    play(bag_a)
    wait_for("the second play", lambda: col_a["ao"].count() >= 2 * FRAMES and
             col_a["sh"].count() >= 2 * FRAMES)
    check_run("a reconfigured", col_a, bag_a, FRAMES, "mono16",
              ["--radius", "0.25", "--prefilter", "none", "--slices", "3",
               "--occlusion-color", "203040", "--frame-index", str(FRAMES)], FRAMES)
    time.sleep(1.0)
    n = (col_a["ao"].count(), col_a["sh"].count(), col_b["ao"].count(), col_c["ao"].count())
    if n != (2 * FRAMES, 2 * FRAMES, FRAMES, 2 * FRAMES):
        fail("published frames (a AO, a shaded, b AO, c AO) %s, expected %s"
             % (n, (2 * FRAMES, 2 * FRAMES, FRAMES, 2 * FRAMES)))
    for name, p in (("a", node_a), ("b", node_b), ("c", node_c)):
        if p.poll() is not None:
            fail("node %s stopped: %s" % (name, log_of(name)))
    # a camera info with distortion: P's intrinsics (the rectified image's, as
    # image_geometry), one warning; new intrinsics make a new context (indices from 0)
    bag_d = os.path.join(WORK, "distorted.bag")
    write_bag(bag_d, "/cam/depth", d16, distorted=True)
    play(bag_d)
    wait_for("the distorted play", lambda: col_a["ao"].count() >= 3 * FRAMES)
    wait_for("the distortion warning", lambda: "the camera info has distortion coefficients: "
             "depthao does not undistort, the depth must be rectified (image_rect; it is used "
             "as it is); intrinsics from P, the rectified image's" in log_of("a"))
    check_run("a distorted", col_a, bag_a, FRAMES, "mono16",
              ["--radius", "0.25", "--prefilter", "none", "--slices", "3",
               "--occlusion-color", "203040", "--intrinsics", "52,53.5,38,28"], 2 * FRAMES)
    # poses from tf: d follows the camera through tf as depthao process follows it
    # through the bag's tf; e's fixed frame is not in the tree: no poses, as motion off
    bag_m = os.path.join(WORK, "moving.bag")
    write_moving_bag(bag_m)
    node_d = start([NODE, "__ns:=/d", "__name:=depthao", "depth/image:=/mov/depth/image",
                    "_queue_size:=50", "_pose_frame:=/world", "_pose_timeout:=5",
                    "_depth_temporal_motion:=source"], os.path.join(WORK, "d.log"))
    node_e = start([NODE, "__ns:=/e", "__name:=depthao", "depth/image:=/mov/depth/image",
                    "_queue_size:=50", "_pose_frame:=nowhere", "_pose_timeout:=0.05",
                    "_depth_temporal_motion:=source"], os.path.join(WORK, "e.log"))
    from genpy.dynamic import generate_dynamic
    pose_cls = generate_dynamic("geometry_msgs/PoseStamped", POSE_STAMPED)["geometry_msgs/PoseStamped"]
    col_d, col_e = {"ao": Collector("/d/ao/image")}, {"ao": Collector("/e/ao/image")}
    col_pose = Collector("/d/camera_pose", pose_cls)
    col_pose_e = Collector("/e/camera_pose", pose_cls)
    for c in (col_d["ao"], col_e["ao"], col_pose, col_pose_e):
        wait_for("%s to be published" % c.topic, lambda: c.sub.get_num_connections() > 0)
    # rosbag play --wait-for-subscribers waits for one subscriber a topic: wait for both
    probe = rosgraph.Master("/dao_test_probe")

    def subscribed(topic, nodes):
        subs = dict(probe.getSystemState()[1]).get(topic, [])
        return all(n in subs for n in nodes)
    wait_for("d and e to subscribe to the moving camera and d to tf", lambda:
             subscribed("/mov/depth/image", ["/d/depthao", "/e/depthao"]) and
             subscribed("/mov/depth/camera_info", ["/d/depthao", "/e/depthao"]) and
             subscribed("/tf", ["/d/depthao"]) and subscribed("/tf_static", ["/d/depthao"]))
    play(bag_m)
    wait_for("%d AO frames of d and e, poses of d" % FRAMES, lambda: col_d["ao"].count() >= FRAMES
             and col_e["ao"].count() >= FRAMES and col_pose.count() >= FRAMES)
    check_run("d (poses from tf)", col_d, bag_m, FRAMES, "mono16",
              ["--depth-temporal-motion", "source", "--pose-frame", "world"], 0)
    check_run("e (no poses)", col_e, bag_m, FRAMES, "mono16",
              ["--depth-temporal-motion", "off"], 0)
    with col_d["ao"].lock, col_e["ao"].lock:
        differ = [int(np.count_nonzero(as_array(a) != as_array(b)))
                  for a, b in zip(col_d["ao"].msgs[1:FRAMES], col_e["ao"].msgs[1:FRAMES])]
    if min(differ) < W * H // 20:
        fail("d's AO (poses) differs from e's (no poses) in only %s pixels of frames 1-%d: "
             "the poses do not reach the temporal filter" % (differ, FRAMES - 1))
    print("poses: d's AO differs from motion off in %s pixels of frames 1-%d" % (differ, FRAMES - 1))
    wait_for("e's reason", lambda: "no pose for the depth image of 200.000000000 s: "
             "'cam_depth_optical' in 'nowhere'" in log_of("e"))
    for name, p in (("d", node_d), ("e", node_e)):
        if p.poll() is not None:
            fail("node %s stopped: %s" % (name, log_of(name)))
    # d's camera_pose: each frame's optical frame in the first's, the truth of the bag's tf
    # (to rounding) and depthao process --pose-out's on the same bag (to its printed digits)
    cli("--input", bag_m, "--depth-temporal-motion", "source", "--pose-frame", "world",
        "--pose-out", os.path.join(WORK, "d-poses.txt"), "--ao-out", os.path.join(WORK, "d-ao"))
    want = [[float(v) for v in l.split()[1:]] for l in open(os.path.join(WORK, "d-poses.txt"))
            if l.strip() and not l.startswith("#")]
    with col_pose.lock:
        got = list(col_pose.msgs)
    if len(got) != FRAMES or len(want) != FRAMES:
        fail("d: %d poses on camera_pose, --pose-out has %d, want %d" % (len(got), len(want), FRAMES))

    def optical(i):
        q, t = link_pose(i)
        return quat_matrix(quat_mul(q, CAM_LINK_TO_OPTICAL)), np.array(t)
    r0, t0 = optical(0)
    for i, (m, w) in enumerate(zip(got, want)):
        p, o = m.pose.position, m.pose.orientation
        v = [p.x, p.y, p.z, o.x, o.y, o.z, o.w]
        ri, ti = optical(i)
        true_r, true_t = r0.T @ ri, r0.T @ (ti - t0)
        if (m.header.stamp, m.header.frame_id) != (stamp(i), "depthao_odom") or \
                np.abs(quat_matrix(v[3:]) - true_r).max() > 1e-9 or \
                np.abs(np.array(v[:3]) - true_t).max() > 1e-9 or \
                any(abs(a - b) > (6e-10 if k < 3 else 6e-13) for k, (a, b) in enumerate(zip(v, w))):
            fail("d pose %d: %s %r %s; truth %s %s; --pose-out %s" % (
                i, m.header.stamp, m.header.frame_id, v, true_t, true_r.tolist(), w))
    print("d: %d poses on camera_pose, the truth and depthao process --pose-out's (moved %.3f m)"
          % (FRAMES, float(np.linalg.norm(want[-1][:3]))))
    # e (no poses, so no motion): the first frame's pose, the origin, and none after it
    # (its frames' AO came long ago, each before its pose)
    with col_pose_e.lock:
        got_e = list(col_pose_e.msgs)
    if len(got_e) != 1 or got_e[0].header.stamp != stamp(0) or \
            [got_e[0].pose.orientation.w, got_e[0].pose.position.x] != [1.0, 0.0]:
        fail("e: %d poses on camera_pose, want the origin of frame 0 only: %s" % (
            len(got_e), [(m.header.stamp, m.pose) for m in got_e]))
    # d's INFO lines go to stdout, a file here, buffered until it exits: stop it first
    node_d.send_signal(signal.SIGINT)
    try:
        node_d.wait(TIMEOUT)
    except subprocess.TimeoutExpired:
        fail("node d did not stop on SIGINT")
    if "poses: 'cam_depth_optical' in 'world' from tf at each image's stamp" not in log_of("d"):
        fail("d did not say where its poses come from: %s" % log_of("d"))
    # pose parameters refused at start
    expect_refused("badpose", ((["_pose_frame:=/"], "~pose_frame '/' names no frame"),
                               (["_pose_frame:=3"], "~pose_frame: give tf's fixed frame as a name"),
                               (["_pose_timeout:=11"], "~pose_timeout: 11 is not a wait"),
                               (["_pose_timeout:=soon"], "~pose_timeout: soon is not"),
                               (["_pose_frame:=odom", "_odom_frame:=odom"],
                                "~odom_frame 'odom' is ~pose_frame")))

    # a sanitizer build (bootstrap.sh test) reports into the logs and may go on
    for name in ("a", "b", "c", "d", "e", "bad", "badpose"):
        for word in ("AddressSanitizer", "runtime error:"):
            if word in log_of(name):
                fail("%s in the log of %s: %s" % (word, name, log_of(name)))
    print("ok")


if __name__ == "__main__":
    main()
