#!/usr/bin/env bash
# A clone alone runs the README: every command-line example of README.md ("## The command
# line") runs, in order, in a temporary folder that holds only the project's tracked files
# and BUILD (as build/), and exits 0 (or the status its comment states: "exits N"). An example
# marked "data: NAME" reads a real volume from data/: it is not run, and the README must say
# where that file comes from (a download line ending in its name). No example may need
# ../shared/. Each runs as written and within 20 s (40 s here: make test runs two suites at
# once, C5_README_LIMIT_S) unless its comment gives its time ("N s", "minutes").
# Usage: readme_test.sh BUILD
set -u
build=${1:-build}
. "$(dirname "$0")/lib.sh"
root=$PWD
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# The clone: tracked files only (no out/, no data/, no ../shared beside it).
mkdir -p "$tmp/clone"
git ls-files -z | tar --null --ignore-failed-read -T - -cf - 2>/dev/null | tar -xf - -C "$tmp/clone"
ln -s "$root/$build" "$tmp/clone/build"

examples=$(awk '/^## The command line/ { on = 1; next } /^## / { on = 0 }
                on && /^```/ { inblock = !inblock; if (!inblock) done = 1; next }
                on && inblock && !done && NF' README.md)
[ -n "$examples" ] || { bad readme_examples_found "no sh block under '## The command line' in README.md"; summary; }

# README promises 20 s on the 2-core VM; make test runs two suites at once, so twice that here.
limit=${C5_README_LIMIT_S:-40}
n=0
while IFS= read -r line; do
    n=$((n + 1))
    name="readme_example_$n"
    cmd=${line%% #*}
    comment=""; [ "$cmd" != "$line" ] && comment=${line#* #}
    if [[ $line == *../shared* ]]; then
        bad "$name" "needs ../shared/, which a clone does not have: $line"
        continue
    fi
    if [[ $comment =~ data:\ *([A-Za-z_]+) ]]; then
        file=$(grep -o 'data/[^ ]*' <<<"$cmd" | head -n 1)
        if [ -n "$file" ] && grep -Eq "^curl .*/${file#data/}( |$)" README.md; then
            ok "$name (needs ${BASH_REMATCH[1]}: not run)"
        else
            bad "$name" "marked as needing data, but README.md has no download line for '${file:-its file}': $line"
        fi
        continue
    fi
    if [[ $cmd == *data/* ]]; then
        bad "$name" "reads data/ without a 'data:' mark: $line"
        continue
    fi
    want=0
    [[ $comment =~ exits\ ([0-9]+) ]] && want=${BASH_REMATCH[1]}
    t0=$(date +%s%N)
    (cd "$tmp/clone" && sh -c "$cmd") >"$tmp/out" 2>&1
    st=$?
    secs=$((($(date +%s%N) - t0) / 1000000000))
    if [ "$st" -ne "$want" ]; then
        bad "$name" "exit $st, README says $want: $cmd" "$(tail -n 5 "$tmp/out")"
    elif [ "$secs" -gt "$limit" ] && ! [[ $comment =~ [0-9]+\ s|minute ]]; then
        bad "$name" "took $secs s (README promises under 20 s unless the comment gives the time): $cmd"
    else
        ok "$name (${secs} s)"
    fi
done <<<"$examples"
summary
