#!/bin/sh
# SPDX-License-Identifier: MIT
# Each built plugin module exports its entry point and nothing else: no
# function, data, weak or unique symbol of its own code or of a static
# library linked into it.  A leaked symbol can clash with the host's or
# another plugin's (RTLD_GLOBAL), and becomes an interface nobody declared.
# usage: check_plugin_exports.sh ENTRY MODULE.so [ENTRY MODULE.so ...]
# ENTRY may list several symbols separated by commas: all must be exported.
set -eu
[ $# -ge 2 ] && [ $(($# % 2)) -eq 0 ] || {
	echo "usage: $0 ENTRY MODULE.so [ENTRY MODULE.so ...]" >&2
	exit 2
}
status=0
while [ $# -ge 2 ]; do
	entry=$1 so=$2
	shift 2
	# defined dynamic symbols, without the version-node (type A) entries
	syms=$(nm -D --defined-only "$so" | awk 'NF == 3 && $2 != "A" { print $3 }' | sort -u)
	entries=$(printf '%s\n' "$entry" | tr ',' '\n')
	for e in $entries; do
		if ! printf '%s\n' "$syms" | grep -qx "$e"; then
			echo "FAIL: $so does not export its entry point $e"
			status=1
		fi
	done
	leaked=$(printf '%s\n' "$syms" | grep -vxF "$entries" | grep -v '^$' || true)
	if [ -n "$leaked" ]; then
		echo "FAIL: $so exports more than $entry (build it with gnu_symbol_visibility 'hidden', its static libraries too, and link it with plugins/plugin.ver):"
		printf '%s\n' "$leaked" | sed 's/^/  /'
		status=1
	else
		echo "ok: $so exports only $entry"
	fi
done
exit $status
