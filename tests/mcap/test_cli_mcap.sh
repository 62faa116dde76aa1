#!/bin/sh
# SPDX-License-Identifier: MIT
# depthao process on MCAP files that the reference implementation writes here
# (make_mcaps.js: @mcap/core, CDR by @foxglove/rosmsg2-serialization): chunked zstd and
# lz4, unchunked, without summary, compressedDepth PNG and RVL, Foxglove RawImage in protobuf
# and JSON and CompressedImage PNG (with CameraCalibration) give the same AO as the same
# frames as 16-bit PNGs; damaged Foxglove messages; --start on the indexes; a file cut short; corrupt files.
# usage: test_cli_mcap.sh DEPTHAO PNG_INFO NODE
. "$(dirname "$0")/../tools/cli_lib.sh"
NODE=$3
M="$WORK/mcap"
command -v "$NODE" >/dev/null 2>&1 || { echo "SKIP: node is not installed"; exit 77; }

set +e
"$NODE" "${DAO_MAKE_MCAPS:?}" "$M"
st=$?
set -e
[ "$st" -eq 77 ] && exit 77 # tests/js/node_modules is absent (the script said so)
[ "$st" -eq 0 ] || { echo "make_mcaps.js failed ($st)"; exit 1; }

expect_exit 0 "PNG frames" -- "$DEPTHAO" process --input "$M/png" --ao-out "$WORK/png-ao" \
	--shaded-out "$WORK/png-sh" --quiet
for f in d16_zstd d16_lz4 d16_none d16_nosum cdepth_png cdepth_rvl fg_proto fg_json fg_png; do
	expect_exit 0 "$f" -- "$DEPTHAO" process --input "$M/$f.mcap" --depth-temporal 0 \
		--ao-out "$WORK/$f-ao" --shaded-out "$WORK/$f-sh" || continue
	grep -q "intrinsics from the source: fx 60.00 fy 61.00 cx 31.50 cy 23.25" "$WORK/err" ||
		fail "$f: intrinsics not from the CameraInfo: $(cat "$WORK/err")"
	grep -q "warning" "$WORK/err" && fail "$f: a warning: $(cat "$WORK/err")"
	[ "$(ls "$WORK/$f-ao" | wc -l)" -eq 5 ] || fail "$f: $(ls "$WORK/$f-ao" | wc -l) AO files"
	for i in 000000 000001 000002 000003 000004; do
		cmp -s "$WORK/$f-ao/$i.png" "$WORK/png-ao/$i.png" || fail "$f: AO $i differs from the PNG run"
		cmp -s "$WORK/$f-sh/$i.png" "$WORK/png-sh/$i.png" || fail "$f: shaded $i differs"
	done
done

# Foxglove schemas damaged: each error names the message and what was expected
fg_error() { # FILE MESSAGE
	expect_exit 1 "$1" -- "$DEPTHAO" process --input "$M/$1.mcap" --ao-out "$WORK/$1" --quiet
	grep -qF "$2" "$WORK/err" || fail "$1: $(cat "$WORK/err")"
}
fg_error fg_yuv "no depth image topic (sensor_msgs/msg/Image in 16UC1, mono16 or 32FC1, or compressedDepth, in CDR; or foxglove.RawImage or 16-bit PNG foxglove.CompressedImage); image topics: /camera/depth/image_raw (yuv422)"
fg_error fg_cut "message 0 of '/camera/depth/image_raw' is not a foxglove.RawImage (protobuf)"
fg_error fg_type "message 0 of '/camera/depth/image_raw' is not a foxglove.RawImage (json)"
fg_error fg_k4 "the first message of '/camera/depth/calibration' is not a foxglove.CameraCalibration (protobuf; K must have 9 values"

# the frame count and --start/--frames through the URI (the chunk indexes of a summary)
expect_exit 0 "mcap: URI, --start 2 --frames 2" -- "$DEPTHAO" process \
	--input "mcap:$M/d16_zstd.mcap?topic=/camera/depth/image_raw&unit=0.001" --start 2 --frames 2 \
	--depth-temporal 0 --ao-out "$WORK/start"
grep -q "image_raw 64x48 16UC1, 5 frames" "$WORK/err" || fail "frame count: $(cat "$WORK/err")"
[ "$(ls "$WORK/start" | tr '\n' ' ')" = "000002.png 000003.png " ] ||
	fail "--start 2 --frames 2 wrote: $(ls "$WORK/start" | tr '\n' ' ')"
for i in 000002 000003; do
	cmp -s "$WORK/start/$i.png" "$WORK/png-ao/$i.png" || fail "--start: AO $i differs"
done
expect_exit 1 "--start past the end" -- "$DEPTHAO" process --input "$M/d16_lz4.mcap" --start 5 \
	--ao-out "$WORK/past" --quiet
grep -q "start frame 5 is past the end (topic '/camera/depth/image_raw' has 5 frames)" "$WORK/err" ||
	fail "--start 5: $(cat "$WORK/err")"
expect_exit 0 "?unit=" -- "$DEPTHAO" process --input "$M/d16_none.mcap?unit=0.0001" --frames 1 \
	--depth-temporal 0 --ao-out "$WORK/unit" --quiet
expect_exit 0 "PNG at 0.1 mm" -- "$DEPTHAO" process --input "$M/png" --depth-unit 0.0001 \
	--ao-out "$WORK/png-unit" --quiet
cmp -s "$WORK/unit/000000.png" "$WORK/png-unit/000000.png" || fail "?unit=0.0001 differs from PNGs"
cmp -s "$WORK/unit/000000.png" "$WORK/png-ao/000000.png" && fail "?unit= changed nothing"

# a recording cut short: the linear scan reads its complete chunks, with a warning
size=$(wc -c <"$M/d16_zstd.mcap")
head -c $((size * 2 / 3)) "$M/d16_zstd.mcap" >"$WORK/cut.mcap"
expect_exit 0 "cut short" -- "$DEPTHAO" process --input "$WORK/cut.mcap" --depth-temporal 0 \
	--ao-out "$WORK/cut"
grep -q "warning: the MCAP file is cut short" "$WORK/err" || fail "cut short: $(cat "$WORK/err")"
n=$(ls "$WORK/cut" | wc -l)
[ "$n" -ge 1 ] && [ "$n" -lt 5 ] || fail "cut short: $n frames"
cmp -s "$WORK/cut/000000.png" "$WORK/png-ao/000000.png" || fail "cut short: AO 0 differs"
head -c 30 "$M/d16_zstd.mcap" >"$WORK/tiny.mcap"
expect_exit 1 "no complete message" -- "$DEPTHAO" process --input "$WORK/tiny.mcap" --ao-out "$WORK/t" --quiet
grep -q "holds no complete message" "$WORK/err" || fail "tiny: $(cat "$WORK/err")"
printf 'not an mcap file at all' >"$WORK/bad.mcap"
expect_exit 1 "no magic" -- "$DEPTHAO" process --input "$WORK/bad.mcap" --ao-out "$WORK/b" --quiet
grep -q "not an MCAP file (no MCAP magic)" "$WORK/err" || fail "no magic: $(cat "$WORK/err")"
# a byte flipped inside a chunk of the file without summary: an error naming the file and byte
python3 - "$M/d16_nosum.mcap" "$WORK/flip.mcap" <<'PY' || fail "flip"
import sys
d = bytearray(open(sys.argv[1], "rb").read())
d[len(d) // 2] ^= 0x55
open(sys.argv[2], "wb").write(d)
PY
expect_exit 1 "a flipped byte" -- "$DEPTHAO" process --input "$WORK/flip.mcap" --ao-out "$WORK/flip" --quiet
grep -q "flip.mcap: byte [0-9]*: .*\(CRC\|zstd\|damaged\|record\)" "$WORK/err" || fail "flipped byte: $(cat "$WORK/err")"
# a colour topic (bgr8): the overlay for each depth frame; the AO as without colour
expect_exit 0 "colour" -- "$DEPTHAO" process --input "$M/color.mcap" --depth-temporal 0 \
	--ao-out "$WORK/col-ao" --overlay-out "$WORK/col-ov" --quiet
[ "$(ls "$WORK/col-ov" 2>/dev/null | wc -l)" -eq 5 ] || fail "colour: $(ls "$WORK/col-ov" 2>/dev/null | wc -l) overlays"
cmp -s "$WORK/col-ao/000004.png" "$WORK/png-ao/000004.png" || fail "colour: AO 4 differs from the PNG run"
png_is "$WORK/col-ov/000000.png" "64 48 rgb24"
cmp -s "$WORK/col-ov/000000.png" "$WORK/col-ov/000001.png" && fail "colour: overlays 0 and 1 are the same"
expect_exit 1 "?color= of a depth topic" -- "$DEPTHAO" process \
	--input "$M/color.mcap?color=/camera/depth/camera_info" --ao-out "$WORK/c2" --overlay-out "$WORK/c2o" --quiet
grep -q "no image topic '/camera/depth/camera_info' (color=)" "$WORK/err" || fail "?color=: $(cat "$WORK/err")"
# two depth topics would be refused with both listed: ?topic= names a missing one here
expect_exit 1 "missing topic" -- "$DEPTHAO" process --input "$M/d16_zstd.mcap?topic=/nope" \
	--ao-out "$WORK/n" --quiet
grep -q "no image topic '/nope'; depth topics: /camera/depth/image_raw (16UC1)" "$WORK/err" ||
	fail "missing topic: $(cat "$WORK/err")"
finish
