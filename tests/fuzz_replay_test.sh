#!/usr/bin/env bash
# Regression for the fuzz harnesses (fuzz/, docs/fuzzing.md): every committed corpus input,
# the reproducers among them, through each harness built with this build's toolchain (under
# `make asan` with AddressSanitizer and UndefinedBehaviorSanitizer). Usage: fuzz_replay_test.sh BUILD
set -u
build=${1:-build}
. "$(dirname "$0")/lib.sh"
for n in scene volume tlp driver; do
    count=$(find "fuzz/corpus/$n" -type f | wc -l)
    if out=$(timeout 300 "$build/fuzz/replay-$n" "fuzz/corpus/$n" 2>&1) &&
        grep -q "^replayed $count input(s)$" <<<"$out"; then
        ok "fuzz replay $n: $count input(s)"
    else
        bad "fuzz replay $n" "$(tail -n 20 <<<"$out")"
    fi
done
summary
