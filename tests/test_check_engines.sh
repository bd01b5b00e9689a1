#!/bin/sh
# The engine cells' baselines pass on the engines as pinned
# (docs/regression.md): check --technique engines on three of the scenes
# their declared cells use, which hold all but one of those cells (every
# scene: check --technique engines, about a minute; the suite keeps to its
# budget). Skips (77) where the engines are not installed.
set -u
sb=$1 src=$2 cache=$3 out=$4
# every engine folder (each with a lockfile) and the driver
skip() { echo "skipped: the engines are not installed (tools/setup installs them)"; exit 77; }
[ -x /usr/bin/chromium ] || skip
for lock in "$src"/engines/*/package-lock.json; do
  [ -e "$(dirname "$lock")/node_modules/.package-lock.json" ] || skip
done
exec "$sb" check -q --technique engines --baselines "$src/results/baselines" --tuned "$src/results/tuned" \
  --cache "$cache" --out "$out" --scene grazing_receiver --scene thin_features --scene contact_hardening
