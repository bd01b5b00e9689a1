#!/bin/sh
# Protects the output folder's promises (docs/outputs.md): one shadowbench
# per folder at a time; a run killed by SIGTERM or SIGINT exits 143 or 130,
# leaves no temporary behind and says it is incomplete; a later run removes
# the temporaries of dead runs and only those; a write that fails is one
# line and an incomplete run, the same for every command, SIGXFSZ or not;
# scene names that would escape their folder or take a run file's name are
# refused before any work; the cache's dead temporaries go; the limits
# (file size, address space, memory) are one line each; standard output
# that fails is said, a pipe closed early stops nothing; a signal after
# "finished" changes no status; no write goes through a link out of --out;
# an interrupted tune leaves its tuned folder as it was.
# Usage: test_data_safety.sh <shadowbench> <source root>
set -u
sb=$1 root=$2
case $sb in /*) ;; *) sb=$PWD/$sb ;; esac  # some cases run from another folder
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failed=0
fail() { echo "FAILED: $*"; failed=$((failed + 1)); }
ok() { echo "ok: $*"; }
small="--width 64 --height 64 --gt-samples 16 --frames 3 --warmup 0 --no-cache -q"

# Two runs on one folder: the second fails at once.
"$sb" run --scene thin_features $small --out "$tmp/a" &  # every technique: seconds
first=$!
i=0
while [ ! -f "$tmp/a/.lock" ] && [ $i -lt 100 ]; do sleep 0.05; i=$((i + 1)); done
out=$("$sb" run --scene parallel_planes $small --out "$tmp/a" 2>&1)
rc=$?
[ $rc = 2 ] && printf '%s' "$out" | grep -q "another shadowbench is writing there" &&
    ok "a second run on the same folder: exit 2, '$out'" || fail "second run: exit $rc: $out"
wait $first && grep -q '"complete":	true' "$tmp/a/run.json" && ok "the first run completes" ||
    fail "the first run did not complete"

# gt into a folder a run is writing is refused too (it wrote its ground
# truth beside the run's cells).
"$sb" run --scene thin_features $small --out "$tmp/a2" >/dev/null 2>&1 &
first=$!
i=0
while [ ! -f "$tmp/a2/.lock" ] && [ $i -lt 100 ]; do sleep 0.05; i=$((i + 1)); done
out=$("$sb" gt --scene parallel_planes --width 32 --height 32 --gt-samples 4 --no-cache -q --out "$tmp/a2" 2>&1)
rc=$?
[ $rc = 2 ] && printf '%s' "$out" | grep -q "another shadowbench is writing there" &&
    ok "gt into a running run's folder: exit 2" || fail "gt into a running run's folder: exit $rc: $out"
kill $first; wait $first

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
# where a full disk gives ENOSPC; the program ignores the SIGXFSZ that
# would kill it): one line naming the file, exit 1, no temporary left, and
# run.json says incomplete. 4 KiB stops a cell's EXR, 40 KiB the ground
# truth's.
for kib in 4 40; do
    out=$( (ulimit -f $kib; "$sb" run --scene parallel_planes --technique hard,pcf \
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

# The file-size limit as the hostile pass met it (a 64² EXR of the ground
# truth past 4 KiB), and one too small for tune.json or run.json: one line,
# exit 1 (a runtime error, the same for every command), no temporary.
out=$( (ulimit -f 4; "$sb" run --scene floating_box_sphere --technique hard,pcss --width 64 --height 64 \
           --gt-samples 16 --frames 1 --settings default --no-cache -q --out "$tmp/fsize") 2>&1)
rc=$?
[ $rc = 1 ] && [ "$(printf '%s\n' "$out" | wc -l)" = 1 ] && printf '%s' "$out" | grep -q "File too large" &&
    [ -z "$(find "$tmp/fsize" -name '*.tmp.*')" ] && ok "ulimit -f 4: '$out'" || fail "ulimit -f 4: exit $rc: $out"
for cmd in "run --scene parallel_planes --technique hard" \
           "tune --scene parallel_planes --scene thin_features --technique hard"; do
    out=$( (ulimit -f 0; "$sb" $cmd $small --out "$tmp/f0") 2>&1)
    rc=$?
    [ $rc = 1 ] && [ "$(printf '%s\n' "$out" | wc -l)" = 1 ] && printf '%s' "$out" | grep -q "cannot write: File too large" &&
        ok "${cmd%% *} with nothing writable past 0 bytes: exit 1, '$out'" || fail "${cmd%% *} under ulimit -f 0: exit $rc: $out"
    rm -rf "$tmp/f0"
done

# A cache writer that died before its rename leaves "<entry>.tmp.<pid>": the
# next command that uses the cache removes it. A live writer's stays: it
# holds its entry's lock (flock), wherever it runs (docs/scale-out.md). A
# file whose name is no cache entry's temporary stays too.
mkdir -p "$tmp/sweep"
: > "$tmp/sweep/parallel_planes-0000000000000000.exr.tmp.4194305"
: > "$tmp/sweep/parallel_planes-0000000000000001.exr.tmp.$$"
: > "$tmp/sweep/notes.txt.tmp.42"
flock "$tmp/sweep/parallel_planes-0000000000000001.exr.lock" "$sb" gt --scene parallel_planes --width 32 --height 32 --gt-samples 4 --cache "$tmp/sweep" -q --out "$tmp/sweep-gt" \
    >/dev/null || fail "gt into the cache"
[ ! -e "$tmp/sweep/parallel_planes-0000000000000000.exr.tmp.4194305" ] && [ -e "$tmp/sweep/parallel_planes-0000000000000001.exr.tmp.$$" ] &&
    [ -e "$tmp/sweep/notes.txt.tmp.42" ] &&
    ok "a dead writer's cache temporary removed, a live one's and a stranger's kept" ||
    fail "cache temporaries: $(ls "$tmp/sweep")"

# A cache entry that cannot be written (its name taken by a folder) costs
# time, not the result: a warning, the run exits 0.
entry=$(ls "$tmp/sweep" | grep -v '\.tmp\.\|\.lock$' | head -1)
rm "$tmp/sweep/$entry" && mkdir "$tmp/sweep/$entry"
out=$("$sb" gt --scene parallel_planes --width 32 --height 32 --gt-samples 4 --cache "$tmp/sweep" --out "$tmp/sweep-gt" \
          2>&1 >/dev/null)
rc=$?
[ $rc = 0 ] && ! printf '%s' "$out" | grep -q "error:" && printf '%s' "$out" | grep -q "warning: ground truth parallel_planes: not cached" &&
    ok "a cache entry that cannot be written: warnings, exit 0" || fail "an unwritable cache entry: exit $rc: $out"

# Under an address-space limit Mesa crashes rather than failing: refused in
# one line before it is reached (exit 2). A scene too large for the memory
# left is out of memory, exit 1, saying how much it needed, not "malformed".
# (Not under the sanitizers: their shadow memory needs terabytes of address
# space.)
if [ -z "${SB_SANITIZED:-}" ]; then
    out=$( (ulimit -v 262144; "$sb" run --scene floating_box_sphere --technique hard --width 64 --height 64 \
               --gt-samples 16 --frames 1 --settings default --no-cache -q --out "$tmp/as") 2>&1)
    rc=$?
    [ $rc = 2 ] && [ "$(printf '%s\n' "$out" | wc -l)" = 1 ] &&
        printf '%s' "$out" | grep -q "^shadowbench: error: OpenGL: the address-space limit (ulimit -v 262144 KiB) is below" &&
        ok "ulimit -v 256 MiB: '$out'" || fail "ulimit -v 256 MiB: exit $rc: $out"
    python3 -c '
import base64, json, sys
blob = bytes(30 << 20)
json.dump({"asset": {"version": "2.0"}, "buffers": [{"byteLength": len(blob),
           "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}]}, open(sys.argv[1], "w"))' \
        "$tmp/big.gltf"
    for kib in 300000 400000; do
        out=$( (ulimit -v $kib; "$sb" gt --scene "$tmp/big.gltf" -q --out "$tmp/big") 2>&1)
        rc=$?
        [ $rc = 1 ] && [ "$(printf '%s\n' "$out" | wc -l)" = 1 ] &&
            printf '%s' "$out" | grep -q "^shadowbench: error: $tmp/big.gltf: out of memory.*: [0-9]* more bytes were needed" &&
            ok "a 40 MB data URI under ulimit -v $kib: '$out'" || fail "a 40 MB data URI under ulimit -v $kib: exit $rc: $out"
    done
    rm -f "$tmp/big.gltf"
fi

# Standard output: a reader that closes the pipe stops nothing (the status
# is the command's own), a full device is one line and exit 1.
status=$( { sleep 0.2; "$sb" list 2>"$tmp/list.err"; echo $? > "$tmp/list.rc"; } | head -c 0; cat "$tmp/list.rc")
[ "$status" = 0 ] && [ ! -s "$tmp/list.err" ] && ok "list | head -c 0: exit 0, nothing said" ||
    fail "list | head -c 0: exit $status: $(cat "$tmp/list.err")"
for args in list --help "help run"; do
    out=$("$sb" $args 2>&1 >/dev/full)
    rc=$?
    # (the reason is known when the last write fails; help's is not the last)
    [ $rc = 1 ] && [ "$(printf '%s\n' "$out" | wc -l)" = 1 ] &&
        printf '%s' "$out" | grep -q "^shadowbench: error: standard output: cannot write: " &&
        ok "$args > /dev/full: exit 1, '$out'" || fail "$args > /dev/full: exit $rc: $out"
done
# stderr closed at the first line: the run goes on and completes (SIGPIPE
# killed it with 141 at its first message).
status=$( { "$sb" run --scene parallel_planes --technique hard $small --out "$tmp/pipe" 2>&1 >/dev/null;
            echo $? > "$tmp/pipe.rc"; } | head -c 1 >/dev/null; cat "$tmp/pipe.rc")
[ "$status" = 0 ] && grep -q '"complete":	true' "$tmp/pipe/run.json" && ok "stderr closed early: the run completes, exit 0" ||
    fail "stderr closed early: exit $status"

# SIGTERM as soon as the run says it has finished: it is complete, so it
# exits 0 (it exited 143 with a whole report). A kill that finds the process
# gone proves nothing: up to 5 tries, at least one must land.
landed=0
for try in 1 2 3 4 5; do
    rm -f "$tmp/late.fifo" && mkfifo "$tmp/late.fifo"
    "$sb" run --scene parallel_planes --technique hard --width 64 --height 64 --gt-samples 16 --frames 3 --warmup 0 \
        --no-cache --out "$tmp/late" 2>"$tmp/late.fifo" >/dev/null &
    pid=$!
    hit=0
    while IFS= read -r line; do
        case $line in *"run finished"*) kill -TERM $pid 2>/dev/null && hit=1 ;; esac
    done < "$tmp/late.fifo"
    wait $pid
    rc=$?
    complete=$(grep -c '"complete":	true' "$tmp/late/run.json")
    if [ $hit = 1 ]; then
        landed=$((landed + 1))
        [ $rc = 0 ] && [ "$complete" = 1 ] && ok "SIGTERM after 'run finished' (try $try): exit 0, complete" ||
            fail "SIGTERM after 'run finished' (try $try): exit $rc, complete $complete"
    fi
    [ $landed -ge 2 ] && break
done
[ $landed -ge 1 ] || fail "SIGTERM after 'run finished': no kill landed in 5 tries"

# A folder inside --out that is a link would take the run's files out of
# it: refused in one line, nothing written through it. A scene's folder is
# looked at before any work (exit 2), a cell's when it is written (exit 1).
mkdir -p "$tmp/linked/out" "$tmp/linked/elsewhere"
for link in parallel_planes parallel_planes/hard; do
    "$sb" run --scene parallel_planes --technique hard $small --out "$tmp/linked/out" >/dev/null 2>&1
    rm -rf "$tmp/linked/out/$link" && ln -s "$tmp/linked/elsewhere" "$tmp/linked/out/$link"
    out=$("$sb" run --scene parallel_planes --technique hard $small --out "$tmp/linked/out" 2>&1)
    rc=$?
    want=$([ $link = parallel_planes ] && echo 2 || echo 1)
    [ $rc = "$want" ] && [ "$(printf '%s\n' "$out" | wc -l)" = 1 ] && printf '%s' "$out" | grep -q "$link: a link" &&
        [ -z "$(ls -A "$tmp/linked/elsewhere")" ] && ok "$link as a link: exit $rc, '$out'" ||
        fail "$link as a link: exit $rc: $out; elsewhere holds $(ls -A "$tmp/linked/elsewhere")"
    rm "$tmp/linked/out/$link"
done
for pair in "tuned tuned/out" "out/tuned out"; do  # --out inside --tuned, --tuned inside --out
    out=$("$sb" tune --scene parallel_planes --scene thin_features --technique hard --write-tuned --allow-uncommitted \
              --tuned "$tmp/nest/${pair% *}" --out "$tmp/nest/${pair#* }" $small 2>&1)
    rc=$?
    [ $rc = 2 ] && printf '%s' "$out" | grep -q "one inside the other" && [ ! -e "$tmp/nest" ] &&
        ok "tune with one of --out and --tuned inside the other: '$out'" || fail "nested --out and --tuned: exit $rc: $out"
done

# An interrupted tune leaves the tuned folder as it was (every file, byte
# for byte) and its next set for the next tune to remove; a whole tune
# replaces the folder as one set, keeping the files of techniques it did
# not tune.
tune="tune --scene parallel_planes --scene thin_features --width 32 --height 32 --gt-samples 4 --frames 1 --no-cache
      --write-tuned --allow-uncommitted -q"
"$sb" $tune --technique hard,pcf --tuned "$tmp/tuned" --out "$tmp/tune1" >/dev/null || fail "the first tune"
before=$(cd "$tmp/tuned" && md5sum hard.json pcf.json)
"$sb" $tune --technique hard,pcf --width 40 --tuned "$tmp/tuned" --out "$tmp/tune2" >/dev/null 2>&1 &
pid=$!
i=0
while [ ! -f "$tmp/tune2/hard.json" ] && [ $i -lt 600 ]; do sleep 0.05; i=$((i + 1)); done
[ -f "$tmp/tune2/hard.json" ] || fail "the second tune's hard.json never came (30 s)"
kill -TERM $pid
wait $pid
rc=$?
[ $rc = 143 ] && [ "$(cd "$tmp/tuned" && md5sum hard.json pcf.json)" = "$before" ] && ls -d "$tmp/tuned.tmp."* >/dev/null 2>&1 &&
    ok "a tune killed after its first technique: exit 143, the tuned folder as it was" ||
    fail "a killed tune: exit $rc, tuned folder $(cd "$tmp/tuned" && md5sum hard.json pcf.json)"
"$sb" $tune --technique hard --width 40 --tuned "$tmp/tuned" --out "$tmp/tune3" >/dev/null || fail "the third tune"
after=$(cd "$tmp/tuned" && md5sum hard.json pcf.json)
[ "$(printf '%s\n' "$after" | grep pcf)" = "$(printf '%s\n' "$before" | grep pcf)" ] &&
    [ "$(printf '%s\n' "$after" | grep hard)" != "$(printf '%s\n' "$before" | grep hard)" ] &&
    ! ls -d "$tmp/tuned.tmp."* >/dev/null 2>&1 && [ "$(ls "$tmp/tuned")" = "$(printf 'hard.json\npcf.json')" ] &&
    ok "a whole tune: hard.json new, pcf.json kept, the dead tune's set removed" ||
    fail "after a whole tune: $(ls -a "$tmp") / $after"

# A run's folder inside the tuned folder it reads would put its report
# among the tuned files: refused.
out=$("$sb" run --scene parallel_planes --technique hard $small --tuned "$tmp/tuned" --out "$tmp/tuned/run" 2>&1)
rc=$?
[ $rc = 2 ] && printf '%s' "$out" | grep -q "inside the tuned folder" && [ ! -e "$tmp/tuned/run" ] &&
    ok "run --out inside --tuned: refused" || fail "run --out inside --tuned: exit $rc: $out"

# A tuned folder holding the current one would be swapped out from under
# the process (and its user's shell): refused.
out=$(cd "$tmp/tuned" && "$sb" $tune --technique hard --tuned . --out "$tmp/tune5" 2>&1)
rc=$?
[ $rc = 2 ] && printf '%s' "$out" | grep -q "holds the current folder" && [ -f "$tmp/tuned/pcf.json" ] &&
    ok "--tuned .: refused, '$out'" || fail "--tuned .: exit $rc: $out"

# --write-tuned into a folder that cannot be made is refused before --out
# is made.
: > "$tmp/plain"
out=$("$sb" $tune --technique hard --tuned "$tmp/plain/tuned" --out "$tmp/tune4" 2>&1)
rc=$?
[ $rc = 2 ] && [ "$(printf '%s\n' "$out" | wc -l)" = 1 ] && [ ! -e "$tmp/tune4" ] &&
    ok "an unmakeable --tuned: refused before --out, '$out'" || fail "an unmakeable --tuned: exit $rc: $out"

# A temporary's name taken by a link (planted for the next writer's pid,
# here a process stopped before it starts): removed and made anew, never
# written through.
"$sb" run --scene parallel_planes --technique hard $small --out "$tmp/planted" >/dev/null 2>&1
echo precious > "$tmp/victim"
sh -c 'kill -STOP $$; exec "$0" "$@"' "$sb" run --scene parallel_planes --technique hard $small \
    --out "$tmp/planted" >/dev/null 2>&1 &
pid=$!
i=0  # until it has stopped itself: a CONT sent before its STOP would leave it stopped for good
while [ "$(cut -d' ' -f3 /proc/$pid/stat 2>/dev/null)" != T ] && [ $i -lt 200 ]; do sleep 0.05; i=$((i + 1)); done
ln -s "$tmp/victim" "$tmp/planted/run.json.tmp.$pid"
ln -s "$tmp/victim" "$tmp/planted/parallel_planes/hard/visibility.exr.tmp.$pid"
kill -CONT $pid
wait $pid
rc=$?
[ $rc = 0 ] && [ "$(cat "$tmp/victim")" = precious ] && [ ! -L "$tmp/planted/run.json" ] &&
    [ ! -L "$tmp/planted/parallel_planes/hard/visibility.exr" ] && ok "temporaries planted as links: not followed" ||
    fail "planted temporaries: exit $rc, victim '$(cat "$tmp/victim")'"

# A standard stream closed at the start is not the next file opened (the
# report's lines went into .lock): stdout closed is one line, exit 1, as a
# full one; stderr closed, the run goes on.
"$sb" run --scene parallel_planes --technique hard $small --out "$tmp/closed1" >&- 2>"$tmp/closed1.err"
rc=$?
[ $rc = 1 ] && [ "$(cat "$tmp/closed1.err")" = "shadowbench: error: standard output: cannot write: it is closed" ] &&
    [ ! -s "$tmp/closed1/.lock" ] && ok "stdout closed: exit 1, one line" || fail "stdout closed: exit $rc: $(cat "$tmp/closed1.err")"
"$sb" run --scene parallel_planes --technique hard $small --out "$tmp/closed2" >/dev/null 2>&-
rc=$?
[ $rc = 0 ] && [ ! -s "$tmp/closed2/.lock" ] && ok "stderr closed: exit 0, nothing in .lock" || fail "stderr closed: exit $rc"

# git that fails (no descriptors left for it) is not "not a git checkout":
# said, and recorded as unknown.
out=$( (ulimit -n 10; "$sb" run --scene parallel_planes --technique hard --width 32 --height 32 --gt-samples 4 \
           --frames 1 --warmup 0 --no-cache --out "$tmp/nofd") 2>&1 >/dev/null)
rc=$?
[ $rc = 0 ] && printf '%s' "$out" | grep -q "warning: git failed on the source tree" &&
    grep -q '"source_tree":	"unknown: git failed"' "$tmp/nofd/run.json" && ok "git failing: said, recorded unknown" ||
    fail "git failing: exit $rc: $out"

[ "$failed" = 0 ] && echo "all passed" || echo "$failed failed"
[ "$failed" = 0 ]
