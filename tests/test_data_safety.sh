#!/bin/sh
# Protects the output folder's promises (README, Outputs): one shadowbench
# per folder at a time; a run killed by SIGTERM or SIGINT exits 143 or 130,
# leaves no temporary behind and says it is incomplete; a later run removes
# the temporaries of dead runs and only those; a write that fails is one
# line and an incomplete run; scene names that would
# escape their folder or take a run file's name are refused before any work.
# Usage: test_data_safety.sh <shadowbench> <source root>
set -u
sb=$1 root=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failed=0
fail() { echo "FAILED: $*"; failed=$((failed + 1)); }
ok() { echo "ok: $*"; }
small="--width 64 --height 64 --gt-samples 16 --frames 3 --warmup 0 --no-cache -q"

# Two runs on one folder: the second fails at once.
"$sb" run --scene parallel_planes --scene stanford_bunny --scene thin_features $small --out "$tmp/a" &
first=$!
i=0
while [ ! -f "$tmp/a/.lock" ] && [ $i -lt 100 ]; do sleep 0.05; i=$((i + 1)); done
out=$("$sb" run --scene parallel_planes $small --out "$tmp/a" 2>&1)
rc=$?
[ $rc = 2 ] && printf '%s' "$out" | grep -q "another shadowbench is writing there" &&
    ok "a second run on the same folder: exit 2, '$out'" || fail "second run: exit $rc: $out"
wait $first && grep -q '"complete":	true' "$tmp/a/run.json" && ok "the first run completes" ||
    fail "the first run did not complete"

# Killed: 143 on SIGTERM, 130 on SIGINT; no temporary left; run.json says
# incomplete; the previous report is gone, not left to pass for this run's.
for sig in TERM INT; do
    "$sb" run $small --out "$tmp/a" &
    pid=$!
    sleep 1.5
    kill -$sig $pid
    wait $pid
    rc=$?
    want=$([ $sig = TERM ] && echo 143 || echo 130)
    [ $rc = "$want" ] && ok "SIGTERM/SIGINT: $sig exits $rc" || fail "$sig: exit $rc, wanted $want"
    left=$(find "$tmp/a" -name '*.tmp.*' | head -3)
    [ -z "$left" ] && ok "$sig: no temporary left" || fail "$sig: temporaries left: $left"
    grep -q '"complete":	false' "$tmp/a/run.json" && [ ! -f "$tmp/a/report.html" ] &&
        ok "$sig: run.json says incomplete, no report" || fail "$sig: run.json or report.html wrong"
done

# Temporaries of dead runs go, a live process's stay.
mkdir -p "$tmp/a/parallel_planes/hard"
: > "$tmp/a/parallel_planes/hard/visibility.exr.tmp.4194305"
: > "$tmp/a/parallel_planes/hard/heatmap.png.tmp.$$"
"$sb" run --scene parallel_planes --technique hard $small --out "$tmp/a" || fail "run after the kills"
[ ! -e "$tmp/a/parallel_planes/hard/visibility.exr.tmp.4194305" ] && [ -e "$tmp/a/parallel_planes/hard/heatmap.png.tmp.$$" ] &&
    ok "a dead run's temporary removed, a live one's kept" || fail "stale temporaries"

# Two ground truths written into one cache at once: both succeed, and the
# entry they leave is whole (a third reads it from the cache).
for i in 1 2; do
    "$sb" gt --scene parallel_planes --width 96 --height 96 --gt-samples 64 --cache "$tmp/cache" \
        --out "$tmp/gt$i" -q >/dev/null &
done
wait %1 && wait %2 || fail "two concurrent ground truths into one cache"
out=$("$sb" gt --scene parallel_planes --width 96 --height 96 --gt-samples 64 --cache "$tmp/cache" \
          --out "$tmp/gt3" 2>&1)
printf '%s' "$out" | grep -q "from cache" && [ -z "$(find "$tmp/cache" -name '*.tmp.*')" ] &&
    ok "concurrent writers leave one whole cache entry" || fail "cache after concurrent writers: $out"

# A write that fails (the file-size limit makes write() fail with EFBIG,
# where a full disk gives ENOSPC): one line naming the file, exit 1, no
# temporary left, and run.json says incomplete. 4 KiB stops a cell's EXR,
# 40 KiB the ground truth's.
for kib in 4 40; do
    out=$( (trap '' XFSZ; ulimit -f $kib; "$sb" run --scene parallel_planes --technique hard,pcf \
               --width 128 --height 128 --gt-samples 16 --frames 1 --warmup 0 --no-cache -q \
               --out "$tmp/full$kib") 2>&1)
    rc=$?
    [ $rc = 1 ] && [ "$(printf '%s\n' "$out" | wc -l)" = 1 ] &&
        printf '%s' "$out" | grep -q "^shadowbench: error: $tmp/full$kib/parallel_planes/.*\.exr: cannot write" &&
        [ -z "$(find "$tmp/full$kib" -name '*.tmp.*')" ] && grep -q '"complete":	false' "$tmp/full$kib/run.json" &&
        ok "a write failing at $kib KiB: '$out'" || fail "a write failing at $kib KiB: exit $rc: $out"
done

# A folder shadowbench did not make is not used (its report.html and
# *.tmp.<pid> files could be someone else's): one line, exit 2, untouched.
mkdir -p "$tmp/mine" && echo keep > "$tmp/mine/report.html" && echo keep > "$tmp/mine/notes.tmp.999999"
out=$("$sb" run --scene parallel_planes $small --out "$tmp/mine" 2>&1)
rc=$?
[ $rc = 2 ] && printf '%s' "$out" | grep -q "was not made by shadowbench" && [ -f "$tmp/mine/report.html" ] &&
    [ -f "$tmp/mine/notes.tmp.999999" ] && ok "a foreign --out is refused and left as it was" ||
    fail "a foreign --out: exit $rc: $out"

# run.json is valid JSON whatever bytes the command line holds (a folder
# named with byte 0xff).
odd=$(printf "$tmp/odd\377")
"$sb" run --scene parallel_planes --technique hard $small --out "$odd" >/dev/null 2>&1
python3 -c 'import json,sys; json.load(open(sys.argv[1], encoding="utf-8"))' "$odd/run.json" 2>/dev/null &&
    ok "run.json stays UTF-8 with a 0xff byte in --out" || fail "run.json with a 0xff byte in --out is not JSON"

# Scene names that cannot name their folder, refused before any work:
# climbing or hidden, a run file's, over 200 bytes, not UTF-8, a control
# character, a bidirectional override (U+202E: "exe.gpj" shows as "jpg.exe").
long=$(printf 'a%.0s' $(seq 201))
bad_utf8=$(printf 'x\377\376')
escape=$(printf 'x\033[31m')
rlo=$(printf 'exe\342\200\256gpj')
for name in ... . .. .hidden report.html matrix.csv run.json charts "$long" "$bad_utf8" "$escape" "$rlo"; do
    cp "$root/scenes/parallel_planes.gltf" "$tmp/$name.gltf"
    out=$("$sb" run --scene "$tmp/$name.gltf" $small --out "$tmp/names" 2>&1)
    rc=$?
    # The error line names the file in stored order: the override prints as '?'.
    [ $rc = 2 ] && printf '%s' "$out" | grep -q "cannot name its output folder" && [ ! -e "$tmp/names/run.json" ] &&
        ! printf '%s' "$out" | LC_ALL=C grep -q "$(printf '\342\200\256')" &&
        ok "scene '$name.gltf' refused" || fail "scene '$name.gltf': exit $rc: $out"
    rm -f "$tmp/$name.gltf"
done

[ "$failed" = 0 ] && echo "all passed" || echo "$failed failed"
[ "$failed" = 0 ]
