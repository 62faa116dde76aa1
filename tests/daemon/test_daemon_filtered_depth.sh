#!/bin/sh
# SPDX-License-Identifier: MIT
# depthaod's filtered-depth stream: into the images sink (equal to depthao process
# --depth-out of the same recording), into the .oni recorder and the MCAP recorder
# (?filtered_depth=true), both read back by depthao's readers; the images sink's
# PNGs keep the recording's unit and its holes.
. "$(dirname "$0")/daemon_lib.sh"

N=5
"$DAEMON" --source "$REC" --playback manual --max-frames $N \
	--sink fd=images:"$WORK/fdepth" --stream fd=filtered-depth \
	--sink rec=oni:"$WORK/fdepth.oni" --stream rec=filtered-depth \
	--sink mc=mcap:"$WORK/rec.mcap?filtered_depth=true" --stream mc=ao \
	--sink ao=images:"$WORK/ao" --stream ao=ao 2>"$WORK/log" ||
	fail "exit status $?: $(cat "$WORK/log")"
[ "$(ls "$WORK/fdepth" | wc -l)" -eq $N ] || fail "filtered-depth: $(ls "$WORK/fdepth" | wc -l) files, expected $N"
"$PNG_INFO" "$WORK/fdepth/000002.png" | grep -q "^640 480 gray16 " ||
	fail "filtered-depth frames are not 16-bit: $("$PNG_INFO" "$WORK/fdepth/000002.png")"
grep -q "sink fd: .*(filtered-depth stream)" "$WORK/log" || fail "log: $(cat "$WORK/log")"

# the same frames through depthao process --depth-out: the same files, byte for byte
"$DEPTHAO" process --input "$REC" --frames $N --depth-out "$WORK/direct" --quiet ||
	fail "depthao process --depth-out"
for f in 000000 000002 000004; do
	cmp -s "$WORK/fdepth/$f.png" "$WORK/direct/$f.png" ||
		fail "filtered-depth $f differs from depthao process --depth-out"
done
# depth only ([ao] algorithm = none): the same depth
"$DAEMON" --source "$REC" --playback manual --max-frames 3 --algorithm none \
	--sink fd=images:"$WORK/none" --stream fd=filtered-depth 2>"$WORK/log-none" ||
	fail "algorithm none: exit $?: $(cat "$WORK/log-none")"
for f in 000000 000002; do
	cmp -s "$WORK/none/$f.png" "$WORK/fdepth/$f.png" ||
		fail "algorithm none: filtered-depth $f differs from the AO run's"
done
grep -q "error" "$WORK/log-none" && fail "algorithm none logged errors: $(cat "$WORK/log-none")"
# ... also beside a sink of the shaded stream: it gets nothing (said once), the depth goes on
"$DAEMON" --source "$REC" --playback manual --max-frames 3 --algorithm none \
	--sink sh=images:"$WORK/none-shaded" \
	--sink fd=images:"$WORK/none2" --stream fd=filtered-depth 2>"$WORK/log-none2" ||
	fail "algorithm none with a shaded sink: exit $?: $(cat "$WORK/log-none2")"
[ "$(ls "$WORK/none2" | wc -l)" -eq 3 ] || fail "algorithm none beside a shaded sink: $(ls "$WORK/none2" | wc -l) depth frames, expected 3: $(cat "$WORK/log-none2")"
[ "$(ls "$WORK/none-shaded" 2>/dev/null | wc -l)" -eq 0 ] || fail "shaded frames with algorithm none"
[ "$(grep -c "algorithm none computes no AO" "$WORK/log-none2")" -eq 1 ] ||
	fail "algorithm none with a shaded sink is not said once: $(cat "$WORK/log-none2")"
# the raw depth (filters off) has a hole wherever the filtered depth has one and more
"$DEPTHAO" process --input "$REC" --frames $N --algorithm none --prefilter none \
	--depth-temporal 0 --depth-min 0 --depth-max 60 --depth-out "$WORK/raw" --quiet
cmp -s "$WORK/raw/000002.png" "$WORK/fdepth/000002.png" &&
	fail "the filtered depth equals the raw depth: was it filtered?"

# read back with the filters off, the recordings give the counts the images sink wrote
replay() { # replay INPUT DIR
	"$DEPTHAO" process --input "$1" --algorithm none --prefilter none --depth-temporal 0 \
		--depth-min 0 --depth-max 60 --depth-out "$2" --quiet 2>"$WORK/log-replay" ||
		fail "replaying $1: $(cat "$WORK/log-replay")"
}
replay "$WORK/fdepth.oni" "$WORK/oni-back"
replay "$WORK/rec.mcap?topic=/depthao/depth_filtered" "$WORK/mcap-back"
for f in 000000 000002 000004; do
	cmp -s "$WORK/oni-back/$f.png" "$WORK/fdepth/$f.png" ||
		fail "the .oni recorder's frame $f is not the filtered depth"
done
# the recorder asks for the stream when it opens, at the first frame: it has it from the
# second frame on (as its point cloud)
n=0
for f in "$WORK"/mcap-back/*.png; do
	n=$((n + 1))
	cmp -s "$f" "$WORK/fdepth/$(printf '%06d' $n).png" ||
		fail "the MCAP recording's filtered depth $n differs from the images sink's"
done
[ $n -eq $((N - 1)) ] || fail "MCAP: $n filtered-depth frames, expected $((N - 1))"

# a sink that cannot take 16-bit depth says so and stays off; the others go on
"$DAEMON" --source "$REC" --playback manual --max-frames 2 \
	--sink y=y4m:"$WORK/x.y4m" --stream y=filtered-depth \
	--sink fd=images:"$WORK/fd2" --stream fd=filtered-depth 2>"$WORK/log2" ||
	fail "y4m with filtered-depth: exit $?: $(cat "$WORK/log2")"
grep -q "sink y .*y4m: cannot stream" "$WORK/log2" || fail "y4m refusal: $(cat "$WORK/log2")"
[ "$(ls "$WORK/fd2" | wc -l)" -eq 2 ] || fail "the images sink beside a refused one lost frames"
"$DAEMON" --check-config /dev/null --stream x=filtered-dept 2>"$WORK/log3" &&
	fail "a misspelt stream was accepted"
grep -q "filtered-depth" "$WORK/log3" || fail "the stream error does not list filtered-depth: $(cat "$WORK/log3")"
finish
