#!/bin/sh
# SPDX-License-Identifier: MIT
# Help, version, and every usage error: exit 2 with one line on stderr.
. "$(dirname "$0")/cli_lib.sh"

expect_exit 0 "--help" -- "$DEPTHAO" --help && grep -q "process" "$WORK/out" || fail "--help lacks commands"
expect_exit 0 "--version" -- "$DEPTHAO" --version && grep -q "^depthao [0-9]" "$WORK/out" || fail "--version output"
# the commands that run the AO pipeline list its parameters in their help
for cmd in process synth eval bench realcheck; do
	expect_exit 0 "$cmd --help" -- "$DEPTHAO" $cmd --help
	grep -q "usage: depthao $cmd" "$WORK/out" || fail "$cmd --help lacks usage"
	grep -q -- "--radius" "$WORK/out" || fail "$cmd --help lacks the AO parameter table"
done

D=$WORK/d.png
expect_usage_error "no command" -- "$DEPTHAO"
expect_usage_error "unknown command" -- "$DEPTHAO" frobnicate
expect_usage_error "unknown option" -- "$DEPTHAO" process --input "$D" --ao-out x.png --bogus
expect_usage_error "missing value" -- "$DEPTHAO" process --input "$D" --ao-out x.png --slices
expect_usage_error "missing --input value" -- "$DEPTHAO" process --input
expect_usage_error "bad number" -- "$DEPTHAO" process --input "$D" --ao-out x.png --radius abc
expect_usage_error "out of range" -- "$DEPTHAO" process --input "$D" --ao-out x.png --slices 0
expect_usage_error "bad enum" -- "$DEPTHAO" process --input "$D" --ao-out x.png --denoise fancy
expect_usage_error "bad depth unit" -- "$DEPTHAO" process --input "$D" --ao-out x.png --depth-unit 0
expect_usage_error "conflicting camera" -- "$DEPTHAO" process --input "$D" --ao-out x.png --fov 58,45 --intrinsics 1,1,1,1
expect_usage_error "bad intrinsics" -- "$DEPTHAO" process --input "$D" --ao-out x.png --intrinsics 1,2,3
expect_usage_error "no output" -- "$DEPTHAO" process --input "$D"
expect_usage_error "no input" -- "$DEPTHAO" process --ao-out x.png
expect_usage_error "bad quality" -- "$DEPTHAO" process --input "$D" --ao-out x.png --quality best
expect_usage_error "inconsistent params" -- "$DEPTHAO" process --input "$D" --ao-out x.png --depth-min 5 --depth-max 1
expect_usage_error "synth unknown scene" -- "$DEPTHAO" synth --scene moon --out "$WORK/s"
expect_usage_error "synth bad rays" -- "$DEPTHAO" synth --scene plane --out "$WORK/s" --rays 10
expect_usage_error "synth no out" -- "$DEPTHAO" synth --scene plane
expect_usage_error "eval bad scene" -- "$DEPTHAO" eval --scenes plane,moon
expect_usage_error "eval check without default" -- "$DEPTHAO" eval --quality low --check
expect_usage_error "eval algorithm parameter without value" -- "$DEPTHAO" eval --algorithms vbao:vbao-thickness-mode
expect_usage_error "eval algorithm parameter unknown" -- "$DEPTHAO" eval --algorithms vbao:depth=1
expect_usage_error "eval algorithm parameter out of range" -- "$DEPTHAO" eval --algorithms vbao:vbao-thickness-max=99
expect_usage_error "compare algorithm parameter" -- "$DEPTHAO" compare --scene plane --rays 1 --out "$WORK/c.png" --algorithms vbao:vbao-thickness-mode=guess
finish
