#!/bin/sh
# SPDX-License-Identifier: MIT
# depthao eval --depth on one small case (boxes, Gaussian noise: no ray-traced sensor, a few
# seconds): the filtered depth beats the raw in the interior, the reference chain fills the
# holes, the picture is written; and the usage errors of its options.
. "$(dirname "$0")/cli_lib.sh"

# boxes_row: the boxes row of $WORK/out in $row, its interior MAE raw and depthao's (mm)
# in $raw and $filt
boxes_row() {
	row=$(grep '^| tune | boxes #0 | gaussian |' "$WORK/out") || fail "no row: $(cat "$WORK/out")"
	# | set | scene | input | raw / depthao / ref | red. | RMSE | edge | filled | flying | CPU |
	mae=$(echo "$row" | awk -F'|' '{ print $5 }')
	raw=$(echo "$mae" | awk -F'/' '{ print $1 + 0 }')
	filt=$(echo "$mae" | awk -F'/' '{ print $2 + 0 }')
}

expect_exit 0 "eval --depth" -- "$DEPTHAO" eval --depth --scenes boxes --sensors gaussian \
	--set tune --picture "$WORK/p.png" --picture-case boxes:gaussian
boxes_row
awk -v r="$raw" -v f="$filt" 'BEGIN { exit !(r > 0.5 && f > 0 && f < 0.8 * r) }' ||
	fail "interior MAE: filtered $filt mm not 20 % below raw $raw mm"
# Gaussian noise drops 2 % of the pixels: depthao fills none, the reference chain some
filled=$(echo "$row" | awk -F'|' '{ print $9 }')
case "$filled" in
" 0 (0 %) / "[1-9]*) ;;
*) fail "filled pixels '$filled': depthao should fill none, the reference some" ;;
esac
grep -q '^| tune | gaussian | 1 |' "$WORK/out" || fail "no summary row: $(cat "$WORK/out")"
png_is "$WORK/p.png" "1600 240 rgb24"

# --depth-fill 8: depthao fills Gaussian drop-outs now, nearly all within 1 cm (99 % measured
# on boxes); the summary's fill precision says so
expect_exit 0 "eval --depth --depth-fill 8" -- "$DEPTHAO" eval --depth --scenes boxes \
	--sensors gaussian --set tune --depth-fill 8
grep -q 'depth-fill 8, depth-temporal 0.80' "$WORK/out" || fail "no filter line: $(cat "$WORK/out")"
boxes_row
filled=$(echo "$row" | awk -F'|' '{ print $9 }' | awk '{ print $1 }')
prec=$(echo "$row" | awk -F'|' '{ print $9 }' | sed 's/^ *[0-9]* (\([0-9]*\) %).*/\1/')
awk -v n="$filled" -v p="$prec" 'BEGIN { exit !(n > 1000 && p >= 95) }' ||
	fail "depth-fill 8 on Gaussian drop-outs: $filled px filled, $prec % within 1 cm"
grep -q '^| tune | gaussian | 1 | .* | [0-9.]* % of [0-9]* (interior ' "$WORK/out" ||
	fail "fill precision in the summary: $(cat "$WORK/out")"

# parameter options change the filter and are named in its line: the prefilter off leaves
# the interior as noisy as raw (within 1 %), the default filter is 20 % below it (above)
expect_exit 0 "eval --depth --prefilter none" -- "$DEPTHAO" eval --depth --scenes boxes \
	--sensors gaussian --set tune --prefilter none
grep -q 'parameter options --prefilter none;' "$WORK/out" || fail "filter line: $(cat "$WORK/out")"
boxes_row
awk -v r="$raw" -v f="$filt" 'BEGIN { exit !(f > 0.99 * r && f < 1.01 * r) }' ||
	fail "--prefilter none: interior MAE $filt mm, raw $raw mm: the option did not reach the filter"

# the options' --name=value and --name_with_underscores forms reach the filter too
expect_exit 0 "eval --depth --depth-fill=8" -- "$DEPTHAO" eval --depth --scenes=plane \
	--sensors=clean --set=tune --depth_fill=8 --prefilter_iterations=1
grep -q 'depth-fill 8, depth-temporal 0.80; parameter options --prefilter_iterations=1;' \
	"$WORK/out" || fail "filter line: $(grep 'Depth filter' "$WORK/out")"

# --check: active stereo on the plane holds the 35 % bar with a wide margin (57 % measured);
# ToF on boxes does not hold its 20 % (3 %: the model's multipath bias, which no depth filter
# removes, docs/depth-accuracy.md) and --check says so with exit 1
expect_exit 0 "eval --depth --check active stereo" -- "$DEPTHAO" eval --depth --scenes plane \
	--sensors active-stereo --set tune --check
grep -q "^Bars .*: all hold" "$WORK/out" || fail "bars line: $(tail -n 1 "$WORK/out")"
expect_exit 1 "eval --depth --check tof" -- "$DEPTHAO" eval --depth --scenes boxes \
	--sensors tof --set tune --check
grep -q "^Bars .*: NOT all hold" "$WORK/out" || fail "bars line: $(tail -n 1 "$WORK/out")"
grep -q '^| tune | tof | 1 | .* | >= 20 % | 0/1 |' "$WORK/out" || fail "ToF summary: $(cat "$WORK/out")"

# a picture of a case the run does not hold is an error, not a silent no-op
expect_exit 1 "eval --depth picture not in the run" -- "$DEPTHAO" eval --depth --scenes plane \
	--sensors clean --set tune --picture "$WORK/q.png"
grep -q "picture-case" "$WORK/err" || fail "message: $(cat "$WORK/err")"
[ ! -e "$WORK/q.png" ] || fail "a picture of another case was written"

expect_usage_error "eval --depth frames 0" -- "$DEPTHAO" eval --depth --frames 0
expect_usage_error "eval --depth bad set" -- "$DEPTHAO" eval --depth --set train
expect_usage_error "eval --depth bad case" -- "$DEPTHAO" eval --depth --picture-case boxes
expect_usage_error "eval --depth bad sensor" -- "$DEPTHAO" eval --depth --sensors lidar
expect_usage_error "eval --depth fill too wide" -- "$DEPTHAO" eval --depth --depth-fill 65
expect_usage_error "eval --depth temporal 1" -- "$DEPTHAO" eval --depth --depth-temporal 1
expect_usage_error "eval --depth temporal word" -- "$DEPTHAO" eval --depth --depth-temporal x
expect_usage_error "eval --depth unknown option" -- "$DEPTHAO" eval --depth --radii 0.5
grep -q "unknown option '--radii'" "$WORK/err" || fail "message: $(cat "$WORK/err")"
expect_usage_error "eval --depth parameter out of range" -- "$DEPTHAO" eval --depth \
	--prefilter-iterations 9
grep -q "prefilter-iterations" "$WORK/err" || fail "message: $(cat "$WORK/err")"
expect_usage_error "eval --depth algorithm" -- "$DEPTHAO" eval --depth --algorithm gtao
grep -q "drop '--algorithm'" "$WORK/err" || fail "message: $(cat "$WORK/err")"
# an AO parameter would change nothing of the filtered depth: refused, not ignored
expect_usage_error "eval --depth AO parameter" -- "$DEPTHAO" eval --depth --radius 0.5
grep -q -- "--radius does not change the filtered depth" "$WORK/err" || fail "message: $(cat "$WORK/err")"
finish
