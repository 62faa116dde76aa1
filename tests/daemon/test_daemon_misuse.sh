#!/bin/sh
# SPDX-License-Identifier: MIT
# What a careless or hostile user does to depthaod, found in review after the merge of the
# daemon branches; each part failed before its fix.
. "$(dirname "$0")/daemon_lib.sh"
export DEPTHAO_PLUGIN_PATH="$TEST_PLUGINS"
ONI_CHECK="$TEST_PLUGINS/oni_check"
SOCK="$WORK/ctl.sock"

# field NAME "LINE": the number after NAME in oni_check's output
field() {
	echo "$2" | awk -v k="$1" '{ for (i = 1; i < NF; i++) if ($i == k) print $(i + 1) }'
}

# ---- 1. started with stderr or stdout closed (depthaod ... 2>&-, >&-) -----------------
# The first file the daemon opened took the number 2 (or 1): its log lines were written
# over the start of the recording, and y4m:- wrote its stream into it.
"$DAEMON" --source "testsrc:fps=100,w=160,h=120" --max-frames 30 --stats-interval 0 \
	--sink rec=oni:"$WORK/no-stderr.oni" --stream rec=depth 2>&- ||
	fail "exit status $? with stderr closed"
out=$("$ONI_CHECK" "$WORK/no-stderr.oni" 100 2>&1) || fail "stderr closed: the recording is damaged: $out"
echo "stderr closed: $out"
[ "$(field frames "$out")" = 30 ] && [ "$(field warning "$out")" = 0 ] ||
	fail "stderr closed: expected 30 finished frames: $out"
# y4m:- fails until the recording is open (a frame is 10 ms), then retries after 0.5 s
"$DAEMON" --source "testsrc:fps=100,w=160,h=120" --max-frames 200 --stats-interval 0 \
	--sink rec=oni:"$WORK/no-stdout.oni" --stream rec=depth --sink out=y4m:- --stream out=ao8 \
	>&- 2>"$WORK/log-no-stdout" || fail "exit status $? with stdout closed"
out=$("$ONI_CHECK" "$WORK/no-stdout.oni" 100 2>&1) || fail "stdout closed: the recording is damaged: $out"
echo "stdout closed: $out"
[ "$(field frames "$out")" = 200 ] && [ "$(field warning "$out")" = 0 ] ||
	fail "stdout closed: expected 200 finished frames: $out"
if grep -a -q -e "FRAME" -e "Cmono" "$WORK/no-stdout.oni"; then
	fail "the y4m stream was written into the recording"
fi
grep -q "stdout was closed" "$WORK/log-no-stdout" ||
	fail "the log does not say that stdout was closed: $(cat "$WORK/log-no-stdout")"

finish
