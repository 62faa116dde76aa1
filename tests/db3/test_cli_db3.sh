#!/bin/sh
# SPDX-License-Identifier: MIT
# depthao process on rosbag2 sqlite3 bags written here by sql.js with CDR from
# @foxglove/rosmsg2-serialization (make_db3.js; the sensor_msgs ones read back by
# @foxglove/rosbag2-web): Image 16UC1, compressedDepth PNG, Foxglove's
# foxglove_msgs/msg/RawImage 16UC1 and CompressedImage PNG with CameraCalibration, a bag
# directory (metadata.yaml) of sqlite3 (one file, and split in two) and of MCAP storage give
# the same AO as the same frames as 16-bit PNGs, with the CameraInfo's intrinsics (RawImage
# 32FC1: as Image 32FC1); --start and the frame count; colour overlays equal to the same
# messages' in MCAP; damaged databases.
# usage: test_cli_db3.sh DEPTHAO PNG_INFO NODE
. "$(dirname "$0")/../tools/cli_lib.sh"
. "$(dirname "$0")/../tools/recording_lib.sh"
NODE=$3
B="$WORK/db3"
need_program "$NODE"
make_recordings "$NODE" "${DAO_MAKE_DB3:?}" "$B"

png_reference "$B"
for f in d16.db3 cdepth.db3 bag split2 zfile zmsg bagmcap "db3:$B/d16.db3"; do
	case "$f" in db3:*) same_as_png uri "$f" ;; *) same_as_png "$f" "$B/$f" ;; esac
done

# Foxglove's schemas as ROS 2 messages (foxglove_msgs/msg/... in CDR; a .db3 has no schema
# encoding): RawImage 16UC1 and CompressedImage PNG give the PNGs' AO, RawImage 32FC1 that
# of the same floats in a sensor_msgs/msg/Image
same_as_png fgcdr_16 "$B/fgcdr_16.db3"
same_as_png fgcdr_png "$B/fgcdr_png.db3"
recording_run d32 "$B/d32.db3"
same_as_run d32 fgcdr_32 "$B/fgcdr_32.db3"

# the frame count, --start/--frames, ?topic= and ?unit= through the URI
start_frames "$B/d16.db3?topic=/camera/depth/image_raw&unit=0.001" \
	"d16.db3: /camera/depth/image_raw 64x48 16UC1, 5 frames"
process_fails "$B/d16.db3" "start frame 5 is past the end (topic '/camera/depth/image_raw' has 5 frames)" \
	--start 5
unit_as_png "$B" "$B/bag?unit=0.0001"
process_fails "$B/d16.db3?topic=/nope" "no image topic '/nope'; depth topics: /camera/depth/image_raw (16UC1)"

# colour (bgr8, 10 ms after the depth): the overlays are those of the same messages in MCAP
for f in color.db3 color.mcap; do
	expect_exit 0 "colour $f" -- "$DEPTHAO" process --input "$B/$f" --depth-temporal 0 \
		--ao-out "$WORK/$f-ao" --overlay-out "$WORK/$f-ov" --quiet
	[ "$(ls "$WORK/$f-ov" 2>/dev/null | wc -l)" -eq 5 ] || fail "$f: $(ls "$WORK/$f-ov" 2>/dev/null | wc -l) overlays"
done
for i in 000000 000001 000002 000003 000004; do
	cmp -s "$WORK/color.db3-ov/$i.png" "$WORK/color.mcap-ov/$i.png" || fail "colour: overlay $i differs from MCAP's"
	cmp -s "$WORK/color.db3-ao/$i.png" "$WORK/png-ao/$i.png" || fail "colour: AO $i differs from the PNG run"
done
cmp -s "$WORK/color.db3-ov/000000.png" "$WORK/color.db3-ov/000001.png" && fail "colour: overlays 0 and 1 are the same"

# damaged databases: one line naming the file and what is wrong
db3_error() { # INPUT MESSAGE [options]
	in=$1 msg=$2
	shift 2
	process_fails "$B/$in" "$B/$in: $msg" "$@"
	[ "$(wc -l <"$WORK/err")" -eq 1 ] || fail "$in: more than one line: $(cat "$WORK/err")"
}
db3_error notopics.db3 "no table 'topics': not a rosbag2 database (its tables are topics and messages)"
db3_error nocolumn.db3 "table messages (id, topic_id, timestamp, data): no such column: timestamp"
db3_error texttime.db3 "table messages, id 4: timestamp is not an integer"
db3_error textdata.db3 "table messages, id 2: data is text, not a blob"
db3_error badtopic.db3 "table messages, id 3: topic_id 99 is not in table topics"
db3_error cut.db3 "message 0 of '/camera/depth/image_raw' is not a sensor_msgs/msg/Image (cdr)"
db3_error fgcdr_cut.db3 "message 0 of '/camera/depth/image_raw' is not a foxglove_msgs/msg/RawImage (cdr)"
db3_error yuv.db3 "no depth image topic (sensor_msgs Image in 16UC1, mono16 or 32FC1, or compressedDepth; Foxglove RawImage or 16-bit PNG CompressedImage); image topics: /camera/depth/image_raw (yuv422)"
db3_error bigblob.db3 "table messages, id 2: 2103368 bytes of data, over the limit of 1052576" --max-pixels 1000
db3_error notsqlite.db3 "not a rosbag2 .db3 file (no SQLite 3 header)"
# a split bag: the frame count and --start across its files; files missing or out of order
expect_exit 0 "split: --start 1 --frames 3" -- "$DEPTHAO" process --input "$B/split2" --start 1 \
	--frames 3 --depth-temporal 0 --ao-out "$WORK/split-start"
grep -q "split2: /camera/depth/image_raw 64x48 16UC1, 5 frames" "$WORK/err" || fail "split frame count: $(cat "$WORK/err")"
frames_as_png "split --start 1 --frames 3" "$WORK/split-start" 000001 000002 000003
process_fails "$B/split" "$B/split: file 1 of the 2 its metadata.yaml lists (a split bag plays only with all its files): "
grep -qF "split_0.db3" "$WORK/err" || fail "split: the file is not named: $(cat "$WORK/err")"
process_fails "$B/splitmiss" "$B/splitmiss: file 2 of the 2 its metadata.yaml lists (a split bag plays only with all its files): "
grep -qF "s_1.db3" "$WORK/err" || fail "splitmiss: $(cat "$WORK/err")"
process_fails "$B/splitorder" "$B/splitorder: $B/splitorder/s_0.db3 starts before the file before it ends on topic /camera/depth/camera_info: the files are not in the order of their messages' times"
# rosbag2's compression, hostile: a bomb of each mode, data that is not zstd, another format
process_fails "$B/zbomb" "$B/zbomb/zbomb_0.db3.zstd: decompresses to more than 67108864 bytes (the limit for a file of its size): refused (if it is genuine, decompress it with zstd -d first)"
process_fails "$B/zmbomb" "$B/zmbomb/zmbomb_0.db3: message 0 of '/camera/depth/image_raw' (zstd, compression_mode message): decompresses to 8388608 bytes, over the limit of 1052576 (--max-pixels raises the limit)" --max-pixels 1000
process_fails "$B/znotz" "$B/znotz/znotz_0.db3.zstd: not zstd data, or damaged: "
process_fails "$B/zlz4" "$B/zlz4/metadata.yaml: compression_format 'lz4' (mode 'FILE'): depthao reads rosbag2's zstd, in file or message mode; decompress the bag first"
# a directory whose metadata.yaml is not rosbag2's
mkdir -p "$WORK/notbag" && printf 'hello: world\n' >"$WORK/notbag/metadata.yaml"
process_fails "$WORK/notbag" "$WORK/notbag/metadata.yaml: no rosbag2_bagfile_information mapping"
# the file is never written: opened read-only and immutable
sum=$(cksum <"$B/d16.db3")
expect_exit 0 "read-only" -- "$DEPTHAO" process --input "$B/d16.db3" --frames 1 --ao-out "$WORK/ro" --quiet
[ "$(cksum <"$B/d16.db3")" = "$sum" ] || fail "d16.db3 changed"
ls "$B"/d16.db3-* 2>/dev/null && fail "a journal or WAL file beside d16.db3"

# --depth-out: the filtered depth of a db3 bag is that of the same frames as PNGs (the
# temporal filter off, which PNG input does not run); with --algorithm none as well
expect_exit 0 "PNG depth" -- "$DEPTHAO" process --input "$B/png" --depth-out "$WORK/png-d" --quiet
for alg in gtao none; do
	expect_exit 0 "db3 --depth-out ($alg)" -- "$DEPTHAO" process --input "$B/d16.db3" \
		--depth-temporal 0 --algorithm $alg --depth-out "$WORK/db3-d-$alg" --quiet
	for i in 000000 000004; do
		cmp -s "$WORK/db3-d-$alg/$i.png" "$WORK/png-d/$i.png" ||
			fail "db3 --depth-out ($alg): $i differs from the PNG run's"
	done
done
finish
