#!/bin/sh
# SPDX-License-Identifier: MIT
# A slow sink does not hold the others back (drops counted, memory flat); a source that
# goes away (-ENODEV) is reopened and the daemon keeps running; a device that cannot be
# opened is waited for, a missing file is an error at once; a corrupt frame of a looping
# recording is skipped.
. "$(dirname "$0")/daemon_lib.sh"
export DEPTHAO_PLUGIN_PATH="$TEST_PLUGINS"

SOCK="$WORK/ctl.sock"
start_daemon "$WORK/log" --source "testsrc:fps=150" --sink fast=y4m:/dev/null \
	--sink slow=slowsink:40 --set sink.slow.queue=4 --socket "$SOCK" --stats-interval 0
wait_for 10 test -S "$SOCK" || fail "no socket: $(cat "$WORK/log")"
sleep 1
rss1=$(rss_kb "$PID")
n1=$(stat_of "$SOCK" frames_processed)
sleep 3
rss2=$(rss_kb "$PID")
n2=$(stat_of "$SOCK" frames_processed)
fast=$(stat_of "$SOCK" sinks.0.frames_out)
slow=$(stat_of "$SOCK" sinks.1.frames_out)
slow_dropped=$(stat_of "$SOCK" sinks.1.frames_dropped)
fast_dropped=$(stat_of "$SOCK" sinks.0.frames_dropped)
echo "processed $n1 -> $n2; fast sink $fast out ($fast_dropped dropped); slow sink $slow out ($slow_dropped dropped); RSS $rss1 -> $rss2 kB"
[ $((n2 - n1)) -ge 150 ] || fail "pipeline rate $(((n2 - n1) / 3)) fps with a slow sink (expected ~150)"
[ "$fast_dropped" -le 2 ] || fail "the fast sink dropped $fast_dropped frames"
[ "$fast" -ge $((n2 - 5)) ] || fail "the fast sink is behind: $fast of $n2"
[ "$slow_dropped" -ge 100 ] || fail "the slow sink's drops were not counted ($slow_dropped)"
[ $((rss2 - rss1)) -le 4096 ] || fail "RSS grew by $((rss2 - rss1)) kB over $((n2 - n1)) frames"
stop_daemon || fail "exit status"

# a sink stuck in a write: SIGTERM still ends the daemon within a second (exit 1, logged)
start_daemon "$WORK/log-stuck" --source "testsrc:fps=50" --sink stuck=slowsink:5000 --stats-interval 0
sleep 1
if stop_daemon; then fail "exit 0 with a stuck sink"; fi
grep -q "sink stuck did not finish within the stop deadline" "$WORK/log-stuck" ||
	fail "stuck sink not reported: $(cat "$WORK/log-stuck")"

# the source is unplugged every 20 frames: reopened each time, the daemon stays up
start_daemon "$WORK/log2" --source "testsrc:fps=200,fail_after=20" --sink fast=y4m:/dev/null \
	--socket "$SOCK" --set source.retry_initial_ms=50
wait_for 10 test -S "$SOCK" || fail "no socket: $(cat "$WORK/log2")"
wait_for 10 sh -c "[ \$('$DEPTHAO' ctl --socket '$SOCK' stats | '$JSON_GET' stats.source_opens) -ge 3 ]" ||
	fail "the source was not reopened: $(cat "$WORK/log2")"
kill -0 "$PID" || fail "the daemon exited on source loss"
grep -q "lost: testsrc: unplugged after 20 frames; reopening" "$WORK/log2" || fail "loss not logged: $(cat "$WORK/log2")"
# (waited for: read at the moment of the third open it was below 40 in 3 runs of 4 on a
# host at load 24, where the input queue drops about a quarter of the 200 fps source)
wait_for 10 sh -c "[ \$('$DEPTHAO' ctl --socket '$SOCK' stats | '$JSON_GET' stats.frames_processed) -ge 40 ]" ||
	fail "frames did not keep flowing: $(stat_of "$SOCK" frames_processed) processed"
stop_daemon || fail "exit status"

# a device that cannot be opened: retried with backoff, logged (a few lines), sinks stay up
start_daemon "$WORK/log3" --source "testsrc:fps=0" --sink fast=y4m:/dev/null \
	--set source.retry_initial_ms=50 --set source.retry_max_ms=200 --socket "$SOCK"
wait_for 10 sh -c "[ \$('$DEPTHAO' ctl --socket '$SOCK' stats | '$JSON_GET' stats.source_failures) -ge 8 ]" ||
	fail "no retries: $(cat "$WORK/log3")"
grep -q "testsrc: bad options.*retrying in" "$WORK/log3" || fail "retry not logged"
[ "$(grep -c "retrying in" "$WORK/log3")" -le 5 ] || fail "every retry logged: $(cat "$WORK/log3")"
stop_daemon || fail "exit status"
grep -q "source: [0-9]* more like this not logged" "$WORK/log3" || fail "held-back retries not counted: $(cat "$WORK/log3")"

# a source file that is not there: an error at once, not retried forever
for uri in "$WORK/missing.oni" "oni:$WORK/missing" "images:$WORK/no-such-dir" "$WORK/no-such-dir/"; do
	t0=$(date +%s%N)
	status=0
	timeout 10 "$DAEMON" --source "$uri" --sink fast=y4m:/dev/null --stats-interval 0 \
		2>"$WORK/log-missing" || status=$?
	ms=$((($(date +%s%N) - t0) / 1000000))
	echo "missing source $uri: exit $status in $ms ms"
	[ "$status" -ne 0 ] && [ "$status" -ne 124 ] || fail "missing source $uri: exit $status"
	[ "$ms" -le 1000 ] || fail "missing source $uri: $ms ms to exit"
	grep -q "must be there when depthaod starts" "$WORK/log-missing" ||
		fail "missing source $uri: $(cat "$WORK/log-missing")"
done

# a looping directory of depth PNGs with a corrupt one: it is skipped (with a warning that
# does not repeat per frame), the frames after it keep coming, the source is not reopened
"$DEPTHAO" synth --scene spheres --out "$WORK/synth" --frames 4 --rays 1 >/dev/null 2>&1 ||
	fail "synth"
truncate -s 60 "$WORK/synth/spheres/depth/0001.png"
start_daemon "$WORK/log4" --source "images:$WORK/synth/spheres/depth" --loop --playback manual \
	--sink png=images:"$WORK/corrupt-out" --sink null=y4m:/dev/null --socket "$SOCK" --stats-interval 0
wait_for 10 test -S "$SOCK" || fail "no socket: $(cat "$WORK/log4")"
wait_for 30 sh -c "[ \$('$DEPTHAO' ctl --socket '$SOCK' stats | '$JSON_GET' stats.source_bad_frames) -ge 5 ]" ||
	fail "the bad frame was not skipped repeatedly: $(cat "$WORK/log4")"
[ "$(stat_of "$SOCK" source_opens)" -eq 1 ] || fail "the source was reopened $(stat_of "$SOCK" source_opens) times"
b=$(stat_of "$SOCK" source_bad_frames)
n=$(stat_of "$SOCK" frames_in)
[ "$n" -ge $((3 * b - 3)) ] || fail "$n frames read for $b bad ones (3 good per loop)"
stop_daemon || fail "exit status"
for f in 000000 000002 000003; do
	[ -f "$WORK/corrupt-out/$f.png" ] || fail "frame $f missing: $(ls "$WORK/corrupt-out")"
done
[ -e "$WORK/corrupt-out/000001.png" ] && fail "a frame for the corrupt PNG"
grep -q "a frame cannot be read and is skipped: .*0001.png" "$WORK/log4" || fail "no warning: $(cat "$WORK/log4")"
[ "$(grep -c "is skipped" "$WORK/log4")" -le 5 ] || fail "the skip is logged per frame"

# a damaged JPEG colour frame (issue 38: it decoded silently): skipped with its
# libjpeg warning in the log, counted in source_bad_frames; the other frames go on
DATA=${DAO_SHARED_DATA:-$ROOT/../shared/data}
if [ -r "$DATA/oni/3DJ_test.oni" ] && command -v python3 >/dev/null; then
	python3 "$ROOT/tests/tools/oni_damage.py" "$DATA/oni/3DJ_test.oni" "$WORK/zero.oni" zero
	start_daemon "$WORK/log5" --source "$WORK/zero.oni" --loop --playback manual \
		--sink ov=images:"$WORK/jpeg-out" --stream ov=overlay --socket "$SOCK" --stats-interval 0
	wait_for 10 test -S "$SOCK" || fail "no socket: $(cat "$WORK/log5")"
	wait_for 30 sh -c "[ \$('$DEPTHAO' ctl --socket '$SOCK' stats | '$JSON_GET' stats.source_bad_frames) -ge 2 ]" ||
		fail "the damaged JPEG frame was not counted: $(cat "$WORK/log5")"
	b=$(stat_of "$SOCK" source_bad_frames)
	n=$(stat_of "$SOCK" frames_in)
	[ "$n" -ge $((11 * b - 11)) ] || fail "$n frames read for $b damaged ones (11 good per loop)"
	stop_daemon || fail "exit status"
	grep -q "is skipped: frame 0 of 'Image1' is corrupt: damaged JPEG data: Corrupt JPEG data" \
		"$WORK/log5" || fail "no JPEG warning: $(cat "$WORK/log5")"
else
	echo "note: no $DATA/oni/3DJ_test.oni or python3; the JPEG part was skipped"
fi
finish
