#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
#
# One entry point for a fresh Debian 12 machine:
#   ./bootstrap.sh demo   install what is missing, build, shade the bundled recording
#   ./bootstrap.sh test   install what is missing, build, run the whole test suite
#   ./bootstrap.sh build  install what is missing and build
#   ./bootstrap.sh deps   only install what is missing (apt-get, as root or with sudo)
set -euo pipefail
cd "$(dirname "$0")"

BUILD_DIR=${BUILD_DIR:-build}
DEMO_INPUT=recordings/spheres-noisy
DEMO_OUT=out

PACKAGES=(
	meson ninja-build pkg-config gcc g++
	libpng-dev libjson-c-dev libcmocka-dev
	libopencv-dev libopencv-contrib-dev
)

usage() {
	cat <<USAGE
usage: ./bootstrap.sh deps|build|demo|test

  deps    install the missing Debian packages (${PACKAGES[*]})
  build   deps, then configure and build in $BUILD_DIR/ (warnings are errors)
  demo    build, then shade the bundled recording $DEMO_INPUT into $DEMO_OUT/
  test    build, then run every test suite (meson test)
USAGE
}

as_root() {
	if [ "$(id -u)" -eq 0 ]; then
		"$@"
	elif command -v sudo >/dev/null 2>&1; then
		sudo "$@"
	else
		echo "bootstrap: need root (or sudo) to install: ${missing[*]}" >&2
		exit 1
	fi
}

deps() {
	missing=()
	for p in "${PACKAGES[@]}"; do
		if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
			missing+=("$p")
		fi
	done
	if [ ${#missing[@]} -eq 0 ]; then
		return 0
	fi
	echo "bootstrap: installing ${missing[*]}"
	as_root env DEBIAN_FRONTEND=noninteractive apt-get update -q
	as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -q "${missing[@]}"
}

build() {
	deps
	if [ -f "$BUILD_DIR/build.ninja" ]; then
		meson setup --reconfigure "$BUILD_DIR" -Dwerror=true >/dev/null
	else
		meson setup "$BUILD_DIR" -Dwerror=true
	fi
	ninja -C "$BUILD_DIR"
}

demo() {
	build
	if [ ! -d "$DEMO_INPUT" ]; then
		echo "bootstrap: the demo recording $DEMO_INPUT is missing" >&2
		exit 1
	fi
	"$BUILD_DIR/tools/depthao/depthao" process --input "$DEMO_INPUT" \
		--ao-out "$DEMO_OUT/ao" --shaded-out "$DEMO_OUT/shaded"
	echo "bootstrap: AO in $DEMO_OUT/ao/, occlusion-shaded images in $DEMO_OUT/shaded/"
}

run_tests() {
	build
	meson test -C "$BUILD_DIR" --print-errorlogs
}

case "${1:-}" in
deps) deps ;;
build) build ;;
demo) demo ;;
test) run_tests ;;
-h | --help) usage ;;
*)
	usage >&2
	exit 2
	;;
esac
