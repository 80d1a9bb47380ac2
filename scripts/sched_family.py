#!/usr/bin/env python3
"""A family of camera paths for the Cell Tree, made from a seed (docs/cell-tree.md, "The
family"): scenes nobody tuned the board on, for `make bench-sched` and the family test.

Each path is a scene file (a volume from a generator, or a real CT volume from --volumes
when given, 0 to 4 mirrors around the camera's orbit with facing pairs among them, 0 to 2
glass spheres, an optional mirror floor, one light) and a camera motion (an orbit of 1 to 90
degrees a frame, log-uniform, with cuts or a dolly on some paths) at 1/8 or 1/27 of the
volume. The same seed gives the same family, byte for byte.

  sched_family.py --seed S --paths N --out DIR [--volumes DIR] [--max-bounces B]

writes DIR/pNNN.json and DIR/family.tsv (id, scene, cells, motion arguments, description).
Exit 2 on bad arguments."""
import argparse
import json
import math
import os
import random
import sys

# Real volumes (../shared/data/volumes): file name -> (dims, a transfer function's lower edge).
REAL = {
    "CThead_256x256x113_uint8.raw": ((256, 256, 113), 40),
    "lobster_301x324x56_uint8.raw": ((301, 324, 56), 40),
    "engine_256x256x128_uint8.raw": ((256, 256, 128), 60),
    "vis_male_128x256x256_uint8.raw": ((128, 256, 256), 40),
    "tooth_103x94x161_uint8.raw": ((103, 94, 161), 40),
    "teddybear_128x128x62_uint8.raw": ((128, 128, 62), 30),
    "neghip_64x64x64_uint8.raw": ((64, 64, 64), 30),
    "fuel_64x64x64_uint8.raw": ((64, 64, 64), 20),
}


def tf(lo):
    """A CT-like transfer function: transparent below lo, soft tissue and bone above."""
    a = lo
    return {
        "opacity": [[0, 0], [a, 0], [a + 40, 0.015], [min(a + 110, 200), 0.09], [225, 0.05], [255, 0.12]],
        "color": [[0, 0, 0, 0], [a + 20, 0.7, 0.25, 0.2], [min(a + 110, 200), 0.95, 0.6, 0.45], [255, 1, 1, 1]],
        "shading": {"ambient": 0.3, "diffuse": 0.7, "specular": 0.25, "specular_power": 20},
    }


def volume(rng, volumes):
    kinds = ["blobs", "blobs", "cloud", "marschner_lobb"]
    reals = [f for f in sorted(REAL) if volumes and os.path.exists(os.path.join(volumes, f))]
    if reals and rng.random() < 0.5:
        f = rng.choice(reals)
        dims, lo = REAL[f]
        return {"file": os.path.join(volumes, f), "dims": list(dims), "type": "uint8"}, tf(lo), f.split("_")[0]
    k = rng.choice(kinds)
    if k == "blobs":
        n = rng.randint(64, 128)
        d = [n, n, rng.randint(48, n)]
        return ({"generator": "blobs", "dims": d, "count": rng.randint(4, 20), "seed": rng.randint(0, 10**6)},
                tf(40), "blobs")
    if k == "cloud":
        n = rng.randint(64, 112)
        return {"generator": "cloud", "dims": [n, n, n // 2 + 16], "seed": rng.randint(0, 10**6)}, tf(30), "cloud"
    n = rng.randint(41, 72)
    return {"generator": "marschner_lobb", "dims": [n, n, n]}, tf(60), "marschner_lobb"


def mirror(side, dist, half_h):
    """A mirror wall at `dist` from the centre on side +x, -x, +y or -y, facing the centre,
    wide enough to stand behind the whole orbit."""
    w = 2.6 * dist
    mat = {"color": [0.1, 0.1, 0.12], "reflectivity": 0.9}
    if side == "+x":
        return {"type": "rect", "corner": [dist, w / 2, -half_h], "u": [0, -w, 0], "v": [0, 0, 2 * half_h], "material": mat}
    if side == "-x":
        return {"type": "rect", "corner": [-dist, -w / 2, -half_h], "u": [0, w, 0], "v": [0, 0, 2 * half_h], "material": mat}
    if side == "+y":
        return {"type": "rect", "corner": [-w / 2, dist, -half_h], "u": [w, 0, 0], "v": [0, 0, 2 * half_h], "material": mat}
    return {"type": "rect", "corner": [w / 2, -dist, -half_h], "u": [-w, 0, 0], "v": [0, 0, 2 * half_h], "material": mat}


def path(rng, i, volumes, max_bounces):
    size = rng.choice([96, 112, 128])
    vol, transfer, vname = volume(rng, volumes)
    # The camera's orbit: distance from the centre, elevation.
    dist = size * rng.uniform(1.6, 2.4)
    az = rng.uniform(0, 2 * math.pi)
    el = math.radians(rng.uniform(-35, 50))
    eye = [dist * math.cos(el) * math.cos(az), dist * math.cos(el) * math.sin(az), dist * math.sin(el)]
    n_mirrors = rng.choice([0, 1, 2, 2, 3, 4])
    if n_mirrors == 2 and rng.random() < 0.6:
        sides = rng.choice([["+x", "-x"], ["+y", "-y"]])  # a facing pair
    else:
        sides = rng.sample(["+x", "-x", "+y", "-y"], n_mirrors)
    wall = dist * rng.uniform(1.15, 1.4)  # the mirrors stand behind the orbit
    surfaces = [mirror(s, wall, dist * 1.2) for s in sides]
    n_glass = rng.choice([0, 0, 1, 2])
    for _ in range(n_glass):
        r = size * rng.uniform(0.1, 0.22)
        c = [rng.uniform(-0.7, 0.7) * size for _ in range(3)]
        surfaces.append({"type": "sphere", "center": c, "radius": r,
                         "material": {"color": [1, 1, 1], "transparency": 0.9, "reflectivity": 0.1,
                                      "ior": round(rng.uniform(1.2, 1.6), 3)}})
    floor = rng.random() < 0.4
    if floor:
        z = -size * 0.6
        w = 2.6 * wall
        surfaces.append({"type": "rect", "corner": [-w / 2, -w / 2, z], "u": [w, 0, 0], "v": [0, w, 0],
                         "material": {"color": [0.5, 0.5, 0.55], "reflectivity": 0.5}})
    bounces = rng.randint(3, max_bounces) if (sides or n_glass or floor) else 1
    light = {"type": "point", "position": [2 * dist, -1.5 * dist, 2 * dist], "intensity": 1.0,
             "shadows": rng.random() < 0.3}
    scene = {
        "name": "family_%03d" % i,
        "grid": {"center": [0, 0, 0], "size": size},
        "volumes": [vol],
        "transfer_function": transfer,
        "lights": [light],
        "surfaces": surfaces,
        "camera": {"eye": [round(x, 3) for x in eye], "target": [0, 0, 0], "up": [0, 0, 1], "fov": 36,
                   "width": 128, "height": 128},
        "render": {"max_bounces": bounces, "background": [0, 0, 0]},
    }
    # The motion: degrees a frame, log-uniform in [1, 90]; cuts or a dolly on some paths.
    deg = round(math.exp(rng.uniform(0, math.log(90))), 2)
    motion = ["--orbit", str(deg)]
    extra = ""
    u = rng.random()
    if u < 0.25:
        motion += ["--jumps", "%d:%d" % (rng.randint(1, 10**6), rng.randint(2, 4))]
        extra = ", cuts"
    elif u < 0.45:
        f = round(rng.choice([rng.uniform(0.9, 0.97), rng.uniform(1.02, 1.06)]), 3)
        motion += ["--dolly", str(f)]
        extra = ", dolly %g" % f
    cells = rng.choice([2, 3])
    desc = "%s, %d mirror(s)%s, %d glass, %sbounces %d, orbit %g deg%s, 1/%d" % (
        vname, len(sides), " (facing pair)" if set(sides) in ({"+x", "-x"}, {"+y", "-y"}) else "", n_glass,
        "floor, " if floor else "", bounces, deg, extra, cells ** 3)
    return scene, cells, motion, desc


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seed", type=int, required=True)
    ap.add_argument("--paths", type=int, required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--volumes", default="")
    ap.add_argument("--max-bounces", type=int, default=8)
    a = ap.parse_args()
    if a.paths < 1 or a.seed < 0 or not 1 <= a.max_bounces <= 15:
        print("sched_family.py: --paths >= 1, --seed >= 0, --max-bounces 1..15", file=sys.stderr)
        sys.exit(2)
    os.makedirs(a.out, exist_ok=True)
    rng = random.Random(a.seed)
    with open(os.path.join(a.out, "family.tsv"), "w") as tsv:
        for i in range(a.paths):
            scene, cells, motion, desc = path(rng, i, a.volumes, a.max_bounces)
            f = os.path.join(a.out, "p%03d.json" % i)
            with open(f, "w") as fh:
                json.dump(scene, fh, indent=1)
                fh.write("\n")
            tsv.write("%d\t%s\t%d\t%s\t%s\n" % (i, f, cells, " ".join(motion), desc))


if __name__ == "__main__":
    main()
