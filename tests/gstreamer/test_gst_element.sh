#!/bin/sh
# SPDX-License-Identifier: MIT
# The GStreamer element: gst-inspect-1.0 sees it with its generated properties;
# gst-launch-1.0 pipelines give the same pixels as `depthao process` (AO 16-bit, AO 8-bit,
# shaded RGB/RGBA/BGRx, the default camera, the frame counter, the temporal depth filter on
# a stream); property changes change the output, also on a playing pipeline; wrong caps
# are not-negotiated errors.
# usage: test_gst_element.sh GST_TEST_UTIL GST_RUNTIME DEPTHAO   (GST_PLUGIN_PATH set)
set -eu
UTIL=$1
RUNTIME=$2
DEPTHAO=$3
if ! command -v gst-launch-1.0 >/dev/null || ! command -v gst-inspect-1.0 >/dev/null; then
	echo "SKIP: gst-launch-1.0 / gst-inspect-1.0 not installed (gstreamer1.0-tools)"
	exit 77
fi
WORK=$(mktemp -d "${TMPDIR:-/tmp}/gst-element.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
trap 'exit 1' INT TERM # a timeout (meson's SIGTERM) cleans up too
export GST_REGISTRY="$WORK/registry.bin" # a fresh registry: no stale cache of the build dir
failures=0
# gst-launch-1.0 with a time limit (an error during preroll can leave it waiting)
launch() {
	timeout 60 gst-launch-1.0 "$@"
}
fail() {
	echo "FAIL: $*"
	failures=$((failures + 1))
}
for e in filesrc pngdec pngenc videoconvert filesink multifilesink imagefreeze rawvideoparse; do
	if ! gst-inspect-1.0 --exists "$e"; then
		echo "SKIP: GStreamer element $e missing (gstreamer1.0-plugins-base/-good)"
		exit 77
	fi
done

# --- gst-inspect-1.0 -------------------------------------------------------------------
gst-inspect-1.0 depthao >"$WORK/inspect" 2>&1 || fail "gst-inspect-1.0 depthao: $(cat "$WORK/inspect")"
grep -q "Long-name *Depth ambient occlusion" "$WORK/inspect" || fail "inspect: no element metadata"
for p in depth-unit fx fy cx cy hfov-deg vfov-deg hfov vfov quality radius slices steps thickness \
	denoise shade occlusion-color depth-min depth-max; do
	grep -q "^  $p *:" "$WORK/inspect" || fail "inspect: property $p missing"
done
# the radian properties are deprecated (flagged, and said so in their description)
for p in hfov vfov; do
	grep -A1 "^  $p *:" "$WORK/inspect" | grep -q "DEPRECATED, use $p-deg" ||
		fail "inspect: $p is not marked deprecated"
	grep -A1 "^  $p *:" "$WORK/inspect" | grep -q "flags:.*deprecated" ||
		fail "inspect: $p lacks the deprecated flag"
done
grep -q "SINK template: 'color_sink'" "$WORK/inspect" || fail "inspect: no color_sink template"
grep -A4 "SINK template: 'sink'" "$WORK/inspect" | grep -q "GRAY16_BE" ||
	fail "inspect: the sink does not take GRAY16_BE"

grep -A1 "^  radius *:" "$WORK/inspect" | grep -q "controllable" || fail "radius is not controllable"
grep -A2 "^  radius *:" "$WORK/inspect" | grep -q "Double. Range: *0.01 - *100 Default: *0.5" ||
	fail "radius range/default: $(grep -A2 "^  radius *:" "$WORK/inspect")"
grep -A2 "^  depth-temporal *:" "$WORK/inspect" | grep -q "Default: *0.8" ||
	fail "the temporal depth filter is not on by default: $(grep -A2 "^  depth-temporal *:" "$WORK/inspect")"
grep -A2 "^  noise-interval *:" "$WORK/inspect" | grep -q "Default: *15 " ||
	fail "the element does not measure the noise every 15th frame by default: $(grep -A2 "^  noise-interval *:" "$WORK/inspect")"
grep -q 'Enum "GstDepthaoShade"' "$WORK/inspect" || fail "shade is not a registered enum"
grep -q "(1): turbo" "$WORK/inspect" || fail "the shade enum lacks its values"
echo "gst-inspect-1.0: element and $(grep -c "controllable" "$WORK/inspect") controllable properties"

# --- pipelines against depthao process ---------------------------------------------------
"$DEPTHAO" synth --scene boxes --rays 1 --out "$WORK/synth" >/dev/null || fail "synth"
DEPTH="$WORK/synth/boxes/depth.png"
K=525,525,319.5,239.5
CAM="fx=525 fy=525 cx=319.5 cy=239.5"
"$DEPTHAO" process --input "$DEPTH" --intrinsics $K --ao-out "$WORK/ref-ao.png" \
	--shaded-out "$WORK/ref-shaded.png" --quiet || fail "depthao process"
RAW="raw:%s:640x480:$WORK/%s"

# gst RAWFILE OUTFORMAT [ELEMENT PROPERTIES...]: one depth frame through depthao
gst() {
	out=$1
	fmt=$2
	shift 2
	# shellcheck disable=SC2086 # word splitting of the property list is intended
	launch -q filesrc location="$DEPTH" ! pngdec ! videoconvert ! \
		video/x-raw,format=GRAY16_LE ! depthao "$@" ! video/x-raw,format="$fmt" ! \
		filesink location="$WORK/$out" >"$WORK/log" 2>&1 || fail "pipeline to $fmt ($*): $(cat "$WORK/log")"
}
# same IMAGE_A IMAGE_B [TOL] WHAT
same() {
	"$UTIL" compare "$1" "$2" "$3" >"$WORK/cmp" || fail "$4: $(cat "$WORK/cmp")"
	echo "$4: $(cat "$WORK/cmp")"
}

# shellcheck disable=SC2086
gst ao.raw GRAY16_LE $CAM
# shellcheck disable=SC2059
same "$(printf "$RAW" gray16le ao.raw)" "$WORK/ref-ao.png" 0 "AO GRAY16_LE vs depthao process"
# the pipeline of docs/gstreamer.md: 16-bit PNG out through videoconvert and pngenc
# shellcheck disable=SC2086
launch -q filesrc location="$DEPTH" ! pngdec ! videoconvert ! video/x-raw,format=GRAY16_LE ! \
	depthao $CAM ! video/x-raw,format=GRAY16_LE ! videoconvert ! video/x-raw,format=GRAY16_BE ! pngenc ! \
	filesink location="$WORK/ao.png" >"$WORK/log" 2>&1 || fail "PNG pipeline: $(cat "$WORK/log")"
"$UTIL" info "$WORK/ao.png" | grep -qx "640 480 gray16" || fail "ao.png: $("$UTIL" info "$WORK/ao.png")"
same "$WORK/ao.png" "$WORK/ref-ao.png" 0 "AO PNG (pngenc) vs depthao process"
# shellcheck disable=SC2086
gst ao8.raw GRAY8 $CAM
# shellcheck disable=SC2059
same "$(printf "$RAW" gray8 ao8.raw)" "$WORK/ref-ao.png" 1 "AO GRAY8 vs 16-bit AO / 257"
for f in RGB RGBA BGRx; do
	lower=$(echo "$f" | tr '[:upper:]' '[:lower:]')
	# shellcheck disable=SC2086
	gst "shaded-$lower.raw" "$f" $CAM
	# shellcheck disable=SC2059
	same "$(printf "$RAW" "$lower" "shaded-$lower.raw")" "$WORK/ref-shaded.png" 0 "shaded $f vs depthao process"
done
# unconstrained output: the shaded image
# shellcheck disable=SC2086
launch -q filesrc location="$DEPTH" ! pngdec ! videoconvert ! depthao $CAM ! videoconvert ! \
	pngenc ! filesink location="$WORK/default.png" >"$WORK/log" 2>&1 || fail "default output: $(cat "$WORK/log")"
same "$WORK/default.png" "$WORK/ref-shaded.png" 0 "unconstrained output (shaded RGB)"

# no camera: 58.5 x 45.6 degrees, as depthao process without one (no camera.json there)
mkdir "$WORK/nocam"
cp "$DEPTH" "$WORK/nocam/depth.png"
"$DEPTHAO" process --input "$WORK/nocam/depth.png" --ao-out "$WORK/ref-nocam.png" --quiet 2>/dev/null ||
	fail "depthao process without a camera"
GST_DEBUG=depthao:2 launch -q filesrc location="$DEPTH" ! pngdec ! videoconvert ! depthao ! \
	video/x-raw,format=GRAY16_LE ! filesink location="$WORK/nocam.raw" >"$WORK/log" 2>&1 ||
	fail "no-camera pipeline: $(cat "$WORK/log")"
grep -q "assuming a 58.5 x 45.6 degree field of view" "$WORK/log" || fail "no warning without a camera: $(cat "$WORK/log")"
# shellcheck disable=SC2059
same "$(printf "$RAW" gray16le nocam.raw)" "$WORK/ref-nocam.png" 0 "default camera vs depthao process"
# the deprecated fov properties in radians: the doubles depthao process makes of --fov 66,50
# (degrees; hfov-deg/vfov-deg are tested in test_gst_color.py)
hfov=$(awk 'BEGIN { printf "%.17g", 66 * (3.14159265358979323846 / 180.0) }')
vfov=$(awk 'BEGIN { printf "%.17g", 50 * (3.14159265358979323846 / 180.0) }')
gst fov.raw GRAY16_LE hfov="$hfov" vfov="$vfov"
"$DEPTHAO" process --input "$WORK/nocam/depth.png" --fov 66,50 --ao-out "$WORK/ref-fov.png" --quiet ||
	fail "depthao process --fov"
# shellcheck disable=SC2059
same "$(printf "$RAW" gray16le fov.raw)" "$WORK/ref-fov.png" 0 "hfov/vfov vs depthao process --fov"
# only hfov: square pixels
gst hfov.raw GRAY16_LE hfov="$hfov"
# shellcheck disable=SC2059
"$UTIL" compare "$(printf "$RAW" gray16le hfov.raw)" "$(printf "$RAW" gray16le fov.raw)" 65535 >/dev/null ||
	fail "hfov alone"

# property changes change the output: radius; the preset; an explicit default changes nothing
# shellcheck disable=SC2086
gst r02.raw GRAY16_LE $CAM radius=0.2
# shellcheck disable=SC2059
if "$UTIL" compare "$(printf "$RAW" gray16le r02.raw)" "$(printf "$RAW" gray16le ao.raw)" >"$WORK/cmp"; then
	fail "radius=0.2 gives the same AO as the default"
fi
echo "radius=0.2 vs default: $(cat "$WORK/cmp")"
"$DEPTHAO" process --input "$DEPTH" --intrinsics $K --radius 0.2 --ao-out "$WORK/ref-r02.png" --quiet
# shellcheck disable=SC2059
same "$(printf "$RAW" gray16le r02.raw)" "$WORK/ref-r02.png" 0 "radius=0.2 vs depthao process --radius 0.2"
# shellcheck disable=SC2086
gst r05.raw GRAY16_LE $CAM radius=0.5
cmp -s "$WORK/r05.raw" "$WORK/ao.raw" || fail "radius=0.5 (the default) changed the AO"
# shellcheck disable=SC2086
gst high.raw GRAY16_LE $CAM quality=high shade=turbo
"$DEPTHAO" process --input "$DEPTH" --intrinsics $K --quality high --ao-out "$WORK/ref-high.png" --quiet
# shellcheck disable=SC2059
same "$(printf "$RAW" gray16le high.raw)" "$WORK/ref-high.png" 0 "quality=high vs depthao process --quality high"
# shellcheck disable=SC2086
gst turbo.raw RGB $CAM shade=turbo occlusion-color=0x200040
"$DEPTHAO" process --input "$DEPTH" --intrinsics $K --shade turbo --occlusion-color 200040 \
	--shaded-out "$WORK/ref-turbo.png" --quiet
# shellcheck disable=SC2059
same "$(printf "$RAW" rgb turbo.raw)" "$WORK/ref-turbo.png" 0 "shade=turbo occlusion-color vs depthao process"

# the frame counter picks the noise pattern: frame 2 of a stream = --frame-index 2
# shellcheck disable=SC2086
launch -q filesrc location="$DEPTH" ! pngdec ! imagefreeze num-buffers=3 ! videoconvert ! \
	video/x-raw,format=GRAY16_LE ! depthao $CAM ! video/x-raw,format=GRAY16_LE ! \
	multifilesink location="$WORK/seq-%d.raw" >"$WORK/log" 2>&1 || fail "3 frames: $(cat "$WORK/log")"
"$DEPTHAO" process --input "$DEPTH" --intrinsics $K --frame-index 2 --ao-out "$WORK/ref-f2.png" --quiet
cmp -s "$WORK/seq-0.raw" "$WORK/ao.raw" || fail "frame 0 of a stream differs from the single frame"
# shellcheck disable=SC2059
same "$(printf "$RAW" gray16le seq-2.raw)" "$WORK/ref-f2.png" 0 "stream frame 2 vs depthao process --frame-index 2"

# a stream of noisy frames: the temporal depth filter (on by default) gives what depthao
# process gives with it on the same frames; depth-temporal=0 what it gives without
NOISY="${DAO_SOURCE_ROOT:?}/recordings/spheres-noisy"
for dt in default 0; do
	prop=""
	[ "$dt" = default ] || prop="depth-temporal=$dt"
	# shellcheck disable=SC2086
	launch -q multifilesrc location="$NOISY/%04d.png" index=0 stop-index=3 \
		caps=image/png,framerate=30/1 ! pngdec ! videoconvert ! video/x-raw,format=GRAY16_LE ! \
		depthao $CAM $prop ! video/x-raw,format=GRAY16_LE ! \
		multifilesink location="$WORK/noisy-$dt-%d.raw" >"$WORK/log" 2>&1 ||
		fail "noisy stream ($dt): $(cat "$WORK/log")"
done
# (and, as a stream, the noise measured in full on frames 0, 1, 2, 4, 8, ..., every 15th:
# frame 3 reuses frame 2's; PNG input measures every frame unless told)
"$DEPTHAO" process --input "images:$NOISY" --intrinsics $K --depth-temporal 0.8 \
	--noise-interval 15 --ao-out "$WORK/noisy-on" --quiet ||
	fail "depthao process images: --depth-temporal 0.8 --noise-interval 15"
"$DEPTHAO" process --input "$NOISY" --intrinsics $K --noise-interval 15 \
	--ao-out "$WORK/noisy-off" --quiet ||
	fail "depthao process on the PNG directory --noise-interval 15"
# shellcheck disable=SC2059
same "$(printf "$RAW" gray16le noisy-default-3.raw)" "$WORK/noisy-on/000003.png" 0 \
	"stream frame 3, depth-temporal on vs depthao process --depth-temporal 0.8"
# shellcheck disable=SC2059
same "$(printf "$RAW" gray16le noisy-0-3.raw)" "$WORK/noisy-off/0003.png" 0 \
	"stream frame 3, depth-temporal=0 vs depthao process on PNGs (off)"
cmp -s "$WORK/noisy-default-3.raw" "$WORK/noisy-0-3.raw" &&
	fail "the temporal depth filter changed nothing on noisy frames"

# properties changed on a playing pipeline reach the next frame (gst_runtime writes f0..f3)
mkdir "$WORK/rt"
"$RUNTIME" "$DEPTH" "$WORK/rt" || fail "gst_runtime"
i=0
for opts in "" "--radius 0.25" "--quality high --radius 0.25" "--quality high --radius 0.25"; do
	# shellcheck disable=SC2086
	"$DEPTHAO" process --input "$DEPTH" --intrinsics $K $opts --frame-index $i \
		--ao-out "$WORK/rt/ref$i.png" --quiet
	# shellcheck disable=SC2059
	same "$(printf "$RAW" gray16le "rt/f$i.raw")" "$WORK/rt/ref$i.png" 0 "playing, frame $i (${opts:-defaults})"
	i=$((i + 1))
done

# --- negotiation failures ----------------------------------------------------------------
# RGB into depthao: caps known only at run time (rawvideoparse) -> not-negotiated
head -c $((4 * 4 * 3 * 2)) /dev/zero >"$WORK/rgb.raw"
if launch filesrc location="$WORK/rgb.raw" ! rawvideoparse format=rgb width=4 height=4 ! \
	depthao ! fakesink async=false >"$WORK/log" 2>&1; then
	fail "RGB input was accepted"
fi
grep -q "not-negotiated" "$WORK/log" || fail "RGB input: no not-negotiated error: $(cat "$WORK/log")"
# and at link time (caps known while building the pipeline)
if launch videotestsrc num-buffers=1 ! video/x-raw,format=RGB ! depthao ! fakesink \
	>"$WORK/log" 2>&1; then
	fail "RGB caps linked to depthao"
fi
grep -q "could not link .*depthao" "$WORK/log" || fail "RGB caps: $(cat "$WORK/log")"
# output caps it cannot make
if launch filesrc location="$DEPTH" ! pngdec ! videoconvert ! depthao ! \
	video/x-raw,format=I420 ! fakesink async=false >"$WORK/log" 2>&1; then
	fail "I420 output was accepted"
fi
# parameters the library rejects: an element error naming the reason, then not-negotiated
if launch filesrc location="$DEPTH" ! pngdec ! videoconvert ! depthao depth-min=10 depth-max=5 ! \
	fakesink async=false >"$WORK/log" 2>&1; then
	fail "depth-min > depth-max was accepted"
fi
grep -q "ERROR: from element .*depthao.*depth-min 10 must be less than depth-max 5" "$WORK/log" ||
	fail "bad parameters: $(cat "$WORK/log")"

if [ "$failures" -ne 0 ]; then
	echo "$failures failure(s)"
	exit 1
fi
echo "all passed"
