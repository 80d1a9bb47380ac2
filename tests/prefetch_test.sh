#!/usr/bin/env bash
# The caster's prefetches are in the compiled workers. A prefetch changes no bit, so no image
# test can see it go; and GCC 12 deletes the calls of a function whose body is only
# __builtin_prefetch (it deems it free of side effects), which is how the brick prefetch went
# missing unnoticed (cref/cast/cast_worker.c). Per helper, counts the prefetch instructions
# that the object file's line table puts inside its body. Usage: prefetch_test.sh BUILD
set -u
build=${1:-build}
src=cref/cast/cast_worker.c
obj=$build/cref/cast/cast_worker.o
. "$(dirname "$0")/lib.sh"

if [ ! -f "$obj" ]; then
    bad prefetch_object "no $obj: build first"
    summary
fi
# the source line of each prefetch instruction
lines=$(objdump -dl --no-show-raw-insn "$obj" |
    awk '/cast_worker\.c:[0-9]+/ { match($0, /cast_worker\.c:[0-9]+/); ln = substr($0, RSTART + 14, RLENGTH - 14) }
         /\tprefetch/ { print ln }')
for helper in prefetch_brick prefetch_cell_values prefetch_cell_codes; do
    first=$(grep -n "void $helper(" "$src" | head -n 1 | cut -d: -f1)
    last=$(awk -v f="$first" 'NR > f && /^}/ { print NR; exit }' "$src")
    if [ -z "$first" ] || [ -z "$last" ]; then
        bad "${helper}_found" "no function $helper in $src"
        continue
    fi
    n=$(awk -v a="$first" -v b="$last" '$1 >= a && $1 <= b' <<<"$lines" | wc -l)
    if [ "$n" -ge 2 ]; then ok "${helper}_compiled"; else bad "${helper}_compiled" "$n prefetch instructions from $src:$first-$last in $obj"; fi
done
summary
