#!/bin/sh
# SPDX-License-Identifier: MIT
# The library's layers include only what is below them (src/<concern>/ may
# include the private headers of the concerns listed for it), and plugins
# include only the public <depthao/...> headers, their own and plugins/common.
# usage: check_layering.sh SOURCE_ROOT
set -eu
[ $# -eq 1 ] || { echo "usage: $0 SOURCE_ROOT" >&2; exit 2; }
cd "$1"

# concern: the concerns whose headers it may include (itself always)
rules='
core:
simd: core
camera: core
params: core simd
depth: core simd
normals: core simd
kernels: core simd
denoise: core simd
shade: core simd
io: core
oni: core io
bag: core
plugin: core io oni bag
pipeline: core simd camera params depth normals kernels denoise shade
synth: core
'

status=0
# the private includes ("dir/file.h") of the C sources under a directory, as "file: dir"
includes() {
	find "$1" -name '*.[ch]' -o -name '*.cpp' -o -name '*.inc.c' | sort |
		xargs grep -Ho '^#[[:space:]]*include[[:space:]]*"[A-Za-z0-9_]*/' |
		sed 's|^\([^:]*\):#[[:space:]]*include[[:space:]]*"\([A-Za-z0-9_]*\)/$|\1 \2|'
}

for dir in src/*/; do
	concern=$(basename "$dir")
	line=$(printf '%s\n' "$rules" | grep "^$concern:" || true)
	if [ -z "$line" ]; then
		echo "FAIL: src/$concern has no layering rule (add it to $0)"
		status=1
		continue
	fi
	allowed="$concern ${line#*:}"
	includes "$dir" | while read -r file dep; do
		case " $allowed " in
		*" $dep "*) ;;
		*) echo "FAIL: $file includes $dep/: src/$concern may include only:$allowed"; echo x ;;
		esac
	done | grep -v '^x$' && status=1 || true
done

# plugins and the ROS nodes: public headers, their own directory's headers,
# plugins/common (ros/ includes its common/ layer by name, "dao_ros.h")
for f in $(find plugins ros -name '*.[ch]' -o -name '*.cpp' | sort); do
	bad=$(grep -o '^#[[:space:]]*include[[:space:]]*"[A-Za-z0-9_]*/[^"]*"' "$f" |
	      grep -v '"common/' || true)
	if [ -n "$bad" ]; then
		echo "FAIL: $f includes a private header: $bad (plugins and ros/ use <depthao/...> only)"
		status=1
	fi
done

[ "$status" -ne 0 ] || echo "layering: every src/ concern includes only the layers below it; plugins and ros/ only public headers"
exit "$status"
