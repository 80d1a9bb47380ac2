#!/usr/bin/env bash
# make bench: at 256x256, every built-in scene rendered by cref (one thread and all cores)
# and by the board model (one thread, 1 and 8 cells; Morton and FIFO queue keys), and the
# model against cref (cube5 compare), and the same frame through the host driver over libusb
# to the emulated board (cell upload MB/s, frames per second over the emulated link).
# The model's host throughput is stated per core: M sample positions (taken or leaped) per
# second of its one thread (the median of RTL_REPS=3 runs); a small table shows how it grows
# with the volume's size and the cell count (the default scene at 96^3 and 192^3 voxels, 1, 8
# and 64 cells). The board model on every core against one: scripts/bench-threads.sh.
# Printed as tables and written to BUILD/bench.json.
# With ../shared/data/volumes/ present, also brain_mirrors with a real CT volume.
# Then the out-of-core section (cref over a 384^3 grid, generated and a raw file, resident and
# out of core: wall seconds and peak RSS; BENCH_LARGE=1 adds 1024^3 and 2048^3):
# scripts/bench-ooc.sh; then the caster section (cube5 cast, the paper's Figures 11-13 and
# Table 2): scripts/bench-cast.sh; the caster's default k on inputs it was not fitted on:
# scripts/bench-cast-k.sh.
set -euo pipefail
build=${1:-build}
cube5="$build/cube5"
cores=$(nproc)
out="$build/bench.json"
data="$(cd "$(dirname "$0")/.." && pwd)/../shared/data/volumes"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
scenes=$("$cube5" scenes | awk '{print $1}')
for scene in $scenes; do
    for t in 1 "$cores"; do
        echo "cref|$scene|$t|$("$cube5" render "$scene" --size 256x256 --frames 1 --threads "$t" --json)"
    done
    for cells in 1 2; do
        for key in morton fifo; do
            # RTL_REPS runs (3 by default) of which the table keeps the median wall time: one
            # run on a shared VM varies by +-15 %.
            for _ in $(seq "${RTL_REPS:-3}"); do
                echo "rtl|$scene|$cells|$key|$("$cube5" render "$scene" --size 256x256 --frames 1 --model rtl \
                    --cells "$cells" --queue-key "$key" --threads 1 --json)"
            done
        done
    done
    echo "compare|$scene|$("$cube5" compare "$scene" --size 256x256 --cells 2 --json)"
    # The same frame through the host driver over libusb to the emulated board (umockdev).
    echo "link|$scene|$("$build/cube5-board" run -- "$build/cube5ctl" render "$scene" --size 256x256 --cells 2 \
        -o "$tmp/link.png" --json)"
done > "$tmp/runs"
# Scaling: the default scene with its volume at 96^3 and 192^3 voxels (same world box, so
# half the spacing), split into 1, 2^3 and 4^3 cells.
for n in 96 192; do
    python3 -c 'import json, sys; s = json.load(open(sys.argv[1])); s["volumes"][0]["dims"] = [int(sys.argv[2])] * 3
json.dump(s, open(sys.argv[3], "w"))' "$(dirname "$0")/../scenes/default.json" "$n" "$tmp/default$n.json"
    for cells in 1 2 4; do
        echo "scale|default|$n|$cells|$("$cube5" render "$tmp/default$n.json" --size 256x256 --frames 1 --model rtl \
            --cells "$cells" --threads 1 --json)"
    done
done >> "$tmp/runs"
if [ -f "$data/CThead_256x256x113_uint8.raw" ]; then
    echo "cref|brain_mirrors+CThead|$cores|$("$cube5" render brain_mirrors --size 256x256 --frames 1 \
        --threads "$cores" --volume "$data/CThead_256x256x113_uint8.raw" --json)" >> "$tmp/runs"
    echo "compare|brain_mirrors+CThead|$("$cube5" compare brain_mirrors --size 256x256 --cells 2 \
        --volume "$data/CThead_256x256x113_uint8.raw" --json)" >> "$tmp/runs"
else
    echo "bench: ../shared/data/volumes/ not found: real-volume runs skipped" >&2
fi
python3 - "$tmp/runs" "$out" <<'PY'
import json, sys
cref, rtl, cmp, link, scale = [], [], [], [], []
MODEL_THREADS = 1  # the runs above pass --threads 1; scripts/bench-threads.sh times more
for line in open(sys.argv[1]):
    kind, rest = line.rstrip("\n").split("|", 1)
    if kind == "cref":
        name, threads, text = rest.split("|", 2)
        o = json.loads(text)
        cref.append({"scene": name, "threads": int(threads), "rays": sum(o["rays"].values()),
                     "samples": o["samples"], "wall_s": o["wall_s"],
                     "msamples_per_s": o["samples"] / o["wall_s"] / 1e6})
    elif kind == "rtl":
        name, cells, key, text = rest.split("|", 3)
        o = json.loads(text)
        b = o["board"]
        passed = o["samples"] + b["samples_leaped"]
        rtl.append({"scene": name, "cells": int(cells) ** 3, "key": key, "rays": sum(o["rays"].values()),
                    "samples": o["samples"], "samples_leaped": b["samples_leaped"], "wall_s": o["wall_s"],
                    "threads": MODEL_THREADS, "msamples_per_s": passed / o["wall_s"] / 1e6,
                    "msample_positions_per_s_per_core": passed / o["wall_s"] / 1e6 / MODEL_THREADS,
                    "board_cycles": b["cycles"],
                    "board_s": b["board_s"], "fetches": b["fetches"], "fetch_bytes": b["fetch_bytes"],
                    "spills": b["spills"], "cache_misses": b["cache_misses"],
                    "cache_miss_rate": b["cache_misses"] / max(1, b["cache_hits"] + b["cache_misses"])})
    elif kind == "scale":
        name, dims, cells, text = rest.split("|", 3)
        o = json.loads(text)
        b = o["board"]
        passed = o["samples"] + b["samples_leaped"]
        scale.append({"scene": name, "dims": int(dims), "cells": int(cells) ** 3, "threads": MODEL_THREADS,
                      "samples": o["samples"], "samples_leaped": b["samples_leaped"], "wall_s": o["wall_s"],
                      "msample_positions_per_s_per_core": passed / o["wall_s"] / 1e6 / MODEL_THREADS,
                      "board_cycles": b["cycles"], "fetches": b["fetches"], "bus_packets": b["bus_packets"]})
    elif kind == "link":
        name, text = rest.split("|", 1)
        o = json.loads(text)
        d, b = o["driver"], o["board"]
        link.append({"scene": name, "cells": 8, "fetches_served": d["fetches_served"], "cell_bytes": d["cell_bytes"],
                     "cell_upload_s": d["cell_upload_s"], "cell_upload_mb_s": d["cell_upload_mb_s"],
                     "dma_reads": d["dma_reads"], "fb_bytes": d["fb_bytes"], "frame_s": d["frame_s"],
                     "fps": 1 / d["frame_s"], "board_cycles": b["cycles"]})
    else:
        name, text = rest.split("|", 1)
        o = json.loads(text)
        cmp.append({k: o[k] for k in ("psnr_db", "rmse", "max_abs_err", "cref_wall_s", "model_wall_s",
                                       "board_cycles", "board_s", "fetches")} | {"scene": name})
# The median run (by wall time) of each scene, split and key's RTL_REPS; every other figure of
# the runs is the same, the model being deterministic.
runs = {}
for r in rtl:
    runs.setdefault((r["scene"], r["cells"], r["key"]), []).append(r)
rtl = [sorted(v, key=lambda r: r["wall_s"])[(len(v) - 1) // 2] | {"runs": len(v)} for v in runs.values()]
print("%-22s %7s %10s %11s %8s %12s" % ("cref 256x256", "threads", "rays", "samples", "wall s", "Msamples/s"))
for r in cref:
    print("%-22s %7d %10d %11d %8.3f %12.2f" % (r["scene"], r["threads"], r["rays"], r["samples"], r["wall_s"],
                                               r["msamples_per_s"]))
print("\n%-16s %5s %6s %7s %10s %9s %8s %11s %11s %8s %7s %9s" % (
    "rtl 256x256", "cells", "key", "threads", "samples", "leaped", "wall s", "M pos/s/core", "cycles", "board s",
    "fetches", "miss rate"))
for r in rtl:
    print("%-16s %5d %6s %7d %10d %9d %8.3f %11.2f %11d %8.4f %7d %8.2f%%" % (
        r["scene"], r["cells"], r["key"], r["threads"], r["samples"], r["samples_leaped"], r["wall_s"],
        r["msample_positions_per_s_per_core"], r["board_cycles"], r["board_s"], r["fetches"],
        100 * r["cache_miss_rate"]))
print("  (M pos/s/core: the model's host throughput, M sample positions per second per core = sample positions")
print("   passed (taken or leaped, as cref's samples count them) / wall s of c5_board_render / %d thread;"
      % MODEL_THREADS)
print("   the median of %d runs)" % max(r["runs"] for r in rtl))
m8 = [r for r in rtl if r["cells"] == 8 and r["key"] == "morton"]
if m8:
    worst = min(m8, key=lambda r: r["msample_positions_per_s_per_core"])
    print("  slowest scene, 8 cells, Morton: %s at %.2f M sample positions/s per core (target: 20)"
          % (worst["scene"], worst["msample_positions_per_s_per_core"]))
print("\n%-22s %5s %5s %7s %10s %9s %8s %12s %11s %7s %9s" % (
    "rtl scaling 256x256", "voxels", "cells", "threads", "samples", "leaped", "wall s", "M pos/s/core", "cycles",
    "fetches", "bus pkts"))
for r in scale:
    print("%-22s %5s %5d %7d %10d %9d %8.3f %12.2f %11d %7d %9d" % (
        r["scene"], "%d^3" % r["dims"], r["cells"], r["threads"], r["samples"], r["samples_leaped"], r["wall_s"],
        r["msample_positions_per_s_per_core"], r["board_cycles"], r["fetches"], r["bus_packets"]))
print("  (the default scene's volume at 96^3 and 192^3 voxels over the same world box, Morton key)")
print("\n%-22s %8s %10s %9s %8s %8s %8s" % ("compare, 8 cells", "PSNR dB", "RMSE", "max err", "cref s", "model s",
                                            "fetches"))
for r in cmp:
    print("%-22s %8.2f %10.2e %9.4f %8.3f %8.3f %8d" % (r["scene"], r["psnr_db"], r["rmse"], r["max_abs_err"],
                                                       r["cref_wall_s"], r["model_wall_s"], r["fetches"]))
print("\n%-22s %7s %10s %9s %11s %8s %7s" % ("host link, 8 cells", "fetches", "cell MB", "upload s", "upload MB/s",
                                            "frame s", "fps"))
for r in link:
    print("%-22s %7d %10.2f %9.3f %11.1f %8.3f %7.2f" % (r["scene"], r["fetches_served"], r["cell_bytes"] / 1e6,
                                                      r["cell_upload_s"], r["cell_upload_mb_s"], r["frame_s"], r["fps"]))
print("  (cube5ctl through libusb to the emulated board under umockdev: MB/s = cell bytes / time from each")
print("   doorbell to the cell's last completion; fps = 1 / (start_frame to frame_done), the model's own time included)")
json.dump({"cref": cref, "rtl": rtl, "rtl_scaling": scale, "compare": cmp, "link": link}, open(sys.argv[2], "w"),
          indent=1)
print("written:", sys.argv[2])
PY
bash "$(dirname "$0")/bench-threads.sh" "$build"
bash "$(dirname "$0")/bench-ooc.sh" "$build"
bash "$(dirname "$0")/bench-cast.sh" "$build"
bash "$(dirname "$0")/bench-cast-k.sh" "$build"
bash "$(dirname "$0")/bench-supervol.sh" "$build"
