#!/bin/sh
# SPDX-License-Identifier: MIT
# check_function_length.py on function_length_sample.cpp (braces in comments,
# strings, characters, raw strings and #if branches; K&R and Allman braces; C++
# members) must name the one function over 100 lines, with its length, and fail.
# usage: check_function_length_selftest.sh PYTHON SCRIPT SAMPLE
set -u
[ $# -eq 3 ] || { echo "usage: $0 PYTHON SCRIPT SAMPLE" >&2; exit 2; }
dir=$(dirname "$3")
out=$("$1" "$2" "$dir" "$3")
rc=$?
want='function_length_sample.cpp:115: at_limit_plus_one is 101 lines (limit 100)'
if [ "$rc" -ne 1 ] || [ "$out" != "$want" ]; then
	echo "check_function_length.py: exit $rc, printed:" >&2
	printf '%s\n' "$out" >&2
	echo "expected exit 1 and: $want" >&2
	exit 1
fi
echo "ok: $out"
