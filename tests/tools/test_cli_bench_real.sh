#!/bin/sh
# SPDX-License-Identifier: MIT
# depthao bench --input on real sensor frames (../shared/data; skipped without them): the
# Kinect v1 recording as a stream, and the TUM frame with its 0.2 mm unit.  Timings are
# printed, never asserted.
. "$(dirname "$0")/cli_lib.sh"

DATA=${DAO_SHARED_DATA:-../shared/data}
ONI="$DATA/oni/3DJ_test.oni"
TUM="$DATA/tum_open3d/TUM_depth.png"
if [ ! -r "$ONI" ] || [ ! -r "$TUM" ]; then
	echo "skip: the real frames are not there ($ONI, $TUM; ../shared/data beside the checkout)"
	exit 77
fi
QUICK="--quality default --threads 1 --min-iterations 1 --min-time 0 --no-reference --json"

# the Kinect recording: its 12 frames, 640x480 16-bit, every stage of the default preset
if expect_exit 0 "bench kinect" -- "$DEPTHAO" bench --input "$ONI" $QUICK; then
	python3 - "$WORK/out" "$ONI" <<'PY' || fail "bench kinect: $(cat "$WORK/out")"
import json, sys
(line,) = open(sys.argv[1]).read().splitlines()
o = json.loads(line)
assert o["input"] == sys.argv[2] and o["input_frames"] == 12 and o["stream"], o
assert (o["width"], o["height"], o["input_format"]) == (640, 480, "depth16"), o
assert o["iterations"] >= 12 and o["depth_temporal"] > 0, o
for k in ("decode", "prefilter", "normals", "gtao", "denoise", "output", "shade"):
    assert o["stage_median_ms"][k] > 0, (k, o)
PY
fi
# one TUM frame in 0.2 mm counts: one frame, not a stream
if expect_exit 0 "bench tum" -- "$DEPTHAO" bench --input "$TUM" --depth-unit 0.0002 $QUICK; then
	python3 - "$WORK/out" <<'PY' || fail "bench tum: $(cat "$WORK/out")"
import json, sys
o = json.loads(open(sys.argv[1]).read())
assert o["input_frames"] == 1 and not o["stream"] and o["depth_temporal"] == 0, o
assert (o["width"], o["height"]) == (640, 480), o
PY
fi

finish
