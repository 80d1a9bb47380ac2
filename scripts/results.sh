#!/usr/bin/env bash
# make results: the paper's Section 4 (Frank & Kaufman) reproduced on the three built-in
# scenes with `cube5 schedule`. Writes docs/results/: the raw JSON of every run (without host
# seconds; with them in BUILD/results/raw), the tables
# (README.md) and the plots (fig6_fetches.png, fig7_tree_vs_rays.png, fig10_tree_sizes.png,
# anim_fetches.png). Installs gnuplot-nox when missing (scripts/setup-deps.sh).
#   Figure 6:  fetches with Max Work, with the Cell Tree schedule and the lower bound, memory
#              1/8 and 1/27 (cells 2 and 3), 256x256, the still view rendered twice so that
#              frame 1 follows frame 0's tree (--still --frames 2).
#   Figure 7:  tree size against rays, every run of Figure 6 and the animation.
#   Figure 10: tree size of brain_mirrors at 100x100, 256x256 and 512x512.
#   Animation: brain_mirrors' 8-frame camera path, frame i's tree scheduling frame i+1.
# The Cell Tree runs follow the paper's rule on the paper's board (--split paper --stale-check
# off): this is the paper's evaluation; cube5 schedule's defaults, the window rule and the
# certificate, are measured in docs/cell-tree.md.
set -euo pipefail
BUILD=${1:-build}
CUBE5="$BUILD/cube5"
OUT=docs/results
RAW="$OUT/raw"
command -v gnuplot >/dev/null || bash scripts/setup-deps.sh gnuplot-nox
mkdir -p "$RAW"
SCENES="brain_mirrors clouds_lake lobster_tunnel"

# The tracked raw JSON leaves out the host seconds (keys ending in host_s), so that running
# make results again on the same model changes no tracked file; the whole output, host times
# included, stays in $HOST_RAW (untracked).
HOST_RAW="$BUILD/results/raw"
mkdir -p "$HOST_RAW"
run() { # name, args...
  local name=$1; shift
  echo "results: cube5 schedule $*" >&2
  "$CUBE5" schedule "$@" --json > "$HOST_RAW/$name.json"
  python3 - "$HOST_RAW/$name.json" > "$RAW/$name.json.tmp" <<'PY'
import json, sys
def strip(o):
    if isinstance(o, dict):
        return {k: strip(v) for k, v in o.items() if not k.endswith("host_s")}
    if isinstance(o, list):
        return [strip(v) for v in o]
    return o
json.dump(strip(json.load(open(sys.argv[1]))), sys.stdout, separators=(",", ":"))
print()
PY
  mv "$RAW/$name.json.tmp" "$RAW/$name.json"
}

for s in $SCENES; do
  for c in 2 3; do
    run "fig6_${s}_c$c" "$s" --cells "$c" --still --frames 2 --size 256x256 --split paper --stale-check off
    run "fig6rollout_${s}_c$c" "$s" --cells "$c" --still --frames 2 --size 256x256 --split rollout --exact-states 0
  done
done
for sz in 100 256 512; do
  for c in 2 3; do
    run "fig10_brain_mirrors_${sz}_c$c" brain_mirrors --cells "$c" --still --frames 1 --size "${sz}x${sz}" --exact-states 0 --split paper --stale-check off
  done
done
for c in 2 3; do
  run "anim_brain_mirrors_c$c" brain_mirrors --cells "$c" --size 256x256 --exact-states 0 --split paper --stale-check off
done

# The model these figures came from (tests/fingerprint_test.sh compares it with the model's).
bash scripts/model-fingerprint.sh "$BUILD" > "$OUT/model-fingerprint"
python3 scripts/results_tables.py "$RAW" "$OUT"
(cd "$OUT" && gnuplot "$OLDPWD/scripts/results_plots.gp")
echo "results: wrote $OUT/README.md and the plots in $OUT" >&2
