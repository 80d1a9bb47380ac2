#!/usr/bin/env bash
# make bench, a super volume at real scale: scenes/large/mirror_hall_1024.json (a 1024^3
# volume between mirrors) on the board model per memory fraction (1/8 .. 1/4096: 2 .. 16
# cells per axis; a cell holds at most 256 voxels a side, so 1/8 and 1/27 are refused at
# 1024^3 and say so): host seconds and peak host memory (getrusage of the child, ru_maxrss)
# of one frame, modelled board seconds, fetches and bytes fetched, and Max Work against the
# Cell Tree (cube5 schedule, still camera: the last of SUPERVOL_FRAMES frames, the DSP's
# group rule having settled; docs/cell-tree.md). The volume's voxels are written once to
# BUILD/bench-data/ (about two minutes) and read from there.
# Printed as a table and added to BUILD/bench.json as "supervolume".
# Then the frame's set-up at 1/512: the whole `cube5 render` process's wall and CPU seconds
# (the volume in the page cache) with the grid's block ranges made in the run
# (C5_CACHE_DIR=off) and read from the cache (docs/out-of-core.md, "Block ranges"), the
# median of SETUP_REPS (3) interleaved runs each; with BASELINE=path/to/an/older/cube5 its
# runs are interleaved with them and the ratio printed. Target: under 2 s from the cache.
# SUPERVOL_SIZE (default 128x128), SUPERVOL_FRAMES (default 5), SUPERVOL_SPLITS (cells per axis,
# default "2 3 4 8 16"; empty: the set-up alone), SUPERVOL=0 skips it all.
# Usage: bench-supervol.sh BUILD
set -euo pipefail
build=${1:-build}
[ "${SUPERVOL:-1}" = 0 ] && { echo "supervolume: skipped (SUPERVOL=0)"; exit 0; }
cube5="$build/cube5"
here=$(cd "$(dirname "$0")" && pwd)
scene="$here/../scenes/large/mirror_hall_1024.json"
size=${SUPERVOL_SIZE:-128x128}
frames=${SUPERVOL_FRAMES:-5}
data="$build/bench-data"
raw="$data/blobs_1024x1024x1024_uint8.raw"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$data"
if [ ! -s "$raw" ]; then
    echo "supervolume: writing the 1024^3 voxels once to $raw (a few minutes)" >&2
    "$cube5" cast "$scene" --views 1 --size 64 --save-raw "$raw.part" >/dev/null
    mv "$raw.part" "$raw"
fi

# run LABEL CMD...: one line LABEL|EXIT|MAXRSS_KIB|STDOUT (a refusal's message as STDOUT)
run() {
    python3 - "$@" <<'PY'
import resource, subprocess, sys
p = subprocess.run(sys.argv[2:], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
out = p.stdout.strip() if p.returncode == 0 else p.stderr.strip().splitlines()[-1]
print("%s|%d|%d|%s" % (sys.argv[1], p.returncode, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss, out))
PY
}

for n in ${SUPERVOL_SPLITS-2 3 4 8 16}; do
    run "render|$n" "$cube5" render "$scene" --volume "$raw" --model rtl --cells "$n" --size "$size" --frames 1 \
        --json >>"$tmp/runs"
    rc=$(tail -n 1 "$tmp/runs" | cut -d'|' -f3)
    [ "$rc" = 0 ] || continue
    run "schedule|$n" "$cube5" schedule "$scene" --volume "$raw" --cells "$n" --size "$size" --still \
        --frames "$frames" --exact-states 0 --split paper --json >>"$tmp/runs"
done

# setup LABEL CACHE_DIR CUBE5: one line setup|LABEL|WALL_S|CPU_S|MODEL_WALL_S
setup() {
    C5_CACHE_DIR=$2 python3 - "$1" "$3" "$scene" "$raw" "$size" "$tmp/setup.png" <<'PY'
import json, resource, subprocess, sys, time
label, cube5, scene, raw, size, png = sys.argv[1:]
r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
t0 = time.perf_counter()
p = subprocess.run([cube5, "render", scene, "--volume", raw, "--model", "rtl", "--cells", "8", "--size", size,
                    "--frames", "1", "--json", "-o", png], stdout=subprocess.PIPE, text=True, check=True)
wall = time.perf_counter() - t0
r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
cpu = r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime
print("setup|%s|%.3f|%.3f|%.3f" % (label, wall, cpu, json.loads(p.stdout)["wall_s"]))
PY
}
mkdir -p "$tmp/cache"
setup prime "$tmp/cache" "$cube5" >/dev/null
for _ in $(seq "${SETUP_REPS:-3}"); do
    setup made off "$cube5" >>"$tmp/runs"
    setup cached "$tmp/cache" "$cube5" >>"$tmp/runs"
    [ -n "${BASELINE:-}" ] && setup baseline off "$BASELINE" >>"$tmp/runs"
done

# BENCH_LARGE=1: the hall at 2048^3 from one 8 GiB raw file (the 1024^3 file tiled 2x2x2,
# written once to BUILD/bench-data/), 1/512: out of core (C5_MEM_BUDGET=1G: the cells from
# their store on disk, rtl_model/mem/cell_store.h) against in core (C5_MEM_BUDGET=9G: the
# file mapped), interleaved, the page cache warm; then, where the page cache can be dropped
# (root), the disk's read speed (dd of 2 GiB) and one cold run of each.
if [ "${BENCH_LARGE:-0}" = 1 ]; then
    raw2=$data/tiled_2048x2048x2048_uint8.raw
    if [ ! -s "$raw2" ]; then
        echo "supervolume: writing the 2048^3 voxels once to $raw2 (8 GiB)" >&2
        python3 - "$raw" "$raw2.part" <<'PY'
import sys
n = 1024
with open(sys.argv[1], "rb") as f, open(sys.argv[2], "wb") as o:
    for _ in range(2):
        f.seek(0)
        for z in range(n):
            p = f.read(n * n)
            half = b"".join(p[y * n:(y + 1) * n] * 2 for y in range(n))
            o.write(half + half)
PY
        mv "$raw2.part" "$raw2"
    fi
    python3 - "$scene" "$tmp/hall2048.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
s["name"], s["grid"]["size"], s["volumes"][0]["dims"] = "mirror_hall_2048", 2048, [2048] * 3
for l in s["lights"]:
    l["position"] = [2 * x for x in l["position"]]
for f in s["surfaces"]:
    for k in ("corner", "u", "v"):
        f[k] = [2 * x for x in f[k]]
for c in [s["camera"]] + s["camera_path"]["keys"]:
    for k in ("eye", "target"):
        c[k] = [2 * x for x in c[k]]
json.dump(s, open(sys.argv[2], "w"))
PY
    # large LABEL BUDGET: one line large|LABEL|WALL_S|CPU_S|MAXRSS_KIB|CYCLES
    large() {
        C5_CACHE_DIR=$tmp/cache C5_MEM_BUDGET=$2 python3 - "$1" "$cube5" "$tmp/hall2048.json" "$raw2" "$size" \
            "$tmp/large.png" <<'PY'
import json, resource, subprocess, sys, time
label, cube5, scene, raw, size, png = sys.argv[1:]
t0 = time.perf_counter()
p = subprocess.Popen([cube5, "render", scene, "--volume", raw, "--model", "rtl", "--cells", "8", "--size", size,
                      "--frames", "1", "--json", "-o", png], stdout=subprocess.PIPE, text=True)
out = p.stdout.read()
_, status, ru = __import__("os").wait4(p.pid, 0)
wall = time.perf_counter() - t0
print("large|%s|%.3f|%.3f|%d|%d" % (label, wall, ru.ru_utime + ru.ru_stime, ru.ru_maxrss,
                                    json.loads(out)["board"]["cycles"]))
PY
    }
    large build 1G >>"$tmp/runs"
    large prime 9G >/dev/null
    for _ in $(seq "${SETUP_REPS:-3}"); do
        large ooc 1G >>"$tmp/runs"
        large incore 9G >>"$tmp/runs"
    done
    if [ -w /proc/sys/vm/drop_caches ]; then
        sync; echo 3 >/proc/sys/vm/drop_caches
        echo "large|disk_mb_s|$(dd if="$raw2" of=/dev/null bs=16M count=128 2>&1 | tail -1 |
            awk '{for (i = 1; i <= NF; i++) if ($i ~ /^(MB|GB)\/s$/) print ($i == "GB/s" ? $(i - 1) * 1000 : $(i - 1))}')|0|0|0" \
            >>"$tmp/runs"
        sync; echo 3 >/proc/sys/vm/drop_caches
        large ooc_cold 1G >>"$tmp/runs"
        sync; echo 3 >/proc/sys/vm/drop_caches
        large incore_cold 9G >>"$tmp/runs"
    else
        echo "supervolume: the page cache cannot be dropped here (not root): no cold runs, no disk speed" >&2
    fi
fi

python3 - "$tmp/runs" "$build/bench.json" "$size" "$frames" <<'PY'
import json, os, sys
runs, out_path, size, frames = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
rows, setup, large = {}, {}, {}
for line in open(runs):
    if line.startswith("large|"):
        _, label, wall, cpu, rss, cycles = line.rstrip("\n").split("|")
        large.setdefault(label, []).append((float(wall), float(cpu), int(rss) / 1024, int(cycles)))
        continue
    if line.startswith("setup|"):
        _, label, wall, cpu, model = line.rstrip("\n").split("|")
        setup.setdefault(label, []).append((float(wall), float(cpu), float(model)))
        continue
    kind, n, rc, rss, text = line.rstrip("\n").split("|", 4)
    r = rows.setdefault(int(n), {"cells_per_axis": int(n), "memory_fraction": "1/%d" % int(n) ** 3})
    if kind == "render":
        if rc != "0":
            r["refused"] = text
            continue
        o = json.loads(text)
        b = o["frames"][0]["board"]
        r.update(host_s=o["wall_s"], peak_rss_mib=int(rss) / 1024, board_s=b["board_s"], fetches=b["fetches"],
                 fetch_bytes=b["fetch_bytes"], samples=o["samples"], samples_leaped=b["samples_leaped"],
                 tree_nodes=b["tree_nodes"], tree_overflow=b["tree_overflow"],
                 tree_demand_nodes=b["tree_demand_nodes"], tree_demand_bytes=b["tree_demand_slots"] * 12)
    elif rc == "0":
        o = json.loads(text)
        last = o["frames"][-1]
        r.update(schedule_frames=len(o["frames"]), fetches_maxwork=last["fetches_maxwork"],
                 fetches_celltree=last["fetches_celltree"], followed=last["followed"],
                 tree_group=o["frames"][-2]["tree_group"] if len(o["frames"]) > 1 else 1,
                 schedule_peak_rss_mib=int(rss) / 1024)
    else:
        r["schedule_refused"] = text
table = [rows[k] for k in sorted(rows)]
print("\nsupervolume: scenes/large/mirror_hall_1024.json, 1024^3 voxels (1 GiB), %s, board model, one frame" % size)
print("%-9s %8s %9s %8s %8s %9s %8s %11s %12s %8s %s" % ("memory", "host s", "peak MiB", "board s", "fetches",
      "GB fetched", "tree", "tree needs", "MaxWork->CT", "fewer", "followed (last frame)"))
for r in table:
    if "refused" in r:
        print("%-9s refused: %s" % (r["memory_fraction"], r["refused"].split(": ", 2)[-1]))
        continue
    ct = "%d->%d" % (r.get("fetches_maxwork", 0), r.get("fetches_celltree", 0))
    fewer = 100.0 * (1 - r["fetches_celltree"] / r["fetches_maxwork"]) if r.get("fetches_maxwork") else 0
    tree = "%d%s" % (r["tree_nodes"], "!" if r["tree_overflow"] else "")
    print("%-9s %8.1f %9.0f %8.2f %8d %9.2f %8s %9.0f KB %12s %7.1f%% %s" % (
        r["memory_fraction"], r["host_s"], r["peak_rss_mib"], r["board_s"], r["fetches"], r["fetch_bytes"] / 1e9,
        tree, r["tree_demand_bytes"] / 1024, ct, fewer, "%s (tree over %d^3 cells)" % (r.get("followed", "-"),
                                                                                      r.get("tree_group", 1))))
print("  (tree: the frame's Cell Tree nodes in the 96 KB, ! = overflowed; tree needs: the RAM its dependencies"
      " need, tree_demand; MaxWork->CT: fetches of the last of %d still frames)" % frames)
med = {k: sorted(v)[(len(v) - 1) // 2] for k, v in setup.items()}
print("\nset-up, 1/512 at %s: the whole cube5 render process, median of %d runs" % (size, len(setup["made"])))
print("%-36s %8s %8s %13s" % ("", "wall s", "CPU s", "model wall s"))
names = {"made": "block ranges made in the run", "cached": "block ranges from the cache",
         "baseline": "BASELINE (%s)" % os.environ.get("BASELINE", "")}
for k in ("made", "cached", "baseline"):
    if k in med:
        print("%-36s %8.2f %8.2f %13.2f" % ((names[k],) + med[k]))
if "baseline" in med:
    print("  baseline / cached: %.1fx wall" % (med["baseline"][0] / med["cached"][0]))
print("  target: under 2 s from the cache (%s)" % ("met" if med["cached"][0] < 2 else "NOT met"))
lmed = {k: sorted(v)[(len(v) - 1) // 2] for k, v in large.items()}
if "ooc" in lmed:
    print("\n2048^3 raw file (8 GiB), 1/512 at %s, one frame: the whole cube5 render process, median of %d runs"
          % (size, len(large["ooc"])))
    print("%-44s %8s %8s %9s" % ("", "wall s", "CPU s", "peak MiB"))
    names = {"build": "out of core, the cell store made (once)", "ooc": "out of core (1 GiB budget), warm",
             "incore": "in core (9 GiB budget, mapped), warm", "ooc_cold": "out of core, page cache dropped",
             "incore_cold": "in core, page cache dropped"}
    for k in ("build", "ooc", "incore", "ooc_cold", "incore_cold"):
        if k in lmed:
            print("%-44s %8.2f %8.2f %9.0f" % ((names[k],) + lmed[k][:3]))
    print("  out of core / in core: %.2fx warm%s (target: at most 1.5x)" % (
        lmed["ooc"][0] / lmed["incore"][0],
        ", %.2fx cold" % (lmed["ooc_cold"][0] / lmed["incore_cold"][0]) if "ooc_cold" in lmed else ""))
    if "disk_mb_s" in lmed:
        print("  the disk's own read speed: %.0f MB/s (dd, 2 GiB, page cache dropped)" % lmed["disk_mb_s"][0])
    print("  same cycles: %s" % (len({v[3] for k, v in lmed.items() if k != "disk_mb_s"}) == 1))
doc = json.load(open(out_path)) if os.path.exists(out_path) else {}
doc["supervolume"] = {"scene": "mirror_hall_1024", "voxels": 1024 ** 3, "size": size, "rows": table,
                      "setup": {k: {"wall_s": v[0], "cpu_s": v[1], "model_wall_s": v[2], "runs": len(setup[k])}
                                for k, v in med.items()},
                      "large_2048": {k: {"wall_s": v[0], "cpu_s": v[1], "peak_rss_mib": v[2], "board_cycles": v[3],
                                         "runs": len(large[k])} for k, v in lmed.items()}}
json.dump(doc, open(out_path, "w"), indent=1)
PY
