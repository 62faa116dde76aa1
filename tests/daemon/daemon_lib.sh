# SPDX-License-Identifier: MIT
# Helpers for the daemon tests (sourced).
# usage: <script> DEPTHAOD DEPTHAO JSON_GET PNG_INFO TEST_PLUGIN_DIR
set -eu
DAEMON=$1
DEPTHAO=$2
JSON_GET=$3
PNG_INFO=$4
TEST_PLUGINS=$5
ROOT=${DAO_SOURCE_ROOT:?}
REC="$ROOT/recordings/spheres-rolling.oni"
WORK=$(mktemp -d "${TMPDIR:-/tmp}/daod-test.XXXXXX")
PID=
BUSY=
DAEMON_LOG=/dev/null
cleanup() {
	[ -n "$PID" ] && kill -KILL "$PID" 2>/dev/null || true
	[ -n "$BUSY" ] && kill $BUSY 2>/dev/null || true
	rm -rf "$WORK"
}
trap cleanup EXIT
failures=0

fail() {
	echo "FAIL: $*"
	failures=$((failures + 1))
}

# start_daemon LOG args...: runs depthaod in the background
start_daemon() {
	DAEMON_LOG=$1
	shift
	"$DAEMON" "$@" 2>"$DAEMON_LOG" &
	PID=$!
}

# busy_loops N [CPU]: N busy loops (pinned to CPU if given) until stop_busy_loops
busy_loops() {
	for _ in $(seq "$1"); do
		if [ -n "${2:-}" ]; then
			taskset -c "$2" timeout 600 sh -c 'while :; do :; done' &
		else
			timeout 600 sh -c 'while :; do :; done' &
		fi
		BUSY="$BUSY $!"
	done
}

stop_busy_loops() {
	[ -n "$BUSY" ] && kill $BUSY 2>/dev/null || true
	BUSY=
}

# wait_for SECONDS COMMAND...: polls until the command succeeds
wait_for() {
	limit=$1
	shift
	i=0
	while ! "$@" >/dev/null 2>&1; do
		i=$((i + 1))
		[ "$i" -le $((limit * 10)) ] || return 1
		sleep 0.1
	done
}

# stop_daemon: SIGTERM, then the exit status; fails if it takes over a second
stop_daemon() {
	t0=$(date +%s%N)
	kill -TERM "$PID"
	set +e
	wait "$PID"
	status=$?
	set -e
	PID=
	ms=$((($(date +%s%N) - t0) / 1000000))
	[ "$ms" -le 1000 ] || fail "SIGTERM took $ms ms (must stop within one second)"
	echo "stopped in $ms ms, exit $status"
	# a failed stop shows the daemon's own words (a sanitizer's report goes there too)
	if [ "$status" -ne 0 ]; then
		echo "depthaod's log: sanitizer lines, then the last 60 lines"
		grep -E "Sanitizer|Tracer caught|SUMMARY" "$DAEMON_LOG" || true
		tail -n 60 "$DAEMON_LOG" || true
	fi
	return "$status"
}

# stat_of SOCKET PATH: one value of 'depthao ctl stats'
stat_of() {
	"$DEPTHAO" ctl --socket "$1" stats | "$JSON_GET" "stats.$2"
}

rss_kb() {
	awk '/^VmRSS/ {print $2}' "/proc/$1/status"
}

finish() {
	if [ "$failures" -ne 0 ]; then
		echo "$failures failure(s)"
		exit 1
	fi
	echo "all passed"
}
