#!/bin/sh
# SPDX-License-Identifier: MIT
# Installs the library into a staging directory, builds examples/shade_depth.c
# against it through pkg-config, and runs it on a depth image.
# usage: check_example.sh BUILD_DIR SOURCE_DIR MAKE_DEPTH
set -eu
build=$1
src=$2
make_depth=$3
stage=$(mktemp -d "${TMPDIR:-/tmp}/dao-install.XXXXXX")
trap 'rm -rf "$stage"' EXIT

meson install -C "$build" --destdir "$stage" --quiet >/dev/null
pc=$(find "$stage" -name depthao.pc | head -n 1)
[ -n "$pc" ] || { echo "FAIL: depthao.pc was not installed"; exit 1; }
lib=$(find "$stage" -name 'libdepthao.so' | head -n 1)
[ -n "$lib" ] || { echo "FAIL: libdepthao.so was not installed"; exit 1; }
[ -f "$(find "$stage" -path '*include/depthao/depthao.h' | head -n 1)" ] || { echo "FAIL: headers missing"; exit 1; }

# the .pc file names the real prefix; the sysroot variable maps it into the stage
flags=$(PKG_CONFIG_PATH=$(dirname "$pc") PKG_CONFIG_SYSROOT_DIR=$stage pkg-config --cflags --libs depthao)
cc -std=c11 -Wall -Wextra -Werror "$src/examples/shade_depth.c" $flags \
	-Wl,-rpath,"$(dirname "$lib")" -o "$stage/shade_depth"

"$make_depth" "$stage/depth.png"
"$stage/shade_depth" "$stage/depth.png" "$stage/out.png" 60 60 31.5 23.5
sig=$(head -c 8 "$stage/out.png" | od -An -tx1 | tr -d ' \n')
[ "$sig" = "89504e470d0a1a0a" ] || { echo "FAIL: output is not a PNG ($sig)"; exit 1; }
# and its error path: a missing input gives a message and a non-zero exit
if "$stage/shade_depth" "$stage/missing.png" "$stage/x.png" 2>"$stage/err"; then
	echo "FAIL: missing input accepted"; exit 1
fi
grep -q "missing.png" "$stage/err" || { echo "FAIL: error message: $(cat "$stage/err")"; exit 1; }
echo "example built against the installed library and ran"
