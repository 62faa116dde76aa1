#!/bin/sh
# SPDX-License-Identifier: MIT
# Runtime errors a user can cause: exit 1, a clear message, nothing half-written.
. "$(dirname "$0")/cli_lib.sh"

S=$WORK/synth
"$DEPTHAO" synth --scene plane --out "$S" --rays 1 >/dev/null
D=$S/plane/depth.png
CAM="--intrinsics 525,525,319.5,239.5"

expect_exit 1 "missing input" -- "$DEPTHAO" process --input "$WORK/nope.png" --ao-out "$WORK/a.png"
grep -q "nope.png" "$WORK/err" || fail "missing input not named"

# an 8-bit PNG (the AO of a gray8 shade) is not a depth image
"$DEPTHAO" process --input "$D" $CAM --shaded-out "$WORK/rgb.png" --quiet
expect_exit 1 "8-bit input" -- "$DEPTHAO" process --input "$WORK/rgb.png" $CAM --ao-out "$WORK/a.png"
grep -q "16-bit" "$WORK/err" || fail "8-bit input message: $(cat "$WORK/err")"
[ ! -e "$WORK/a.png" ] || fail "output written for a bad input"

# a truncated PNG
size=$(wc -c <"$D")
head -c $((size / 2)) "$D" >"$WORK/trunc.png"
expect_exit 1 "truncated" -- "$DEPTHAO" process --input "$WORK/trunc.png" $CAM --ao-out "$WORK/a.png"
grep -q "corrupt or truncated" "$WORK/err" || fail "truncated message: $(cat "$WORK/err")"
[ ! -e "$WORK/a.png" ] || fail "output written for a truncated input"
printf 'garbage' >"$WORK/garbage.png"
expect_exit 1 "not a PNG" -- "$DEPTHAO" process --input "$WORK/garbage.png" $CAM --ao-out "$WORK/a.png"
grep -q "not a PNG" "$WORK/err" || fail "not-a-PNG message: $(cat "$WORK/err")"

# mismatched sizes in a directory (a 640x480 and a 320x240 frame)
mkdir "$WORK/mixed"
cp "$D" "$WORK/mixed/a.png"
"$DEPTHAO" process --input "$D" $CAM --ao-out "$WORK/ao-full.png" --quiet
cat >"$WORK/small.json" <<JSON
{ "width": 320, "height": 240, "intrinsic_matrix": [262.5,0,0, 0,262.5,0, 159.5,119.5,1] }
JSON
expect_exit 1 "camera file size mismatch" -- "$DEPTHAO" process --input "$D" --intrinsics-file "$WORK/small.json" --ao-out "$WORK/a.png"
grep -q "is for 320x240" "$WORK/err" || fail "camera size mismatch message: $(cat "$WORK/err")"
printf '{ "width": 640 ' >"$WORK/bad.json"
expect_exit 1 "broken camera file" -- "$DEPTHAO" process --input "$D" --intrinsics-file "$WORK/bad.json" --ao-out "$WORK/a.png"
grep -q "bad.json" "$WORK/err" || fail "broken camera file not named"
# a second frame of another size: a 16-bit gray PNG made from the AO of a cropped camera
"$DEPTHAO" synth --scene plane --out "$WORK/s2" --rays 1 >/dev/null
cp "$WORK/ao-full.png" "$WORK/mixed/b.png" # 16-bit, same size: fine
expect_exit 0 "same sizes" -- "$DEPTHAO" process --input "$WORK/mixed" $CAM --ao-out "$WORK/mixed-out" --quiet
printf '\211PNG\r\n\032\n' >"$WORK/mixed/c.png" # a third, broken file stops the run
expect_exit 1 "broken file in a directory" -- "$DEPTHAO" process --input "$WORK/mixed" $CAM --ao-out "$WORK/mixed-out2"
grep -q "c.png" "$WORK/err" || fail "broken file in a directory not named"

# unwritable outputs
expect_exit 1 "output dir missing" -- "$DEPTHAO" process --input "$D" $CAM --ao-out "$WORK/no/such/dir/a.png"
grep -q "cannot create" "$WORK/err" || fail "unwritable output message: $(cat "$WORK/err")"
echo x >"$WORK/afile"
expect_exit 1 "output dir under a file" -- "$DEPTHAO" process --input "$WORK/mixed" $CAM --ao-out "$WORK/afile/sub"
grep -q "afile" "$WORK/err" || fail "output under a file not named: $(cat "$WORK/err")"
if [ "$(id -u)" -ne 0 ]; then
	mkdir "$WORK/ro" && chmod 555 "$WORK/ro"
	expect_exit 1 "read-only dir" -- "$DEPTHAO" process --input "$D" $CAM --ao-out "$WORK/ro/a.png"
	chmod 755 "$WORK/ro"
fi
no_temp_files "$WORK"

# an empty directory
mkdir "$WORK/empty"
expect_exit 1 "empty dir" -- "$DEPTHAO" process --input "$WORK/empty" $CAM --ao-out "$WORK/e"
grep -q "no \*.png files" "$WORK/err" || fail "empty dir message: $(cat "$WORK/err")"
finish
