#!/bin/sh
# SPDX-License-Identifier: MIT
# depthao eval --depth --real on the Kinect recording as a stream (the stream defaults:
# the temporal depth filter, the noise measured in full on frames 0, 1, 2, 4, 8): the
# 16 px tile residual of every frame stays under 1.6 mm. Frames 5-7 were 2.1-2.6 mm
# (about 1 mm on the others) when one cell's noise, measured on frame 4 with half of its
# blocks inside one disparity band, read half the band step and was reused: the far wall
# came out in stairs (docs/depth-accuracy.md); 0.92-1.25 mm since.
# usage: test_cli_eval_depth_real.sh DEPTHAO PNG_INFO
. "$(dirname "$0")/cli_lib.sh"

DATA=${DAO_SHARED_DATA:-../shared/data}
if [ ! -r "$DATA/oni/3DJ_test.oni" ]; then
	echo "SKIP: $DATA/oni/3DJ_test.oni not found (../shared/data is not beside the project)"
	exit 77
fi
# the smallest synthetic part (one clean plane) beside the real frames
expect_exit 0 "eval --depth --real" -- "$DEPTHAO" eval --depth --real --data "$DATA" \
	--scenes plane --sensors clean --set tune
# the stream's table: the rows after its heading; column 9 is the tile residual
# "raw / depthao / ref" (mm)
sed -n '/as a stream/,$p' "$WORK/out" | grep '^| kinect-oni-' >"$WORK/stream" ||
	fail "no stream table: $(cat "$WORK/out")"
[ "$(wc -l <"$WORK/stream")" -eq 12 ] || fail "stream rows: $(cat "$WORK/stream")"
awk -F'|' '{ split($9, t, "/"); f = t[2] + 0;
	if (!(f > 0.3 && f < 1.6)) { print $2 ": tile residual " f " mm"; bad = 1 } }
	END { exit bad }' "$WORK/stream" >"$WORK/bad" ||
	fail "the stream's filtered depth on the Kinect's planes: $(cat "$WORK/bad")"
finish
