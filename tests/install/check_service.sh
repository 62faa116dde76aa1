#!/bin/sh
# SPDX-License-Identifier: MIT
# The systemd service as installed (issue #16, item 13): meson install into a staging
# directory, then
#   - the unit, the example configuration and the three manual pages are installed;
#   - the example configuration passes depthaod --check-config;
#   - every path the configuration writes (sinks, stats_json, socket) lies in a
#     directory the unit gives the service (StateDirectory=, LogsDirectory=,
#     RuntimeDirectory=; with DynamicUser= nothing else is writable and /tmp is private);
#   - Type=notify and WatchdogSec= exactly when depthaod notifies (--version);
#   - systemd-analyze verify passes without a word, with ExecStart pointing at the staged
#     depthaod and MANPATH at the staged pages, so Documentation=man:... must resolve.
# usage: check_service.sh BUILD_DIR
set -eu
[ $# -eq 1 ] || { echo "usage: $0 BUILD_DIR" >&2; exit 2; }
build=$1
stage=$(mktemp -d "${TMPDIR:-/tmp}/dao-service.XXXXXX")
trap 'rm -rf "$stage"' EXIT
failures=0
fail() {
	echo "FAIL: $*"
	failures=$((failures + 1))
}

unset LD_LIBRARY_PATH
meson install -C "$build" --destdir "$stage" --quiet >/dev/null || { echo "FAIL: meson install"; exit 1; }
unit=$(find "$stage" -path '*/systemd/system/depthaod.service' | head -n 1)
ini=$(find "$stage" -path '*/depthao/depthaod.ini' | head -n 1)
daemon=$(find "$stage" -path '*/bin/depthaod' | head -n 1)
[ -n "$unit" ] && [ -n "$ini" ] && [ -n "$daemon" ] ||
	{ echo "FAIL: not installed: unit '$unit', configuration '$ini', depthaod '$daemon'"; exit 1; }
for page in man1/depthao.1 man5/depthaod.ini.5 man8/depthaod.8; do
	[ -n "$(find "$stage" -path "*/man/$page")" ] || fail "$page was not installed"
done
# the staged binaries run on the staged library (an install runs ldconfig, or has
# the rpath of a prefix outside the system's library directories)
lib=$(find "$stage" -name 'libdepthao.so.1' | head -n 1)
[ -n "$lib" ] || fail "libdepthao.so.1 was not installed"
export LD_LIBRARY_PATH="$(dirname "$lib")${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
man_dir=$(dirname "$(dirname "$(find "$stage" -path '*/man/man8/depthaod.8' | head -n 1)")")

"$daemon" --check-config "$ini" >"$stage/out" 2>&1 || fail "the installed configuration: $(cat "$stage/out")"

# unit_value KEY: the value of KEY= in the unit
unit_value() {
	sed -n "s/^$1=//p" "$unit"
}
# a refused configuration (exit 2) is not restarted every RestartSec
[ "$(unit_value RestartPreventExitStatus)" = 2 ] ||
	fail "the unit restarts a refused configuration: RestartPreventExitStatus='$(unit_value RestartPreventExitStatus)'"
dirs=""
for key in StateDirectory:/var/lib LogsDirectory:/var/log RuntimeDirectory:/run; do
	v=$(unit_value "${key%%:*}")
	[ -n "$v" ] || { fail "the unit has no ${key%%:*}="; continue; }
	dirs="$dirs ${key#*:}/$v"
done
[ "$(unit_value DynamicUser)" = yes ] || fail "the unit is not DynamicUser=yes"
# the paths the example writes: sink URIs (scheme:path?options), stats_json, socket,
# also in the commented-out examples ("; uri = ...") a user would uncomment
paths=$(sed -n 's/^\(; *\)\{0,1\}uri *= *\(images\|oni\|y4m\|opencv\):\([^?]*\).*/\3/p
	s/^\(; *\)\{0,1\}\(stats_json\|socket\) *= *\([^ ]*\).*/\3/p' "$ini" | grep -v '^-$' || true)
[ -n "$paths" ] || fail "the example configuration writes nowhere: nothing to check"
for p in $paths; do
	ok=0
	for d in $dirs; do
		case "$p" in "$d"/*) ok=1 ;; esac
	done
	[ "$ok" -eq 1 ] || fail "$p (in the example configuration) is outside the service's directories:$dirs"
done
echo "paths:" $paths "in" $dirs

if "$daemon" --version | grep -q "systemd notification: yes"; then
	[ "$(unit_value Type)" = notify ] || fail "depthaod notifies, but the unit is Type=$(unit_value Type)"
	[ -n "$(unit_value WatchdogSec)" ] || fail "depthaod notifies, but the unit has no WatchdogSec="
else
	[ "$(unit_value Type)" = simple ] || fail "depthaod does not notify, but the unit is Type=$(unit_value Type)"
	[ -z "$(unit_value WatchdogSec)" ] || fail "depthaod does not notify, but the unit has WatchdogSec="
fi
doc=$(unit_value Documentation)
for m in depthaod.8 depthaod.ini.5 depthao.1; do
	case "$doc" in *"man:${m%.*}(${m##*.})"*) ;; *) fail "Documentation= does not name man:${m%.*}(${m##*.}): $doc" ;; esac
done

if ! command -v systemd-analyze >/dev/null 2>&1; then
	echo "SKIP: systemd-analyze is not installed (package systemd); the other checks passed"
	[ "$failures" -eq 0 ] || exit 1
	exit 77
fi
mkdir "$stage/verify"
sed "s|^ExecStart=[^ ]*|ExecStart=$daemon|" "$unit" >"$stage/verify/depthaod.service"
MANPATH=$man_dir systemd-analyze verify --man=yes "$stage/verify/depthaod.service" \
	>"$stage/verify.out" 2>&1 || fail "systemd-analyze verify failed: $(cat "$stage/verify.out")"
[ ! -s "$stage/verify.out" ] || fail "systemd-analyze verify says: $(cat "$stage/verify.out")"

if [ "$failures" -ne 0 ]; then
	echo "$failures failure(s)"
	exit 1
fi
echo "all passed"
