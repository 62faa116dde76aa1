#!/bin/sh
# SPDX-License-Identifier: MIT
# process on real sensor frames from ../shared/data, with their camera files and units.
. "$(dirname "$0")/cli_lib.sh"

DATA=${DAO_SHARED_DATA:-../shared/data}
if [ ! -r "$DATA/redwood_open3d/depth_00000.png" ]; then
	echo "SKIP: $DATA/redwood_open3d not found (../shared/data is not beside the project)"
	exit 77
fi
expect_exit 0 "redwood" -- "$DEPTHAO" process --input "$DATA/redwood_open3d/depth_00000.png" \
	--intrinsics-file "$DATA/redwood_open3d/camera_primesense.json" \
	--ao-out "$WORK/redwood-ao.png" --shaded-out "$WORK/redwood.png"
png_is "$WORK/redwood-ao.png" "640 480 gray16"
expect_exit 0 "tum" -- "$DEPTHAO" process --input "$DATA/tum_open3d/TUM_depth.png" --depth-unit 0.0002 \
	--intrinsics 525,525,319.5,239.5 --ao-out "$WORK/tum-ao.png"
expect_exit 0 "realsense" -- "$DEPTHAO" process --input "$DATA/realsense_6dpose/depth.png" \
	--intrinsics-file "$DATA/realsense_6dpose/realsense_intrinsic.json" --shaded-out "$WORK/rs.png"
png_is "$WORK/rs.png" "640 480 rgb24"
# the 8-bit colour image beside the depth is refused with a clear message
expect_exit 1 "colour image as depth" -- "$DEPTHAO" process --input "$DATA/realsense_6dpose/rgb.png" \
	--intrinsics 622,622,315,250 --ao-out "$WORK/x.png"
grep -q "16-bit" "$WORK/err" || fail "colour image message: $(cat "$WORK/err")"
finish
