#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Writes the test bags with rosbag's own Python writer (python3-rosbag).

usage: make_bags.py OUTDIR
       make_bags.py --seeds OUTDIR   the fuzzer's seed corpus (fuzz/corpus/bag): 8x6
                                     images, 2 frames, the .bag files only
Exits 77 (skip) when rosbag or sensor_msgs cannot be imported.

The depth of frame i at pixel (x, y) is depth_count(x, y, i) (test_source_bag.c
computes the same); 0 on the diagonal x == y (no data).  Files written:
  d16_none.bag, d16_bz2.bag, d16_lz4.bag  16UC1 on /camera/depth/image_raw
      (+ /camera/depth/camera_info, and an rgb8 topic that is not depth);
      header stamps 100 + i s + i ms
  f32_be.bag     32FC1 metres, big-endian, header stamp 0 (record times count),
                 NaN on the diagonal, lz4 chunks
  two.bag        two 16UC1 topics /cam1/depth/image_raw, /cam2/depth/image_raw
  realsense.bag  the realsense-viewer layout, Depth Units 0.0001, bz2 chunks
  unindexed.bag  d16_lz4.bag as a crash after frame 2 leaves it: 3 frames (--seeds: 1), chunks
                 closed, no index (the header's index_pos still 0)
  color.bag      16UC1 on /camera/aligned_depth_to_color/image_raw and bgr8 colour at
                 twice the size on /camera/color/image_raw, at its own rate (one every
                 0.7 s from 99.9 s; depth at 100 + i s + i ms): colour_pixel() below
  colors.bag     d16 frames with two colour topics, rgba8 and mono8, of the depth's size
  implausible.bag  d16 frames with a CameraInfo whose fx is 1e308 (refused)
  distorted.bag  d16 frames with a CameraInfo that has distortion and a P (P_RECT) other
                 than K: the rectified camera's intrinsics (also a seed)
  png/NNNNNN.png and png/camera.json  the frames of d16_*.bag as 16-bit PNGs
"""
import json
import os
import struct
import sys
import zlib

try:
    import genpy
    import rosbag
    from sensor_msgs.msg import CameraInfo, Image
    from std_msgs.msg import Float32
except ImportError as e:
    print("skip: python3-rosbag / python3-sensor-msgs not importable: %s" % e)
    sys.exit(77)

W, H, FRAMES = 64, 48, 5
# chunks of about two frames: the index spans several chunks
CHUNK = 10000
K = [60.0, 0.0, 31.5, 0.0, 61.0, 23.25, 0.0, 0.0, 1.0]
# distorted.bag's P: fx 45, fy 46.5, cx 30, cy 22 (the rectified image's camera)
P_RECT = [45.0, 0.0, 30.0, 0.0, 0.0, 46.5, 22.0, 0.0, 0.0, 0.0, 1.0, 0.0]


def depth_count(x, y, i):
    return 0 if x == y else 500 + 7 * x + 13 * y + 100 * i


def pixels(i):
    return [depth_count(x, y, i) for y in range(H) for x in range(W)]


def image(i, encoding, data, step, stamp, big_endian=0):
    m = Image()
    m.header.seq = i
    m.header.stamp = stamp
    m.header.frame_id = "depth_optical"
    m.height, m.width = H, W
    m.encoding = encoding
    m.is_bigendian = big_endian
    m.step = step
    m.data = data
    return m


def d16(i, stamp):
    return image(i, "16UC1", struct.pack("<%dH" % (W * H), *pixels(i)), 2 * W, stamp)


def camera_info(distorted=False):
    c = CameraInfo()
    c.header.frame_id = "depth_optical"
    c.height, c.width = H, W
    c.distortion_model = "plumb_bob"
    c.D = [-0.12, 0.03, 0.001, 0.0, 0.0] if distorted else [0.0] * 5
    c.K = K
    c.R = [1.0, 0, 0, 0, 1.0, 0, 0, 0, 1.0]
    c.P = P_RECT if distorted else K[:3] + [0.0] + K[3:6] + [0.0] + K[6:] + [0.0]
    return c


def rgb(i, stamp):
    return image(i, "rgb8", bytes((x + y + i) % 256 for y in range(H) for x in range(W)
                                  for _ in range(3)), 3 * W, stamp)


def stamp(i):
    return genpy.Time(100 + i, i * 1000000)


def write_d16(path, compression):
    with rosbag.Bag(path, "w", compression=compression, chunk_threshold=CHUNK) as b:
        b.write("/camera/depth/camera_info", camera_info(), stamp(0))
        for i in range(FRAMES):
            t = stamp(i) + genpy.Duration(0, 3000000)  # recorded 3 ms after capture
            b.write("/camera/color/image_raw", rgb(i, stamp(i)), t)
            b.write("/camera/depth/image_raw", d16(i, stamp(i)), t)


def write_distorted(path):
    with rosbag.Bag(path, "w") as b:
        b.write("/camera/depth/camera_info", camera_info(True), stamp(0))
        for i in range(FRAMES):
            b.write("/camera/depth/image_raw", d16(i, stamp(i)), stamp(i))


def write_implausible(path):
    """A CameraInfo whose K has fx = 1e308 (finite, > 0, and no camera's)."""
    with rosbag.Bag(path, "w") as b:
        c = camera_info()
        c.K = [1e308] + list(K[1:])
        c.P = [1e308] + list(c.P[1:])
        b.write("/camera/depth/camera_info", c, stamp(0))
        for i in range(FRAMES):
            b.write("/camera/depth/image_raw", d16(i, stamp(i)), stamp(i))


def write_unindexed(path, crash_copy):
    with rosbag.Bag(path, "w", compression="lz4", chunk_threshold=CHUNK) as b:
        b.write("/camera/depth/camera_info", camera_info(), stamp(0))
        for i in range(FRAMES):
            t = stamp(i) + genpy.Duration(0, 3000000)
            b.write("/camera/color/image_raw", rgb(i, stamp(i)), t)
            b.write("/camera/depth/image_raw", d16(i, stamp(i)), t)
            if i == min(2, FRAMES - 2):  # what the disk holds if the writer dies now
                b.flush()
                b._file.flush()
                with open(path, "rb") as f, open(crash_copy, "wb") as out:
                    out.write(f.read())
    os.unlink(path)


def write_f32_be(path):
    with rosbag.Bag(path, "w", compression="lz4", chunk_threshold=CHUNK) as b:
        b.write("/cam/depth/camera_info", camera_info(), genpy.Time(50, 0))
        for i in range(FRAMES):
            v = [float("nan") if c == 0 else c / 1000.0 for c in pixels(i)]
            data = struct.pack(">%df" % (W * H), *v)
            b.write("/cam/depth/image", image(i, "32FC1", data, 4 * W, genpy.Time(0, 0), 1),
                    genpy.Time(50, 250000000 * i))


def write_two(path):
    with rosbag.Bag(path, "w") as b:
        for i in range(FRAMES):
            b.write("/cam1/depth/image_raw", d16(i, stamp(i)), stamp(i))
            b.write("/cam2/depth/image_raw", d16(i + 1, stamp(i)), stamp(i))
        b.write("/cam2/depth/camera_info", camera_info(), stamp(0))


def write_realsense(path):
    with rosbag.Bag(path, "w", compression="bz2", chunk_threshold=CHUNK) as b:
        b.write("/device_0/sensor_0/option/Depth Units/value", Float32(0.0001), stamp(0))
        b.write("/device_0/sensor_0/Depth_0/info/camera_info", camera_info(), stamp(0))
        for i in range(FRAMES):
            b.write("/device_0/sensor_1/Color_0/image/data", rgb(i, stamp(i)), stamp(i))
            b.write("/device_0/sensor_0/Depth_0/image/data", d16(i, stamp(i)), stamp(i))


def colour_pixel(x, y, j):
    """Colour message j at (x, y), as R, G, B."""
    return ((3 * x + 40 * j) % 256, (5 * y + 7 * x) % 256, (x * y + 90 * j) % 256)


def colour_stamp(j):
    return genpy.Time(99, 900000000) + genpy.Duration(0, 700000000 * j)


def colour_image(j, encoding, w, h):
    px = [colour_pixel(x, y, j) for y in range(h) for x in range(w)]
    if encoding == "bgr8":
        data, step = bytes(c for p in px for c in (p[2], p[1], p[0])), 3 * w
    elif encoding == "rgba8":
        data, step = bytes(c for p in px for c in (p[0], p[1], p[2], 200)), 4 * w
    else:  # mono8: the red channel
        data, step = bytes(p[0] for p in px), w
    m = image(j, encoding, data, step, colour_stamp(j))
    m.width, m.height = w, h
    m.header.frame_id = "color_optical"
    return m


def write_color(path):
    """Depth and colour at different rates, written in record-time order."""
    with rosbag.Bag(path, "w", compression="lz4", chunk_threshold=CHUNK) as b:
        b.write("/camera/aligned_depth_to_color/camera_info", camera_info(), stamp(0))
        msgs = []
        for i in range(FRAMES):
            msgs.append((stamp(i) + genpy.Duration(0, 3000000),
                         "/camera/aligned_depth_to_color/image_raw", d16(i, stamp(i))))
        for j in range(int(FRAMES / 0.7) + 2):
            msgs.append((colour_stamp(j) + genpy.Duration(0, 5000000),
                         "/camera/color/image_raw", colour_image(j, "bgr8", 2 * W, 2 * H)))
        for t, topic, m in sorted(msgs, key=lambda x: x[0]):
            b.write(topic, m, t)


def write_colors(path):
    with rosbag.Bag(path, "w") as b:
        for i in range(FRAMES):
            b.write("/cam/depth/image_raw", d16(i, stamp(i)), stamp(i))
            b.write("/cam/rgba/image_raw", colour_image(i, "rgba8", W, H), stamp(i))
            b.write("/cam/mono/image_raw", colour_image(i, "mono8", W, H), stamp(i))


def png_chunk(kind, data):
    return (struct.pack(">I", len(data)) + kind + data +
            struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))


def write_png(path, counts):
    raw = b"".join(b"\0" + struct.pack(">%dH" % W, *counts[y * W:(y + 1) * W]) for y in range(H))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(png_chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, 16, 0, 0, 0, 0)))
        f.write(png_chunk(b"IDAT", zlib.compress(raw)))
        f.write(png_chunk(b"IEND", b""))


def main():
    global W, H, FRAMES, CHUNK, K, P_RECT
    seeds = len(sys.argv) == 3 and sys.argv[1] == "--seeds"
    if len(sys.argv) != 2 and not seeds:
        sys.exit(__doc__)
    out = sys.argv[-1]
    if seeds:
        W, H, FRAMES, CHUNK = 8, 6, 2, 300
        # the intrinsics scaled to the small images: implausible ones (a principal
        # point far outside the image) are refused (dao_camera_from_intrinsics)
        K = [v * W / 64.0 if v not in (0.0, 1.0) else v for v in K]
        P_RECT = [v * W / 64.0 if v not in (0.0, 1.0) else v for v in P_RECT]
    os.makedirs(out, exist_ok=True)
    for comp in ("none", "bz2", "lz4"):
        write_d16(os.path.join(out, "d16_%s.bag" % comp), comp)
    write_f32_be(os.path.join(out, "f32_be.bag"))
    if not seeds:
        write_two(os.path.join(out, "two.bag"))
        write_color(os.path.join(out, "color.bag"))
        write_colors(os.path.join(out, "colors.bag"))
    write_distorted(os.path.join(out, "distorted.bag"))
    if not seeds:
        write_implausible(os.path.join(out, "implausible.bag"))
    write_realsense(os.path.join(out, "realsense.bag"))
    write_unindexed(os.path.join(out, "finished.bag"), os.path.join(out, "unindexed.bag"))
    if seeds:
        return
    os.makedirs(os.path.join(out, "png"), exist_ok=True)
    for i in range(FRAMES):
        write_png(os.path.join(out, "png", "%06d.png" % i), pixels(i))
    # Open3D's camera JSON: the intrinsic matrix column-major
    cam = {"width": W, "height": H,
           "intrinsic_matrix": [K[0], K[3], K[6], K[1], K[4], K[7], K[2], K[5], K[8]]}
    with open(os.path.join(out, "png", "camera.json"), "w") as f:
        json.dump(cam, f)


if __name__ == "__main__":
    main()
