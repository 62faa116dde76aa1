#!/bin/sh
# SPDX-License-Identifier: MIT
# What an output path of `depthao process` is: a regular file or a new path is written
# through a temporary file renamed into place, unless it is write-protected; '-' is
# standard output for one file; a dangling symlink is refused; a FIFO or a character device is written
# straight into and stays what it was; a directory is refused with a message.  The
# devices are made with mknod inside the test directory (as root), never the system's.
. "$(dirname "$0")/cli_lib.sh"

S=$WORK/synth
"$DEPTHAO" synth --scene plane --out "$S" --rays 1 >/dev/null
D=$S/plane/depth.png
CAM="--intrinsics 525,525,319.5,239.5"
"$DEPTHAO" process --input "$D" $CAM --ao-out "$WORK/ref.png" --quiet
png_is "$WORK/ref.png" "640 480 gray16"

# a regular file is replaced atomically (a new inode), nothing left behind
echo old >"$WORK/reg.png"
ino0=$(stat -c %i "$WORK/reg.png")
"$DEPTHAO" process --input "$D" $CAM --ao-out "$WORK/reg.png" --quiet || fail "regular file"
cmp -s "$WORK/reg.png" "$WORK/ref.png" || fail "regular file: not the PNG"
[ "$(stat -c %i "$WORK/reg.png")" != "$ino0" ] || fail "regular file written in place, not renamed"
no_temp_files "$WORK"

# a symlink to a regular file: the target is replaced, the link stays a link
echo old >"$WORK/target.png"
ln -s target.png "$WORK/link.png"
"$DEPTHAO" process --input "$D" $CAM --ao-out "$WORK/link.png" --quiet || fail "symlink"
[ -L "$WORK/link.png" ] || fail "the symlink was replaced by a file"
cmp -s "$WORK/target.png" "$WORK/ref.png" || fail "symlink: the target is not the PNG"
no_temp_files "$WORK"

# a write-protected file is never replaced, even by root (the rename replaced it: issue 38);
# through a symlink the same
echo old >"$WORK/ro.png"
chmod 444 "$WORK/ro.png"
if expect_exit 1 "write-protected file" -- "$DEPTHAO" process --input "$D" $CAM --ao-out "$WORK/ro.png"; then
	grep -q "'$WORK/ro.png' is write-protected (mode 0444" "$WORK/err" || fail "write-protected: $(cat "$WORK/err")"
	grep -q "chmod u+w" "$WORK/err" || fail "write-protected: no advice: $(cat "$WORK/err")"
fi
[ "$(cat "$WORK/ro.png")" = old ] || fail "the write-protected file was replaced"
ln -s ro.png "$WORK/ro-link.png"
expect_exit 1 "symlink to a write-protected file" -- "$DEPTHAO" process --input "$D" $CAM \
	--ao-out "$WORK/ro-link.png" && grep -q "write-protected" "$WORK/err" ||
	fail "symlink to write-protected: $(cat "$WORK/err")"
[ "$(cat "$WORK/ro.png")" = old ] && [ -L "$WORK/ro-link.png" ] || fail "the link or its file changed"
chmod 644 "$WORK/ro.png"
"$DEPTHAO" process --input "$D" $CAM --ao-out "$WORK/ro.png" --quiet || fail "writable again"
cmp -s "$WORK/ro.png" "$WORK/ref.png" || fail "writable again: not the PNG"
# a dangling symlink: refused, nothing created at either end
ln -s nowhere.png "$WORK/dangling.png"
if expect_exit 1 "dangling symlink" -- "$DEPTHAO" process --input "$D" $CAM --ao-out "$WORK/dangling.png"; then
	grep -q "symlink to something that does not exist" "$WORK/err" || fail "dangling: $(cat "$WORK/err")"
fi
[ -L "$WORK/dangling.png" ] && [ ! -e "$WORK/nowhere.png" ] || fail "the dangling symlink was changed"
no_temp_files "$WORK"

# '-' is standard output for one file (a PNG, a cloud), an error for numbered outputs;
# never a file or directory named '-' (--cloud-out - made a directory '-': issue 38);
# run in $WORK, where such a thing would appear
DEPTHAO_ABS=$(cd "$(dirname "$DEPTHAO")" && pwd)/$(basename "$DEPTHAO")
(cd "$WORK" && "$DEPTHAO_ABS" process --input "$D" $CAM --ao-out - --quiet >"$WORK/stdout.png") ||
	fail "--ao-out -"
cmp -s "$WORK/stdout.png" "$WORK/ref.png" || fail "--ao-out -: not the PNG on stdout"
(cd "$WORK" && "$DEPTHAO_ABS" process --input "$D" $CAM --cloud-out - --quiet >"$WORK/stdout.ply") ||
	fail "--cloud-out -"
head -c 4 "$WORK/stdout.ply" | grep -q ply || fail "--cloud-out -: no PLY on stdout"
mkdir "$WORK/pngs"
cp "$D" "$WORK/pngs/a.png"
cp "$D" "$WORK/pngs/b.png"
cd "$WORK"
# a directory of PNGs writes one file per image: '-' is an error (1), and for a cloud
# the usage error it was for any single file (2)
for case in "--ao-out 1" "--cloud-out 2"; do
	set -- $case
	if expect_exit "$2" "$1 - with two images" -- "$DEPTHAO_ABS" process --input "$WORK/pngs" \
		$CAM "$1" -; then
		grep -q "standard output\|is one file" "$WORK/err" || fail "$1 - with two images: $(cat "$WORK/err")"
	fi
done
cd - >/dev/null
[ ! -e "$WORK/-" ] || fail "a file or directory named '-' was made"

# a FIFO: written straight into, read by a background reader; it stays a FIFO
mkfifo "$WORK/fifo"
timeout 20 cat "$WORK/fifo" >"$WORK/from-fifo.png" & # a reader that never gets a writer gives up
reader=$!
sleep 0.2 # the reader opens the FIFO
"$DEPTHAO" process --input "$D" $CAM --ao-out "$WORK/fifo" --quiet 2>"$WORK/err" ||
	fail "FIFO: $(cat "$WORK/err")"
wait "$reader" || true
[ -p "$WORK/fifo" ] || fail "the FIFO was replaced: $(ls -l "$WORK/fifo")"
cmp -s "$WORK/from-fifo.png" "$WORK/ref.png" || fail "FIFO: the reader did not get the PNG"
no_temp_files "$WORK"
# a FIFO nobody reads: an error at once, not a hang
if expect_exit 1 "FIFO without a reader" -- timeout 10 "$DEPTHAO" process --input "$D" $CAM \
	--ao-out "$WORK/fifo"; then
	grep -q "no reader" "$WORK/err" || fail "FIFO without a reader: $(cat "$WORK/err")"
fi
[ -p "$WORK/fifo" ] || fail "the FIFO was replaced after a failed write"

# a directory: refused, untouched
mkdir "$WORK/adir"
if expect_exit 1 "directory" -- "$DEPTHAO" process --input "$D" $CAM --ao-out "$WORK/adir"; then
	grep -q "is a directory" "$WORK/err" || fail "directory: $(cat "$WORK/err")"
fi
[ -d "$WORK/adir" ] && [ -z "$(ls "$WORK/adir")" ] || fail "the directory was changed"
no_temp_files "$WORK"

# character devices: null and full, made here (root), or the system's /dev/null
# (not root: the old code could not replace it, and the new one must write into it)
if [ "$(id -u)" -eq 0 ]; then
	mknod "$WORK/null" c 1 3
	mknod "$WORK/full" c 1 7
	NULLDEV=$WORK/null
	"$DEPTHAO" process --input "$D" $CAM --ao-out "$WORK/full" 2>"$WORK/err" &&
		fail "a full device took the PNG"
	grep -q "No space left" "$WORK/err" || fail "full device: $(cat "$WORK/err")"
	[ -c "$WORK/full" ] || fail "the full device was replaced: $(ls -l "$WORK/full")"
else
	NULLDEV=/dev/null
	echo "note: not root; the character device part uses /dev/null, no full device"
fi
"$DEPTHAO" process --input "$D" $CAM --ao-out "$NULLDEV" --quiet 2>"$WORK/err" ||
	fail "null device: $(cat "$WORK/err")"
[ -c "$NULLDEV" ] || fail "$NULLDEV was replaced: $(ls -l "$NULLDEV")"
no_temp_files "$WORK"
finish
