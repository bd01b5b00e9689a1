#!/bin/sh
# An engine's faults (docs/engines.md): each is one line that names the
# engine and the cell, and exit status 2 — no Chromium, an engine that
# fails to load, a page error, a cell over its time limit, an image of the
# wrong size (the driver's own check of the page's reply, and the
# harness's of the file), a driver that exits, answers another request or
# replies with a line too long to be a reply, an engine whose packages are
# not installed — or, with --keep-going, the cell marked failed in the
# matrix while the run goes on, whether it failed when rendered or when
# timed. No browser outlives the command, whatever ends it: a normal exit,
# a fault, a time limit, SIGTERM, SIGINT, SIGHUP or SIGKILL.
#
# The faults come from a copy of engines/ ($SB_ENGINES) whose three page
# misbehaves as each case asks; the real driver and packages are linked.
# Skips (77) where the engines are not installed.
set -u
sb=$1
src=$(cd "$(dirname "$0")/.." && pwd)
[ -e "$src/engines/three/node_modules/.package-lock.json" ] && [ -x /usr/bin/chromium ] || {
  echo "skipped: the engines are not installed (tools/setup installs them)"; exit 77; }
t=$(mktemp -d /tmp/sb_test_engine_faults_XXXXXX)
trap 'pkill -KILL -f "$t/" 2>/dev/null; rm -rf "$t"' EXIT
fails=0
fail() { echo "FAILED: $*"; fails=$((fails + 1)); }

mkdir -p "$t/engines/three" "$t/tmp"
ln -s "$src/engines/driver" "$t/engines/driver"
ln -s "$src/engines/common" "$t/engines/common"
ln -s "$src/engines/three/node_modules" "$t/engines/three/node_modules"

# A three page whose sbRender is the given JavaScript body (req in scope).
page() {
  cat > "$t/engines/three/page.html" <<EOF
<!doctype html><meta charset="utf-8"><link rel="icon" href="data:,">
<script>
window.sbRender = async (req) => { $1 };
window.sbReady = ${2:-true};
</script>
EOF
}

# No process of ours may be left: none whose command line names the
# test's folder (the browser's profile is under its \$TMPDIR).
no_browser_left() {  # within 3 s: a dying browser's children may take a moment
  for i in $(seq 1 30); do
    pgrep -f "$t/tmp" > /dev/null || return 0
    sleep 0.1
  done
  fail "$1: $(pgrep -f "$t/tmp" | wc -l) process(es) left running:"
  pgrep -af "$t/tmp" | head -5
}

run() {  # run [options]: one three cell on parallel_planes, small; the adapters in $engines
  TMPDIR="$t/tmp" SB_ENGINES="${engines:-$t/engines}" "$sb" run --scene parallel_planes --technique three_basic \
    --settings default --width 64 --height 48 --gt-samples 16 --no-cache --frames 1 --warmup 0 \
    --out "$t/out" "$@" > "$t/stdout" 2> "$t/stderr"
}

# expect NAME PATTERN: exit 2 and one error line naming the engine, the cell and PATTERN
expect() {
  status=$1 name=$2 pattern=$3
  [ "$status" -eq 2 ] || fail "$name: exit $status, not 2"
  lines=$(grep -c "error: engine three, cell three_basic (.*) on parallel_planes: .*$pattern" "$t/stderr")
  [ "$lines" -eq 1 ] || { fail "$name: $lines lines naming the engine, cell and '$pattern'"; cat "$t/stderr"; }
  no_browser_left "$name"
}

page 'throw new Error("unreachable")'
SB_CHROMIUM=/nonexistent/chromium run; expect $? "no chromium" "no Chromium at /nonexistent/chromium"

page 'return null;' '"the engine did not load"'
run; expect $? "load" "failed to load: the engine did not load"

page 'throw new Error("the adapter broke");'
run; expect $? "page error" "the adapter broke"

page 'return new Promise(() => {});'
run --engine-timeout 3; expect $? "time limit" "over its time limit of 3 s"

page 'return { version: "x", renderer: "y", ms: [1], data: btoa("12345678") };'
run; expect $? "wrong size" "an image of the wrong size"

# --keep-going: the engine cell marked failed, shadowbench's own measured, exit 2
page 'throw new Error("the adapter broke");'
run --keep-going --technique hard; status=$?
[ "$status" -eq 2 ] || fail "keep-going: exit $status, not 2"
grep -q '"failed":' "$t/out/matrix.json" || fail "keep-going: the matrix does not mark the cell failed"
grep -q '^"parallel_planes","three_basic",.*,false,".*the adapter broke",,$' "$t/out/matrix.csv" ||
  fail "keep-going: matrix.csv's failed column does not say why"
grep -q '"cell":	"hard' "$t/out/matrix.json" || fail "keep-going: the run did not go on to hard"
grep -q '"complete":	true' "$t/out/run.json" || fail "keep-going: the run is not complete"
no_browser_left "keep-going"

# --keep-going when the cell renders, then fails while it is timed: marked
# failed too, the run complete.
page 'window.calls = (window.calls || 0) + 1;
  if (window.calls > 1) throw new Error("broke while timed");
  const f = new Float32Array(req.width * req.height * req.outputs.length).fill(1);
  const b = new Uint8Array(f.buffer); let s = "";
  for (let i = 0; i < b.length; i++) s += String.fromCharCode(b[i]);
  return { version: "x", renderer: "y", ms: [1], data: btoa(s) };'
run --keep-going; status=$?
[ "$status" -eq 2 ] || fail "keep-going while timed: exit $status, not 2"
grep -q '"failed":.*broke while timed' "$t/out/matrix.json" ||
  fail "keep-going while timed: the matrix does not mark the cell failed"
grep -q '"complete":	true' "$t/out/run.json" || fail "keep-going while timed: the run is not complete"
no_browser_left "keep-going while timed"

# A driver that misbehaves (a stand-in: engines/driver/driver.mjs of another
# $SB_ENGINES): it exits, answers another request, or writes an image of
# the wrong size; and an engine whose packages are not installed.
mkdir -p "$t/bad/driver/node_modules" "$t/bad/three/node_modules"
: > "$t/bad/driver/node_modules/.package-lock.json"
: > "$t/bad/three/node_modules/.package-lock.json"
driver() {  # driver BODY: JavaScript run for each request (req parsed; say prints a reply)
  {
    echo "import fs from 'node:fs';"
    echo "import readline from 'node:readline';"
    echo "const say = (r) => process.stdout.write(JSON.stringify(r) + String.fromCharCode(10));"
    echo "say({ id: 0, ok: true, version: 'stand-in' });"
    echo "readline.createInterface({ input: process.stdin })"
    echo "  .on('line', (line) => { const req = JSON.parse(line); $1 });"
  } > "$t/bad/driver/driver.mjs"
}
engines="$t/bad"
driver 'process.exit(3);'
run; expect $? "driver exits" "its driver exited"
driver 'say({ id: req.id + 7, ok: true });'
run; expect $? "another request" "its driver answered another request"
driver 'say({ id: req.id, ok: true, version: "x".repeat(2 << 20) });'
run; expect $? "reply too long" "its driver's reply is too long"
driver 'fs.writeFileSync(req.output, "12345678"); say({ id: req.id, ok: true, version: "x", renderer: "y", ms: [1] });'
run; expect $? "wrong size (the harness)" "an image of the wrong size: 8 bytes, not 2 image(s) of 64x48 float32"
rm "$t/bad/three/node_modules/.package-lock.json"
run; expect $? "not installed" "the packages of $t/bad/three are not installed"
engines=""

# A cell that works leaves nothing running either.
rm -f "$t/engines/three/page.html"
ln -s "$src/engines/three/page.html" "$t/engines/three/page.html"
ln -s "$src/engines/three/adapter.js" "$t/engines/three/adapter.js"
run; status=$?
[ "$status" -eq 0 ] || { fail "the real adapter: exit $status"; cat "$t/stderr"; }
no_browser_left "a normal exit"

# Signals, while a cell hangs in the browser: the command ends (128 + the
# signal; SIGKILL: 137) and takes the browser with it.
rm -f "$t/engines/three/page.html"
page 'return new Promise(() => {});'
# The four at once, each with its own folder.
for sig in TERM INT HUP KILL; do
  mkdir -p "$t/tmp/$sig"
  TMPDIR="$t/tmp/$sig" SB_ENGINES="$t/engines" "$sb" run --scene parallel_planes --technique three_basic \
    --settings default --width 64 --height 48 --gt-samples 16 --no-cache --frames 1 --warmup 0 \
    --out "$t/out_$sig" 2> "$t/stderr_$sig" &
  eval "pid_$sig=$!"
done
for sig in TERM INT HUP KILL; do
  for i in $(seq 1 200); do  # until its browser runs (up to 20 s)
    pgrep -f "chromium.*$t/tmp/$sig/" > /dev/null && break
    sleep 0.1
  done
  pgrep -f "chromium.*$t/tmp/$sig/" > /dev/null || fail "SIG$sig: the browser never started"
done
sleep 0.5
for sig in TERM INT HUP KILL; do
  eval "pid=\$pid_$sig"
  kill -s "$sig" "$pid"
  wait "$pid"; status=$?
  case $sig in TERM) want=143 ;; INT) want=130 ;; HUP) want=129 ;; KILL) want=137 ;; esac
  [ "$status" -eq "$want" ] || fail "SIG$sig: exit $status, not $want"
done
no_browser_left "the signals"
for sig in TERM INT HUP KILL; do mv "$t/tmp/$sig"/* "$t/tmp/" 2>/dev/null; rmdir "$t/tmp/$sig"; done

# A signal's exit leaves the driver's folder (nothing can remove a tree
# then); the next command's driver removes those of dead processes.
[ -n "$(ls "$t/tmp")" ] || fail "the signals left no folder to test the sweep on"
rm -f "$t/engines/three/page.html"
ln -s "$src/engines/three/page.html" "$t/engines/three/page.html"
run; status=$?
[ "$status" -eq 0 ] || fail "after the signals: exit $status"
left=$(ls "$t/tmp" | wc -l)
[ "$left" -eq 0 ] || fail "$left folder(s) of dead drivers left in \$TMPDIR: $(ls "$t/tmp")"

[ "$fails" -eq 0 ] && echo "engine faults: every case passed"
[ "$fails" -eq 0 ]
