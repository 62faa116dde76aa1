#!/bin/sh
# SPDX-License-Identifier: MIT
# depthao bench --compare / --compare-params: the structure of the side-by-side
# table and JSON, the rounds each build ran, the ratios computed from the
# rounds (exactly, against a fake other build printing canned JSON), and the
# errors: a missing or wrong --compare, an option the other build rejects, a
# failing child.  Timings are printed, never asserted.
. "$(dirname "$0")/cli_lib.sh"

FAKE="$(cd "$(dirname "$0")" && pwd)/fake_depthao.sh"
BUILD=$(cd "$(dirname "$DEPTHAO")/../.." && pwd)
export FAKE_LOG="$WORK/fake.log"
export FAKE_MODE=ok
SMALL="--quality default --min-time 0 --min-iterations 1 --no-reference"

# the same build directory, table: every configuration with A, B and A/B rows
if expect_exit 0 "compare table" -- "$DEPTHAO" bench --compare "$BUILD" --rounds 2 \
	--size 32x24,48x32 --threads 1 $SMALL; then
	for want in "^  A  this build .*tools/depthao/depthao   depthao [0-9]" \
		"^  B  other build .*tools/depthao/depthao   depthao [0-9]" "2 rounds" \
		"^each run: depthao bench --threads 1 --quality default .* --size WxH --json$" \
		"one run per size WxH: 32x24 48x32" "^load average before: " \
		"^load average after: " "^32x24 default 2x6, 1 thread$" "^48x32 default 2x6, 1 thread$"; do
		grep -q -- "$want" "$WORK/out" || fail "compare table lacks '$want': $(cat "$WORK/out")"
	done
	[ "$(grep -c '^  A/B  ' "$WORK/out")" -eq 2 ] || fail "compare table: not 2 A/B rows"
	[ "$(grep -c '^  B  *[0-9]' "$WORK/out")" -eq 2 ] || fail "compare table: not 2 B rows"
fi

# the same build by its binary, JSON: each build ran every round, and the ratios are the
# rounds' medians divided
if expect_exit 0 "compare json" -- "$DEPTHAO" bench --compare "$DEPTHAO" --rounds 3 \
	--size 32x24 --threads 1,2 $SMALL --json; then
	python3 - "$WORK/out" <<'PY' || fail "compare --json: $(cat "$WORK/out")"
import json, statistics, sys
lines = open(sys.argv[1]).read().splitlines()
assert len(lines) == 1, lines
o = json.loads(lines[0])
assert o["rounds"] == 3 and o["sizes"] == ["32x24"], o
assert len(o["load_before"]) == 3 and len(o["load_after"]) == 3, o
assert [b["build"] for b in o["builds"]] == ["A", "B"], o["builds"]
for b in o["builds"]:
    assert b["runs"] == 3, b
    assert b["version"].startswith("depthao "), b
    assert b["args"][0] == "bench" and b["args"][-1] == "--json", b
    assert b["args"][1:] == o["builds"][0]["args"][1:], b
    assert "--threads" in b["args"] and "--rounds" not in b["args"], b
    assert "--compare" not in b["args"], b
assert b["what"] == "other build", b
assert [(c["width"], c["threads"]) for c in o["configurations"]] == [(32, 1), (32, 2)]
stages = {"decode", "noise", "prefilter", "normals", "gtao", "denoise", "output", "shade"}
for c in o["configurations"]:
    a, b = c["builds"]
    for x in (a, b):
        assert len(x["round_median_ms"]) == 3 and len(x["round_p95_ms"]) == 3, x
        assert x["median_ms"] == statistics.median(x["round_median_ms"]), x
        assert abs(x["fps"] - 1e3 / x["median_ms"]) < 1e-9, x
        assert set(x["stage_median_ms"]) == stages, x
    (q,) = c["ratios"]
    want = [u / v for u, v in zip(a["round_median_ms"], b["round_median_ms"])]
    assert q["ratio"] == "A/B" and q["rounds"] == want, (q, want)
    assert abs(q["median"] - statistics.median(want)) < 1e-12, q
    assert q["min"] == min(want) and q["max"] == max(want), q
    assert set(q["stage"]) == stages, q
PY
fi

# two parameter sets of this build: B is A with the options added, and only B has them
if expect_exit 0 "compare-params" -- "$DEPTHAO" bench --compare-params '--noise-model fixed' \
	--rounds 2 --size 32x24 --threads 1 $SMALL --json; then
	python3 - "$WORK/out" <<'PY' || fail "compare-params --json: $(cat "$WORK/out")"
import json, sys
o = json.loads(open(sys.argv[1]).read())
a, b = o["builds"]
assert a["what"] == "this build" and b["what"] == "--noise-model fixed", o["builds"]
assert a["path"] == b["path"] and a["version"] == b["version"], o["builds"]
assert b["args"][-3:] == ["--noise-model", "fixed", "--json"], b
assert "--noise-model" not in a["args"], a
assert a["runs"] == b["runs"] == 2, o["builds"]
assert len(o["configurations"]) == 1 and len(o["configurations"][0]["ratios"]) == 1, o
PY
fi

# a fake other build with canned times: its rounds' medians are 4, 8, 2 (its first bench
# run, the check of the options, printed 2); it has no noise stage and a zero output stage
rm -f "$FAKE_LOG"
if expect_exit 0 "compare fake" -- "$DEPTHAO" bench --compare "$FAKE" --rounds 3 \
	--size 32x24 --threads 1 $SMALL --json; then
	python3 - "$WORK/out" "$FAKE_LOG" <<'PY' || fail "compare fake: $(cat "$WORK/out")"
import json, statistics, sys
o = json.loads(open(sys.argv[1]).read())
calls = open(sys.argv[2]).read().splitlines()
# --version, the check of the options, then one run per round
assert len(calls) == 5 and calls[0] == "--version", calls
assert "--min-iterations 1 --no-reference --json" in calls[1], calls
for call in calls[2:]:
    assert call == ("bench --threads 1 --quality default --min-time 0 --min-iterations 1 "
                    "--no-reference --size 32x24 --json"), call
a, b = o["builds"]
assert b["version"] == "depthao 0.0.1 (fake)" and b["runs"] == 3, b
(c,) = o["configurations"]
ca, cb = c["builds"]
assert cb["round_median_ms"] == [4, 8, 2] and cb["median_ms"] == 4 and cb["p95_ms"] == 8, cb
assert cb["stage_median_ms"] == {"decode": 1, "prefilter": 0.5, "gtao": 4, "output": 0}, cb
(q,) = c["ratios"]
want = [x / y for x, y in zip(ca["round_median_ms"], [4, 8, 2])]
assert q["rounds"] == want, (q, want)
assert abs(q["median"] - statistics.median(want)) < 1e-12, q
assert (q["min"], q["max"]) == (min(want), max(want)), q
# a stage the fake lacks and one it times as 0 have no ratio; the others have
assert q["stage"]["noise"] is None and q["stage"]["output"] is None, q
assert q["stage"]["normals"] is None and q["stage"]["shade"] is None, q
assert q["stage"]["decode"] > 0 and q["stage"]["prefilter"] > 0 and q["stage"]["gtao"] > 0, q
PY
fi

# the table shows '-' for a stage the other build lacks, n/a for one it times as 0
rm -f "$FAKE_LOG"
if expect_exit 0 "compare fake table" -- "$DEPTHAO" bench --compare "$FAKE" --rounds 1 \
	--size 32x24 --threads 1 $SMALL; then
	# columns: label median p95 fps | decode noise prefilter normals gtao denoise output shade
	awk '$1 == "B" && $5 == "|" { exit !($7 == "-" && $8 == "0.50" && $9 == "-" && $12 == "0.00" && $13 == "-") }' \
		"$WORK/out" || fail "compare fake table, B row: $(grep '^  B  *[0-9]' "$WORK/out")"
	# (the ratio row: label median (min-max) | the stages)
	awk '$1 == "A/B" { exit !($6 == "-" && $8 == "-" && $11 == "n/a" && $12 == "-") }' \
		"$WORK/out" || fail "compare fake table, A/B row: $(grep '^  A/B ' "$WORK/out")"
fi

# errors: each one line on stderr, nothing on stdout
expect_error() { # CODE DESCRIPTION PATTERN -- command...
	code=$1
	what=$2
	pattern=$3
	shift 3
	if expect_exit "$code" "$what" "$@"; then
		[ "$(wc -l <"$WORK/err")" -eq 1 ] || fail "$what: not one stderr line: $(cat "$WORK/err")"
		grep -q -- "$pattern" "$WORK/err" || fail "$what: stderr lacks '$pattern': $(cat "$WORK/err")"
	fi
}
ONE="--rounds 2 --size 32x24 --threads 1 $SMALL"
expect_error 2 "compare missing" "--compare $WORK/nowhere: No such file or directory" -- \
	"$DEPTHAO" bench --compare "$WORK/nowhere" $ONE
[ -s "$WORK/out" ] && fail "compare missing: printed on stdout"
mkdir "$WORK/notabuild"
expect_error 2 "compare not a build dir" "no depthao in this directory" -- \
	"$DEPTHAO" bench --compare "$WORK/notabuild" $ONE
printf '#!/bin/sh\necho hello\n' >"$WORK/hello"
chmod +x "$WORK/hello"
expect_error 2 "compare not depthao" "not a depthao binary (.*prints 'hello')" -- \
	"$DEPTHAO" bench --compare "$WORK/hello" $ONE
chmod -x "$WORK/hello"
expect_error 2 "compare not executable" "not executable" -- \
	"$DEPTHAO" bench --compare "$WORK/hello" $ONE
# an option the other build does not know: said before any round is run
rm -f "$FAKE_LOG"
FAKE_MODE=reject
expect_error 2 "compare rejected" \
	"rejects an option that this build accepts (it says: unknown option '--noise-model')" -- \
	"$DEPTHAO" bench --compare "$FAKE" $ONE --noise-model fixed
[ -s "$WORK/out" ] && fail "compare rejected: printed on stdout: $(cat "$WORK/out")"
[ "$(wc -l <"$FAKE_LOG")" -eq 2 ] || fail "compare rejected: ran the rounds: $(cat "$FAKE_LOG")"
expect_error 2 "compare-params rejected" \
	"this build with --compare-params '--frobnicate 1': unknown option '--frobnicate'" -- \
	"$DEPTHAO" bench --compare-params '--frobnicate 1' $ONE
# a child that fails, is killed, prints something else, or times other sizes
FAKE_MODE=fail
expect_error 1 "compare failing child" \
	"(.*fake_depthao.sh) failed (exit 1) in round 1: depthao bench: out of memory" -- \
	"$DEPTHAO" bench --compare "$FAKE" $ONE --json
FAKE_MODE=crash
expect_error 1 "compare crashing child" "was killed by signal 11 in round 1" -- \
	"$DEPTHAO" bench --compare "$FAKE" $ONE --json
FAKE_MODE=garbage
expect_error 1 "compare garbage" "printed a line that is not bench's JSON: 'not json'" -- \
	"$DEPTHAO" bench --compare "$FAKE" $ONE --json
FAKE_MODE=other
expect_error 1 "compare other sizes" "not the same sizes and thread counts" -- \
	"$DEPTHAO" bench --compare "$FAKE" $ONE --json
# --rounds alone, or out of range
expect_usage_error "rounds without compare" -- "$DEPTHAO" bench --rounds 3 --size 32x24 $SMALL
expect_usage_error "rounds 0" -- "$DEPTHAO" bench --compare "$BUILD" $ONE --rounds 0

finish
