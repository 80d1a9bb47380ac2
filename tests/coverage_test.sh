#!/usr/bin/env bash
# Functional coverage of the golden vectors (spec/coverage.toml, scripts/vectors_coverage.py,
# docs/vectors.md "Coverage"): every point is hit or a declared hole; a set that lost
# vectors fails naming the point it no longer reaches; a declared hole that is hit fails
# (the spec must be updated); the rounding probe names each event right; bad input exits 2.
# Usage: coverage_test.sh [BUILD_DIR] (its libc5ref.so replays the vectors; default build)
set -u
cd "$(dirname "$0")/.."
build=${1:-build}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/lib.sh"
cov="python3 scripts/vectors_coverage.py --ref $build/libc5ref.so"

# refused NAME PATTERN CMD...: CMD exits 2 (bad input) and says PATTERN (grep).
refused() {
    local name=$1 pat=$2 st
    shift 2
    "$@" >"$tmp/out" 2>&1
    st=$?
    if [ "$st" -eq 2 ] && grep -q -- "$pat" "$tmp/out"; then ok "$name"; else bad "$name" "exit $st" "$(cat "$tmp/out")"; fi
}

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

# The probe's events on blends built to round a known way: corners 0 and v1 at frac_x
# 2^-9 (64) blend to v1 * 2^-9: half an LSB of UQ8.8 for v1 = 1, a tie kept at 0 (even), one
# and a half for v1 = 3, a tie rounded up to 2 (even); at 2^-10 (32), 1 rounds down, 3 up.
cat >"$tmp/probe.py" <<'EOF'
import sys
sys.path.insert(0, 'scripts')
from vectors_probe import EVENTS, Probe
p = Probe(sys.argv[1])
site = p.sites.index('interp.value')
for fx, v1, value, event in [(64, 1, 0, 'tie_kept'), (64, 3, 2, 'tie_up'), (32, 1, 0, 'down'), (32, 3, 1, 'up'),
                             (128, 1, 1, 'exact')]:
    p.lib.c5ref_probe_reset()
    got = (p.lib.c5ref_interp(fx, 0, 0, 0, v1, 0, 0, 0, 0, 0, 0), p.lib.c5ref_probe_seen(site))
    assert got == (value, EVENTS[event]), (fx, v1, got, value, event)
EOF
if python3 "$tmp/probe.py" "$build/libc5ref.so" >"$tmp/out" 2>&1; then
    ok probe_names_rounding_events
else
    bad probe_names_rounding_events "$(tail -n 3 "$tmp/out")"
fi

# A vector whose output the model does not give: its events would be another computation's.
cp -r vectors/golden "$tmp/wrong"
python3 -c '
import sys
lines = open(sys.argv[1]).read().split("\n")
cols = lines[0].split()
cols[-1] = "%04x" % ((int(cols[-1], 16) + 1) % 65536)
lines[0] = " ".join(cols)
open(sys.argv[2], "w").write("\n".join(lines))' vectors/golden/interp.directed.hex "$tmp/wrong/interp.directed.hex"
refused wrong_output_exits_2 "interp.directed.hex line 1: interp: the model replayed gives other outputs" \
    $cov "$tmp/wrong"

# Every rounding site of the model is declared: the spec without one is refused.
python3 -c '
import re, sys
s = open(sys.argv[1]).read()
print(re.sub(r"\[\[site\]\]\nblock = \"interp\"\nsite = \"interp.value\"\n(?:[^\n]+\n)*", "", s))' spec/coverage.toml >"$tmp/nosite.toml"
refused undeclared_site_exits_2 "rounding site interp.value: the spec does not declare it" \
    $cov vectors/golden --spec "$tmp/nosite.toml"

# Bad input: no vector set; a hole naming no point; no reference library.
refused no_set_exits_2 "no vector set" $cov "$tmp/none"
cp spec/coverage.toml "$tmp/bad.toml"
printf '\n[[hole]]\nblock = "ray_queue"\npoint = "no_such"\nreason = "test"\n' >>"$tmp/bad.toml"
refused unknown_hole_exits_2 "hole ray_queue.no_such is no point" $cov vectors/golden --spec "$tmp/bad.toml"
refused no_reference_exits_2 "none.so: .*make .*none.so builds it" \
    python3 scripts/vectors_coverage.py vectors/golden --ref "$tmp/none.so"
summary
