#!/bin/sh
# SPDX-License-Identifier: MIT
# Every function the library's public headers declare must be exported by it
# (marked DAO_API) in the version node of its version script, and the library
# must export nothing else: no symbol of any kind (functions, ifuncs, weak
# symbols, data) that those headers do not declare.  Run once per library:
#   libdepthao.so     src/libdepthao.ver        depthao/depthao.h (the AO core)
#   libdepthao-io.so  src/io/libdepthao-io.ver  depthao/io.h minus depthao/depthao.h
# so a core function exported by libdepthao-io (a second copy of the core in
# it) fails, as does an io function exported by libdepthao.
# usage: check_exports.sh LIB VERSION_SCRIPT HEADER INCLUDE_DIR GENERATED_INCLUDE_DIR [BASE_HEADER]
#   HEADER, BASE_HEADER: names under INCLUDE_DIR (depthao/io.h); the functions
#   BASE_HEADER declares are another library's and are left out of HEADER's
set -eu
[ $# -eq 5 ] || [ $# -eq 6 ] || {
	echo "usage: $0 LIB VERSION_SCRIPT HEADER INCLUDE_DIR GENERATED_INCLUDE_DIR [BASE_HEADER]" >&2
	exit 2
}
lib=$1 map=$2 header=$3 inc=$4 geninc=$5 base=${6:-}
tmp=$(mktemp -d "${TMPDIR:-/tmp}/dao-exports.XXXXXX")
trap 'rm -rf "$tmp"' EXIT

# the version node the script defines (one per library, "NAME {")
node=$(sed -n 's/^\([A-Z][A-Z0-9_]*\)[[:space:]]*{.*/\1/p' "$map")
[ "$(printf '%s\n' "$node" | grep -c .)" -eq 1 ] ||
	{ echo "FAIL: $map defines not exactly one version node: '$node'"; exit 1; }

# the dao_* functions a header declares, static inline wrappers left out
# (dao_params_init passes the caller's sizeof to dao_params_init_sized: they live in the caller)
declared() {
	echo "#include <$1>" |
		${CC:-cc} -std=c11 -E -P -I"$inc" -I"$geninc" -x c - >"$tmp/headers"
	grep -o 'static inline [a-z_ ]*[ *]dao_[a-z0-9_]*[[:space:]]*(' "$tmp/headers" |
		grep -o 'dao_[a-z0-9_]*' | sort -u >"$tmp/inline"
	grep -o 'dao_[a-z0-9_]*[[:space:]]*(' "$tmp/headers" | tr -d ' \t(' | sort -u |
		comm -23 - "$tmp/inline"
}
declared "$header" >"$tmp/declared"
if [ -n "$base" ]; then
	declared "$base" >"$tmp/base"
	comm -23 "$tmp/declared" "$tmp/base" >"$tmp/own"
	mv "$tmp/own" "$tmp/declared"
fi
[ -s "$tmp/declared" ] || { echo "FAIL: $header declares no function of its own"; exit 1; }
# name@@VERSION type, for every defined dynamic symbol but the version node itself
nm -D --defined-only --with-symbol-versions "$lib" |
	awk 'NF == 3 && $2 != "A" { print $3, $2 }' | sort -u >"$tmp/symbols"
sed 's/@.*//' "$tmp/symbols" | awk '{ print $1 }' | sort -u >"$tmp/exported"

name=$(basename "$lib")
status=0
for f in $(comm -23 "$tmp/declared" "$tmp/exported"); do
	echo "FAIL: $f is declared by $header but not exported by $name (add DAO_API to its declaration; is its source built into $name?)"
	status=1
done
for f in $(comm -13 "$tmp/declared" "$tmp/exported"); do
	if [ -n "$base" ] && grep -qx "$f" "$tmp/base"; then
		echo "FAIL: $f is $base's (the other library's) but $name exports it: a copy of the other library's code is linked in"
	else
		echo "FAIL: $f ($(grep "^$f[@ ]" "$tmp/symbols" | awk '{ print "type " $2 }' | head -n 1)) is exported by $name but not declared by $header (make it static or hidden; a target_clones function goes into local: of $map)"
	fi
	status=1
done
while read -r sym type; do
	case "$sym" in
	*"@@$node") ;;
	*) echo "FAIL: $sym (type $type) is not in the version node $node ($map)"; status=1 ;;
	esac
done <"$tmp/symbols"
[ "$status" -ne 0 ] || echo "$name: $(wc -l <"$tmp/declared") public functions of $header, all exported at $node, nothing else"
exit "$status"
