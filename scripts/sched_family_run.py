#!/usr/bin/env python3
"""Runs a family of camera paths (sched_family.py) through `cube5 schedule` twice each: the
board as it ships (the certificate on) and the paper's board (`--stale-check off`: the same
rule followed with no check), and reports per path the saving against Max Work of each, the
part of the unchecked saving the board keeps, and the certificate's bound frame by frame.

  sched_family_run.py --cube5 BIN --family DIR --size WxH --frames N [--jobs J] [--json FILE]

Checks, whatever the numbers (exit 1 naming the path and frame when one fails):
  - every frame: fetches <= Max Work's + the frame's budget (the path's bank + one allowance, 0 when
    that is negative);
  - every frame: Max Work's fetches found by the board's shadow == those of the Max Work run;
  - every path: the bank never falls below minus one allowance.
The kept fraction is reported (and judged by the caller: --min-kept)."""
import argparse
import concurrent.futures as cf
import json
import subprocess
import sys


def run(cube5, scene, cells, motion, size, frames, off):
    cmd = [cube5, "schedule", scene, "--cells", str(cells), "--size", size, "--frames", str(frames),
           "--exact-states", "0", "--local-window", "0", "--json"] + motion.split()
    if off:
        cmd += ["--stale-check", "off"]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError("%s: exit %d: %s" % (" ".join(cmd), p.returncode, p.stderr.strip()))
    return json.loads(p.stdout)


def path_result(row, on, off):
    fr_on, fr_off = on["frames"][1:], off["frames"][1:]
    mw = sum(f["fetches_maxwork"] for f in fr_on)
    ct = sum(f["fetches_celltree"] for f in fr_on)
    un = sum(f["fetches_celltree"] for f in fr_off)
    problems = []
    for f in fr_on:
        c = f.get("certificate")
        if c is None:
            continue
        if c["broken"]:
            problems.append("frame %d: the shadow broke" % f["frame"])
            continue
        # below 0: no load past the shadow's; a frame identical to the tree's: the exact replay's
        # choice. Either makes at most Max Work's fetches.
        budget = 0 if c["identical"] else max(c["budget"], 0)
        if f["fetches_celltree"] > f["fetches_maxwork"] + budget:
            problems.append("frame %d: %d fetches > Max Work %d + budget %d" % (
                f["frame"], f["fetches_celltree"], f["fetches_maxwork"], budget))
        if c["maxwork_fetches"] != f["fetches_maxwork"]:
            problems.append("frame %d: the shadow found %d Max Work fetches, the Max Work run made %d" % (
                f["frame"], c["maxwork_fetches"], f["fetches_maxwork"]))
    saving_on = mw - ct
    saving_off = mw - un
    return {
        "id": row["id"], "scene": row["scene"], "cells": row["cells"], "motion": row["motion"], "desc": row["desc"],
        "frames": len(fr_on), "fetches_maxwork": mw, "fetches_board": ct, "fetches_unchecked": un,
        "saving_board_pct": 100.0 * saving_on / mw if mw else 0.0,
        "saving_unchecked_pct": 100.0 * saving_off / mw if mw else 0.0,
        "kept": saving_on / saving_off if saving_off > 0 else None,
        "over_maxwork": ct > mw,
        "frames_followed": sum(1 for f in fr_on if f.get("certificate")),
        "problems": problems,
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cube5", required=True)
    ap.add_argument("--family", required=True)
    ap.add_argument("--size", default="128x128")
    ap.add_argument("--frames", type=int, default=8)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--json", default="")
    ap.add_argument("--min-kept", type=float, default=-1, help="exit 1 when the family keeps less (0..1)")
    ap.add_argument("--min-saving", type=float, default=5.0, help="paths whose unchecked saving is at least this %%")
    a = ap.parse_args()
    rows = []
    for line in open(a.family + "/family.tsv"):
        i, scene, cells, motion, desc = line.rstrip("\n").split("\t")
        rows.append({"id": int(i), "scene": scene, "cells": int(cells), "motion": motion, "desc": desc})
    with cf.ThreadPoolExecutor(max_workers=a.jobs) as ex:
        futs = {(r["id"], off): ex.submit(run, a.cube5, r["scene"], r["cells"], r["motion"], a.size, a.frames, off)
                for r in rows for off in (False, True)}
        try:
            res = [path_result(r, futs[(r["id"], False)].result(), futs[(r["id"], True)].result()) for r in rows]
        except RuntimeError as e:
            print("sched_family_run: %s" % e, file=sys.stderr)
            sys.exit(1)
    judged = [r for r in res if r["saving_unchecked_pct"] >= a.min_saving]
    kept = sorted(r["kept"] for r in judged)
    tot_on = sum(r["fetches_maxwork"] - r["fetches_board"] for r in judged)
    tot_off = sum(r["fetches_maxwork"] - r["fetches_unchecked"] for r in judged)
    summary = {
        "paths": len(res), "judged": len(judged), "min_saving_pct": a.min_saving,
        "kept_min": kept[0] if kept else None,
        "kept_median": kept[len(kept) // 2] if kept else None,
        "kept_total": tot_on / tot_off if tot_off > 0 else None,
        "paths_kept_90": sum(1 for k in kept if k >= 0.9),
        "paths_over_maxwork": sum(1 for r in res if r["over_maxwork"]),
        "unchecked_over_maxwork": sum(1 for r in res if r["fetches_unchecked"] > r["fetches_maxwork"]),
        "problems": sum(len(r["problems"]) for r in res),
    }
    print("%4s %-70s %6s %7s %7s %6s" % ("path", "scene and motion", "MW", "board", "unchkd", "kept"))
    for r in res:
        print("%4d %-70s %6d %6.1f%% %6.1f%% %6s%s" % (
            r["id"], r["desc"][:70], r["fetches_maxwork"], r["saving_board_pct"], r["saving_unchecked_pct"],
            "-" if r["kept"] is None else "%.0f%%" % (100 * r["kept"]), " OVER MAX WORK" if r["over_maxwork"] else ""))
        for p in r["problems"]:
            print("     PROBLEM: %s" % p)
    w = min(judged, key=lambda r: r["kept"]) if judged else None
    print("family: %d paths, %d where the unchecked rule saves >= %g%%; kept: total %s, median %s, worst %s%s; "
          "%d of %d keep >= 90%%; paths over Max Work: board %d, unchecked %d" % (
              len(res), len(judged), a.min_saving,
              "-" if summary["kept_total"] is None else "%.1f%%" % (100 * summary["kept_total"]),
              "-" if summary["kept_median"] is None else "%.1f%%" % (100 * summary["kept_median"]),
              "-" if w is None else "%.1f%%" % (100 * w["kept"]), "" if w is None else " (path %d)" % w["id"],
              summary["paths_kept_90"], len(judged), summary["paths_over_maxwork"], summary["unchecked_over_maxwork"]))
    if a.json:
        with open(a.json, "w") as fh:
            json.dump({"size": a.size, "frames": a.frames, "summary": summary, "paths": res}, fh, indent=1)
    bad = summary["problems"] > 0
    if a.min_kept >= 0 and summary["kept_total"] is not None and summary["kept_total"] < a.min_kept:
        print("sched_family_run: the family keeps %.1f%% of the unchecked saving, below %.0f%%" % (
            100 * summary["kept_total"], 100 * a.min_kept), file=sys.stderr)
        bad = True
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
