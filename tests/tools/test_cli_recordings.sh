#!/bin/sh
# SPDX-License-Identifier: MIT
# process on .oni recordings (the bundled ones, one synth writes, the real Kinect
# recording), --start/--frames, devices, and the errors a user can cause.
. "$(dirname "$0")/cli_lib.sh"

ROOT=${DAO_SOURCE_ROOT:?}
REC="$ROOT/recordings/spheres-rolling.oni"

# the bundled recording: every frame, numbered by frame, FOV from the file
expect_exit 0 "bundled recording" -- "$DEPTHAO" process --input "$REC" \
	--ao-out "$WORK/all/ao" --shaded-out "$WORK/all/sh"
n=$(ls "$WORK/all/ao" | wc -l)
[ "$n" -eq 16 ] || fail "bundled recording: $n AO files, expected 16"
png_is "$WORK/all/ao/000015.png" "640 480 gray16"
png_is "$WORK/all/sh/000000.png" "640 480 rgb24"
grep -q "field of view from the source" "$WORK/err" || fail "FOV not taken from the file: $(cat "$WORK/err")"
no_temp_files "$WORK/all"
# consecutive frames differ (the sphere rolls), so playback is animated
cmp -s "$WORK/all/ao/000000.png" "$WORK/all/ao/000015.png" && fail "first and last frames are identical"

# --start/--frames pick frames by index; without the temporal depth filter (whose
# history depends on the frames before) they give the same pixels as a full run
expect_exit 0 "start/frames" -- "$DEPTHAO" process --input "oni:$REC" --start 5 --frames 3 \
	--ao-out "$WORK/part" --quiet
[ "$(ls "$WORK/part" | tr '\n' ' ')" = "000005.png 000006.png 000007.png " ] ||
	fail "start/frames wrote: $(ls "$WORK/part" | tr '\n' ' ')"
expect_exit 0 "start/frames, filter off" -- "$DEPTHAO" process --input "oni:$REC" --start 5 \
	--frames 3 --depth-temporal 0 --ao-out "$WORK/part-off" --quiet
expect_exit 0 "first frames, filter off" -- "$DEPTHAO" process --input "$REC" --frames 7 \
	--depth-temporal 0 --ao-out "$WORK/head-off" --quiet
cmp -s "$WORK/part-off/000006.png" "$WORK/head-off/000006.png" || fail "frame 6 differs from the full run"
# a recording is a stream: the temporal depth filter is on (0.8) unless turned off; the
# first frame of a run has no history yet
expect_exit 0 "start/frames, filter 0.8" -- "$DEPTHAO" process --input "oni:$REC" --start 5 \
	--frames 3 --depth-temporal 0.8 --ao-out "$WORK/part-on" --quiet
for f in 5 6 7; do
	cmp -s "$WORK/part/00000$f.png" "$WORK/part-on/00000$f.png" ||
		fail "frame $f: the default is not --depth-temporal 0.8"
done
cmp -s "$WORK/part/000005.png" "$WORK/part-off/000005.png" || fail "frame 5: the first frame was filtered"
cmp -s "$WORK/part/000007.png" "$WORK/part-off/000007.png" &&
	fail "frame 7: the temporal depth filter changed nothing where the sphere rolls"
# PNG input is not: a directory's files need not follow each other
NOISY="$ROOT/recordings/spheres-noisy"
expect_exit 0 "PNG directory" -- "$DEPTHAO" process --input "$NOISY" --ao-out "$WORK/png-dir" --quiet
expect_exit 0 "PNG directory, filter off" -- "$DEPTHAO" process --input "$NOISY" --depth-temporal 0 \
	--ao-out "$WORK/png-off" --quiet
expect_exit 0 "PNG directory, filter on" -- "$DEPTHAO" process --input "$NOISY" --depth-temporal 0.8 \
	--ao-out "$WORK/png-on" --quiet
cmp -s "$WORK/png-dir/0003.png" "$WORK/png-off/0003.png" || fail "PNG input: the filter was on by default"
cmp -s "$WORK/png-dir/0003.png" "$WORK/png-on/0003.png" && fail "PNG input: --depth-temporal 0.8 changed nothing"

# synth writes a recording that process reads back
expect_exit 0 "synth --oni" -- "$DEPTHAO" synth --scene boxes --frames 3 --rays 1 --oni 16z \
	--out "$WORK/syn"
[ -s "$WORK/syn/boxes.oni" ] || fail "synth wrote no boxes.oni"
expect_exit 0 "synth recording" -- "$DEPTHAO" process --input "$WORK/syn/boxes.oni" \
	--ao-out "$WORK/syn-ao" --quiet
[ "$(ls "$WORK/syn-ao" | wc -l)" -eq 3 ] || fail "synth recording: not 3 frames"
# the depth PNG frame 1 and the recording's frame 1 shade identically (same camera; the
# boxes stand still and the depth is clean: the temporal depth filter passes it unchanged)
expect_exit 0 "png frame" -- "$DEPTHAO" process --input "$WORK/syn/boxes/depth/0001.png" \
	--ao-out "$WORK/png1.png" --frame-index 1 --quiet
cmp -s "$WORK/png1.png" "$WORK/syn-ao/000001.png" || fail ".oni and PNG frame 1 give different AO"

# a PNG directory through the images source gives the same AO as the PNG path
expect_exit 0 "images source" -- "$DEPTHAO" process --input "images:$WORK/syn/boxes/depth" \
	--ao-out "$WORK/img" --quiet
cmp -s "$WORK/img/000001.png" "$WORK/png1.png" || fail "images:DIR frame 1 differs from the PNG path"

# compare: the algorithms side by side (depth, ground truth, 5 algorithms at half size)
expect_exit 0 "compare" -- "$DEPTHAO" compare --scene floating-plate --rays 1 --out "$WORK/cmp.png"
png_is "$WORK/cmp.png" "1280 480 rgb24"
expect_usage_error "compare without input" -- "$DEPTHAO" compare --out "$WORK/x.png"

# errors a user can cause
expect_exit 1 "--start past the end" -- "$DEPTHAO" process --input "$REC" --start 99 --ao-out "$WORK/x"
grep -q "start frame 99 is past the end" "$WORK/err" || fail "start past end: $(cat "$WORK/err")"
expect_exit 1 "unknown plugin" -- "$DEPTHAO" process --input "nosuch:x" --ao-out "$WORK/x"
grep -q "no source plugin 'nosuch'.*available: oni" "$WORK/err" || fail "unknown plugin: $(cat "$WORK/err")"
printf 'NI10garbage' >"$WORK/bad.oni"
expect_exit 1 "corrupt recording" -- "$DEPTHAO" process --input "$WORK/bad.oni" --ao-out "$WORK/x"
grep -q "bad.oni" "$WORK/err" || fail "corrupt recording: $(cat "$WORK/err")"
expect_usage_error "--frames on PNG input" -- "$DEPTHAO" process --input "$WORK/png1.png" --frames 2 \
	--ao-out "$WORK/y.png"
expect_usage_error "--frames 0" -- "$DEPTHAO" process --input "$REC" --frames 0 --ao-out "$WORK/x"

# devices lists the built-in source and says where plugins come from; every plugin
# that was built loads (an unresolved symbol in a module shows up here)
expect_exit 0 "devices" -- "$DEPTHAO" devices
grep -q "oni .*built-in" "$WORK/out" || fail "devices: $(cat "$WORK/out")"
grep -q "not loaded" "$WORK/out" && fail "a plugin did not load: $(grep "not loaded" "$WORK/out")"
# libcamera without a camera: a clear error
if grep -q "^  libcamera " "$WORK/out" && ! grep -q "libcamera:" "$WORK/out"; then
	expect_exit 1 "libcamera without a camera" -- "$DEPTHAO" process --input libcamera:any \
		--frames 1 --ao-out "$WORK/lc"
	grep -q "no cameras found" "$WORK/err" || fail "libcamera: $(cat "$WORK/err")"
fi

# from the build tree, the plugins built beside depthao are found without DEPTHAO_PLUGIN_PATH
if env -u DEPTHAO_PLUGIN_PATH "$DEPTHAO" devices | grep -q "^  openni2 "; then
	expect_exit 0 "openni2 Dummy device" -- env -u DEPTHAO_PLUGIN_PATH "$DEPTHAO" process \
		--input openni2:Dummy --frames 2 --ao-out "$WORK/dummy" --quiet
	png_is "$WORK/dummy/000001.png" "320 240 gray16"
	expect_exit 0 "openni2 playback" -- env -u DEPTHAO_PLUGIN_PATH "$DEPTHAO" process \
		--input "openni2:$REC" --start 14 --ao-out "$WORK/ni" --quiet
	[ "$(ls "$WORK/ni" | tr '\n' ' ')" = "000014.png 000015.png " ] ||
		fail "openni2 playback wrote: $(ls "$WORK/ni" | tr '\n' ' ')"
else
	echo "note: the openni2 plugin is not built; its part was skipped"
fi

# the real Kinect recording (../shared/data), when present
DATA=${DAO_SHARED_DATA:-../shared/data}
if [ -r "$DATA/oni/3DJ_test.oni" ]; then
	expect_exit 0 "kinect recording" -- "$DEPTHAO" process --input "$DATA/oni/3DJ_test.oni" \
		--frames 2 --shaded-out "$WORK/kinect" --quiet
	png_is "$WORK/kinect/000001.png" "640 480 rgb24"
	# a damaged JPEG colour frame is not decoded silently (issue 38): a warning for that
	# frame, the others written, the count at the end and exit 1; the intact recording
	# overlays all 12 frames with status 0
	expect_exit 0 "kinect overlay" -- "$DEPTHAO" process --input "$DATA/oni/3DJ_test.oni" \
		--overlay-out "$WORK/kov" --quiet
	[ "$(ls "$WORK/kov" | wc -l)" -eq 12 ] || fail "kinect overlay: $(ls "$WORK/kov" | wc -l) files"
	grep -q "warning" "$WORK/err" && fail "kinect overlay warns: $(cat "$WORK/err")"
	if command -v python3 >/dev/null; then
		for mode in zero arith; do
			python3 "$ROOT/tests/tools/oni_damage.py" "$DATA/oni/3DJ_test.oni" \
				"$WORK/$mode.oni" "$mode"
			if expect_exit 1 "JPEG damage ($mode)" -- "$DEPTHAO" process \
				--input "$WORK/$mode.oni" --overlay-out "$WORK/ov-$mode" --quiet; then
				case $mode in
				zero) want="frame 0 of 'Image1' is corrupt: damaged JPEG data: Corrupt JPEG data" ;;
				arith) want="frame 0 of 'Image1' is corrupt: an arithmetic-coded JPEG (SOF9)" ;;
				esac
				grep -q "warning: a frame is skipped: $want" "$WORK/err" ||
					fail "JPEG damage ($mode): no per-frame warning: $(cat "$WORK/err")"
				grep -q "1 frame of '$WORK/$mode.oni' could not be read and was skipped" \
					"$WORK/err" || fail "JPEG damage ($mode): no count: $(cat "$WORK/err")"
				n=$(ls "$WORK/ov-$mode" | wc -l)
				[ "$n" -eq 11 ] || fail "JPEG damage ($mode): $n overlays, expected 11"
			fi
		done
	fi
else
	echo "note: $DATA/oni/3DJ_test.oni not found; the Kinect part was skipped"
fi

# .oni damage is not an interrupted recording (issue 38): a record whose size runs past
# the end while records follow is an error naming it; the same record cut by the end
# of the file is recovered with the warning, status 0
RG=$ROOT/tests/oni/regress
if expect_exit 1 "damaged record size" -- "$DEPTHAO" process \
	--input "$RG/corrupt-payload-size-mid-file.oni" --fov 60,45 --ao-out "$WORK/dmg"; then
	grep -q "corrupt .oni file: record 13 at byte 1228: size 4294967335 runs past the end, yet a record follows at byte 1750: damage, not an interrupted recording; head -c 1228" \
		"$WORK/err" || fail "damaged record size: $(cat "$WORK/err")"
	grep -q "not finalised" "$WORK/err" && fail "damage reported as an interrupted recording"
fi
if expect_exit 0 "cut record" -- "$DEPTHAO" process \
	--input "$RG/cut-in-payload-mid-file.oni" --fov 60,45 --ao-out "$WORK/cut"; then
	grep -q "warning: .*the recording was not finalised .*recovered 1 frame up to byte 1228" \
		"$WORK/err" || fail "cut record: $(cat "$WORK/err")"
fi
finish
