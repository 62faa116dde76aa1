#!/bin/sh
# SPDX-License-Identifier: MIT
# A slow sink does not hold the others back (drops counted, memory flat); a source that
# goes away (-ENODEV) is reopened and the daemon keeps running.
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
[ "$(stat_of "$SOCK" frames_processed)" -ge 40 ] || fail "frames did not keep flowing"
stop_daemon || fail "exit status"

# a source that cannot be opened: retried with backoff, logged, sinks stay up
start_daemon "$WORK/log3" --source "oni:$WORK/missing.oni" --sink fast=y4m:/dev/null \
	--set source.retry_initial_ms=50 --set source.retry_max_ms=200 --socket "$SOCK"
wait_for 10 sh -c "[ \$('$DEPTHAO' ctl --socket '$SOCK' stats | '$JSON_GET' stats.source_failures) -ge 4 ]" ||
	fail "no retries: $(cat "$WORK/log3")"
grep -q "missing.oni.*retrying in" "$WORK/log3" || fail "retry not logged"
stop_daemon || fail "exit status"
finish
