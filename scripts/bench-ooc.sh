#!/usr/bin/env bash
# make bench, out of core (docs/out-of-core.md): cref at 256x256 on every core over an N^3
# grid, a generated one (sphere) and a raw uint8 file written here, each with the default
# memory budget and with one an eighth of the grid (out of core): wall seconds and peak RSS
# (getrusage of the child, ru_maxrss). N is 384; BENCH_LARGE=1 adds 1024 and 2048 (the 2048^3
# file is 8 GiB: written into a temporary folder, deleted at the end; some minutes per run).
# Printed as a table and added to BUILD/bench.json as "out_of_core".
# Usage: bench-ooc.sh BUILD
set -euo pipefail
build=${1:-build}
cube5="$build/cube5"
cores=$(nproc)
sizes="384"
[ "${BENCH_LARGE:-0}" = 1 ] && sizes="384 1024 2048"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

scene() { # N SOURCE_JSON OUT
    cat >"$3" <<EOF
{"grid": {"center": [0, 0, 0], "size": 2},
 "volumes": [$2],
 "transfer_function": {"opacity": [[0, 0], [100, 0], [200, 0.02], [255, 0.05]],
                       "color": [[0, 0.2, 0.4, 0.9], [255, 1, 0.9, 0.7]]},
 "lights": [{"type": "directional", "direction": [-0.4, 0.3, -1]}],
 "camera": {"eye": [2.6, -3.4, 2.0], "target": [0, 0, 0], "up": [0, 0, 1], "fov": 34, "width": 256, "height": 256}}
EOF
}

# voxel (x, y, z) = (x + 2 y + 3 z) mod 256, written slab by slab
mkraw() {
    python3 - "$1" "$2" <<'PY'
import sys
n, out = int(sys.argv[1]), sys.argv[2]
ramp = bytes(range(256)) * (n // 256 + 2)
with open(out, "wb") as f:
    for z in range(n):
        f.write(b"".join(ramp[(2 * y + 3 * z) % 256:(2 * y + 3 * z) % 256 + n] for y in range(n)))
PY
}

# run KIND N BUDGET SCENE: one line KIND|N|BUDGET|MAXRSS_KIB|JSON (the peak RSS of the child, getrusage)
run() {
    local budget=(-u C5_MEM_BUDGET)
    [ "$3" != default ] && budget=(C5_MEM_BUDGET="$3")
    python3 - "$1|$2|$3" env "${budget[@]}" "$cube5" render "$4" --threads "$cores" --json <<'PY'
import resource, subprocess, sys
out = subprocess.run(sys.argv[2:], check=True, stdout=subprocess.PIPE, text=True).stdout
print("%s|%d|%s" % (sys.argv[1], resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss, out.strip()))
PY
}

for n in $sizes; do
    small=$((n * n * n / 8))
    scene "$n" "{\"generator\": \"sphere\", \"dims\": [$n, $n, $n], \"radius\": 0.4, \"value\": 200}" "$tmp/gen$n.json"
    run generated "$n" default "$tmp/gen$n.json"
    run generated "$n" "$small" "$tmp/gen$n.json"
    mkraw "$n" "$tmp/vol_${n}x${n}x${n}_uint8.raw"
    scene "$n" "{\"file\": \"vol_${n}x${n}x${n}_uint8.raw\"}" "$tmp/raw$n.json"
    run raw "$n" default "$tmp/raw$n.json"
    run raw "$n" "$small" "$tmp/raw$n.json"
    rm -f "$tmp/vol_${n}x${n}x${n}_uint8.raw"
done >"$tmp/runs"

python3 - "$tmp/runs" "$build/bench.json" "$cores" <<'PY'
import json, os, sys
rows = []
for line in open(sys.argv[1]):
    kind, n, budget, rss, text = line.rstrip("\n").split("|", 4)
    o = json.loads(text)
    n = int(n)
    rows.append({"volume": kind, "dims": n, "grid_bytes": n ** 3,
                 "budget": "default (1 GiB)" if budget == "default" else int(budget),
                 "resident": budget == "default" and n ** 3 <= 1 << 30, "threads": int(sys.argv[3]),
                 "wall_s": o["wall_s"], "samples": o["samples"], "peak_rss_mib": int(rss) / 1024})
print("\n%-24s %6s %16s %9s %8s %10s %12s" % ("out of core, cref 256x256", "voxels", "budget", "resident",
                                               "threads", "render s", "peak RSS MiB"))
for r in rows:
    b = r["budget"] if isinstance(r["budget"], str) else "%.0f MiB" % (r["budget"] / 2 ** 20)
    print("%-24s %6s %16s %9s %8d %10.2f %12.0f" % (r["volume"], "%d^3" % r["dims"], b, "yes" if r["resident"] else "no",
                                                   r["threads"], r["wall_s"], r["peak_rss_mib"]))
print("  (render s: cref's frame alone; the process also builds the grid (resident) or opens its sources;")
print("   peak RSS: the process's ru_maxrss; formula and figures in docs/out-of-core.md)")
path = sys.argv[2]
j = json.load(open(path)) if os.path.exists(path) else {}
j["out_of_core"] = rows
json.dump(j, open(path, "w"), indent=1)
PY
