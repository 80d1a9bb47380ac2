#!/usr/bin/env bash
# man/cube5.1's command sections, between its BEGIN and END lines, as `cube5 help --man`
# prints them from the commands' option tables. Usage: man-commands.sh CUBE5 PAGE [--check]
# writes PAGE (make man); with --check it only says whether PAGE is up to date (exit 1 if not).
set -euo pipefail
cube5=$1 page=$2 check=${3:-}
made=$(mktemp "${page}.XXXXXX")
trap 'rm -f "$made"' EXIT
commands=$("$cube5" help --man)
awk -v commands="$commands" '
    /^\.\\" BEGIN:/ {print; print commands; skip = 1; next}
    /^\.\\" END$/ {skip = 0}
    !skip' "$page" >"$made"
if [ "$check" = --check ]; then
    if ! cmp -s "$made" "$page"; then
        echo "$page differs from the option tables ('make man' writes it):" >&2
        diff "$page" "$made" >"$made.diff" || true
        sed -n 1,20p "$made.diff" >&2
        rm -f "$made.diff"
        exit 1
    fi
    exit 0
fi
chmod 644 "$made"
mv "$made" "$page"
