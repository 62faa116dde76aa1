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
# shellcheck disable=SC2086 # $flags is a list of words
${CC:-cc} -std=c11 -Wall -Wextra -Werror "$src/examples/shade_depth.c" $flags \
	-o "$work/shade_depth" || fail "building the example against the build tree: $flags"
libs=$(PKG_CONFIG_PATH=$pcdir pkg-config --libs-only-L depthao-io | sed 's/-L//g; s/ /:/g')
"$make_depth" "$work/depth.png" || fail "make_depth"
LD_LIBRARY_PATH=$libs "$work/shade_depth" "$work/depth.png" "$work/out.png" 60 60 31.5 23.5 ||
	fail "shade_depth on the build tree's libraries"
[ -s "$work/out.png" ] || fail "no image written"
echo "ok: examples/shade_depth.c built and run against $build through $pcdir"
