#!/bin/bash
# Shards without a scheduler (docs/scale-out.md): a check and a stability
# study in two shards, run side by side, merge into what the command
# writes unsharded — the check's lines, page and heatmaps (with a cell
# that moved), the study's files and pictures (its run record aside) —
# and merge refuses, in one line and exit 2 each, what is not the parts of
# one command: a missing shard, a duplicate, another command, other
# settings, other code, another ground-truth version, an unfinished shard,
# a missing or linked picture, hand-edited records, OUT inside a shard.
# test_slurm does the same for a run and a tuning on a real Slurm cluster.
set -u
sb=$1 same_results=$2
src=$(cd "$(dirname "$0")/.." && pwd)
t=$(mktemp -d /tmp/sb_test_shards_XXXXXX)
trap 'rm -rf "$t"' EXIT
fails=0
fail() { echo "FAILED: $*"; fails=$((fails + 1)); }
ok() { echo "ok: $*"; }

# both shards of a command at once (a shared cache), then the merge
sharded() {  # sharded NAME COMMAND ARGS...
  local name=$1; shift
  "$sb" "$@" --shard 1/2 --out "$t/$name-1" >"$t/$name-1.log" 2>&1 &
  local p=$!
  "$sb" "$@" --shard 2/2 --out "$t/$name-2" >"$t/$name-2.log" 2>&1
  wait $p
  "$sb" merge "$t/$name" "$t/$name-1" "$t/$name-2" >"$t/$name.out" 2>"$t/$name.err"
}

# ---- check: a baseline that records a far smaller rmse than hard's makes
# it REGRESSED (a section and a heatmap on the page); the others pass
scene=contact_hardening
mkdir -p "$t/baselines"
cp -r "$src/results/baselines/$scene" "$t/baselines/"
sed -i '0,/"rmse":/s/"rmse":[^,]*/"rmse": 0.001/' "$t/baselines/$scene/hard.json"
cargs="--scene $scene --technique hard --technique pcf --baselines $t/baselines --tuned $src/results/tuned
       --cache $t/cache"
"$sb" check $cargs --out "$t/check-alone" >"$t/check-alone.out" 2>/dev/null
alone=$?
sharded check check $cargs
merged=$?
[ $alone = 1 ] && [ $merged = 1 ] || fail "check: exit $alone alone, $merged merged (1: a cell regressed)"
# the same lines, but the seconds and the folder in the last one
same_lines() { sed 's/; [0-9.]* s;/; s;/; s|'"$t"'/[a-z-]*/check.html|OUT/check.html|' "$1"; }
if diff <(same_lines "$t/check-alone.out") <(same_lines "$t/check.out") >"$t/check.diff"; then
  ok "check: the merge says what the check says, line for line ($(wc -l < "$t/check.out") lines)"
else
  fail "check: the merge's lines differ: $(head -5 "$t/check.diff")"
fi
grep -q "REGRESSED   $scene *hard" "$t/check.out" || fail "check: the moved cell is not REGRESSED"
cmp -s "$t/check-alone/check.html" "$t/check/check.html" && grep -q "$scene/hard.png" "$t/check/check.html" &&
  cmp -s "$t/check-alone/$scene/hard.png" "$t/check/$scene/hard.png" &&
  ok "check: the same page and heatmap" || fail "check: the page or the heatmap differs"

# ---- stability: two motions and a variation on two scenes
sargs="--scene floating_box_sphere --scene sun_contact --technique hard --technique pcf --frames 3
       --motion light_shift --motion static --vary light_scale=0.5,1,2 --width 64 --height 64 --gt-samples 64
       --cache $t/cache"
"$sb" stability $sargs --out "$t/stab-alone" >/dev/null 2>&1 || fail "stability alone"
sharded stab stability $sargs || fail "stability merged: $(cat "$t/stab.err")"
same=1
for f in stability.csv $(cd "$t/stab-alone" && find charts floating_box_sphere sun_contact -type f | sort); do
  cmp -s "$t/stab-alone/$f" "$t/stab/$f" || { same=0; fail "stability: $f differs"; }
done
# stability.json: the same but its run record (command line, date, seconds, the shards)
"$same_results" stability "$t/stab-alone" "$t/stab" >/dev/null || { same=0; fail "stability: stability.json differs"; }
[ "$(cd "$t/stab" && find floating_box_sphere sun_contact -type f | wc -l)" = \
  "$(cd "$t/stab-alone" && find floating_box_sphere sun_contact -type f | wc -l)" ] ||
  { same=0; fail "stability: the merge holds other frames than the study alone"; }
[ $same = 1 ] && ok "stability: the same data, charts and frames"

# ---- merge refuses what is not one command's shards, one line each, and
# writes nothing
rargs="--scene parallel_planes --technique hard --width 64 --height 64 --gt-samples 64 --cache $t/cache"
for k in 1 2; do "$sb" run $rargs --shard $k/2 --out "$t/r$k" >/dev/null 2>&1 || fail "run shard $k"; done
"$sb" run $rargs --width 48 --shard 2/2 --out "$t/other" >/dev/null 2>&1 || fail "run shard of other settings"
cp -r "$t/r2" "$t/oldgt" && sed -i 's/"ground_truth_version":[^,]*/"ground_truth_version": 0/' "$t/oldgt/shard.json"
cp -r "$t/r2" "$t/oldcode" && sed -i 's/"code":[^,]*/"code": "git 0000"/' "$t/oldcode/shard.json"
cp -r "$t/r2" "$t/unfinished" && rm "$t/unfinished/shard.json"
refuse() {  # refuse WHAT PATTERN SHARD... [--out-is OUT]
  local what=$1 pattern=$2 out="$t/refused"; shift 2
  [ "${3-}" = --out-is ] && { out=$4; set -- "$1" "$2"; }
  "$sb" merge -q "$out" "$@" >"$t/refused.out" 2>"$t/refused.err"  # -q: its errors alone
  local rc=$?
  if [ $rc -eq 2 ] && [ "$(wc -l < "$t/refused.err")" -eq 1 ] && grep -q "$pattern" "$t/refused.err" &&
     [ ! -e "$out" ]; then
    ok "merge of $what: $(cat "$t/refused.err")"
  else
    fail "merge of $what: exit $rc, $(cat "$t/refused.err")"
  fi
}
refuse "a missing shard" "shard(s) 2 of 2 missing" "$t/r1"
refuse "a duplicate shard" "both shard 1 of 2" "$t/r1" "$t/r1"
refuse "shards of two commands" "another command" "$t/r1" "$t/stab-2"
refuse "shards of other settings" "other arguments" "$t/r1" "$t/other"
refuse "shards of another ground truth" "another ground-truth version" "$t/r1" "$t/oldgt"
refuse "shards of other code" "other code" "$t/r1" "$t/oldcode"
refuse "an unfinished shard" "not a finished shard" "$t/r1" "$t/unfinished"
# records and files edited by hand: each refused, as a shard that is not one
cell=$(cd "$t/r2" && ls -d parallel_planes/*/ | head -1)  # one of shard 2's cells
cp -r "$t/r2" "$t/nofile" && rm "$t/nofile/${cell}heatmap.png"
refuse "a shard missing a cell's picture" "heatmap.png" "$t/r1" "$t/nofile"
cp -r "$t/r2" "$t/linked" && ln -sf "$t/r1/run.json" "$t/linked/${cell}visibility.png"
refuse "a shard whose picture is a link" "not a file" "$t/r1" "$t/linked"
mkdir -p "$t/edited"
for k in 1 2; do cp -r "$t/check-$k" "$t/edited/check-$k"; done
sed -i '0,/"status":\t2/s//"status":\t1/' "$t/edited/check-1/shard.json" "$t/edited/check-2/shard.json"
sed -i '0,/"failures":\t1/s//"failures":\t0/' "$t/edited/check-1/shard.json" "$t/edited/check-2/shard.json"
refuse "a check cell REGRESSED with no failure" "no record of cell" "$t/edited/check-1" "$t/edited/check-2"
for k in 1 2; do cp -r "$t/stab-$k" "$t/edited/stab-$k"; done
sed -i '0,/"technique":\t"hard"/s//"technique":\t"vsm"/' "$t/edited/stab-1/shard.json" "$t/edited/stab-2/shard.json"
refuse "a stability row of a technique not studied" "holds no results of" "$t/edited/stab-1" "$t/edited/stab-2"
mkdir -p "$t/sub"
refuse "OUT inside a shard, through a folder that is not there" "one inside the other" "$t/r1" "$t/r2" \
  --out-is "$t/nothere/../r1/merged"
"$sb" merge "$t/r12" "$t/r1" "$t/r2" >/dev/null 2>&1 && ok "the two shards themselves merge" ||
  fail "the two run shards do not merge"

[ $fails -eq 0 ] && echo "test_shards: passed"
exit $((fails > 0))
