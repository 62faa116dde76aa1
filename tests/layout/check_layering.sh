#!/bin/sh
# SPDX-License-Identifier: MIT
# The libraries' layers include only what is below them (src/<concern>/ and
# src/io/<concern>/ may include the private headers of the concerns listed for
# them), the AO core (libdepthao, src/ but src/io/) nothing of libdepthao-io
# (src/io/), neither its private headers nor its public ones nor a container
# library's, and plugins include only the public <depthao/...> headers and their own.
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
motion: core simd
pipeline: core simd camera params depth normals kernels denoise shade motion
'
# libdepthao-io (src/io/<concern>/), on top of the whole core (its public API; of
# src/ only the header-only core/ helpers)
io_rules='
file: core
oni: core file
tf: core
bag: core tf
mcap: core file tf
db3: core
plugin: core file oni bag mcap db3 tf
'
# what the core may not include: libdepthao-io's public headers, the container and
# codec libraries, dlopen (the plugin registry is libdepthao-io's)
io_public='depthao/\(io\|png\|ply\|oni\|plugin\|output_file\)\.h'
container='png\.h\|pngconf\.h\|lz4[a-z]*\.h\|sqlite3\.h\|yaml\.h\|json-c/[a-z_]*\.h\|bzlib\.h\|turbojpeg\.h\|jpeglib\.h\|zlib\.h\|dlfcn\.h'

status=0
# the private includes ("dir/file.h") of the C sources under a directory, as "file: dir"
includes() {
	find "$1" -name '*.[ch]' -o -name '*.cpp' -o -name '*.inc.c' | sort |
		xargs grep -Ho '^#[[:space:]]*include[[:space:]]*"[A-Za-z0-9_]*/' |
		sed 's|^\([^:]*\):#[[:space:]]*include[[:space:]]*"\([A-Za-z0-9_]*\)/$|\1 \2|'
}

for dir in src/*/ src/io/*/; do
	concern=$(basename "$dir")
	case "$dir" in
	src/io/) continue ;;
	src/io/*) table=$io_rules ;;
	*) table=$rules ;;
	esac
	line=$(printf '%s\n' "$table" | grep "^$concern:" || true)
	if [ -z "$line" ]; then
		echo "FAIL: ${dir%/} has no layering rule (add it to $0)"
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

# the AO core: nothing of libdepthao-io, no container library
for dir in src/*/; do
	[ "$dir" != src/io/ ] || continue
	bad=$(find "$dir" -name '*.[ch]' | sort |
	      xargs grep -Hn "^#[[:space:]]*include[[:space:]]*[<\"]\($io_public\|$container\)[>\"]" || true)
	if [ -n "$bad" ]; then
		echo "FAIL: the AO core (libdepthao) includes libdepthao-io or a container library:"
		echo "$bad"
		status=1
	fi
done
# no stray sources at src/io/'s top: each io concern is a directory with a rule above
stray=$(find src/io -maxdepth 1 -name '*.[ch]')
[ -z "$stray" ] || { echo "FAIL: $stray: put it in a concern directory of src/io/"; status=1; }

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

[ "$status" -ne 0 ] || echo "layering: every src/ and src/io/ concern includes only the layers below it, the AO core nothing of libdepthao-io; plugins, tools and ros/ only public headers"
exit "$status"
