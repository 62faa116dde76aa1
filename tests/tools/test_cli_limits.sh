#!/bin/sh
# SPDX-License-Identifier: MIT
# The pixel limit on decoded input (issue #16, item 9): a PNG or recording larger than
# --max-pixels (default 4096x4096) is refused with exit 1 and a message that names the
# file, its size and the limit, before anything of its size is allocated.
. "$(dirname "$0")/cli_lib.sh"
ZERO_PNG="python3 $(dirname "$0")/zero_png.py"
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
REC="$ROOT/recordings/spheres-rolling.oni"
CAM="--intrinsics 525,525,319.5,239.5"

# one row over 4096 x 4096: refused by default, without --max-pixels
$ZERO_PNG 16384 1025 "$WORK/over.png"
expect_exit 1 "16384x1025 by default" -- "$DEPTHAO" process --input "$WORK/over.png" $CAM --ao-out "$WORK/a.png"
grep -q "over.png' is 16384x1025 (16793600 pixels), more than the limit of 16777216 pixels" "$WORK/err" ||
	fail "default limit message: $(cat "$WORK/err")"
grep -q -- "--max-pixels" "$WORK/err" || fail "the message does not say how to raise the limit"
[ ! -e "$WORK/a.png" ] || fail "output written for a refused input"

# the file of issue #16: a header declaring 16384x16384 (here followed by only 64 rows);
# refused at the header, so it costs neither the 512 MB nor the time (bounded by ulimit -v)
$ZERO_PNG 16384 16384 "$WORK/huge.png" 64
set +e
(ulimit -v 400000 && "$DEPTHAO" process --input "$WORK/huge.png" $CAM --ao-out "$WORK/a.png") \
	>"$WORK/out" 2>"$WORK/err"
st=$?
set -e
[ "$st" -eq 1 ] || fail "16384x16384 header: exit $st, expected 1: $(cat "$WORK/err")"
grep -q "16384x16384 (268435456 pixels), more than the limit" "$WORK/err" ||
	fail "16384x16384 header message: $(cat "$WORK/err")"

# --max-pixels N or WxH moves the limit both ways
"$DEPTHAO" synth --scene plane --out "$WORK/s" --rays 1 >/dev/null
D=$WORK/s/plane/depth.png
expect_exit 1 "640x480 over 640x479" -- "$DEPTHAO" process --input "$D" $CAM --max-pixels 640x479 --ao-out "$WORK/a.png"
grep -q "640x480 (307200 pixels), more than the limit of 306560 pixels" "$WORK/err" ||
	fail "--max-pixels WxH message: $(cat "$WORK/err")"
expect_exit 0 "640x480 at 307200" -- "$DEPTHAO" process --input "$D" $CAM --max-pixels 307200 --ao-out "$WORK/a.png" --quiet
png_is "$WORK/a.png" "640 480 gray16"

# a directory: the first image sets up the run, a later one over the limit stops it, named
mkdir "$WORK/dir"
cp "$D" "$WORK/dir/a.png"
$ZERO_PNG 16384 1025 "$WORK/dir/b.png"
expect_exit 1 "directory with a huge second frame" -- "$DEPTHAO" process --input "$WORK/dir" $CAM --ao-out "$WORK/dir-out" --quiet
grep -q "b.png' is 16384x1025" "$WORK/err" || fail "directory message: $(cat "$WORK/err")"
expect_exit 1 "images: source over the limit" -- "$DEPTHAO" process --input "images:$WORK/dir" $CAM --max-pixels 1000 --ao-out "$WORK/img-out" --quiet
grep -q "a.png' is 640x480 (307200 pixels), more than the limit of 1000 pixels" "$WORK/err" ||
	fail "images: source message: $(cat "$WORK/err")"

# recordings: the depth stream's declared size, before its decode buffers exist
expect_exit 1 "recording over the limit" -- "$DEPTHAO" process --input "$REC" --max-pixels 300000 --ao-out "$WORK/rec" --quiet
grep -q "depth node '.*' is 640x480 (307200 pixels), more than the limit of 300000 pixels" "$WORK/err" ||
	fail "recording message: $(cat "$WORK/err")"
[ ! -e "$WORK/rec" ] || [ -z "$(ls "$WORK/rec")" ] || fail "frames written from a refused recording"
expect_exit 0 "recording at its size" -- "$DEPTHAO" process --input "$REC" --max-pixels 640x480 --frames 1 --ao-out "$WORK/rec" --quiet

# bad values are usage errors
for bad in 0 abc 640x 16385x2 20000x20000 -5 268435457; do
	expect_usage_error "--max-pixels $bad" -- "$DEPTHAO" process --input "$D" $CAM --max-pixels "$bad" --ao-out "$WORK/a.png"
done
finish
