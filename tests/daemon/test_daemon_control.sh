#!/bin/sh
# SPDX-License-Identifier: MIT
# The control socket (stats, get/set, errors, who may connect, clients that misbehave,
# 'depthao ctl --timeout') and SIGHUP reloads.
. "$(dirname "$0")/daemon_lib.sh"
SOCK_CLIENT="$TEST_PLUGINS/sock_client"

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
if getent group depthao >/dev/null; then
	[ "$(stat -c %a:%G "$SOCK")" = 660:depthao ] || fail "socket $(stat -c %a:%G "$SOCK"), expected 660:depthao"
else
	[ "$(stat -c %a "$SOCK")" = 600 ] || fail "socket mode $(stat -c %a "$SOCK"), expected 600"
fi
# (frames are named by their index in the loop; on a busy host some are dropped)
wait_for 20 sh -c "[ \$(ls '$WORK/out' 2>/dev/null | wc -l) -ge 3 ]" || fail "no frames"

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

# stats parse and add up, within one reply (three requests would each see other counts)
"$DEPTHAO" ctl --socket "$SOCK" stats >"$WORK/stats.json" || fail "ctl stats"
in=$("$JSON_GET" stats.frames_in <"$WORK/stats.json")
done_=$("$JSON_GET" stats.frames_processed <"$WORK/stats.json")
out=$("$JSON_GET" stats.sinks.0.frames_out <"$WORK/stats.json")
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

# processed_beyond N: more than N frames processed
processed_beyond() {
	[ "$(stat_of "$SOCK" frames_processed)" -gt "$1" ]
}

# the camera's motion and pose in the stats: "none" while depth-temporal-motion is off;
# with icp (and the depth filter on) the frames are estimated and the pose moves from the
# identity (the recording's camera stands still: within 10 cm, a unit quaternion); turned
# off again, the state is "none" and the pose stays where it was
[ "$(stat_of "$SOCK" motion.state)" = none ] || fail "motion state with motion off"
"$DEPTHAO" ctl --socket "$SOCK" set depth-temporal 0.8 >/dev/null || fail "set depth-temporal 0.8"
"$DEPTHAO" ctl --socket "$SOCK" set depth-temporal-motion icp >/dev/null ||
	fail "set depth-temporal-motion icp"
motion_accepted() {
	[ "$(stat_of "$SOCK" motion.frames_accepted)" -ge 3 ]
}
wait_for 20 motion_accepted ||
	fail "no camera motion accepted: $("$DEPTHAO" ctl --socket "$SOCK" stats)"
[ "$(stat_of "$SOCK" motion.followed)" = true ] || fail "motion.followed with icp on"
"$DEPTHAO" ctl --socket "$SOCK" set depth-temporal-motion off >/dev/null
n0=$(stat_of "$SOCK" frames_processed)
wait_for 10 processed_beyond $((n0 + 2)) || fail "no frames after depth-temporal-motion off"
"$DEPTHAO" ctl --socket "$SOCK" stats >"$WORK/stats.json" || fail "ctl stats"
sleep 0.3
"$DEPTHAO" ctl --socket "$SOCK" stats >"$WORK/stats2.json" || fail "ctl stats"
[ "$("$JSON_GET" stats.motion.state <"$WORK/stats2.json")" = none ] ||
	fail "motion state after off: $(cat "$WORK/stats2.json")"
[ "$("$JSON_GET" stats.motion.followed <"$WORK/stats2.json")" = false ] ||
	fail "motion.followed after off: $(cat "$WORK/stats2.json")"
for k in 0 1 2; do
	p=$("$JSON_GET" stats.motion.position_m.$k <"$WORK/stats.json")
	[ "$p" = "$("$JSON_GET" stats.motion.position_m.$k <"$WORK/stats2.json")" ] ||
		fail "the pose moved with the motion off"
	echo "$p" | awk '{ exit !($1 > -0.1 && $1 < 0.1) }' || fail "position $k: $p"
done
q=""
for k in 0 1 2 3; do
	q="$q $("$JSON_GET" stats.motion.orientation_xyzw.$k <"$WORK/stats.json")"
done
echo "$q" | awk '{ n = $1*$1 + $2*$2 + $3*$3 + $4*$4; exit !(n > 0.999999 && n < 1.000001 && $4 > 0.99) }' ||
	fail "orientation:$q"
# on again: the pose starts over (logged); off and on back to back, which the daemon may
# take together before its next frame: it starts over all the same
restarts() {
	grep -c "its pose starts over" "$WORK/log" || true # (grep -c exits 1 on a count of 0)
}
restarted_beyond() {
	[ "$(restarts)" -gt "$1" ]
}
r0=$(restarts)
"$DEPTHAO" ctl --socket "$SOCK" set depth-temporal-motion icp >/dev/null
wait_for 10 restarted_beyond "$r0" || fail "the pose did not start over: $(cat "$WORK/log")"
n0=$(stat_of "$SOCK" frames_processed)
wait_for 10 processed_beyond $((n0 + 2)) || fail "no frames with the motion on again"
"$DEPTHAO" ctl --socket "$SOCK" set depth-temporal-motion off >/dev/null
"$DEPTHAO" ctl --socket "$SOCK" set depth-temporal-motion icp >/dev/null
wait_for 10 restarted_beyond $((r0 + 1)) ||
	fail "off and on again: the pose did not start over: $(cat "$WORK/log")"
"$DEPTHAO" ctl --socket "$SOCK" set depth-temporal-motion off >/dev/null
"$DEPTHAO" ctl --socket "$SOCK" set depth-temporal 0 >/dev/null

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
n0=$(stat_of "$SOCK" frames_processed)
wait_for 10 processed_beyond $((n0 + 1)) || fail "no frames after set"
"$DEPTHAO" ctl --socket "$SOCK" snapshot "$WORK/r150.png" >/dev/null || fail "snapshot 2"
cmp -s "$WORK/r025.png" "$WORK/r150.png" && fail "radius 0.25 and 1.5 give the same image"
# a write-protected PNG is not replaced by a snapshot (the output rule: issue 38)
cp "$WORK/r025.png" "$WORK/ro.png"
chmod 444 "$WORK/ro.png"
if "$DEPTHAO" ctl --socket "$SOCK" snapshot "$WORK/ro.png" >"$WORK/ro.out" 2>&1; then
	fail "a snapshot replaced a write-protected PNG"
fi
grep -q "is write-protected" "$WORK/ro.out" || fail "write-protected snapshot: $(cat "$WORK/ro.out")"
cmp -s "$WORK/ro.png" "$WORK/r025.png" || fail "the write-protected PNG changed"

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
wait_for 10 processed_beyond "$n1" || fail "the pipeline stopped after a broken reload"

# pause stops processing (once the frame in hand is done), resume restarts it
"$DEPTHAO" ctl --socket "$SOCK" pause >/dev/null
still_for_half_a_second() {
	a=$(stat_of "$SOCK" frames_processed)
	sleep 0.5
	[ "$(stat_of "$SOCK" frames_processed)" -eq "$a" ]
}
wait_for 5 still_for_half_a_second || fail "frames still processed 5 s after pause"
p2=$(stat_of "$SOCK" frames_processed)
sleep 1
[ "$(stat_of "$SOCK" frames_processed)" -eq "$p2" ] || fail "frames processed while paused"
"$DEPTHAO" ctl --socket "$SOCK" resume >/dev/null
wait_for 10 processed_beyond "$p2" || fail "resume did not restart"

stop_daemon || fail "exit status"
[ -e "$SOCK" ] && fail "control socket left behind"

# --- clients that misbehave hold nobody up --------------------------------------------
export DEPTHAO_PLUGIN_PATH="$TEST_PLUGINS"
# ask TIMEOUT_MS JSON: one request on its own connection; the reply, or fails
ask() {
	"$SOCK_CLIENT" ask "$SOCK" "$1" "$2" 2>>"$WORK/ask.log"
}
start_daemon "$WORK/log-abuse" --source "testsrc:fps=50" --sink ok=y4m:/dev/null --socket "$SOCK" \
	--stats-interval 0 --set daemon.socket_idle_timeout=2
wait_for 10 test -S "$SOCK" || fail "no control socket: $(cat "$WORK/log-abuse")"

# twenty connections that say nothing (eight locked everyone out before): others get in
"$SOCK_CLIENT" idle "$SOCK" 20 30 >"$WORK/idle.out" &
idle=$!
wait_for 10 grep -q ready "$WORK/idle.out" || fail "idle connections not made"
ask 2000 '{"cmd":"stats"}' | grep -q '"ok":true' || fail "stats with 20 idle connections: $(tail -n 2 "$WORK/ask.log")"
# ... and the daemon closes idle ones after socket_idle_timeout (2 s here)
wait_for 10 grep -q "all closed" "$WORK/idle.out" || fail "idle connections still open after 10 s"
kill "$idle" 2>/dev/null || true

# a client that sends requests and never reads the replies: others are answered, it is
# disconnected, and it does not delay SIGTERM (11 s before)
"$SOCK_CLIENT" flood "$SOCK" 30 >"$WORK/flood.out" 2>"$WORK/flood.err" &
flood=$!
wait_for 20 grep -q ready "$WORK/flood.out" || fail "flood client: $(cat "$WORK/flood.err")"
ask 2000 '{"cmd":"get","key":"radius"}' | grep -q '"radius"' || fail "get during a flood: $(tail -n 2 "$WORK/ask.log")"
wait_for 15 grep -q "took none of its replies" "$WORK/log-abuse" || fail "the flooding client was not disconnected: $(cat "$WORK/log-abuse") $(cat "$WORK/flood.err")"

# a snapshot is written from the running pipeline (its client holds on without reading)
"$SOCK_CLIENT" hold "$SOCK" '{"cmd":"snapshot","path":"'"$WORK/snap.png"'"}' 10 >"$WORK/hold.out" &
hold=$!
"$SOCK_CLIENT" flood "$SOCK" 30 >"$WORK/flood2.out" 2>&1 &
flood2=$!
wait_for 20 grep -q ready "$WORK/flood2.out" || fail "second flood client"
ask 1000 '{"cmd":"stats"}' | grep -q '"ok":true' || fail "stats with a snapshot pending: $(tail -n 2 "$WORK/ask.log")"
wait_for 10 test -s "$WORK/snap.png" || fail "the pending snapshot was not written"
# while paused a snapshot is refused at once, not after 3 s
"$DEPTHAO" ctl --socket "$SOCK" pause >/dev/null || fail "pause"
ask 1000 '{"cmd":"snapshot","path":"'"$WORK/snap2.png"'"}' | grep -q "paused" ||
	fail "snapshot while paused: $(tail -n 2 "$WORK/ask.log")"
[ -e "$WORK/snap2.png" ] && fail "a snapshot was written while paused"
"$DEPTHAO" ctl --socket "$SOCK" resume >/dev/null || fail "resume"
# with algorithm none there is no shaded image: refused at once, not after the timeout
"$DEPTHAO" ctl --socket "$SOCK" set algorithm none >/dev/null || fail "set algorithm none"
ask 1000 '{"cmd":"snapshot","path":"'"$WORK/snap3.png"'"}' | grep -q "algorithm is none" ||
	fail "snapshot with algorithm none: $(tail -n 2 "$WORK/ask.log")"
[ -e "$WORK/snap3.png" ] && fail "a snapshot was written with algorithm none"
"$DEPTHAO" ctl --socket "$SOCK" set algorithm gtao >/dev/null || fail "set algorithm gtao"
stop_daemon || fail "exit status with misbehaving clients: $(cat "$WORK/log-abuse")"
kill "$flood" "$flood2" "$hold" 2>/dev/null || true

# a snapshot waiting for a frame that does not come (a camera that cannot open) holds up
# no other client (all waited 3 s before), and ends with a timeout error
start_daemon "$WORK/log-snap" --source "testsrc:fps=0" --sink ok=y4m:/dev/null --socket "$SOCK" \
	--stats-interval 0
wait_for 10 test -S "$SOCK" || fail "no control socket: $(cat "$WORK/log-snap")"
ask 6000 '{"cmd":"snapshot","path":"'"$WORK/never.png"'"}' >"$WORK/snap-wait.out" &
snap=$!
sleep 0.3
ask 1000 '{"cmd":"stats"}' | grep -q '"ok":true' || fail "stats with a snapshot pending: $(tail -n 2 "$WORK/ask.log")"
ask 1000 '{"cmd":"snapshot","path":"'"$WORK/second.png"'"}' | grep -q "in progress" ||
	fail "a second snapshot: $(tail -n 2 "$WORK/ask.log")"
wait "$snap" || fail "the pending snapshot got no reply"
grep -q "no frame within 3000 ms" "$WORK/snap-wait.out" || fail "snapshot timeout: $(cat "$WORK/snap-wait.out")"
stop_daemon || fail "exit status: $(cat "$WORK/log-snap")"

# SIGTERM while a client floods and reads nothing (it took 26 s before: until the client left)
start_daemon "$WORK/log-flood" --source "testsrc:fps=50" --sink ok=y4m:/dev/null --socket "$SOCK" \
	--stats-interval 0
wait_for 10 test -S "$SOCK" || fail "no control socket: $(cat "$WORK/log-flood")"
"$SOCK_CLIENT" flood "$SOCK" 30 >"$WORK/flood3.out" 2>&1 &
flood=$!
wait_for 20 grep -q ready "$WORK/flood3.out" || fail "third flood client"
stop_daemon || fail "exit status during a flood: $(cat "$WORK/log-flood")"
kill "$flood" 2>/dev/null || true

# 'depthao ctl' gives up after --timeout on a socket that never answers
"$SOCK_CLIENT" listen "$WORK/dead.sock" 30 >"$WORK/dead.out" &
dead=$!
wait_for 10 grep -q ready "$WORK/dead.out" || fail "listening socket"
t0=$(date +%s%N)
if timeout 20 "$DEPTHAO" ctl --socket "$WORK/dead.sock" --timeout 1 stats >"$WORK/dead.log" 2>&1; then
	fail "ctl succeeded on a silent socket"
fi
ms=$((($(date +%s%N) - t0) / 1000000))
[ "$ms" -lt 5000 ] || fail "ctl --timeout 1 took $ms ms"
grep -q "no reply from .* within 1 s" "$WORK/dead.log" || fail "ctl timeout message: $(cat "$WORK/dead.log")"
kill "$dead" 2>/dev/null || true

# --- who may connect: the daemon's user, root, the socket's group --------------------
if [ "$(id -u)" -eq 0 ] && command -v setpriv >/dev/null && getent group daemon >/dev/null; then
	gid=$(getent group daemon | cut -d: -f3)
	mkdir -m 1777 "$WORK/run"
	chmod 755 "$WORK"
	as_nobody() { # (not for background jobs: $! would be a subshell)
		setpriv --reuid=65534 --regid=65534 "$@"
	}
	# root runs it with socket_group = daemon: 0660, group daemon; members get in
	start_daemon "$WORK/log-g" --source "testsrc:fps=50" --sink ok=y4m:/dev/null \
		--socket "$WORK/run/g.sock" --set daemon.socket_group=daemon --stats-interval 0
	wait_for 10 test -S "$WORK/run/g.sock" || fail "no socket: $(cat "$WORK/log-g")"
	[ "$(stat -c %a:%G "$WORK/run/g.sock")" = 660:daemon ] ||
		fail "socket with a group: $(stat -c %a:%G "$WORK/run/g.sock")"
	as_nobody --groups="$gid" "$DEPTHAO" ctl --socket "$WORK/run/g.sock" stats >"$WORK/g1" 2>&1 ||
		fail "a member of the group was refused: $(cat "$WORK/g1") $(cat "$WORK/log-g")"
	as_nobody --clear-groups "$DEPTHAO" ctl --socket "$WORK/run/g.sock" stats >"$WORK/g2" 2>&1 &&
		fail "a non-member got in: $(cat "$WORK/g2")"
	# the file mode keeps others out; if it did not, the daemon would
	chmod 666 "$WORK/run/g.sock"
	as_nobody --clear-groups "$DEPTHAO" ctl --socket "$WORK/run/g.sock" --timeout 2 stats \
		>"$WORK/g3" 2>&1 && fail "a non-member got in through a 0666 socket: $(cat "$WORK/g3")"
	wait_for 5 grep -q "control: refused uid 65534 (pid [0-9]*): only uid 0, root and group daemon may connect" "$WORK/log-g" ||
		fail "refusal not logged: $(cat "$WORK/log-g")"
	stop_daemon || fail "exit status"
	if ! getent group depthao >/dev/null; then
		# a group that does not exist is an error at start
		if "$DAEMON" --source "testsrc:fps=50" --sink ok=y4m:/dev/null --socket "$WORK/run/x.sock" \
			--set daemon.socket_group=no-such-group-here 2>"$WORK/log-nogroup"; then
			fail "a missing socket_group was accepted"
		fi
		grep -q "socket_group: there is no group 'no-such-group-here'" "$WORK/log-nogroup" ||
			fail "missing group: $(cat "$WORK/log-nogroup")"
	fi
	# the daemon as another user (systemd's DynamicUser): root can still use the socket
	setpriv --reuid=65534 --regid=65534 --clear-groups "$DAEMON" --source "testsrc:fps=50" \
		--sink ok=y4m:/dev/null --socket "$WORK/run/n.sock" --stats-interval 0 2>"$WORK/log-n" &
	PID=$!
	wait_for 10 test -S "$WORK/run/n.sock" || fail "no socket as nobody: $(cat "$WORK/log-n")"
	"$DEPTHAO" ctl --socket "$WORK/run/n.sock" stats >"$WORK/n1" 2>&1 ||
		fail "root was refused by a daemon running as nobody: $(cat "$WORK/n1") $(cat "$WORK/log-n")"
	stop_daemon || fail "exit status (as nobody)"
else
	echo "note: not root, or no setpriv or group 'daemon'; the permission checks were skipped"
fi
finish
