#!/bin/sh
# SPDX-License-Identifier: MIT
# The MCAP recorder (mcap:FILE.mcap) in depthaod keeps what it accepted: SIGTERM finalises
# the file (summary, indexes; every frame the sink counted); kill -9 leaves a file that
# depthao's linear scan and @mcap/core's stream reader read up to its last chunk, losing at
# most the chunk being built (chunks close after 1 s, and at ?chunk= bytes); a full tmpfs
# (root) refuses the frame that does not fit and keeps every frame accepted, finalised; a
# disk that fails writes without fallocate (LD_PRELOAD, no root) keeps the chunks before.
. "$(dirname "$0")/daemon_lib.sh"
export DEPTHAO_PLUGIN_PATH="$TEST_PLUGINS"
NODE=${DAO_NODE:-node-not-found}
CHECK="${DAO_CHECK_MCAP:?the path of check_mcap.js}"
PRELOAD="${DAO_ENOSPC_PRELOAD:?the path of dao-enospc-preload.so}"
ASAN_PRELOAD="${ASAN_OPTIONS:+$ASAN_OPTIONS:}verify_asan_link_order=0"
SOCK="$WORK/ctl.sock"
HAVE_NODE=0
if command -v "$NODE" >/dev/null 2>&1; then
	set +e
	"$NODE" "$CHECK" /dev/null >/dev/null 2>&1
	[ $? -ne 77 ] && HAVE_NODE=1
	set -e
fi
[ "$HAVE_NODE" -eq 1 ] || echo "note: node or tests/js/node_modules missing: the @mcap/core checks are skipped"

# theirs FILE ARGS...: @mcap/core's count of AO messages ("-" without node)
theirs() {
	if [ "$HAVE_NODE" -eq 0 ]; then
		echo -
		return 0
	fi
	"$NODE" "$CHECK" "$@" >"$WORK/check" 2>&1 || { fail "check_mcap.js $*: $(cat "$WORK/check")"; echo -; return 0; }
	awk '{ print $2 }' "$WORK/check"
}

# ours FILE: the AO frames depthao's MCAP source plays (its warnings in $WORK/err-ours)
ours() {
	rm -rf "$WORK/ours"
	"$DEPTHAO" process --input "$1?topic=/depthao/ao" --ao-out "$WORK/ours" 2>"$WORK/err-ours" ||
		fail "depthao process $1: $(cat "$WORK/err-ours")"
	find "$WORK/ours" -name '*.png' 2>/dev/null | wc -l
}

# ---- 1. SIGTERM: finalised, every frame counted is in it ----------------------------
start_daemon "$WORK/log-term" --source "testsrc:fps=30,w=160,h=120" --socket "$SOCK" \
	--stats-interval 0 --stats-json "$WORK/term.jsonl" \
	--sink rec=mcap:"$WORK/term.mcap" --stream rec=ao
wait_for 10 test -S "$SOCK" || fail "no socket: $(cat "$WORK/log-term")"
took() { [ "$(stat_of "$SOCK" sinks.0.frames_out 2>/dev/null || echo 0)" -ge 30 ]; }
wait_for 30 took || fail "the recorder took no 30 frames"
stop_daemon || fail "SIGTERM: exit status"
n=$(tail -n 1 "$WORK/term.jsonl" | "$JSON_GET" sinks.0.frames_out)
t=$(theirs "$WORK/term.mcap")
o=$(ours "$WORK/term.mcap")
echo "SIGTERM: frames_out $n; @mcap/core: $(cat "$WORK/check" 2>/dev/null); depthao reads $o"
[ "$t" = - ] || [ "$t" -eq "$n" ] || fail "SIGTERM: @mcap/core reads $t AO frames, the sink wrote $n"
[ "$o" -eq "$n" ] || fail "SIGTERM: depthao reads $o AO frames, the sink wrote $n"
grep -q "warning" "$WORK/err-ours" && fail "SIGTERM: the file is not finished: $(cat "$WORK/err-ours")"
rm -f "$SOCK"

# ---- 1a. the camera's poses: depth-temporal-motion icp on a moving camera (synth: a pan
# of 1 degree a frame, a sideways move of 17 mm a frame): /tf holds each frame's pose, just
# before its AO image, within 2 mm and 0.002 in each quaternion component of the true one
# (synth's poses.txt, in the first frame's optical frame; the estimate is 1.5 mm off at
# worst here, with the intrinsics of the camera.json beside the PNGs; 6 mm with the
# default field of view): a pose inverted, its rotation conjugated or left out is at
# least 7.7 mm or 0.0077 off from the first moved frame on; with the motion off, no /tf
for name in pan-30 sideways; do
	"$DEPTHAO" synth --scene boxes --trajectory "$name" --frames 5 --rays 1 --out "$WORK/syn" \
		>"$WORK/err-syn" 2>&1 || fail "synth $name: $(cat "$WORK/err-syn")"
	"$DAEMON" --source "$WORK/syn/boxes-$name/depth" --playback manual --stats-interval 0 \
		--sink rec=mcap:"$WORK/$name.mcap" --stream rec=ao --depth-temporal 0.8 \
		--depth-temporal-motion icp >"$WORK/log-poses" 2>&1 ||
		fail "poses $name: $(cat "$WORK/log-poses")"
	grep -q "info  intrinsics from .*/camera.json: fx 525.00 fy 525.00 cx 319.50 cy 239.50" \
		"$WORK/log-poses" || fail "camera.json beside the PNGs not used: $(cat "$WORK/log-poses")"
	[ "$HAVE_NODE" -eq 1 ] || continue
	"$NODE" "$CHECK" "$WORK/$name.mcap" --poses "$WORK/syn/boxes-$name/poses.txt" \
		--pose-tolerance 0.002 >"$WORK/check" 2>&1 || fail "poses $name: $(cat "$WORK/check")"
	grep -q "^ao 5 shaded [0-9]* info 5 .* tf 5$" "$WORK/check" || fail "poses $name: $(cat "$WORK/check")"
	echo "poses $name within 2 mm and 0.002 of the truth: $(cat "$WORK/check")"
done
"$DAEMON" --source "$WORK/syn/boxes-sideways/depth" --playback manual --stats-interval 0 \
	--sink rec=mcap:"$WORK/still.mcap" --stream rec=ao --depth-temporal 0.8 \
	>"$WORK/log-still" 2>&1 || fail "no motion: $(cat "$WORK/log-still")"
[ "$HAVE_NODE" -eq 0 ] || "$NODE" "$CHECK" "$WORK/still.mcap" >"$WORK/check" 2>&1 ||
	fail "motion off: $(cat "$WORK/check")"

# ---- 1b. configured for the shaded stream, with the point cloud: the AO and depth come
# through want_streams; a cloud for each AO frame whose depth came too (a slow sink's
# queue, under ASan, may drop some of either; the sink counts its shaded frames)
"$DAEMON" --source "testsrc:fps=30,w=160,h=120" --max-frames 20 --stats-interval 0 \
	--stats-json "$WORK/cloud.jsonl" --sink "rec=mcap:$WORK/cloud.mcap?cloud=true" \
	--stream rec=shaded 2>"$WORK/log-cloud" || fail "cloud run: $(cat "$WORK/log-cloud")"
n=$(tail -n 1 "$WORK/cloud.jsonl" | "$JSON_GET" sinks.0.frames_out)
if [ "$HAVE_NODE" -eq 1 ]; then
	theirs "$WORK/cloud.mcap" >/dev/null
	echo "shaded stream with ?cloud=true: $(cat "$WORK/check"); frames_out $n"
	set -- $(cat "$WORK/check") # ao N shaded N info N points N chunks N
	[ "$4" -eq "$n" ] || fail "cloud: $4 shaded frames, the sink wrote $n"
	[ "$6" -eq "$2" ] && [ "$8" -le "$2" ] && [ "$8" -ge 1 ] ||
		fail "cloud: $2 AO, $6 CameraInfo, $8 clouds for $4 shaded frames"
fi

# ---- 2. kill -9: the complete chunks are there (at most 1 s or one chunk lost) ------
# kill9 NAME URI-OPTIONS: runs, kills, sets w0 (frames 2.5 s before), w1 (just before), t, o
kill9() {
	start_daemon "$WORK/log-$1" --source "testsrc:fps=30,w=160,h=120" --socket "$SOCK" \
		--stats-interval 0 --sink rec=mcap:"$WORK/$1.mcap$2" --stream rec=ao
	wait_for 10 test -S "$SOCK" || fail "no socket: $(cat "$WORK/log-$1")"
	sleep 3
	w0=$(stat_of "$SOCK" sinks.0.frames_out)
	sleep 2.5 # more than the chunks' 1 s: the frames counted in w0 are in closed chunks
	w1=$(stat_of "$SOCK" sinks.0.frames_out)
	kill -KILL "$PID"
	wait "$PID" 2>/dev/null || true
	PID=
	rm -f "$SOCK"
	[ -f "$WORK/$1.mcap" ] || fail "$1: no file after kill -9: $(ls "$WORK")"
	t=$(theirs "$WORK/$1.mcap" --cut)
	o=$(ours "$WORK/$1.mcap")
	echo "kill -9 ($1): the sink had written $w0 frames 2.5 s before, $w1 just before; depthao reads $o, @mcap/core $t"
	[ "$t" = - ] || [ "$t" -eq "$o" ] || fail "$1: @mcap/core reads $t AO frames, depthao $o"
	[ "$o" -ge "$w0" ] || fail "$1: $o frames recovered, $w0 were written 2.5 s before the kill"
	[ "$w0" -ge 30 ] || fail "$1: only $w0 frames in 3 s at 30 fps"
}
kill9 kill ""
# the chunks close after 1 s: what is lost is what came in the last ~second (30 fps; 60
# leaves room for a late frame on a loaded host)
[ $((w1 - o)) -le 60 ] || fail "kill: $((w1 - o)) frames lost, more than a chunk of 1 s"
# chunks of 200000 bytes hold two 160x120 frames (AO 38 KB, shaded 58 KB): at most 2 lost
kill9 kill-small "?chunk=200000"
[ $((w1 - o)) -le 2 ] || fail "kill-small: $((w1 - o)) frames lost; a chunk holds two"

# ---- 3. a full tmpfs (root): the frame that does not fit is refused, the rest kept ----
if [ "$(id -u)" -ne 0 ] || ! unshare -m true 2>/dev/null; then
	echo "note: not root or no mount namespaces; the tmpfs part is skipped"
else
	mkdir -p "$WORK/tmpfs" "$WORK/saved"
	status=0
	# 640x480 frames without compression: 1.5 MB each (AO, shaded, CameraInfo); 4 MB
	unshare -m sh -c '
		mount -t tmpfs -o size=4m tmpfs "$1" || exit 90
		"$2" --source "$3" --playback manual --stats-json "$4/tmpfs.jsonl" \
			--sink rec=mcap:"$1/rec.mcap?compression=none" --stream rec=ao \
			--sink other=y4m:/dev/null 2>"$4/log-tmpfs"
		status=$?
		cp -a "$1/." "$5/"
		exit $status' sh "$WORK/tmpfs" "$DAEMON" "$REC" "$WORK" "$WORK/saved" || status=$?
	if [ "$status" -eq 90 ]; then
		echo "note: cannot mount a tmpfs here; the tmpfs part is skipped"
	else
		n=$(tail -n 1 "$WORK/tmpfs.jsonl" | "$JSON_GET" sinks.0.frames_out)
		other=$(tail -n 1 "$WORK/tmpfs.jsonl" | "$JSON_GET" sinks.1.frames_out)
		t=$(theirs "$WORK/saved/rec.mcap" --compression none)
		o=$(ours "$WORK/saved/rec.mcap")
		echo "full tmpfs (4 MB): frames_out $n, depthao reads $o, @mcap/core $t (finalised: $(cat "$WORK/check" 2>/dev/null)); other sink $other; exit $status"
		[ "$n" -ge 1 ] || fail "tmpfs: no frame recorded"
		[ "$o" -eq "$n" ] || fail "tmpfs: depthao reads $o frames, the sink accepted $n"
		[ "$t" = - ] || [ "$t" -eq "$n" ] || fail "tmpfs: @mcap/core reads $t frames, the sink accepted $n"
		grep -q "warning" "$WORK/err-ours" && fail "tmpfs: not finalised: $(cat "$WORK/err-ours")"
		[ "$(ls "$WORK/saved")" = rec.mcap ] || fail "files on the tmpfs: $(ls "$WORK/saved")"
		[ "$other" -eq 16 ] || fail "tmpfs: the sink beside it wrote $other of 16 frames"
		grep -q "sink rec.*No space left" "$WORK/log-tmpfs" || fail "tmpfs: no error line: $(cat "$WORK/log-tmpfs")"
	fi
fi

# ---- 3b. writes that fail on a full disk, without fallocate's reservation (no root) ----
mkdir -p "$WORK/full"
env LD_PRELOAD="$PRELOAD" ASAN_OPTIONS="$ASAN_PRELOAD" DAO_ENOSPC_PATH="$WORK/full/" DAO_ENOSPC_AFTER=5000000 \
	"$DAEMON" --source "$REC" --playback manual --stats-json "$WORK/full.jsonl" \
	--sink rec=mcap:"$WORK/full/rec.mcap?compression=none&chunk=2000000" --stream rec=ao \
	2>"$WORK/log-full" || echo "note: exit status $? (see the log)"
n=$(tail -n 1 "$WORK/full.jsonl" | "$JSON_GET" sinks.0.frames_out)
t=$(theirs "$WORK/full/rec.mcap" --cut)
o=$(ours "$WORK/full/rec.mcap")
echo "failing writes (preload, 5 MB): frames_out $n, depthao reads $o, @mcap/core $t"
[ "$o" -ge 2 ] || fail "failing writes: $o frames kept of 3 that fit"
[ "$t" = - ] || [ "$t" -eq "$o" ] || fail "failing writes: @mcap/core reads $t, depthao $o"
grep -q "sink rec.*No space left" "$WORK/log-full" || fail "failing writes: no error line: $(cat "$WORK/log-full")"
finish
