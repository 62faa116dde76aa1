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
# the recorder stores the camera the pipeline used: configured intrinsics as its FOV
"$DAEMON" --source "$REC" --playback manual --max-frames 2 --set source.fov=60,45 \
	--sink rec=oni:"$WORK/fov.oni" --stream rec=depth 2>"$WORK/log-fov" || fail "fov run"
"$DEPTHAO" process --input "$WORK/fov.oni" --ao-out "$WORK/fov-ao" 2>&1 |
	grep -q "field of view from the source: 60.00 x 45.00 degrees" || fail "the recorder did not keep the configured FOV"

# y4m to stdout, for '| ffplay -': header + 16 x (FRAME\n + 640x480 4:4:4)
bytes=$("$DAEMON" --source "$REC" --playback manual --sink y4m:- 2>"$WORK/log-stdout" | wc -c)
hdr=$(head -n 1 "$WORK/out.y4m" | wc -c)
[ "$bytes" -eq $((hdr + 16 * (6 + 3 * 640 * 480))) ] || fail "y4m on stdout: $bytes bytes"

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

# the opencv plugin (when built): an MJPG video with every frame; a window without a
# display stays off and does not disturb the other sinks
if [ -n "${DAO_VIDEO_INFO:-}" ]; then
	env -u DISPLAY -u WAYLAND_DISPLAY "$DAEMON" --source "$REC" --playback manual \
		--sink vid=opencv:"$WORK/out.avi" --sink win=opencv:window \
		--sink png=images:"$WORK/v-png" 2>"$WORK/log-cv" || fail "opencv run: $(cat "$WORK/log-cv")"
	info=$("$DAO_VIDEO_INFO" "$WORK/out.avi") || fail "the video does not read back"
	[ "$info" = "16 640 480" ] || fail "video: '$info', expected 16 frames of 640x480"
	grep -q "sink win .*no display.*stays off" "$WORK/log-cv" || fail "window without display: $(cat "$WORK/log-cv")"
	[ "$(ls "$WORK/v-png" | wc -l)" -eq 16 ] || fail "the PNG sink beside the window lost frames"
	# with a display (Xvfb), the window shows every frame and closes cleanly at the end
	if command -v xvfb-run >/dev/null; then
		xvfb-run -a -s "-screen 0 800x600x24" "$DAEMON" --source "$REC" --playback manual \
			--sink win=opencv:window:test 2>"$WORK/log-win" || fail "window run: $(cat "$WORK/log-win")"
		grep -q "stats: sink win: 16 out, 0 dropped" "$WORK/log-win" || fail "window: $(cat "$WORK/log-win")"
	else
		echo "note: no xvfb-run; the window was not shown"
	fi
else
	echo "note: the opencv plugin is not built; its part was skipped"
fi

# colour sources: the overlay stream (Kinect recording through OpenNI2, when both exist);
# the recorder's file plays in OpenNI2 itself
KINECT="${DAO_SHARED_DATA:-$ROOT/../shared/data}/oni/3DJ_test.oni"
if "$DEPTHAO" devices | grep -q "^  openni2 " && [ -r "$KINECT" ]; then
	"$DAEMON" --source "openni2:$KINECT" --playback manual --max-frames 4 \
		--sink ov=images:"$WORK/overlay" --stream ov=overlay 2>"$WORK/log-ov" ||
		fail "overlay run: $(cat "$WORK/log-ov")"
	"$PNG_INFO" "$WORK/overlay/000002.png" | grep -q "640 480 rgb24" ||
		fail "overlay frames: $(ls "$WORK/overlay" 2>&1) $(cat "$WORK/log-ov")"
	"$DEPTHAO" process --input "openni2:$WORK/depth.oni" --ao-out "$WORK/ni-replay" --quiet ||
		fail "OpenNI2 cannot play the recorder's file"
	cmp -s "$WORK/ni-replay/000009.png" "$WORK/ao/000009.png" ||
		echo "note: OpenNI2 replay differs in AO (its FOV is single precision)"
	[ "$(ls "$WORK/ni-replay" | wc -l)" -eq 16 ] || fail "OpenNI2 replay: not 16 frames"
else
	echo "note: openni2 plugin or the Kinect recording absent; the colour part was skipped"
fi

# logs under systemd carry journald priorities and no timestamps
JOURNAL_STREAM=8:1234 "$DAEMON" --source "$REC" --playback manual --max-frames 1 \
	--sink j=images:"$WORK/j" 2>"$WORK/log-j" || fail "journald run"
grep -q '^<6>depthaod ' "$WORK/log-j" || fail "journald format: $(cat "$WORK/log-j")"
grep -v '^<[0-7]>' "$WORK/log-j" | grep -q . && fail "lines without a priority: $(cat "$WORK/log-j")"

# SIGTERM while running (looping, real time): stops within a second, files finalised
start_daemon "$WORK/log2" --source "$REC" --loop --sink rec=oni:"$WORK/live.oni" --stream rec=depth \
	--sink png=images:"$WORK/live"
# (frames are named by their index in the loop; on a busy host some are dropped)
wait_for 20 sh -c "[ \$(ls '$WORK/live' 2>/dev/null | wc -l) -ge 3 ]" ||
	fail "no output while running: $(cat "$WORK/log2")"
stop_daemon || fail "exit status after SIGTERM"
"$DEPTHAO" process --input "$WORK/live.oni" --ao-out "$WORK/live-replay" --quiet ||
	fail "the .oni recorded until SIGTERM is not readable: $(cat "$WORK/log2")"
find "$WORK" -name '*.tmp-*' -o -name 'live.oni.*' | grep -q . && fail "temporary files left after SIGTERM"
grep -q "SIGTERM: stopping" "$WORK/log2" || fail "log: $(cat "$WORK/log2")"
finish
