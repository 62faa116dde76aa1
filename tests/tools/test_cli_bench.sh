#!/bin/sh
# SPDX-License-Identifier: MIT
# depthao bench: the table and JSON lines carry what the README promises, and
# its options are checked.  Timings are printed, never asserted.
. "$(dirname "$0")/cli_lib.sh"

expect_exit 0 "bench --help" -- "$DEPTHAO" bench --help
grep -q "usage: depthao bench" "$WORK/out" || fail "bench --help lacks usage"

# one small configuration, JSON: one object per line with the documented keys
if expect_exit 0 "bench --json" -- "$DEPTHAO" bench --size 96x64 --quality low --threads 1 \
	--min-iterations 3 --min-time 0 --json; then
	lines=$(wc -l <"$WORK/out")
	[ "$lines" -eq 1 ] || fail "bench --json: $lines lines, expected 1"
	python3 - "$WORK/out" <<'PY' || fail "bench --json: bad object: $(cat "$WORK/out")"
import json, sys
o = json.loads(open(sys.argv[1]).readline())
for k in ("width", "height", "quality", "slices", "steps", "threads", "median_ms", "p95_ms",
          "simd", "speedup", "reference_median_ms", "stage_median_ms"):
    assert k in o, k
assert (o["width"], o["height"], o["quality"], o["threads"]) == (96, 64, "low", 1), o
assert (o["slices"], o["steps"]) == (1, 6), o
assert 0 < o["median_ms"] <= o["p95_ms"], o
assert abs(o["fps"] - 1e3 / o["median_ms"]) < 1e-9 * o["fps"], o
assert o["iterations"] >= 3, o
assert set(o["stage_median_ms"]) == {"decode", "noise", "prefilter", "normals", "gtao",
                                     "denoise", "output", "shade"}, o
PY
fi

# --slices/--steps override the preset and mark it custom; table output has a header with the CPU
if expect_exit 0 "bench table" -- "$DEPTHAO" bench --size 64x48 --quality default --slices 3 \
	--steps 4 --threads 1 --min-iterations 2 --min-time 0 --no-reference; then
	grep -q "kernels " "$WORK/out" || fail "bench header lacks the kernel set"
	grep -q "^64x48 *custom 3x4 *1 " "$WORK/out" || fail "bench row: $(cat "$WORK/out")"
fi

# sizes and thread counts as lists, repeated, and the sensors' set, in the order given
if expect_exit 0 "bench size lists" -- "$DEPTHAO" bench --size 32x24,40x30 --size 48x32 \
	--quality low --threads 1,2 --min-iterations 1 --min-time 0 --no-reference --json; then
	python3 - "$WORK/out" <<'PY' || fail "bench size lists: $(cat "$WORK/out")"
import json, sys
got = [(o["width"], o["height"], o["threads"]) for o in map(json.loads, open(sys.argv[1]))]
assert got == [(w, h, t) for w, h in ((32, 24), (40, 30), (48, 32)) for t in (1, 2)], got
PY
fi
if expect_exit 0 "bench sensors" -- "$DEPTHAO" bench --size sensors --quality low --threads 1 \
	--min-iterations 1 --min-time 0 --no-reference; then
	sizes=$(awk '$2 == "low" { printf "%s ", $1 }' "$WORK/out")
	[ "$sizes" = "640x480 848x480 1280x720 1024x1024 " ] || fail "bench sensors: $sizes"
	grep -q "  fps " "$WORK/out" || fail "bench table lacks fps: $(cat "$WORK/out")"
fi

# (quick options too, in case one were accepted)
QUICK="--quality low --min-iterations 1 --min-time 0 --no-reference"
expect_usage_error "bench bad size" -- "$DEPTHAO" bench --size 64by48 $QUICK
expect_usage_error "bench bad size in a list" -- "$DEPTHAO" bench --size 64x48,sensor $QUICK
expect_usage_error "bench empty size in a list" -- "$DEPTHAO" bench --size 64x48, $QUICK
expect_usage_error "bench too many sizes" -- "$DEPTHAO" bench $QUICK \
	--size sensors,sensors,sensors,sensors,32x32
expect_usage_error "bench bad thread list" -- "$DEPTHAO" bench --threads 1,,2 --size 32x24 $QUICK
expect_usage_error "bench bad quality" -- "$DEPTHAO" bench --quality extreme --size 32x24 $QUICK
expect_usage_error "bench bad threads" -- "$DEPTHAO" bench --threads 0 --size 32x24 $QUICK
expect_usage_error "bench reference" -- "$DEPTHAO" bench --simd reference --size 32x24 $QUICK
expect_usage_error "bench unknown option" -- "$DEPTHAO" bench --frobnicate --size 32x24 $QUICK

[ "$failures" -eq 0 ] || exit 1
echo "bench CLI: ok"
