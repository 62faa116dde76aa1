#!/bin/sh
# SPDX-License-Identifier: MIT
# process on real sensor frames from ../shared/data, with their camera files and units,
# and what the AO says about them (ao_stats.c):
#  - the AO's statistics over the pixels with depth within bounds measured on this
#    project's build (524fa42, simd=auto on AVX-512; in brackets), with margins for
#    tuning that an all-ones, all-zeros, noise, transposed or mirrored AO fails;
#  - the AO correlates with a crude occlusion estimate from the depth alone;
#  - pixels without depth are exactly the invalid value (1);
#  - the kernels of this CPU agree with the scalar reference (simd=reference) within the
#    SIMD oracle's bound for the whole pipeline (a shift by one pixel is 7e-3);
#  - open planes stay open: on the open planar regions `depthao realcheck` finds (planes
#    with nothing in front of them within the AO radius), mean AO >= 0.99 (issue #15's
#    target for the false occlusion) and under 1 % of them darker than 0.9.
# usage: test_cli_real_data.sh DEPTHAO PNG_INFO AO_STATS
. "$(dirname "$0")/cli_lib.sh"
AO_STATS=$3

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
png_is "$WORK/tum-ao.png" "640 480 gray16"
expect_exit 0 "realsense" -- "$DEPTHAO" process --input "$DATA/realsense_6dpose/depth.png" \
	--intrinsics-file "$DATA/realsense_6dpose/realsense_intrinsic.json" --shaded-out "$WORK/rs.png" \
	--ao-out "$WORK/rs-ao.png"
png_is "$WORK/rs.png" "640 480 rgb24"
# the 8-bit colour image beside the depth is refused with a clear message
expect_exit 1 "colour image as depth" -- "$DEPTHAO" process --input "$DATA/realsense_6dpose/rgb.png" \
	--intrinsics 622,622,315,250 --ao-out "$WORK/x.png"
grep -q "16-bit" "$WORK/err" || fail "colour image message: $(cat "$WORK/err")"

calc() { awk "BEGIN { print $1 }"; }

# field KEY of a line of key=value
field() { echo "$1" | tr ' ' '\n' | sed -n "s/^$2=//p"; }

# within NAME STATS KEY LO HI: LO <= value <= HI
within() {
	v=$(field "$2" "$3")
	[ -n "$v" ] || { fail "$1: no $3 in '$2'"; return; }
	awk -v v="$v" -v lo="$4" -v hi="$5" 'BEGIN { exit !(v >= lo && v <= hi) }' ||
		fail "$1: $3 = $v outside [$4, $5] ($2)"
}

# content NAME AO DEPTH UNIT FOCAL MEAN P05 P50 CORR [MASK]: the statistics of one frame
# against its measured mean, 5th and 50th percentiles and correlation
content() {
	name=$1 ao=$2 depth=$3 unit=$4 focal=$5 mean=$6 p05=$7 p50=$8 corr=$9
	shift 9
	stats=$("$AO_STATS" "$ao" "$depth" "$unit" "$focal" "$@") || { fail "$name: ao_stats"; return; }
	echo "$name: $stats"
	[ "$(field "$stats" holes_ok)" = 1 ] || fail "$name: a pixel without depth is not 1 ($stats)"
	within "$name" "$stats" mean "$(calc "$mean - 0.05")" "$(calc "$mean + 0.05")"
	within "$name" "$stats" p05 "$(calc "$p05 - 0.08")" "$(calc "$p05 + 0.08")"
	within "$name" "$stats" p50 "$(calc "$p50 - 0.05")" "$(calc "$p50 + 0.05")"
	within "$name" "$stats" p95 0.97 1
	within "$name" "$stats" lit 0 0.05
	# 0.7 of the measured correlation: 8 px to the side fails on realsense, mirroring on all
	within "$name" "$stats" corr "$(calc "$corr * 0.7")" 1
	if [ $# -gt 0 ]; then
		within "$name" "$stats" open 2000 1000000
		within "$name" "$stats" open_mean 0.99 1
		within "$name" "$stats" open_dark 0 0.01
	fi
}

# the open planar regions: at the default radius (0.5 m) in the Redwood frame; TUM's and
# the table top's are open at 0.25 m only, so their AO is checked there at that radius
expect_exit 0 "realcheck redwood" -- "$DEPTHAO" realcheck --data "$DATA" --frames redwood-0 \
	--masks-out "$WORK/open"
expect_exit 0 "realcheck tum, realsense" -- "$DEPTHAO" realcheck --data "$DATA" \
	--frames tum,realsense --radius 0.25 --masks-out "$WORK/open025"
expect_exit 0 "tum at 0.25 m" -- "$DEPTHAO" process --input "$DATA/tum_open3d/TUM_depth.png" \
	--depth-unit 0.0002 --intrinsics 525,525,319.5,239.5 --radius 0.25 --ao-out "$WORK/tum-ao025.png"
expect_exit 0 "realsense at 0.25 m" -- "$DEPTHAO" process --input "$DATA/realsense_6dpose/depth.png" \
	--intrinsics-file "$DATA/realsense_6dpose/realsense_intrinsic.json" --radius 0.25 \
	--ao-out "$WORK/rs-ao025.png"

#       name                  AO                      depth                         unit  focal  mean [measured] p05  p50  corr
content "redwood" "$WORK/redwood-ao.png" "$DATA/redwood_open3d/depth_00000.png" 0.001 525 \
	0.79 0.45 0.84 0.40 "$WORK/open/redwood-0-mask.png"       # [0.791 0.446 0.841 0.400]
content "tum" "$WORK/tum-ao.png" "$DATA/tum_open3d/TUM_depth.png" 0.0002 525 \
	0.83 0.44 0.90 0.34                                        # [0.825 0.438 0.897 0.345]
content "realsense" "$WORK/rs-ao.png" "$DATA/realsense_6dpose/depth.png" 0.001 622.439 \
	0.88 0.56 0.96 0.30                                        # [0.883 0.559 0.959 0.295]
content "tum R=0.25" "$WORK/tum-ao025.png" "$DATA/tum_open3d/TUM_depth.png" 0.0002 525 \
	0.89 0.53 0.98 0.34 "$WORK/open025/tum-mask.png"           # [0.895 0.528 0.976 0.335]
content "realsense R=0.25" "$WORK/rs-ao025.png" "$DATA/realsense_6dpose/depth.png" 0.001 622.439 \
	0.90 0.58 0.98 0.28 "$WORK/open025/realsense-mask.png"     # [0.904 0.584 0.979 0.278]

# this CPU's kernels against the scalar reference, the whole pipeline (the SIMD oracle's
# bound, test_simd_kernels.c PIPELINE_MAE; measured 4e-6 and 5e-6)
expect_exit 0 "redwood, reference" -- "$DEPTHAO" process --input "$DATA/redwood_open3d/depth_00000.png" \
	--intrinsics-file "$DATA/redwood_open3d/camera_primesense.json" --simd reference \
	--ao-out "$WORK/redwood-ref.png"
expect_exit 0 "realsense, reference" -- "$DEPTHAO" process --input "$DATA/realsense_6dpose/depth.png" \
	--intrinsics-file "$DATA/realsense_6dpose/realsense_intrinsic.json" --simd reference \
	--ao-out "$WORK/rs-ref.png"
for f in redwood rs; do
	d=$("$AO_STATS" --diff "$WORK/$f-ao.png" "$WORK/$f-ref.png") || fail "$f: ao_stats --diff"
	echo "$f against simd=reference: $d"
	within "$f against the reference" "$d" mae 0 5e-5
done
finish
