#!/bin/sh
# SPDX-License-Identifier: MIT
# The configuration syntax (issue #16, item 10): lines of any length up to 64 KiB
# (comments and values: 200, 1000 and 4000 characters), and every error reported at
# the line where it is, with that line's message, also after long lines.
. "$(dirname "$0")/daemon_lib.sh"

# pad N: N 'a's
pad() {
	printf "%${1}s" | tr ' ' a
}

# check_ok NAME: --check-config $WORK/NAME.ini must pass; its output in $WORK/out
check_ok() {
	"$DAEMON" --check-config "$WORK/$1.ini" >"$WORK/out" 2>&1 || fail "$1: $(cut -c1-300 "$WORK/out")"
}

# check_error NAME EXPECTED: exit 2 and a message starting with EXPECTED
check_error() {
	set +e
	"$DAEMON" --check-config "$WORK/$1.ini" >"$WORK/out" 2>&1
	st=$?
	set -e
	[ "$st" -eq 2 ] || fail "$1: exit $st, expected 2: $(cut -c1-300 "$WORK/out")"
	grep -q -F -- "depthaod: $WORK/$1.ini:$2" "$WORK/out" || fail "$1: '$(cut -c1-300 "$WORK/out")' lacks ':$2'"
}

for n in 200 1000 4000; do
	# a comment line of n characters, and a sink URI making a line of n characters
	line="uri = images:$WORK/"
	dir=$(pad $((n - ${#line})))
	{
		printf '; %s\n' "$(pad $((n - 2)))"
		printf '[source]\nuri = %s\n[sink.a]\n' "$REC"
		printf '%s%s\n' "$line" "$dir"
	} >"$WORK/long$n.ini"
	[ "$(sed -n 5p "$WORK/long$n.ini" | tr -d '\n' | wc -c)" -eq "$n" ] || fail "test setup: line is not $n characters"
	check_ok "long$n"
	# the URI arrives whole: a bad stream after it is reported on the next line with its key
	printf 'stream = colour\n' >>"$WORK/long$n.ini"
	check_error "long$n" "6: [sink.a] stream: 'colour' must be"
	# and an AO value with a long inline comment
	printf '[source]\nuri = %s ; %s\n[sink.a]\nuri = images:%s/x\n[ao]\nradius = 0.3 ; %s\n' \
		"$REC" "$(pad "$n")" "$WORK" "$(pad "$n")" >"$WORK/inline$n.ini"
	check_ok "inline$n"
done
# the 4000-character URI is kept whole (the check prints the source)
printf '[source]\nuri = images:%s/%s\n[sink.a]\nuri = images:%s/x\n' "$WORK" "$(pad 3900)" "$WORK" >"$WORK/longsrc.ini"
check_ok longsrc
grep -q "(source images:$WORK/$(pad 3900), 1 sink)" "$WORK/out" || fail "long source URI cut: $(cut -c1-200 "$WORK/out")"

# an error on line N is reported as line N with line N's message
good="[source]
uri = $REC
[sink.a]
uri = images:$WORK/a"
printf '%s\n; %s\n[daemon]\nstats_interval = 5\nnot a pair\nlog_level = info\n[sink.a]\ncolour = red\n' \
	"$good" "$(pad 1000)" >"$WORK/syntax_first.ini"
check_error syntax_first "8: not 'key = value' or '[section]'"
printf '%s\n; %s\n[sink.a]\ncolour = red\nnot a pair\n' "$good" "$(pad 4000)" >"$WORK/key_first.ini"
check_error key_first "7: [sink.a] colour: unknown key"
for n in 3 10 57; do
	{
		printf '%s\n' "$good"
		i=5
		while [ "$i" -lt "$n" ]; do
			printf '; %s\n' "$(pad $((i * 37)))"
			i=$((i + 1))
		done
		printf 'queue = 99\n'
	} >"$WORK/line$n.ini"
	want=$n
	[ "$n" -ge 5 ] || want=5
	check_error "line$n" "$want: [sink.a] queue: '99' must be a frame count in 1..64"
done
printf '%s\n[ao\n' "$good" >"$WORK/bracket.ini"
check_error bracket "5: '[' without ']'"
printf '%s\n[ao] radius = 1\n' "$good" >"$WORK/after.ini"
check_error after "5: text after [ao]"
printf '%s\n= 5\n' "$good" >"$WORK/nokey.ini"
check_error nokey "5: not 'key = value'"
printf '%s\n' "$good" >"$WORK/toolong.ini"
printf '; %s\n' "$(pad 70000)" >>"$WORK/toolong.ini"
check_error toolong "5: the line is longer than 65536 bytes"
printf '%s\nstats\000 = 1\n' "$good" >"$WORK/nul.ini"
check_error nul "5: the line holds a NUL byte"

# what libinih took stays valid: a byte order mark, CR LF, '#' comments, indentation,
# blanks around '=', an empty file section
printf '\357\273\277[source]\r\n  uri=%s\r\n# comment\r\n\t[sink.a]\r\n\turi   =   images:%s/a  ; x\r\n[ao]\r\n' \
	"$REC" "$WORK" >"$WORK/compat.ini"
check_ok compat
grep -q "compat.ini: ok (source $REC, 1 sink)" "$WORK/out" || fail "compat: $(cat "$WORK/out")"
finish
