# SPDX-License-Identifier: MIT
"""Colour nodes of .oni recordings, read through depthao's "oni" source
(oni-color-dump) and checked against independent decoders: the Kinect
recording's JPEG frames decoded by PIL from the bytes this script's own
record walker finds, raw RGB888 / YUV422 / YUYV / GRAY8 and JPEG nodes
written by oni_py.Writer with known pixels, and each depth frame's colour
partner against the nearest timestamp.  Exit 77 without PIL or the data."""
import io
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import oni_py  # noqa: E402

try:
    import numpy as np
    from PIL import Image
except ImportError as e:
    print("SKIP: %s (python3-numpy, python3-pil)" % e)
    sys.exit(77)

DUMP = sys.argv[1]
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what)


def dump(path, out):
    p = subprocess.run([DUMP, path, out], capture_output=True, text=True)
    if p.returncode:
        return None, p.stderr
    lines = [tuple(int(v) for v in l.split()) for l in p.stdout.splitlines()]
    return lines, p.stderr


def ppm(path):
    return np.asarray(Image.open(path).convert("RGB"))


def yuv_to_rgb(y, u, v):
    """BT.601 full range (JFIF), rounded and clamped."""
    y, u, v = (np.asarray(a, dtype=np.float64) for a in (y, u, v))
    r = y + 1.402 * (v - 128)
    g = y - 0.344136 * (u - 128) - 0.714136 * (v - 128)
    b = y + 1.772 * (u - 128)
    return np.clip(np.floor(np.stack([r, g, b], -1) + 0.5), 0, 255).astype(np.uint8)


def kinect(tmp):
    data = os.environ.get("DAO_SHARED_DATA", "../shared/data")
    path = os.path.join(data, "oni", "3DJ_test.oni")
    if not os.path.exists(path):
        print("SKIP part: %s is absent" % path)
        return
    frames, nodes = oni_py.frames(path)
    depth_id = next(k for k, v in nodes.items() if v[1] == oni_py.DEPTH)
    color_id = next(k for k, v in nodes.items() if v[1] == oni_py.IMAGE)
    check(nodes[color_id][2] == "JPEG", "the Kinect colour node is JPEG: %s" % (nodes[color_id],))
    out = os.path.join(tmp, "kinect")
    os.mkdir(out)
    lines, err = dump(path, out)
    check(lines is not None, "oni-color-dump on the Kinect recording: %s" % err)
    if lines is None:
        return
    check(len(lines) == len(frames[depth_id]) == 12, "12 frames: %d" % len(lines))
    cts = [f[0] for f in frames[color_id]]
    worst = 0
    for index, dseq, dts, cseq, cts_us in lines:
        # the pairing: the colour frame recorded nearest in time; here colour N with depth N
        want = oni_py.nearest(cts, frames[depth_id][index][0])
        check(cts_us == cts[want] and cseq == frames[color_id][want][1],
              "frame %d: colour %d at %d us, want %d at %d" % (index, cseq, cts_us,
                                                             frames[color_id][want][1], cts[want]))
        check(cseq == dseq, "Kinect frame %d: colour %d with depth %d" % (index, cseq, dseq))
        got = ppm(os.path.join(out, "%06d.ppm" % index))
        ref = np.asarray(Image.open(io.BytesIO(frames[color_id][want][2])).convert("RGB"))
        check(got.shape == (480, 640, 3), "frame %d is %s" % (index, got.shape))
        if got.shape == ref.shape:
            worst = max(worst, int(np.abs(got.astype(int) - ref.astype(int)).max()))
        # a real picture, not a constant: many distinct colours
        check(len(np.unique(got.reshape(-1, 3), axis=0)) > 1000, "frame %d is flat" % index)
    # the same libjpeg decoding (accurate DCT, fancy upsampling) as PIL's: identical
    check(worst == 0, "Kinect JPEG frames differ from PIL's decoding by up to %d" % worst)
    print("kinect: 12 JPEG frames identical to PIL's decoding, colour N with depth N")


def synthetic(tmp, name, codec, pixel_format, xn, payload_of, expect, w=8, h=6):
    """A recording with a 16-bit depth node and one colour node; colour leads depth by
    12 ms, then lags it by 20 ms (33 ms apart), so pairing by nearest time is tested."""
    rng = np.random.default_rng(len(name))
    wr = oni_py.Writer()
    wr.node(1, "Depth1", oni_py.DEPTH, "NONE", w, h)
    props = {"xnPixelFormat": xn} if xn else {"oniPixelFormat": pixel_format}
    wr.node(2, "Image1", oni_py.IMAGE, codec, w, h, props=props)
    depth_ts = [100000 + 33333 * i for i in range(5)]
    color_ts = [t - 12000 for t in depth_ts[:3]] + [depth_ts[3] + 20000, depth_ts[4] + 20000]
    raws = []
    events = []
    for i, t in enumerate(color_ts):
        raw = rng.integers(0, 256, size=(h, w, 3), dtype=np.uint8)
        raws.append(raw)
        events.append((t, 2, i))
    for i, t in enumerate(depth_ts):
        events.append((t, 1, i))
    for t, nid, i in sorted(events):
        if nid == 1:
            d = np.full((h, w), 1000 + i, dtype="<u2")
            wr.frame(1, t, i + 1, d.tobytes())
        else:
            wr.frame(2, t, i + 1, payload_of(raws[i]))
    path = os.path.join(tmp, name + ".oni")
    wr.save(path)
    out = os.path.join(tmp, name)
    os.mkdir(out)
    lines, err = dump(path, out)
    check(lines is not None, "%s: oni-color-dump: %s" % (name, err))
    if lines is None:
        return
    check(len(lines) == 5, "%s: 5 frames, got %d" % (name, len(lines)))
    worst = 0
    for index, dseq, dts, cseq, cts_us in lines:
        want = oni_py.nearest(color_ts, depth_ts[index])
        check(cseq == want + 1 and cts_us == color_ts[want],
              "%s: depth %d paired with colour %d, want %d" % (name, index, cseq, want + 1))
        got = ppm(os.path.join(out, "%06d.ppm" % index)).astype(int)
        worst = max(worst, int(np.abs(got - expect(raws[want], payload_of(raws[want]))
                                      .astype(int)).max()))
    check(worst <= (1 if codec == "NONE" else 0), "%s: pixels off by up to %d" % (name, worst))
    print("%s: 5 frames, pairs by nearest time, pixels within %d" % (name, worst))


def broken(tmp):
    """A raw colour frame of the wrong size, and the Im8z codec: the colour is left out
    with the reason (info.warning), the depth still opens."""
    for name, codec, fmt, payload in [("short", "NONE", 200, bytes(8 * 6 * 3 - 1)),
                                      ("im8z", "Im8z", 202, bytes(10))]:
        wr = oni_py.Writer()
        wr.node(1, "Depth1", oni_py.DEPTH, "NONE", 8, 6)
        wr.node(2, "Image1", oni_py.IMAGE, codec, 8, 6, props={"oniPixelFormat": fmt})
        wr.frame(2, 1000, 1, payload)
        wr.frame(1, 2000, 1, np.full((6, 8), 900, "<u2").tobytes())
        path = os.path.join(tmp, name + ".oni")
        wr.save(path)
        out = os.path.join(tmp, name)
        os.mkdir(out)
        lines, err = dump(path, out)
        want = "not what a raw" if name == "short" else "codec 'Im8z'"
        check(lines is None and "no colour:" in err and want in err,
              "%s: the colour is not refused with its reason: %s" % (name, err))
    print("a colour node that cannot be decoded: left out with the reason, depth opens")


def main():
    with tempfile.TemporaryDirectory() as tmp:
        kinect(tmp)
        # RGB888, raw
        synthetic(tmp, "rgb888", "NONE", 200, 0, lambda a: a.tobytes(), lambda a, p: a)
        # OpenNI 1's xnPixelFormat 1 = RGB24 means the same
        synthetic(tmp, "rgb24-xn", "NONE", 0, 1, lambda a: a.tobytes(), lambda a, p: a)
        # GRAY8: the first channel as grey
        synthetic(tmp, "gray8", "NONE", 202, 0, lambda a: a[:, :, 0].tobytes(),
                  lambda a, p: np.repeat(a[:, :, :1], 3, axis=2))

        # YUV422 (U Y0 V Y1) and YUYV (Y0 U Y1 V): the raw channels as Y, U, V samples
        def yuv(order):
            def payload(a):
                b = a.reshape(a.shape[0], -1, 2, 3)
                y0, y1, u, v = b[:, :, 0, 0], b[:, :, 1, 0], b[:, :, 0, 1], b[:, :, 0, 2]
                q = [u, y0, v, y1] if order == "uyvy" else [y0, u, y1, v]
                return np.stack(q, -1).astype(np.uint8).tobytes()

            def expect(a, p):
                b = a.reshape(a.shape[0], -1, 2, 3)
                u, v = b[:, :, 0, 1], b[:, :, 0, 2]
                rgb0 = yuv_to_rgb(b[:, :, 0, 0], u, v)
                rgb1 = yuv_to_rgb(b[:, :, 1, 0], u, v)
                return np.stack([rgb0, rgb1], 2).reshape(a.shape)
            return payload, expect
        p, e = yuv("uyvy")
        synthetic(tmp, "yuv422", "NONE", 201, 0, p, e)
        p, e = yuv("yuyv")
        synthetic(tmp, "yuyv", "NONE", 205, 0, p, e)

        # JPEG written by PIL, 32x16 (4:2:0): decoded as PIL decodes it
        def jpeg(a):
            buf = io.BytesIO()
            Image.fromarray(np.kron(a, np.ones((2, 2, 1), dtype=np.uint8))[:16, :32])\
                .save(buf, "JPEG", quality=90)
            return buf.getvalue()
        synthetic(tmp, "jpeg", "JPEG", 204, 0, jpeg,
                  lambda a, p: np.asarray(Image.open(io.BytesIO(p)).convert("RGB")), w=32, h=16)
        broken(tmp)
    if failures:
        print("%d failure(s)" % len(failures))
        return 1
    return 0


sys.exit(main())
