#!/bin/sh
# SPDX-License-Identifier: MIT
# Bad configurations: each is exit 2 with a message naming file:line and key.
. "$(dirname "$0")/daemon_lib.sh"

good="[source]
uri = $REC
[sink.a]
uri = images:$WORK/a"
printf '%s\n' "$good" >"$WORK/good.ini"
"$DAEMON" --check-config "$WORK/good.ini" >"$WORK/out" 2>&1 || fail "good config: $(cat "$WORK/out")"
grep -q "good.ini: ok" "$WORK/out" || fail "check output: $(cat "$WORK/out")"

# the example configuration that is installed is valid
"$DAEMON" --check-config "$ROOT/data/depthaod.ini" >"$WORK/out" 2>&1 || fail "data/depthaod.ini: $(cat "$WORK/out")"

# check NAME "EXTRA LINES" "EXPECTED MESSAGE PART"
check() {
	printf '%s\n%s\n' "$good" "$2" >"$WORK/$1.ini"
	set +e
	"$DAEMON" --check-config "$WORK/$1.ini" >"$WORK/out" 2>&1
	st=$?
	set -e
	[ "$st" -eq 2 ] || fail "$1: exit $st, expected 2: $(cat "$WORK/out")"
	grep -q -- "$3" "$WORK/out" || fail "$1: message '$(cat "$WORK/out")' lacks '$3'"
}
check unknown_key "[sink.a]
colour = red" "unknown_key.ini:6: \[sink.a\] colour: unknown key"
check unknown_section "[camera]
fx = 5" "unknown_section.ini:6: \[camera\]: unknown section"
check bad_radius "[ao]
radius = -1" "bad_radius.ini:6: \[ao\] radius"
check unknown_param "[ao]
radiance = 1" "unknown_param.ini:6: \[ao\] radiance: unknown AO parameter"
check bad_playback "[source]
playback = slow" "bad_playback.ini:6: \[source\] playback: 'slow' must be realtime or manual"
check bad_queue "[sink.a]
queue = 0" "bad_queue.ini:6: \[sink.a\] queue"
check bad_stream "[sink.a]
stream = colour" "bad_stream.ini:6: \[sink.a\] stream"
check bad_fov "[source]
fov = 200,40" "bad_fov.ini:6: \[source\] fov"
check bad_level "[daemon]
log_level = loud" "bad_level.ini:6: \[daemon\] log_level"
check garbage "this is not ini" "garbage.ini:5: not 'key = value'"
check both_camera "[source]
fov = 60,45
intrinsics = 500,500,320,240" "give intrinsics or fov, not both"
# [source] intrinsics (issue 38): the error names the value and what to give instead
check intr_huge "[source]
intrinsics = 1e308,1e308,320,240" "intr_huge.ini:6: \[source\] intrinsics: focal length fx=1e+308 is implausible: give pixels in (0, 1.6384e+07\]"
check intr_zero_fy "[source]
intrinsics = 500,0,320,240" "intrinsics: focal length fy=0 is implausible"
check intr_center "[source]
intrinsics = 500,500,320,-1e9" "intrinsics: principal point cy=-1e+09 is implausible: give pixels, near the image centre (from -16384 to 32768"
check intr_denormal "[source]
intrinsics = 5e-324,500,320,240" "intrinsics: '5e-324,500,320,240' must be four numbers fx,fy,cx,cy in pixels"
check intr_three "[source]
intrinsics = 500,500,320" "intrinsics: '500,500,320' must be four numbers"
check intr_nan "[source]
intrinsics = nan,500,320,240" "intrinsics: 'nan,500,320,240' must be four numbers"
check intr_path "[source]
intrinsics = cam/kinect.yaml" "intrinsics: 'cam/kinect.yaml' is not four numbers: a camera file goes in intrinsics_file = PATH"
# a camera file that is not one: refused when the config is read, saying why
mkfifo "$WORK/cam.fifo"
check intr_fifo "[source]
intrinsics_file = $WORK/cam.fifo" "intrinsics_file: camera file '.*cam.fifo' is a FIFO (named pipe), not a regular file"
printf 'image_width: 640\nimage_height: 480\ncamera_matrix:\n  rows: 3\n  cols: 3\n  data: [500, 0, 1e9, 0, 500, 240, 0, 0, 1]\n' >"$WORK/cx.yaml"
check intr_file_center "[source]
intrinsics_file = $WORK/cx.yaml" "intrinsics_file: camera file '.*cx.yaml': .*principal point cx=1e+09 is implausible for 640x480 images"
# plausible for some image but not for the source's 640x480: the pipeline's error says
# which setting and the range for this size (it said 'bad camera or out of memory')
printf '%s\n[source]\nintrinsics = 1000000,1000000,320,240\n' "$good" >"$WORK/intr_run.ini"
"$DAEMON" --check-config "$WORK/intr_run.ini" >"$WORK/out" 2>&1 || fail "intr_run: --check-config: $(cat "$WORK/out")"
set +e
timeout 20 "$DAEMON" -c "$WORK/intr_run.ini" >"$WORK/out" 2>&1
set -e
grep -q "cannot set up the pipeline for 640x480 frames: \[source\] intrinsics: focal length fx=1e+06 is implausible for 640x480 images: give pixels, from 3.2 to 640000" "$WORK/out" ||
	fail "intr_run: the pipeline's error lacks the setting and its range: $(head -5 "$WORK/out")"
printf '[sink.a]\nuri = images:x\n' >"$WORK/nosource.ini"
set +e
"$DAEMON" --check-config "$WORK/nosource.ini" >"$WORK/out" 2>&1
st=$?
set -e
[ "$st" -eq 2 ] && grep -q "nosource.ini: \[source\] uri is required" "$WORK/out" || fail "no source: $st $(cat "$WORK/out")"
# a missing file, and a bad command-line override
set +e
"$DAEMON" -c "$WORK/nonexistent.ini" >"$WORK/out" 2>&1
st=$?
set -e
[ "$st" -eq 2 ] && grep -q "cannot open configuration file '.*/nonexistent.ini': No such file" "$WORK/out" || fail "missing file: $st $(cat "$WORK/out")"
set +e
"$DAEMON" -c "$WORK/good.ini" --radius nine >"$WORK/out" 2>&1
st=$?
set -e
[ "$st" -eq 2 ] && grep -q "command line: \[ao\] radius" "$WORK/out" || fail "bad override: $st $(cat "$WORK/out")"
finish
