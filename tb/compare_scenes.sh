#!/usr/bin/env bash
# The testbench of the board model against cref: every built-in scene, split into 1, 8 and
# 27 cells as in the paper, through `cube5 compare`. Prints one table (image error and the
# cost of each renderer) and writes BUILD/tb.json. Usage: tb/compare_scenes.sh [BUILD [WxH]]
set -euo pipefail
build=${1:-build}
size=${2:-256x256}
cube5="$build/cube5"
out="$build/tb.json"
for scene in $("$cube5" scenes | awk '{print $1}'); do
    for cells in 1 2 3; do
        echo "$scene|$((cells * cells * cells))|$("$cube5" compare "$scene" --size "$size" --cells "$cells" --json)"
    done
done | python3 -c '
import json, sys
rows = []
for line in sys.stdin:
    scene, cells, text = line.rstrip("\n").split("|", 2)
    o = json.loads(text)
    rows.append({"scene": scene, "cells": int(cells)} | {k: o[k] for k in (
        "psnr_db", "rmse", "max_abs_err", "cref_wall_s", "model_wall_s", "board_cycles", "board_s", "fetches")})
print("%-16s %5s %8s %10s %9s %8s %8s %12s %9s %7s" % ("scene", "cells", "PSNR dB", "RMSE", "max err", "cref s",
      "model s", "board cycles", "board s", "fetches"))
for r in rows:
    print("%-16s %5d %8.2f %10.2e %9.4f %8.3f %8.3f %12d %9.4f %7d" % (r["scene"], r["cells"], r["psnr_db"],
          r["rmse"], r["max_abs_err"], r["cref_wall_s"], r["model_wall_s"], r["board_cycles"], r["board_s"],
          r["fetches"]))
json.dump(rows, open(sys.argv[1], "w"), indent=1)
print("written:", sys.argv[1])
' "$out"
