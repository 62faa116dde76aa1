#!/bin/sh
# SPDX-License-Identifier: MIT
# Builds examples/shade_depth.c against the build tree, not installed, through the
# uninstalled pkg-config files meson writes (BUILD/meson-uninstalled: docs/building.md),
# and runs it on a depth image made by MAKE_DEPTH with those libraries.
# usage: check_uninstalled.sh BUILD_DIR SOURCE_DIR MAKE_DEPTH
set -eu
[ $# -eq 3 ] || { echo "usage: $0 BUILD_DIR SOURCE_DIR MAKE_DEPTH" >&2; exit 2; }
build=$1
src=$2
make_depth=$3
work=$(mktemp -d "${TMPDIR:-/tmp}/dao-uninstalled.XXXXXX")
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

pcdir=$build/meson-uninstalled
[ -f "$pcdir/depthao-uninstalled.pc" ] || fail "no $pcdir/depthao-uninstalled.pc"
flags=$(PKG_CONFIG_PATH=$pcdir pkg-config --cflags --libs depthao-io) ||
	fail "pkg-config depthao-io with PKG_CONFIG_PATH=$pcdir"
# the headers from this tree (an install in /usr/local would hide a missing -I)
real_src=$(cd "$src" && pwd -P)
real_build=$(cd "$build" && pwd -P)
incs=$(PKG_CONFIG_PATH=$pcdir pkg-config --cflags-only-I depthao-io)
for want in "$real_src/include" "$real_build/include"; do
	found=0
	for f in $incs; do
		d=${f#-I}
		[ -d "$d" ] && [ "$(cd "$d" && pwd -P)" = "$want" ] && found=1
	done
	[ "$found" = 1 ] || fail "pkg-config --cflags depthao-io lacks -I$want: $incs"
done
# shellcheck disable=SC2086 # $flags is a list of words
${CC:-cc} -std=c11 -Wall -Wextra -Werror "$src/examples/shade_depth.c" $flags \
	-o "$work/shade_depth" || fail "building the example against the build tree: $flags"
libs=
for f in $(PKG_CONFIG_PATH=$pcdir pkg-config --libs-only-L depthao-io); do
	libs=${libs:+$libs:}${f#-L}
done
# it must load this tree's libraries, not ones installed on this machine
for l in libdepthao.so.1 libdepthao-io.so.1; do
	LD_LIBRARY_PATH=$libs ldd "$work/shade_depth" | grep -q "$l => $real_build/" ||
		fail "the example does not load $l from $real_build: $(LD_LIBRARY_PATH=$libs ldd "$work/shade_depth" | grep depthao)"
done
"$make_depth" "$work/depth.png" || fail "make_depth"
LD_LIBRARY_PATH=$libs "$work/shade_depth" "$work/depth.png" "$work/out.png" 60 60 31.5 23.5 ||
	fail "shade_depth on the build tree's libraries"
[ -s "$work/out.png" ] || fail "no image written"
echo "ok: examples/shade_depth.c built and run against $build through $pcdir"
