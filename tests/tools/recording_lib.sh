# SPDX-License-Identifier: MIT
# Helpers for the CLI tests of recorded formats (ROS bag, MCAP, rosbag2 .db3): sourced after
# cli_lib.sh.  Each such test makes its recordings with an independent writer, beside the
# same frames as 16-bit PNGs with camera.json (DIR/png: 5 frames, 64x48), and checks that
# depthao process gives the recording the same AO as the PNGs.

# The intrinsics of the CameraInfo the writers store, as depthao process reports them.
REC_INTRINSICS="fx 60.00 fy 61.00 cx 31.50 cy 23.25"
REC_FRAMES="000000 000001 000002 000003 000004"

# need_program PROGRAM: the test is skipped (exit 77) when PROGRAM is not installed
need_program() {
	command -v "$1" >/dev/null 2>&1 || { echo "SKIP: $1 is not installed"; exit 77; }
}

# make_recordings COMMAND...: runs the writer; its exit 77 (what it needs is missing, which
# it said) skips the test, any other failure fails it
make_recordings() {
	set +e
	"$@"
	st=$?
	set -e
	[ "$st" -eq 77 ] && exit 77
	[ "$st" -eq 0 ] || { echo "$* failed ($st)"; exit 1; }
}

# png_reference DIR: the reference AO and shaded images of DIR/png (no temporal filter on
# PNGs) in $WORK/png-ao and $WORK/png-sh, with the intrinsics of DIR/png/camera.json
png_reference() {
	expect_exit 0 "PNG frames" -- "$DEPTHAO" process --input "$1/png" --ao-out "$WORK/png-ao" \
		--shaded-out "$WORK/png-sh" || return 0
	grep -q "using intrinsics from" "$WORK/err" ||
		fail "PNG run did not use camera.json: $(cat "$WORK/err")"
	[ "$(ls "$WORK/png-ao" | wc -l)" -eq 5 ] || fail "PNG run: $(ls "$WORK/png-ao" | wc -l) AO files"
}

# same_as_png NAME INPUT [OPTIONS...]: depthao process on INPUT (the temporal depth filter
# off, a recording being a stream) uses the CameraInfo's intrinsics without a warning and
# gives the 5 AO and shaded images of the PNG run, to the byte ($WORK/NAME-ao, NAME-sh)
same_as_png() {
	name=$1 input=$2
	shift 2
	same_as_run png "$name" "$input" "$@"
}

# recording_run NAME INPUT [OPTIONS...]: depthao process on INPUT (the temporal depth filter
# off, a recording being a stream) writes 5 AO and shaded images ($WORK/NAME-ao, NAME-sh),
# with the CameraInfo's intrinsics and without a warning; 1 if it did not exit 0
recording_run() {
	name=$1 input=$2
	shift 2
	expect_exit 0 "$name" -- "$DEPTHAO" process --input "$input" --depth-temporal 0 \
		--ao-out "$WORK/$name-ao" --shaded-out "$WORK/$name-sh" "$@" || return 1
	grep -q "intrinsics from the source: $REC_INTRINSICS" "$WORK/err" ||
		fail "$name: intrinsics not from the CameraInfo: $(cat "$WORK/err")"
	grep -q "warning" "$WORK/err" && fail "$name: a warning: $(cat "$WORK/err")"
	[ "$(ls "$WORK/$name-ao" | wc -l)" -eq 5 ] || fail "$name: $(ls "$WORK/$name-ao" | wc -l) AO files"
	return 0
}

# same_as_run REF NAME INPUT [OPTIONS...]: as same_as_png, against the AO and shaded images
# of an earlier run ($WORK/REF-ao, $WORK/REF-sh: png_reference's, a recording_run's)
same_as_run() {
	ref=$1 name=$2
	shift
	recording_run "$@" || return 0
	for i in $REC_FRAMES; do
		cmp -s "$WORK/$name-ao/$i.png" "$WORK/$ref-ao/$i.png" || fail "$name: AO $i differs from the $ref run"
		cmp -s "$WORK/$name-sh/$i.png" "$WORK/$ref-sh/$i.png" || fail "$name: shaded $i differs from the $ref run"
	done
}

# frames_as_png WHAT DIR FRAME...: DIR holds exactly those AO frames, each the PNG run's
frames_as_png() {
	what=$1 dir=$2
	shift 2
	want=$(for i in "$@"; do printf '%s.png ' "$i"; done)
	[ "$(ls "$dir" | tr '\n' ' ')" = "$want" ] || fail "$what wrote: $(ls "$dir" | tr '\n' ' ')"
	for i in "$@"; do
		cmp -s "$dir/$i.png" "$WORK/png-ao/$i.png" || fail "$what: AO $i differs from the PNG run"
	done
}

# start_frames INPUT REPORT: depthao process --start 2 --frames 2 on INPUT reports REPORT (the
# topic and its frame count) and writes frames 2 and 3, the PNG run's
start_frames() {
	rm -rf "$WORK/start"
	expect_exit 0 "$1 --start 2 --frames 2" -- "$DEPTHAO" process --input "$1" --start 2 \
		--frames 2 --depth-temporal 0 --ao-out "$WORK/start" || return 0
	grep -qF "$2" "$WORK/err" || fail "$1: the frame count: $(cat "$WORK/err")"
	frames_as_png "$1 --start 2 --frames 2" "$WORK/start" 000002 000003
}

# unit_as_png DIR INPUT: INPUT (a recording with ?unit=0.0001 or a depth unit of 0.1 mm)
# gives the AO of DIR/png read with --depth-unit 0.0001 ($WORK/png-unit), frame by frame,
# which differs from the PNG run at 1 mm
unit_as_png() {
	[ -d "$WORK/png-unit" ] ||
		expect_exit 0 "PNG frames at 0.1 mm" -- "$DEPTHAO" process --input "$1/png" \
			--depth-unit 0.0001 --ao-out "$WORK/png-unit" --quiet
	rm -rf "$WORK/unit"
	expect_exit 0 "$2" -- "$DEPTHAO" process --input "$2" --depth-temporal 0 \
		--ao-out "$WORK/unit" --quiet || return 0
	[ "$(ls "$WORK/unit" | wc -l)" -eq 5 ] || fail "$2: $(ls "$WORK/unit" | wc -l) AO files"
	for i in $REC_FRAMES; do
		cmp -s "$WORK/unit/$i.png" "$WORK/png-unit/$i.png" || fail "$2: AO $i differs from 0.1 mm PNGs"
	done
	cmp -s "$WORK/unit/000000.png" "$WORK/png-ao/000000.png" && fail "$2: the 0.1 mm unit changed nothing"
	return 0
}

# process_fails INPUT MESSAGE [OPTIONS...]: depthao process on INPUT exits 1 and its stderr
# holds MESSAGE (a fixed string)
process_fails() {
	input=$1 msg=$2
	shift 2
	expect_exit 1 "$input" -- "$DEPTHAO" process --input "$input" --ao-out "$WORK/bad" --quiet "$@" ||
		return 0
	grep -qF "$msg" "$WORK/err" || fail "$input: $(cat "$WORK/err")"
}
