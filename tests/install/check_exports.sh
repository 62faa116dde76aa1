#!/bin/sh
# SPDX-License-Identifier: MIT
# Every function the public headers declare must be exported by libdepthao.so
# (marked DAO_API), and the library must export nothing else.
# usage: check_exports.sh LIBDEPTHAO_SO INCLUDE_DIR GENERATED_INCLUDE_DIR
set -eu
[ $# -eq 3 ] || { echo "usage: $0 LIBDEPTHAO_SO INCLUDE_DIR GENERATED_INCLUDE_DIR" >&2; exit 2; }
tmp=$(mktemp -d "${TMPDIR:-/tmp}/dao-exports.XXXXXX")
trap 'rm -rf "$tmp"' EXIT

echo '#include <depthao/depthao.h>' |
	${CC:-cc} -std=c11 -E -P -I"$2" -I"$3" -x c - |
	grep -o 'dao_[a-z0-9_]*[[:space:]]*(' | tr -d ' \t(' | sort -u >"$tmp/declared"
nm -D --defined-only "$1" | awk '$2 == "T" { print $3 }' | grep '^dao_' | sort -u >"$tmp/exported"
nm -D --defined-only "$1" | awk 'NF == 3 && $3 !~ /^dao_/ { print $3 }' >"$tmp/foreign"

status=0
for f in $(comm -23 "$tmp/declared" "$tmp/exported"); do
	echo "FAIL: $f is declared in include/depthao/ but not exported (add DAO_API to its declaration)"
	status=1
done
for f in $(comm -13 "$tmp/declared" "$tmp/exported") $(cat "$tmp/foreign"); do
	echo "FAIL: $f is exported but not declared in the public headers"
	status=1
done
[ "$status" -ne 0 ] || echo "$(wc -l <"$tmp/declared") public functions, all exported, nothing else"
exit "$status"
