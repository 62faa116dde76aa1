#!/bin/sh
# SPDX-License-Identifier: MIT
# depthao process --mcap-out: the file validates and reads back in the reference
# implementation (check_mcap.js: @mcap/core's indexed and stream readers, CRCs, the schemas
# and CDR by @foxglove/rosmsg2-serialization) frame by frame equal to the PNG outputs of the
# same run, with zstd, lz4 and no compression and the point cloud; depthao's own MCAP source
# reads it back (mcap_roundtrip.c: the AO topic's pixels, timestamps and CameraInfo); a file cut short reads up to its last chunk in both readers;
# option and path errors.
# usage: test_mcap_sink.sh DEPTHAO PNG_INFO NODE
. "$(dirname "$0")/../tools/cli_lib.sh"
NODE=$3
CHECK="${DAO_CHECK_MCAP:?the path of check_mcap.js}"
REC="${DAO_SOURCE_ROOT:?}/recordings/spheres-rolling.oni"
HAVE_NODE=1
command -v "$NODE" >/dev/null 2>&1 || HAVE_NODE=0
if [ "$HAVE_NODE" -eq 1 ]; then
	set +e
	"$NODE" "$CHECK" /dev/null >/dev/null 2>&1
	[ $? -eq 77 ] && HAVE_NODE=0
	set -e
fi
[ "$HAVE_NODE" -eq 1 ] || echo "note: node or tests/js/node_modules missing: the @mcap/core checks are skipped (cd tests/js && npm ci)"

# check FILE ARGS...: check_mcap.js, its summary line in $WORK/check
check() {
	[ "$HAVE_NODE" -eq 1 ] || return 0
	"$NODE" "$CHECK" "$@" >"$WORK/check" 2>&1 || fail "check_mcap.js $*: $(cat "$WORK/check")"
}

expect_exit 0 "process --mcap-out" -- "$DEPTHAO" process --input "$REC" --ao-out "$WORK/ao" \
	--shaded-out "$WORK/sh" --mcap-out "$WORK/out.mcap" || true
[ -s "$WORK/out.mcap" ] || fail "no MCAP written: $(cat "$WORK/err")"
check "$WORK/out.mcap" --ao "$WORK/ao" --shaded "$WORK/sh" --compression zstd
[ "$HAVE_NODE" -eq 0 ] || grep -q "^ao 16 shaded 16 info 16 points 0 chunks" "$WORK/check" ||
	fail "zstd: $(cat "$WORK/check")"
for c in lz4 none; do
	expect_exit 0 "?compression=$c&cloud=true" -- "$DEPTHAO" process --input "$REC" --quiet \
		--mcap-out "$WORK/$c.mcap?compression=$c&cloud=true&chunk=2000000" || continue
	check "$WORK/$c.mcap" --ao "$WORK/ao" --shaded "$WORK/sh" --compression "$c"
	[ "$HAVE_NODE" -eq 0 ] || grep -q "^ao 16 shaded 16 info 16 points 16 chunks" "$WORK/check" ||
		fail "$c: $(cat "$WORK/check")"
done

# ?filtered_depth=true: the filtered depth on /depthao/depth_filtered (16UC1 for 1 mm), read by
# @mcap/core, equal to --depth-out's PNGs
expect_exit 0 "?filtered_depth=true" -- "$DEPTHAO" process --input "$REC" --quiet --frames 4 \
	--depth-out "$WORK/fd" --mcap-out "$WORK/fd.mcap?filtered_depth=true" || true
check "$WORK/fd.mcap" --depth "$WORK/fd"
[ "$HAVE_NODE" -eq 0 ] || grep -q "^ao 4 shaded 4 info 4 points 0 chunks .* depth 4$" "$WORK/check" ||
	fail "filtered_depth: $(cat "$WORK/check")"

# a moving camera (synth sideways) with depth-temporal-motion icp: the pose of every frame
# on /tf, just before its AO image, equal to --pose-out's (@mcap/core); depthao's own source
# reads them back as the camera's poses (source motion, --pose-out again: the same poses)
expect_exit 0 "synth sideways" -- "$DEPTHAO" synth --scene boxes --trajectory sideways \
	--frames 5 --rays 1 --out "$WORK/syn" || true
SEQ="$WORK/syn/boxes-sideways/depth"
expect_exit 0 "?pose_frame= with icp" -- "$DEPTHAO" process --input "$SEQ" --quiet \
	--depth-temporal 0.8 --depth-temporal-motion icp --pose-out "$WORK/poses.txt" \
	--mcap-out "$WORK/tf.mcap?filtered_depth=true&pose_frame=odom&frame_id=cam" || true
check "$WORK/tf.mcap" --poses "$WORK/poses.txt" --pose-frame odom --frame-id cam
[ "$HAVE_NODE" -eq 0 ] || grep -q "^ao 5 shaded 5 info 5 points 0 chunks .* tf 5$" "$WORK/check" ||
	fail "poses: $(cat "$WORK/check")"
moved=$(awk '!/^#/ && $2 > 0.05 { n++ } END { print n + 0 }' "$WORK/poses.txt")
[ "$moved" -ge 1 ] || fail "the camera did not move 5 cm in the estimate: $(cat "$WORK/poses.txt")"
expect_exit 0 "the poses read back" -- "$DEPTHAO" process \
	--input "$WORK/tf.mcap?topic=/depthao/depth_filtered" --algorithm none --depth-out "$WORK/back" \
	--depth-temporal 0.8 --depth-temporal-motion source --pose-out "$WORK/back.txt" || true
grep -q "camera poses: 'cam' in 'odom' from /tf (5 transforms)" "$WORK/err" ||
	fail "read back: $(cat "$WORK/err")"
[ "$(grep -v '^#' "$WORK/poses.txt")" = "$(grep -v '^#' "$WORK/back.txt")" ] ||
	fail "the poses read back differ: $(cat "$WORK/back.txt")"
# icp without the temporal depth filter (PNG input's default) follows nothing: no /tf
expect_exit 0 "icp with depth-temporal 0" -- "$DEPTHAO" process --input "$SEQ" --quiet \
	--depth-temporal-motion icp --mcap-out "$WORK/notf.mcap" || true
check "$WORK/notf.mcap"
expect_exit 1 "pose_frame = frame_id" -- "$DEPTHAO" process --input "$SEQ" \
	--mcap-out "$WORK/y.mcap?pose_frame=cam&frame_id=cam"
grep -q "frame_id 'cam' and pose_frame 'cam' must be two names" "$WORK/err" ||
	fail "pose_frame = frame_id: $(cat "$WORK/err")"

# depthao's own source: the AO topic's pixels are the AO PNGs', its timestamps the
# recording's, the CameraInfo the pinhole of the recording's field of view
out=$("${DAO_MCAP_ROUNDTRIP:?}" "$WORK/out.mcap" "$WORK/ao" "$REC" 2>&1) || fail "round trip: $out"
echo "through depthao's MCAP source: $out"
echo "$out" | grep -q "^frames 16 " || fail "round trip: $out"

# cut short: both readers read the complete chunks
size=$(wc -c <"$WORK/out.mcap")
head -c $((size / 2)) "$WORK/out.mcap" >"$WORK/cut.mcap"
expect_exit 0 "a file cut short" -- "$DEPTHAO" process --input "$WORK/cut.mcap?topic=/depthao/ao" \
	--ao-out "$WORK/cut" || true
grep -q "warning: the MCAP file is cut short" "$WORK/err" || fail "cut: no warning: $(cat "$WORK/err")"
ours=$(ls "$WORK/cut" | wc -l)
[ "$ours" -ge 4 ] || fail "cut at half: $ours frames"
if [ "$HAVE_NODE" -eq 1 ]; then
	check "$WORK/cut.mcap" --cut
	theirs=$(awk '{ print $2 }' "$WORK/check")
	echo "cut at half: depthao reads $ours AO frames, @mcap/core $theirs"
	[ "$theirs" = "$ours" ] || fail "cut: @mcap/core reads $theirs AO frames, depthao $ours"
fi

# a recording never replaces a file: out-1.mcap, said on stderr; ?overwrite=true replaces
expect_exit 0 "again to out.mcap" -- "$DEPTHAO" process --input "$REC" --frames 2 \
	--mcap-out "$WORK/out.mcap" || true
grep -q "out.mcap exists; recording to .*out-1.mcap instead" "$WORK/err" || fail "numbered: $(cat "$WORK/err")"
check "$WORK/out-1.mcap"
[ "$HAVE_NODE" -eq 0 ] || grep -q "^ao 2 " "$WORK/check" || fail "out-1.mcap: $(cat "$WORK/check")"
check "$WORK/out.mcap"
[ "$HAVE_NODE" -eq 0 ] || grep -q "^ao 16 " "$WORK/check" || fail "out.mcap changed: $(cat "$WORK/check")"
expect_exit 0 "?overwrite=true" -- "$DEPTHAO" process --input "$REC" --frames 3 --quiet \
	--mcap-out "$WORK/out.mcap?overwrite=true" || true
check "$WORK/out.mcap"
[ "$HAVE_NODE" -eq 0 ] || grep -q "^ao 3 " "$WORK/check" || fail "overwrite: $(cat "$WORK/check")"
chmod a-w "$WORK/out-1.mcap"
expect_exit 1 "a write-protected file" -- "$DEPTHAO" process --input "$REC" --frames 1 \
	--mcap-out "$WORK/out-1.mcap?overwrite=true" || true
grep -q "chmod u+w" "$WORK/err" || fail "write-protected: $(cat "$WORK/err")"
mkdir "$WORK/dir.mcap"
expect_exit 1 "into a directory" -- "$DEPTHAO" process --input "$REC" --mcap-out "$WORK/dir.mcap"
grep -q "mcap: .*dir.mcap is a directory" "$WORK/err" || fail "directory: $(cat "$WORK/err")"
expect_exit 1 "a bad option" -- "$DEPTHAO" process --input "$REC" --mcap-out "$WORK/x.mcap?compression=bz2"
grep -q "compression" "$WORK/err" && grep -q "zstd" "$WORK/err" || fail "bad option: $(cat "$WORK/err")"
expect_exit 1 "a chunk too small" -- "$DEPTHAO" process --input "$REC" --mcap-out "$WORK/x.mcap?chunk=10"
grep -q "chunk" "$WORK/err" || fail "chunk=10: $(cat "$WORK/err")"
[ ! -e "$WORK/x.mcap" ] || fail "a refused recording left a file"
expect_exit 1 "standard output" -- "$DEPTHAO" process --input "$REC" --mcap-out -
grep -q "cannot go to standard output" "$WORK/err" || fail "-: $(cat "$WORK/err")"
expect_exit 1 "a missing directory" -- "$DEPTHAO" process --input "$REC" --mcap-out "$WORK/no/x.mcap"
grep -q "cannot record to .*no/x.mcap" "$WORK/err" || fail "missing directory: $(cat "$WORK/err")"
finish
