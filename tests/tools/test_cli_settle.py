#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""depthao eval --sequence --settle K: the flicker and change from frame K on.

A still structured-light camera of 6 frames (synth). The filters-off column's
figures are checked against the AO that `depthao process` writes with the
same settings, read here by PIL and reduced by numpy:
- the tracked flicker (depth_gt/ and poses.txt beside the frames): the
  per-pixel standard deviation over frames K..5 at the points with a true
  surface in frame 0 and input depth in every frame from K on (a still
  camera's points are its pixels), and the same over every frame, which must
  differ by far more than the tolerance: a --settle that measured every frame
  would fail;
- the change from frame K: the mean |AO_k - AO_k-1| over the pairs from
  (K, K+1) on, at the pixels with depth in both frames;
- the per-pixel flicker of the frames alone (depth/ and its camera.json: no
  truth), over the pixels with depth in every frame that stays within 3 % of
  frame 0's.
Usage errors: K too large for the sequence, K not a number.

usage: test_cli_settle.py DEPTHAO_CLI
"""

import glob
import os
import re
import sys
import tempfile

try:
    import numpy as np
    from PIL import Image
except ImportError:
    print("SKIP: numpy or PIL is not installed (python3-numpy, python3-pil)")
    sys.exit(77)

from cli_run import check, run

FRAMES, K = 6, 2
FLICKER = (r"(\d+) surface points seen in every frame\): off ([\d.]+), depth ([\d.]+), "
           r"depth\+AO ([\d.]+)")


def frames(directory):
    paths = sorted(glob.glob(os.path.join(directory, "*.png")))
    check(len(paths) == FRAMES, "%s: %d PNGs, want %d" % (directory, len(paths), FRAMES))
    return np.stack([np.asarray(Image.open(p)).astype(np.float64) for p in paths])


def flicker(ao, depth, truth0, first):
    """Mean per-pixel std over frames first.. where frame 0 has a surface and
    every frame from `first` on has input depth; and the number of pixels."""
    mask = (truth0 > 0) & (depth[first:] > 0).all(axis=0)
    return ao[first:].std(axis=0)[mask].mean(), int(mask.sum())


def change(ao, depth, first):
    """Mean |AO_k - AO_k-1| over k = first+1.. at the pixels with depth in both."""
    diffs = [np.abs(ao[k] - ao[k - 1])[(depth[k] > 0) & (depth[k - 1] > 0)]
             for k in range(first + 1, len(ao))]
    return np.concatenate(diffs).mean()


def near(got, want, what):
    # 1 %: the AO as 16-bit PNG, and the per-file R2 pattern of process
    check(abs(got - want) <= 0.01 * want, "%s: %.6f, the PNGs give %.6f" % (what, got, want))


def main():
    cli = sys.argv[1]
    with tempfile.TemporaryDirectory() as tmp:
        run(cli, "synth", "--scene", "boxes", "--trajectory", "still", "--sensor",
            "structured-light", "--frames", str(FRAMES), "--rays", "1", "--out", tmp)
        base = os.path.join(tmp, "boxes-still-structured-light")
        text = run(cli, "eval", "--sequence", base, "--quality", "low", "--settle", str(K))
        whole = re.search(r"flicker \(tracked over the true poses, " + FLICKER, text)
        settled = re.search(r"flicker from frame %d \(%d frames\) \(tracked over the true poses, "
                            % (K, FRAMES - K) + FLICKER, text)
        check(whole and settled, "the two flicker lines: " + text)
        check(re.search(r"change from frame %d: off 0\.\d+, depth 0\.\d+" % K, text), text)

        depth = frames(os.path.join(base, "depth"))
        truth0 = frames(os.path.join(base, "depth_gt"))[0]
        off_dir = os.path.join(tmp, "off")
        run(cli, "process", "--quiet", "--input", os.path.join(base, "depth"), "--quality", "low",
            "--depth-temporal", "0", "--temporal", "0", "--ao-out", off_dir)
        ao = frames(off_dir) / 65535.0
        for m, first in ((settled, K), (whole, 0)):
            want, count = flicker(ao, depth, truth0, first)
            check(int(m.group(1)) == count,
                  "from frame %d: %s points, the PNGs give %d" % (first, m.group(1), count))
            near(float(m.group(2)), want, "off's flicker from frame %d" % first)
        m = re.search(r"change from frame %d: off ([\d.]+)," % K, text)
        check(m, text)
        near(float(m.group(1)), change(ao, depth, K), "off's change from frame %d" % K)

        # the frames alone: per-pixel flicker over the pixels whose depth stays
        text = run(cli, "eval", "--sequence", os.path.join(base, "depth"), "--quality", "low",
                   "--settle", str(K))
        m = re.search(r"flicker from frame %d \(%d frames\) \((\d+) static px\): off ([\d.]+),"
                      % (K, FRAMES - K), text)
        check(m, "the frames alone: " + text)
        static = (depth > 0).all(axis=0) & (np.abs(depth - depth[0]) <= 0.03 * depth[0]).all(axis=0)
        check(int(m.group(1)) == int(static.sum()),
              "%s static pixels, the PNGs give %d" % (m.group(1), static.sum()))
        near(float(m.group(2)), ao[K:].std(axis=0)[static].mean(),
             "off's flicker of the frames alone from frame %d" % K)

        err = run(cli, "eval", "--sequence", base, "--settle", str(FRAMES - 1), expect=2)
        check("--settle %d: the sequence has %d frames" % (FRAMES - 1, FRAMES) in err and
              "needs K + 2 frames at least (%d here)" % (FRAMES + 1) in err, err)
        err = run(cli, "eval", "--sequence", base, "--settle", "x", expect=2)
        check("--settle 'x' must be an integer" in err, err)
    print("ok")


main()
