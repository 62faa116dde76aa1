#!/bin/sh
# SPDX-License-Identifier: MIT
# depthao process and depthaod on ROS bags that rosbag's Python writer makes here
# (make_bags.py): plain FILE.bag and bag:FILE?topic= inputs give the same AO as the same
# frames as 16-bit PNGs with the same intrinsics; the errors a user can cause.
# usage: test_cli_bag.sh DEPTHAO PNG_INFO DEPTHAOD
. "$(dirname "$0")/../tools/cli_lib.sh"
. "$(dirname "$0")/../tools/recording_lib.sh"
DAEMON=$3
BAGS="$WORK/bags"
make_recordings /usr/bin/python3 "${DAO_MAKE_BAGS:?}" "$BAGS"

# the reference: the PNG frames with camera.json beside them (no temporal filter on PNGs)
png_reference "$BAGS"
for comp in none bz2 lz4; do
	same_as_png "$comp" "$BAGS/d16_$comp.bag"
done
png_is "$WORK/lz4-ao/000004.png" "64 48 gray16"

# RealSense layout: counts of 0.1 mm, the same as the PNGs read with --depth-unit 0.0001;
# a plain ROS bag's 16UC1 counts take --depth-unit (and ?unit=) like PNGs
unit_as_png "$BAGS" "$BAGS/realsense.bag"
unit_as_png "$BAGS" "$BAGS/d16_bz2.bag?unit=0.0001"
expect_exit 0 "--depth-unit on a bag" -- "$DEPTHAO" process --input "$BAGS/d16_bz2.bag" \
	--depth-unit 0.0001 --depth-temporal 0 --frames 1 --ao-out "$WORK/unit-opt" --quiet
cmp -s "$WORK/unit-opt/000000.png" "$WORK/png-unit/000000.png" || fail "--depth-unit 0.0001 on a bag"

# two depth topics: refused with the candidates; ?topic= picks one (--start/--frames by index)
process_fails "$BAGS/two.bag" \
	"choose one with ?topic=NAME: /cam1/depth/image_raw (16UC1), /cam2/depth/image_raw (16UC1)"
expect_exit 0 "?topic=" -- "$DEPTHAO" process --input "bag:$BAGS/two.bag?topic=/cam2/depth/image_raw" \
	--start 2 --frames 2 --depth-temporal 0 --ao-out "$WORK/cam2" --quiet
[ "$(ls "$WORK/cam2" | tr '\n' ' ')" = "000002.png 000003.png " ] ||
	fail "?topic= with --start 2 --frames 2 wrote: $(ls "$WORK/cam2" | tr '\n' ' ')"
# cam1 has the PNGs' frames (and no camera_info: given here), cam2 other ones
expect_exit 0 "?topic= cam1" -- "$DEPTHAO" process --input "$BAGS/two.bag?topic=/cam1/depth/image_raw" \
	--start 2 --frames 2 --depth-temporal 0 --intrinsics 60,61,31.5,23.25 --ao-out "$WORK/cam1" --quiet
frames_as_png "?topic= cam1 --start 2 --frames 2" "$WORK/cam1" 000002 000003
cmp -s "$WORK/cam1/000002.png" "$WORK/cam2/000002.png" && fail "?topic=: cam1 and cam2 gave the same AO"

# a CameraInfo with distortion and a P other than K: P's intrinsics (the rectified image's,
# as ROS's image_geometry), a warning that the depth must be rectified
expect_exit 0 "distorted bag" -- "$DEPTHAO" process --input "$BAGS/distorted.bag" --depth-temporal 0 \
	--ao-out "$WORK/dist-ao"
grep -q "intrinsics from the source: fx 45.00 fy 46.50 cx 30.00 cy 22.00" "$WORK/err" ||
	fail "distorted: intrinsics not from P: $(cat "$WORK/err")"
grep -q "has lens distortion: the depth must be rectified" "$WORK/err" ||
	fail "distorted: no warning: $(cat "$WORK/err")"
expect_exit 0 "PNG frames with P's intrinsics" -- "$DEPTHAO" process --input "$BAGS/png" \
	--intrinsics 45,46.5,30,22 --ao-out "$WORK/png-p" --quiet
for f in 000000 000001 000002 000003 000004; do
	cmp -s "$WORK/dist-ao/$f.png" "$WORK/png-p/$f.png" || fail "distorted: AO $f differs from --intrinsics of P"
done
cmp -s "$WORK/dist-ao/000000.png" "$WORK/png-ao/000000.png" && fail "distorted: P's intrinsics changed nothing"

# a truncated bag: an error naming the file and the byte
head -c 20000 "$BAGS/d16_none.bag" >"$WORK/cut.bag"
process_fails "$WORK/cut.bag" "$WORK/cut.bag: byte 13: "
grep -q "byte 13: .*truncated" "$WORK/err" || fail "truncated bag: $(cat "$WORK/err")"

# the daemon: a .bag as its source, outputs equal to depthao process
"$DAEMON" --source "$BAGS/d16_lz4.bag" --playback manual --set ao.depth-temporal=0 \
	--sink ao=images:"$WORK/d-ao" --stream ao=ao 2>"$WORK/dlog" || fail "daemon: $(cat "$WORK/dlog")"
[ "$(ls "$WORK/d-ao" 2>/dev/null | wc -l)" -eq 5 ] || fail "daemon: $(ls "$WORK/d-ao" 2>/dev/null | wc -l) AO files"
for f in 000000 000004; do
	cmp -s "$WORK/d-ao/$f.png" "$WORK/png-ao/$f.png" || fail "daemon: AO $f differs from the PNG run"
done
finish
