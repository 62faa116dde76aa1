#!/bin/sh
# SPDX-License-Identifier: MIT
# Sinks that fail: a full disk, a quota, a read-only filesystem or a reader that went
# away stop that sink for good with one clear line; other errors are retried with a
# growing backoff and logged at a limited rate with a count; counters count only what a
# sink took.  Floods of control requests do not flood the log.
. "$(dirname "$0")/daemon_lib.sh"
export DEPTHAO_PLUGIN_PATH="$TEST_PLUGINS"
SOCK="$WORK/ctl.sock"
SOCK_CLIENT="$TEST_PLUGINS/sock_client"

# sink_stat NAME KEY: one value of sink NAME in 'depthao ctl stats'
sink_stat() {
	i=0
	while :; do
		n=$(stat_of "$SOCK" "sinks.$i.name") || return 1
		[ "$n" = "$1" ] && break
		i=$((i + 1))
	done
	stat_of "$SOCK" "sinks.$i.$2"
}

opens() {
	grep -c OPEN "$1" 2>/dev/null || true
}

written() {
	grep -cv OPEN "$1" 2>/dev/null || true
}

# 1. Permanent errors: each stops its sink after one error line; never reopened; the
# frames before the error are counted, the daemon and the other sinks go on.
start_daemon "$WORK/log1" --source "testsrc:fps=100" --socket "$SOCK" --stats-interval 0 \
	--sink full=slowsink:0,fail=ENOSPC,after=3,out="$WORK/full.txt" \
	--sink quota=slowsink:0,fail=EDQUOT,out="$WORK/quota.txt" \
	--sink ro=slowsink:0,open_fail=EROFS \
	--sink dev=y4m:/dev/full --sink ok=y4m:/dev/null
wait_for 10 test -S "$SOCK" || fail "no socket: $(cat "$WORK/log1")"
sleep 2
kill -0 "$PID" || fail "the daemon died"
for s in full quota ro dev; do
	[ "$(sink_stat $s state)" = stopped ] || fail "sink $s: state $(sink_stat $s state), expected stopped"
	[ "$(grep -c "sink $s (.*) stopped" "$WORK/log1")" -eq 1 ] ||
		fail "sink $s: $(grep -c "sink $s " "$WORK/log1") lines, expected one: $(grep "sink $s " "$WORK/log1")"
done
sink_stat full stop_reason | grep -q "No space left on device" || fail "full: reason '$(sink_stat full stop_reason)'"
[ "$(sink_stat full stop_code)" = ENOSPC ] || fail "full: code '$(sink_stat full stop_code)'"
sink_stat dev stop_reason | grep -q "No space left on device" || fail "dev: reason '$(sink_stat dev stop_reason)'"
sink_stat quota stop_reason | grep -qi "quota" || fail "quota: reason '$(sink_stat quota stop_reason)'"
sink_stat ro stop_reason | grep -qi "read-only" || fail "ro: reason '$(sink_stat ro stop_reason)'"
grep "sink full (" "$WORK/log1" | grep -q "free space on that filesystem" || fail "no advice: $(grep 'sink full' "$WORK/log1")"
grep "sink dev (y4m:/dev/full) stopped" "$WORK/log1" | grep -q "/dev/full" || fail "the path is not named"
[ "$(opens "$WORK/full.txt")" -eq 1 ] || fail "full: opened $(opens "$WORK/full.txt") times"
[ "$(opens "$WORK/quota.txt")" -eq 1 ] || fail "quota: opened $(opens "$WORK/quota.txt") times"
[ "$(sink_stat full frames_out)" -eq 3 ] || fail "full: frames_out $(sink_stat full frames_out), it took 3"
[ "$(written "$WORK/full.txt")" -eq 3 ] || fail "full: the sink took $(written "$WORK/full.txt") frames"
[ "$(sink_stat quota frames_out)" -eq 0 ] || fail "quota: frames_out $(sink_stat quota frames_out)"
[ "$(sink_stat ok state)" = running ] || fail "the good sink: $(sink_stat ok state)"
o1=$(sink_stat ok frames_out)
sleep 0.5
[ "$(sink_stat ok frames_out)" -gt "$o1" ] || fail "the good sink stopped writing"
stop_daemon || fail "exit status: $(cat "$WORK/log1")"

# 2. y4m on stdout whose reader goes away (EPIPE): that sink stops, the PNG sink goes on
mkfifo "$WORK/fifo"
head -c 1000 <"$WORK/fifo" >/dev/null &
start_daemon "$WORK/log2" --source "testsrc:fps=100" --socket "$SOCK" --stats-interval 0 \
	--sink out=y4m:- --sink png=images:"$WORK/png" --set sink.png.queue=64 >"$WORK/fifo"
wait_for 10 test -S "$SOCK" || fail "no socket: $(cat "$WORK/log2")"
wait_for 10 sh -c "[ \"\$('$DEPTHAO' ctl --socket '$SOCK' stats | '$JSON_GET' stats.sinks.0.state)\" = stopped ]" ||
	fail "y4m:- after its reader left: $(sink_stat out state) $(cat "$WORK/log2")"
sink_stat out stop_reason | grep -qi "broken pipe" || fail "reason '$(sink_stat out stop_reason)'"
[ "$(sink_stat out stop_code)" = EPIPE ] || fail "code '$(sink_stat out stop_code)'"
sleep 1
[ "$(grep -c "sink out" "$WORK/log2")" -le 2 ] || fail "y4m:- logged $(grep -c "sink out" "$WORK/log2") lines: $(cat "$WORK/log2")"
[ "$(sink_stat out opens)" -eq 1 ] || fail "y4m:- reopened: $(sink_stat out opens) opens"
p1=$(sink_stat png frames_out)
sleep 0.5
[ "$(sink_stat png frames_out)" -gt "$p1" ] || fail "the PNG sink stopped with the pipe"
stop_daemon || fail "exit status after EPIPE: $(cat "$WORK/log2")"

# 3. Other errors: closed, reopened after 0.5, 1, 2, 4 s...; three sinks failing on every
# write at 100 frames/s log a handful of lines (3,471 in 20 s before), with counts.
t3=$(date +%s.%N) # no attempt before this
start_daemon "$WORK/log3" --source "testsrc:fps=100" --socket "$SOCK" --stats-interval 0 \
	--sink e1=slowsink:0,fail=EIO,out="$WORK/e1.txt" \
	--sink e2=slowsink:0,fail=EACCES,after=2,out="$WORK/e2.txt" \
	--sink e3=slowsink:0,open_fail=ENOENT --sink ok=y4m:/dev/null
wait_for 10 test -S "$SOCK" || fail "no socket: $(cat "$WORK/log3")"
sleep 5
kill -0 "$PID" || fail "the daemon died"
for s in e1 e2 e3; do
	[ "$(sink_stat $s state)" = retrying ] || fail "sink $s: state $(sink_stat $s state)"
	errs=$(sink_stat $s errors)
	# the first failure at the start or later, the retries at least 0.5, 1.5, 3.5, 7.5 s
	# after it (a loaded host only delays them): at least 2 in the 5 s slept, at most
	# as many as those times fit in the seconds since before the start (under ASan on a
	# busy host the readings come late enough for a fifth)
	el=$(awk -v a="$t3" -v b="$(date +%s.%N)" 'BEGIN { print b - a }')
	most=$(awk -v t="$el" 'BEGIN { n = split("0 0.5 1.5 3.5 7.5 15.5 31.5", c, " ");
		k = 0; for (i = 1; i <= n; i++) if (c[i] <= t) k++; print k }')
	[ "$errs" -ge 2 ] && [ "$errs" -le "$most" ] ||
		fail "sink $s: $errs failures in ${el} s, expected 2..$most (backoff)"
	lines=$(grep -c "sink $s " "$WORK/log3")
	[ "$lines" -le 3 ] || fail "sink $s: $lines log lines in 5 s: $(grep "sink $s " "$WORK/log3")"
done
# every open is followed by one failed write: between two readings of the error count
# (the sink retries meanwhile, at 7.5 s, on a loaded host) the opens lie within them
e_before=$(sink_stat e1 errors)
o=$(opens "$WORK/e1.txt")
e_after=$(sink_stat e1 errors)
[ "$o" -ge "$e_before" ] && [ "$o" -le $((e_after + 1)) ] ||
	fail "e1: opens $o, errors $e_before then $e_after"
[ "$(sink_stat e1 frames_out)" -eq 0 ] || fail "e1 counted $(sink_stat e1 frames_out) frames it never took"
# two good writes per open: the counter is exactly what the sink took
[ "$(sink_stat e2 frames_out)" = "$(written "$WORK/e2.txt")" ] ||
	fail "e2: frames_out $(sink_stat e2 frames_out), the sink took $(written "$WORK/e2.txt")"
grep "sink e1 " "$WORK/log3" | head -n 1 | grep -q "retrying in 0.5 s" || fail "e1: $(grep 'sink e1' "$WORK/log3")"
stop_daemon || fail "exit status: $(cat "$WORK/log3")"
grep -q "sink e1: [0-9]* more like this not logged" "$WORK/log3" ||
	fail "the held-back count is not reported at the end: $(grep 'sink e1' "$WORK/log3")"

# 4. a flood of accepted 'set' requests logs a few lines, not one per request
start_daemon "$WORK/log4" --source "testsrc:fps=50" --socket "$SOCK" --stats-interval 0 \
	--sink ok=y4m:/dev/null
wait_for 10 test -S "$SOCK" || fail "no socket: $(cat "$WORK/log4")"
ok=$("$SOCK_CLIENT" many "$SOCK" 2000 '{"cmd":"set","key":"radius","value":"0.3"}') || fail "set flood"
[ "$ok" = 2000 ] || fail "$ok of 2000 sets answered ok"
lines=$(grep -c "control: radius = 0.3" "$WORK/log4")
[ "$lines" -ge 1 ] && [ "$lines" -le 10 ] || fail "2000 sets logged $lines lines"
stop_daemon || fail "exit status: $(cat "$WORK/log4")"
grep -q "more like this not logged" "$WORK/log4" || fail "the held-back sets are not counted: $(cat "$WORK/log4")"
finish
