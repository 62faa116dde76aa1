# SPDX-License-Identifier: MIT
"""Colour from ROS bags through the built-in "bag" source (want_color): the
bags of make_bags.py, read back here with rosbag's own reader, give each
depth frame the colour message whose header stamp is nearest to the depth's,
converted from bgr8 / rgba8 / mono8 to RGB exactly; RealSense Color_0 is
found by itself; several colour topics need ?color=; depthao process
--overlay-out on a bag writes round(colour x AO16 / 65535) with the colour
at twice the depth's size averaged down.
usage: test_bag_color.py MAKE_BAGS COLOR_DUMP DEPTHAO   (exit 77 without
python3-rosbag, numpy or PIL)"""
import os
import subprocess
import sys
import tempfile

try:
    import numpy as np
    from PIL import Image
    import rosbag  # noqa: F401
except ImportError as e:
    print("SKIP: %s (python3-rosbag, python3-numpy, python3-pil)" % e)
    sys.exit(77)

MAKE, DUMP, DEPTHAO = sys.argv[1:4]
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what)


def messages(path, topic):
    """[(stamp_ns, message)] of a topic, by rosbag."""
    with rosbag.Bag(path) as b:
        return [(m.header.stamp.to_nsec(), m) for _, m, _ in b.read_messages(topics=[topic])]


def rgb_of(m):
    a = np.frombuffer(m.data, np.uint8)
    if m.encoding == "bgr8":
        return a.reshape(m.height, m.width, 3)[:, :, ::-1]
    if m.encoding == "rgba8":
        return a.reshape(m.height, m.width, 4)[:, :, :3]
    if m.encoding == "rgb8":
        return a.reshape(m.height, m.width, 3)
    return np.repeat(a.reshape(m.height, m.width, 1), 3, axis=2)  # mono8


def nearest(stamps, t):
    best = 0
    for i, s in enumerate(stamps):
        if abs(s - t) < abs(stamps[best] - t):
            best = i
    return best


def dump(uri, out):
    os.makedirs(out, exist_ok=True)
    p = subprocess.run([DUMP, uri, out], capture_output=True, text=True)
    if p.returncode:
        return None, p.stderr
    return [tuple(int(v) for v in l.split()) for l in p.stdout.splitlines()], p.stderr


def check_pairs(name, uri, bag, depth_topic, color_topic, tmp):
    depth = messages(bag, depth_topic)
    colour = messages(bag, color_topic)
    stamps = [s for s, _ in colour]
    lines, err = dump(uri, os.path.join(tmp, name))
    check(lines is not None and len(lines) == len(depth),
          "%s: %s frames (%s)" % (name, lines and len(lines), err))
    pairs = []
    for index, dseq, dts, cseq, cts in lines or []:
        want = nearest(stamps, depth[index][0])
        pairs.append(want)
        check(cseq == want + 1 and cts * 1000 == stamps[want],
              "%s: depth %d paired with colour %d, want %d" % (name, index, cseq - 1, want))
        got = np.asarray(Image.open(os.path.join(tmp, name, "%06d.ppm" % index)))
        ref = rgb_of(colour[want][1])
        check(got.shape == ref.shape and np.array_equal(got, ref),
              "%s frame %d: colour differs from the message's pixels" % (name, index))
    print("%s: %d frames, colour pairs %s by nearest stamp, pixels exact" % (name, len(pairs),
                                                                           pairs))
    return pairs


def main():
    with tempfile.TemporaryDirectory() as tmp:
        bags = os.path.join(tmp, "bags")
        p = subprocess.run([sys.executable, MAKE, bags], capture_output=True, text=True)
        if p.returncode == 77:
            print("SKIP: " + p.stdout)
            return 77
        if p.returncode:
            print("FAIL: make_bags.py: %s" % p.stderr)
            return 1
        color = os.path.join(bags, "color.bag")
        pairs = check_pairs("bgr8 2x, own rate", color, color,
                            "/camera/aligned_depth_to_color/image_raw",
                            "/camera/color/image_raw", tmp)
        check(pairs == [0, 2, 3, 4, 6], "pairs %s, want [0, 2, 3, 4, 6]" % pairs)
        colors = os.path.join(bags, "colors.bag")
        for enc in ("rgba", "mono"):
            check_pairs(enc, "bag:%s?color=/cam/%s/image_raw" % (colors, enc), colors,
                        "/cam/depth/image_raw", "/cam/%s/image_raw" % enc, tmp)
        rs = os.path.join(bags, "realsense.bag")
        check_pairs("realsense Color_0", rs, rs, "/device_0/sensor_0/Depth_0/image/data",
                    "/device_0/sensor_1/Color_0/image/data", tmp)
        # two colour topics: choose
        lines, err = dump(colors, os.path.join(tmp, "ambiguous"))
        check(lines is None and "2 colour topics" in err and "/cam/rgba/image_raw" in err
              and "?color=" in err, "two colour topics: %s" % err)
        lines, err = dump("bag:%s?color=/cam/depth/image_raw" % colors, os.path.join(tmp, "x"))
        check(lines is None and "not colour" in err, "a depth topic as colour: %s" % err)

        # depthao process --overlay-out: colour x AO, the 2x colour averaged down
        ao, ov = os.path.join(tmp, "ao"), os.path.join(tmp, "ov")
        p = subprocess.run([DEPTHAO, "process", "--input", color, "--ao-out", ao,
                            "--overlay-out", ov], capture_output=True, text=True)
        check(p.returncode == 0, "process --overlay-out on a bag: %s" % p.stderr)
        check("not registered" not in p.stderr, "aligned_depth_to_color warned: %s" % p.stderr)
        colour = messages(color, "/camera/color/image_raw")
        occluded = 0
        for i, want in enumerate(pairs if p.returncode == 0 else []):
            c = rgb_of(colour[want][1]).astype(np.float64)
            h, w = c.shape[0] // 2, c.shape[1] // 2
            small = np.floor(c.reshape(h, 2, w, 2, 3).mean(axis=(1, 3)) + 0.5).astype(np.uint32)
            a = np.asarray(Image.open(os.path.join(ao, "%06d.png" % i)), dtype=np.uint32)
            o = np.asarray(Image.open(os.path.join(ov, "%06d.png" % i)).convert("RGB"))
            want_o = (small * a[:, :, None] + 32767) // 65535
            check(np.array_equal(o, want_o), "bag overlay frame %d: %d pixels differ" % (
                i, np.count_nonzero(np.any(o != want_o, axis=2))))
            occluded += int(np.count_nonzero(a < 65535))
        check(occluded > 0, "no occlusion in the bag's AO: the overlay test would not see it")
        # a bag without colour, with an overlay output: refused at start
        p = subprocess.run([DEPTHAO, "process", "--input", os.path.join(bags, "two.bag") +
                            "?topic=/cam1/depth/image_raw", "--overlay-out",
                            os.path.join(tmp, "none")], capture_output=True, text=True)
        check(p.returncode == 1 and "depth only" in p.stderr, "depth-only bag: %s" % p.stderr)
        print("process --overlay-out on a bag: colour x AO (%d occluded pixels); "
              "a bag without colour is refused" % occluded)
    if failures:
        print("%d failure(s)" % len(failures))
        return 1
    return 0


sys.exit(main())
