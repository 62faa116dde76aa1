#!/bin/sh
# SPDX-License-Identifier: MIT
# The rtsp sink of depthaod on loopback: depthaod plays the bundled recording in a loop
# into rtsp:PORT/depthao; GStreamer clients (rtspsrc ! rtpjpegdepay ! jpegdec) receive
# 640x480 frames that are the shaded frames of the recording (JPEG-close) and change with
# the scene.  Two clients at once, clients killed without TEARDOWN, clients reconnecting,
# over TCP (the default) and UDP (transport=udp); the sink never drops a frame (it never
# blocks the pipeline), the daemon keeps processing, stops within a second on SIGTERM with
# a client connected; a port in use and a bad URI are errors naming the cause.
# usage: test_gst_rtsp.sh DEPTHAOD DEPTHAO GST_TEST_UTIL   (DEPTHAO_PLUGIN_PATH set)
set -eu
DAEMON=$1
DEPTHAO=$2
UTIL=$3
ROOT=${DAO_SOURCE_ROOT:?}
REC="$ROOT/recordings/spheres-rolling.oni"
if ! command -v gst-launch-1.0 >/dev/null || ! command -v gst-inspect-1.0 >/dev/null; then
	echo "SKIP: gst-launch-1.0 / gst-inspect-1.0 not installed (gstreamer1.0-tools)"
	exit 77
fi
for e in rtspsrc rtpjpegdepay jpegdec videoconvert identity pngenc multifilesink; do
	if ! gst-inspect-1.0 --exists "$e"; then
		echo "SKIP: GStreamer element $e missing (gstreamer1.0-plugins-base/-good)"
		exit 77
	fi
done
WORK=$(mktemp -d "${TMPDIR:-/tmp}/gst-rtsp.XXXXXX")
export GST_REGISTRY="$WORK/registry.bin"
DPID=
UPID=
CLIENTS=
# kills a process and its children (a `timeout` and the client it runs)
kill_tree() {
	for c in $(cat "/proc/$1/task/$1/children" 2>/dev/null); do
		kill -KILL "$c" 2>/dev/null || true
	done
	kill -KILL "$1" 2>/dev/null || true
}
cleanup() {
	for p in $CLIENTS $DPID $UPID; do
		kill_tree "$p"
	done
	wait 2>/dev/null
	rm -rf "$WORK"
}
trap cleanup EXIT
trap 'exit 1' INT TERM # a timeout (meson's SIGTERM) cleans up too
failures=0
fail() {
	echo "FAIL: $*"
	failures=$((failures + 1))
}
# wait_for SECONDS COMMAND...: polls until the command succeeds
wait_for() {
	limit=$1
	shift
	i=0
	while ! "$@" >/dev/null 2>&1; do
		i=$((i + 1))
		[ "$i" -le $((limit * 10)) ] || return 1
		sleep 0.1
	done
}
count() {
	find "$WORK/$1" -name '*.png' 2>/dev/null | wc -l
}
has_frames() {
	[ "$(count "$1")" -ge "$2" ]
}

"$DEPTHAO" process --input "$REC" --shaded-out "$WORK/ref" --quiet || fail "depthao process"
PORT=$("$UTIL" free-port)
URL="rtsp://127.0.0.1:$PORT/depthao"

# client_wait PID NAME: the client's exit; an error only in its own teardown after it got
# its frames (rtspsrc sending PAUSE/TEARDOWN on a connection the server already closed,
# "Received end-of-file") is gst-launch's shutdown, not a failure of the server
client_wait() {
	wait "$1" && return 0
	st=$?
	if grep -q "Could not send message. (Received end-of-file)" "$WORK/$2.log" &&
		! grep -v "Received end-of-file\|Could not write to resource\|Additional debug info\|gstrtspsrc.c" \
			"$WORK/$2.log" | grep -q "ERROR"; then
		echo "note: client $2 ended with a teardown error after its frames (exit $st)"
		return 0
	fi
	fail "client $2: exit $st: $(cat "$WORK/$2.log")"
}

# client NAME FRAMES [rtspsrc properties...]: receives FRAMES frames (0 = until killed)
# as NAME/NNN.png, in the background ($! is its pid)
client() {
	name=$1
	frames=$2
	shift 2
	mkdir -p "$WORK/$name"
	# a client that ends by itself gets 60 s; one that runs until killed is started
	# directly, so that $! is gst-launch itself and SIGKILL really ends it (killing
	# `timeout` would leave its child writing frames)
	lim="timeout 60"
	eos=
	if [ "$frames" -gt 0 ]; then
		eos="eos-after=$((frames + 1))"
	else
		lim=
	fi
	# shellcheck disable=SC2086 # $lim and $eos are words or nothing
	$lim gst-launch-1.0 -q rtspsrc location="$URL" latency=100 "$@" ! rtpjpegdepay ! \
		jpegdec ! videoconvert ! video/x-raw,format=RGB ! identity $eos ! pngenc compression-level=1 ! \
		multifilesink location="$WORK/$name/%03d.png" >"$WORK/$name.log" 2>&1 &
	CLIENTS="$CLIENTS $!"
}
# check_frames NAME MIN: at least MIN frames, 640x480 RGB, each close to a frame of the
# recording (mean difference < 3 of 255, JPEG), at least two different frames among them
check_frames() {
	n=$(count "$1")
	[ "$n" -ge "$2" ] || { fail "client $1: $n frames, expected $2: $(cat "$WORK/$1.log")"; return; }
	for f in "$WORK/$1"/*.png; do
		info=$("$UTIL" info "$f")
		[ "$info" = "640 480 rgb24" ] || fail "client $1: $(basename "$f") is $info"
	done
	"$UTIL" match "$WORK/$1"/*.png -- "$WORK"/ref/*.png >"$WORK/$1.match" ||
		fail "client $1: $(cat "$WORK/$1.match")"
	bad=$(awk '$3 >= 3' "$WORK/$1.match" | wc -l)
	[ "$bad" -eq 0 ] || fail "client $1: frames unlike the recording: $(awk '$3 >= 3' "$WORK/$1.match")"
	distinct=$(awk '{ print $2 }' "$WORK/$1.match" | sort -u | wc -l)
	[ "$distinct" -ge 2 ] || fail "client $1: the frames do not change ($(cat "$WORK/$1.match"))"
	mean=$(awk '{ s += $3 } END { printf "%.2f", s / NR }' "$WORK/$1.match")
	echo "client $1: $n frames of 640x480, $distinct different frames of the recording, mean difference $mean"
}
# processed: frames processed, from the daemon's last stats line
processed() {
	grep "stats: .* processed" "$WORK/daemon.log" | tail -n 1 | sed 's/.*), \([0-9]*\) processed.*/\1/'
}
# sink_counts LOG SINK: "OUT DROPPED" from the sink's last stats line (empty if none yet)
sink_counts() {
	grep "stats: sink $2:" "$WORK/$1" | tail -n 1 |
		sed -n 's/.*: \([0-9]*\) out, \([0-9]*\) dropped.*/\1 \2/p'
}
# sink_running LOG SINK: the sink has written a frame (its stats line says so)
sink_running() {
	set -- $(sink_counts "$1" "$2")
	[ "${1:-0}" -gt 0 ]
}
# mark_sink LOG SINK: the counts once the sink runs, the base of check_sink_drops: frames
# dropped while it opened (GStreamer's first start builds its plugin registry, which takes
# seconds on a loaded host) are a live source's normal drops, not the sink holding anything up
mark_sink() {
	wait_for 20 sink_running "$1" "$2" || fail "sink $2 wrote nothing: $(tail -n 5 "$WORK/$1")"
	MARK=$(sink_counts "$1" "$2")
}
# check_sink_drops LOG SINK: since mark_sink, at most 5 % of the sink's frames dropped (a sink
# that blocked would lose most of them; a loaded 2-CPU machine may lose a few when the sink
# thread is not scheduled for a quarter of a second)
check_sink_drops() {
	set -- "$1" "$2" $MARK $(sink_counts "$1" "$2")
	out=$(( ${5:-0} - ${3:-0} ))
	dropped=$(( ${6:-0} - ${4:-0} ))
	if [ -z "${5:-}" ] || [ "$out" -lt 30 ] || [ $((dropped * 20)) -gt "$out" ]; then
		fail "sink $2: $out frames out and $dropped dropped since it ran ($(sink_counts "$1" "$2") in all)"
	fi
	echo "sink $2: $out frames out, $dropped dropped since it ran ($(sink_counts "$1" "$2") in all)"
}
daemon_alive() {
	kill -0 "$DPID" 2>/dev/null || fail "the daemon died: $(tail -n 20 "$WORK/daemon.log")"
}

"$DAEMON" --source "$REC" --loop --sink net=rtsp:"$PORT"/depthao --set sink.net.queue=8 \
	--stats-interval 1 2>"$WORK/daemon.log" &
DPID=$!
wait_for 20 grep -q "sink net: rtsp:$PORT/depthao" "$WORK/daemon.log" ||
	fail "the rtsp sink did not open: $(cat "$WORK/daemon.log")"
mark_sink daemon.log net

# two clients at once: one asking for UDP first (falls back to TCP, the default
# transport), one asking for TCP
client auto1 15
a=$!
client tcp1 15 protocols=tcp
b=$!
client_wait "$a" auto1
client_wait "$b" tcp1
check_frames auto1 15
check_frames tcp1 15

# clients that vanish without TEARDOWN (SIGKILL)
client gone1 0 protocols=tcp
a=$!
client gone2 0
b=$!
wait_for 20 has_frames gone1 3 || fail "client gone1 got no frames: $(cat "$WORK/gone1.log")"
wait_for 20 has_frames gone2 3 || fail "client gone2 got no frames: $(cat "$WORK/gone2.log")"
kill -KILL "$a" "$b"
wait "$a" 2>/dev/null || true
wait "$b" 2>/dev/null || true
before=$(processed)
sleep 1.5
daemon_alive
after=$(processed)
[ "${after:-0}" -gt "${before:-0}" ] || fail "processing stalled after clients vanished: $before -> $after frames"
echo "after two clients were killed: $before -> $after frames processed in 1.5 s"

# reconnecting: one client, then another
client again1 10
a=$!
client_wait "$a" again1
check_frames again1 10
client again2 10 protocols=tcp
a=$!
client_wait "$a" again2
check_frames again2 10
# a client that insists on UDP gets an error, not a hang
if timeout 30 gst-launch-1.0 rtspsrc location="$URL" protocols=udp ! fakesink >"$WORK/udp-only.log" 2>&1; then
	fail "a UDP-only client was served by a TCP server"
fi
grep -q "No supported stream" "$WORK/udp-only.log" || fail "UDP-only client: $(cat "$WORK/udp-only.log")"

# a second server on the same port: the error names the cause (the daemon retries)
"$DAEMON" --source "$REC" --playback manual --max-frames 8 --sink net2=rtsp:"$PORT"/depthao \
	2>"$WORK/daemon2.log" || fail "second daemon: exit $?: $(cat "$WORK/daemon2.log")"
grep -q "sink net2 (rtsp:$PORT/depthao): rtsp: cannot listen on 0.0.0.0:$PORT: .*in use" \
	"$WORK/daemon2.log" || fail "port in use: $(cat "$WORK/daemon2.log")"
# a bad URI
"$DAEMON" --source "$REC" --playback manual --max-frames 4 --sink bad=rtsp:depthao \
	2>"$WORK/daemon3.log" || fail "bad URI daemon: exit $?"
grep -q "rtsp: 'depthao' is not PORT/MOUNT" "$WORK/daemon3.log" || fail "bad URI: $(cat "$WORK/daemon3.log")"

# the sink never held up the pipeline: its queue (8 frames) dropped next to nothing
sleep 1.1
daemon_alive
check_sink_drops daemon.log net

# SIGTERM with a client connected: stops within a second
client last 0 protocols=tcp
c=$!
wait_for 20 has_frames last 2 || fail "client last got no frames: $(cat "$WORK/last.log")"
t0=$(date +%s%N)
kill -TERM "$DPID"
status=0
wait "$DPID" || status=$?
ms=$((($(date +%s%N) - t0) / 1000000))
DPID=
[ "$status" -eq 0 ] || fail "daemon exit status $status: $(tail -n 5 "$WORK/daemon.log")"
[ "$ms" -le 1000 ] || fail "SIGTERM with a client connected took $ms ms"
echo "SIGTERM with a client connected: stopped in $ms ms"
# the client sees the end of the stream (or the connection close) and exits by itself
wait_for 20 sh -c "! kill -0 $c 2>/dev/null" || echo "note: the last client did not notice the server going away"
kill -KILL "$c" 2>/dev/null || true

# transport=udp (and a JPEG quality, one address): another server; two UDP clients at
# once, one of them killed, then another
UPORT=$("$UTIL" free-port)
"$DAEMON" --source "$REC" --loop --sink unet="rtsp:127.0.0.1:$UPORT/udp?transport=udp&quality=70" \
	--set sink.unet.queue=8 --stats-interval 1 2>"$WORK/daemon-udp.log" &
UPID=$!
wait_for 20 grep -q "sink unet: rtsp:" "$WORK/daemon-udp.log" ||
	fail "the UDP rtsp sink did not open: $(cat "$WORK/daemon-udp.log")"
mark_sink daemon-udp.log unet
URL="rtsp://127.0.0.1:$UPORT/udp"
client udp1 10 protocols=udp
a=$!
client udpgone 0 protocols=udp
b=$!
client_wait "$a" udp1
wait_for 20 has_frames udpgone 3 || fail "client udpgone got no frames: $(cat "$WORK/udpgone.log")"
kill -KILL "$b"
wait "$b" 2>/dev/null || true
client udp2 10 protocols=udp
a=$!
client_wait "$a" udp2
check_frames udp1 10
check_frames udp2 10
kill -TERM "$UPID"
wait "$UPID" || fail "UDP daemon: exit $?: $(tail -n 5 "$WORK/daemon-udp.log")"
UPID=
check_sink_drops daemon-udp.log unet

if [ "$failures" -ne 0 ]; then
	echo "$failures failure(s)"
	exit 1
fi
echo "all passed"
