#!/bin/sh
# SPDX-License-Identifier: MIT
# synth -> process round trips on real files, single and directory mode.
. "$(dirname "$0")/cli_lib.sh"

S=$WORK/synth
expect_exit 0 "synth spheres" -- "$DEPTHAO" synth --scene spheres --out "$S" --rays 16
for f in depth.png ao_gt.png camera.json; do
	[ -s "$S/spheres/$f" ] || fail "synth did not write spheres/$f"
done
png_is "$S/spheres/depth.png" "640 480 gray16"
png_is "$S/spheres/ao_gt.png" "640 480 gray16"
grep -q '"intrinsic_matrix"' "$S/spheres/camera.json" || fail "camera.json lacks intrinsic_matrix"
expect_exit 0 "synth noisy" -- "$DEPTHAO" synth --scene thin-pole --noise --out "$S" --rays 16
[ -s "$S/thin-pole-noisy/depth.png" ] || fail "noisy variant not written"
[ ! -e "$S/thin-pole" ] || fail "--noise also wrote the clean variant"

# single file, camera.json picked up from beside the input
expect_exit 0 "process file" -- "$DEPTHAO" process --input "$S/spheres/depth.png" \
	--ao-out "$WORK/ao.png" --shaded-out "$WORK/shaded.png"
grep -q "using intrinsics from .*camera.json" "$WORK/err" || fail "camera.json pickup not reported"
grep -q "1 frame" "$WORK/err" || fail "no summary line"
png_is "$WORK/ao.png" "640 480 gray16"
png_is "$WORK/shaded.png" "640 480 rgb24"
# AO values: 16-bit visibility, open areas at the top of the range, some occlusion somewhere
set -- $("$PNG_INFO" "$WORK/ao.png")
[ "$5" -eq 65535 ] || fail "AO maximum $5, expected 65535"
[ "$4" -lt 50000 ] || fail "AO minimum $4: no occlusion found"

# explicit intrinsics and fov, a quality preset and parameter overrides
expect_exit 0 "process intrinsics" -- "$DEPTHAO" process --input "$S/spheres/depth.png" \
	--ao-out "$WORK/ao2.png" --intrinsics 525,525,319.5,239.5 --quality low --radius=0.4 --denoise bilateral
grep -q "using intrinsics" "$WORK/err" && fail "camera.json used although --intrinsics was given"
expect_exit 0 "process fov" -- "$DEPTHAO" process --input "$S/spheres/depth.png" \
	--shaded-out "$WORK/s3.png" --fov 62.7,49.1 --shade turbo --quiet
[ -s "$WORK/err" ] && fail "--quiet still printed: $(cat "$WORK/err")"

# directory mode: same names, numbered frames, outputs created
mkdir -p "$WORK/seq"
cp "$S/spheres/depth.png" "$WORK/seq/0001.png"
cp "$S/spheres/depth.png" "$WORK/seq/0002.png"
echo "not an image" > "$WORK/seq/notes.txt"
expect_exit 0 "process dir" -- "$DEPTHAO" process --input "$WORK/seq" --intrinsics 525,525,319.5,239.5 \
	--ao-out "$WORK/out-ao" --shaded-out "$WORK/nested/out-shaded"
grep -q "2 frames" "$WORK/err" || fail "directory summary: $(cat "$WORK/err")"
for n in 0001 0002; do
	png_is "$WORK/out-ao/$n.png" "640 480 gray16"
	png_is "$WORK/nested/out-shaded/$n.png" "640 480 rgb24"
done
[ ! -e "$WORK/out-ao/notes.txt" ] || fail "non-PNG file processed"
no_temp_files "$WORK"

# a sequence from synth --frames plays as a directory, camera.json included
expect_exit 0 "synth frames" -- "$DEPTHAO" synth --scene thin-pole --frames 3 --rays 1 --out "$S"
expect_exit 0 "process sequence" -- "$DEPTHAO" process --input "$S/thin-pole/depth" --ao-out "$WORK/seq-ao"
grep -q "3 frames" "$WORK/err" || fail "sequence summary: $(cat "$WORK/err")"
grep -q "using intrinsics from" "$WORK/err" || fail "sequence camera.json not used"
[ -s "$S/thin-pole/ao_gt/0002.png" ] || fail "sequence ground truth missing"
finish
