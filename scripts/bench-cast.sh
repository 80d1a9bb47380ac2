#!/usr/bin/env bash
# make bench, caster section: `cube5 cast` (the streaming-model ray caster of Kim & JaJa's Cell
# B.E. paper, sections 5-6) over the peer benchmark's views, per dataset:
#   headline fps (approx, the default mode, 2 threads, shading off/on at distance 3.8637, unshaded at 2.0),
#   Figure 11 producer vs worker ms (ess, approx, approx+refine), Table 2 prefetch off / bricks / cells
#   (on the SSE2 loop, which has all three),
#   Figure 12 load imbalance (from the headline run), Figure 13 speed-up with 1, 2, 4 threads.
# The paper's own figures are printed beside ours as reference lines.
# Needs: BUILD/cube5 built, python3 (stdlib only). Uses ../shared/data/volumes/ when present;
# the phantoms always. Prints tables and writes BUILD/bench-cast.json. About 1-2 minutes.
set -euo pipefail
build=${1:-build}
cube5="$build/cube5"
out="$build/bench-cast.json"
data="$(cd "$(dirname "$0")/.." && pwd)/../shared/data/volumes"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# name|volume|spacing|tf
sets="shell|phantom:shell:256|1,1,1|default
ml|phantom:ml:256|1,1,1|ml"
if [ -d "$data" ]; then
    for f in engine_256x256x128_uint8.raw:1,1,1 fuel_64x64x64_uint8.raw:1,1,1 \
             lobster_301x324x56_uint8.raw:1,1,1.4 vis_male_128x256x256_uint8.raw:1.57774,0.995861,1.00797 \
             CThead_256x256x113_uint8.raw:1,1,1; do
        file=${f%%:*} sp=${f#*:}
        if [ -f "$data/$file" ]; then
            sets="$sets
${file%%_*}|$data/$file|$sp|default"
        else
            echo "bench-cast: $data/$file not found: skipped" >&2
        fi
    done
    echo "bench-cast: CThead's voxel spacing is unknown: cast with 1,1,1" >&2
else
    echo "bench-cast: ../shared/data/volumes/ not found: only the phantoms are cast" >&2
fi

run() { # kind name volume spacing tf [cast options...]
    local kind=$1 name=$2 vol=$3 sp=$4 tf=$5
    shift 5
    echo "$kind|$name|$*|$("$cube5" cast "$vol" --spacing "$sp" --tf "$tf" --json "$@")"
}
while IFS='|' read -r name vol sp tf; do
    for sh in off on; do
        run head "$name" "$vol" "$sp" "$tf" --views 24 --threads 2 --mode approx --shading "$sh" --distance 3.8637
    done
    run head2 "$name" "$vol" "$sp" "$tf" --views 24 --threads 2 --mode approx --shading off --distance 2.0
    for m in ess approx approx+refine; do
        run fig11 "$name" "$vol" "$sp" "$tf" --views 8 --threads 2 --mode "$m" --shading off
    done
    for sh in off on; do
        for p in off bricks cells; do
            run tab2 "$name" "$vol" "$sp" "$tf" --views 8 --threads 2 --mode approx --shading "$sh" --prefetch "$p" \
                --wide off
        done
    done
    for t in 1 2 4; do
        run fig13 "$name" "$vol" "$sp" "$tf" --views 8 --threads "$t" --mode approx --shading off
    done
done <<< "$sets" > "$tmp/runs"

python3 - "$tmp/runs" "$out" <<'PY'
import json, sys
runs = {}
for line in open(sys.argv[1]):
    kind, name, args, text = line.rstrip("\n").split("|", 3)
    o = json.loads(text)
    o.pop("per_view", None)
    o["args"] = args
    runs.setdefault(name, {}).setdefault(kind, []).append(o)
names = list(runs)
res = {"datasets": {}}
print("cube5 cast, 256x256, 24 views, approx, 2 worker threads (producer: auto): fps = 1000 / median ms")
print("%-9s %-11s %11s %10s %11s %10s %11s %10s %4s" % ("dataset", "dims", "d3.86 unsh", "fps", "d3.86 shad",
      "fps", "d2.0 unsh", "fps", "k"))
for n in names:
    r = runs[n]
    h0, h1 = r["head"]; h2 = r["head2"][0]
    d = h0["dataset"]["dims"]
    print("%-9s %-11s %8.1f ms %10.1f %8.1f ms %10.1f %8.1f ms %10.1f %d-%d" % (
        n, "x".join(map(str, d)), h0["ms_median"], h0["fps_median"], h1["ms_median"], h1["fps_median"],
        h2["ms_median"], h2["fps_median"], h0["k_min"], h0["k_max"]))
    res["datasets"][n] = {"dims": d, "spacing": h0["dataset"]["spacing"], "headline": [
        {k: x[k] for k in ("distance_factor", "shading", "ms_median", "ms_mean", "fps_median", "samples_mean",
                          "k_min", "k_max", "load_imbalance_pct_mean", "producer_ms_mean", "worker_ms_mean")}
        for x in (h0, h1, h2)]}
print("  paper (Cell B.E., 3.2 GHz, 8 SPEs; its own datasets, 256x256 image): 9-26 fps")

print("\nFigure 11: producer (PPE role) vs worker (SPE role) ms per frame, 8 views, 2 threads, unshaded, d 3.86")
print("%-9s %-14s %11s %11s %9s %9s %12s" % ("dataset", "mode", "producer ms", "worker ms", "frame ms", "fps",
                                              "samples"))
for n in names:
    res["datasets"][n]["fig11"] = []
    for x in runs[n]["fig11"]:
        print("%-9s %-14s %11.2f %11.2f %9.2f %9.1f %12.0f" % (n, x["mode"], x["producer_ms_mean"],
              x["worker_ms_mean"], x["ms_median"], x["fps_median"], x["samples_mean"]))
        res["datasets"][n]["fig11"].append({k: x[k] for k in ("mode", "producer_ms_mean", "worker_ms_mean",
                                                              "ms_median", "samples_mean")})
print("  (worker ms: mean over the workers of each one's busy time per frame)")

print("\nTable 2: ms per frame by prefetch (off; bricks: the paper's whole next brick; cells: each")
print("sample's lines a batch ahead, the default), approx, 8 views, 2 threads, the SSE2 loop (--wide off)")
print("%-9s %7s %9s %9s %9s %10s %9s" % ("dataset", "shading", "off ms", "bricks ms", "cells ms", "off/bricks",
                                         "off/cells"))
for n in names:
    res["datasets"][n]["table2"] = []
    for i in range(0, len(runs[n]["tab2"]), 3):
        off, bricks, cells = runs[n]["tab2"][i:i + 3]
        print("%-9s %7s %9.2f %9.2f %9.2f %10.2f %9.2f" % (n, "on" if off["shading"] else "off", off["ms_median"],
              bricks["ms_median"], cells["ms_median"], off["ms_median"] / bricks["ms_median"],
              off["ms_median"] / cells["ms_median"]))
        res["datasets"][n]["table2"].append({"shading": off["shading"], "off_ms": off["ms_median"],
                                             "bricks_ms": bricks["ms_median"], "cells_ms": cells["ms_median"]})
for n, a, b in (("foot", 224, 113), ("aneurism", 210, 99), ("engine", 133, 72), ("fuel", 76, 38)):
    print("  paper   %-9s w/o %d ms, with %d ms: %.2f   (Cell B.E. Table 2, reference)" % (n, a, b, a / b))

print("\nFigure 12: load imbalance, % std of the workers' busy time, mean over the 24 headline views")
print("%-9s %10s %10s %10s" % ("dataset", "d3.86 off", "d3.86 on", "d2.0 off"))
for n in names:
    h = res["datasets"][n]["headline"]
    print("%-9s %9.2f%% %9.2f%% %9.2f%%" % ((n,) + tuple(x["load_imbalance_pct_mean"] for x in h)))
print("  paper: 1.7% std on average among 8 SPEs (Figure 12, reference; we have 2 workers)")

print("\nFigure 13: speed-up with worker threads (ms at 1 / ms at N), approx, 8 views, unshaded")
print("%-9s %9s %9s %9s %8s %8s" % ("dataset", "1 thr ms", "2 thr ms", "4 thr ms", "x2", "x4"))
for n in names:
    t1, t2, t4 = runs[n]["fig13"]
    print("%-9s %9.2f %9.2f %9.2f %8.2f %8.2f" % (n, t1["ms_median"], t2["ms_median"], t4["ms_median"],
          t1["ms_median"] / t2["ms_median"], t1["ms_median"] / t4["ms_median"]))
    res["datasets"][n]["fig13"] = {str(x["threads"]): x["ms_median"] for x in (t1, t2, t4)}
print("  (this machine has 2 cores shared with other work; 4 threads oversubscribe it)")
res["paper"] = {"fps_range": [9, 26], "table2_ms_without_with": {"foot": [224, 113], "aneurism": [210, 99],
                "engine": [133, 72], "fuel": [76, 38]}, "fig12_mean_std_pct_8spe": 1.7}
res["runs"] = runs
json.dump(res, open(sys.argv[2], "w"), indent=1)
print("written:", sys.argv[2])
PY
