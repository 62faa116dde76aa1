#!/bin/sh
# SPDX-License-Identifier: MIT
# How depthaod ends: at the natural end of a lossless run every queue drains completely,
# however long that takes; on SIGTERM it stops within a second and every sink, the
# recorder first of all, finalises what it has, whatever the processing thread is doing.
. "$(dirname "$0")/daemon_lib.sh"
export DEPTHAO_PLUGIN_PATH="$TEST_PLUGINS"
SOCK="$WORK/ctl.sock"

# final_out LOG SINK: frames the sink wrote, from the last statistics line of the log
final_out() {
	sed -n "s/.*stats: sink $2: \([0-9]*\) out.*/\1/p" "$1" | tail -n 1
}

# 1. Manual playback into a sink that takes 200 ms a frame: when the source ends, 8
# frames are still queued for it (1.6 s of work).  All 16 reach it, in order; exit 0.
"$DAEMON" --source "$REC" --playback manual --stats-interval 0 \
	--sink slow=slowsink:200,out="$WORK/slow.txt" --sink png=images:"$WORK/png" \
	2>"$WORK/log1" || fail "lossless run with a slow sink: exit $?: $(cat "$WORK/log1")"
[ "$(grep -cv OPEN "$WORK/slow.txt")" -eq 16 ] || fail "slow sink got $(grep -cv OPEN "$WORK/slow.txt") of 16 frames"
[ "$(grep -v OPEN "$WORK/slow.txt" | tr '\n' ' ')" = "0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 " ] ||
	fail "slow sink frames out of order: $(tr '\n' ' ' <"$WORK/slow.txt")"
[ "$(ls "$WORK/png" | wc -l)" -eq 16 ] || fail "png: $(ls "$WORK/png" | wc -l) of 16 files"
[ "$(final_out "$WORK/log1" slow)" = 16 ] || fail "stats of the slow sink: $(grep 'sink slow' "$WORK/log1")"
grep -q "deadline" "$WORK/log1" && fail "a deadline applied at the natural end: $(cat "$WORK/log1")"

# 2. The reporter's case: two PNG sinks and a y4m sink with the daemon pinned to one CPU
# that busy loops share.  Nothing is lost, nothing temporary is left, exit 0.
if command -v taskset >/dev/null && taskset -c 0 true 2>/dev/null; then
	busy_loops 4 0
	status=0
	taskset -c 0 "$DAEMON" --source "$REC" --playback manual --stats-interval 0 \
		--sink a=images:"$WORK/pa" --sink b=images:"$WORK/pb" --stream b=ao \
		--sink v=y4m:"$WORK/v.y4m" 2>"$WORK/log2" || status=$?
	stop_busy_loops
	[ "$status" -eq 0 ] || fail "pinned to a busy CPU: exit $status: $(cat "$WORK/log2")"
	[ "$(ls "$WORK/pa" | wc -l)" -eq 16 ] || fail "pinned: shaded $(ls "$WORK/pa" | wc -l) of 16"
	[ "$(ls "$WORK/pb" | wc -l)" -eq 16 ] || fail "pinned: ao $(ls "$WORK/pb" | wc -l) of 16"
	[ "$(grep -c FRAME "$WORK/v.y4m")" -eq 16 ] || fail "pinned: y4m $(grep -c FRAME "$WORK/v.y4m") of 16"
	find "$WORK" -name '*.tmp-*' | grep -q . && fail "pinned: temporary files left: $(find "$WORK" -name '*.tmp-*')"
else
	echo "note: no taskset; the pinned run was skipped"
fi

# 3. SIGTERM while the processing thread is inside a frame that takes seconds (reference
# kernels, many samples): the recorder still closes its file within the second, and the
# file holds every frame the recorder reported written.
start_daemon "$WORK/log3" --source "$REC" --loop --simd reference --slices 4 --steps 16 \
	--threads 1 --sink rec=oni:"$WORK/rec.oni" --stream rec=depth --socket "$SOCK" \
	--stats-interval 0
wait_for 10 test -S "$SOCK" || fail "no control socket: $(cat "$WORK/log3")"
wait_for 90 sh -c "[ \$('$DEPTHAO' ctl --socket '$SOCK' stats | '$JSON_GET' stats.sinks.0.frames_out) -ge 1 ]" ||
	fail "the recorder got no frame: $(cat "$WORK/log3")"
stop_daemon || fail "exit status after SIGTERM during a slow frame: $(cat "$WORK/log3")"
n=$(final_out "$WORK/log3" rec)
[ -n "$n" ] && [ "$n" -ge 1 ] || fail "no final statistics for the recorder: $(cat "$WORK/log3")"
"$DEPTHAO" process --input "$WORK/rec.oni" --ao-out "$WORK/rec-replay" --quiet ||
	fail "the recording is not readable after SIGTERM: $(ls -l "$WORK"; cat "$WORK/log3")"
[ "$(ls "$WORK/rec-replay" 2>/dev/null | wc -l)" = "$n" ] ||
	fail "the recording holds $(ls "$WORK/rec-replay" 2>/dev/null | wc -l) frames, the recorder wrote $n"

# 4. SIGTERM with a full queue in front of a slow sink (real time, 300 ms a frame, 8
# queued): within a second; what could not be written in the budget is dropped and
# counted, and the counters equal what the sink took.
start_daemon "$WORK/log4" --source "testsrc:fps=100" --stats-interval 0 \
	--sink slow=slowsink:300,out="$WORK/slow4.txt" --sink fast=y4m:/dev/null
wait_for 10 sh -c "[ \$(grep -cv OPEN '$WORK/slow4.txt' 2>/dev/null || echo 0) -ge 3 ]" ||
	fail "the slow sink wrote nothing: $(cat "$WORK/log4")"
stop_daemon || fail "exit status with a slow sink: $(cat "$WORK/log4")"
[ "$(final_out "$WORK/log4" slow)" = "$(grep -cv OPEN "$WORK/slow4.txt")" ] ||
	fail "slow sink: stats say $(final_out "$WORK/log4" slow) out, it took $(grep -cv OPEN "$WORK/slow4.txt")"
grep "stats: sink slow" "$WORK/log4" | tail -n 1 | grep -q "[1-9][0-9]* dropped" ||
	fail "frames left at the stop budget were not counted: $(grep 'sink slow' "$WORK/log4")"
finish
