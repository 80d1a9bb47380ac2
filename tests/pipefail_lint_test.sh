#!/usr/bin/env bash
# Under `set -o pipefail` a pipeline into a reader that may stop early (grep -q, grep -m,
# head) fails at random: the reader exits at its first match, the writer then dies of SIGPIPE
# (status 141) and pipefail reports that instead of the match. `ldd X | grep -q libasan` in
# tests/link_test.sh failed that way in 40 of 100 tries. Capture the output first
# (grep -q PAT <<<"$(cmd)"), or use a reader that reads to the end (sed -n 1p).
# Checks every shell script of the project that sets pipefail, and tests/lib.sh (sourced by
# them).
set -u
cd "$(dirname "$0")/.."
. tests/lib.sh

# A pipe (not ||) into grep with -q/-m/--quiet/--silent/--max-count, or into head.
early='(^|[^|])\|&?[[:space:]]*(grep([[:space:]]+-[^[:space:]|]+)*[[:space:]]+(-[A-Za-z]*[qm][^[:space:]|]*|--quiet|--silent|--max-count)|head)([[:space:]]|$)'

# Prints FILE:LINE:TEXT for each early reader in a pipefail script (nothing when clean).
scan() {
    local f
    for f in "$@"; do
        grep -qE '^[[:space:]]*set[[:space:]]+(-[a-z]*o[[:space:]]+pipefail|-o[[:space:]]+pipefail)' "$f" ||
            [ "$f" = tests/lib.sh ] || continue
        grep -nE "$early" "$f" | grep -vE '^[0-9]+:[[:space:]]*#' | sed "s|^|$f:|"
    done
}

# The check itself must see the pattern: a sample with each form, and one without.
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf '%s\n' 'set -euo pipefail' 'ldd x | grep -q y' 'a |grep -c . | grep -qx 4' 'b | grep -m1 z' \
    'c 2>&1 | head -n 1' 'd |& grep --quiet e' >"$tmp/bad.sh"
printf '%s\n' 'set -uo pipefail' 'grep -q y <<<"$(ldd x)"' 'a || grep -q b f' 'c | sed -n 1p' \
    '# ldd x | grep -q y' >"$tmp/good.sh"
n=$(scan "$tmp/bad.sh" | wc -l)
[ "$n" -eq 5 ] && ok "pipefail lint finds all 5 early readers in a sample" ||
    bad "pipefail lint on a sample" "$n of 5 found: $(scan "$tmp/bad.sh")"
found=$(scan "$tmp/good.sh")
[ -z "$found" ] && ok "pipefail lint passes captured output, ||, sed and comments" ||
    bad "pipefail lint flags a safe form" "$found"

mapfile -t scripts < <(git ls-files '*.sh' 2>/dev/null || find tests scripts -name '*.sh')
found=$(scan "${scripts[@]}")
[ -z "$found" ] && ok "no pipe into grep -q/-m or head under pipefail (${#scripts[@]} shell scripts read)" ||
    bad "pipe into an early reader under pipefail (SIGPIPE makes it fail at random)" "$found"
summary
