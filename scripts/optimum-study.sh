#!/usr/bin/env bash
# The optimum of every 8- and 27-cell Cell Tree of the built-in scenes at 256x256: each
# scene's camera path (frame 0 is the still view; brain_mirrors has 8 frames, the others 1),
# split into 2^3 and 3^3 cells, through `cube5 schedule SCENE --cells C --size 256x256 --json`.
# One row per tree: scene, cells, frame, nodes, the proven lower bound, the optimum (or the
# best known schedule, as "<=N"), the interval's width (best known - bound) / bound in %,
# and the host seconds of the offline analysis (exact_host_s). Extra arguments go to
# `cube5 schedule` (say --exact-states 2000000). docs/cell-tree.md, "Bounds".
#   usage: scripts/optimum-study.sh [BUILD] [-- cube5 schedule options]
set -euo pipefail
build=build
if [ $# -gt 0 ] && [ "$1" != "--" ]; then
    build=$1
    shift
fi
[ "${1:-}" = "--" ] && shift
cube5="$build/cube5"
[ -x "$cube5" ] || { echo "optimum-study: $cube5 not found (make $cube5)" >&2; exit 2; }
printf '%-15s %5s %5s %6s %6s %8s %7s %8s\n' scene cells frame nodes bound optimum width% host_s
for scene in $("$cube5" scenes | awk '{print $1}'); do
    for c in 2 3; do
        "$cube5" schedule "$scene" --cells "$c" --size 256x256 --local-walk 500 --json "$@" |
            jq -r --arg s "$scene" --arg c "$((c * c * c))" '.frames | to_entries[] | .key as $f | .value |
                [$s, $c, $f, .nodes, .lower_bound,
                 (if .optimum != null then .optimum else "<=\(.best_known)" end),
                 ((.best_known - .lower_bound) * 1000 / .lower_bound | round / 10),
                 (.exact_host_s * 100 | round / 100)] | @tsv' |
            awk -F'\t' '{printf "%-15s %5s %5s %6s %6s %8s %7.1f %8.2f\n", $1, $2, $3, $4, $5, $6, $7, $8}'
    done
done
