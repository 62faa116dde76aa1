#!/bin/sh
# SPDX-License-Identifier: MIT
# A stand-in for another build's depthao in test_cli_bench_compare.sh: answers
# --version and prints canned `bench --json` lines, so that what `depthao bench
# --compare` makes of them can be checked exactly.  Each call is appended to
# $FAKE_LOG; $FAKE_MODE picks the behaviour:
#   ok       one line per --threads (1 if none) for the --size given; median_ms
#            2, 4, 8, 2, 4, 8 ... by call (the --version call not counted), p95
#            twice that; no "noise" stage (as the last release) and a zero
#            "output" stage
#   reject   rejects --noise-model and --input (bench's before --input was added) as
#            unknown options (exit 2, as bench does)
#   fail     exits 1 with a message on stderr
#   crash    kills itself with SIGSEGV
#   garbage  prints a line that is not JSON
#   other    prints a size other than the one asked for
set -eu
echo "$*" >>"$FAKE_LOG"
if [ "${1:-}" = "--version" ]; then
	echo "depthao 0.0.1 (fake)"
	exit 0
fi
[ "${1:-}" = "bench" ] || { echo "fake: no command" >&2; exit 2; }
shift
size=""
threads=""
prev=""
for a in "$@"; do
	case "$prev:$a" in
	--size:*) size=$a ;;
	--threads:*) threads="$threads $a" ;;
	esac
	case "$FAKE_MODE:$a" in
	reject:--noise-model | reject:--input)
		echo "depthao: unknown option '$a' (see 'depthao bench --help')" >&2
		exit 2
		;;
	esac
	prev=$a
done
case "$FAKE_MODE" in
fail) echo "depthao bench: out of memory for the benchmark buffers" >&2; exit 1 ;;
crash) kill -SEGV $$ ;;
garbage) echo "not json"; exit 0 ;;
esac
n=$(grep -vc -- '^--version' "$FAKE_LOG")
median=$((2 << ((n - 1) % 3)))
w=${size%x*}
h=${size#*x}
[ "$FAKE_MODE" = other ] && w=$((w + 1))
for t in ${threads:-1}; do
	printf '{"width":%d,"height":%d,"quality":"default","slices":2,"steps":6,"threads":%d,' \
		"$w" "$h" "$t"
	printf '"median_ms":%d,"p95_ms":%d,"stage_median_ms":{"decode":1,"prefilter":0.5,' \
		"$median" $((2 * median))
	printf '"gtao":%d,"output":0}}\n' "$median"
done
