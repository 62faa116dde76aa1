#!/bin/sh
# SPDX-License-Identifier: MIT
#
# The library's ABI against the committed baseline (docs/abi.md):
#   check_abi.sh LIB BASELINE HEADERS_DIR            compare (the test 'abi-baseline')
#   check_abi.sh --update LIB BASELINE HEADERS_DIR   write the baseline from LIB
# LIB is the built libdepthao.so.N.N.N (with debug info: src/meson.build adds -g),
# HEADERS_DIR include/depthao (only the types of the public headers count).
# Fails on any change abidiff reports except added functions; exits 77 (skip) when
# abidiff/abidw are absent or the baseline is of another architecture.
set -u
update=0
if [ "${1:-}" = --update ]; then
	update=1
	shift
fi
[ $# -eq 3 ] || { echo "usage: $0 [--update] LIB BASELINE HEADERS_DIR" >&2; exit 2; }
lib=$1 baseline=$2 headers=$3

for tool in abidw abidiff; do
	if ! command -v "$tool" >/dev/null 2>&1; then
		echo "SKIP: $tool not found: install abigail-tools (Debian; ./bootstrap.sh deps does)"
		exit 77
	fi
done
arch=$(uname -m)
if [ "$arch" != x86_64 ]; then
	echo "SKIP: the baseline is of x86_64 (LP64); this machine is $arch"
	exit 77
fi
if ! readelf -S "$lib" 2>/dev/null | grep -q '\.debug_info'; then
	echo "FAIL: $lib has no debug info (.debug_info): abidw cannot see the structs;" \
		"src/meson.build compiles the library with -g in every build type"
	exit 1
fi

# What the baseline holds: the exported functions and the public types they reach,
# with the source locations (the suppressions tell public types by them), without
# paths of the build or DT_NEEDED (they differ from build to build).
suppr=$(dirname "$0")/libdepthao.suppr
dump() {
	abidw --headers-dir "$headers" --drop-private-types --no-corpus-path \
		--no-comp-dir-path --no-elf-needed --type-id-style hash \
		--out-file "$1" "$lib"
}

if [ "$update" -eq 1 ]; then
	dump "$baseline" || { echo "FAIL: abidw could not read $lib"; exit 1; }
	echo "wrote $baseline from $lib ($(grep -c '<function-decl' "$baseline") functions);" \
		"commit it with the change that made it differ (docs/abi.md)"
	exit 0
fi

[ -f "$baseline" ] || { echo "FAIL: no baseline $baseline: ninja abi-baseline writes it"; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
dump "$tmp/now.abi" || { echo "FAIL: abidw could not read $lib"; exit 1; }
# abidiff's exit status is a bit mask: 1 error, 2 usage, 4 ABI change, 8 incompatible
# change.  Added functions alone are allowed (a minor version adds); any other change
# (a struct's layout, a removed or changed function, an enumerator) fails, and is either
# a mistake or, for a field appended to a sized struct, a baseline to update on purpose.
abidiff --suppressions "$suppr" --no-added-syms "$baseline" "$tmp/now.abi" \
	>"$tmp/diff.txt" 2>&1
rc=$?
cat "$tmp/diff.txt"
if [ $((rc & 3)) -ne 0 ]; then
	echo "FAIL: abidiff failed (exit $rc)"
	exit 1
fi
if [ $((rc & 12)) -ne 0 ]; then
	if [ $((rc & 8)) -ne 0 ]; then
		echo "FAIL: incompatible ABI change against $baseline (see above):" \
			"an existing program would break; see docs/abi.md"
	else
		echo "FAIL: the ABI changed against $baseline (see above): if the change is" \
			"one docs/abi.md allows (a field appended to a sized struct, a new" \
			"enumerator at the end), run 'ninja abi-baseline' and commit" \
			"tests/abi/libdepthao.abi with it; else undo it"
	fi
	exit 1
fi
added=$(abidiff --suppressions "$suppr" --added-fns "$baseline" "$tmp/now.abi" 2>/dev/null |
	grep -c "^  \[A\]")
[ "$added" -eq 0 ] || echo "note: $added function(s) added since the baseline (allowed;" \
	"'ninja abi-baseline' records them)"
echo "ABI unchanged against $(basename "$baseline"): $(grep -c '<function-decl' "$baseline") functions"
