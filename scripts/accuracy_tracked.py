#!/usr/bin/env python3
"""make accuracy: the deterministic part of one `cube5 sweep` folder, for docs/accuracy/.

Usage: accuracy_tracked.py FULL_DIR OUT_DIR
FULL_DIR is the sweep's own output (sweep.csv, sweep.txt; build/accuracy/NAME, untracked):
its host seconds and the host-time Pareto front change from run to run. OUT_DIR gets
sweep.csv without the columns host_s and pareto_host, sweep.txt without the host-time column,
the reference's seconds and the H flags, and sweep.png drawn from the tracked CSV alone
(error against samples, and against modelled board time): running make accuracy twice
leaves the tracked files unchanged.
"""
import csv
import os
import re
import subprocess
import sys

full, out = sys.argv[1], sys.argv[2]
os.makedirs(out, exist_ok=True)

with open(os.path.join(full, "sweep.csv"), newline="") as f:
    rows = list(csv.DictReader(f))
keep = [c for c in rows[0].keys() if c not in ("host_s", "pareto_host")] if rows else []
with open(os.path.join(out, "sweep.csv"), "w", newline="") as f:
    wr = csv.DictWriter(f, fieldnames=keep, extrasaction="ignore", lineterminator="\n")
    wr.writeheader()
    wr.writerows(rows)

# sweep.txt: fixed-width rows; the host column is cut at the header's "host s" span and the
# Pareto flags keep B (board) only.
lines = open(os.path.join(full, "sweep.txt")).read().split("\n")
cut = None
text = []
for ln in lines:
    if cut is None and "host s" in ln and "board s" in ln:
        end = ln.index("host s") + len("host s")
        start = ln.rindex("  ", 0, ln.index("host s")) if "  " in ln[: ln.index("host s")] else 0
        cut = (start, end)
    if ln.lstrip().startswith("wrote "):
        continue  # names the untracked folder
    if ln.lstrip().startswith("("):
        ln = re.sub(r"host time H, ", "", ln)
    elif cut and len(ln) >= cut[1] and ln.startswith("  ") and not ln.startswith("   "):
        ln = ln[: cut[0]] + ln[cut[1]:]
        ln = re.sub(r"\s+[HB]{0,2}$", lambda m: m.group(0).replace("H", " "), ln).rstrip()
    ln = re.sub(r" \(\d+(\.\d+)? s\)", "", ln)
    text.append(ln)
with open(os.path.join(out, "sweep.txt"), "w") as f:
    f.write("\n".join(text))

title = lines[0].replace("_", " ") if lines else "cube5 sweep"
gp = f"""set terminal pngcairo size 1400,620 font 'sans,10'
set output '{os.path.join(out, "sweep.png")}'
set datafile separator ','
set logscale xy
set grid
set format x '%g'
set format y '%.0e'
set ylabel 'RMSE against the reference (peak 1.0)'
set key outside right top box font ',9'
set multiplot layout 1,2 title '{title} (deterministic figures; host times: build/accuracy/)'
set xlabel 'samples'
plot '{os.path.join(out, "sweep.csv")}' using (strcol(4) eq 'cref' && strcol(5) eq 'ok' ? $10 : NaN):7 with points pt 7 title 'cref', \\
     '' using (strcol(4) eq 'model' && strcol(5) eq 'ok' ? $10 : NaN):7 with points pt 5 title 'model', \\
     '' using (strcol(4) eq 'cast' && strcol(5) eq 'ok' ? $10 : NaN):7 with points pt 9 title 'caster'
set xlabel 'modelled board time (s, 100 MHz)'
plot '{os.path.join(out, "sweep.csv")}' using (strcol(4) eq 'model' && strcol(5) eq 'ok' ? $9 : NaN):7 with points pt 5 title 'model', \\
     '' using (strcol(4) eq 'model' && strcol(5) eq 'ok' && $11 == 1 ? $9 : NaN):7 with points pt 6 ps 2.5 lc rgb '#000000' title 'Pareto front (board)'
unset multiplot
"""
subprocess.run(["gnuplot"], input=gp, text=True, check=True)
