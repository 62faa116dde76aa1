#!/bin/sh
# SPDX-License-Identifier: MIT
# Every function the public headers declare must be exported by libdepthao.so
# (marked DAO_API) in the version node DEPTHAO_1 (src/libdepthao.ver), and the
# library must export nothing else: no symbol of any kind (functions, ifuncs,
# weak symbols, data) that the headers do not declare.
# usage: check_exports.sh LIBDEPTHAO_SO INCLUDE_DIR GENERATED_INCLUDE_DIR
set -eu
[ $# -eq 3 ] || { echo "usage: $0 LIBDEPTHAO_SO INCLUDE_DIR GENERATED_INCLUDE_DIR" >&2; exit 2; }
tmp=$(mktemp -d "${TMPDIR:-/tmp}/dao-exports.XXXXXX")
trap 'rm -rf "$tmp"' EXIT

echo '#include <depthao/depthao.h>' |
	${CC:-cc} -std=c11 -E -P -I"$2" -I"$3" -x c - >"$tmp/headers"
# static inline wrappers (dao_params_init passes the caller's sizeof to
# dao_params_init_sized) live in the caller, not in the library
grep -o 'static inline [a-z_ ]*[ *]dao_[a-z0-9_]*[[:space:]]*(' "$tmp/headers" |
	grep -o 'dao_[a-z0-9_]*' | sort -u >"$tmp/inline"
grep -o 'dao_[a-z0-9_]*[[:space:]]*(' "$tmp/headers" | tr -d ' \t(' | sort -u |
	comm -23 - "$tmp/inline" >"$tmp/declared"
# name@@VERSION type, for every defined dynamic symbol but the version node itself
nm -D --defined-only --with-symbol-versions "$1" |
	awk 'NF == 3 && $2 != "A" { print $3, $2 }' | sort -u >"$tmp/symbols"
sed 's/@.*//' "$tmp/symbols" | awk '{ print $1 }' | sort -u >"$tmp/exported"

status=0
for f in $(comm -23 "$tmp/declared" "$tmp/exported"); do
	echo "FAIL: $f is declared in include/depthao/ but not exported (add DAO_API to its declaration)"
	status=1
done
for f in $(comm -13 "$tmp/declared" "$tmp/exported"); do
	echo "FAIL: $f ($(grep "^$f[@ ]" "$tmp/symbols" | awk '{ print "type " $2 }' | head -n 1)) is exported but not declared in the public headers (make it static or hidden; a target_clones function goes into local: of src/libdepthao.ver)"
	status=1
done
while read -r sym type; do
	case "$sym" in
	*@@DEPTHAO_1) ;;
	*) echo "FAIL: $sym (type $type) is not in the version node DEPTHAO_1 (src/libdepthao.ver)"; status=1 ;;
	esac
done <"$tmp/symbols"
[ "$status" -ne 0 ] || echo "$(wc -l <"$tmp/declared") public functions, all exported at DEPTHAO_1, nothing else"
exit "$status"
