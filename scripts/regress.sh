#!/usr/bin/env bash
# The full regression tier (`make regress`; `make test` is the fast tier): docs/vectors.md,
# "Regression tiers". Runs, and sums up in one table:
#   golden-c      the model regenerates vectors/golden/ bit for bit (tests/vectors_test.sh)
#   golden-vhdl   every VHDL testbench on every golden vector file (tests/fpga_test.sh)
#   coverage      the golden set against spec/coverage.toml (tests/coverage_test.sh)
#   random-vhdl   per seed S: `cube5 vectors --scene none --seed S` (fresh directed and
#                 random cases) replayed by every VHDL testbench, and the points it covers
#   live          per seed S: every block's VHDL against the C model running beside it (VHPIDIRECT,
#                 tests/live_test.sh), CYCLES cycles
#   tree-ram      the Cell Tree at 1/512 and 1/4096 saves at least 25 % of Max Work's fetches
#                 (tests/tree_ram_test.sh; docs/cell-tree.md, "Where the tree lives")
# Every run is reproducible from its seed alone: `scripts/regress.sh BUILD` with SEEDS="S"
# repeats seed S. A failure is printed with its tier and seed above the sub-suite's own
# FAIL lines, which name the block (testbench), the vector (line) and the field (column).
# Usage: regress.sh [BUILD]; environment SEEDS (default "1 2 3 4 5 6 7 8"), COUNT (vectors
# per block and seed, default 1024), CYCLES (live cycles per seed, default 5000).
set -u
cd "$(dirname "$0")/.."
build=${1:-build}
SEEDS=${SEEDS:-1 2 3 4 5 6 7 8}
COUNT=${COUNT:-1024}
CYCLES=${CYCLES:-5000}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
rows=()
covs=()
fails=0

# tier NAME SEED CMD...: runs a sub-suite, keeps its verdict for the table.
tier() {
    local name=$1 seed=$2 t0 p f line
    shift 2
    t0=$(date +%s)
    "$@" >"$tmp/log" 2>&1
    line=$(grep '^SUMMARY ' "$tmp/log" | tail -n 1)
    p=$(sed -E 's/.*passed=([0-9]+).*/\1/' <<<"${line:-passed=0}")
    f=$(sed -E 's/.*failed=([0-9]+).*/\1/' <<<"${line:-failed=1}")
    [ -n "$line" ] || f=1
    if [ "$f" -ne 0 ]; then
        fails=$((fails + 1))
        echo "FAIL tier $name, seed $seed:"
        grep -E '^FAIL|^    ' "$tmp/log" | head -n 20
        [ -n "$line" ] || tail -n 5 "$tmp/log"
    fi
    rows+=("$(printf '| %-12s | %4s | %6s | %6s | %5ss |' "$name" "$seed" "$p" "$f" "$(($(date +%s) - t0))")")
}

tier golden-c - bash tests/vectors_test.sh "$build"
tier golden-vhdl - bash tests/fpga_test.sh "$build"
tier coverage - bash tests/coverage_test.sh "$build"
tier tree-ram - bash tests/tree_ram_test.sh "$build"
for s in $SEEDS; do
    d="$tmp/vec$s"
    if "$build/cube5" vectors --out "$d" --scene none --seed "$s" --count "$COUNT" >"$tmp/gen" 2>&1; then
        tier random-vhdl "$s" env C5_VECTORS="$d" bash tests/fpga_test.sh "$build"
        # What the seed's set reaches (reported, not judged: a set without scenes misses the
        # points only scene traces reach, and hits some of the golden set's holes).
        python3 scripts/vectors_coverage.py "$d" --ref "$build/libc5ref.so" --json >"$tmp/cov" 2>"$tmp/cov.err"
        [ $? -le 1 ] && covs+=("$(python3 -c 'import json, sys; d = json.load(open(sys.argv[1]))
print("seed %s: %d of %d points hit" % (sys.argv[2], d["hit"], len(d["points"])))' "$tmp/cov" "$s")") ||
            covs+=("seed $s: coverage failed: $(tail -n 1 "$tmp/cov.err")")
    else
        fails=$((fails + 1))
        echo "FAIL tier random-vhdl, seed $s: cube5 vectors failed"
        cat "$tmp/gen"
        rows+=("| random-vhdl  | $s | 0 | 1 | - |")
    fi
    rm -rf "$d"
    tier live "$s" bash tests/live_test.sh "$build" "$s" "$CYCLES"
done

echo
echo "| tier         | seed | passed | failed |  time |"
echo "|--------------|------|--------|--------|-------|"
printf '%s\n' "${rows[@]}"
echo
echo "coverage of the random sets (scripts/vectors_coverage.py):"
printf '  %s\n' "${covs[@]}"
echo "regress: $((${#rows[@]} - fails)) runs passed, $fails failed (seeds: $SEEDS)"
[ "$fails" -eq 0 ]
