#!/bin/sh
# SPDX-License-Identifier: MIT
# depthao process on MCAP files that the reference implementation writes here
# (make_mcaps.js: @mcap/core, CDR by @foxglove/rosmsg2-serialization): chunked zstd and
# lz4, unchunked, without summary, compressedDepth PNG and RVL, Foxglove RawImage in protobuf
# and JSON and CompressedImage PNG (with CameraCalibration), and the same as foxglove_msgs in
# CDR, give the same AO as the same frames as 16-bit PNGs (32FC1: as sensor_msgs 32FC1);
# damaged Foxglove messages; --start on the indexes; a file cut short; corrupt files.
# usage: test_cli_mcap.sh DEPTHAO PNG_INFO NODE
. "$(dirname "$0")/../tools/cli_lib.sh"
. "$(dirname "$0")/../tools/recording_lib.sh"
NODE=$3
M="$WORK/mcap"
need_program "$NODE"
make_recordings "$NODE" "${DAO_MAKE_MCAPS:?}" "$M"

png_reference "$M"
for f in d16_zstd d16_lz4 d16_none d16_nosum cdepth_png cdepth_rvl fg_proto fg_json fg_png; do
	same_as_png "$f" "$M/$f.mcap"
done

# Foxglove schemas damaged: each error names the message and what was expected
process_fails "$M/fg_yuv.mcap" "no depth image topic (sensor_msgs Image in 16UC1, mono16 or 32FC1, or compressedDepth; Foxglove RawImage or 16-bit PNG CompressedImage); image topics: /camera/depth/image_raw (yuv422)"
process_fails "$M/fg_cut.mcap" "message 0 of '/camera/depth/image_raw' is not a foxglove.RawImage (protobuf)"
process_fails "$M/fg_type.mcap" "message 0 of '/camera/depth/image_raw' is not a foxglove.RawImage (json)"
process_fails "$M/fg_k4.mcap" "the first message of '/camera/depth/calibration' is not a foxglove.CameraCalibration (protobuf; K must have 9 values"

# Foxglove's schemas as ROS 2 messages (foxglove_msgs/msg/... in CDR, ros2msg), as ros2 bag
# record stores them: RawImage 16UC1 and CompressedImage PNG give the PNGs' AO; RawImage 32FC1
# that of the same floats in a sensor_msgs/msg/Image (d32.mcap)
same_as_png fgcdr_16 "$M/fgcdr_16.mcap"
same_as_png fgcdr_png "$M/fgcdr_png.mcap"
recording_run d32 "$M/d32.mcap"
same_as_run d32 fgcdr_32 "$M/fgcdr_32.mcap"
# damaged in CDR: a message cut short, a nanosec of 1e9, yuv422, a calibration cut short or
# with fx < 0
process_fails "$M/fgcdr_cut.mcap" "message 0 of '/camera/depth/image_raw' is not a foxglove_msgs/msg/RawImage (cdr)"
process_fails "$M/fgcdr_nsec.mcap" "message 0 of '/camera/depth/image_png' is not a foxglove_msgs/msg/CompressedImage (cdr)"
process_fails "$M/fgcdr_yuv.mcap" "no depth image topic (sensor_msgs Image in 16UC1, mono16 or 32FC1, or compressedDepth; Foxglove RawImage or 16-bit PNG CompressedImage); image topics: /camera/depth/image_raw (yuv422)"
process_fails "$M/fgcdr_calcut.mcap" "the first message of '/camera/depth/calibration' is not a foxglove_msgs/msg/CameraCalibration (cdr)"
process_fails "$M/fgcdr_fx.mcap" "/camera/depth/calibration is damaged, fix or drop it: "
for f in fgcdr_cut fgcdr_nsec fgcdr_yuv fgcdr_calcut fgcdr_fx; do
	expect_exit 1 "$f" -- "$DEPTHAO" process --input "$M/$f.mcap" --ao-out "$WORK/bad" --quiet
	[ "$(wc -l <"$WORK/err")" -eq 1 ] || fail "$f: not one line: $(cat "$WORK/err")"
done

# the frame count and --start/--frames through the URI (the chunk indexes of a summary)
start_frames "mcap:$M/d16_zstd.mcap?topic=/camera/depth/image_raw&unit=0.001" \
	"image_raw 64x48 16UC1, 5 frames"
process_fails "$M/d16_lz4.mcap" "start frame 5 is past the end (topic '/camera/depth/image_raw' has 5 frames)" \
	--start 5
unit_as_png "$M" "$M/d16_none.mcap?unit=0.0001"

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
process_fails "$WORK/tiny.mcap" "holds no complete message"
printf 'not an mcap file at all' >"$WORK/bad.mcap"
process_fails "$WORK/bad.mcap" "not an MCAP file (no MCAP magic)"
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
process_fails "$M/color.mcap?color=/camera/depth/camera_info" "no image topic '/camera/depth/camera_info' (color=)" \
	--overlay-out "$WORK/c2o"
# a foxglove_msgs/msg/RawImage bgr8 colour topic: color.mcap's overlays (the same pixels and stamps)
expect_exit 0 "colour in CDR" -- "$DEPTHAO" process --input "$M/fgcdr_16.mcap" --depth-temporal 0 \
	--ao-out "$WORK/fgc-ao" --overlay-out "$WORK/fgc-ov" --quiet
for i in $REC_FRAMES; do
	cmp -s "$WORK/fgc-ov/$i.png" "$WORK/col-ov/$i.png" || fail "colour in CDR: overlay $i differs from color.mcap's"
done
# two depth topics would be refused with both listed: ?topic= names a missing one here
process_fails "$M/d16_zstd.mcap?topic=/nope" "no image topic '/nope'; depth topics: /camera/depth/image_raw (16UC1)"
finish
