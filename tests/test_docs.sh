#!/bin/sh
# Protects the front door (docs/README.md): every generated table of the
# README and docs/ is what tools/readme-tables prints from the committed
# results (tools/update-docs --check; a table with one number changed must
# fail it); the README is at most 250 lines; no prose carries a commit id,
# a -dirty tag or a date; every link into docs/ and every picture the
# README and docs name exists; code comments cite docs/, not a design file
# outside the repository.
# Usage: test_docs.sh <source root>
set -u
root=$1
cd "$root" || exit 1
status=0
fail() { echo "FAILED: $*"; status=1; }

tools/update-docs --check || fail "a generated table differs from the committed results"

# The check can fail: one number of a generated table changed.
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
awk '/^<!-- generated: /{g=1} g && /^\| `.*[0-9]\.[0-9][0-9][0-9]/ && !done {sub(/[0-9]\.[0-9][0-9][0-9]/, "9.999"); done=1} {print}' README.md >"$tmp/README.md"
cmp -s README.md "$tmp/README.md" && fail "the README has no generated table with a number to change"
tools/update-docs --check "$tmp/README.md" 2>/dev/null && fail "a changed number in a generated table passed the check"

lines=$(wc -l <README.md)
[ "$lines" -le 250 ] || fail "README.md is $lines lines (at most 250)"

# Commit ids (7 to 40 hex digits with a digit and a letter), -dirty, dates.
hits=$(grep -nHoE '\b[0-9a-f]{7,40}\b' README.md docs/*.md | grep -E ':[0-9a-f]*[0-9][0-9a-f]*$' |
       grep -E ':[0-9]*[a-f][0-9a-f]*$' | grep -vE ':#?[0-9a-fA-F]{6}$' | head -5)
[ -z "$hits" ] || fail "commit ids in prose: $hits"
hits=$(grep -nHE -- '-dirty|\b20[0-9]{2}-[01][0-9]-[0-3][0-9]\b' README.md docs/*.md | head -5)
[ -z "$hits" ] || fail "dates or -dirty in prose: $hits"

# Links and pictures: relative targets exist (from the file's folder).
for f in README.md docs/*.md; do
  d=$(dirname "$f")
  for target in $(grep -oE '\]\([^)#[:space:]]+|src="[^"]+"' "$f" | sed -E 's/^\]\(//; s/^src="//; s/"$//' |
                  grep -vE '^(https?:|mailto:)'); do
    [ -e "$d/$target" ] || fail "$f links to $target, which does not exist"
  done
done

hits=$(grep -rnE 'DESIGN\.md' harness techniques shaders tests tools CMakeLists.txt 2>/dev/null |
       grep -v '^tests/test_docs.sh' | head -5)
[ -z "$hits" ] || fail "comments cite DESIGN.md, which is not in the repository: $hits"
exit $status
