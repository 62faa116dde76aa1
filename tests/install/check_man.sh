#!/bin/sh
# SPDX-License-Identifier: MIT
# The manual pages (issue #16, item 14): each renders with groff's warnings as errors
# (and through man -l), and nothing the programs accept is missing from them, so they
# cannot drift: every option in 'depthao --help' and each command's --help is in
# depthao(1), every option in 'depthaod --help' in depthaod(8), and every key the
# configuration parser accepts (the keys its messages list, and every key name compared
# in tools/depthaod/config.c) in depthaod.ini(5), with the sections.
# usage: check_man.sh MAN_DIR DEPTHAO DEPTHAOD SOURCE_DIR
set -eu
[ $# -eq 4 ] || { echo "usage: $0 MAN_DIR DEPTHAO DEPTHAOD SOURCE_DIR" >&2; exit 2; }
man_dir=$1
depthao=$2
depthaod=$3
src=$4
command -v groff >/dev/null 2>&1 || { echo "SKIP: groff is not installed (groff-base)"; exit 77; }
work=$(mktemp -d "${TMPDIR:-/tmp}/dao-man.XXXXXX")
trap 'rm -rf "$work"' EXIT
failures=0
fail() {
	echo "FAIL: $*"
	failures=$((failures + 1))
}

# render PAGE: plain text in $work/PAGE.txt; any warning fails
for page in depthao.1 depthaod.8 depthaod.ini.5; do
	p=$man_dir/$page
	[ -f "$p" ] || { fail "$p is missing"; continue; }
	LC_ALL=C.UTF-8 groff -man -Tutf8 -ww -P-cbou "$p" >"$work/$page.txt" 2>"$work/$page.err" ||
		fail "$page: groff failed"
	[ ! -s "$work/$page.err" ] || fail "$page: groff warnings: $(cat "$work/$page.err")"
	if command -v man >/dev/null 2>&1; then
		MANWIDTH=80 LC_ALL=C.UTF-8 man --warnings=w -l "$p" >/dev/null 2>"$work/$page.man" ||
			fail "$page: man -l failed"
		[ ! -s "$work/$page.man" ] || fail "$page: man -l warnings: $(cat "$work/$page.man")"
	fi
	grep -q '@[A-Z]*@' "$p" && fail "$page: a placeholder was not substituted"
	# the rendered text uses a real hyphen-minus for \-, so options read as typed
	grep -q -- '--help' "$work/$page.txt" || [ "$page" = depthaod.ini.5 ] ||
		fail "$page: --help does not render as typed"
done

# options FILE: the --long options (and -c) a help text shows, one per line
options() {
	grep -oE -- "(^|[^a-zA-Z0-9-])--?[a-zA-Z][a-zA-Z0-9.-]*" "$1" | sed 's/^[^-]*//; s/[.]$//' |
		sort -u
}

"$depthao" --help >"$work/help"
for cmd in process synth eval compare sensorstats realcheck bench devices ctl; do
	"$depthao" "$cmd" --help >>"$work/help" 2>&1 || true
done
n=0
for o in $(options "$work/help"); do
	case "$o" in -h | -[a-z]) continue ;; esac # none so far; short forms would need their own check
	n=$((n + 1))
	grep -qE -- "$o([^a-zA-Z0-9-]|\$)" "$work/depthao.1.txt" || fail "depthao(1) lacks $o (from depthao --help)"
done
[ "$n" -ge 50 ] || fail "only $n options found in depthao's help: the check does not work"

"$depthaod" --help >"$work/dhelp"
n=0
for o in $(options "$work/dhelp"); do
	n=$((n + 1))
	grep -qE -- "$o([^a-zA-Z0-9-]|\$)" "$work/depthaod.8.txt" || fail "depthaod(8) lacks $o (from depthaod --help)"
done
[ "$n" -ge 15 ] || fail "only $n options found in depthaod's help: the check does not work"

# config keys: what the parser lists when a key is unknown, per section ...
printf '[source]\nuri = x\n[sink.a]\nuri = y4m:-\n' >"$work/base.ini"
: >"$work/keys"
for section in source sink.a daemon; do
	set +e
	"$depthaod" --check-config "$work/base.ini" --set "$section.no_such_key=1" >"$work/out" 2>&1
	set -e
	sed -n 's/.*unknown key (keys: \(.*\)).*/\1/p' "$work/out" | tr ',' '\n' | tr -d ' ' >>"$work/keys"
done
# ... and every key name the parser compares against (the source, in case a list lags)
grep -o 'strcmp(key, "[a-z_]*")' "$src/tools/depthaod/config.c" | sed 's/.*"\(.*\)")/\1/' >>"$work/keys"
n=0
for k in $(sort -u "$work/keys"); do
	n=$((n + 1))
	# a key is documented where a tagged paragraph starts with it: "       key = ..."
	grep -q "^       $k\\( =\\|\$\\)" "$work/depthaod.ini.5.txt" ||
		fail "depthaod.ini(5) does not document the key '$k'"
done
[ "$n" -ge 15 ] || fail "only $n config keys found: the check does not work"
for s in '\[source\]' '\[ao\]' '\[sink\.NAME\]' '\[daemon\]'; do
	grep -q "^$s" "$work/depthaod.ini.5.txt" || fail "depthaod.ini(5) has no section $s"
done
# [ao] takes every AO parameter: those are depthao(1)'s, checked above through process --help

if [ "$failures" -ne 0 ]; then
	echo "$failures failure(s)"
	exit 1
fi
echo "all passed"
