#!/bin/sh
# SPDX-License-Identifier: MIT
# The library's layers include only what is below them (src/<concern>/ may
# include the private headers of the concerns listed for it), and plugins
# include only the public <depthao/...> headers and their own.
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

# plugins and the ROS nodes: public headers and their own directory's headers
# (ros/ includes its C layer ros/common by name, "dao_ros.h")
for f in $(find plugins ros -name '*.[ch]' -o -name '*.cpp' | sort); do
	bad=$(grep -o '^#[[:space:]]*include[[:space:]]*"[A-Za-z0-9_]*/[^"]*"' "$f" || true)
	if [ -n "$bad" ]; then
		echo "FAIL: $f includes a private header: $bad (plugins and ros/ use <depthao/...> only)"
		status=1
	fi
done

# tools: public headers, their own directory's, tools/common and tools/synth;
# nothing of src/ (they link the shared library and see only its API)
for f in $(find tools -name '*.[ch]' -o -name '*.cpp' | sort); do
	bad=$(grep -o '^#[[:space:]]*include[[:space:]]*"[^"]*"' "$f" |
	      grep -v '"common/\|"synth/\|"[A-Za-z0-9_.-]*"' || true)
	if [ -n "$bad" ]; then
		echo "FAIL: $f includes a private header: $bad (tools use <depthao/...>, their own, common/ and synth/)"
		status=1
	fi
done
[ -z "$(ls -d src/synth 2>/dev/null)" ] || { echo "FAIL: src/synth is back: the scenes and the ray tracer are not part of libdepthao (tools/synth)"; status=1; }

[ "$status" -ne 0 ] || echo "layering: every src/ concern includes only the layers below it; plugins, tools and ros/ only public headers"
exit "$status"
