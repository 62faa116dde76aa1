# SPDX-License-Identifier: MIT
# Helpers for the CLI tests: sourced by each test script.
# usage: <script> DEPTHAO PNG_INFO
set -eu
DEPTHAO=$1
PNG_INFO=$2
WORK=$(mktemp -d "${TMPDIR:-/tmp}/dao-cli.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
failures=0

fail() {
	echo "FAIL: $*"
	failures=$((failures + 1))
}

# expect_exit CODE DESCRIPTION -- command...   (captures stderr in $WORK/err)
expect_exit() {
	want=$1
	what=$2
	shift 3
	set +e
	"$@" >"$WORK/out" 2>"$WORK/err"
	got=$?
	set -e
	if [ "$got" -ne "$want" ]; then
		fail "$what: exit $got, expected $want; stderr: $(cat "$WORK/err")"
		return 1
	fi
	return 0
}

# expect_usage_error DESCRIPTION -- command...: exit 2 with exactly one stderr line
expect_usage_error() {
	what=$1
	shift
	if expect_exit 2 "$what" "$@"; then
		lines=$(wc -l <"$WORK/err")
		[ "$lines" -eq 1 ] || fail "$what: $lines stderr lines, expected one: $(cat "$WORK/err")"
		grep -q "^depthao: " "$WORK/err" || fail "$what: message lacks the 'depthao:' prefix"
	fi
}

# png_is FILE "W H FORMAT"
png_is() {
	info=$("$PNG_INFO" "$1" 2>&1) || { fail "$1 unreadable: $info"; return; }
	case "$info" in
	"$2"*) ;;
	*) fail "$1 is '$info', expected '$2 ...'" ;;
	esac
}

no_temp_files() {
	if find "$1" -name '*.tmp-*' | grep -q .; then
		fail "temporary files left in $1: $(find "$1" -name '*.tmp-*')"
	fi
}

finish() {
	if [ "$failures" -ne 0 ]; then
		echo "$failures failure(s)"
		exit 1
	fi
	echo "all passed"
}
