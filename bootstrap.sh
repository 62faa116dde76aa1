#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
#
# The one entry point for a fresh Debian 12 machine:
#   ./bootstrap.sh deps   install the missing Debian packages (apt-get, as root or with sudo)
#   ./bootstrap.sh build  deps, then configure and build in build/ (release, warnings are errors)
#   ./bootstrap.sh demo   build, then run depthaod on the bundled recording: out/shaded, out/ao,
#                         out/shaded.y4m
#   ./bootstrap.sh view   build, then serve the bundled recording in a loop to the browser viewer
#                         (http://127.0.0.1:8080/) until Ctrl-C
#   ./bootstrap.sh test   build, then run every test suite, the installed-library example included,
#                         then the install suite again in a default `meson setup` outside the
#                         source tree, then the .oni/plugin/bag/daemon/ros suites and the http
#                         sink's tests under ASan + UBSan
set -euo pipefail
cd "$(dirname "$0")"

# The recording the demo shades (an .oni file, or a directory of 16-bit depth PNGs).
DEMO_INPUT=${DEMO_INPUT:-recordings/spheres-rolling.oni}
DEMO_OUT=${DEMO_OUT:-out}
# Where `./bootstrap.sh view` serves the viewer (HOST:PORT; every interface only when asked).
VIEW_ADDR=${VIEW_ADDR:-127.0.0.1:8080}
BUILD_DIR=${BUILD_DIR:-build}
# `./bootstrap.sh test`'s second configuration, meson's defaults, outside the source tree
# (one per checkout)
DEFAULT_BUILD_DIR=${DEFAULT_BUILD_DIR:-${TMPDIR:-/tmp}/depthao-default-$(pwd -P | cksum | cut -d' ' -f1)}
DEPTHAO=$BUILD_DIR/tools/depthao/depthao
DEPTHAOD=$BUILD_DIR/tools/depthaod/depthaod

PACKAGES=(
	meson ninja-build pkg-config gcc g++ abigail-tools clang libclang-rt-dev
	doxygen
	libpng-dev libjson-c-dev libcmocka-dev liblz4-dev libbz2-dev libturbojpeg0-dev
	libopencv-dev libopencv-contrib-dev
	libopenni2-dev libv4l-dev libcamera-dev
	libsystemd-dev systemd groff-base man-db
	xvfb xauth
	python3 python3-numpy python3-pytest python3-pil python3-rosbag python3-sensor-msgs
	python3-open3d python3-mesonpy python3-venv python3-yaml libyaml-dev
	ros-core libroscpp-dev libimage-transport-dev libsensor-msgs-dev libtf2-ros-dev
	libdynamic-reconfigure-config-init-mutex-dev python3-dynamic-reconfigure
	libgstreamer1.0-dev libgstreamer-plugins-base1.0-dev libgstrtspserver-1.0-dev
	gstreamer1.0-tools gstreamer1.0-plugins-base gstreamer1.0-plugins-good
	python3-gi gir1.2-gstreamer-1.0
	libmicrohttpd-dev libturbojpeg0-dev chromium chromium-driver
	libzstd-dev libsqlite3-dev libwebsockets-dev protobuf-compiler lz4
)

usage() {
	cat <<USAGE
usage: ./bootstrap.sh deps|build|demo|view|test

  deps    install the missing Debian packages with apt-get (as root, or through sudo):
          ${PACKAGES[*]}
  build   deps, then configure $BUILD_DIR/ (release, -Dwerror=true) and build it
  demo    build, then run depthaod on the recording $DEMO_INPUT: shaded and AO frames
          into $DEMO_OUT/shaded and $DEMO_OUT/ao, a video into $DEMO_OUT/shaded.y4m
  view    build, then serve $DEMO_INPUT in a loop, in real time, to the browser viewer at
          http://$VIEW_ADDR/ (parameters may be changed from the page) until Ctrl-C
  test    build, then run every test suite (meson test), including the example built
          against the installed library (suite 'install'); then the install suite and
          simd-odd-sizes again in a default 'meson setup' outside the source tree
          (in $DEFAULT_BUILD_DIR); then the oni, plugin, bag, daemon and ros suites,
          web-http and simd-odd-sizes again under ASan + UBSan (in $BUILD_DIR-asan);
          then the fuzz targets with clang over their seed corpora (in $BUILD_DIR-fuzz)

environment: BUILD_DIR (default build), DEFAULT_BUILD_DIR, DEMO_INPUT, DEMO_OUT (default out),
             VIEW_ADDR (default 127.0.0.1:8080; 0.0.0.0:8080 for other machines)
USAGE
}

say() { echo "bootstrap: $*"; }
die() {
	echo "bootstrap: error: $*" >&2
	exit 1
}

deps() {
	if ! command -v dpkg-query >/dev/null 2>&1 || ! command -v apt-get >/dev/null 2>&1; then
		die "dpkg/apt-get not found: this script installs Debian 12 packages (${PACKAGES[*]})"
	fi
	local missing=() p sudo=()
	for p in "${PACKAGES[@]}"; do
		if [ "$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)" != "install ok installed" ]; then
			missing+=("$p")
		fi
	done
	if [ ${#missing[@]} -eq 0 ]; then
		say "all ${#PACKAGES[@]} packages are installed"
		return 0
	fi
	if [ "$(id -u)" -ne 0 ]; then
		command -v sudo >/dev/null 2>&1 ||
			die "missing packages: ${missing[*]}
installing them needs root, and sudo is not available; as root, run:
  apt-get update && apt-get install ${missing[*]}"
		sudo=(sudo)
	fi
	say "installing ${missing[*]}"
	"${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -q
	"${sudo[@]}" env DEBIAN_FRONTEND=noninteractive \
		apt-get install -y -q "${missing[@]}"
}

build() {
	deps
	if [ -f "$BUILD_DIR/meson-private/coredata.dat" ]; then
		meson setup --reconfigure "$BUILD_DIR" --buildtype=release -Dwerror=true -Ddocs=enabled >/dev/null
	else
		meson setup "$BUILD_DIR" --buildtype=release -Dwerror=true -Ddocs=enabled
	fi
	ninja -C "$BUILD_DIR"
}

# The demo's main job: depthaod plays the recording once, every frame, into a PNG
# sequence of the shaded stream, one of the AO, and a y4m video; adjust the flags here.
# With a display, a window shows the stream too (the OpenCV plugin; it stays off without one).
demo_command() {
	local window=()
	if [ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ]; then
		window=(--sink window=opencv:window:depthao)
	fi
	"$DEPTHAOD" --source "$DEMO_INPUT" --playback manual --stats-interval 0 \
		--sink shaded=images:"$DEMO_OUT/shaded" \
		--sink ao=images:"$DEMO_OUT/ao" --stream ao=ao \
		--sink video=y4m:"$DEMO_OUT/shaded.y4m" "${window[@]}"
}

demo() {
	[ -e "$DEMO_INPUT" ] ||
		die "the demo recording $DEMO_INPUT does not exist (set DEMO_INPUT=<.oni file or dir of 16-bit depth PNGs>)"
	build
	rm -rf "$DEMO_OUT/shaded" "$DEMO_OUT/ao" "$DEMO_OUT/shaded.y4m"
	mkdir -p "$DEMO_OUT"
	demo_command
	local out
	out=$(cd "$DEMO_OUT" && pwd)
	say "occlusion-shaded frames (RGB PNG): $out/shaded/"
	say "ambient occlusion (16-bit PNG):    $out/ao/"
	say "shaded video (YUV4MPEG2):          $out/shaded.y4m (e.g. ffplay $out/shaded.y4m)"
}

# The browser viewer on the demo recording, looped in real time, until Ctrl-C.
view() {
	[ -e "$DEMO_INPUT" ] ||
		die "the demo recording $DEMO_INPUT does not exist (set DEMO_INPUT=<.oni file or dir of 16-bit depth PNGs>)"
	build
	[ -f "$BUILD_DIR/plugins/http/depthao-http.so" ] ||
		die "the http plugin was not built (it needs libmicrohttpd-dev and libturbojpeg0-dev)"
	say "open http://$VIEW_ADDR/ in a browser (Ctrl-C stops)"
	exec "$DEPTHAOD" --source "$DEMO_INPUT" --loop --stats-interval 0 \
		--sink web="http:$VIEW_ADDR?control=true"
}

# The independent reference implementations some tests check against (MCAP, Foxglove
# WebSocket, rosbag2; tests/js/package-lock.json pins them), installed with npm ci into
# tests/js/node_modules.  Without npm, or offline, the tests that need them skip.
js_deps() {
	if ! command -v npm >/dev/null 2>&1; then
		say "npm not found: the tests against the npm reference implementations will skip"
		return 0
	fi
	(cd tests/js && npm ci --no-audit --no-fund --loglevel=error) ||
		say "npm ci in tests/js failed: the tests against the npm reference implementations will skip"
}

# One closing line a CI reader understands: "meson: N passed, N failed, N skipped".
summarize() {
	python3 - "$BUILD_DIR/meson-logs/testlog.json" <<'PY' || true
import json, sys
n = {"passed": 0, "failed": 0, "skipped": 0}
for line in open(sys.argv[1]):
    r = json.loads(line)["result"]
    n["passed" if r in ("OK", "EXPECTEDFAIL") else "skipped" if r == "SKIP" else "failed"] += 1
print("meson: %(passed)d passed, %(failed)d failed, %(skipped)d skipped" % n)
PY
}

run_tests() {
	build
	# the example check (examples/shade_depth.c against a staged install) is a meson test
	# (the list is read whole first: grep -q stopping early would SIGPIPE meson under pipefail)
	local tests
	tests=$(meson test -C "$BUILD_DIR" --list 2>/dev/null)
	grep -q 'example-installed$' <<<"$tests" ||
		die "the test 'example-installed' is not registered: add 'install' to the subdir list in tests/meson.build"
	js_deps
	local status=0
	meson test -C "$BUILD_DIR" --print-errorlogs || status=$?
	summarize
	default_build_tests || status=1
	sanitized_tests || status=1
	fuzz_tests || status=1
	return "$status"
}

# The project as a plain `meson setup DIR` configures it -- its default build type
# (debugoptimized: debug information, assertions on), every option at its default -- in a
# build directory outside the source tree ($DEFAULT_BUILD_DIR), where $BUILD_DIR is the
# release build inside it: built whole, then the suite that depends on how it is built
# and installed rather than on the optimiser (install: nothing installed names the build
# tree, the example against the installed library, exports, systemd unit, manual pages;
# 20 s)
# and every kernel set at odd sizes with assertions on (simd-odd-sizes, 8 s).  The rest
# of the suite ran above; a second full run (33 min of tests on 2 cores) would not fit
# CI's time.
default_build_tests() {
	local dir="$DEFAULT_BUILD_DIR"
	mkdir -p "$dir" || return 1
	case "$(cd "$dir" && pwd -P)/" in
	"$(pwd -P)/"*) die "DEFAULT_BUILD_DIR ($dir) must be outside the source tree" ;;
	esac
	# (called after ||, so errexit is off in here: each status is kept by hand)
	if [ ! -f "$dir/meson-private/coredata.dat" ]; then
		meson setup "$dir" >/dev/null || return 1
	fi
	ninja -C "$dir" >/dev/null || return 1
	say "the default configuration (meson setup $dir): the install suite, simd-odd-sizes"
	local st=0
	meson test -C "$dir" --suite install --print-errorlogs || st=1
	meson test -C "$dir" simd-odd-sizes --print-errorlogs || st=1
	return "$st"
}

# The parsers of untrusted files (.oni reader, 16z codecs) and the sources again, under
# AddressSanitizer and UndefinedBehaviorSanitizer, in $BUILD_DIR-asan.
sanitized_tests() {
	local dir="$BUILD_DIR-asan"
	if [ ! -f "$dir/meson-private/coredata.dat" ]; then
		meson setup "$dir" --buildtype=debugoptimized -Db_sanitize=address,undefined \
			-Db_lundef=false -Dwerror=true >/dev/null
	fi
	ninja -C "$dir" >/dev/null
	say "sanitizers: the oni, plugin, bag, daemon and ros suites and the http sink under ASan + UBSan"
	export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 ASAN_OPTIONS=detect_leaks=1
	export LSAN_OPTIONS="suppressions=$(pwd)/tests/lsan.supp"
	# (called after ||, so errexit is off in here: each status is kept by hand)
	local st=0
	meson test -C "$dir" --suite oni --suite plugin --suite bag --suite daemon --suite ros \
		--print-errorlogs || st=1
	# the http sink parses what the network sends (its plain-HTTP tests, and hostile JSON
	# and slowloris; not the browser's, nor the flood, whose drop and RSS bars are not
	# for an instrumented daemon)
	meson test -C "$dir" web-http web-hostile-json web-hostile-slowloris --print-errorlogs || st=1
	# every kernel set at widths 1-67 against the reference, guard bytes and pages around
	# their buffers: ASan sees reads and writes into the allocator's redzones as well
	meson test -C "$dir" simd-odd-sizes --print-errorlogs || st=1
	return "$st"
}

# The libFuzzer targets (fuzz/, -Dfuzzing=true: clang, ASan + UBSan) built in
# $BUILD_DIR-fuzz and run once over each input of their seed corpus (fuzz/corpus/NAME;
# the .oni reader also over tests/oni/regress): that they build with clang and that no
# seed crashes.  Seconds; fuzzing for real is in fuzz/README.md.
fuzz_tests() {
	if ! command -v clang >/dev/null 2>&1; then
		say "clang not found: the fuzz targets are not built (apt-get install clang libclang-rt-dev)"
		return 0
	fi
	local dir="$BUILD_DIR-fuzz" src targets=() t
	for src in fuzz/fuzz_*.c; do
		t=$(basename "$src" .c)
		targets+=("$t")
	done
	# (called after ||, so errexit is off in here: each status is kept by hand)
	if [ ! -f "$dir/meson-private/coredata.dat" ]; then
		CC=clang meson setup "$dir" -Dfuzzing=true -Dtests=disabled \
			-Dwerror=true >/dev/null || return 1
	fi
	ninja -C "$dir" "${targets[@]/#/fuzz/}" >/dev/null || return 1
	say "fuzz: ${targets[*]} over their seed corpora"
	local st=0 corpus inputs
	for t in "${targets[@]}"; do
		corpus=${t#fuzz_}
		corpus=fuzz/corpus/${corpus%_reader}
		inputs=("$corpus"/*)
		[ "$t" != fuzz_oni_reader ] || inputs+=(tests/oni/regress/*)
		if [ ! -e "${inputs[0]}" ]; then
			echo "bootstrap: error: $t has no seed corpus in $corpus" >&2
			st=1
			continue
		fi
		"$dir/fuzz/$t" "${inputs[@]}" >"$dir/$t.log" 2>&1 ||
			{ echo "bootstrap: error: $t failed on its seeds (see $dir/$t.log)" >&2; st=1; }
	done
	return "$st"
}

case "${1:-}" in
deps) deps ;;
build) build ;;
demo) demo ;;
view) view ;;
test) run_tests ;;
-h | --help | help) usage ;;
*)
	[ $# -eq 0 ] || echo "bootstrap: unknown argument '$1'" >&2
	usage >&2
	exit 2
	;;
esac
