#!/usr/bin/env bash
# make bench-peer: our caster (`cube5 cast`) against the peer benchmark, VTK's
# vtkFixedPointVolumeRayCastMapper (../shared/bench/peer-vtk/render_vtk.py, called, not copied),
# on the same voxels, cameras, TF and 256x256 image, 2 threads, 24 views, shading off and on,
# eye distance 3.8637 and 2.0 bounding-sphere radii. Per dataset and distance, ROUNDS interleaved
# rounds (VTK, then ours, so both share the same time window on a shared machine); reported:
# median over rounds of VTK's median ms/frame and of ours, the ratio VTK/ours (>1: we are
# faster), whether we beat 26 fps (the paper's Cell B.E. top figure), and the view-0 image
# difference (PSNR, mean |diff| on 0..255). Prints a table and writes BUILD/bench-peer.json.
# Needs: BUILD/cube5; ../shared/bench/peer-vtk beside the project checkout; /usr/bin/python3 with
# vtk and numpy and xvfb-run (apt-get installs python3-vtk9 python3-numpy xvfb xauth if missing).
# Uses ../shared/data/volumes/ when present; the phantoms always.
# Env: ROUNDS (default 3), ONLY (regex on dataset names: shell ml engine fuel lobster vis CThead),
#      DISTS (default "3.8637 2.0"). VTK is run with --repeats 1 and no extra passes for
#      contention (--max-extra-passes 0): the interleaved rounds take care of the noise.
set -euo pipefail
build=${1:-build}
cube5="$build/cube5"
out="$build/bench-peer.json"
rounds=${ROUNDS:-3}
only=${ONLY:-.}
dists=${DISTS:-3.8637 2.0}
shared="$(cd "$(dirname "$0")/../.." && pwd)/shared"
peer="$shared/bench/peer-vtk"
data="$shared/data/volumes"
py=/usr/bin/python3

if [ ! -f "$peer/render_vtk.py" ]; then
    echo "bench-peer: the peer benchmark is not there: $peer/render_vtk.py (../shared/bench/peer-vtk beside" \
         "the project checkout) is needed" >&2
    exit 1
fi
if ! "$py" -c 'import vtk, numpy' 2>/dev/null || ! command -v xvfb-run >/dev/null || ! command -v xauth >/dev/null; then
    echo "bench-peer: installing python3-vtk9 python3-numpy xvfb xauth" >&2
    sudo=""
    [ "$(id -u)" -ne 0 ] && sudo=sudo
    $sudo apt-get update -q
    $sudo apt-get install -y -q python3-vtk9 python3-numpy xvfb xauth
fi

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pngdir="$build/bench-peer-png"
mkdir -p "$pngdir"

# name|raw file|spacing (comma)|tf
sets=""
for ph in shell:default ml:ml; do
    n=${ph%%:*}
    [[ $n =~ $only ]] || continue
    raw="$tmp/${n}_256x256x256_uint8.raw"
    "$cube5" cast "phantom:$n:256" --views 1 --save-raw "$raw" > /dev/null
    sets+="$n|$raw|1,1,1|${ph#*:}"$'\n'
done
if [ -d "$data" ]; then
    for f in engine_256x256x128_uint8.raw:1,1,1 fuel_64x64x64_uint8.raw:1,1,1 \
             lobster_301x324x56_uint8.raw:1,1,1.4 vis_male_128x256x256_uint8.raw:1.57774,0.995861,1.00797 \
             CThead_256x256x113_uint8.raw:1,1,1; do
        file=${f%%:*} sp=${f#*:} n=${file%%_*}
        [[ $n =~ $only ]] || continue
        if [ -f "$data/$file" ]; then
            sets+="$n|$data/$file|$sp|default"$'\n'
        else
            echo "bench-peer: $data/$file not found: skipped" >&2
        fi
    done
    [[ CThead =~ $only ]] && echo "bench-peer: CThead's voxel spacing is unknown: 1,1,1 for both" >&2
else
    echo "bench-peer: $data not found: only the phantoms are compared" >&2
fi
[ -n "$sets" ] || { echo "bench-peer: no dataset matches ONLY=$only" >&2; exit 1; }

while IFS='|' read -r name raw sp tf; do
    [ -n "$name" ] || continue
    dims=$(basename "$raw" | sed -E 's/.*_([0-9]+)x([0-9]+)x([0-9]+)_uint8\.raw$/\1 \2 \3/')
    for d in $dists; do
        dir="$pngdir/${name}_d$d"
        mkdir -p "$dir"
        for r in $(seq 1 "$rounds"); do
            echo "bench-peer: $name d=$d round $r/$rounds" >&2
            # shellcheck disable=SC2086
            if ! "$py" "$peer/render_vtk.py" --raw "$raw" --dims $dims --spacing ${sp//,/ } --name "$name" \
                    --tf "$tf" --threads 2 --shading off on --repeats 1 --max-extra-passes 0 --views 24 \
                    --size 256 --distance-factor "$d" --save-views 1 --out-dir "$dir" \
                    --json "$tmp/vtk.json" > "$tmp/vtk.log" 2>&1; then
                tail -20 "$tmp/vtk.log" >&2
                echo "bench-peer: render_vtk.py failed on $name" >&2
                exit 1
            fi
            echo "vtk|$name|$d|$r|$dir|$("$py" -c 'import json,sys; o=json.load(open(sys.argv[1]))
print(json.dumps({"configs": [{k: c[k] for k in ("threads", "shading", "median_ms", "mean_ms", "warmup_ms",
    "noisy")} | {"other_cpu_frac": c["repeats"][0].get("other_cpu_frac")} for c in o["configs"]]}))' "$tmp/vtk.json")"
            for sh in off on; do
                tag=noshade
                [ "$sh" = on ] && tag=shade
                echo "ours|$name|$d|$r|$dir|$("$cube5" cast "$raw" --spacing "$sp" --tf "$tf" --threads 2 \
                    --mode approx --shading "$sh" --views 24 --size 256 --distance "$d" -o "$dir/ours_view00_$tag.png" --json)"
            done
        done
    done
done <<< "$sets" > "$tmp/runs"

"$py" - "$tmp/runs" "$out" "$pngdir" <<'PY'
import json, statistics, sys
import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

def load_png(path):
    r = vtk.vtkPNGReader()
    r.SetFileName(path)
    r.Update()
    im = r.GetOutput()
    x, y, _ = im.GetDimensions()
    a = vtk_to_numpy(im.GetPointData().GetScalars()).reshape(y, x, -1)
    return a[:, :, :3].astype(np.float64)

vtk_ms, ours_ms, dirs = {}, {}, {}
for line in open(sys.argv[1]):
    kind, name, d, rnd, dr, text = line.rstrip("\n").split("|", 5)
    o = json.loads(text)
    dirs[(name, d)] = dr
    if kind == "vtk":
        for c in o["configs"]:
            vtk_ms.setdefault((name, d, c["shading"]), []).append(c["median_ms"])
    else:
        ours_ms.setdefault((name, d, o["shading"]), []).append(o["ms_median"])
rows = []
for key in vtk_ms:
    name, d, sh = key
    tag = "shade" if sh else "noshade"
    a = load_png("%s/%s_view00_%s.png" % (dirs[(name, d)], name, tag))
    b = load_png("%s/ours_view00_%s.png" % (dirs[(name, d)], tag))
    mse = float(np.mean((a - b) ** 2))
    lum = lambda im: float(np.mean(im @ np.array([0.2126, 0.7152, 0.0722])))
    v, u = statistics.median(vtk_ms[key]), statistics.median(ours_ms[key])
    rows.append({"dataset": name, "distance_factor": float(d), "shading": sh, "vtk_ms": v, "ours_ms": u,
                 "vtk_ms_rounds": vtk_ms[key], "ours_ms_rounds": ours_ms[key], "ratio_vtk_over_ours": v / u,
                 "ours_fps": 1000 / u, "vtk_fps": 1000 / v, "beats_26fps": 1000 / u > 26,
                 "psnr_db": 10 * np.log10(255 ** 2 / mse) if mse > 0 else float("inf"),
                 "mean_abs_diff": float(np.mean(np.abs(a - b))), "vtk_mean_lum": lum(a), "ours_mean_lum": lum(b)})
print("VTK vtkFixedPointVolumeRayCastMapper vs cube5 cast (approx), 256x256, 24 views, 2 threads;")
print("ms = median over %d interleaved rounds of each one's median ms/frame; images: view 0" %
      len(next(iter(vtk_ms.values()))))
print("%-8s %6s %5s %9s %9s %9s %8s %6s %8s %8s %11s" % ("dataset", "dist", "shade", "VTK ms", "ours ms",
      "VTK/ours", "our fps", ">26?", "PSNR dB", "mean|d|", "lum V/o"))
for r in rows:
    print("%-8s %6.4f %5s %9.1f %9.1f %9.2f %8.1f %6s %8.2f %8.2f %5.1f/%-5.1f" % (
        r["dataset"], r["distance_factor"], "on" if r["shading"] else "off", r["vtk_ms"], r["ours_ms"],
        r["ratio_vtk_over_ours"], r["ours_fps"], "yes" if r["beats_26fps"] else "no", r["psnr_db"],
        r["mean_abs_diff"], r["vtk_mean_lum"], r["ours_mean_lum"]))
print("  VTK/ours > 1: ours is faster. 26 fps: the paper's best Cell B.E. figure. mean|d| on 0..255;")
print("  lum V/o: mean luminance of VTK's and our view 0. PNGs kept under", sys.argv[3])
json.dump({"rows": rows}, open(sys.argv[2], "w"), indent=1)
print("written:", sys.argv[2])
PY
