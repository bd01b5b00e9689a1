#!/bin/sh
# A technique is two files and one registry line (docs/techniques.md,
# Adding a technique): in a scratch copy of the tree, pcf is copied as pcf_copy --
# techniques/pcf_copy.c, shaders/pcf_copy.glsl and X(pcf_copy) in
# techniques/registry.c, nothing else -- and the copy is built. Then list
# shows it with its parameters, run renders it exactly as pcf (the same
# shader under another name: the same metrics, to the last digit), tune
# tunes it, and check finds its regression cells (its descriptor's, copied
# from pcf's) without baselines and says how to record them. The copy is a
# git repository, committed before pcf_copy is added: tune --write-tuned
# and check --update refuse its uncommitted technique (one line, exit 2)
# unless --allow-uncommitted, which the files record, and record it
# without once it is committed.
# Usage: test_add_technique.sh <source root>
set -u
root=$1
scratch=$(mktemp -d) && trap 'rm -rf "$scratch"' EXIT
fail() { echo "FAILED: $*"; exit 1; }

# The tree as git has it (tracked files and new ones not ignored), or all of it.
if git -C "$root" rev-parse --git-dir >/dev/null 2>&1; then
    # but the committed results (50 MB of baselines): no step here reads
    # them, pcf_copy has none
    (cd "$root" && git ls-files -z --cached --others --exclude-standard -- . ':!results' |
        xargs -0 cp --parents -t "$scratch" 2>/dev/null) || fail "copying the tree"
else
    cp -r "$root"/. "$scratch" && rm -rf "$scratch"/build* "$scratch"/results
fi
git="git -C $scratch -c user.name=test -c user.email=test@localhost"
$git init -q && $git add -A && $git commit -qm "the tree" || fail "a git repository of the copy"
t=$scratch/techniques s=$scratch/shaders
# The two files: every name of pcf's that is its own (its settings struct,
# table, hooks, descriptor; its shader's #defines) spelled pcf_copy.
sed -e 's/\bpcf_/pcf_copy_/g' -e 's/TECHNIQUE(pcf,/TECHNIQUE(pcf_copy,/' "$t/pcf.c" > "$t/pcf_copy.c"
sed -e 's/\bPCF_/PCF_COPY_/g' "$s/pcf.glsl" > "$s/pcf_copy.glsl"
# The registry line.
sed -i 's/X(vssm)/X(vssm) X(pcf_copy)/' "$t/registry.c"
grep -q 'X(pcf_copy)' "$t/registry.c" || fail "the registry has no TECHNIQUES list to add to"

# unoptimised (CMAKE_BUILD_TYPE None): what is tested is that it builds and works, not its speed;
# the compile is most of this test
cmake -S "$scratch" -B "$scratch/build" -DBUILD_TESTING=OFF -DCMAKE_BUILD_TYPE=None >/dev/null &&
    cmake --build "$scratch/build" --target shadowbench -j "$(nproc)" >/dev/null 2>&1 || fail "the copy does not build"
sb=$scratch/build/shadowbench
cd "$scratch" || exit 1  # results/ and scenes/ of the copy

"$sb" list | grep -q '^  pcf_copy ' || fail "list does not show pcf_copy"
"$sb" list | sed -n '/^  pcf_copy /,/^$/p' | grep -q 'radius_texels' || fail "list does not show its parameters"

small="--scene parallel_planes --width 48 --height 48 --gt-samples 16 --shadow-map-size 256 --frames 1 --no-cache -q"
"$sb" run $small --technique pcf,pcf_copy --settings default --out "$scratch/run" >/dev/null || fail "run"
[ -f "$scratch/run/parallel_planes/pcf_copy/metrics.json" ] || fail "run wrote no cell for pcf_copy"
# matrix.csv: the same metrics for both (column 4 on; the times aside)
rows=$(sed -n 's/^"parallel_planes","\(pcf\|pcf_copy\)",//p' "$scratch/run/matrix.csv" | cut -d, -f2-14 | sort -u | wc -l)
[ "$rows" = 1 ] || fail "pcf_copy's metrics differ from pcf's: $(cat "$scratch/run/matrix.csv")"

"$sb" tune --technique pcf_copy --scene parallel_planes --scene contact_hardening --width 32 --height 32 \
    --gt-samples 16 --shadow-map-size 256 --frames 1 --no-cache -q --out "$scratch/tune" >/dev/null || fail "tune"
grep -q '"technique":[[:space:]]*"pcf_copy"' "$scratch/tune/pcf_copy.json" || fail "tune wrote no pcf_copy.json"

out=$("$sb" check --technique pcf_copy --scene parallel_planes --scene grazing_receiver --out "$scratch/check" 2>&1)
rc=$?
[ $rc = 1 ] || fail "check: exit $rc, wanted 1 (cells without baselines): $out"
cells=$(printf '%s\n' "$out" | grep -c '^  no baseline .* pcf_copy.*shadowbench check --update --scene .* --technique pcf_copy')
# its default cell on each scene and its 11 declared cells there (8 on parallel_planes, 3 on grazing_receiver)
[ "$cells" = 13 ] || fail "check named $cells cells of pcf_copy without a baseline, wanted 13: $out"
# Recording from a tree whose technique is not committed: refused, one line, exit 2.
out=$("$sb" tune --technique pcf_copy --scene parallel_planes --scene contact_hardening --write-tuned \
    --tuned "$scratch/tuned" --out "$scratch/tune2" 2>&1)
rc=$?
want="shadowbench: error: tune --write-tuned: the source tree has uncommitted changes to code that renders or scores"
[ $rc = 2 ] && [ "$(printf '%s\n' "$out" | wc -l)" = 1 ] && case "$out" in "$want"*) true ;; *) false ;; esac ||
    fail "tune --write-tuned on a changed tree: exit $rc: $out"
out=$("$sb" check --update --technique pcf_copy --scene parallel_planes --out "$scratch/check" 2>&1)
[ $? = 2 ] || fail "check --update on a changed tree was not refused: $out"
# --allow-uncommitted records, and says so in the file.
"$sb" check -q --update --allow-uncommitted --technique pcf_copy --scene parallel_planes --out "$scratch/check" \
    >/dev/null || fail "check --update --allow-uncommitted"
base=$scratch/results/baselines/parallel_planes/pcf_copy.json
grep -q '"source_tree":[[:space:]]*"uncommitted changes' "$base" && grep -q '"command_line":.*--allow-uncommitted' "$base" ||
    fail "$base does not record the uncommitted tree and the override"
# Committed: recorded without an override, and the file says so.
$git add -A && $git commit -qm "pcf_copy" || fail "committing pcf_copy"
"$sb" check -q --update --technique pcf_copy --scene parallel_planes --out "$scratch/check" >/dev/null ||
    fail "check --update on the committed tree"
grep -q '"source_tree":[[:space:]]*"committed"' "$base" || fail "$base does not record the committed tree"
echo "pcf_copy: listed, run (the same metrics as pcf), tuned, $cells cells without a baseline in check;" \
     "recording refused from the uncommitted tree, recorded with the override and once committed"
