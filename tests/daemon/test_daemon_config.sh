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
