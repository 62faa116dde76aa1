#!/bin/sh
# SPDX-License-Identifier: MIT
# The control socket (stats, get/set, errors, permissions) and SIGHUP reloads.
. "$(dirname "$0")/daemon_lib.sh"

SOCK="$WORK/ctl.sock"
cat >"$WORK/a.ini" <<INI
[source]
uri = $REC
loop = true

[ao]
radius = 0.5

[sink.png]
uri = images:$WORK/out

[daemon]
socket = $SOCK
stats_interval = 0
INI
start_daemon "$WORK/log" -c "$WORK/a.ini"
wait_for 10 test -S "$SOCK" || fail "no control socket: $(cat "$WORK/log")"
[ "$(stat -c %a "$SOCK")" = 600 ] || fail "socket mode $(stat -c %a "$SOCK"), expected 600"
wait_for 10 test -f "$WORK/out/000002.png" || fail "no frames"

# another user cannot talk to it (the socket is 0600; the daemon also checks SO_PEERCRED)
if [ "$(id -u)" -eq 0 ] && command -v setpriv >/dev/null; then
	chmod 755 "$WORK"
	if setpriv --reuid=65534 --regid=65534 --clear-groups "$DEPTHAO" ctl --socket "$SOCK" stats \
		>"$WORK/other" 2>&1; then
		fail "another user got an answer: $(cat "$WORK/other")"
	fi
	grep -q "cannot connect" "$WORK/other" || fail "other user: $(cat "$WORK/other")"
else
	echo "note: not root or no setpriv; the other-user check was skipped"
fi

# stats parse and add up
in=$(stat_of "$SOCK" frames_in)
done_=$(stat_of "$SOCK" frames_processed)
out=$(stat_of "$SOCK" sinks.0.frames_out)
[ "$done_" -le "$in" ] || fail "processed $done_ > captured $in"
[ "$out" -le "$done_" ] || fail "sink wrote $out > processed $done_"
[ "$out" -ge 1 ] || fail "sink wrote nothing"
stat_of "$SOCK" sinks.0.latency_ms_p99 >/dev/null || fail "no latency in stats"

# a source is a stream: the temporal depth filter is on (0.8), and can be turned off
"$DEPTHAO" ctl --socket "$SOCK" get depth-temporal | "$JSON_GET" params.depth-temporal | grep -qx 0.8 ||
	fail "the temporal depth filter is not on by default in the daemon"
"$DEPTHAO" ctl --socket "$SOCK" set depth-temporal 0 >/dev/null || fail "set depth-temporal 0"
"$DEPTHAO" ctl --socket "$SOCK" get depth-temporal | "$JSON_GET" params.depth-temporal | grep -qx 0 ||
	fail "depth-temporal 0 did not stick"

# set/get round trip; a bad value and a bad command are errors, and the daemon carries on
"$DEPTHAO" ctl --socket "$SOCK" set radius 0.25 >/dev/null || fail "set radius"
"$DEPTHAO" ctl --socket "$SOCK" get radius | "$JSON_GET" params.radius | grep -qx 0.25 || fail "get radius"
if "$DEPTHAO" ctl --socket "$SOCK" set radius -3 >"$WORK/r" 2>&1; then fail "set radius -3 accepted"; fi
"$JSON_GET" error <"$WORK/r" | grep -q radius || fail "bad value reply: $(cat "$WORK/r")"
if "$DEPTHAO" ctl --socket "$SOCK" get nosuch >"$WORK/r" 2>&1; then fail "get nosuch accepted"; fi
printf 'not json\n' | timeout 5 sh -c "cat >/dev/null" # (ctl only sends JSON; see below)
kill -0 "$PID" || fail "daemon died after bad commands"

# snapshots with two radii differ: the parameter reaches the running pipeline
"$DEPTHAO" ctl --socket "$SOCK" snapshot "$WORK/r025.png" >/dev/null || fail "snapshot"
"$DEPTHAO" ctl --socket "$SOCK" set radius 1.5 >/dev/null
sleep 0.3
"$DEPTHAO" ctl --socket "$SOCK" snapshot "$WORK/r150.png" >/dev/null || fail "snapshot 2"
cmp -s "$WORK/r025.png" "$WORK/r150.png" && fail "radius 0.25 and 1.5 give the same image"

# SIGHUP: the file's radius comes back (0.5), the output changes
sed -i 's/^radius = 0.5/radius = 0.1/' "$WORK/a.ini"
kill -HUP "$PID"
wait_for 5 grep -q "reloaded \[ao\]" "$WORK/log" || fail "no reload: $(cat "$WORK/log")"
"$DEPTHAO" ctl --socket "$SOCK" get radius | "$JSON_GET" params.radius | grep -qx 0.1 || fail "radius after HUP"
# a broken file: the old settings stay, the daemon keeps running
printf '[ao]\nradius = banana\n' >>"$WORK/a.ini"
kill -HUP "$PID"
wait_for 5 grep -q "reload failed, keeping the old settings" "$WORK/log" || fail "broken reload not logged"
grep "reload failed" "$WORK/log" | grep -q "a.ini:[0-9]*:.*radius" || fail "reload message lacks file:line:key"
"$DEPTHAO" ctl --socket "$SOCK" get radius | "$JSON_GET" params.radius | grep -qx 0.1 || fail "radius after broken HUP"
n1=$(stat_of "$SOCK" frames_processed)
sleep 0.5
n2=$(stat_of "$SOCK" frames_processed)
[ "$n2" -gt "$n1" ] || fail "the pipeline stopped after a broken reload"

# pause stops processing, resume restarts it
"$DEPTHAO" ctl --socket "$SOCK" pause >/dev/null
sleep 0.3
p1=$(stat_of "$SOCK" frames_processed)
sleep 0.5
p2=$(stat_of "$SOCK" frames_processed)
[ "$p2" -eq "$p1" ] || fail "frames processed while paused ($p1 -> $p2)"
"$DEPTHAO" ctl --socket "$SOCK" resume >/dev/null
sleep 0.5
[ "$(stat_of "$SOCK" frames_processed)" -gt "$p2" ] || fail "resume did not restart"

stop_daemon || fail "exit status"
[ -e "$SOCK" ] && fail "control socket left behind"
finish
