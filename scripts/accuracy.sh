#!/usr/bin/env bash
# Regenerates docs/accuracy/: the error-against-time sweeps that docs/accuracy.md quotes
# (`make accuracy`, about 2 minutes on 2 cores). Each folder gets the sweep's sweep.csv,
# sweep.png and its text table sweep.txt. Host times vary from run to run; errors, sample
# counts and board times do not.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=docs/accuracy
command -v gnuplot >/dev/null || bash scripts/setup-deps.sh gnuplot-nox   # sweep.png
run() { # NAME SCENE [ARGS...]
    local name=$1 scene=$2
    shift 2
    mkdir -p "$out/$name"
    echo "accuracy: $name" >&2
    "$build/cube5" sweep "$scene" --out "$out/$name" --force "$@" >"$out/$name/sweep.txt"
}
run default default
run clouds_lake clouds_lake
run marschner_lobb "$out/marschner_lobb.json"
for s in brain_mirrors lobster_tunnel; do
    run "et_$s" "$s" --knob et=0.9,0.95,0.99,1
done
