#!/bin/sh
# SPDX-License-Identifier: MIT
# [source] max_pixels (issue #16, item 9): a source larger than the limit is refused at
# open, before its frames are allocated, with a message naming the size and the limit;
# a recording over it stops the start (exit 1), a directory's image over it is skipped.
# images:DIR?keep=N (item 11): the disk holds at most N frames of the sink, across runs.
. "$(dirname "$0")/daemon_lib.sh"
SOCK="$WORK/ctl.sock"

# a recording (640x480) over a limit of 300000 pixels: a source file that cannot be opened
# at start is an error (exit 1 at once, nothing processed)
status=0
timeout 10 "$DAEMON" --source "$REC" --set source.max_pixels=300000 \
	--sink a=images:"$WORK/a" --stats-interval 0 2>"$WORK/log" || status=$?
[ "$status" -eq 1 ] || fail "exit status $status for a recording over the limit, expected 1"
grep -q "is 640x480 (307200 pixels), more than the limit of 300000 pixels" "$WORK/log" ||
	fail "limit not logged: $(cat "$WORK/log")"
[ "$(find "$WORK/a" -name '*.png' 2>/dev/null | wc -l)" -eq 0 ] || fail "frames written from a refused source"

# a directory of depth PNGs whose first image is over the limit (given as WxH)
mkdir "$WORK/pngs"
"$DEPTHAO" synth --scene plane --out "$WORK/s" --rays 1 >/dev/null
cp "$WORK/s/plane/depth.png" "$WORK/pngs/0001.png"
status=0
timeout 10 "$DAEMON" --source "images:$WORK/pngs" --set source.max_pixels=320x240 \
	--sink a=images:"$WORK/b" --stats-interval 0 2>"$WORK/log2" || status=$?
[ "$status" -eq 1 ] || fail "exit status $status for images over the limit, expected 1"
grep -q "0001.png' is 640x480 (307200 pixels), more than the limit of 76800 pixels" "$WORK/log2" ||
	fail "PNG limit not logged: $(cat "$WORK/log2")"
grep -q "must be there when depthaod starts and open" "$WORK/log2" || fail "no advice: $(cat "$WORK/log2")"

# the limit at the size: every frame of the recording goes through
"$DAEMON" --source "$REC" --playback manual --set source.max_pixels=640x480 \
	--sink a=images:"$WORK/c" --stream a=ao8 --stats-interval 0 --max-frames 5 2>"$WORK/log3" ||
	fail "run at the limit: $(cat "$WORK/log3")"
[ "$(ls "$WORK/c" | wc -l)" -eq 5 ] || fail "expected 5 frames at the limit: $(ls "$WORK/c")"

# keep=4 over 10 frames: the last 4; a second run numbers from 0 again and replaces them
# (an earlier run's files go first), foreign files stay
mkdir -p "$WORK/keep"
echo notes >"$WORK/keep/notes.txt"
for run in 1 2; do
	"$DAEMON" --source "$REC" --playback manual --sink "k=images:$WORK/keep?keep=4&compression=3" \
		--stream k=ao8 --stats-interval 0 --max-frames $((8 + 2 * run)) 2>"$WORK/log-keep" ||
		fail "keep run $run: $(cat "$WORK/log-keep")"
done
[ "$(ls "$WORK/keep" | tr '\n' ' ')" = "000008.png 000009.png 000010.png 000011.png notes.txt " ] ||
	fail "keep=4: $(ls "$WORK/keep" | tr '\n' ' ')"

# the key is checked like every other
printf '[source]\nuri = %s\nmax_pixels = 0\n[sink.a]\nuri = images:%s\n' "$REC" "$WORK/d" >"$WORK/bad.ini"
set +e
"$DAEMON" --check-config "$WORK/bad.ini" >"$WORK/out" 2>&1
st=$?
set -e
[ "$st" -eq 2 ] && grep -q "bad.ini:3: \[source\] max_pixels: '0' must be a pixel count or WxH" "$WORK/out" ||
	fail "bad max_pixels: $st $(cat "$WORK/out")"
finish
