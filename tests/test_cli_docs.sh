#!/bin/sh
# docs/cli.md is what the program prints of its own command and option
# tables (shadowbench help --markdown), and each command's block in it is
# that command's --help, byte for byte: the page cannot drift from the
# program.
# Usage: test_cli_docs.sh <shadowbench> <docs/cli.md>
set -u
sb=$1 page=$2
tmp=$(mktemp -d) && trap 'rm -rf "$tmp"' EXIT
"$sb" help --markdown > "$tmp/page" || { echo "help --markdown failed"; exit 1; }
if ! cmp -s "$tmp/page" "$page"; then
    echo "$page differs from 'shadowbench help --markdown' (regenerate: build/shadowbench help --markdown > docs/cli.md):"
    diff "$page" "$tmp/page" | head -20
    exit 1
fi
bad=0 count=0
for cmd in $("$sb" --help | sed -n '/^commands:/,/^$/s/^  \([a-z]*\) .*/\1/p'); do
    "$sb" "$cmd" --help > "$tmp/help" || { echo "$cmd --help failed"; bad=1; }
    # the block after "## shadowbench <cmd>", between its ```text and ```
    awk -v want="## shadowbench $cmd" '$0 == want { on = 1; next }
        on && /^```text$/ { inside = 1; next } inside && /^```$/ { exit } inside { print }' "$page" > "$tmp/block"
    if ! cmp -s "$tmp/help" "$tmp/block"; then
        echo "$cmd --help is not its block in $page"
        bad=1
    fi
    count=$((count + 1))
done
echo "$count commands' help in $page"
[ "$bad" = 0 ] && [ "$count" -ge 9 ]
