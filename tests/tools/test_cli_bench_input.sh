#!/bin/sh
# SPDX-License-Identifier: MIT
# depthao bench --input: the user's frames timed instead of the synthetic one (a PNG
# directory, one PNG, an .oni recording, float-metre depth from an MCAP), what the JSON
# and the header say about them, --compare with --input, and the errors.  Timings are
# printed, never asserted: only that a stage that ran took some time.
# usage: test_cli_bench_input.sh DEPTHAO PNG_INFO TEST_PLUGINS (tests/daemon's build
# directory: the test camera testsrc)
. "$(dirname "$0")/cli_lib.sh"

ROOT=${DAO_SOURCE_ROOT:?}
NOISY="$ROOT/recordings/spheres-noisy"
REC="$ROOT/recordings/boxes-sliding.oni"
FAKE="$(cd "$(dirname "$0")" && pwd)/fake_depthao.sh"
TEST_PLUGINS=${3:?the directory of the test camera plugin, depthao-testsrc.so}
BUILD=$(cd "$(dirname "$DEPTHAO")/../.." && pwd)
QUICK="--quality default --threads 1 --min-iterations 1 --min-time 0 --no-reference"

# json_is FILE INPUT FRAMES W H FORMAT STREAM DEPTH_TEMPORAL: the one line bench printed
json_is() {
	python3 - "$@" <<'PY' || fail "bench --input $2 --json: $(cat "$1")"
import json, sys
path, inp, frames, w, h, fmt, stream, temporal = sys.argv[1:]
lines = open(path).read().splitlines()
assert len(lines) == 1, lines
o = json.loads(lines[0])
assert o["input"] == inp, o
assert o["input_frames"] == int(frames), o
assert (o["width"], o["height"], o["threads"]) == (int(w), int(h), 1), o
assert o["input_format"] == fmt, o
assert o["stream"] == (stream == "stream"), o
assert abs(o["depth_temporal"] - float(temporal)) < 1e-6, o
assert o["iterations"] >= int(frames), o  # each frame timed at least once
assert 0 < o["median_ms"] <= o["p95_ms"], o
# the stages of the default preset run on every frame: each took time
for k in ("decode", "prefilter", "normals", "gtao", "denoise", "output", "shade"):
    assert o["stage_median_ms"][k] > 0, (k, o)
PY
}

# a directory of PNGs: its 4 frames at their size, as a stream, camera.json's camera
if expect_exit 0 "bench --input dir" -- "$DEPTHAO" bench --input "$NOISY" $QUICK --json; then
	json_is "$WORK/out" "$NOISY" 4 640 480 depth16 stream 0.8
	grep -q "using intrinsics from $NOISY/camera.json" "$WORK/err" ||
		fail "bench --input dir: camera.json not used: $(cat "$WORK/err")"
fi
# ... fewer of them, and the temporal filter off as asked
if expect_exit 0 "bench --input-frames" -- "$DEPTHAO" bench --input "$NOISY" --input-frames 2 \
	--depth-temporal 0 $QUICK --json; then
	json_is "$WORK/out" "$NOISY" 2 640 480 depth16 stream 0
fi
# the table: the header says what was timed
if expect_exit 0 "bench --input table" -- "$DEPTHAO" bench --input "$NOISY" $QUICK; then
	for want in "on --input $NOISY\$" "4 frames of 640x480 depth16 (1 mm) in memory, cycled in order as a stream" \
		"^640x480 *default 2x6 *1 "; do
		grep -q -- "$want" "$WORK/out" || fail "bench --input table lacks '$want': $(cat "$WORK/out")"
	done
	grep -q "synthetic" "$WORK/out" && fail "bench --input table says synthetic: $(cat "$WORK/out")"
fi
# one PNG: one frame, not a stream (no temporal filter, as `process` runs a PNG)
if expect_exit 0 "bench --input png" -- "$DEPTHAO" bench --input "$NOISY/0001.png" $QUICK --json; then
	json_is "$WORK/out" "$NOISY/0001.png" 1 640 480 depth16 png 0
fi
# a recording: its 8 frames (fewer than --input-frames' default), its field of view
if expect_exit 0 "bench --input oni" -- "$DEPTHAO" bench --input "$REC" $QUICK --json; then
	json_is "$WORK/out" "$REC" 8 640 480 depth16 stream 0.8
	grep -q "field of view from the source" "$WORK/err" ||
		fail "bench --input oni: the recording's field of view not used: $(cat "$WORK/err")"
fi
# float metres (32FC1): the filtered depth of the PNGs, in 0.5 mm, to MCAP and back
MC="$WORK/half.mcap"
if expect_exit 0 "mcap of float depth" -- "$DEPTHAO" process --input "$NOISY" --quiet \
	--depth-unit 0.0005 --mcap-out "$MC?filtered_depth=true" &&
	expect_exit 0 "bench --input float" -- "$DEPTHAO" bench \
		--input "$MC?topic=/depthao/depth_filtered" --input-frames 3 $QUICK --json; then
	json_is "$WORK/out" "$MC?topic=/depthao/depth_filtered" 3 640 480 depth-f32 stream 0.8
fi

# --compare with --input: one run per build on the input's frames, no --size
if expect_exit 0 "compare --input" -- "$DEPTHAO" bench --compare "$BUILD" --rounds 1 \
	--input "$NOISY" --input-frames 2 $QUICK --json; then
	python3 - "$WORK/out" "$NOISY" <<'PY' || fail "compare --input: $(cat "$WORK/out")"
import json, sys
o = json.loads(open(sys.argv[1]).read())
assert o["input"] == sys.argv[2] and o["sizes"] == [], o
for b in o["builds"]:
    assert b["runs"] == 1, b
    assert "--size" not in b["args"], b
    i = b["args"].index("--input")
    assert b["args"][i + 1] == sys.argv[2], b
    assert b["args"][b["args"].index("--input-frames") + 1] == "2", b
(c,) = o["configurations"]
assert (c["width"], c["height"], c["threads"]) == (640, 480, 1), c
PY
fi
if expect_exit 0 "compare --input table" -- "$DEPTHAO" bench --compare-params '--depth-temporal 0' \
	--rounds 1 --input "$NOISY" --input-frames 2 $QUICK; then
	grep -q "one run on the frames of --input $NOISY" "$WORK/out" ||
		fail "compare --input table: $(cat "$WORK/out")"
fi
# an older build that does not know --input: said before any round
export FAKE_LOG="$WORK/fake.log" FAKE_MODE=reject
if expect_exit 2 "compare --input, older build" -- "$DEPTHAO" bench --compare "$FAKE" \
	--rounds 1 --input "$NOISY" $QUICK; then
	grep -q "is older than bench --input (it says: unknown option '--input'): it times the synthetic frame only" \
		"$WORK/err" || fail "compare --input, older build: $(cat "$WORK/err")"
	[ -s "$WORK/out" ] && fail "compare --input, older build: printed on stdout: $(cat "$WORK/out")"
fi

# errors: usage errors (exit 2, one line), then what is wrong with the input (exit 1)
expect_usage_error "--size with --input" -- "$DEPTHAO" bench --input "$NOISY" --size 64x48 $QUICK
grep -q "leave out --size" "$WORK/err" || fail "--size with --input: $(cat "$WORK/err")"
expect_usage_error "--input-frames alone" -- "$DEPTHAO" bench --input-frames 3 --size 32x24 $QUICK
grep -q -- "--input-frames goes with --input" "$WORK/err" || fail "--input-frames alone: $(cat "$WORK/err")"
expect_usage_error "--fov alone" -- "$DEPTHAO" bench --fov 58,45 --size 32x24 $QUICK
expect_usage_error "--input-frames 0" -- "$DEPTHAO" bench --input "$NOISY" --input-frames 0 $QUICK
expect_usage_error "two cameras" -- "$DEPTHAO" bench --input "$NOISY" --fov 58,45 \
	--intrinsics 525,525,319.5,239.5 $QUICK
expect_usage_error "bad fov" -- "$DEPTHAO" bench --input "$NOISY" --fov 58 $QUICK
expect_usage_error "bad depth unit" -- "$DEPTHAO" bench --input "$NOISY" --depth-unit 2 $QUICK
expect_usage_error "source poses" -- "$DEPTHAO" bench --input "$REC" \
	--depth-temporal-motion source $QUICK

# input_error DESCRIPTION PATTERN -- command...: exit 1, one stderr line with PATTERN, no stdout
input_error() {
	what=$1
	pattern=$2
	shift 2
	if expect_exit 1 "$what" "$@"; then
		[ "$(wc -l <"$WORK/err")" -eq 1 ] || fail "$what: not one stderr line: $(cat "$WORK/err")"
		grep -q -- "$pattern" "$WORK/err" || fail "$what: stderr lacks '$pattern': $(cat "$WORK/err")"
		[ -s "$WORK/out" ] && fail "$what: printed on stdout: $(cat "$WORK/out")"
	fi
	return 0
}
input_error "missing input" "cannot read --input '$WORK/nowhere': No such file or directory" -- \
	"$DEPTHAO" bench --input "$WORK/nowhere" $QUICK
input_error "missing recording" "cannot read --input '$WORK/nowhere.oni'" -- \
	"$DEPTHAO" bench --input "$WORK/nowhere.oni" $QUICK
mkdir "$WORK/empty"
input_error "empty directory" "no \*.png files in" -- "$DEPTHAO" bench --input "$WORK/empty" $QUICK
# frames of two sizes: the one that differs named, and how to time the ones before it
mkdir "$WORK/mixed"
cp "$NOISY/0000.png" "$NOISY/0001.png" "$WORK/mixed/"
python3 "$ROOT/tests/tools/zero_png.py" 32 24 "$WORK/mixed/0002.png"
input_error "mixed sizes" \
	"frame 2 of '$WORK/mixed' cannot be read: .*0002.png is 32x24, but the sequence is 640x480 (--input-frames 2 times the frames before it)" -- \
	"$DEPTHAO" bench --input "$WORK/mixed" --fov 58,45 $QUICK
if expect_exit 0 "mixed sizes, the frames before" -- "$DEPTHAO" bench --input "$WORK/mixed" \
	--fov 58,45 --input-frames 2 $QUICK --json; then
	json_is "$WORK/out" "$WORK/mixed" 2 640 480 depth16 stream 0.8
fi
# ... from a camera whose mode changes after 2 frames (a live source delivers them; bench
# checks each frame it keeps against the first): the same, as bench says it
[ -e "$TEST_PLUGINS/depthao-testsrc.so" ] || fail "no test camera in $TEST_PLUGINS"
CAM="testsrc:fps=200,w=64,h=48,resize_after=2,w2=32,h2=24"
input_error "camera changing size" \
	"^depthao: frame 2 of '$CAM' is 32x24 depth16, but the input's frames are 64x48 depth16: bench times frames of one size and format (--input-frames 2 times the frames before it)\$" -- \
	env DEPTHAO_PLUGIN_PATH="$TEST_PLUGINS" "$DEPTHAO" bench --input "$CAM" --fov 58,45 $QUICK
if expect_exit 0 "camera changing size, the frames before" -- env DEPTHAO_PLUGIN_PATH="$TEST_PLUGINS" \
	"$DEPTHAO" bench --input "$CAM" --fov 58,45 --input-frames 2 $QUICK --json; then
	json_is "$WORK/out" "$CAM" 2 64 48 depth16 stream 0.8
fi
# larger than the pixel limit: refused before it is decoded
input_error "pixel limit" "(--max-pixels raises the limit)" -- \
	"$DEPTHAO" bench --input "$NOISY" --max-pixels 64x64 $QUICK
# more depth than bench holds: 65 frames of 4096x4096 (32 MiB each), refused before they
# are read, with the count that fits
mkdir "$WORK/big"
python3 "$ROOT/tests/tools/zero_png.py" 4096 4096 "$WORK/big/0000.png"
i=1
while [ $i -lt 65 ]; do
	ln -s 0000.png "$WORK/big/$(printf %04d $i).png"
	i=$((i + 1))
done
input_error "too much depth" \
	"65 frames of 4096x4096 depth16 take 2080 MiB, more than bench holds in memory (2048 MiB): give --input-frames 64 or fewer" -- \
	"$DEPTHAO" bench --input "$WORK/big" --input-frames 65 $QUICK

finish
