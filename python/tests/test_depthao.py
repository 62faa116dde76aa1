# SPDX-License-Identifier: MIT
"""Tests of the Python bindings against libdepthao and the depthao command.

Environment (set by meson's 'python' test; guessed from the layout otherwise):
DEPTHAO_LIBRARY (the libdepthao.so under test), DEPTHAO_CLI (the depthao
command of the same build), DAO_SOURCE_ROOT (the project), DAO_SHARED_DATA
(../shared/data: real sensor frames, tests skip without them).
"""

import ctypes
import errno
import itertools
import os
import shutil
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))  # python/, for running pytest without installing

import depthao  # noqa: E402
from depthao import _frames, _lib, _params  # noqa: E402

SOURCE_ROOT = os.environ.get("DAO_SOURCE_ROOT") or os.path.dirname(os.path.dirname(HERE))
SHARED = os.environ.get("DAO_SHARED_DATA") or os.path.join(SOURCE_ROOT, "..", "shared", "data")
ONI = os.path.join(SOURCE_ROOT, "recordings", "spheres-rolling.oni")
IMAGES = os.path.join(SOURCE_ROOT, "recordings", "spheres-noisy")
REDWOOD = os.path.join(SHARED, "redwood_open3d", "depth_00000.png")


def _cli():
    env = os.environ.get("DEPTHAO_CLI")
    if env:
        return env
    # the command of the build the library came from: BUILD/src/libdepthao.so
    build = os.path.dirname(os.path.dirname(os.path.abspath(depthao.library_path)))
    p = os.path.join(build, "tools", "depthao", "depthao")
    return p if os.path.exists(p) else None


CLI = _cli()
needs_cli = pytest.mark.skipif(CLI is None, reason="the depthao command was not found "
                               "(set DEPTHAO_CLI)")


def ao16(vis):
    """What the library writes into a 16-bit AO PNG: lrintf(v * 65535.0f)."""
    return np.rint(vis * np.float32(65535.0)).astype(np.uint16)


def run_cli(*args):
    r = subprocess.run([CLI, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                       universal_newlines=True)
    assert r.returncode == 0, "depthao %s: %s" % (" ".join(args), r.stderr)
    return r


@pytest.fixture(scope="module")
def oni_frames():
    with depthao.open(ONI) as src:
        frames = [(i, d, info) for i, d, info in src]
        cam = src.camera()
    return cam, frames


@pytest.fixture(scope="module")
def frame0(oni_frames):
    cam, frames = oni_frames
    return cam, frames[0][1]


# --- the library is the C library ------------------------------------------


def test_library_loaded():
    assert isinstance(depthao.library_version, str) and depthao.library_version.count(".") == 2
    if os.environ.get("DEPTHAO_LIBRARY"):
        assert depthao.library_path == os.environ["DEPTHAO_LIBRARY"]
    if os.environ.get("DEPTHAO_IO_LIBRARY"):
        # libdepthao-io uses the one libdepthao loaded (its dependency), not a copy of it:
        # dao_context_create looked up through it is the core's own
        assert depthao._lib.io_path == os.environ["DEPTHAO_IO_LIBRARY"]
        addr = lambda f: ctypes.cast(f, ctypes.c_void_p).value  # noqa: E731
        assert addr(depthao._lib._io.dao_context_create) == addr(depthao._lib.lib.dao_context_create)
        assert addr(depthao._lib.lib.dao_png_read) == addr(depthao._lib._io.dao_png_read)


@needs_cli
def test_bit_exact_with_cli_on_recording(tmp_path, oni_frames):
    """Every frame of the recording: AO and shaded image equal the command's."""
    cam, frames = oni_frames
    run_cli("process", "--input", ONI, "--frames", str(len(frames)), "--quiet",
            "--ao-out", str(tmp_path / "ao"), "--shaded-out", str(tmp_path / "shaded"))
    ao = depthao.AO(cam, stream=True)  # a recording: the temporal depth filter on
    for i, depth, info in frames:
        vis = ao.process(depth, unit=info["depth_unit"], frame_index=i)
        ref = depthao.read_png_depth(str(tmp_path / "ao" / ("%06d.png" % i)), 0.001)
        q = ao16(vis)
        assert np.array_equal(q, ref), "frame %d: %d pixels differ, max %d" % (
            i, np.count_nonzero(q != ref), np.abs(q.astype(int) - ref).max())
        shaded = depthao.read_png(str(tmp_path / "shaded" / ("%06d.png" % i)))
        assert shaded.shape == (480, 640, 3)
        assert np.array_equal(ao.shade(), shaded), "frame %d: shaded image differs" % i


@needs_cli
def test_bit_exact_with_cli_options(tmp_path):
    """A PNG input, another preset and parameters given by name."""
    png = os.path.join(IMAGES, "0001.png")
    out = tmp_path / "ao.png"
    run_cli("process", "--input", png, "--depth-unit", "0.001",
            "--intrinsics", "525,525,319.5,239.5", "--quality", "high", "--radius", "0.3",
            "--denoise", "bilateral", "--frame-index", "7", "--ao-out", str(out), "--quiet")
    cam = depthao.Camera(525, 525, 319.5, 239.5, 640, 480)
    ao = depthao.AO(cam, quality="high", radius=0.3, denoise="bilateral")
    vis = ao.process(depthao.read_png_depth(png, 0.001), unit=0.001, frame_index=7)
    assert np.array_equal(ao16(vis), depthao.read_png_depth(str(out)))


def test_stream_and_reset():
    """stream=True turns on the temporal depth filter; reset() and a gap in the
    frame indices start its history over (the result equals the filter off)."""
    cam = depthao.Camera(525, 525, 319.5, 239.5, 640, 480)
    assert depthao.AO(cam).depth_temporal == 0
    assert depthao.AO(cam, stream=True).depth_temporal > 0
    assert depthao.AO(cam, stream=True, depth_temporal=0).depth_temporal == 0
    frames = [depthao.read_png_depth(os.path.join(IMAGES, "%04d.png" % i), 0.001)
              for i in range(3)]
    on, off = depthao.AO(cam, stream=True), depthao.AO(cam)
    for i in range(2):
        on.process(frames[i], frame_index=i)
        off.process(frames[i], frame_index=i)
    assert not np.array_equal(on.filtered_depth(), off.filtered_depth())
    on.reset()
    a = on.process(frames[2], frame_index=2)
    assert np.array_equal(a, off.process(frames[2], frame_index=2))
    on.process(frames[0], frame_index=3)
    b = on.process(frames[2], frame_index=20)  # a jump: starts over too
    assert np.array_equal(b, off.process(frames[2], frame_index=20))


def test_float_depth_equals_counts(frame0):
    """float32 metres decode like counts x unit."""
    cam, d = frame0
    # the fixed noise model: with the measured one (the default) a frame of counts
    # floors the filters' noise at its quantum, which float metres do not have, and
    # on this clean recording the AO differs by up to 0.04
    ao = depthao.AO(cam, noise_model="fixed")
    a = ao.process(d, unit=0.001)
    b = ao.process((d.astype(np.float32) * np.float32(0.001)))
    assert np.abs(a - b).max() <= 1e-6


# --- strides -----------------------------------------------------------------


def _no_copy(monkeypatch):
    def fail(*a, **k):
        raise AssertionError("the array was copied although its rows could be passed")
    monkeypatch.setattr(_frames, "packed", fail)


def test_strided_inputs(frame0, monkeypatch):
    cam, d = frame0
    h, w = d.shape
    ao = depthao.AO(cam, threads=1, noise_model="fixed")  # float32 below: see above
    ref = ao.process(np.ascontiguousarray(d))

    transposed = np.ascontiguousarray(d.T).T            # column-major
    big = np.zeros((2 * h, 3 * w), np.uint16)
    big[::2, ::3] = d
    sliced = big[::2, ::3]                              # every other row, every third column
    flipped = np.ascontiguousarray(d[::-1])[::-1]       # negative row stride
    raw = np.zeros(h * w * 2 + 1, np.uint8)
    unaligned = np.ndarray((h, w), np.uint16, raw, offset=1)
    unaligned[...] = d
    odd = np.zeros(h * (2 * w + 1), np.uint8)            # row stride not a multiple of 2
    odd_rows = np.ndarray((h, w), np.uint16, odd, strides=(2 * w + 1, 2))
    odd_rows[...] = d
    swapped = d.astype(d.dtype.newbyteorder(">"))        # big-endian samples
    for name, v in [("transposed", transposed), ("sliced", sliced), ("flipped", flipped),
                    ("unaligned", unaligned), ("odd row stride", odd_rows),
                    ("big-endian", swapped)]:
        assert np.array_equal(v, d), name
        assert np.array_equal(ao.process(v), ref), name

    # padded rows (and row views of a wider image) go to the library as they are
    padded = np.zeros((h, w + 37), np.uint16)
    padded[:, :w] = d
    window = np.zeros((h + 10, w + 20), np.uint16)
    window[5:-5, 7:-13] = d
    readonly = d.copy()
    readonly.flags.writeable = False
    f32 = np.zeros((h, w + 3), np.float32)
    f32[:, 1:-2] = d * np.float32(0.001)
    _no_copy(monkeypatch)
    assert np.array_equal(ao.process(padded[:, :w]), ref)
    assert np.array_equal(ao.process(window[5:-5, 7:-13]), ref)
    assert np.array_equal(ao.process(readonly), ref)
    assert np.abs(ao.process(f32[:, 1:-2]) - ref).max() <= 1e-6


def test_out_arrays(frame0, monkeypatch):
    cam, d = frame0
    h, w = d.shape
    ao = depthao.AO(cam, threads=1)
    ref = ao.process(d)

    out = np.full((h, w), -1, np.float32)
    assert ao.process(d, out=out) is out
    assert np.array_equal(out, ref)

    padded = np.full((h, w + 5), -1, np.float32)
    r = ao.process(d, out=padded[:, 2:-3])
    assert r.base is padded
    assert np.array_equal(padded[:, 2:-3], ref)
    assert (padded[:, :2] == -1).all() and (padded[:, -3:] == -1).all()

    transposed = np.empty((w, h), np.float32).T            # written through a copy
    ao.process(d, out=transposed)
    assert np.array_equal(transposed, ref)

    rgb = ao.shade()
    out_rgb = np.zeros((h, w + 1, 3), np.uint8)
    ao.shade(out=out_rgb[:, 1:])
    assert np.array_equal(out_rgb[:, 1:], rgb)
    rgb_t = np.zeros((w, h, 3), np.uint8).transpose(1, 0, 2)
    ao.shade(out=rgb_t)
    assert np.array_equal(rgb_t, rgb)
    ao.set("shade", "ao")  # AO alone, as gray (pixels without depth black)
    gray = ao.shade(out=np.zeros((h, w), np.uint8))
    assert np.abs(gray[d > 0].astype(int) - ref[d > 0] * 255).max() <= 1
    gray_t = np.zeros((w, h), np.uint8).T
    ao.shade(out=gray_t)
    assert np.array_equal(gray_t, gray)

    # aliasing input and output still gives the right answer
    f = d.astype(np.float32) * np.float32(0.001)
    expect = ao.process(f.copy())
    assert np.array_equal(ao.process(f, out=f), expect)


def test_process_shaded(oni_frames):
    """process_shaded() gives process() then shade(), byte for byte, on a recording's
    frames with the temporal filters on (the histories advance alike), into new arrays,
    strided and transposed ones, and gray; with algorithm="none" it processes and then
    raises ENODATA, as shade() does."""
    cam, frames = oni_frames
    i0, d0, _ = frames[0]
    a = depthao.AO(cam, stream=True, threads=2)
    b = depthao.AO(cam, stream=True, threads=2)
    h, w = d0.shape
    padded = np.zeros((h, w + 2, 3), np.uint8)
    for k, (i, d, info) in enumerate(frames[:4]):
        want_vis = a.process(d, unit=info["depth_unit"], frame_index=i)
        want_rgb = a.shade()
        if k == 1:
            vis, rgb = b.process_shaded(d, unit=info["depth_unit"], frame_index=i,
                                        shaded_out=padded[:, 1:-1])
            assert rgb.base is padded and (padded[:, 0] == 0).all()
        elif k == 2:
            t = np.zeros((w, h, 3), np.uint8).transpose(1, 0, 2)   # written through a copy
            vis, rgb = b.process_shaded(d, unit=info["depth_unit"], frame_index=i,
                                        shaded_out=t)
            assert rgb is t
        else:
            vis, rgb = b.process_shaded(d, unit=info["depth_unit"], frame_index=i)
        assert np.array_equal(vis, want_vis), k
        assert np.array_equal(rgb, want_rgb), k
    a.set("shade", "ao")
    b.set("shade", "ao")
    i4, d4, _ = frames[4]
    want_vis = a.process(d4, frame_index=i4)
    gray = a.shade(out=np.zeros((h, w), np.uint8))
    vis, g = b.process_shaded(d4, frame_index=i4, shaded_out=np.zeros((h, w), np.uint8))
    assert np.array_equal(vis, want_vis) and np.array_equal(g, gray)
    with pytest.raises(ValueError, match="shaded_out must be uint8"):
        b.process_shaded(d4, shaded_out=np.zeros((h, w, 3), np.float32))
    with pytest.raises(ValueError, match="shaded_out must have shape"):
        b.process_shaded(d4, shaded_out=np.zeros((h, w, 4), np.uint8))
    n = depthao.AO(cam, algorithm="none")
    with pytest.raises(OSError) as e:
        n.process_shaded(d0, frame_index=i0)
    assert e.value.errno == errno.ENODATA
    assert np.array_equal(n.filtered_depth(unit=0.001) > 0, d0 > 0)  # the frame was processed


def test_no_allocation_per_call_with_out(frame0, monkeypatch):
    """With out= and a contiguous input nothing is copied or allocated."""
    cam, d = frame0
    ao = depthao.AO(cam, threads=1)
    out = np.empty(d.shape, np.float32)
    _no_copy(monkeypatch)
    monkeypatch.setattr(np, "empty", lambda *a, **k: pytest.fail("np.empty called"))
    ao.process(d, out=out)


# --- errors ------------------------------------------------------------------


def test_input_errors(frame0):
    cam, d = frame0
    ao = depthao.AO(cam)
    for bad, what in [(d.astype(np.float16), "float16"), (d.astype(np.int16), "int16"),
                      (d.astype(np.uint8), "uint8"), (d.astype(np.int32), "int32")]:
        with pytest.raises(ValueError, match="uint16.*float32.*got " + what):
            ao.process(bad)
    with pytest.raises(ValueError, match=r"shape \(480, 640\).*got \(640, 480\)"):
        ao.process(np.zeros((640, 480), np.uint16))
    with pytest.raises(ValueError, match=r"shape \(480, 640\).*got \(480, 639\)"):
        ao.process(d[:, 1:])
    with pytest.raises(ValueError, match="shape"):
        ao.process(d[..., None])
    with pytest.raises(ValueError, match="numpy array"):
        ao.process(d.tolist())
    with pytest.raises(ValueError, match="unit"):
        ao.process(d, unit=0)
    with pytest.raises(ValueError, match="frame_index"):
        ao.process(d, frame_index=-1)
    with pytest.raises(ValueError, match="out must be float32"):
        ao.process(d, out=np.zeros(d.shape, np.float64))
    with pytest.raises(ValueError, match="out must have shape"):
        ao.process(d, out=np.zeros((480, 641), np.float32))
    ro = np.zeros(d.shape, np.float32)
    ro.flags.writeable = False
    with pytest.raises(ValueError, match="read-only"):
        ao.process(d, out=ro)
    with pytest.raises(ValueError, match="out must be uint8"):
        ao.shade(out=np.zeros((480, 640, 3), np.float32))


def test_shade_before_process(frame0):
    cam, _ = frame0
    with pytest.raises(OSError) as e:
        depthao.AO(cam).shade()
    assert e.value.errno == errno.EAGAIN
    assert "process" in str(e.value)


def test_parameter_errors(frame0):
    cam, _ = frame0
    ao = depthao.AO(cam)
    with pytest.raises(AttributeError, match="unknown parameter 'radiuss'"):
        ao.radiuss = 0.3
    with pytest.raises(AttributeError):
        ao.radiuss
    with pytest.raises(ValueError, match="unknown parameter 'radiuss'"):
        ao.set("radiuss", 0.3)
    with pytest.raises(ValueError, match="unknown parameter 'radiuss'"):
        depthao.AO(cam, radiuss=0.3)
    with pytest.raises(ValueError, match=r"radius: 1000.0 is out of range \[0.01, 100\] m"):
        ao.radius = 1000
    with pytest.raises(ValueError, match="radius: 'far' is not a number"):
        ao.radius = "far"
    with pytest.raises(ValueError, match="slices: '2.5' is not an integer"):
        ao.slices = 2.5
    with pytest.raises(ValueError, match="denoise: 'blur' is not one of: none, plane, bilateral"):
        ao.denoise = "blur"
    with pytest.raises(ValueError, match="occlusion-color: 'red' is not a colour"):
        ao.occlusion_color = "red"
    with pytest.raises(ValueError, match="depth-min 30 must be less than depth-max 20"):
        ao.depth_min = 30
    with pytest.raises(ValueError, match="unknown quality 'best'"):
        depthao.AO(cam, quality="best")
    with pytest.raises(ValueError, match="threads: 1000 is out of range"):
        depthao.AO(cam, threads=1000)
    with pytest.raises(AttributeError, match="method"):
        ao.shade = "turbo"
    # nothing changed by the failures
    assert ao.params == depthao.AO(cam).params


def test_camera_errors():
    with pytest.raises(ValueError, match="fx"):
        depthao.Camera(0, 525, 319.5, 239.5, 640, 480)
    with pytest.raises(ValueError, match="width"):
        depthao.Camera(525, 525, 319.5, 239.5, -640, 480)
    with pytest.raises(ValueError, match="height"):
        depthao.Camera(525, 525, 319.5, 239.5, 640, 480.5)
    with pytest.raises(ValueError):
        depthao.Camera.from_fov(640, 480, 3.2, 0.8)
    with pytest.raises(ValueError, match="16384"):
        depthao.Camera(525, 525, 319.5, 239.5, 100000, 480)


def test_file_errors(tmp_path):
    with pytest.raises(FileNotFoundError) as e:
        depthao.read_png_depth(str(tmp_path / "missing.png"))
    assert "missing.png" in str(e.value)
    rgb = tmp_path / "rgb.png"
    depthao.write_png(str(rgb), np.zeros((4, 5, 3), np.uint8))
    with pytest.raises(ValueError, match="16-bit"):
        depthao.read_png_depth(str(rgb))
    not_png = tmp_path / "x.png"
    not_png.write_bytes(b"not a png")
    with pytest.raises(ValueError):
        depthao.read_png(str(not_png))
    with pytest.raises(FileNotFoundError, match="missing.oni"):
        depthao.open(str(tmp_path / "missing.oni"))
    bad = tmp_path / "bad.oni"
    bad.write_bytes(b"NIR" + bytes(100))
    with pytest.raises(ValueError, match="bad.oni"):
        depthao.open(str(bad))
    with pytest.raises(OSError, match="no source plugin 'nope'"):
        depthao.open("nope:thing")
    with pytest.raises(ValueError, match="playback"):
        depthao.open(ONI, playback="fast")


# --- parameters --------------------------------------------------------------


def test_parameters_from_the_table(frame0):
    cam, _ = frame0
    ao = depthao.AO(cam, threads=1, radius=0.4, denoise="bilateral", occlusion_color=0x202040)
    p = ao.params
    assert list(p) == [i.attr for i in depthao.PARAMETERS]
    assert p["threads"] == 1 and p["radius"] == 0.4 and p["denoise"] == "bilateral"
    assert p["occlusion_color"] == 0x202040
    # every parameter (including ones added later) survives a round trip, as
    # attribute where it is not a method name, and by set() always
    for info in depthao.PARAMETERS:
        v = ao.get(info.attr)
        ao.set(info.name, v)
        if not hasattr(depthao.AO, info.attr):
            setattr(ao, info.attr, v)
            assert getattr(ao, info.attr) == v
        assert info.attr in dir(ao)
    assert ao.params == p
    ao.radius = 0.3
    assert ao.radius == 0.3 and ao.params["radius"] == 0.3
    ao.noise = 1  # an enum by index
    assert ao.noise == "r2"
    ao.update(depth_min=25, depth_max=40)  # checked together
    assert (ao.depth_min, ao.depth_max) == (25, 40)
    assert ao.get("depth-min") == 25
    presets = {q: depthao.AO(cam, quality=q).params for q in ("low", "medium", "high", "ultra")}
    assert presets["medium"] == depthao.AO(cam).params
    assert presets["high"]["slices"] > presets["low"]["slices"]


def test_parameters_change_results(frame0):
    cam, d = frame0
    ao = depthao.AO(cam)
    a = ao.process(d)
    ao.radius = 0.25
    b = ao.process(d)
    assert not np.array_equal(a, b)
    assert np.array_equal(depthao.AO(cam, radius=0.25).process(d), b)
    t = ao.timings
    assert t["process"] > 0 and set(t) >= {"gtao", "denoise", "shade"}
    assert ao.simd in ("avx512", "avx2", "sse4.1", "generic", "reference")


def test_noise_model(frame0):
    """noise-model=auto measures the recording's noise; fixed reports the parameter."""
    cam, d = frame0
    ao = depthao.AO(cam, prefilter="domain", noise_model="auto")
    ao.process(d)
    n = ao.noise_info
    assert n["measured"] and 0 < n["sigma_area"] < 0.01 and 1 <= n["normal_radius"] <= 8
    assert n["denoise_noise"] == n["sigma_area"]
    ao.noise_model = "fixed"
    ao.process(d)
    n = ao.noise_info
    assert not n["measured"] and n["sigma_area"] == pytest.approx(ao.depth_noise)


# --- real data and recordings ------------------------------------------------


def test_real_frame():
    if not os.path.exists(REDWOOD):
        pytest.skip("%s not found (../shared/data is not beside the project)" % REDWOOD)
    d = depthao.read_png_depth(REDWOOD, 0.001)
    assert d.dtype == np.uint16 and d.shape == (480, 640)
    cam = depthao.Camera(525, 525, 319.5, 239.5, 640, 480)
    ao = depthao.AO(cam)
    v = ao.process(d, unit=0.001)
    assert v.dtype == np.float32 and v.shape == (480, 640)
    assert np.isfinite(v).all() and v.min() >= 0 and v.max() <= 1
    assert (v[d == 0] == 1).all()  # no depth: open
    assert 0.5 < v[d > 0].mean() < 1
    assert np.array_equal(ao.process(d, unit=0.001), v)  # deterministic
    rgb = ao.shade()
    assert rgb.shape == (480, 640, 3) and rgb.std() > 0
    if CLI:
        out = os.path.join(os.environ.get("TMPDIR", "/tmp"), "depthao-py-redwood-%d.png"
                           % os.getpid())
        try:
            run_cli("process", "--input", REDWOOD, "--intrinsics", "525,525,319.5,239.5",
                    "--ao-out", out, "--quiet")
            assert np.array_equal(ao16(v), depthao.read_png_depth(out))
        finally:
            if os.path.exists(out):
                os.unlink(out)


def test_oni_recording(oni_frames):
    cam, frames = oni_frames
    assert [i for i, _, _ in frames] == list(range(16))
    for i, d, info in frames:
        assert d.dtype == np.uint16 and d.shape == (480, 640) and d.flags.owndata
        assert info["sequence"] == i + 1 and info["depth_unit"] == 0.001
    assert frames[1][2]["timestamp_ns"] > frames[0][2]["timestamp_ns"]
    assert not np.array_equal(frames[0][1], frames[15][1])  # it rolls
    assert (cam.width, cam.height) == (640, 480)
    with depthao.open(ONI) as src:
        assert src.info["frame_count"] == src.frame_count == 16
        assert src.info["width"] == 640 and src.info["height"] == 480
        assert src.info["has_fov"] and not src.info["live"]
        assert "spheres-rolling.oni" in src.info["description"]
    # start, step, loop, seek
    assert [i for i, _, _ in depthao.open(ONI, start=10)] == list(range(10, 16))
    assert [i for i, _, _ in depthao.open("oni:" + ONI, step=5)] == [0, 5, 10, 15]
    looped = [i for i, _, _ in itertools.islice(depthao.open(ONI, loop=True, start=14), 5)]
    assert looped == [14, 15, 14, 15, 14]  # loops wrap to the start frame
    src = depthao.open(ONI)
    src.seek(3)
    i, d, _ = next(src)
    assert i == 3 and np.array_equal(d, frames[3][1])
    src.close()
    with pytest.raises(ValueError, match="closed"):
        next(src)


def test_unfinished_recording(tmp_path, oni_frames):
    """A recording whose writer died (no end record, the last frame cut short)
    plays up to its last complete frame, with a RuntimeWarning."""
    _, frames = oni_frames
    data = open(ONI, "rb").read()
    cut = tmp_path / "cut.oni"
    cut.write_bytes(data[:len(data) * 2 // 3])
    with pytest.warns(RuntimeWarning, match="not finalised"):
        src = depthao.open(str(cut))
    with src:
        assert "cut.oni" in src.info["warning"]
        got = [(i, d) for i, d, _ in src]
    assert 0 < len(got) < 16
    for i, d in got:
        assert np.array_equal(d, frames[i][1])
    with depthao.open(ONI) as src:
        assert src.info["warning"] is None


def test_ros_bag(tmp_path):
    """A ROS bag written by rosbag's own writer (tests/bag/make_bags.py): frames,
    and the camera from its CameraInfo."""
    script = os.path.join(SOURCE_ROOT, "tests", "bag", "make_bags.py")
    r = subprocess.run(["/usr/bin/python3", script, str(tmp_path)], capture_output=True,
                       text=True)
    if r.returncode == 77:
        pytest.skip(r.stdout.strip())
    assert r.returncode == 0, r.stderr
    ys, xs = np.mgrid[0:48, 0:64]
    with depthao.open(str(tmp_path / "d16_lz4.bag")) as src:
        assert src.frame_count == 5
        assert src.info["intrinsics"] == (60.0, 61.0, 31.5, 23.25)
        cam = src.camera()
        assert (cam.fx, cam.fy, cam.cx, cam.cy) == (60.0, 61.0, 31.5, 23.25)
        for i, d, info in src:
            want = np.where(xs == ys, 0, 500 + 7 * xs + 13 * ys + 100 * i).astype(np.uint16)
            assert np.array_equal(d, want)
            assert info["timestamp_ns"] == (100 + i) * 10**9 + i * 10**6
    with pytest.raises(Exception, match="choose one with"):
        depthao.open(str(tmp_path / "two.bag"))


def test_realtime_playback():
    t0 = time.monotonic()
    n = sum(1 for _ in depthao.open(ONI, playback="realtime", start=12))
    assert n == 4
    assert time.monotonic() - t0 >= 0.08  # 4 frames at 30 fps: >= 3 intervals


def test_images_source(tmp_path):
    with depthao.open("images:" + IMAGES) as src:
        frames = list(src)
        assert src.info["frame_count"] == 4 and not src.info["has_fov"]
        # the camera.json beside the images, as depthao process reads it
        assert src.info["camera_file"] == os.path.join(IMAGES, "camera.json")
        assert src.camera() == depthao.Camera(525, 525, 319.5, 239.5, 640, 480)
    # without one: no camera
    shutil.copy(os.path.join(IMAGES, "0000.png"), tmp_path / "0000.png")
    with depthao.open(str(tmp_path)) as src:
        assert src.info["camera_file"] is None
        with pytest.raises(ValueError, match="field of view"):
            src.camera()
    assert [i for i, _, _ in frames] == [0, 1, 2, 3]
    for i, d, info in frames:
        assert np.array_equal(d, depthao.read_png_depth(os.path.join(IMAGES, "%04d.png" % i)))
    assert [info["depth_unit"] for *_, info in depthao.open("images:" + IMAGES, unit=0.0002)] \
        == [0.0002] * 4


def test_png_round_trip(tmp_path):
    rng = np.random.default_rng(1)
    for img in [rng.integers(0, 65536, (7, 9), dtype=np.uint16),
                rng.integers(0, 256, (7, 9), dtype=np.uint8),
                rng.integers(0, 256, (7, 9, 3), dtype=np.uint8)]:
        p = str(tmp_path / "x.png")
        depthao.write_png(p, img.T.copy().T)
        back = depthao.read_png(p)
        assert back.dtype == img.dtype and np.array_equal(back, img)
    with pytest.raises(ValueError, match="uint8"):
        depthao.write_png(p, np.zeros((3, 3), np.float32))


# --- threads -----------------------------------------------------------------


def test_two_threads_match_sequential(oni_frames):
    cam, frames = oni_frames
    halves = [frames[0::2], frames[1::2]]

    def run(part, results):
        ao = depthao.AO(cam, threads=1)
        for i, d, info in part:
            results[i] = ao.process(d, unit=info["depth_unit"], frame_index=i)

    sequential = {}
    for part in halves:
        run(part, sequential)
    threaded = {}
    ts = [threading.Thread(target=run, args=(part, threaded)) for part in halves]
    for t in ts:
        t.start()
    for t in ts:
        t.join()
    assert sorted(threaded) == list(range(16))
    for i in range(16):
        assert np.array_equal(threaded[i], sequential[i]), "frame %d" % i


def test_same_object_from_two_threads(frame0):
    """Calls on one AO from two threads are serialised, not corrupted."""
    cam, d = frame0
    ao = depthao.AO(cam, threads=1)
    ref = [ao.process(d, frame_index=k) for k in range(2)]
    got = {}

    def run(k):
        for _ in range(3):
            got.setdefault(k, []).append(ao.process(d, frame_index=k))

    ts = [threading.Thread(target=run, args=(k,)) for k in range(2)]
    for t in ts:
        t.start()
    for t in ts:
        t.join()
    for k in range(2):
        assert all(np.array_equal(v, ref[k]) for v in got[k])


def test_gil_released(frame0):
    """Python code runs while the library processes a frame."""
    cam, d = frame0
    ao = depthao.AO(cam, threads=1, simd="reference")  # slow on purpose: ~0.5 s
    done = threading.Event()
    t = threading.Thread(target=lambda: (ao.process(d), done.set()))
    ticks = 0
    t.start()
    time.sleep(0.02)
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    t.join()
    assert ticks > 20


# --- the declarations match the C headers -----------------------------------

_STRUCTS = {
    "dao_error": _lib.dao_error, "dao_camera": _lib.dao_camera, "dao_frame": _lib.dao_frame,
    "dao_param_info": _lib.dao_param_info, "dao_timings": _lib.dao_timings,
    "dao_noise_info": _lib.dao_noise_info,
    "dao_source_info": _lib.dao_source_info, "dao_source_options": _lib.dao_source_options,
    "dao_source_frame": _lib.dao_source_frame,
    "dao_motion_info": _lib.dao_motion_info, "dao_source_pose": _lib.dao_source_pose,
    "dao_pose_track": _lib.dao_pose_track,
}


def test_struct_layouts_match_headers(tmp_path):
    """Compiles a C program that prints sizeof/offsetof of every structure
    this package declares, and compares them with ctypes."""
    cc = shutil.which(os.environ.get("CC", "cc")) or shutil.which("gcc")
    include = os.path.join(SOURCE_ROOT, "include")
    if not cc or not os.path.isdir(include):
        pytest.skip("no C compiler or no include/ to check the structure layouts against")
    lines = ["#include <stddef.h>", "#include <stdio.h>",
             "#include <depthao/context.h>", "#include <depthao/plugin.h>",
             "int main(void) {"]
    for name, cls in _STRUCTS.items():
        lines.append('printf("%s %%zu\\n", sizeof(struct %s));' % (name, name))
        for field, _ in cls._fields_:
            lines.append('printf("%s.%s %%zu\\n", offsetof(struct %s, %s));'
                         % (name, field, name, field))
    lines.append('printf("dao_params %zu\\n", sizeof(struct dao_params));')
    lines.append("return 0; }")
    src = tmp_path / "layout.c"
    src.write_text("\n".join(lines))
    exe = tmp_path / "layout"
    subprocess.run([cc, "-std=c11", "-I", include, str(src), "-o", str(exe)], check=True)
    got = dict(line.split() for line in subprocess.check_output([str(exe)]).decode().split("\n")
               if line)
    for name, cls in _STRUCTS.items():
        assert int(got[name]) == ctypes.sizeof(cls), name
        for field, _ in cls._fields_:
            assert int(got[name + "." + field]) == getattr(cls, field).offset, name + "." + field
    assert int(got["dao_params"]) <= _params.PARAMS_BUFFER_SIZE


# --- cameras from matrices, CameraInfo and camera files; float64 depth ------------------

def test_camera_from_matrix():
    want = depthao.Camera(525, 524, 319.5, 239.25, 640, 480)
    k = [[525, 0, 319.5], [0, 524, 239.25], [0, 0, 1]]
    assert depthao.Camera.from_matrix(k, 640, 480) == want
    assert depthao.Camera.from_matrix(np.array(k, np.float32), 640, 480) == want
    assert depthao.Camera.from_matrix(np.ravel(k).tolist(), 640, 480) == want  # ROS K
    for bad in ([[1, 0, 0], [0, 1, 0]], [[525, 0, 319.5], [0, 524, 239.25], [0, 0, 2]],
                [[525, 0, 319.5], [0, 524, 239.25], [0, float("nan"), 1]], "K"):
        with pytest.raises(ValueError):
            depthao.Camera.from_matrix(bad, 640, 480)
    with pytest.raises(ValueError, match="focal"):
        depthao.Camera.from_matrix([[-5, 0, 1], [0, 5, 1], [0, 0, 1]], 640, 480)


def _camera_info_yaml(k, d, p):
    return {"image_width": 64, "image_height": 48, "camera_name": "d",
            "camera_matrix": {"rows": 3, "cols": 3, "data": np.ravel(k).tolist()},
            "distortion_model": "plumb_bob",
            "distortion_coefficients": {"rows": 1, "cols": len(d), "data": list(d)},
            "rectification_matrix": {"rows": 3, "cols": 3, "data": [1, 0, 0, 0, 1, 0, 0, 0, 1]},
            "projection_matrix": {"rows": 3, "cols": 4, "data": np.ravel(p).tolist()}}


def test_camera_from_camera_info(tmp_path):
    k = [[50.0, 0, 31.5], [0, 51.0, 23.5], [0, 0, 1]]
    p = [[49.0, 0, 32.0, 0], [0, 49.5, 24.0, 0], [0, 0, 1, 0]]
    plain = depthao.Camera(50, 51, 31.5, 23.5, 64, 48)
    rect = depthao.Camera(49, 49.5, 32, 24, 64, 48)
    info = _camera_info_yaml(k, [0.0] * 5, p)
    assert depthao.Camera.from_camera_info(info) == plain
    # a YAML file written by PyYAML (an independent writer), by path and via from_file
    yaml = pytest.importorskip("yaml", reason="PyYAML (python3-yaml) is not installed")
    f = tmp_path / "cam.yaml"
    f.write_text(yaml.safe_dump(info))
    assert depthao.Camera.from_camera_info(str(f)) == plain
    assert depthao.Camera.from_camera_info(f) == plain
    assert depthao.Camera.from_file(f) == plain
    # distortion: a warning, and the projection matrix (the rectified image's camera)
    info = _camera_info_yaml(k, [-0.1, 0.01, 0, 0, 0], p)
    f.write_text(yaml.safe_dump(info))
    with pytest.warns(RuntimeWarning, match="must be rectified"):
        assert depthao.Camera.from_camera_info(str(f)) == rect
    # a message object: ROS 1 fields (K, D, P) and ROS 2 ones (k, d, p)
    try:
        from sensor_msgs.msg import CameraInfo  # python3-sensor-msgs (ROS 1)
        msg = CameraInfo(width=64, height=48, K=np.ravel(k).tolist(), D=[0.0] * 5,
                         P=np.ravel(p).tolist(), distortion_model="plumb_bob")
    except ImportError:
        import types
        msg = types.SimpleNamespace(width=64, height=48, K=np.ravel(k).tolist(), D=[0.0] * 5,
                                    P=np.ravel(p).tolist(), distortion_model="plumb_bob")
    assert depthao.Camera.from_camera_info(msg) == plain
    import types
    ros2 = types.SimpleNamespace(width=64, height=48, k=np.ravel(k), d=np.array([0.2]),
                                 p=np.ravel(p), distortion_model="plumb_bob")
    with pytest.warns(RuntimeWarning, match="rectified"):
        assert depthao.Camera.from_camera_info(ros2) == rect
    # broken ones: ValueError naming the file and what is wrong
    for text, what in [("image_width: 64\nimage_height: [48\n", "not valid YAML"),
                       ("- 1\n", "not a ROS CameraInfo"),
                       (yaml.safe_dump(dict(info, image_width=0)), "width"),
                       (yaml.safe_dump({k2: v for k2, v in info.items()
                                        if k2 != "camera_matrix"}), "camera_matrix")]:
        f.write_text(text)
        with pytest.raises(ValueError, match=what) as e:
            depthao.Camera.from_camera_info(str(f))
        assert "cam.yaml" in str(e.value)
    with pytest.raises(ValueError, match="no K"):
        depthao.Camera.from_camera_info({"width": 64})


def test_open_images_with_camera_yaml(tmp_path):
    yaml = pytest.importorskip("yaml", reason="PyYAML (python3-yaml) is not installed")
    shutil.copy(os.path.join(IMAGES, "0000.png"), tmp_path / "0000.png")
    k = [[500.0, 0, 320], [0, 501.0, 240], [0, 0, 1]]
    info = _camera_info_yaml(k, [0.0] * 5, [[500.0, 0, 320, 0], [0, 501.0, 240, 0], [0, 0, 1, 0]])
    (tmp_path / "camera.yaml").write_text(yaml.safe_dump(dict(info, image_width=640,
                                                               image_height=480)))
    with depthao.open(str(tmp_path)) as src:
        assert src.camera() == depthao.Camera(500, 501, 320, 240, 640, 480)
    (tmp_path / "camera.yaml").write_text(yaml.safe_dump(info))  # 64x48: not these images
    with pytest.raises(ValueError, match="64x48"):
        depthao.open(str(tmp_path))


def test_float64_depth():
    cam = depthao.Camera(525, 525, 319.5, 239.5, 640, 480)
    depth = depthao.read_png_depth(os.path.join(IMAGES, "0000.png"))
    metres32 = depth.astype(np.float32) * np.float32(0.001)
    metres32[::9, ::7] = np.nan
    ao = depthao.AO(cam)
    want = ao.process(metres32)
    got = ao.process(metres32.astype(np.float64))
    assert np.array_equal(got, want)
    got = ao.process(metres32.astype(np.float64)[::-1, :][::-1, :])  # a strided view
    assert np.array_equal(got, want)


def test_type_stubs_cover_the_api():
    """__init__.pyi (PEP 561, with py.typed) names every public class, function and
    method of the package, so that a type checker sees the whole API."""
    import ast
    here = os.path.dirname(depthao.__file__)
    assert os.path.exists(os.path.join(here, "py.typed"))
    tree = ast.parse(open(os.path.join(here, "__init__.pyi")).read())
    stub = {n.name: n for n in tree.body if isinstance(n, (ast.ClassDef, ast.FunctionDef))}
    for name in depthao.__all__ + ["open"]:
        obj = getattr(depthao, name)
        if callable(obj) and not name.startswith("_"):
            assert name in stub, "%s is not in __init__.pyi" % name
    for cls in (depthao.Camera, depthao.AO, depthao.Source):
        body = stub[cls.__name__].body
        members = {n.name for n in body if isinstance(n, ast.FunctionDef)} | \
            {n.target.id for n in body if isinstance(n, ast.AnnAssign)}
        for m in vars(cls):
            if not m.startswith("_"):
                assert m in members, "%s.%s is not in __init__.pyi" % (cls.__name__, m)


def test_open_bag(tmp_path):
    """A ROS bag written by rosbag (tests/bag/make_bags.py): depthao.open() takes it
    with its CameraInfo's intrinsics; its frames equal the PNGs written beside it."""
    make = os.path.join(SOURCE_ROOT, "tests", "bag", "make_bags.py")
    py = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable
    p = subprocess.run([py, make, str(tmp_path)], capture_output=True, text=True)
    if p.returncode == 77:
        pytest.skip(p.stdout.strip())
    assert p.returncode == 0, p.stdout + p.stderr
    with depthao.open(str(tmp_path / "d16_lz4.bag")) as src:
        cam = src.camera()
        frames = list(src)
    want = depthao.Camera.from_file(tmp_path / "png" / "camera.json")
    assert cam == want and src.info["intrinsics"] == (want.fx, want.fy, want.cx, want.cy)
    assert [i for i, _, _ in frames] == list(range(len(frames))) and len(frames) == 5
    for i, d, info in frames:
        assert np.array_equal(d, depthao.read_png_depth(tmp_path / "png" / ("%06d.png" % i)))
