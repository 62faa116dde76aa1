# SPDX-License-Identifier: MIT
"""Colour in the Python binding: colour frames in iteration (open(...,
color=True)) and AO.overlay(), checked against PIL's decoding of the
recording's JPEG bytes and against depthao process --overlay-out."""
import io
import os
import subprocess
import sys

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import depthao  # noqa: E402

SOURCE_ROOT = os.environ.get("DAO_SOURCE_ROOT") or os.path.dirname(os.path.dirname(HERE))
SHARED = os.environ.get("DAO_SHARED_DATA") or os.path.join(SOURCE_ROOT, "..", "shared", "data")
KINECT = os.path.join(SHARED, "oni", "3DJ_test.oni")
ONI = os.path.join(SOURCE_ROOT, "recordings", "spheres-rolling.oni")
sys.path.insert(0, os.path.join(SOURCE_ROOT, "tests", "oni"))
import oni_py  # noqa: E402

needs_kinect = pytest.mark.skipif(not os.path.exists(KINECT), reason="%s is absent" % KINECT)


def ao16(vis):
    return np.rint(vis * np.float32(65535.0)).astype(np.uint32)


def composite(color, vis):
    return ((color.astype(np.uint32) * ao16(vis)[:, :, None] + 32767) // 65535).astype(np.uint8)


@needs_kinect
def test_color_frames_in_iteration():
    Image = pytest.importorskip("PIL.Image")
    frames, nodes = oni_py.frames(KINECT)
    color_id = next(k for k, v in nodes.items() if v[1] == oni_py.IMAGE)
    with depthao.open(KINECT, color=True) as src:
        assert src.info["has_color"]
        assert (src.info["color_width"], src.info["color_height"]) == (640, 480)
        got = [(i, info["color"], info["sequence"]) for i, _, info in src]
    assert len(got) == 12
    for i, color, seq in got:
        assert color.dtype == np.uint8 and color.shape == (480, 640, 3) and color.flags.owndata
        ref = np.asarray(Image.open(io.BytesIO(frames[color_id][i][2])).convert("RGB"))
        assert np.array_equal(color, ref), "frame %d differs from PIL's decoding" % i
    # without color=True: no colour decoded
    with depthao.open(KINECT) as src:
        assert not src.info["has_color"]
        assert next(src)[2]["color"] is None


def test_depth_only_source_has_no_color():
    with depthao.open(ONI, color=True) as src:
        assert not src.info["has_color"] and src.info["color_width"] is None
        assert next(src)[2]["color"] is None


@needs_kinect
def test_overlay_equals_cli(tmp_path):
    cli = os.environ.get("DEPTHAO_CLI")
    if not cli:
        pytest.skip("DEPTHAO_CLI is not set")
    r = subprocess.run([cli, "process", "--input", KINECT, "--frames", "3", "--quiet",
                        "--overlay-out", str(tmp_path / "ov")], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    with depthao.open(KINECT, color=True) as src:
        ao = depthao.AO(src.camera(), stream=True)
        for i, depth, info in src:
            if i == 3:
                break
            vis = ao.process(depth, unit=info["depth_unit"], frame_index=i)
            ov = ao.overlay(info["color"])
            assert np.array_equal(ov, composite(info["color"], vis))
            ref = depthao.read_png(str(tmp_path / "ov" / ("%06d.png" % i)))
            assert np.array_equal(ov, ref), "frame %d: overlay differs from the command's" % i
            # an explicit AO, and out=
            out = np.zeros((480, 640, 3), np.uint8)
            assert ao.overlay(info["color"], ao=vis, out=out) is out
            assert np.array_equal(out, ov)


def test_overlay_scaling_and_errors():
    cam = depthao.Camera(60, 60, 31.5, 23.5, 64, 48)
    ao = depthao.AO(cam)
    with pytest.raises(ValueError, match="before process"):
        ao.overlay(np.zeros((48, 64, 3), np.uint8))
    y, x = np.mgrid[0:48, 0:64]
    depth = (1500 + 20 * y - 3 * x).astype(np.uint16)
    depth[16:32, 20:32] -= 400
    vis = ao.process(depth)
    assert vis.min() < 0.9  # the box occludes the floor
    rng = np.random.default_rng(3)
    big = rng.integers(0, 256, size=(96, 128, 3), dtype=np.uint8)
    mean = np.floor(big.astype(np.float64).reshape(48, 2, 64, 2, 3).mean(axis=(1, 3)) + 0.5)
    assert np.array_equal(ao.overlay(big), composite(mean.astype(np.uint8), vis))
    # a strided (every other column) colour view is handled like a packed one
    wide = np.zeros((48, 128, 3), np.uint8)
    wide[:, ::2] = big[::2, ::2]
    assert np.array_equal(ao.overlay(wide[:, ::2]), composite(big[::2, ::2], vis))
    with pytest.raises(ValueError, match="aspect ratio"):
        ao.overlay(np.zeros((36, 64, 3), np.uint8))
    with pytest.raises(ValueError, match="uint8 RGB"):
        ao.overlay(np.zeros((48, 64), np.uint8))
    with pytest.raises(ValueError, match="uint8 RGB"):
        ao.overlay(np.zeros((48, 64, 3), np.float32))
