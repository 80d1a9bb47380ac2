#!/usr/bin/env bash
# make bench-boards: several boards on one super volume (docs/multi-board.md). Four parts:
#  1. Every scene renders one frame on 1, 2, 4 and 8 boards (MPI ranks on this machine,
#     oversubscribed, over the loopback) for each cell-assignment rule and each exchange
#     (async, rounds); per run the modelled frame time (in board cycles: no host time enters
#     it), the speed-up over one board, the cell fetches of all boards, the bytes between
#     boards and the load balance (mean busy cycles of the boards / the largest). The image of
#     every run is checked against one board's (crc32). With ../shared/data/volumes/ present,
#     also brain_mirrors with the CThead CT volume (256x256x113), else the run says it is
#     absent. -> bench-boards.json, boards.dat, boards.png.
#  2. Scaling (scripts/bench_boards_curves.py): brain_mirrors and default at 1/512 (8x8x8
#     cells), 1 to 64 asynchronous boards as threads of one process (--loopback) over 1 GbE,
#     10 GbE and PCIe 4.0 x16; as MPI ranks too at 2, 4 and 8 boards, whose figures must be the
#     loopback's. -> curves.json, curves.txt, curves.png.
#  3. A camera path (brain_mirrors 1/64, 8 boards, orbiting 8 degrees a frame, 8 frames): per
#     frame the speed-up and balance with the k-d split and with the load rule (the assignment
#     from the previous frame's measured cycles). -> path.json, in curves.txt.
#  4. Scheduling across boards: `cube5 schedule` on brain_mirrors (SCHED_SIZE 32x32, 3x3x3
#     cells, SCHED_FRAMES 4 frames orbiting 2 degrees a frame) on SCHED_BOARDS ("1 2 4") boards:
#     per board count the fetches of all boards with Max Work and following the plan across
#     boards (the pooled Cell Tree's schedule; frames 1..), and the lower bounds summed over
#     frames: sched.txt and bench-boards-sched.json.
# Environment: SIZE (128x128), CELLS (4), BOARDS ("1 2 4 8"), RULES ("kd slab mod"), EXCHANGES
# ("async rounds"), SCENES (the built-in scenes), LINK_BW / LINK_LATENCY (MB/s, us; empty: the
# defaults), RENDER=0, CURVES=0 or SCHED=0 to skip a part.
set -euo pipefail
build=${1:-build}
cube5="$build/cube5"
out="$build/bench-boards"
data="$(cd "$(dirname "$0")/.." && pwd)/../shared/data/volumes"
SIZE=${SIZE:-128x128}
CELLS=${CELLS:-4}
BOARDS=${BOARDS:-1 2 4 8}
RULES=${RULES:-kd slab mod}
EXCHANGES=${EXCHANGES:-async rounds}
SCENES=${SCENES:-$("$cube5" scenes | awk '{print $1}')}
command -v gnuplot >/dev/null || bash "$(dirname "$0")/setup-deps.sh" gnuplot-nox
command -v mpirun >/dev/null || bash "$(dirname "$0")/setup-deps.sh" openmpi-bin libopenmpi-dev
# Open MPI refuses to start as root unless told; told for these runs only.
if [ "$(id -u)" -eq 0 ]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
export OMPI_MCA_btl=self,vader,tcp OMPI_MCA_btl_tcp_if_include=lo OMPI_MCA_oob_tcp_if_include=lo
link=()
[ -n "${LINK_BW:-}" ] && link+=(--link-bw "$LINK_BW")
[ -n "${LINK_LATENCY:-}" ] && link+=(--link-latency "$LINK_LATENCY")
mkdir -p "$out/runs"
cases=()
for s in $SCENES; do cases+=("$s|$s|"); done
if [ -f "$data/CThead_256x256x113_uint8.raw" ]; then
    cases+=("brain_mirrors+CThead|brain_mirrors|--volume $data/CThead_256x256x113_uint8.raw")
else
    echo "bench-boards: $data absent: brain_mirrors with the CThead volume not run" >&2
fi
list="$out/runs.list"
: >"$list"
[ "${RENDER:-1}" = 0 ] && cases=()
for c in "${cases[@]}"; do
    IFS='|' read -r label scene extra <<<"$c"
    for ex in $EXCHANGES; do
        for rule in $RULES; do
            for n in $BOARDS; do
                f="$out/runs/${label}_${rule}_${ex}_$n.json"
                # shellcheck disable=SC2086
                mpirun --oversubscribe -np "$n" "$cube5" render "$scene" $extra --model rtl --size "$SIZE" --frames 1 \
                    --cells "$CELLS" --boards "$n" --assign "$rule" --exchange "$ex" "${link[@]}" --json >"$f"
                echo "$label $rule $ex $n $f" >>"$list"
                echo "bench-boards: $label $rule $ex $n boards" >&2
            done
        done
    done
done
[ "${RENDER:-1}" = 0 ] || python3 - "$list" "$out" "$SIZE" "$CELLS" <<'PY'
import json, sys
lst, out, size, cells = sys.argv[1:5]
rows, one = [], {}
for line in open(lst):
    label, rule, ex, n, f = line.split()
    d = json.load(open(f))
    m = d["multi_board"]
    r = dict(scene=label, rule=rule, exchange=ex, boards=int(n), frame_cycles=m["frame_cycles"], frame_s=m["frame_s"],
             fetches=d["board"]["fetches"], link_bytes=m["link_bytes"], rounds=m["rounds"], balance=m["balance"],
             crc32=d["frames"][0]["crc32"],
             busy_max=max(b["busy_cycles"] for b in m["per_board"]),
             link_max=max(b["link_cycles"] for b in m["per_board"]))
    rows.append(r)
    if r["boards"] == 1:
        one[(label, rule, ex)] = r
for r in rows:
    base = one[(r["scene"], r["rule"], r["exchange"])]
    r["speedup"] = base["frame_cycles"] / r["frame_cycles"]
    r["fetches_x"] = r["fetches"] / base["fetches"]
    r["same_image"] = r["crc32"] == base["crc32"]
json.dump(dict(size=size, cells=cells, runs=rows), open(out + "/bench-boards.json", "w"), indent=1)
print("%-22s %-5s %-6s %6s %12s %8s %9s %7s %12s %7s %8s %5s" % ("scene", "rule", "exch", "boards", "frame cyc",
      "speedup", "fetches", "x one", "link bytes", "rounds", "balance", "image"))
for r in rows:
    print("%-22s %-5s %-6s %6d %12d %8.2f %9d %7.2f %12d %7d %8.3f %5s" % (r["scene"], r["rule"], r["exchange"],
          r["boards"], r["frame_cycles"], r["speedup"], r["fetches"], r["fetches_x"], r["link_bytes"], r["rounds"],
          r["balance"], "same" if r["same_image"] else "DIFF"))
with open(out + "/boards.dat", "w") as f:
    for scene in dict.fromkeys(r["scene"] for r in rows):
        f.write('"%s"\n' % scene)
        for r in rows:
            if r["scene"] == scene and r["rule"] == rows[0]["rule"] and r["exchange"] == rows[0]["exchange"]:
                f.write("%d %.4f %.4f %.4f\n" % (r["boards"], r["speedup"], r["fetches_x"], r["balance"]))
        f.write("\n\n")
if not all(r["same_image"] for r in rows):
    sys.exit("bench-boards: an image differs from one board's")
PY
rule0=${RULES%% *}
[ "${RENDER:-1}" = 0 ] || cat >"$out/boards.gp" <<GP
set terminal pngcairo size 1100,420 noenhanced
set output "$out/boards.png"
set multiplot layout 1,2 title "cube5: several boards, $SIZE, ${CELLS}x${CELLS}x${CELLS} cells, $rule0 assignment, ${EXCHANGES%% *} (modelled)"
set key top left
set xlabel "boards"
set logscale x 2
set xtics (1, 2, 4, 8)
set xrange [0.9:9]
set ylabel "speed-up of the frame time over one board"
plot for [i=0:*] "$out/boards.dat" index i using 1:2 with linespoints title columnheader(1), x with lines dt 2 title "linear"
set ylabel "cell fetches, x one board's"
plot for [i=0:*] "$out/boards.dat" index i using 1:3 with linespoints title columnheader(1)
unset multiplot
GP
[ "${RENDER:-1}" = 0 ] || gnuplot "$out/boards.gp"
[ "${RENDER:-1}" = 0 ] || echo "bench-boards: wrote $out/bench-boards.json and $out/boards.png" >&2

if [ "${CURVES:-1}" != 0 ]; then
    python3 "$(dirname "$0")/bench_boards_curves.py" --cube5 "$cube5" --out "$out" | tee "$out/curves.txt"
    cat >"$out/curves.gp" <<GP
set terminal pngcairo size 760,520 noenhanced
set output "$out/curves.png"
set title "cube5: asynchronous boards, 128x128, 8x8x8 cells, kd (modelled)"
set key top left
set xlabel "boards"
set ylabel "speed-up of the frame time over one board"
set logscale xy 2
set xtics (1, 2, 4, 8, 16, 32, 64)
set xrange [0.9:72]
plot for [i=0:*] "$out/curves.dat" index i using 1:2 with linespoints title columnheader(1), x with lines dt 2 title "linear"
GP
    gnuplot "$out/curves.gp"
    echo "bench-boards: wrote $out/curves.json, $out/path.json and $out/curves.png" >&2
fi

[ "${SCHED:-1}" = 0 ] && exit 0
SCHED_SIZE=${SCHED_SIZE:-32x32}
SCHED_FRAMES=${SCHED_FRAMES:-4}
SCHED_BOARDS=${SCHED_BOARDS:-1 2 4}
slist="$out/sched.list"
: >"$slist"
for n in $SCHED_BOARDS; do
    f="$out/runs/sched_brain_mirrors_$n.json"
    mpirun --oversubscribe -np "$n" "$cube5" schedule brain_mirrors --size "$SCHED_SIZE" --cells 3 \
        --frames "$SCHED_FRAMES" --orbit 2 --exact-states 1000 --local-window 0 --boards "$n" "${link[@]}" --json >"$f"
    echo "$n $f" >>"$slist"
    echo "bench-boards: schedule on $n boards" >&2
done
python3 - "$slist" "$out" <<'PY' | tee "$out/sched.txt"
import json, sys
rows = []
for line in open(sys.argv[1]):
    n, f = line.split()
    d = json.load(open(f))
    fr = d["frames"][1:]
    mb = [r["multi_board"] for r in fr]
    rows.append(dict(boards=int(n), frames=len(fr),
                     fetches_maxwork=sum(r["fetches_maxwork"] for r in fr),
                     fetches_celltree=sum(r["fetches_celltree"] for r in fr),
                     bound_sum=(None if any(m["lower_bound_sum"] is None for m in mb)
                                else sum(m["lower_bound_sum"] for m in mb)),
                     cycles_maxwork=sum(m["maxwork"]["frame_cycles"] for m in mb),
                     cycles_celltree=sum(m["celltree"]["frame_cycles"] for m in mb),
                     followed=[r["followed"] for r in fr]))
json.dump(rows, open(sys.argv[2] + "/bench-boards-sched.json", "w"), indent=1)
print("%6s %8s %9s %7s %14s %15s  %s" % ("boards", "maxwork", "celltree", "bound", "cycles maxwork",
      "cycles celltree", "followed (frames 1..)"))
for r in rows:
    print("%6d %8d %9d %7s %14d %15d  %s" % (r["boards"], r["fetches_maxwork"], r["fetches_celltree"],
          "-" if r["bound_sum"] is None else r["bound_sum"], r["cycles_maxwork"], r["cycles_celltree"],
          "; ".join(r["followed"])))
PY
