#!/usr/bin/env bash
# The board model's host threads (docs/board-model.md, "Host threads"): every built-in scene at
# 256x256, one frame, split 3x3x3 (1/27), ROUNDS (default 3) interleaved rounds of
# `cube5 render --model rtl --threads 1` and `--threads N` (N = nproc: the CPUs it may run on, at least 2).
# Reported per scene: the median wall time of c5_board_render at each count, the speed-up, M
# sample positions/s per core and per machine, the visits that had to wake a sleeping helper
# (host_helper_wakes), and that both runs drew the same frame (image CRC, cycles, cache
# misses); for brain_mirrors' speed-up and the slowest scene per core, the
# same from the fastest round of each count too. Beside it, what this machine gives two copies of the one-thread
# frame run at once (pinned to two CPUs with taskset when there is one): the throughput of two
# against one, the ceiling of any split of one frame over two cores of this machine.
# Prints a table and writes BUILD/bench-threads.json.
set -euo pipefail
build=${1:-build}
cube5="$build/cube5"
out="$build/bench-threads.json"
rounds=${ROUNDS:-3}
n=$(nproc)
[ "$n" -ge 2 ] || n=2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
run() { # scene threads
    "$cube5" render "$1" --size 256x256 --frames 1 --model rtl --cells 3 --threads "$2" --json -o "$tmp/img.png"
}
scenes=$("$cube5" scenes | awk '{print $1}')
for r in $(seq "$rounds"); do
    for scene in $scenes; do
        for t in 1 "$n"; do
            echo "run|$scene|$t|$(run "$scene" "$t")|$(cksum < "$tmp/img.png" | awk '{print $1}')"
        done
    done
    pin0=() pin1=()
    if command -v taskset >/dev/null; then
        pin0=(taskset -c 0) pin1=(taskset -c 1)
    fi
    "${pin0[@]}" "$cube5" render brain_mirrors --size 256x256 --frames 1 --model rtl --cells 3 --threads 1 --json \
        > "$tmp/a.json" &
    "${pin1[@]}" "$cube5" render brain_mirrors --size 256x256 --frames 1 --model rtl --cells 3 --threads 1 --json \
        > "$tmp/b.json"
    wait
    echo "pair|$(tr -d '\n' < "$tmp/a.json")|$(tr -d '\n' < "$tmp/b.json")"
done > "$tmp/runs"
python3 - "$tmp/runs" "$out" "$n" <<'PY'
import json, statistics, sys
runs, pairs = {}, []
n = int(sys.argv[3])
for line in open(sys.argv[1]):
    kind, rest = line.rstrip("\n").split("|", 1)
    if kind == "run":
        scene, t, text, crc = rest.split("|", 3)
        o = json.loads(text)
        b = o["board"]
        runs.setdefault((scene, int(t)), []).append({"wall_s": o["wall_s"], "passed": o["samples"] + b["samples_leaped"],
            "frame": (crc, b["cycles"], b["cache_misses"], o["samples"]), "helper_runs": b["host_helper_runs"],
            "helper_wakes": b["host_helper_wakes"]})
    else:
        a, b = rest.split("|", 1)
        pairs.append(max(json.loads(a)["wall_s"], json.loads(b)["wall_s"]))
rows = []
for scene in dict.fromkeys(s for s, _ in runs):
    one, many = runs[(scene, 1)], runs[(scene, n)]
    w1 = statistics.median(r["wall_s"] for r in one)
    wn = statistics.median(r["wall_s"] for r in many)
    f1 = min(r["wall_s"] for r in one)
    fn = min(r["wall_s"] for r in many)
    passed = one[0]["passed"]
    same = len({r["frame"] for r in one + many}) == 1
    rows.append({"scene": scene, "split": "3x3x3", "threads": n, "wall_s_1": w1, "wall_s_n": wn, "speedup": w1 / wn,
                 "msample_positions_per_s_per_core_1": passed / w1 / 1e6,
                 "msample_positions_per_s_per_core_n": passed / wn / 1e6 / n,
                 "msample_positions_per_s_machine_n": passed / wn / 1e6,
                 "fastest_wall_s_1": f1, "fastest_wall_s_n": fn, "fastest_speedup": f1 / fn,
                 "fastest_msample_positions_per_s_per_core_1": passed / f1 / 1e6,
                 "helper_runs": statistics.median(r["helper_runs"] for r in many),
                 "helper_wakes": statistics.median(r["helper_wakes"] for r in many), "same_frame": same,
                 "rounds": len(one)})
bm1 = statistics.median(r["wall_s"] for r in runs[("brain_mirrors", 1)])
pair = statistics.median(pairs)
print("rtl host threads, 256x256, split 3x3x3, median of %d interleaved rounds" % rows[0]["rounds"])
print("%-16s %9s %9s %8s %13s %13s %12s %6s %6s" % ("scene", "1 thr s", "%d thr s" % n, "speed-up", "M pos/s/core 1",
                                                    "M pos/s/core %d" % n, "helper runs", "wakes", "same"))
for r in rows:
    print("%-16s %9.3f %9.3f %7.2fx %13.2f %13.2f %12d %6d %6s" % (
        r["scene"], r["wall_s_1"], r["wall_s_n"], r["speedup"], r["msample_positions_per_s_per_core_1"],
        r["msample_positions_per_s_per_core_n"], r["helper_runs"], r["helper_wakes"],
        "yes" if r["same_frame"] else "NO"))
bm = next(r for r in rows if r["scene"] == "brain_mirrors")
ceiling = 2 * bm1 / pair
print("  brain_mirrors 1/27: 1 -> %d threads %.2fx (target: 1.7x); between the fastest rounds %.2fx"
      % (n, bm["speedup"], bm["fastest_speedup"]))
print("  this machine, two one-thread brain_mirrors frames at once: %.3f s against %.3f s alone, %.2fx the"
      % (pair, bm1, ceiling))
print("   throughput of one (the most any split of one frame over two of its cores can give);")
print("   the split reaches %.0f %% of it" % (100 * bm["speedup"] / ceiling))
worst = min(rows, key=lambda r: r["msample_positions_per_s_per_core_1"])
print("  slowest scene per core, one thread: %s at %.2f M sample positions/s (target: 20); in its fastest round %.2f"
      % (worst["scene"], worst["msample_positions_per_s_per_core_1"], worst["fastest_msample_positions_per_s_per_core_1"]))
print("  (the fastest round is what a loaded host's noise cannot make faster: docs/board-model.md, \"Host threads\")")
json.dump({"threads": n, "scenes": rows, "pair_wall_s": pair, "pair_throughput": ceiling,
           "brain_mirrors_speedup": bm["speedup"], "brain_mirrors_of_pair": bm["speedup"] / ceiling,
           "target_speedup": 1.7}, open(sys.argv[2], "w"), indent=1)
print("written:", sys.argv[2])
if not all(r["same_frame"] for r in rows):
    sys.exit("bench-threads: a frame differs between thread counts")
PY
