#!/usr/bin/env bash
# make bench: cref's speed on every built-in scene at 256x256, one thread and all cores,
# printed as a table and written to BUILD/bench.json. With ../shared/data/volumes/ present,
# also brain_mirrors with a real CT volume in place of its stand-in.
set -euo pipefail
build=${1:-build}
cube5="$build/cube5"
cores=$(nproc)
out="$build/bench.json"
data="$(cd "$(dirname "$0")/.." && pwd)/../shared/data/volumes"
runs=()
for scene in $("$cube5" scenes | awk '{print $1}'); do
    for t in 1 "$cores"; do
        runs+=("$scene|$t|$("$cube5" render "$scene" --size 256x256 --frames 1 --threads "$t" --json)")
    done
done
if [ -f "$data/CThead_256x256x113_uint8.raw" ]; then
    runs+=("brain_mirrors+CThead|$cores|$("$cube5" render brain_mirrors --size 256x256 --frames 1 \
        --threads "$cores" --volume "$data/CThead_256x256x113_uint8.raw" --json)")
else
    echo "bench: ../shared/data/volumes/ not found: real-volume runs skipped" >&2
fi
printf '%s\n' "${runs[@]}" | python3 -c '
import json, sys
rows = []
for line in sys.stdin:
    name, threads, text = line.rstrip("\n").split("|", 2)
    o = json.loads(text)
    rays = sum(o["rays"].values())
    rows.append({"scene": name, "threads": int(threads), "rays": rays, "samples": o["samples"],
                 "wall_s": o["wall_s"], "msamples_per_s": o["samples"] / o["wall_s"] / 1e6})
print("%-22s %7s %10s %11s %8s %12s" % ("cref 256x256", "threads", "rays", "samples", "wall s", "Msamples/s"))
for r in rows:
    print("%-22s %7d %10d %11d %8.3f %12.2f" % (r["scene"], r["threads"], r["rays"], r["samples"], r["wall_s"],
                                               r["msamples_per_s"]))
json.dump({"cref": rows}, open(sys.argv[1], "w"), indent=1)
print("written:", sys.argv[1])
' "$out"
