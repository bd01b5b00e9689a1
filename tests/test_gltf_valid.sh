#!/bin/sh
# Every shipped scene passes the Khronos glTF validator (npm gltf-validator,
# pinned by tools/gltf-validator/package-lock.json, installed by
# tools/setup) with no error; warnings are printed. test_scenes proves that
# make_scenes writes exactly these files, and the scenes other tests write
# come from the same writer (tools/gltf_writer.c), whose branches these
# cover: one part and many, rect and disk lights, a 70 k-triangle mesh.
# A known-bad file (an accessor past its buffer view) must fail, so the
# validator is seen to be running.
# Usage: test_gltf_valid.sh <source root>
set -u
root=$1
validate="$root/tools/gltf-validator/validate.mjs"
command -v node >/dev/null || { echo "FAILED: node is not installed (tools/setup installs it)"; exit 1; }
[ -d "$root/tools/gltf-validator/node_modules/gltf-validator" ] ||
  { echo "FAILED: the glTF validator is not installed (tools/setup: npm ci in tools/gltf-validator)"; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
status=0
node "$validate" "$root"/scenes/*.gltf || status=1
# The negative control: a position accessor reaching past its view.
sed '0,/"count":[[:space:]]*8,/s//"count": 800,/' "$root/scenes/parallel_planes.gltf" > "$tmp/bad.gltf"
cmp -s "$tmp/bad.gltf" "$root/scenes/parallel_planes.gltf" && { echo "FAILED: the negative control did not change"; exit 1; }
node "$validate" "$tmp/bad.gltf" >"$tmp/bad.out"
rc=$?
[ $rc = 1 ] && grep -q ACCESSOR_TOO_LONG "$tmp/bad.out" ||
  { echo "FAILED: a file with an accessor past its view passed (exit $rc): $(cat "$tmp/bad.out")"; status=1; }
exit $status
