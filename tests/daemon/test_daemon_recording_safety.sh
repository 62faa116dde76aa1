#!/bin/sh
# SPDX-License-Identifier: MIT
# Nothing recorded is lost: a recorder killed with SIGKILL leaves its file at its name with
# every frame it wrote (read back pixel for pixel, with a warning; synced every second, so
# OpenNI2 plays it up to the last sync); the daemon started again records beside it; a full
# disk keeps the frames that fit and the counters count exactly those while the other sinks
# go on (LD_PRELOAD without root; a 4 MB tmpfs as root); ctl snapshot writes into FIFOs and
# character devices and refuses directories.
. "$(dirname "$0")/daemon_lib.sh"
export DEPTHAO_PLUGIN_PATH="$TEST_PLUGINS"
ONI_CHECK="$TEST_PLUGINS/oni_check"
PRELOAD="${DAO_ENOSPC_PRELOAD:?the path of dao-enospc-preload.so}"
# under AddressSanitizer (bootstrap's build-asan) a preloaded module comes before its runtime
ASAN_PRELOAD="${ASAN_OPTIONS:+$ASAN_OPTIONS:}verify_asan_link_order=0"
SOCK="$WORK/ctl.sock"
# OpenNI2 (when its plugin is built) is looked for beside depthao, not among the test plugins
NI="env -u DEPTHAO_PLUGIN_PATH $DEPTHAO"
OPENNI2=0
$NI devices 2>/dev/null | grep -q "^  openni2 " && OPENNI2=1

count_png() {
	find "$1" -name '*.png' 2>/dev/null | wc -l
}

# field NAME "LINE": the number after NAME in oni_check's output
field() {
	echo "$2" | awk -v k="$1" '{ for (i = 1; i < NF; i++) if ($i == k) print $(i + 1) }'
}

# same_ao A B N: the first N AO images of two runs are identical
same_ao() {
	i=0
	while [ "$i" -lt "$3" ]; do
		f=$(printf "%06d.png" "$i")
		cmp -s "$1/$f" "$2/$f" || return 1
		i=$((i + 1))
	done
}

# ---- 1. kill -9 while recording a live camera --------------------------------------
# The preload module only logs the syncs of the recording here (nothing fails).
env LD_PRELOAD="$PRELOAD" ASAN_OPTIONS="$ASAN_PRELOAD" DAO_ENOSPC_PATH="$WORK/session" DAO_ENOSPC_AFTER=1000000000000 \
	DAO_SYNC_LOG="$WORK/syncs" "$DAEMON" --source "testsrc:fps=30,w=160,h=120" \
	--socket "$SOCK" --stats-interval 0 --sink rec=oni:"$WORK/session.oni" --stream rec=depth \
	2>"$WORK/log-kill" &
PID=$!
wait_for 10 test -S "$SOCK" || fail "no socket: $(cat "$WORK/log-kill")"
t_start=$(date +%s%N)
sleep 3
w0=$(stat_of "$SOCK" sinks.0.frames_out)
sleep 2.5 # more than one sync interval: the frames counted in w0 are synced by now
w1=$(stat_of "$SOCK" sinks.0.frames_out)
kill -KILL "$PID"
wait "$PID" 2>/dev/null || true
PID=
run_ms=$((($(date +%s%N) - t_start) / 1000000))
if [ ! -f "$WORK/session.oni" ]; then
	fail "no recording at its name after kill -9: $(ls "$WORK")"
else
	out=$("$ONI_CHECK" "$WORK/session.oni" 30) || fail "the killed recording does not read back: $out"
	frames=$(field frames "$out")
	header=$(field header "$out")
	echo "kill -9 after $run_ms ms: $out; the sink had written $w0 frames 2.5 s before, $w1 just before"
	[ "${frames:-0}" -ge "$w1" ] || fail "$frames frames recovered, the sink had written $w1"
	[ "${header:-0}" -ge "$w0" ] || fail "the header counts $header synced frames, $w0 were written 2.5 s before the kill"
	[ "$(field warning "$out")" = 1 ] || fail "no warning for an unfinished recording"
	[ "$w0" -ge 30 ] || fail "only $w0 frames in 3 s at 30 fps"
	# fdatasync about once a second, not per frame
	n_syncs=$(grep -c "fdatasync .*session.oni" "$WORK/syncs" 2>/dev/null || true)
	gap=$(grep "fdatasync .*session.oni" "$WORK/syncs" 2>/dev/null |
		awk 'NR > 1 && $1 - p > g { g = $1 - p } { p = $1 } END { print g + 0 }')
	echo "syncs: $n_syncs in $run_ms ms, longest gap $gap ms"
	[ "$n_syncs" -ge 3 ] || fail "$n_syncs syncs in $run_ms ms"
	[ "$n_syncs" -le $((run_ms / 1000 + 2)) ] || fail "$n_syncs syncs in $run_ms ms: more than one a second"
	[ "$gap" -le 2500 ] || fail "$gap ms between two syncs while frames came every 33 ms"
	# depthao process reads it, every frame, and says it was recovered
	"$DEPTHAO" process --input "$WORK/session.oni" --ao-out "$WORK/kill-ao" --quiet 2>"$WORK/err-kill" ||
		fail "depthao process: $(cat "$WORK/err-kill")"
	[ "$(count_png "$WORK/kill-ao")" -eq "${frames:-0}" ] ||
		fail "depthao process wrote $(count_png "$WORK/kill-ao") frames of $frames"
	grep -q "warning: .*session.oni.*not finalised" "$WORK/err-kill" ||
		fail "no warning from depthao process: $(cat "$WORK/err-kill")"
	# OpenNI2 plays it up to the last sync (the frame count in its header)
	if [ "$OPENNI2" -eq 1 ]; then
		$NI process --input "openni2:$WORK/session.oni" --ao-out "$WORK/kill-ni" --quiet \
			2>"$WORK/err-ni" || fail "OpenNI2 cannot play the killed recording: $(cat "$WORK/err-ni")"
		echo "OpenNI2 played $(count_png "$WORK/kill-ni") frames of the killed recording"
		[ "$(count_png "$WORK/kill-ni")" -eq "${header:-0}" ] ||
			fail "OpenNI2 played $(count_png "$WORK/kill-ni") frames, the header counts $header"
	fi
fi

# ---- 1b. the camera stops sending (no error): its last frames are synced within ~1 s ----
# The sink syncs when a frame comes a second after the last sync, and when it has been idle
# for a second; the 20 frames of a 0.6 s burst are counted in the header (synced) before the kill.
env LD_PRELOAD="$PRELOAD" ASAN_OPTIONS="$ASAN_PRELOAD" DAO_ENOSPC_PATH="$WORK/stall" DAO_ENOSPC_AFTER=1000000000000 \
	DAO_SYNC_LOG="$WORK/syncs-stall" "$DAEMON" --source "testsrc:fps=30,w=160,h=120,stall_after=20" \
	--socket "$SOCK" --stats-interval 0 --sink rec=oni:"$WORK/stall.oni" --stream rec=depth \
	2>"$WORK/log-stall" &
PID=$!
wait_for 10 test -S "$SOCK" || fail "no socket: $(cat "$WORK/log-stall")"
recorder_wrote() { [ "$(stat_of "$SOCK" sinks.0.frames_out 2>/dev/null)" = "$1" ]; }
wait_for 20 recorder_wrote 20 || fail "the recorder did not take 20 frames"
t_stall=$(date +%s%N)
# the idle flush comes 1 s after the last frame; waited for in the file itself (a fixed
# wait failed on a loaded host), up to 20 s
header_counts() { [ "$(field header "$("$ONI_CHECK" "$WORK/stall.oni" 30 2>/dev/null)")" = "$1" ]; }
wait_for 20 header_counts 20 || true
flush_ms=$((($(date +%s%N) - t_stall) / 1000000))
kill -KILL "$PID"
wait "$PID" 2>/dev/null || true
PID=
out=$("$ONI_CHECK" "$WORK/stall.oni" 30) || fail "the stalled recording does not read back: $out"
echo "camera stalled after 20 frames, header complete $flush_ms ms after the 20th frame was seen, then kill -9: $out"
[ "$(field frames "$out")" -eq 20 ] || fail "$(field frames "$out") frames in the stalled recording, 20 written"
[ "$(field header "$out")" -eq 20 ] || fail "the header counts $(field header "$out") synced frames of 20: the last frames were not synced while the camera was silent"
rm -f "$SOCK"

# ---- 2. started again (systemd after the crash): the next recording goes beside it ----
cp "$WORK/session.oni" "$WORK/session.copy" 2>/dev/null || true
"$DAEMON" --source "testsrc:fps=100,w=160,h=120" --max-frames 20 --stats-interval 0 \
	--sink rec=oni:"$WORK/session.oni" --stream rec=depth 2>"$WORK/log-again" ||
	fail "second run: $(cat "$WORK/log-again")"
cmp -s "$WORK/session.oni" "$WORK/session.copy" || fail "the killed recording was changed"
grep -q "session.oni exists; recording to $WORK/session-1.oni" "$WORK/log-again" ||
	fail "the log does not say where the new recording went: $(cat "$WORK/log-again")"
out=$("$ONI_CHECK" "$WORK/session-1.oni" 100) || fail "session-1.oni: $out"
[ "$(field frames "$out")" -eq 20 ] && [ "$(field warning "$out")" = 0 ] ||
	fail "session-1.oni: $out (expected 20 frames, finished)"

# ---- 3. a full disk, without root: writes to the recording fail after a byte budget ----
# 640x480 NONE frames are 614440 bytes; the preamble is under 1 KB: room for 5.5 frames
mkdir -p "$WORK/full"
env LD_PRELOAD="$PRELOAD" ASAN_OPTIONS="$ASAN_PRELOAD" DAO_ENOSPC_PATH="$WORK/full/" DAO_ENOSPC_AFTER=3380000 \
	"$DAEMON" --source "$REC" --playback manual --stats-json "$WORK/full.jsonl" \
	--sink rec=oni:"$WORK/full/rec.oni?codec=none" --stream rec=depth \
	--sink other=y4m:/dev/null 2>"$WORK/log-full" || echo "note: exit status $? (see the log)"
last=$(tail -n 1 "$WORK/full.jsonl")
rec_out=$(echo "$last" | "$JSON_GET" sinks.0.frames_out)
other_out=$(echo "$last" | "$JSON_GET" sinks.1.frames_out)
out=$("$ONI_CHECK" "$WORK/full/rec.oni" 30 any) || fail "the recording on the full disk: $out"
kept=$(field frames "$out")
echo "full disk (preload): $out; frames_out $rec_out; other sink $other_out"
[ "$kept" -eq 5 ] || fail "$kept frames kept, 5 fit"
[ "$rec_out" -eq "$kept" ] || fail "frames_out says $rec_out, the file keeps $kept"
[ "$other_out" -eq 16 ] || fail "the other sink wrote $other_out of 16 frames"
[ "$(field warning "$out")" = 0 ] || fail "the kept frames were not finalised: $out"
[ "$(ls "$WORK/full")" = rec.oni ] || fail "files on the full disk: $(ls "$WORK/full")"
lines=$(grep -c "sink rec.*No space left" "$WORK/log-full" || true)
[ "$lines" -ge 1 ] || fail "no error line names the full disk: $(cat "$WORK/log-full")"
echo "error lines about the full disk: $lines"
"$DEPTHAO" process --input "$WORK/full/rec.oni" --ao-out "$WORK/full-ao" --quiet ||
	fail "depthao process cannot read the kept frames"
"$DEPTHAO" process --input "$REC" --ao-out "$WORK/ref-ao" --quiet
same_ao "$WORK/full-ao" "$WORK/ref-ao" "$kept" || fail "the kept frames are not the recorded ones"
if [ "$OPENNI2" -eq 1 ]; then
	$NI process --input "openni2:$WORK/full/rec.oni" --ao-out "$WORK/full-ni" --quiet \
		2>"$WORK/err-ni2" || fail "OpenNI2: $(cat "$WORK/err-ni2")"
	[ "$(count_png "$WORK/full-ni")" -eq "$kept" ] ||
		fail "OpenNI2 played $(count_png "$WORK/full-ni") of $kept frames"
fi

# the y4m sink on a full disk: the header and whole frames (6 + 640x480x3 bytes each)
mkdir -p "$WORK/full-y4m"
hdr=$(printf 'YUV4MPEG2 W640 H480 F30:1 Ip A1:1 C444\n' | wc -c)
frame=$((6 + 3 * 640 * 480))
env LD_PRELOAD="$PRELOAD" ASAN_OPTIONS="$ASAN_PRELOAD" DAO_ENOSPC_PATH="$WORK/full-y4m/" \
	DAO_ENOSPC_AFTER=$((hdr + 4 * frame + frame / 2)) \
	"$DAEMON" --source "$REC" --playback manual --stats-json "$WORK/y4m.jsonl" \
	--sink vid=y4m:"$WORK/full-y4m/out.y4m" 2>"$WORK/log-y4m" || echo "note: exit status $?"
size=$(stat -c %s "$WORK/full-y4m/out.y4m")
vid_out=$(tail -n 1 "$WORK/y4m.jsonl" | "$JSON_GET" sinks.0.frames_out)
echo "full disk, y4m: $size bytes, frames_out $vid_out"
[ "$size" -eq $((hdr + 4 * frame)) ] || fail "y4m on a full disk: $size bytes, expected $((hdr + 4 * frame))"
[ "$vid_out" -eq 4 ] || fail "y4m frames_out $vid_out, the file keeps 4"

# ---- 4. a full tmpfs (root): the same, on a real file system ------------------------
if [ "$(id -u)" -ne 0 ] || ! unshare -m true 2>/dev/null; then
	echo "note: not root or no mount namespaces; the tmpfs part is skipped"
else
	mkdir -p "$WORK/tmpfs" "$WORK/saved"
	status=0
	unshare -m sh -c '
		mount -t tmpfs -o size=4m tmpfs "$1" || exit 90
		"$2" --source "$3" --playback manual --stats-json "$4/tmpfs.jsonl" \
			--sink rec=oni:"$1/rec.oni?codec=none" --stream rec=depth \
			--sink other=y4m:/dev/null 2>"$4/log-tmpfs"
		status=$?
		cp -a "$1/." "$5/"
		exit $status' sh "$WORK/tmpfs" "$DAEMON" "$REC" "$WORK" "$WORK/saved" || status=$?
	if [ "$status" -eq 90 ]; then
		echo "note: cannot mount a tmpfs here; the tmpfs part is skipped"
	else
		out=$("$ONI_CHECK" "$WORK/saved/rec.oni" 30 any) || fail "tmpfs: $out"
		kept=$(field frames "$out")
		rec_out=$(tail -n 1 "$WORK/tmpfs.jsonl" | "$JSON_GET" sinks.0.frames_out)
		echo "full tmpfs (4 MB): $out; frames_out $rec_out; exit $status"
		[ "$kept" -ge 5 ] && [ "$kept" -le 6 ] || fail "tmpfs: $kept frames kept (4 MB holds 6)"
		[ "$rec_out" -eq "$kept" ] || fail "tmpfs: frames_out $rec_out, the file keeps $kept"
		[ "$(ls "$WORK/saved")" = rec.oni ] || fail "files on the tmpfs: $(ls "$WORK/saved")"
		other_out=$(tail -n 1 "$WORK/tmpfs.jsonl" | "$JSON_GET" sinks.1.frames_out)
		[ "$other_out" -eq 16 ] || fail "tmpfs: the sink beside it wrote $other_out of 16 frames"
		grep -q "sink rec.*No space left" "$WORK/log-tmpfs" || fail "tmpfs: no error line: $(cat "$WORK/log-tmpfs")"
		"$DEPTHAO" process --input "$WORK/saved/rec.oni" --ao-out "$WORK/tmpfs-ao" --quiet ||
			fail "tmpfs: depthao process cannot read the kept frames"
		same_ao "$WORK/tmpfs-ao" "$WORK/ref-ao" "$kept" || fail "tmpfs: the kept frames differ"
		if [ "$OPENNI2" -eq 1 ]; then
			$NI process --input "openni2:$WORK/saved/rec.oni" --ao-out "$WORK/tmpfs-ni" \
				--quiet 2>/dev/null || fail "tmpfs: OpenNI2 cannot play the kept frames"
			[ "$(count_png "$WORK/tmpfs-ni")" -eq "$kept" ] || fail "tmpfs: OpenNI2 played $(count_png "$WORK/tmpfs-ni")"
		fi
	fi
fi

# ---- 5. ctl snapshot into a FIFO, a character device, a directory ------------------
start_daemon "$WORK/log-snap" --source "testsrc:fps=30" --socket "$SOCK" --stats-interval 0 \
	--sink null=y4m:/dev/null
wait_for 10 test -S "$SOCK" || fail "no socket: $(cat "$WORK/log-snap")"
mkfifo "$WORK/snap.fifo"
timeout 20 cat "$WORK/snap.fifo" >"$WORK/from-fifo.png" &
reader=$!
sleep 0.2
"$DEPTHAO" ctl --socket "$SOCK" snapshot "$WORK/snap.fifo" >"$WORK/ctl-out" 2>&1 ||
	fail "snapshot into a FIFO: $(cat "$WORK/ctl-out")"
wait "$reader" || true
[ -p "$WORK/snap.fifo" ] || fail "the FIFO was replaced by the snapshot"
"$PNG_INFO" "$WORK/from-fifo.png" | grep -q "64 48 rgb24" || fail "the FIFO's reader got no PNG"
mkdir "$WORK/snapdir"
if "$DEPTHAO" ctl --socket "$SOCK" snapshot "$WORK/snapdir" >"$WORK/ctl-out" 2>&1; then
	fail "a snapshot into a directory succeeded"
fi
grep -q "directory" "$WORK/ctl-out" || fail "snapshot into a directory: $(cat "$WORK/ctl-out")"
if [ "$(id -u)" -eq 0 ]; then
	mknod "$WORK/null" c 1 3
	"$DEPTHAO" ctl --socket "$SOCK" snapshot "$WORK/null" >"$WORK/ctl-out" 2>&1 ||
		fail "snapshot into a character device: $(cat "$WORK/ctl-out")"
	[ -c "$WORK/null" ] || fail "the character device was replaced by the snapshot"
fi
stop_daemon || true
finish
