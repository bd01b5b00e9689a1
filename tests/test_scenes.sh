#!/bin/sh
# Protects the provenance of the shipped scenes: tools/make_scenes (from
# tools/scene_library.c and Debian's glmark2-data) writes exactly the
# committed scenes/*.gltf, and no shipped scene lacks its recipe.
# usage: test_scenes.sh <make_scenes executable> <scenes folder>
set -u
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$1" "$tmp" >/dev/null || { echo "make_scenes failed"; exit 1; }
status=0
for f in "$2"/*.gltf "$2"/*.glb; do
  [ -e "$f" ] || continue
  name=$(basename "$f")
  if [ ! -e "$tmp/$name" ]; then
    echo "FAILED: $name is shipped but make_scenes does not write it"; status=1
  elif ! cmp -s "$f" "$tmp/$name"; then
    echo "FAILED: $name differs from what make_scenes writes"; status=1
  fi
done
for f in "$tmp"/*.gltf; do
  [ -e "$2/$(basename "$f")" ] || { echo "FAILED: $(basename "$f") is not in $2"; status=1; }
done
[ $status -eq 0 ] && echo "$(ls "$tmp" | wc -l) scenes reproduced"
exit $status
