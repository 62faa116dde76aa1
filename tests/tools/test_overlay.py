# SPDX-License-Identifier: MIT
"""AO over colour in depthao process (--overlay-out) and depthaod (stream
overlay): every overlay pixel is round(colour x AO16 / 65535), with the colour
decoded independently (PIL on the JPEG bytes of the Kinect recording, known
pixels of recordings written by tests/oni/oni_py.py) and the AO from the same
run's --ao-out; colour of twice the depth's size is averaged down (bilinear
at pixel centres); another aspect ratio and depth-only input are errors at
start, with a message, and nothing is written.
usage: test_overlay.py DEPTHAO DEPTHAOD"""
import io
import os
import subprocess
import sys
import tempfile

ROOT = os.environ.get("DAO_SOURCE_ROOT", os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tests", "oni"))
import oni_py  # noqa: E402

try:
    import numpy as np
    from PIL import Image
except ImportError as e:
    print("SKIP: %s (python3-numpy, python3-pil)" % e)
    sys.exit(77)

DEPTHAO, DEPTHAOD = sys.argv[1], sys.argv[2]
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what)


def run(args):
    return subprocess.run(args, capture_output=True, text=True, timeout=300)


def png(path):
    im = Image.open(path)
    if im.mode in ("I;16", "I;16B", "I"):
        return np.asarray(im, dtype=np.uint32)
    return np.asarray(im.convert("RGB"), dtype=np.uint32)


def composite(color, ao16):
    return (color * ao16[:, :, None] + 32767) // 65535


def check_dir(name, ao_dir, ov_dir, colours):
    """colours: frame index -> the expected colour at the overlay's size."""
    files = sorted(os.listdir(ov_dir))
    check(files == ["%06d.png" % i for i in sorted(colours)],
          "%s: overlay files %s" % (name, files[:5]))
    darker = 0
    for i, colour in colours.items():
        ao = png(os.path.join(ao_dir, "%06d.png" % i))
        ov = png(os.path.join(ov_dir, "%06d.png" % i))
        want = composite(colour.astype(np.uint32), ao)
        bad = int(np.count_nonzero(np.any(ov != want, axis=2)))
        check(bad == 0, "%s frame %d: %d pixels are not colour x AO" % (name, i, bad))
        darker += int(np.count_nonzero(ao < 65535 * 0.9))
    check(darker > 0, "%s: no occluded pixels: the test would not see the AO" % name)
    return darker


def kinect(tmp):
    data = os.environ.get("DAO_SHARED_DATA", os.path.join(ROOT, "..", "shared", "data"))
    rec = os.path.join(data, "oni", "3DJ_test.oni")
    if not os.path.exists(rec):
        print("SKIP part: %s is absent" % rec)
        return
    frames, nodes = oni_py.frames(rec)
    depth_id = next(k for k, v in nodes.items() if v[1] == oni_py.DEPTH)
    color_id = next(k for k, v in nodes.items() if v[1] == oni_py.IMAGE)
    cts = [f[0] for f in frames[color_id]]

    def colour(i):
        j = oni_py.nearest(cts, frames[depth_id][i][0])
        return np.asarray(Image.open(io.BytesIO(frames[color_id][j][2])).convert("RGB"))
    ao, ov = os.path.join(tmp, "k-ao"), os.path.join(tmp, "k-ov")
    p = run([DEPTHAO, "process", "--input", rec, "--start", "2", "--frames", "3", "--ao-out", ao,
             "--overlay-out", ov, "--quiet"])
    check(p.returncode == 0, "process --overlay-out on the Kinect recording: %s" % p.stderr)
    if p.returncode == 0:
        n = check_dir("process kinect", ao, ov, {i: colour(i) for i in (2, 3, 4)})
        print("process: Kinect overlay frames 2-4 = colour x AO exactly (%d occluded pixels)" % n)
    # OpenNI2's own playback of the file (when its plugin is built): the same colour frame
    # with each depth frame, decoded alike (the AO differs by a count or two: OpenNI2 gives
    # the field of view in single precision)
    dev = run([DEPTHAO, "devices"])
    if any(l.startswith("  openni2 ") for l in dev.stdout.splitlines()):
        nov = os.path.join(tmp, "ni-ov")
        p = run([DEPTHAO, "process", "--input", "openni2:" + rec, "--frames", "6",
                 "--overlay-out", nov, "--quiet"])
        check(p.returncode == 0, "process --overlay-out through OpenNI2: %s" % p.stderr)
        own = os.path.join(tmp, "own-ov")
        run([DEPTHAO, "process", "--input", rec, "--frames", "6", "--overlay-out", own,
             "--quiet"])
        for i in range(6 if p.returncode == 0 else 0):
            a, b = (png(os.path.join(d, "%06d.png" % i)).astype(int) for d in (own, nov))
            diff = np.abs(a - b)
            check(diff.max() <= 1 and diff.mean() < 0.001,
                  "frame %d: overlay differs from OpenNI2's playback (max %d, mean %.4f)"
                  % (i, diff.max(), diff.mean()))
        print("overlay frames 0-5 = OpenNI2 playback's within 1 (same colour pairing)")
    else:
        print("note: no openni2 plugin; the comparison with OpenNI2's playback was skipped")
    # the daemon, its overlay and AO sinks in one run
    dao, dov = os.path.join(tmp, "d-ao"), os.path.join(tmp, "d-ov")
    p = run([DEPTHAOD, "--source", rec, "--playback", "manual", "--max-frames", "3",
             "--sink", "a=images:" + dao, "--stream", "a=ao",
             "--sink", "o=images:" + dov, "--stream", "o=overlay"])
    check(p.returncode == 0, "depthaod overlay on the Kinect recording: %s" % p.stderr)
    if p.returncode == 0:
        check_dir("depthaod kinect", dao, dov, {i: colour(i) for i in (0, 1, 2)})
        print("depthaod: Kinect overlay frames 0-2 = colour x AO exactly")


def recording(path, depth_size, color_size, registered=True):
    """A 4-frame recording: a tilted floor and a box (depth, mm) and random colour."""
    (w, h), (cw, ch) = depth_size, color_size
    rng = np.random.default_rng(7)
    wr = oni_py.Writer()
    wr.node(1, "Depth1", oni_py.DEPTH, "NONE", w, h,
            props={"AlternativeViewPoint": 1 if registered else 0})
    wr.general(1, "xnFOV", np.array([1.0, 0.78], dtype="<f8").tobytes())
    wr.node(2, "Image1", oni_py.IMAGE, "NONE", cw, ch, props={"oniPixelFormat": 200})
    y, x = np.mgrid[0:h, 0:w]
    colours = []
    for i in range(4):
        d = (1500 + 20 * y - 3 * x).astype("<u2")
        d[h // 3:2 * h // 3, w // 3:w // 2] -= 400  # a box standing out of the floor
        c = rng.integers(0, 256, size=(ch, cw, 3), dtype=np.uint8)
        colours.append(c)
        wr.frame(2, 1000 + 33333 * i, i + 1, c.tobytes())
        wr.frame(1, 2000 + 33333 * i, i + 1, d.tobytes())
    wr.save(path)
    return colours


def synthetic(tmp):
    # the same size: pixel for pixel
    rec = os.path.join(tmp, "same.oni")
    colours = recording(rec, (64, 48), (64, 48))
    ao, ov = os.path.join(tmp, "s-ao"), os.path.join(tmp, "s-ov")
    p = run([DEPTHAO, "process", "--input", rec, "--ao-out", ao, "--overlay-out", ov, "--quiet"])
    check(p.returncode == 0, "process, same size: %s" % p.stderr)
    if p.returncode == 0:
        check_dir("same size", ao, ov, dict(enumerate(colours)))
        print("same size: 4 overlay frames = colour x AO")
    # colour at twice the size: each overlay pixel from the mean of its 2x2 colour pixels
    rec = os.path.join(tmp, "double.oni")
    colours = recording(rec, (64, 48), (128, 96))
    ao, ov = os.path.join(tmp, "d-ao2"), os.path.join(tmp, "d-ov2")
    p = run([DEPTHAO, "process", "--input", rec, "--ao-out", ao, "--overlay-out", ov, "--quiet"])
    check(p.returncode == 0, "process, colour 2x: %s" % p.stderr)
    if p.returncode == 0:
        small = {i: np.floor(c.astype(np.float64).reshape(48, 2, 64, 2, 3).mean(axis=(1, 3)) +
                             0.5) for i, c in enumerate(colours)}
        check_dir("colour 2x", ao, ov, small)
        check(png(os.path.join(ov, "000000.png")).shape == (48, 64, 3), "2x: overlay size")
        print("colour 2x: scaled to the depth's 64x48, = mean of 2x2 x AO")
    # another aspect ratio: refused at start
    rec = os.path.join(tmp, "aspect.oni")
    recording(rec, (64, 48), (64, 36))
    ov = os.path.join(tmp, "a-ov")
    p = run([DEPTHAO, "process", "--input", rec, "--overlay-out", ov, "--quiet"])
    check(p.returncode == 1 and "aspect ratio" in p.stderr and "64x36" in p.stderr,
          "another aspect ratio: exit %d, %s" % (p.returncode, p.stderr))
    check(not os.path.exists(ov) or not os.listdir(ov), "another aspect ratio: files written")
    p = run([DEPTHAOD, "--source", rec, "--playback", "manual",
             "--sink", "o=images:" + ov, "--stream", "o=overlay"])
    check(p.returncode == 1 and "aspect ratio" in p.stderr,
          "depthaod, another aspect ratio: exit %d, %s" % (p.returncode, p.stderr[-400:]))
    # not registered: it works, with a warning
    rec = os.path.join(tmp, "unreg.oni")
    recording(rec, (64, 48), (64, 48), registered=False)
    p = run([DEPTHAO, "process", "--input", rec, "--overlay-out", os.path.join(tmp, "u-ov")])
    check(p.returncode == 0 and "not registered" in p.stderr,
          "unregistered: exit %d, %s" % (p.returncode, p.stderr))


def depth_only(tmp):
    rec = os.path.join(ROOT, "recordings", "spheres-rolling.oni")
    ov = os.path.join(tmp, "none")
    p = run([DEPTHAO, "process", "--input", rec, "--overlay-out", ov, "--ao-out",
             os.path.join(tmp, "none-ao"), "--quiet"])
    check(p.returncode == 1 and "depth only" in p.stderr and "--overlay-out" in p.stderr,
          "process, depth-only + overlay: exit %d, %s" % (p.returncode, p.stderr))
    check(not os.path.exists(os.path.join(tmp, "none-ao")), "depth-only: AO written anyway")
    p = run([DEPTHAO, "process", "--input", os.path.join(ROOT, "recordings", "spheres-noisy"),
             "--overlay-out", ov])
    check(p.returncode == 2 and "depth-only" in p.stderr,
          "process, PNG input + overlay: exit %d, %s" % (p.returncode, p.stderr))
    p = run([DEPTHAOD, "--source", rec, "--playback", "manual",
             "--sink", "o=images:" + ov, "--stream", "o=overlay",
             "--sink", "s=images:" + os.path.join(tmp, "none-s")])
    check(p.returncode == 1 and "depth only" in p.stderr and "overlay" in p.stderr,
          "depthaod, depth-only + overlay: exit %d, %s" % (p.returncode, p.stderr[-600:]))
    check(not os.path.exists(ov) or not os.listdir(ov), "depth-only: overlay files written")
    print("depth-only input with an overlay output: refused at start (process, depthaod)")


def main():
    with tempfile.TemporaryDirectory() as tmp:
        kinect(tmp)
        synthetic(tmp)
        depth_only(tmp)
    if failures:
        print("%d failure(s)" % len(failures))
        return 1
    return 0


sys.exit(main())
