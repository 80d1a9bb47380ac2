#!/usr/bin/env python3
"""make bench-boards, the scaling part (docs/multi-board.md, "Scaling to 64 boards"): one frame on
1 to 64 asynchronous boards over each named link, the boards as threads of one process
(--loopback); on the first link also as MPI ranks up to --mpi boards, whose figures must equal
the loopback's. Then a camera path on 8 boards with the k-d split and with the load rule (the
assignment from the previous frame's measured cycles): per frame the speed-up over one board
and the balance.

  bench_boards_curves.py --cube5 BIN --out DIR [--scenes S] [--cells N] [--size WxH]
                         [--boards "1 2 ... 64"] [--links "1gbe 10gbe pcie4x16"] [--mpi "2 4 8"]
                         [--path-scene S] [--path-cells N] [--path-orbit DEG] [--path-frames N]

Writes DIR/curves.json, curves.dat, path.json and prints the tables; exit 1 when an image differs
from one board's or MPI and the loopback disagree."""
import argparse
import json
import os
import subprocess
import sys


def render(cube5, scene, size, cells, boards, extra, mpi=False):
    cmd = [cube5, "render", scene, "--model", "rtl", "--size", size, "--cells", str(cells), "--json"] + extra
    if boards > 1:
        cmd += ["--boards", str(boards)]
        if mpi:
            cmd = ["mpirun", "--oversubscribe", "-np", str(boards)] + cmd
        else:
            cmd += ["--loopback"]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("bench-boards: %s: exit %d: %s" % (" ".join(cmd), p.returncode, p.stderr.strip()[-500:]))
    return json.loads(p.stdout)


def frame_cycles(d):
    return d["multi_board"]["frame_cycles"] if "multi_board" in d else d["board"]["cycles"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cube5", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--scenes", default="brain_mirrors default")
    ap.add_argument("--cells", type=int, default=8)
    ap.add_argument("--size", default="128x128")
    ap.add_argument("--boards", default="1 2 4 8 16 32 64")
    ap.add_argument("--links", default="1gbe 10gbe pcie4x16")
    ap.add_argument("--mpi", default="2 4 8")
    ap.add_argument("--path-scene", default="brain_mirrors")
    ap.add_argument("--path-cells", type=int, default=4)
    ap.add_argument("--path-boards", type=int, default=8)
    ap.add_argument("--path-orbit", default="8")
    ap.add_argument("--path-frames", type=int, default=8)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    boards = [int(x) for x in a.boards.split()]
    links = a.links.split()
    mpi = [int(x) for x in a.mpi.split()]
    one_frame = ["--frames", "1"]
    rows, bad = [], []
    for scene in a.scenes.split():
        one = render(a.cube5, scene, a.size, a.cells, 1, one_frame)
        base, crc = frame_cycles(one), one["frames"][0]["crc32"]
        for link in links:
            for n in boards:
                d = one if n == 1 else render(a.cube5, scene, a.size, a.cells, n, one_frame + ["--link", link])
                m = d.get("multi_board", {})
                r = dict(scene=scene, link=link, boards=n, frame_cycles=frame_cycles(d),
                         speedup=base / frame_cycles(d), balance=m.get("balance", 1.0),
                         fetches=d["board"]["fetches"], link_bytes=m.get("link_bytes", 0),
                         same_image=d["frames"][0]["crc32"] == crc, mpi_agrees=None)
                if n > 1 and n in mpi and link == links[0]:
                    dm = render(a.cube5, scene, a.size, a.cells, n, one_frame + ["--link", link], mpi=True)
                    r["mpi_agrees"] = dm["multi_board"] == m and dm["frames"][0]["crc32"] == d["frames"][0]["crc32"]
                    if not r["mpi_agrees"]:
                        bad.append("%s %s %d boards: MPI %d cycles, loopback %d" % (
                            scene, link, n, dm["multi_board"]["frame_cycles"], m["frame_cycles"]))
                if not r["same_image"]:
                    bad.append("%s %s %d boards: the image differs from one board's" % (scene, link, n))
                rows.append(r)
                print("bench-boards: %s %s %d boards: %.2fx" % (scene, link, n, r["speedup"]), file=sys.stderr)
    print("%-16s %-9s %6s %12s %8s %8s %9s %12s %5s %4s" % ("scene", "link", "boards", "frame cyc", "speedup",
          "balance", "fetches", "link bytes", "image", "mpi"))
    for r in rows:
        print("%-16s %-9s %6d %12d %8.2f %8.3f %9d %12d %5s %4s" % (r["scene"], r["link"], r["boards"],
              r["frame_cycles"], r["speedup"], r["balance"], r["fetches"], r["link_bytes"],
              "same" if r["same_image"] else "DIFF", {None: "-", True: "=", False: "DIFF"}[r["mpi_agrees"]]))
    with open(os.path.join(a.out, "curves.dat"), "w") as f:
        for scene in a.scenes.split():
            for link in links:
                f.write('"%s %s"\n' % (scene, link))
                for r in rows:
                    if r["scene"] == scene and r["link"] == link:
                        f.write("%d %.4f %.4f\n" % (r["boards"], r["speedup"], r["balance"]))
                f.write("\n\n")

    # The camera path: per frame, one board, and the boards under kd and under the load rule.
    motion = ["--orbit", a.path_orbit, "--frames", str(a.path_frames)]
    one = render(a.cube5, a.path_scene, a.size, a.path_cells, 1, motion)
    path = {"scene": a.path_scene, "cells": a.path_cells, "boards": a.path_boards, "orbit_deg": float(a.path_orbit),
            "frames": []}
    runs = {rule: render(a.cube5, a.path_scene, a.size, a.path_cells, a.path_boards, motion + ["--assign", rule])
            for rule in ("kd", "load")}
    print("\npath: %s, 1/%d, %d boards, orbit %s degrees a frame" % (a.path_scene, a.path_cells ** 3, a.path_boards,
                                                                   a.path_orbit))
    print("%5s %12s %8s %8s %8s %8s" % ("frame", "one board", "kd x", "kd bal", "load x", "load bal"))
    for f in range(a.path_frames):
        c1 = one["frames"][f]["board"]["cycles"]
        row = {"frame": f, "one_board_cycles": c1}
        for rule, d in runs.items():
            m = d["frames"][f]["multi_board"]
            row[rule] = {"frame_cycles": m["frame_cycles"], "speedup": c1 / m["frame_cycles"], "balance": m["balance"]}
            if d["frames"][f]["crc32"] != one["frames"][f]["crc32"]:
                bad.append("path frame %d, %s: the image differs from one board's" % (f, rule))
        path["frames"].append(row)
        print("%5d %12d %8.2f %8.3f %8.2f %8.3f" % (f, c1, row["kd"]["speedup"], row["kd"]["balance"],
                                                  row["load"]["speedup"], row["load"]["balance"]))
    tot = {rule: sum(r[rule]["frame_cycles"] for r in path["frames"]) for rule in runs}
    t1 = sum(r["one_board_cycles"] for r in path["frames"])
    path["speedup"] = {rule: t1 / tot[rule] for rule in runs}
    print("%5s %12d %8.2f %8s %8.2f" % ("all", t1, path["speedup"]["kd"], "", path["speedup"]["load"]))
    json.dump(dict(size=a.size, cells=a.cells, runs=rows), open(os.path.join(a.out, "curves.json"), "w"), indent=1)
    json.dump(path, open(os.path.join(a.out, "path.json"), "w"), indent=1)
    if bad:
        sys.exit("bench-boards: " + "; ".join(bad))


if __name__ == "__main__":
    main()
