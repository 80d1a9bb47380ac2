#!/usr/bin/env bash
# make bench-sched: the Cell Tree against Max Work while the camera moves (docs/cell-tree.md,
# "Camera motion"). For every scene, split and camera motion (orbits of SPEEDS degrees a
# frame about the target, and seeded random jumps), `cube5 schedule` renders FRAMES frames
# twice a frame (Max Work; and following the schedule the DSP made from the previous frame's
# tree) once per split rule. Frames 1..N-1 are counted (frame 0 has no previous tree).
# Per run: fetches with Max Work and following the rule, the worst frame against Max Work,
# the frames beyond the certificate's bound (Max Work + budget), and the sum over frames of
# each frame's proven lower bound and best known schedule (the optimum when proven) from
# the frame's own tree: no order of loads, whatever chose it, fetches fewer than that
# frame's optimum.
# Writes BUILD/bench-sched/: runs/*.json (cube5 schedule --json), bench-sched.json (the
# table), table.md (the table of docs/results/cell-tree-studies.md, "Camera speed"), sched_motion.dat and
# sched_motion.png (fetches in % of Max Work against degrees a frame, one panel per scene and
# split). With ../shared/data/volumes/ present, also
# brain_mirrors with the CThead CT volume and lobster_tunnel with the lobster CT volume.
# Environment: SIZE (128x128), FRAMES (8), CELLS ("2 3"), SPEEDS ("0 2 8 30 90"), JUMPS
# (the jump motion's --jumps value, "7:3"; empty: none), RULES (below), SCENES (the built-in
# scenes), EXACT_STATES (20000: the exact search's budget per frame, run once per
# configuration, on the first rule's run; the best known schedule is the beam search's or
# the unbudgeted window rule's, --local-window 0), REUSE (1: keep the runs already written),
# FAMILY_SEED (2) and FAMILY_PATHS (60): the generated family of camera paths; TREE_RAM (1):
# the real memory fractions and the scale table (scripts/tree_ram_bench.py), run last.
set -euo pipefail
build=${1:-build}
cube5="$build/cube5"
out="$build/bench-sched"
data="$(cd "$(dirname "$0")/.." && pwd)/../shared/data/volumes"
SIZE=${SIZE:-128x128}
FRAMES=${FRAMES:-8}
CELLS=${CELLS:-2 3}
SPEEDS=${SPEEDS:-0 2 8 30 90}
JUMPS=${JUMPS-7:3}
EXACT_STATES=${EXACT_STATES:-20000}
SCENES=${SCENES:-$("$cube5" scenes | awk '{print $1}')}
# The paper's rule, the rollout (the best rule without a budget) and the window rule (the
# default: the DSP's budget); RULES=all: every rule of the --split line of the help.
RULES=${RULES:-paper rollout window}
if [ "$RULES" = all ]; then
    RULES=$("$cube5" schedule --help | sed -n 's/.*\[--split \([a-z|]*\)\].*/\1/p' | tr '|' ' ')
fi
command -v gnuplot >/dev/null || bash "$(dirname "$0")/setup-deps.sh" gnuplot-nox
mkdir -p "$out/runs"
list="$out/runs.list"
: > "$list"

# Cases: "label|scene|extra args" (extra: a --volume replacing the stand-in).
cases=()
for s in $SCENES; do cases+=("$s|$s|"); done
if [ -f "$data/CThead_256x256x113_uint8.raw" ] && [ -f "$data/lobster_301x324x56_uint8.raw" ]; then
    cases+=("brain_mirrors+CThead|brain_mirrors|--volume $data/CThead_256x256x113_uint8.raw")
    cases+=("lobster_tunnel+lobster|lobster_tunnel|--volume $data/lobster_301x324x56_uint8.raw")
else
    echo "bench-sched: ../shared/data/volumes/ not found: the real CT volumes are left out" >&2
fi
motions=()
for d in $SPEEDS; do motions+=("orbit$d|--orbit $d"); done
[ -n "$JUMPS" ] && motions+=("jumps|--orbit 2 --jumps $JUMPS")

for c in "${cases[@]}"; do
    IFS='|' read -r label scene extra <<< "$c"
    for cells in $CELLS; do
        for m in "${motions[@]}"; do
            IFS='|' read -r mname margs <<< "$m"
            first=1
            for rule in $RULES; do
                states=0
                [ "$first" = 1 ] && states=$EXACT_STATES
                first=0
                f="$out/runs/${label}_c${cells}_${mname}_${rule}.json"
                echo "$label|$cells|$mname|$rule|$f" >> "$list"
                # REUSE=1: keep the runs already in BUILD/bench-sched/runs (a replot).
                [ "${REUSE:-0}" = 1 ] && [ -s "$f" ] && continue
                echo "bench-sched: $label cells $cells $mname $rule" >&2
                # shellcheck disable=SC2086 # extra and margs are lists of arguments
                "$cube5" schedule "$scene" $extra --cells "$cells" --size "$SIZE" --frames "$FRAMES" $margs \
                    --split "$rule" --exact-states "$states" --local-window 0 --json > "$f"
            done
        done
    done
done

python3 - "$list" "$out" "$SIZE" "$FRAMES" <<'PY'
import json, math, sys
lst, out, size, frames = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
rows, bounds = [], {}
for line in open(lst):
    label, cells, motion, rule, path = line.rstrip("\n").split("|")
    d = json.load(open(path))
    fr = d["frames"][1:]
    mw = sum(f["fetches_maxwork"] for f in fr)
    ct = sum(f["fetches_celltree"] for f in fr)
    # A frame beyond the certificate's bound: Max Work plus its budget (0 when the budget is
    # negative or the frame is identical to its tree's; docs/cell-tree.md, "The certificate").
    def limit(f):
        c = f.get("certificate")
        if c is None or c["broken"]:
            return None
        return f["fetches_maxwork"] + (0 if c["identical"] else max(c["budget"], 0))
    over = [f for f in fr if limit(f) is not None and f["fetches_celltree"] > limit(f)]
    worst = max((100.0 * (f["fetches_celltree"] - f["fetches_maxwork"]) / f["fetches_maxwork"]
                 for f in fr if f["fetches_maxwork"]), default=0.0)
    key = (label, int(cells), motion)
    if d.get("exact_states", 0) > 0:
        lb = sum(f["lower_bound"] for f in fr)
        best = [f["optimum"] if f["optimum"] is not None else f["best_known"] for f in fr]
        bounds[key] = {"lower_bound": lb, "best_known": sum(best) if all(b is not None for b in best) else None,
                       "optimum_frames": sum(1 for f in fr if f["optimum"] is not None)}
    rows.append({"case": label, "cells": int(cells), "motion": motion, "rule": rule, "frames": len(fr),
                 "fetches_maxwork": mw, "fetches_celltree": ct,
                 "saving_pct": 100.0 * (mw - ct) / mw if mw else 0.0, "worst_frame_pct": worst,
                 "frames_over_limit": len(over), "switches": sum(1 for f in fr if f.get("switched_at_load") is not None)})
for r in rows:
    r.update(bounds.get((r["case"], r["cells"], r["motion"]), {}))
json.dump({"size": size, "frames": frames, "runs": rows}, open(out + "/bench-sched.json", "w"), indent=1)

print("%-24s %5s %8s %-10s %8s %8s %8s %8s %6s %8s %8s" % (
    "case (frames 1..N-1)", "cells", "motion", "rule", "MaxWork", "rule", "saving", "worst fr", "over", "bound",
    "best"))
for r in rows:
    print("%-24s %5d %8s %-10s %8d %8d %7.1f%% %7.1f%% %6d %8s %8s" % (
        r["case"], r["cells"], r["motion"], r["rule"], r["fetches_maxwork"], r["fetches_celltree"], r["saving_pct"],
        r["worst_frame_pct"], r["frames_over_limit"], r.get("lower_bound", "-"), "-" if r.get("best_known") is None else r["best_known"]))
# docs/results/cell-tree-studies.md's table ("Camera speed"): per case, memory fraction and rule, the path's
# fetches against Max Work's per motion; bold: a frame beyond the limit or the path over Max
# Work; "(none)": no fetch; then the sum of the proven bounds.
motions = list(dict.fromkeys(r["motion"] for r in rows))
cases = list(dict.fromkeys((r["case"], r["cells"]) for r in rows))
names = {"orbit0": "still", "jumps": "jumps"}
with open(out + "/table.md", "w") as md:
    heads = [names.get(m, m.replace("orbit", "") + " deg") for m in motions]
    md.write("| case | memory | rule | " + " | ".join(heads) + " |\n|---|---|---|" + "---|" * len(motions) + "\n")
    for case, cells in cases:
        mem = "1/%d" % cells ** 3
        label = case.replace("+", " + ")
        for rule in dict.fromkeys(r["rule"] for r in rows if (r["case"], r["cells"]) == (case, cells)):
            cols = []
            for m in motions:
                r = next(x for x in rows if (x["case"], x["cells"], x["motion"], x["rule"]) == (case, cells, m, rule))
                mw, ct = r["fetches_maxwork"], r["fetches_celltree"]
                v = "(none)" if mw == 0 else "0 %" if ct == mw else "%+.1f %%" % (100.0 * (ct - mw) / mw)
                cols.append("**%s**" % v if ct > mw else v)
            md.write("| %s | %s | %s | %s |\n" % (label, mem, rule, " | ".join(cols)))
        cols = []
        for m in motions:
            r = next(x for x in rows if (x["case"], x["cells"], x["motion"]) == (case, cells, m))
            lb = r.get("lower_bound")
            cols.append("(none)" if not r["fetches_maxwork"] else "-" if lb is None
                        else "%+.0f %%" % (100.0 * (lb - r["fetches_maxwork"]) / r["fetches_maxwork"]))
        md.write("| %s | %s | proven bound | %s |\n" % (label, mem, " | ".join(cols)))

print("  (%s, frames 1..%d of %d, each following the previous frame's tree; saving: fewer fetches than Max Work"
      % (size, frames - 1, frames))
print("   over the path; worst fr: the worst single frame against Max Work, + is more fetches; over: frames beyond")
print("   the certificate's bound (Max Work + budget); bound, best: sums of each frame's proven lower bound and best known")
print("   schedule, the optimum where proven)")
bad = [r for r in rows if r["frames_over_limit"]]
print("bench-sched: %d of %d runs with a frame beyond the certificate's bound; %d end over Max Work (by at most one allowance)"
      % (len(bad), len(rows), sum(1 for r in rows if r["saving_pct"] < 0)))

# The plot's data: one block per (case, cells), rows by degrees a frame, columns per rule.
rules = sorted({r["rule"] for r in rows}, key=[r["rule"] for r in rows].index)
panels = sorted({(r["case"], r["cells"]) for r in rows}, key=[(r["case"], r["cells"]) for r in rows].index)
with open(out + "/sched_motion.dat", "w") as f:
    f.write("# deg/frame, then per rule: fetches in %% of Max Work (frames 1..N-1); bound %%; best %%\n")
    f.write("# rules: %s\n" % " ".join(rules))
    for case, cells in panels:
        f.write('"%s 1/%d"\n' % (case.replace("_", "\\\\_"), cells ** 3))
        for r0 in [r for r in rows if r["case"] == case and r["cells"] == cells and r["rule"] == rules[0]]:
            if not r0["motion"].startswith("orbit"):
                continue
            # A path whose frames see no volume (the eye behind a mirror) fetches nothing.
            mw = r0["fetches_maxwork"]
            pct = lambda v: "%.2f" % (100.0 * v / mw) if v is not None and mw else "NaN"
            vals = [next(r for r in rows if r["case"] == case and r["cells"] == cells and r["motion"] == r0["motion"]
                         and r["rule"] == rule)["fetches_celltree"] for rule in rules]
            f.write("%s %s %s %s\n" % (r0["motion"][5:], " ".join(pct(v) for v in vals), pct(r0.get("lower_bound")),
                                       pct(r0.get("best_known"))))
        f.write("\n\n")
with open(out + "/sched_motion.gp", "w") as g:
    n = len(panels)
    cols = 2 if n > 1 else 1
    nrows = (n + cols - 1) // cols
    g.write('set terminal pngcairo size %d,%d font "sans,9"\nset output "%s/sched_motion.png"\n'
            % (520 * cols, 330 * nrows, out))
    g.write('set multiplot layout %d,%d title "Cell fetches in %% of Max Work against camera speed (%s, frames 1..%d)"\n'
            % (nrows, cols, size, frames - 1))
    g.write('set grid\nset xlabel "degrees a frame"\nset ylabel "% of Max Work"\nset key bottom right font ",7"\n')
    g.write("set logscale x 2\nset xrange [0.7:128]\nset offsets 0, 0, graph 0.08, graph 0.05\n")
    for i, (case, cells) in enumerate(panels):
        g.write('set title "%s, 1/%d"\n' % (case.replace("_", "\\\\_"), cells ** 3))
        # degree 0 (still) drawn at 1 on the log axis
        cols_ = ['"%s/sched_motion.dat" index %d using ($1 < 1 ? 1 : $1):%d title "%s" with linespoints lw 2'
                 % (out, i, 2 + k, rule) for k, rule in enumerate(rules)]
        cols_.append('"" index %d using ($1 < 1 ? 1 : $1):%d title "proven bound" with lines dt 2 lc "black"'
                     % (i, 2 + len(rules)))
        cols_.append('"" index %d using ($1 < 1 ? 1 : $1):%d title "best known" with lines dt 3 lc "gray30"'
                     % (i, 3 + len(rules)))
        g.write("plot 100 title \"Max Work\" lc \"red\" lw 1, " + ", ".join(cols_) + "\n")
    g.write("unset multiplot\n")
PY
gnuplot "$out/sched_motion.gp"
echo "bench-sched: wrote $out/bench-sched.json and $out/sched_motion.png" >&2

# The family (docs/cell-tree.md, "The family"): FAMILY_PATHS camera paths from FAMILY_SEED,
# nobody tuned on, the board against the unchecked rule; FAMILY_PATHS=0 skips it.
if [ "${FAMILY_PATHS:-60}" -gt 0 ]; then
    vols=()
    [ -d "$data" ] && vols=(--volumes "$data")
    python3 "$(dirname "$0")/sched_family.py" --seed "${FAMILY_SEED:-2}" --paths "${FAMILY_PATHS:-60}" \
        --out "$out/family" "${vols[@]}"
    python3 "$(dirname "$0")/sched_family_run.py" --cube5 "$cube5" --family "$out/family" --size "$SIZE" \
        --frames "$FRAMES" --json "$out/family.json"
    echo "bench-sched: wrote $out/family.json" >&2
fi

# Real memory fractions (docs/cell-tree.md, "Where the tree lives"): still cameras at 1/512
# and 1/4096 on the mirrored scenes, the board as it ships against the tree kept on chip, and
# the scale table of every built-in scene from 1/8 to 1/4096 (Max Work, the board, the proven
# bound). TREE_RAM=0 skips them.
if [ "${TREE_RAM:-1}" = 1 ]; then
    python3 "$(dirname "$0")/tree_ram_bench.py" --cube5 "$cube5" --size "$SIZE" \
        --json "$out/tree_ram.json" --table "$out/tree_ram.md"
    python3 "$(dirname "$0")/tree_ram_bench.py" --cube5 "$cube5" --size "$SIZE" --frames 3 --rams auto \
        --scenes "$("$cube5" scenes | awk '{print $1}' | tr '\n' ' ')" --cells "2 3 4 8 16" \
        --extra "--exact-states 20000 --local-window 0" --json "$out/scale.json" --table "$out/scale.md"
    echo "bench-sched: wrote $out/tree_ram.json and $out/scale.json" >&2
fi
