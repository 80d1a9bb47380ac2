#!/usr/bin/env bash
# Runs every test suite against the build in $1 (default build/) and ends with the line
# "N passed, N failed". Exit status 0 only when nothing failed.
set -uo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
passed=0 failed=0
log=$(mktemp)
run_suite() {
    local t0=$SECONDS
    "$@" 2>&1 | tee "$log"
    local line
    line=$(grep '^SUMMARY ' "$log" | tail -n 1)
    if [ -z "$line" ]; then
        echo "FAIL suite $* ended without a summary (crashed?)"
        failed=$((failed + 1))
        return
    fi
    local p f
    p=$(sed -E 's/.*passed=([0-9]+).*/\1/' <<<"$line")
    f=$(sed -E 's/.*failed=([0-9]+).*/\1/' <<<"$line")
    passed=$((passed + p)) failed=$((failed + f))
    echo "suite ${*:1:2}: $p passed, $f failed, $((SECONDS - t0)) s"
}
run_suite "$build/tests/unit"
run_suite "$build/tests/cast-nosimd" cast   # the caster on its scalar definition (no SSE2)
run_suite bash tests/cli_test.sh "$build"
run_suite bash tests/mpi_test.sh "$build"
run_suite bash tests/scene_limits_test.sh "$build"
run_suite bash tests/prefetch_test.sh "$build"
run_suite bash tests/sched_family_test.sh "$build"
run_suite bash tests/layouts_test.sh
run_suite bash tests/regmap_test.sh
run_suite bash tests/vectors_test.sh "$build"
run_suite bash tests/coverage_test.sh "$build"
run_suite bash tests/fingerprint_test.sh "$build"
run_suite bash tests/fpga_test.sh "$build"
run_suite bash tests/vcd_test.sh "$build"
run_suite bash tests/write_fault_test.sh "$build"
run_suite bash tests/live_test.sh "$build"
run_suite bash tests/link_test.sh "$build"
run_suite bash tests/pipefail_lint_test.sh
run_suite bash tests/man_test.sh "$build"
run_suite bash tests/install_test.sh "$build"
run_suite bash tests/fuzz_replay_test.sh "$build"
run_suite bash tests/volume_inputs_test.sh "$build"
run_suite bash tests/deps_test.sh "$build"
run_suite bash tests/readme_test.sh "$build"
rm -f "$log"
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
