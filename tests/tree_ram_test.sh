#!/usr/bin/env bash
# The Cell Tree at real memory fractions (docs/cell-tree.md, "Where the tree lives"): on the
# mirrored stills brain_mirrors and default at 1/512 and 1/4096, 128x128, 5 frames, the board
# as it ships makes at least 25 % fewer fetches than Max Work over frames 1-4, with the tree in
# the DSP's SDRAM (scripts/tree_ram_bench.py --target 25). Four runs of minutes each: a tier of
# `make regress` (scripts/regress.sh), not of `make test`. The judging is shown failing on the
# quick run at a target of 100 %.
# Usage: tree_ram_test.sh BUILD
set -u
build=${1:-build}
. "$(dirname "$0")/lib.sh"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

out=$(python3 scripts/tree_ram_bench.py --cube5 "$build/cube5" --scenes "brain_mirrors default" --cells "8 16" \
    --size 128x128 --frames 5 --rams auto --target 25 --json "$tmp/tr.json" 2>&1)
st=$?
if [ $st -eq 0 ]; then
    ok tree_ram_saves_25_percent_at_512_and_4096_cells
else
    bad tree_ram_saves_25_percent_at_512_and_4096_cells "exit $st" "$out"
fi
rows=$(python3 -c '
import json, sys
rows = json.load(open(sys.argv[1]))
rows = rows["runs"] if isinstance(rows, dict) else rows
print(" ".join("%s/%d/%s/%d" % (r["scene"], r["cells"], "+".join(r["rams"]), len(r["fewer_pct_per_frame"])) for r in rows))
' "$tmp/tr.json" 2>&1)
want="brain_mirrors/512/sdram/4 brain_mirrors/4096/sdram/4 default/512/sdram/4 default/4096/sdram/4"
if [ "$rows" = "$want" ]; then ok tree_ram_runs_in_sdram; else bad tree_ram_runs_in_sdram "got '$rows', want '$want'"; fi
# the judgement fails a run that saves less than the target (a small, quick run at 100 %)
out=$(python3 scripts/tree_ram_bench.py --cube5 "$build/cube5" --scenes brain_mirrors --cells 3 --size 32x32 \
    --frames 3 --rams auto --target 100 2>&1)
st=$?
if [ $st -eq 1 ] && grep -q 'under the target 100.0%' <<<"$out"; then
    ok tree_ram_judgement_can_fail
else
    bad tree_ram_judgement_can_fail "exit $st" "$out"
fi
summary
