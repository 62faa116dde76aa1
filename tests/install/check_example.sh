#!/bin/sh
# SPDX-License-Identifier: MIT
# Installs the libraries into a staging directory, checks what was installed,
# builds examples/shade_depth.c against them through pkg-config alone (depthao-io,
# which brings depthao) and runs it on a depth image made by MAKE_DEPTH; builds
# tests/install/core_only.c with `pkg-config depthao` alone and checks that the
# AO core needs no container library (docs/libraries.md).
# usage: check_example.sh BUILD_DIR SOURCE_DIR MAKE_DEPTH
set -eu
[ $# -eq 3 ] || { echo "usage: $0 BUILD_DIR SOURCE_DIR MAKE_DEPTH" >&2; exit 2; }
build=$1
src=$2
make_depth=$3
stage=$(mktemp -d "${TMPDIR:-/tmp}/dao-install.XXXXXX")
trap 'rm -rf "$stage"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

"$make_depth" "$stage/depth.png" || fail "make_depth"
# meson test points LD_LIBRARY_PATH at the build tree; the example must not see it
unset LD_LIBRARY_PATH
meson install -C "$build" --destdir "$stage" --quiet >/dev/null || fail "meson install"

# What installed libdepthao and libdepthao-io consist of, wherever the prefix and libdir are.
pc=$(find "$stage" -name depthao.pc | head -n 1)
[ -n "$pc" ] || fail "depthao.pc was not installed"
[ -n "$(find "$stage" -name depthao-io.pc)" ] || fail "depthao-io.pc was not installed"
lib=$(find "$stage" -name libdepthao.so | head -n 1)
[ -n "$lib" ] || fail "libdepthao.so was not installed"
io_lib=$(find "$stage" -name libdepthao-io.so | head -n 1)
[ -n "$io_lib" ] || fail "libdepthao-io.so was not installed"
for h in depthao api version error frame camera params context cpu overlay \
	io png ply oni plugin output_file; do
	[ -n "$(find "$stage" -path "*/include/depthao/$h.h")" ] || fail "include/depthao/$h.h was not installed"
done

# No path of the build tree in what is installed (reproducible builds; the tools
# find the plugins built beside them through a file that is not installed)
real_build=$(cd "$build" && pwd -P)
for f in $(find "$stage" -type f \( -name 'depthao' -o -name 'depthaod' -o -name 'libdepthao*.so*' -o -name '*.so' \)); do
	if grep -qF "$real_build" "$f"; then
		fail "$f contains the build directory $real_build"
	fi
done
[ -z "$(find "$stage" -name dao-build-plugin-path)" ] || fail "dao-build-plugin-path was installed"

# The .pc files name the real prefix (/usr/local): redefine it to the staged one
# (libdir and includedir are derived from it; libpng's own flags stay as they are).
prefix=$(PKG_CONFIG_PATH=$(dirname "$pc") pkg-config --variable=prefix depthao)
pkgconf() {
	PKG_CONFIG_PATH=$(dirname "$pc") pkg-config --define-variable=prefix="$stage$prefix" "$@"
}
# The AO core pulls no container library, not even for static linking
containers='-lpng|-lpng16|-llz4|-lbz2|-lturbojpeg|-ljpeg|-lz|-ldl|libpng|liblz4|libturbojpeg|depthao-io'
for args in "--libs depthao" "--libs --static depthao" "--print-requires depthao" \
	"--print-requires-private depthao"; do
	# shellcheck disable=SC2086 # $args is a list of words
	out=$(pkgconf $args) || fail "pkg-config $args"
	if printf '%s\n' "$out" | tr ' ' '\n' | grep -Eqx -- "$containers"; then
		fail "pkg-config $args lists a container library: $out"
	fi
done
# ... and libdepthao-io brings the core and its containers (static linking)
pkgconf --print-requires depthao-io | grep -qx 'depthao' ||
	fail "depthao-io.pc does not require depthao: $(pkgconf --print-requires depthao-io)"
static_io=$(pkgconf --libs --static depthao-io) || fail "pkg-config --libs --static depthao-io"
for l in -ldepthao-io -ldepthao -lpng16 -llz4 -lbz2 -lturbojpeg; do
	printf '%s\n' "$static_io" | tr ' ' '\n' | grep -qx -- "$l" ||
		fail "pkg-config --libs --static depthao-io lacks $l: $static_io"
done

flags=$(pkgconf --cflags --libs depthao-io) || fail "pkg-config depthao-io"
case "$flags" in
*"-I$stage"*"-L$stage"* | *"-L$stage"*"-I$stage"*) ;;
*) fail "pkg-config flags do not point into the staged install: $flags" ;;
esac
# shellcheck disable=SC2086 # $flags is a list of words
${CC:-cc} -std=c11 -Wall -Wextra -Werror "$src/examples/shade_depth.c" $flags \
	-Wl,-rpath,"$(dirname "$lib")" -o "$stage/shade_depth" || fail "building the example"
# it must run on the staged libraries, not on ones installed on this machine
for l in libdepthao.so.1 libdepthao-io.so.1; do
	ldd "$stage/shade_depth" | grep -q "$l => $stage/" ||
		fail "the example does not load the staged $l: $(ldd "$stage/shade_depth" | grep depthao)"
done

# The AO core alone, through `pkg-config depthao`: it builds, it loads neither
# libdepthao-io nor a container library, and it shades
core_flags=$(pkgconf --cflags --libs depthao) || fail "pkg-config depthao"
# shellcheck disable=SC2086 # $core_flags is a list of words
${CC:-cc} -std=c11 -Wall -Wextra -Werror "$src/tests/install/core_only.c" $core_flags \
	-Wl,-rpath,"$(dirname "$lib")" -o "$stage/core_only" || fail "building core_only.c with pkg-config depthao"
ldd "$stage/core_only" | grep -q "libdepthao.so.1 => $stage/" ||
	fail "core_only does not load the staged libdepthao: $(ldd "$stage/core_only" | grep depthao)"
if ldd "$stage/core_only" | grep -Eq 'libdepthao-io|libpng|liblz4|libbz2|libturbojpeg|libz\.|libdl\.'; then
	fail "the AO core alone loads more than libc, libm and pthreads: $(ldd "$stage/core_only" | tr -s '\t ' ' ')"
fi
"$stage/core_only" || fail "core_only (the AO core alone)"

# The installed tools run on the shared library too (one copy of it in a daemon
# that loads plugins, and the tools exercise the ABI), not on a private static copy
libdir=$(dirname "$lib")
for t in depthao depthaod; do
	exe=$(find "$stage" -type f -name "$t" | head -n 1)
	[ -n "$exe" ] || fail "$t was not installed"
	for l in libdepthao libdepthao-io; do
		readelf -d "$exe" | grep -q "NEEDED.*\[$l\.so\.1\]" ||
			fail "$t does not link $l.so.1: $(readelf -d "$exe" | grep NEEDED | tr -s ' ')"
		LD_LIBRARY_PATH="$libdir" ldd "$exe" | grep -q "$l.so.1 => $libdir/" ||
			fail "$t does not load the staged $l: $(LD_LIBRARY_PATH="$libdir" ldd "$exe" | grep depthao)"
	done
	for f in dao_context_create dao_png_write; do
		if nm "$exe" 2>/dev/null | grep -q " [Tt] $f\$"; then
			fail "$t carries its own copy of a library ($f is defined in it)"
		fi
	done
	LD_LIBRARY_PATH="$libdir" "$exe" --version >/dev/null || fail "$t --version on the staged library"
done

"$stage/shade_depth" "$stage/depth.png" "$stage/out.png" 60 60 31.5 23.5 || fail "shade_depth with intrinsics"
"$stage/shade_depth" "$stage/depth.png" "$stage/default.png" || fail "shade_depth with the default camera"
for f in out default; do
	sig=$(head -c 8 "$stage/$f.png" | od -An -tx1 | tr -d ' \n')
	[ "$sig" = "89504e470d0a1a0a" ] || fail "$f.png is not a PNG (starts with '$sig')"
done

# Errors come back as the library's message and a non-zero exit.
if "$stage/shade_depth" "$stage/missing.png" "$stage/x.png" 2>"$stage/err"; then
	fail "a missing input was accepted"
fi
grep -q "missing.png" "$stage/err" || fail "no message naming the missing file: $(cat "$stage/err")"
if "$stage/shade_depth" "$stage/depth.png" "$stage/x.png" 0 60 31.5 23.5 2>"$stage/err"; then
	fail "fx = 0 was accepted"
fi
grep -q "shade_depth: ." "$stage/err" || fail "no message for fx = 0"
[ ! -e "$stage/x.png" ] || fail "an output was written after an error"
echo "example built against the installed libraries and ran; the AO core alone needs no container library"
