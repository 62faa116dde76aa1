#!/bin/sh
# SPDX-License-Identifier: MIT
# The sensor commands: synth --sensor/--variant, sensorstats, realcheck and the eval options,
# with their usage errors.
. "$(dirname "$0")/cli_lib.sh"

# a simulated structured-light frame: depth, ground truth and its description
expect_exit 0 "synth structured light" -- "$DEPTHAO" synth --scene plane --sensor structured-light \
	--rays 1 --seed 3 --out "$WORK/s"
png_is "$WORK/s/plane-structured-light/depth.png" "640 480 gray16"
png_is "$WORK/s/plane-structured-light/ao_gt.png" "640 480 gray16"
grep -q '"sensor":"structured-light"' "$WORK/s/plane-structured-light/camera.json" ||
	fail "camera.json lacks the sensor: $(cat "$WORK/s/plane-structured-light/camera.json")"
grep -q '"seed":3' "$WORK/s/plane-structured-light/camera.json" || fail "camera.json lacks the seed"
# the same seed gives the same frame; a variant is another scene
expect_exit 0 "synth again" -- "$DEPTHAO" synth --scene plane --sensor sl --rays 1 --seed 3 --out "$WORK/t"
cmp -s "$WORK/s/plane-structured-light/depth.png" "$WORK/t/plane-structured-light/depth.png" ||
	fail "the same seed gave a different frame"
expect_exit 0 "synth variant" -- "$DEPTHAO" synth --scene plane --variant 1 --rays 1 --out "$WORK/v"
expect_exit 0 "synth clean" -- "$DEPTHAO" synth --scene plane --rays 1 --out "$WORK/c"
cmp -s "$WORK/v/plane/depth.png" "$WORK/c/plane/depth.png" && fail "variant 1 equals the scene"

# its statistics: one plane, bands of a 1/8-px disparity (f b / q = 348 m px)
expect_exit 0 "sensorstats" -- "$DEPTHAO" sensorstats --input "$WORK/s/plane-structured-light/depth.png"
grep -q "^planes 1," "$WORK/out" || fail "sensorstats found other than one plane: $(cat "$WORK/out")"
grep -q "f b / q = 3[3-6][0-9] m px" "$WORK/out" || fail "band constant: $(grep bands "$WORK/out")"
expect_exit 0 "sensorstats residual" -- "$DEPTHAO" sensorstats --input "$WORK/s/plane-structured-light/depth.png" \
	--residual-out "$WORK/res.png"
png_is "$WORK/res.png" "640 480 gray8"

expect_usage_error "synth unknown sensor" -- "$DEPTHAO" synth --scene plane --sensor lidar --out "$WORK/x"
grep -q "structured-light" "$WORK/err" || fail "the unknown sensor message does not list the models"
expect_usage_error "synth bad variant" -- "$DEPTHAO" synth --scene plane --variant -1 --out "$WORK/x"
expect_usage_error "sensorstats without a mode" -- "$DEPTHAO" sensorstats
expect_usage_error "sensorstats two modes" -- "$DEPTHAO" sensorstats --real --compare
expect_usage_error "sensorstats scene without sensor" -- "$DEPTHAO" sensorstats --scene plane
expect_usage_error "sensorstats picture without compare" -- "$DEPTHAO" sensorstats --real --picture x.png
expect_exit 1 "sensorstats missing file" -- "$DEPTHAO" sensorstats --input "$WORK/none.png"
grep -q "none.png" "$WORK/err" || fail "the missing file is not named: $(cat "$WORK/err")"
expect_usage_error "eval unknown set" -- "$DEPTHAO" eval --set train
expect_usage_error "eval sensor twice" -- "$DEPTHAO" eval --sensors clean,clean
expect_usage_error "eval check without clean" -- "$DEPTHAO" eval --check --sensors gaussian
expect_usage_error "eval variants" -- "$DEPTHAO" eval --variants 0
expect_usage_error "realcheck unknown frame" -- "$DEPTHAO" realcheck --frames kinect-oni-99
expect_usage_error "realcheck unknown option" -- "$DEPTHAO" realcheck --bogus
expect_exit 0 "realcheck help" -- "$DEPTHAO" realcheck --help
grep -q "kinect-oni-0" "$WORK/out" || fail "realcheck --help does not list the frames"
finish
