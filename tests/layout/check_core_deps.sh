#!/bin/sh
# SPDX-License-Identifier: MIT
# The AO core stands alone, as built (check_layering.sh checks the includes):
#   - libdepthao.so needs libc, libm and pthreads only (no libpng, liblz4, libbz2,
#     libturbojpeg, libdl, and no libdepthao-io);
#   - no object of the core (its internal static library and its kernel
#     libraries) refers to a symbol defined by libdepthao-io's objects or to a
#     function of a container library, even one the link would have dropped;
#   - libdepthao-io.so needs libdepthao.so.1 (one copy of the core, not its own).
# usage: check_core_deps.sh LIBDEPTHAO_SO LIBDEPTHAO_IO_SO CORE_STATIC IO_STATIC [KERNEL_STATIC...]
set -eu
[ $# -ge 4 ] || { echo "usage: $0 LIBDEPTHAO_SO LIBDEPTHAO_IO_SO CORE_STATIC IO_STATIC [KERNEL_STATIC...]" >&2; exit 2; }
core_so=$1 io_so=$2 core_a=$3 io_a=$4
shift 4
tmp=$(mktemp -d "${TMPDIR:-/tmp}/dao-core-deps.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
status=0

needed() { readelf -d "$1" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p'; }
needed "$core_so" >"$tmp/needed"
[ -s "$tmp/needed" ] || { echo "FAIL: readelf found no NEEDED entry in $core_so"; exit 1; }
while read -r n; do
	case "$n" in
	libc.so.* | libm.so.* | libpthread.so.* | ld-linux*.so.* | libmvec.so.*) ;;
	*) echo "FAIL: $(basename "$core_so") needs $n: the AO core links libc, libm and pthreads only"; status=1 ;;
	esac
done <"$tmp/needed"
needed "$io_so" | grep -qx 'libdepthao\.so\.1' ||
	{ echo "FAIL: $(basename "$io_so") does not need libdepthao.so.1: $(needed "$io_so" | tr '\n' ' ')"; status=1; }

# symbols defined by the io objects, and those the core's objects refer to
nm --defined-only "$io_a" 2>/dev/null | awk 'NF == 3 && $2 ~ /[TDBRVWi]/ { print $3 }' | sort -u >"$tmp/io_defined"
[ -s "$tmp/io_defined" ] || { echo "FAIL: nm found no symbol in $io_a"; exit 1; }
nm -u "$core_a" "$@" 2>/dev/null | awk 'NF == 2 { print $2 }' | sort -u >"$tmp/core_undefined"
[ -s "$tmp/core_undefined" ] || { echo "FAIL: nm found no undefined symbol in $core_a"; exit 1; }
for s in $(comm -12 "$tmp/io_defined" "$tmp/core_undefined"); do
	echo "FAIL: the AO core refers to $s, defined by libdepthao-io ($(nm -A -u "$core_a" "$@" 2>/dev/null | grep " $s\$" | head -n 1 | cut -d: -f2))"
	status=1
done
# libpng png_*, liblz4 LZ4*, libbz2 BZ2_*, libturbojpeg tj*, zlib, dlopen
bad=$(grep -E '^(png_|LZ4|BZ2_|tj[A-Z]|tjInit|jpeg_|deflate|inflate|dlopen|dlsym|dlclose)' "$tmp/core_undefined" || true)
if [ -n "$bad" ]; then
	echo "FAIL: the AO core calls a container library's functions: $(echo "$bad" | tr '\n' ' ')"
	status=1
fi
[ "$status" -ne 0 ] ||
	echo "libdepthao needs only $(tr '\n' ' ' <"$tmp/needed")and refers to nothing of libdepthao-io ($(wc -l <"$tmp/io_defined") symbols) nor of a container library"
exit "$status"
