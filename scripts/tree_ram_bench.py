#!/usr/bin/env python3
"""Where the Cell Tree lives, at real memory fractions (docs/cell-tree.md, "Where the tree
lives"): still cameras on the mirrored scenes at 1/512 and 1/4096 of the volume in board
memory, the board as it ships (--tree-ram auto) against the tree kept in the 96 KB on chip
(--tree-ram onchip: groups of cells after an overflow).

  tree_ram_bench.py --cube5 BIN [--scenes "brain_mirrors default"] [--cells "8 16"]
                    [--size 128x128] [--frames 5] [--rams "auto onchip"] [--jobs 2]
                    [--json FILE] [--table FILE] [--target PCT] [--extra "OPTIONS"]

Per run, over the frames that follow a schedule (1..N-1): Max Work's fetches, the board's,
the sum of each frame's proven lower bound (its own tree's, tree_analysis.h: no order of loads
serves the frame with fewer),
the saving per frame, the tree's bytes, the DSP's operations between frames (the next frame
waits for them) and during the frame (the refinement), and the frame time with the DSP's
wait against Max Work's. --target: exit 1 when an auto run saves less than PCT over the
frames that follow a schedule (1..N-1)."""
import argparse
import concurrent.futures as cf
import json
import subprocess
import sys

MIPS = 255e6


def run(cube5, scene, cells, size, frames, ram, extra):
    cmd = [cube5, "schedule", scene, "--cells", str(cells), "--still", "--frames", str(frames), "--size", size,
           "--tree-ram", ram, "--json"] + extra.split()
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError("%s: exit %d: %s" % (" ".join(cmd), p.returncode, p.stderr.strip()))
    return " ".join(cmd), json.loads(p.stdout)


def summarize(cmd, scene, cells, ram, d):
    fr = d["frames"]
    follow = fr[1:]
    mw = sum(f["fetches_maxwork"] for f in follow)
    ct = sum(f["fetches_celltree"] for f in follow)
    late = fr[2:]
    mw2 = sum(f["fetches_maxwork"] for f in late)
    ct2 = sum(f["fetches_celltree"] for f in late)
    # The next frame waits for the DSP's work between frames; the refinement runs during it.
    wait = [fr[k - 1]["dsp_ops_schedule"] / MIPS for k in range(1, len(fr))]
    t_ct = sum(f["board_s_celltree"] for f in follow) + sum(wait)
    t_mw = sum(f["board_s_maxwork"] for f in follow)
    # The proven bound on each frame's loads: its own tree's (the frame's fetches are a
    # schedule of it), else the unbounded instrument's sum of maxGen; None when neither.
    bounds = [f["lower_bound"] if f["lower_bound"] is not None else f["lower_bound_demand"] for f in follow]
    return {
        "command": cmd, "scene": scene, "cells": cells ** 3, "tree_ram": ram,
        "rams": sorted({f["tree_ram"] for f in fr}), "groups": sorted({f["tree_group"] for f in fr}),
        "fetches_maxwork": mw, "fetches_board": ct,
        "lower_bound": None if None in bounds else sum(bounds), "fewer_pct": 100.0 * (mw - ct) / mw if mw else 0.0,
        "fewer_pct_from_frame2": 100.0 * (mw2 - ct2) / mw2 if mw2 else 0.0,
        "fewer_pct_per_frame": [100.0 * (f["fetches_maxwork"] - f["fetches_celltree"]) / f["fetches_maxwork"]
                                for f in follow],
        "tree_bytes_max": max(f["tree_bytes"] for f in fr),
        "dsp_wait_ms_max": 1e3 * max(wait) if wait else 0.0,
        "dsp_refine_ops_max": max((f["refined"]["dsp_ops"] for f in fr if f.get("refined")), default=0),
        "frame_s_board": t_ct, "frame_s_maxwork": t_mw,
    }


def table(rows):
    out = ["| scene | cells | tree | Max Work | board | bound | fewer | per frame 1..N-1 | from frame 2 | tree bytes "
           "| DSP between frames | frame time vs Max Work |",
           "|---|---:|---|---:|---:|---:|---:|---|---:|---:|---:|---:|"]
    for r in rows:
        where = "+".join(r["rams"]) + ("" if r["groups"] == [1] else ", groups " + "/".join(map(str, r["groups"])))
        out.append("| %s | %d | %s: %s | %d | %d | %s | %.1f%% | %s | %.1f%% | %s | %.0f ms | %.1f%% |" % (
            r["scene"], r["cells"], r["tree_ram"], where, r["fetches_maxwork"], r["fetches_board"],
            "-" if r["lower_bound"] is None else str(r["lower_bound"]), r["fewer_pct"],
            " ".join("%.1f" % x for x in r["fewer_pct_per_frame"]), r["fewer_pct_from_frame2"],
            "{:,}".format(r["tree_bytes_max"]), r["dsp_wait_ms_max"],
            100.0 * (r["frame_s_board"] - r["frame_s_maxwork"]) / r["frame_s_maxwork"]))
    return "\n".join(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cube5", required=True)
    ap.add_argument("--scenes", default="brain_mirrors default")
    ap.add_argument("--cells", default="8 16")
    ap.add_argument("--size", default="128x128")
    ap.add_argument("--frames", type=int, default=5)
    ap.add_argument("--rams", default="auto onchip")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--json")
    ap.add_argument("--table")
    ap.add_argument("--target", type=float)
    ap.add_argument("--extra", default="", help="more cube5 schedule options, e.g. '--volume FILE'")
    a = ap.parse_args()
    if a.frames < 3:
        ap.error("--frames: at least 3 (frame 0 runs Max Work, frame 2 is the first the DSP refined)")
    cases = [(s, int(c), r) for s in a.scenes.split() for c in a.cells.split() for r in a.rams.split()]
    with cf.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as ex:
        futs = [ex.submit(run, a.cube5, s, c, a.size, a.frames, r, a.extra) for s, c, r in cases]
        try:
            rows = [summarize(*f.result()[:1], s, c, r, f.result()[1]) for f, (s, c, r) in zip(futs, cases)]
        except RuntimeError as e:
            print("tree_ram_bench: %s" % e, file=sys.stderr)
            return 1
    text = table(rows)
    print(text)
    if a.table:
        with open(a.table, "w") as f:
            f.write(text + "\n")
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"size": a.size, "frames": a.frames, "runs": rows}, f, indent=1)
    if a.target is not None:
        low = [r for r in rows if r["tree_ram"] == "auto" and r["fewer_pct"] < a.target]
        for r in low:
            print("tree_ram_bench: %s at %d cells saves %.1f%% over frames 1..N-1, under the target %.1f%%"
                  % (r["scene"], r["cells"], r["fewer_pct"], a.target), file=sys.stderr)
        if low:
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
