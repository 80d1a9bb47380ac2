#!/usr/bin/env bash
# Runs every test suite against the build in $1 (default build/) and ends with the line
# "N passed, N failed". Exit status 0 only when nothing failed.
# The suites are independent (each works in its own temporary folder), so C5_TEST_JOBS of them
# (default: the machine's cores, at most 4) run at once; each suite's output is printed whole
# when it ends, followed by "suite NAME: N passed, N failed, S s".
set -uo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
jobs=${C5_TEST_JOBS:-$(nproc 2>/dev/null || echo 1)}
[[ $jobs =~ ^[1-9][0-9]*$ ]] || { echo "tests/run.sh: C5_TEST_JOBS must be a positive integer" >&2; exit 2; }
[ "$jobs" -gt 4 ] && jobs=4
logs=$(mktemp -d)
trap 'rm -rf "$logs"' EXIT
# The grids' block-range cache (common/block_range.h) in the run's own folder: a test run
# leaves nothing in the user's cache.
export C5_CACHE_DIR=$logs/cache

# Longest first, so the last suite to start is a short one.
suites=(
    "bash tests/cli_test.sh $build"
    "bash tests/readme_test.sh $build"
    "$build/tests/unit"
    "bash tests/deps_test.sh $build"
    "bash tests/mpi_test.sh $build"
    "bash tests/boards_test.sh $build"
    "bash tests/vcd_test.sh $build"
    "bash tests/live_test.sh $build"
    "bash tests/link_test.sh $build"
    "bash tests/fpga_test.sh $build"
    "bash tests/write_fault_test.sh $build"
    "bash tests/outputs_fuzz_test.sh $build"
    "bash tests/options_test.sh $build"
    "bash tests/sched_family_test.sh $build"
    "bash tests/scene_limits_test.sh $build"
    "bash tests/layouts_test.sh"
    "bash tests/regmap_test.sh"
    "bash tests/vectors_test.sh $build"
    "bash tests/coverage_test.sh $build"
    "bash tests/volume_inputs_test.sh $build"
    "bash tests/man_test.sh $build"
    "bash tests/blocks_index_test.sh"
    "bash tests/fingerprint_test.sh $build"
    "bash tests/install_test.sh $build"
    "$build/tests/cast-nosimd cast"   # the caster on its scalar definition (no SSE2)
    "bash tests/prefetch_test.sh $build"
    "bash tests/pipefail_lint_test.sh"
    "bash tests/fuzz_replay_test.sh $build"
)

passed=0 failed=0
# report I: print suite I's output and its line, add its counts.
report() {
    local i=$1 words line p f
    read -ra words <<<"${suites[$i]}"
    cat "$logs/$i.log"
    line=$(grep '^SUMMARY ' "$logs/$i.log" | tail -n 1)
    if [ -z "$line" ]; then
        echo "FAIL suite ${suites[$i]} ended without a summary (crashed?)"
        failed=$((failed + 1))
        return
    fi
    p=$(sed -E 's/.*passed=([0-9]+).*/\1/' <<<"$line")
    f=$(sed -E 's/.*failed=([0-9]+).*/\1/' <<<"$line")
    passed=$((passed + p)) failed=$((failed + f))
    echo "suite ${words[*]:0:2}: $p passed, $f failed, $(cat "$logs/$i.secs") s"
}

running=0 next=0 shown=()
while [ "$next" -lt "${#suites[@]}" ] || [ "$running" -gt 0 ]; do
    while [ "$running" -lt "$jobs" ] && [ "$next" -lt "${#suites[@]}" ]; do
        (
            t0=$SECONDS
            # shellcheck disable=SC2086 # a suite is a command and its words
            ${suites[$next]} >"$logs/$next.log" 2>&1 </dev/null
            echo $((SECONDS - t0)) >"$logs/$next.secs"
        ) &
        running=$((running + 1)) next=$((next + 1))
    done
    wait -n
    running=$((running - 1))
    for ((i = 0; i < next; i++)); do
        if [ -f "$logs/$i.secs" ] && [ -z "${shown[$i]:-}" ]; then
            shown[i]=1
            report "$i"
        fi
    done
done
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
