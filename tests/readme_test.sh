#!/usr/bin/env bash
# A clone alone runs the README: every command-line example of README.md ("## The command
# line") runs, in order, in a temporary folder that holds only the project's tracked files
# and BUILD (as build/), and exits 0 (or the status its comment states: "exits N"). An example
# marked "data: NAME" reads a real volume from data/: it is not run, and the README must say
# where that file comes from (a download line ending in its name). No example may need
# ../shared/. Long examples (also behind VAR=value) run small: render, compare, schedule and sweep get --size 64x64
# unless they give a size, schedule --frames 2 unless it gives frames, cast --views 2 --size 64.
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
    # small sizes for the long ones (the words after build/cube5, past any VAR=value before it)
    if [[ $cmd =~ ^([A-Z0-9_]+=[^\ ]*\ )*build/cube5\ (render|compare|schedule|sweep)\  ]]; then
        [[ $cmd == *--size* ]] || cmd+=" --size 64x64"
        [[ ${BASH_REMATCH[2]} == schedule && $cmd != *--frames* ]] && cmd+=" --frames 2"
    elif [[ $cmd =~ ^([A-Z0-9_]+=[^\ ]*\ )*build/cube5\ cast\  ]]; then
        [[ $cmd == *--views* ]] || cmd+=" --views 2"
        [[ $cmd == *--size* ]] || cmd+=" --size 64"
    fi
    want=0
    [[ $comment =~ exits\ ([0-9]+) ]] && want=${BASH_REMATCH[1]}
    (cd "$tmp/clone" && sh -c "$cmd") >"$tmp/out" 2>&1
    st=$?
    if [ "$st" -eq "$want" ]; then
        ok "$name"
    else
        bad "$name" "exit $st, README says $want: $cmd" "$(tail -n 5 "$tmp/out")"
    fi
done <<<"$examples"
summary
