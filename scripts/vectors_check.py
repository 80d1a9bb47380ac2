#!/usr/bin/env python3
"""Compares a freshly generated vector set with the golden one, bit for bit.

Usage: vectors_check.py GOLDEN_DIR FRESH_DIR

Every difference is named: the file's block and source, the vector index (0-based line)
and the field, with the expected and the generated value; for the end-to-end records, the
scene and the CRC (frame_buffer, packet_trace, dsp_ram). The golden files are also checked
against their own manifest (format, column widths, CRC-32), so a hand-edited golden file
is caught even before it is compared. Prints one line per problem (at most 20 a file) and
exits 1 when there is any, 0 otherwise.
"""
import json
import os
import re
import sys
import zlib

MAX_REPORT = 20


def load_manifest(d):
    with open(os.path.join(d, "manifest.json")) as f:
        return json.load(f)


def check_format(d, entry, problems):
    """The file's bytes against its manifest entry: columns, digits, newline, count, CRC."""
    path = os.path.join(d, entry["file"])
    with open(path, "rb") as f:
        data = f.read()
    where = f"{d}/{entry['file']}"
    crc = "crc32:%08x" % (zlib.crc32(data) & 0xFFFFFFFF)
    if crc != entry["checksum"]:
        problems.append(f"{where}: checksum {crc}, manifest says {entry['checksum']}")
    if data and not data.endswith(b"\n"):
        problems.append(f"{where}: does not end in a newline")
    lines = data.decode("ascii", "replace").split("\n")[:-1] if data else []
    if len(lines) != entry["count"]:
        problems.append(f"{where}: {len(lines)} vectors, manifest says {entry['count']}")
    pat = re.compile(" ".join("[0-9a-f]{%d}" % fl["digits"] for fl in entry["fields"]) + "$")
    bad = 0
    for i, line in enumerate(lines):
        if not pat.match(line):
            bad += 1
            if bad <= MAX_REPORT:
                problems.append(f"{where}: vector {i}: not the manifest's columns: {line[:80]!r}")
    return lines


def compare_file(golden, fresh, ge, fe, problems):
    name = f"{ge['file']} (block {ge['block']}, {ge['source']} {ge['scene'] or ''})".replace(" )", ")")
    if [f["name"] for f in ge["fields"]] != [f["name"] for f in fe["fields"]] or [
        f["width"] for f in ge["fields"]
    ] != [f["width"] for f in fe["fields"]]:
        problems.append(f"{name}: the fields changed: golden {[(f['name'], f['width']) for f in ge['fields']]}, "
                        f"now {[(f['name'], f['width']) for f in fe['fields']]}")
        return
    for key in ("config", "seed", "kind", "image"):
        if ge.get(key) != fe.get(key):
            problems.append(f"{name}: manifest {key} golden {ge.get(key)}, now {fe.get(key)}")
    gl = check_format(golden, ge, problems)
    fl = check_format(fresh, fe, problems)
    names = [f["name"] for f in ge["fields"]]
    shown = 0
    for i in range(max(len(gl), len(fl))):
        if i >= len(gl) or i >= len(fl):
            problems.append(f"{name}: vector {i}: {'missing now' if i >= len(fl) else 'extra now'} "
                            f"(golden {len(gl)} vectors, now {len(fl)})")
            break
        if gl[i] == fl[i]:
            continue
        gv, fv = gl[i].split(" "), fl[i].split(" ")
        diffs = [f"{names[k]} expected {gv[k]} got {fv[k]}" for k in range(min(len(gv), len(fv))) if gv[k] != fv[k]]
        problems.append(f"{name}: vector {i}: " + "; ".join(diffs))
        shown += 1
        if shown >= MAX_REPORT:
            problems.append(f"{name}: ... further differences not shown")
            break


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    golden, fresh = sys.argv[1], sys.argv[2]
    gm, fm = load_manifest(golden), load_manifest(fresh)
    problems = []
    for key in ("format", "seed", "count", "size", "cells"):
        if gm.get(key) != fm.get(key):
            problems.append(f"manifest {key}: golden {gm.get(key)}, now {fm.get(key)}")
    gfiles = {e["file"]: e for e in gm["files"]}
    ffiles = {e["file"]: e for e in fm["files"]}
    for f in sorted(set(gfiles) - set(ffiles)):
        problems.append(f"{f} (block {gfiles[f]['block']}): in the golden set, no longer generated")
    for f in sorted(set(ffiles) - set(gfiles)):
        problems.append(f"{f} (block {ffiles[f]['block']}): generated now, not in the golden set")
    for f in sorted(set(gfiles) & set(ffiles)):
        compare_file(golden, fresh, gfiles[f], ffiles[f], problems)
    gs = {s["scene"]: s for s in gm.get("scenes", [])}
    fs = {s["scene"]: s for s in fm.get("scenes", [])}
    for s in sorted(set(gs) | set(fs)):
        if s not in gs or s not in fs:
            problems.append(f"scene {s}: {'not in the golden set' if s not in gs else 'no longer generated'}")
            continue
        for key in sorted(set(gs[s]) | set(fs[s])):
            if gs[s].get(key) != fs[s].get(key):
                problems.append(f"scene {s}: {key} golden {gs[s].get(key)}, now {fs[s].get(key)}")
    for p in problems:
        print(p)
    n_vec = sum(e["count"] for e in gm["files"])
    if problems:
        print(f"vectors_check: {len(problems)} difference(s) against {golden}")
        return 1
    print(f"vectors_check: {len(gfiles)} files, {n_vec} vectors and {len(gs)} scene CRC records identical to {golden}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
