# SPDX-License-Identifier: MIT
"""AO.filtered_depth() and algorithm="none" (issue #36): the filtered depth as the C
library gives it (a C program built here against the same libdepthao), in metres and in
counts of a unit, 0 where there is no depth, the same depth with and without the AO,
and the errors a caller can cause.

Environment as test_depthao.py (DEPTHAO_LIBRARY, DAO_SOURCE_ROOT)."""

import errno
import math
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))  # python/, for running pytest without installing

import depthao  # noqa: E402

SOURCE_ROOT = os.environ.get("DAO_SOURCE_ROOT") or os.path.dirname(os.path.dirname(HERE))
ONI = os.path.join(SOURCE_ROOT, "recordings", "spheres-rolling.oni")
FRAMES = 4


@pytest.fixture(scope="module")
def recording():
    """The first frames of the recording: camera, [(index, uint16 depth, unit)]."""
    with depthao.open(ONI) as src:
        frames = []
        for i, d, info in src:
            frames.append((i, d.copy(), info["depth_unit"]))
            if len(frames) == FRAMES:
                break
        cam = src.camera()
    return cam, frames


def with_holes(depth):
    """The frame with a block and a scatter of pixels set to 0 (no depth)."""
    d = depth.copy()
    d[100:130, 200:260] = 0
    d[::7, ::11] = 0
    return d


# --- equal to the C library --------------------------------------------------------

C_PROGRAM = r"""
#include <stdio.h>
#include <stdlib.h>
#include <depthao/context.h>

/* argv: in.raw (uint16 frames) w h frames unit fx fy cx cy out.raw
 * out.raw: per frame, the float32 metres then the uint16 counts of 0.5 mm */
int main(int argc, char **argv)
{
	if (argc != 11)
		return 2;
	int w = atoi(argv[2]), h = atoi(argv[3]), n = atoi(argv[4]);
	float unit = strtof(argv[5], NULL);
	struct dao_error err = {0};
	struct dao_camera cam;
	struct dao_params p;
	struct dao_context *ctx;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	dao_params_stream_defaults(&p);
	if (dao_camera_from_intrinsics(&cam, w, h, atof(argv[6]), atof(argv[7]), atof(argv[8]),
				       atof(argv[9]), &err) ||
	    dao_context_create(&ctx, &cam, &p, &err))
		return fprintf(stderr, "%s\n", err.message), 1;
	unsigned short *in = malloc((size_t)w * h * 2), *c16 = malloc((size_t)w * h * 2);
	float *m = malloc((size_t)w * h * 4), *ao = malloc((size_t)w * h * 4);
	FILE *fi = fopen(argv[1], "rb"), *fo = fopen(argv[10], "wb");
	if (!fi || !fo)
		return 1;
	for (int i = 0; i < n; i++) {
		if (fread(in, 2, (size_t)w * h, fi) != (size_t)w * h)
			return 1;
		struct dao_frame d = { .size = DAO_FRAME_SIZE, .format = DAO_PIXFMT_DEPTH16,
				       .width = w, .height = h, .stride = w * 2, .data = in,
				       .depth_unit = unit };
		struct dao_frame a = { .size = DAO_FRAME_SIZE, .format = DAO_PIXFMT_GRAY_F32,
				       .width = w, .height = h, .stride = w * 4, .data = ao };
		struct dao_frame fm = { .size = DAO_FRAME_SIZE, .format = DAO_PIXFMT_DEPTH_F32,
					.width = w, .height = h, .stride = w * 4, .data = m };
		struct dao_frame fc = { .size = DAO_FRAME_SIZE, .format = DAO_PIXFMT_DEPTH16,
					.width = w, .height = h, .stride = w * 2, .data = c16,
					.depth_unit = 0.0005f };
		if (dao_context_process(ctx, &d, NULL, (uint64_t)i, &a, &err) ||
		    dao_context_get_depth(ctx, &fm, &err) || dao_context_get_depth(ctx, &fc, &err))
			return fprintf(stderr, "%s\n", err.message), 1;
		fwrite(m, 4, (size_t)w * h, fo);
		fwrite(c16, 2, (size_t)w * h, fo);
	}
	fclose(fo);
	dao_context_destroy(ctx);
	return 0;
}
"""


def test_equal_to_the_c_library(tmp_path, recording):
    """Frames of a recording with the temporal filter on (stream): filtered_depth() and
    filtered_depth(unit) equal, bit for bit, what a C program gets from
    dao_context_get_depth() on the same frames."""
    cc = shutil.which(os.environ.get("CC", "cc")) or shutil.which("gcc")
    include = os.path.join(SOURCE_ROOT, "include")
    libpath = os.path.abspath(depthao.library_path)
    if not cc or not os.path.isdir(include) or os.sep not in depthao.library_path:
        pytest.skip("no C compiler, no include/ or no library file to link against")
    cam, frames = recording
    h, w = cam.shape
    unit = frames[0][2]
    src = tmp_path / "get_depth.c"
    src.write_text(C_PROGRAM)
    exe = tmp_path / "get_depth"
    subprocess.run([cc, "-std=c11", "-I", include, str(src), libpath,
                    "-Wl,-rpath," + os.path.dirname(libpath), "-o", str(exe)], check=True)
    inputs = [with_holes(d) if i % 2 else d for i, d, _ in frames]
    (tmp_path / "in.raw").write_bytes(b"".join(d.astype("<u2").tobytes() for d in inputs))
    subprocess.run([str(exe), str(tmp_path / "in.raw"), str(w), str(h), str(len(frames)),
                    repr(unit), repr(cam.fx), repr(cam.fy), repr(cam.cx), repr(cam.cy),
                    str(tmp_path / "out.raw")], check=True)
    out = (tmp_path / "out.raw").read_bytes()
    ao = depthao.AO(cam, stream=True)
    per = w * h * 6
    for k, ((i, _, _), d) in enumerate(zip(frames, inputs)):
        ao.process(d, unit=unit, frame_index=k)
        ref_m = np.frombuffer(out, "<f4", w * h, k * per).reshape(h, w)
        ref_c = np.frombuffer(out, "<u2", w * h, k * per + w * h * 4).reshape(h, w)
        got_m, got_c = ao.filtered_depth(), ao.filtered_depth(unit=0.0005)
        assert got_m.dtype == np.float32 and got_m.shape == (h, w)
        assert got_c.dtype == np.uint16 and got_c.shape == (h, w)
        assert np.array_equal(got_m.view(np.uint32), ref_m.view(np.uint32)), "frame %d" % i
        assert np.array_equal(got_c, ref_c), "frame %d" % i
        assert np.count_nonzero(got_m) > w * h // 2  # a frame with depth


# --- units, scale, no depth -----------------------------------------------------------

def test_counts_and_metres_agree(recording):
    """filtered_depth(unit) is the metres in counts of unit, rounded; 0 stays 0."""
    cam, frames = recording
    _, d, unit = frames[0]
    ao = depthao.AO(cam)
    ao.process(with_holes(d), unit=unit)
    m = ao.filtered_depth()
    for u in (unit, 0.0005, 0.0001, 0.01):
        c = ao.filtered_depth(unit=u)
        want = np.rint(m.astype(np.float64) / np.float32(u))
        has = m > 0
        assert np.array_equal(c == 0, ~has), "unit %g: 0 only where there is no depth" % u
        # rounding in float32 may land one count off at a tie
        assert np.abs(c[has].astype(np.float64) - np.clip(want[has], 1, 65535)).max() <= 1, u
    # counts beyond 65535 saturate: 1 m at 10 um is 100000 counts
    assert ao.filtered_depth(unit=1e-5)[m > 0.7].min() == 65535


def test_unit_and_scale_kept(recording):
    """With the filters off, uint16 depth read back in its own unit is the input,
    count for count; with the default prefilter the counts stay in the input's unit
    and scale (the mean difference well under a millimetre, per-pixel within noise)."""
    cam, frames = recording
    _, d, unit = frames[0]
    # +-3 counts of noise (the recording's depth is smooth): the prefilter has work to do
    rng = np.random.default_rng(7)
    d = with_holes(d)
    d = np.where(d > 0, d.astype(np.int32) + rng.integers(-3, 4, d.shape), 0).astype(np.uint16)
    off = depthao.AO(cam, prefilter="none", depth_temporal=0)
    off.process(d, unit=unit)
    p = off.params
    inside = (d * unit >= p["depth_min"]) & (d * unit <= p["depth_max"]) & (d > 0)
    got = off.filtered_depth(unit=unit)
    assert np.array_equal(got[inside], d[inside])
    assert not got[~inside].any()
    on = depthao.AO(cam)
    on.process(d, unit=unit)
    f = on.filtered_depth(unit=unit).astype(np.float64)
    both = inside & (f > 0)
    assert both.sum() > 0.95 * inside.sum()  # the prefilter makes no holes (nearly)
    diff = (f - d)[both]
    assert abs(diff.mean()) < 0.5e-3 / unit
    assert np.percentile(np.abs(diff), 99) < 20e-3 / unit  # within the sensor's noise
    assert np.count_nonzero(diff) > 0.1 * both.sum()  # the filter did something


def test_no_depth_is_zero():
    """Holes, NaN, inf and depth outside depth-min/max are 0, in metres and counts."""
    cam = depthao.Camera(120, 120, 39.5, 29.5, 80, 60)
    z = np.full((60, 80), 1.5, np.float32)
    z[10:20, 10:20] = 0
    z[30, :] = np.nan
    z[40, :] = np.inf
    z[50:, 60:] = 50.0  # beyond depth-max
    ao = depthao.AO(cam, algorithm="none")
    ao.process(z)
    for out in (ao.filtered_depth(), ao.filtered_depth(unit=0.001)):
        empty = (z == 0) | ~np.isfinite(z) | (z > ao.depth_max)
        assert not out[empty].any()
        assert out[~empty].all()
    assert np.all(ao.filtered_depth(unit=0.001)[~empty] == 1500)


# --- algorithm none ----------------------------------------------------------------------

def test_depth_only_equals_the_depth_the_ao_used(recording):
    """algorithm="none": the same filtered depth as with the AO, frame after frame
    (temporal filter on); the AO output is 1 where there is depth and invalid_value
    elsewhere; shade() and normals() refused with ENODATA."""
    cam, frames = recording
    full = depthao.AO(cam, stream=True)
    only = depthao.AO(cam, stream=True, algorithm="none", invalid_value=0.25)
    assert only.algorithm == "none"
    for k, (i, d, unit) in enumerate(frames):
        d = with_holes(d) if k % 2 else d
        vis = full.process(d, unit=unit, frame_index=k)
        vis_none = only.process(d, unit=unit, frame_index=k)
        a, b = full.filtered_depth(), only.filtered_depth()
        assert np.array_equal(a.view(np.uint32), b.view(np.uint32)), "frame %d" % i
        assert np.array_equal(full.filtered_depth(unit), only.filtered_depth(unit))
        assert np.array_equal(vis_none == 1.0, b > 0) and np.all(vis_none[b == 0] == 0.25)
        assert not np.all(vis[b > 0] == 1.0)  # the AO run computed occlusion
    for call in (only.shade, only.normals):
        with pytest.raises(OSError) as e:
            call()
        assert e.value.errno == errno.ENODATA
    # back to an AO algorithm: the AO again, same depth
    only.algorithm = "gtao"
    only.process(frames[0][1], unit=frames[0][2], frame_index=0)
    assert only.normals().shape == cam.shape + (3,)


# --- errors ----------------------------------------------------------------------------

def test_errors():
    cam = depthao.Camera(120, 120, 39.5, 29.5, 80, 60)
    ao = depthao.AO(cam)
    for unit in (None, 0.001):
        with pytest.raises(OSError) as e:
            ao.filtered_depth(unit)
        assert e.value.errno == errno.EAGAIN and "process" in str(e.value)
    ao.process(np.full((60, 80), 1000, np.uint16))
    for bad in (0, -0.001, math.nan, math.inf, "0.001", True, [0.001]):
        with pytest.raises(ValueError, match="unit must be a positive number"):
            ao.filtered_depth(unit=bad)
    assert ao.filtered_depth(0.001).max() == 1000
    ao.close()
    with pytest.raises(ValueError, match="closed"):
        ao.filtered_depth()
