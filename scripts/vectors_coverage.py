#!/usr/bin/env python3
"""Functional coverage of a vector set (docs/vectors.md, "Coverage"): hits per coverage point
of spec/coverage.toml over the vector files of DIR (a `cube5 vectors` set with its manifest).

Usage: vectors_coverage.py DIR [--spec spec/coverage.toml] [--ref build/libc5ref.so]
                           [--json | --markdown] [--all]

Points: for every field of every block (formats uint, sint, UQ, SQ; not the 256-bit packet)
`FIELD.zero`, `FIELD.max` (its largest value), and for signed fields `FIELD.min` (its most
negative value) and `FIELD.sign_change` (two consecutive vectors of a file with opposite
signs); then the points the spec declares per block, each a Python expression over `v` (the
vector: its fields by name, signed fields as negative numbers), `p` (the previous vector
of the same file, None for the first) and first(key) / count(key) (what the file has shown
so far: true the first time key is seen; calls with key); a point with `file_when` instead
is an expression over `c`, the config of the file's manifest entry, and counts files. A field's declared range (the
values the signal can take) replaces its format's extremes. Then, for every rounding or
saturation site the spec declares ([[site]]), a point per event it lists
(`rnd.SITE.EVENT`, EVENT one of vectors_probe.EVENTS): each vector of the block is replayed
through the model's block function in the live-reference library (--ref, built with the probe
of rtl_model/proc/round_probe.h), which must give the vector's outputs, and the events its
rounders and clamps met are counted; `v.ev` holds them ({site: bits}) for declared points.
Every site the library has must be declared, and the reverse. A point the golden set cannot
reach is declared a hole with its reason. Exit status: 0 when every point is hit or a declared hole; 1 when a point
is missed or a hole is hit (the spec must say so); 2 on bad input."""
import json, os, sys, tomllib

from vectors_probe import EVENTS, Probe, ProbeError


class Vec:
    def __init__(self, d):
        self.__dict__.update(d)


def load(path):
    try:
        with open(path, 'rb') as f:
            return tomllib.load(f)
    except (OSError, tomllib.TOMLDecodeError) as e:
        sys.exit(f'vectors_coverage: {path}: {e}')


def signed(fmt):
    return fmt == 'sint' or fmt.startswith('SQ')


def auto_points(fields, ranges):
    """Per field: its least and largest value (the declared range, else the format's) and
    zero inside the range; for a range across zero, a sign change between two vectors."""
    pts = []
    for f in fields:
        if f['format'] == 'bits':
            continue
        w, n = f['width'], f['name']
        lo, hi = (-(1 << (w - 1)), (1 << (w - 1)) - 1) if signed(f['format']) else (0, (1 << w) - 1)
        lo, hi = ranges.get(n, (lo, hi))
        if lo == 0:
            pts.append((f'{n}.zero', f'v.{n} == 0'))
        else:
            pts.append((f'{n}.min', f'v.{n} == {lo}'))
            if lo < 0 < hi:
                pts.append((f'{n}.zero', f'v.{n} == 0'))
                pts.append((f'{n}.sign_change', f'p is not None and v.{n} * p.{n} < 0'))
        pts.append((f'{n}.max', f'v.{n} == {hi}'))
    return pts


class FileState:
    """What a point may remember along one file: first(key) is true the first time key is
    seen, count(key) counts its calls."""
    def __init__(self):
        self.seen, self.counts = set(), {}

    def first(self, key):
        if key in self.seen:
            return False
        self.seen.add(key)
        return True

    def count(self, key):
        self.counts[key] = self.counts.get(key, 0) + 1
        return self.counts[key]


def main():
    args = sys.argv[1:]
    as_json, as_md, show_all = '--json' in args, '--markdown' in args, '--all' in args
    args = [a for a in args if a not in ('--json', '--markdown', '--all')]
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..')
    spec_path = os.path.join(root, 'spec', 'coverage.toml')
    ref_path = os.path.join(root, os.environ.get('BUILD', 'build'), 'libc5ref.so')
    for opt in ('--spec', '--ref'):
        if opt in args:
            i = args.index(opt)
            if i + 1 >= len(args):
                print(f'vectors_coverage: {opt} needs a path', file=sys.stderr)
                return 2
            if opt == '--spec':
                spec_path = args[i + 1]
            else:
                ref_path = args[i + 1]
            del args[i:i + 2]
    if len(args) != 1:
        print(__doc__, file=sys.stderr)
        return 2
    d = args[0]
    try:
        manifest = json.load(open(os.path.join(d, 'manifest.json')))
    except (OSError, ValueError) as e:
        print(f'vectors_coverage: {d}: no vector set ({e})', file=sys.stderr)
        return 2
    spec = load(spec_path)
    holes = {(h['block'], h['point']): h['reason'] for h in spec.get('hole', [])}
    ranges = {}
    for r in spec.get('range', []):
        for fld in r['fields']:
            ranges.setdefault(r['block'], {})[fld] = (r['lo'], r['hi'])
    declared, per_file = {}, {}
    for pt in spec.get('point', []):
        if 'file_when' in pt:
            per_file.setdefault(pt['block'], []).append((pt['name'], pt['file_when'], pt.get('doc', '')))
        else:
            declared.setdefault(pt['block'], []).append((pt['name'], pt['when'], pt.get('doc', '')))
    try:
        probe = Probe(ref_path)
    except ProbeError as e:
        print(f'vectors_coverage: {e}', file=sys.stderr)
        return 2
    sites = {s['site']: s for s in spec.get('site', [])}
    lib_sites = set(probe.sites[1:])  # "none" is no site
    for name in sorted(lib_sites ^ set(sites)):
        where = 'the spec does not declare it' if name in lib_sites else f'{ref_path} has no such site'
        print(f'vectors_coverage: {spec_path}: rounding site {name}: {where}', file=sys.stderr)
        return 2
    for name, st in sites.items():
        bad_ev = [e for e in st['events'] if e not in EVENTS]
        if bad_ev or name.split('.')[0] != st['block']:
            print(f'vectors_coverage: {spec_path}: site {name}: block {st["block"]}, events {st["events"]}: '
                  f'events are {", ".join(EVENTS)}', file=sys.stderr)
            return 2
        site_short = name.split('.', 1)[1]
        for e in st['events']:
            declared.setdefault(st['block'], []).append(
                (f'rnd.{site_short}.{e}', f'v.ev.get({name!r}, 0) & {EVENTS[e]}', ''))
    blocks = {}  # block -> (fields, [(file, {image kind: path}, config)])
    images = {e['file']: e['image'] for e in manifest['files'] if e['kind'] == 'image'}
    for e in manifest['files']:
        if e['kind'] == 'vectors':
            cfg = e.get('config') or {}
            imgs = {images[f]: os.path.join(d, f) for f in cfg.values() if isinstance(f, str) and f in images}
            blocks.setdefault(e['block'], (e['fields'], []))[1].append((e['file'], imgs, cfg))
    unknown = [b for b in list(declared) + list(per_file) if b not in blocks] + [b for (b, _) in holes if b not in blocks]
    if unknown:
        print(f'vectors_coverage: {spec_path}: block {unknown[0]} has no vectors in {d}', file=sys.stderr)
        return 2
    report, bad = [], 0
    for block, (fields, files) in blocks.items():
        names_in = {fd['name'] for fd in fields}
        for fld in ranges.get(block, {}):
            if fld not in names_in:
                print(f'vectors_coverage: {spec_path}: range of {block}.{fld}: no such field', file=sys.stderr)
                return 2
        pts = [(n, w, '') for n, w in auto_points(fields, ranges.get(block, {}))] + declared.get(block, [])
        code = [(n, compile(w, f'{block}.{n}', 'eval'), doc) for n, w, doc in pts]
        fcode = [(n, compile(w, f'{block}.{n}', 'eval'), doc) for n, w, doc in per_file.get(block, [])]
        hits, fhits = [0] * len(code), [0] * len(fcode)
        outs = [fd['name'] for fd in fields if fd['dir'] == 'out']
        for fn, imgs, cfg in files:
            for k, (_, c, _) in enumerate(fcode):
                fhits[k] += bool(eval(c, {}, {'c': cfg}))
            prev, st = None, [FileState() for _ in code]  # each point remembers on its own
            with open(os.path.join(d, fn)) as f:
                for lineno, line in enumerate(f, 1):
                    vals = {}
                    for fd, col in zip(fields, line.split()):
                        x = int(col, 16)
                        if signed(fd['format']) and x >> (fd['width'] - 1):
                            x -= 1 << fd['width']
                        vals[fd['name']] = x
                    try:
                        ev = probe.events(block, vals, outs, imgs)
                    except (ProbeError, KeyError, OSError) as e:
                        print(f'vectors_coverage: {fn} line {lineno}: {e}', file=sys.stderr)
                        return 2
                    v = Vec(vals)
                    v.ev = ev or {}
                    for k, (_, c, _) in enumerate(code):
                        if eval(c, {}, {'v': v, 'p': prev, 'first': st[k].first, 'count': st[k].count}):
                            hits[k] += 1
                    prev = v
        code, hits = code + fcode, hits + fhits
        names = {n for n, _, _ in code}
        for (b, pt) in holes:
            if b == block and pt not in names:
                print(f'vectors_coverage: {spec_path}: hole {b}.{pt} is no point', file=sys.stderr)
                return 2
        for (n, _, doc), h in zip(code, hits):
            reason = holes.get((block, n))
            status = 'hit' if h and reason is None else 'HOLE' if reason is not None and not h else \
                'HIT HOLE' if h else 'MISSED'
            bad += status in ('MISSED', 'HIT HOLE')
            report.append({'block': block, 'point': n, 'hits': h, 'status': status.lower(),
                           'doc': doc, 'reason': reason})
    if as_json:
        json.dump({'dir': d, 'spec': os.path.relpath(spec_path), 'points': report,
                   'hit': sum(r['status'] == 'hit' for r in report),
                   'holes': sum(r['status'] == 'hole' for r in report), 'bad': bad}, sys.stdout, indent=1)
        print()
    elif as_md:  # the testplan of docs/vectors.md: declared points, then the holes
        print('| block | point | what it covers | hits |\n|---|---|---|---:|')
        for r in report:
            if r['doc']:
                print(f'| {r["block"]} | {r["point"]} | {r["doc"]} | {r["hits"]} |')
        cols = [e for e in EVENTS if any(e in st['events'] for st in sites.values())]
        print('\n| block | site | what rounds or clamps | ' + ' | '.join(cols) + ' |\n|---|---|---|' +
              '---:|' * len(cols))
        by_point = {(r['block'], r['point']): r for r in report}
        for name, st in sites.items():
            cells = []
            for e in cols:
                r = by_point.get((st['block'], f'rnd.{name.split(".", 1)[1]}.{e}'))
                cells.append('' if r is None else 'hole' if r['status'] == 'hole' else str(r['hits']))
            print(f'| {st["block"]} | {name.split(".", 1)[1]} | {st["doc"]} | ' + ' | '.join(cells) + ' |')
        print('\n| block | holes | why |\n|---|---|---|')
        groups = {}
        for r in report:
            if r['reason']:
                groups.setdefault((r['block'], r['reason']), []).append(r['point'])
        for (b, why), pts in groups.items():
            print(f'| {b} | {", ".join(pts)} | {why} |')
    else:
        for r in report:
            if r['status'] != 'hit' or show_all:
                extra = f' ({r["reason"]})' if r['reason'] else ''
                print(f'{r["status"].upper():8} {r["block"]}.{r["point"]}: {r["hits"]} hits{extra}')
        print(f'coverage of {d}: {sum(r["status"] == "hit" for r in report)} points hit, '
              f'{sum(r["status"] == "hole" for r in report)} declared holes, {bad} missed or hit holes')
    return 1 if bad else 0


sys.exit(main())
