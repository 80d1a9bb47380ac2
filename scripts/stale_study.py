#!/usr/bin/env python3
"""Stale schedules under camera motion (docs/cell-tree.md, "Stale schedules"): runs
`cube5 schedule` over scenes, splits and camera motions and prints, per run, the fetches of
frames 1..N-1 with Max Work and following the Cell Tree, the worst frame, and what the board
followed. Usage:
  scripts/stale_study.py [--cube5 build/cube5] [--size 128x128] [--frames 12]
                         [--scenes a,b] [--cells 2,3] [--motions "orbit:0,orbit:2,..."]
                         [--volume FILE] [--split RULE] [--frames-detail] [--table]
A motion is orbit:DEG, jumps:SEED:EVERY, jumpsp:SEED:PROB or dolly:F; '+' combines them.
--table ends with docs/cell-tree.md's table: per scene and motion, the path's fetches against
Max Work's summed over the splits, check off and on, and the frames and paths over the
promise. The property test's matrix (tests/test_stale_sched.c) is
  --size 48x48 --frames 6 --cells 2,3,2x3x1,3x1x2 --split paper
  --motions still,orbit:2,orbit:8,orbit:30,jumps:5:3,orbit:4+jumpsp:9:0.3,dolly:0.9"""
import argparse, json, math, subprocess, sys

def motion_args(spec):
    out = []
    for term in spec.split('+'):
        k, _, v = term.partition(':')
        if k == 'orbit':
            out += ['--orbit', v]
        elif k == 'jumps':
            out += ['--jumps', v]
        elif k == 'jumpsp':
            seed, _, p = v.partition(':')
            out += ['--jumps', f'{seed}:p{p}']
        elif k == 'dolly':
            out += ['--dolly', v]
        elif k == 'still':
            out += ['--orbit', '0']
        else:
            sys.exit(f'bad motion {term}')
    return out

def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--cube5', default='build/cube5')
    ap.add_argument('--size', default='128x128')
    ap.add_argument('--frames', default='12')
    ap.add_argument('--scenes', default='brain_mirrors,default,lobster_tunnel,clouds_lake')
    ap.add_argument('--cells', default='2,3')
    ap.add_argument('--motions', default='orbit:0,orbit:2,orbit:8,orbit:30,jumps:1:3,orbit:8+jumps:2:4')
    ap.add_argument('--volume')
    ap.add_argument('--split')
    ap.add_argument('--frames-detail', action='store_true')
    ap.add_argument('--table', action='store_true')
    a = ap.parse_args()
    print(f'{"scene":15} {"cells":5} {"motion":18} {"maxwork":>7} | check off: {"celltree":>8} {"diff%":>6} '
          f'{"worst%":>6} {"bad":>3} | check on: {"celltree":>8} {"diff%":>6} {"worst%":>6} {"bad":>3} {"switched":>8}')
    table = {}
    for scene in a.scenes.split(','):
        for cells in a.cells.split(','):
            for m in a.motions.split(','):
                cmd = [a.cube5, 'schedule', scene, '--cells', cells, '--size', a.size, '--frames', a.frames,
                       '--exact-states', '0', '--json'] + motion_args(m)
                if a.split:
                    cmd += ['--split', a.split]
                if a.volume and scene == 'brain_mirrors':
                    cmd += ['--volume', a.volume]
                cols, detail = [], []
                for chk in ('off', 'on'):
                    out = subprocess.run(cmd + ['--stale-check', chk], check=True, capture_output=True, text=True)
                    fr = json.loads(out.stdout)['frames'][1:]
                    mw = sum(f['fetches_maxwork'] for f in fr)
                    ct = sum(f['fetches_celltree'] for f in fr)
                    worst = max((f['fetches_celltree'] - f['fetches_maxwork']) / max(1, f['fetches_maxwork'])
                                for f in fr)
                    bad = sum(f['fetches_celltree'] > max(math.ceil(1.02 * f['fetches_maxwork']),
                                                          f['fetches_maxwork'] + 1) for f in fr)
                    sw = sum(1 for f in fr if f['switched_at_load'] is not None)
                    key = (scene, m, chk)
                    t = table.setdefault(key, [0, 0, 0, 0])
                    t[0] += mw
                    t[1] += ct
                    t[2] += bad
                    t[3] += ct > mw
                    cols.append(f'{ct:8} {100 * (ct - mw) / max(1, mw):6.1f} {100 * worst:6.1f} {bad:3}')
                    detail.append(' '.join(f'{f["fetches_maxwork"]}/{f["fetches_celltree"]}'
                                           + (f'@{f["switched_at_load"]}' if f['switched_at_load'] is not None else '')
                                           for f in fr))
                print(f'{scene:15} {cells:5} {m:18} {mw:7} | {cols[0]} | {cols[1]} {sw:8}', flush=True)
                if a.frames_detail:
                    print('    off:', detail[0])
                    print('    on: ', detail[1])
    if not a.table:
        return
    motions = a.motions.split(',')
    print('\n| scene | ' + ' | '.join(motions) + ' |')
    print('|---|' + '---|' * len(motions))
    over = {'off': [0, 0], 'on': [0, 0]}
    for scene in a.scenes.split(','):
        for chk in ('off', 'on'):
            cells = []
            for m in motions:
                mw, ct, bad, paths = table[(scene, m, chk)]
                over[chk][0] += bad
                over[chk][1] += paths
                v = 100 * (ct - mw) / max(1, mw)
                cells.append(f'{v:+.1f} %' if round(v, 1) else '0.0 %')
            print(f'| {scene}, check {chk} | ' + ' | '.join(cells) + ' |')
    for chk in ('off', 'on'):
        print(f'check {chk}: {over[chk][0]} frames over the promise, {over[chk][1]} paths over Max Work')

main()
