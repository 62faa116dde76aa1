#!/bin/sh
# SPDX-License-Identifier: MIT
# A module whose source or sink lacks a callback the host calls unchecked (a source's
# start or read, a sink's write) is refused by the loader, and every program says so
# with the module, the callback and what to do, instead of crashing on the NULL call
# (depthao process and bench --input: exit 1; depthaod: exit 2 at start, not a retry
# for ever).  A source with the required callbacks only (no probe, release, seek, stop)
# streams.
# usage: test_plugins_refused.sh DEPTHAO DEPTHAOD FAKE_PLUGIN_DIR
FAKE=$3
DAEMON=$2
set -- "$1" none # cli_lib.sh's DEPTHAO and PNG_INFO (not used here)
. "$(dirname "$0")/../tools/cli_lib.sh"
export DEPTHAO_PLUGIN_PATH="$FAKE"

SRC_WHY="fake-nostart.so: source 'nostart' has no start(), read(); a source plugin must implement open, get_info, start, read and close: add them and rebuild it"
SINK_WHY="fake-nowrite.so: sink 'nowrite' has no write(); a sink plugin must implement open, negotiate, write and close: add it and rebuild it"

# expect STATUS WHY CMD...: CMD exits with STATUS (not a signal) and its stderr has WHY
expect() {
	want=$1
	why=$2
	shift 2
	expect_exit "$want" "$*" -- timeout 20 "$@" || true
	grep -qF "$why" "$WORK/err" || fail "$*: the reason is not given: $(cat "$WORK/err")"
}

expect 1 "no source plugin 'nostart': $FAKE/$SRC_WHY" \
	"$DEPTHAO" process --input nostart:64x48 --frames 2 --ao-out "$WORK/ao"
expect 1 "no source plugin 'nostart': $FAKE/$SRC_WHY" \
	"$DEPTHAO" bench --input nostart:64x48 --threads 1 --no-reference
# depthao devices lists both with the reason
"$DEPTHAO" devices >"$WORK/devices.log" 2>&1 || fail "devices: $(cat "$WORK/devices.log")"
grep -qF "not loaded: $FAKE/$SRC_WHY" "$WORK/devices.log" || fail "devices: $(cat "$WORK/devices.log")"
grep -qF "not loaded: $FAKE/$SINK_WHY" "$WORK/devices.log" || fail "devices: $(cat "$WORK/devices.log")"

# the daemon: an error at start, before any frame, with what to do
expect 2 "source nostart:64x48: no source plugin 'nostart': $FAKE/$SRC_WHY" \
	"$DAEMON" --source nostart:64x48 --sink a=images:"$WORK/d" --stats-interval 0
grep -q "depthaod loads its plugins when it starts" "$WORK/err" ||
	fail "daemon: no advice: $(cat "$WORK/err")"
expect 2 "sink a (nowrite:x): no sink plugin 'nowrite': $FAKE/$SINK_WHY" \
	"$DAEMON" --source fakebig:64x48 --sink a=nowrite:x --stats-interval 0
[ ! -e "$WORK/d" ] || fail "daemon: the images sink wrote $(ls "$WORK/d")"
# --check-config sees it too (exit 2, the same reason), and says ok to loaded plugins
printf '[source]\nuri = nostart:64x48\n[sink.a]\nuri = images:%s/d\n' "$WORK" >"$WORK/bad.ini"
expect 2 "source nostart:64x48: no source plugin 'nostart': $FAKE/$SRC_WHY" \
	"$DAEMON" --check-config "$WORK/bad.ini"
printf '[source]\nuri = fakebig:64x48\n[sink.a]\nuri = images:%s/d\n' "$WORK" >"$WORK/ok.ini"
"$DAEMON" --check-config "$WORK/ok.ini" >"$WORK/okc.log" 2>&1 ||
	fail "--check-config fakebig: $(cat "$WORK/okc.log")"
grep -q "ok.ini: ok (source fakebig:64x48, 1 sink)" "$WORK/okc.log" ||
	fail "--check-config fakebig: $(cat "$WORK/okc.log")"

# only optional callbacks left out: the source streams in all three programs
"$DEPTHAO" process --input fakebig:64x48 --frames 3 --ao-out "$WORK/ao" >"$WORK/ok.log" 2>&1 ||
	fail "process fakebig: $(cat "$WORK/ok.log")"
[ "$(ls "$WORK/ao" | wc -l)" -eq 3 ] || fail "process fakebig: $(ls "$WORK/ao")"
"$DEPTHAO" bench --input fakebig:64x48 --threads 1 --no-reference >"$WORK/okb.log" 2>&1 ||
	fail "bench fakebig: $(cat "$WORK/okb.log")"
grep -q "^64x48 " "$WORK/okb.log" || fail "bench fakebig: $(cat "$WORK/okb.log")"
timeout 20 "$DAEMON" --source fakebig:64x48 --sink a=images:"$WORK/d" --stats-interval 0 \
	--max-frames 4 >"$WORK/okd.log" 2>&1 || fail "depthaod fakebig: $(cat "$WORK/okd.log")"
[ "$(ls "$WORK/d" | wc -l)" -eq 4 ] || fail "depthaod fakebig: $(ls "$WORK/d")"

finish
