#!/bin/sh
# The engine cells' baselines pass on the engines as pinned
# (docs/regression.md): check --technique engines on grazing_receiver,
# where every engine mode has declared cells besides its defaults and
# tuned ones (biases, map size, format). Every scene (check --technique engines, 590 cells) takes about
# three minutes here, past the suite's budget.
# Skips (77) where any engine folder's packages are not installed.
set -u
sb=$1 src=$2 cache=$3 out=$4
installed=true  # every engine folder with a lockfile (the driver's too), as npm ci installed it
for lock in "$src"/engines/*/package-lock.json; do
  [ -e "${lock%/package-lock.json}/node_modules/.package-lock.json" ] || installed=false
done
if ! $installed || [ ! -x /usr/bin/chromium ]; then
  echo "skipped: the engines are not installed (tools/setup installs them)"
  exit 77
fi
exec "$sb" check -q --technique engines --baselines "$src/results/baselines" --tuned "$src/results/tuned" \
  --cache "$cache" --out "$out" --scene grazing_receiver
