#!/bin/sh
# SPDX-License-Identifier: MIT
# depthaod on the bundled recording: PNG + y4m sinks, outputs equal to depthao process,
# finalised files, clean stop on SIGTERM.
. "$(dirname "$0")/daemon_lib.sh"

# the whole recording, lossless: every frame reaches every sink, then the daemon exits
"$DAEMON" --source "$REC" --playback manual --sink png=images:"$WORK/shaded" \
	--sink ao=images:"$WORK/ao" --stream ao=ao --sink y4m=y4m:"$WORK/out.y4m" \
	--sink rec=oni:"$WORK/depth.oni" --stream rec=depth \
	--stats-json "$WORK/stats.jsonl" 2>"$WORK/log" || fail "exit status $?: $(cat "$WORK/log")"
[ "$(ls "$WORK/shaded" | wc -l)" -eq 16 ] || fail "shaded: $(ls "$WORK/shaded" | wc -l) files, expected 16"
[ "$(ls "$WORK/ao" | wc -l)" -eq 16 ] || fail "ao: $(ls "$WORK/ao" | wc -l) files, expected 16"
"$PNG_INFO" "$WORK/ao/000003.png" | grep -q "640 480 gray16" || fail "ao frames are not gray16"
frames=$(grep -c FRAME "$WORK/out.y4m" || true)
[ "$frames" -eq 16 ] || fail "y4m: $frames FRAME markers, expected 16"
head -c 40 "$WORK/out.y4m" | grep -q "^YUV4MPEG2 W640 H480 F30:1" || fail "y4m header: $(head -c 40 "$WORK/out.y4m")"
find "$WORK" -name '*.tmp-*' -o -name '*.oni.*' | grep -q . && fail "temporary files left"
# the recorder's file replays the same depth: AO from it equals AO from the original
"$DEPTHAO" process --input "$WORK/depth.oni" --ao-out "$WORK/replay" --quiet ||
	fail "the recorded .oni does not replay"
cmp -s "$WORK/replay/000009.png" "$WORK/ao/000009.png" || fail "replayed recording gives other AO"
# the same frames through the library directly (depthao process): identical images
"$DEPTHAO" process --input "$REC" --ao-out "$WORK/direct-ao" --shaded-out "$WORK/direct" --quiet
for f in 000000 000007 000015; do
	cmp -s "$WORK/shaded/$f.png" "$WORK/direct/$f.png" || fail "shaded $f differs from depthao process"
	cmp -s "$WORK/ao/$f.png" "$WORK/direct-ao/$f.png" || fail "ao $f differs from depthao process"
done
# the last stats line counts every frame
tail -n 1 "$WORK/stats.jsonl" | "$JSON_GET" frames_processed | grep -qx 16 ||
	fail "stats: $(tail -n 1 "$WORK/stats.jsonl")"
tail -n 1 "$WORK/stats.jsonl" | "$JSON_GET" sinks.2.frames_out | grep -qx 16 || fail "y4m frames_out"

# SIGTERM while running (looping, real time): stops within a second, files finalised
start_daemon "$WORK/log2" --source "$REC" --loop --sink rec=oni:"$WORK/live.oni" --stream rec=depth \
	--sink png=images:"$WORK/live"
wait_for 10 test -f "$WORK/live/000003.png" || fail "no output while running: $(cat "$WORK/log2")"
stop_daemon || fail "exit status after SIGTERM"
"$DEPTHAO" process --input "$WORK/live.oni" --ao-out "$WORK/live-replay" --quiet ||
	fail "the .oni recorded until SIGTERM is not readable: $(cat "$WORK/log2")"
find "$WORK" -name '*.tmp-*' -o -name 'live.oni.*' | grep -q . && fail "temporary files left after SIGTERM"
grep -q "SIGTERM: stopping" "$WORK/log2" || fail "log: $(cat "$WORK/log2")"
finish
