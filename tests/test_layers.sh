#!/bin/sh
# Protects the layout (docs/design.md §3): the folders follow the data flow, and
# a file includes only its own folder and the folders before it in this
# order. An include of a later folder is a dependency pointing against the
# flow (e.g. the report reaching into the command line for a constant).
# Usage: test_layers.sh <source root>
set -u
cd "$1" || exit 2
order="base scene truth gl techniques render engine score pipeline output view cli"
rank() {
    i=0
    for f in $order; do
        [ "$f" = "$1" ] && { echo $i; return; }
        i=$((i + 1))
    done
    echo 99
}
bad=0 files=0
for file in harness/*/*.c harness/*/*.h harness/*/*.cpp techniques/*.c techniques/*.h; do
    files=$((files + 1))
    case "$file" in
        harness/*) own=$(echo "$file" | cut -d/ -f2) ;;
        *) own=techniques ;;
    esac
    own_rank=$(rank "$own")
    [ "$own_rank" = 99 ] && { echo "$file: folder '$own' is not in the layer order"; bad=$((bad + 1)); }
    # Every quoted include is a file of the own folder or "<folder>/<file>":
    # a path that climbs (..) or starts at the root would hide its folder.
    if grep -E '^#include "' "$file" | grep -vqE '^#include "([a-z_]+/)?[a-z_0-9]+\.(h|glsl)"'; then
        echo "$file: an include that does not name its folder: $(grep -E '^#include "' "$file" |
            grep -vE '^#include "([a-z_]+/)?[a-z_0-9]+\.(h|glsl)"' | head -1)"
        bad=$((bad + 1))
    fi
    for dep in $(sed -n 's|^#include "\([a-z_]*\)/[a-z_0-9]*\.h".*|\1|p' "$file"); do
        if [ "$(rank "$dep")" -gt "$own_rank" ]; then
            echo "$file includes $dep/, a later stage than $own/"
            bad=$((bad + 1))
        fi
    done
done
echo "$files files, $bad includes against the flow"
[ "$files" -gt 40 ] && [ "$bad" -eq 0 ]
