#!/usr/bin/env bash
# Regenerates docs/accuracy/: the error-against-time sweeps that docs/accuracy.md quotes
# (`make accuracy`, about 2 minutes on 2 cores). Each sweep's own output (sweep.csv, sweep.png,
# sweep.txt, with host times) goes to BUILD/accuracy/NAME, untracked: host times vary from
# run to run. docs/accuracy/NAME gets its deterministic part (errors, sample counts, board
# times; scripts/accuracy_tracked.py) and docs/accuracy/model-fingerprint the board model's
# fingerprint (scripts/model-fingerprint.sh), so that a second run changes no tracked file.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=docs/accuracy
command -v gnuplot >/dev/null || bash scripts/setup-deps.sh gnuplot-nox   # sweep.png
run() { # NAME SCENE [ARGS...]
    local name=$1 scene=$2
    shift 2
    local full="$build/accuracy/$name"
    mkdir -p "$full"
    echo "accuracy: $name" >&2
    "$build/cube5" sweep "$scene" --out "$full" "$@" >"$full/sweep.txt"
    python3 scripts/accuracy_tracked.py "$full" "$out/$name"
}
bash scripts/model-fingerprint.sh "$build" > "$out/model-fingerprint"
run default default
run clouds_lake clouds_lake
run marschner_lobb "$out/marschner_lobb.json"
for s in brain_mirrors lobster_tunnel; do
    run "et_$s" "$s" --knob et=0.9,0.95,0.99,1
done
# The gradient study (docs/accuracy.md, "Gradients"): its images in BUILD/accuracy/gradients.
echo "accuracy: gradients" >&2
"$build/grad-study" --size 256 --out "$build/accuracy/gradients" default brain_mirrors \
    "$out/marschner_lobb_lit.json" >"$out/gradients.txt"
