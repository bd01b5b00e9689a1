#!/bin/sh
# Protects `shadowbench check` as a user meets it (docs/regression.md):
# recording, passing, each kind of failure with its exit status and the line
# that says it, the page of moved cells, bad baselines refused with one
# line naming the file, an interrupted --update that changes nothing, a
# pipe closed early and the baselines of a scene no longer shipped. On one scene and one technique, in a scratch folder.
# Usage: test_check_cli.sh <shadowbench>
set -u
sb=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
B=$tmp/baselines
cell=$B/parallel_planes/hard.json
failed=0

# expect STATUS PATTERN ARGS...: check ARGS exits STATUS and prints PATTERN.
expect() {
    want=$1 pattern=$2
    shift 2
    out=$("$sb" check -q --scene parallel_planes --baselines "$B" --out "$tmp/out" --cache "$tmp/cache" "$@" 2>&1)
    rc=$?
    if [ "$rc" != "$want" ] || ! printf '%s\n' "$out" | grep -q -- "$pattern"; then
        echo "FAILED: check $* -> exit $rc (expected $want and '$pattern'):"
        printf '%s\n' "$out" | sed 's/^/    /'
        failed=$((failed + 1))
    else
        echo "ok: check $* -> $rc, '$pattern'"
    fi
}
record() { "$sb" check -q --update --allow-uncommitted --scene parallel_planes --technique hard,pcf --baselines "$B" \
               --out "$tmp/out" --cache "$tmp/cache" >/dev/null 2>&1 || { echo "FAILED: --update"; failed=$((failed + 1)); }; }
# edit SED-EXPRESSION: rewrites the hard cell's JSON in place.
edit() { sed -i -e "$1" "$cell"; }

expect 1 "no baseline .*hard" --technique hard
record
# A committed baselines folder has files and no .lock (git ignores it):
# --update takes it all the same.
rm "$B/.lock"
record
[ -f "$cell" ] && [ -f "${cell%.json}.png" ] || { echo "FAILED: --update wrote no files"; failed=$((failed + 1)); }
# The set as recorded, put back before each case that edits it (faster
# than recording it again, which the cases of --update itself still do).
cp -a "$B" "$tmp/recorded"
restore() { rm -rf "$B" && cp -a "$tmp/recorded" "$B"; }
expect 0 "pass .*hard" --technique hard
expect 0 "0 REGRESSED" --technique hard,pcf

# A metric worse than recorded (the file says it was far lower): REGRESSED,
# with the metric's line. Better than recorded: improved, not a failure
# unless --strict, with the command that records it.
edit '0,/"rmse":\t[0-9]/s/"rmse":\t[-0-9.e]*/"rmse":\t0.0001/'
expect 1 "rmse .*worse" --technique hard
restore
edit '0,/"rmse":\t[0-9]/s/"rmse":\t[-0-9.e]*/"rmse":\t0.9/'
expect 0 "record it: shadowbench check --update" --technique hard
expect 1 "improved .*hard" --technique hard --strict

# A change that moves the picture: recorded with pcf's kernel 1.5 times
# wider than its radius says, checked with the real one.
cp -r "$(dirname "$0")/../shaders" "$tmp/shaders"
sed -i 's/PCF_RADIUS_TEXELS \*/1.5 * PCF_RADIUS_TEXELS */' "$tmp/shaders/pcf.glsl"
"$sb" check -q --update --allow-uncommitted --scene parallel_planes --technique pcf --baselines "$B" --out "$tmp/out" \
    --cache "$tmp/cache" --shaders "$tmp/shaders" >/dev/null 2>&1
expect 1 "pixels moved" --technique pcf
[ -f "$tmp/out/check.html" ] && grep -q "pcf" "$tmp/out/check.html" && [ -f "$tmp/out/parallel_planes/pcf.png" ] ||
    { echo "FAILED: no page or heatmap of the moved cell"; failed=$((failed + 1)); }

# Another cell's picture (or an interrupted --update): its fingerprint.
restore
cp "$B/parallel_planes/pcf.png" "${cell%.json}.png"
expect 2 "hard.json: its picture is not the one it recorded" --technique hard

# Recorded parameters that the cell's name no longer means (a default changed).
restore
edit 's/"constant_bias":\t"[0-9.e-]*"/"constant_bias":\t"0.001"/'
expect 1 "no longer what 'hard' means" --technique hard

# Unreadable baselines: exit 2, one line naming the file and the problem.
restore
edit 's/"constant_bias":/"no_such":\t"1",\n\t\t\t"constant_bias":/'
expect 2 "hard.json: hard.no_such: unknown parameter" --technique hard
restore
edit 's/"constant_bias":\t"[0-9.e-]*"/"constant_bias":\t"5"/'
expect 2 "hard.json: hard.constant_bias: 5 is out of range" --technique hard
restore
edit 's/"gt_version":\t[0-9]*/"gt_version":\t1/'
expect 2 "hard.json: recorded with ground-truth version 1" --technique hard
restore
printf '{"cell": ' > "$cell"
expect 2 "hard.json: not valid JSON (at byte 8)" --technique hard
restore
rm "${cell%.json}.png"
expect 2 "hard.json: its picture .* is missing" --technique hard
restore
printf '{}' > "$B/parallel_planes/nosuch.json"
expect 2 "nosuch.json: cell 'nosuch': unknown technique 'nosuch'" --technique hard
rm "$B/parallel_planes/nosuch.json"
restore
edit 's/"rmse":\t[-0-9.e]*,/"rmse":\t"abc",/'
expect 2 "hard.json: metric rmse: needs a number" --technique hard
restore
edit '0,/"value":/s/"value":\t[-0-9.e]*/"value":\t-1/'
expect 2 "hard.json: metric rmse: needs a number in \[0, 1\] and a tolerance" --technique hard
restore
# A null metric (it would make any value "better" and hide a moved
# picture), one out of its range, a count that is not whole: refused.
edit 's/"rmse":\t[-0-9.e]*,/"rmse":\tnull,/'
expect 2 "hard.json: metric rmse: needs a number in \[0, 1\]" --technique hard
restore
edit 's/"leak_fraction":\t[-0-9.e]*,/"leak_fraction":\t-1,/'
expect 2 "hard.json: metric leak_fraction: needs a number in \[0, 1\]" --technique hard
restore
edit 's/"nonfinite":\t0$/"nonfinite":\t0.5/'
expect 2 "hard.json: metric nonfinite: needs a number in \[0, inf\], whole" --technique hard
restore
# A key twice (JSON readers differ on which counts), a parameter missing or
# empty params (a default would stand in unseen), a value that is no float.
edit 's/"rmse":\t\([-0-9.e]*\),/"rmse":\t\1, "rmse": 99,/'
expect 2 "hard.json: the key \"rmse\" appears twice in one object" --technique hard
restore
edit '/"slope_bias":/d'
edit 's/"constant_bias":\t"\([^"]*\)",/"constant_bias":\t"\1"/'
expect 2 "hard.json: lacks hard.slope_bias" --technique hard
restore
edit 's/"params":\t{/"params":\t{}, "x": {/'
expect 2 "hard.json: lacks hard.constant_bias" --technique hard
restore
edit 's/"constant_bias":\t"[^"]*"/"constant_bias":\t"1e-320"/'
expect 2 "hard.json: hard.constant_bias: 1e-320 is too close to 0 for a float" --technique hard
restore
edit 's/"scene":\t"parallel_planes"/"scene":\t"map_border"/'
expect 2 "hard.json: its \"scene\" is not its folder's" --technique hard
restore
printf 'x' >> "$cell"
expect 2 "hard.json: not valid JSON" --technique hard
restore
rm "$cell" && mkfifo "$cell"
expect 2 "hard.json: cannot read: not a regular file" --technique hard
rm "$cell"
restore
printf '{}' > "$B/parallel_planes/hard@slope_bias=2,slope_bias=3.json"
expect 2 "slope_bias is given twice" --technique hard
rm "$B/parallel_planes/hard@slope_bias=2,slope_bias=3.json"

# Folders: the page inside the baselines; baselines that are a file.
expect 2 "inside the baselines folder" --technique hard --out "$B/page"
expect 2 "not a folder" --technique hard --baselines "$cell"

# Options that are not check's, or that cannot go together.
expect 2 "has no effect with --update" --update --strict
expect 2 "an empty folder name" --baselines ""
expect 2 "unknown option for check" --set hard.slope_bias=2
expect 2 "unknown option for check" --width 64
out=$("$sb" run --baselines "$B" 2>&1)
[ $? = 2 ] && printf '%s' "$out" | grep -q "unknown option for run" ||
    { echo "FAILED: run --baselines: $out"; failed=$((failed + 1)); }

# --update stopped before the end leaves the baselines as they were (every
# file byte for byte) and its next set for the next --update to remove.
record
sums() { (cd "$B" && find . -type f ! -name .lock | sort | xargs md5sum); }
before=$(sums)
rm -f "$tmp/update.fifo" && mkfifo "$tmp/update.fifo"
"$sb" check --update --allow-uncommitted --scene parallel_planes --technique hard,pcf --baselines "$B" --out "$tmp/out" \
    --cache "$tmp/cache" >"$tmp/update.fifo" 2>/dev/null &
pid=$!
while IFS= read -r line; do
    case $line in *"  hard"*) kill -TERM $pid ;; esac
done < "$tmp/update.fifo"
wait $pid
rc=$?
[ $rc = 143 ] && [ "$(sums)" = "$before" ] && ls -d "$B.tmp."* >/dev/null 2>&1 &&
    echo "ok: --update killed after its first cell: exit 143, the baselines as they were" ||
    { echo "FAILED: a killed --update: exit $rc"; failed=$((failed + 1)); }
record
! ls -d "$B.tmp."* >/dev/null 2>&1 && echo "ok: the next --update removes the dead one's set" ||
    { echo "FAILED: a dead --update's set left: $(ls -d "$B.tmp."*)"; failed=$((failed + 1)); }

# A reader that closes the pipe stops nothing: check checks every cell and
# its status is its verdict (SIGPIPE killed it before the first cell).
status=$( { "$sb" check -q --scene parallel_planes --technique hard --baselines "$B" --out "$tmp/piped" \
                --cache "$tmp/cache"; echo $? > "$tmp/piped.rc"; } | head -c 0; cat "$tmp/piped.rc")
[ "$status" = 0 ] && [ -f "$tmp/piped/check.html" ] && echo "ok: check | head -c 0: every cell checked, exit 0" ||
    { echo "FAILED: check | head -c 0: exit $status"; failed=$((failed + 1)); }

# With every shipped scene checked, a baselines folder of a scene no longer
# shipped is named (its baselines would go unchecked without a word).
# A folder's name printed is one line in stored order (an escape as '?').
escape=$(printf 'x\033[31m')
mkdir -p "$B/no_longer_shipped" "$B/$escape" && cp "$cell" "$B/no_longer_shipped/hard.json"
out=$("$sb" check -q --technique hard --baselines "$B" --out "$tmp/out" --cache "$tmp/cache" 2>&1)
printf '%s\n' "$out" | grep -q "ORPHANED    $B/no_longer_shipped: no shipped scene is called 'no_longer_shipped'" &&
    printf '%s\n' "$out" | grep -q "ORPHANED    $B/x?\[31m: " && ! printf '%s' "$out" | grep -q "$(printf '\033')" &&
    echo "ok: a scene no longer shipped: ORPHANED" || { echo "FAILED: no ORPHANED line: $out"; failed=$((failed + 1)); }
rm -r "$B/no_longer_shipped" "$B/$escape"

[ "$failed" = 0 ] && echo "all passed" || echo "$failed failed"
[ "$failed" = 0 ]
