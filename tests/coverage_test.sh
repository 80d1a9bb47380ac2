#!/usr/bin/env bash
# Functional coverage of the golden vectors (spec/coverage.toml, scripts/vectors_coverage.py,
# docs/vectors.md "Coverage"): every point is hit or a declared hole; a set that lost
# vectors fails naming the point it no longer reaches; a declared hole that is hit fails
# (the spec must be updated); bad input exits 2. Usage: coverage_test.sh
set -u
cd "$(dirname "$0")/.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/lib.sh"
cov="python3 scripts/vectors_coverage.py"

if $cov vectors/golden >"$tmp/out" 2>&1 && grep -q ", 0 missed or hit holes$" "$tmp/out"; then
    ok golden_reaches_every_point_or_hole
else
    bad golden_reaches_every_point_or_hole "$(grep -E 'MISSED|HIT HOLE|coverage of|error' "$tmp/out" | head -n 8)"
fi
if $cov vectors/golden --json >"$tmp/j" && python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))
pts = d["points"]
assert d["bad"] == 0 and d["hit"] == sum(p["status"] == "hit" for p in pts) > 300
assert d["holes"] == sum(p["status"] == "hole" for p in pts) and all(p["reason"] for p in pts if p["status"] == "hole")
assert {"full", "refused_insert", "extension_slot", "overflow", "leap"} <= {p["point"] for p in pts}' "$tmp/j"; then
    ok coverage_json
else
    bad coverage_json "$(head -c 400 "$tmp/j")"
fi

# Coverage drops: the directed queue trace cut before the queue first fills.
cp -r vectors/golden "$tmp/cut"
head -n 100 vectors/golden/ray_queue.directed.hex >"$tmp/cut/ray_queue.directed.hex"
if $cov "$tmp/cut" >"$tmp/out" 2>&1; then
    bad coverage_drop_fails "a set without the full-queue cycles passed"
elif grep -q "^MISSED   ray_queue.full: 0 hits" "$tmp/out" && grep -q "^MISSED   ray_queue.refused_insert" "$tmp/out"; then
    ok coverage_drop_fails
else
    bad coverage_drop_fails "$(head -n 5 "$tmp/out")"
fi

# A hole that the set reaches is an error in the spec.
cp spec/coverage.toml "$tmp/spec.toml"
printf '\n[[hole]]\nblock = "ray_queue"\npoint = "full"\nreason = "test"\n' >>"$tmp/spec.toml"
if $cov vectors/golden --spec "$tmp/spec.toml" >"$tmp/out" 2>&1; then
    bad hit_hole_fails "a hole that is hit passed"
elif grep -q "^HIT HOLE ray_queue.full" "$tmp/out"; then
    ok hit_hole_fails
else
    bad hit_hole_fails "$(head -n 5 "$tmp/out")"
fi

# Bad input: no vector set; a hole naming no point.
$cov "$tmp/none" >"$tmp/out" 2>&1
st=$?
if [ "$st" -eq 2 ] && grep -q "no vector set" "$tmp/out"; then ok no_set_exits_2; else bad no_set_exits_2 "exit $st" "$(cat "$tmp/out")"; fi
printf '\n[[hole]]\nblock = "ray_queue"\npoint = "no_such"\nreason = "test"\n' >"$tmp/bad.toml"
$cov vectors/golden --spec "$tmp/bad.toml" >"$tmp/out" 2>&1
st=$?
if [ "$st" -eq 2 ] && grep -q "hole ray_queue.no_such is no point" "$tmp/out"; then
    ok unknown_hole_exits_2
else
    bad unknown_hole_exits_2 "exit $st" "$(cat "$tmp/out")"
fi
summary
