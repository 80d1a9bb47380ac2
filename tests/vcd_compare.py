#!/usr/bin/env python3
"""Waveform checks of `cube5 vectors --vcd` and `cube5 render --vcd` (docs/vectors.md,
"Waveforms", "Waveforms of a frame").

  vcd_compare.py hex VCD HEX MANIFEST   the VCD's values at every rising clock edge after
                                        reset are the vector file's lines, field by field
  vcd_compare.py ghdl MODEL.vcd GHDL.vcd TB
                                        every signal of the model's VCD has a namesake in
                                        GHDL's VCD of testbench TB (its top scope), equal
                                        at every rising edge after reset
  vcd_compare.py scope A.vcd SCOPE_A B.vcd SCOPE_B
                                        every signal of B's scope has a namesake in A's,
                                        equal at every rising edge after reset that both
                                        have (the cycles both cover; at least one)
  vcd_compare.py bus FRAME.vcd PACKET.hex MANIFEST
                                        the ray_bus scope of `cube5 render --vcd` against
                                        the packet vectors of the same scene holding every
                                        packet written to a queue (count = offered): in
                                        order, each packet from the DSP is the next queue
                                        write but one, field for field; each packet to the
                                        DSP is a later write but for its Cell Tree node (the
                                        DSP tags it); the writes left over are the sorter's
                                        accepted inserts that did not come over the bus
Values are sampled just before each rising edge of clk. Prints one line; exit status 0
when the check holds, 1 on the first difference (named), 2 on bad input."""
import json, os, sys


def parse(path, top=None):
    """{name: [(time, value)]} of the signals directly in scope `top` (None: the first
    scope), and the rising edges of its clk."""
    ids, scopes, changes, t = {}, [], {}, 0
    first, unit = None, 1  # unit: fs per time step ($timescale)
    with open(path) as f:
        tokens = f.read().split()
    i = 0
    while i < len(tokens):
        tok = tokens[i]
        if tok == '$scope':
            scopes.append(tokens[i + 2])
            first = first or tokens[i + 2]
            i += 4
        elif tok == '$upscope':
            scopes.pop()
            i += 2
        elif tok == '$var':
            width, ident, name = tokens[i + 2], tokens[i + 3], tokens[i + 4]
            j = i + 5
            while tokens[j] != '$end':
                j += 1
            if scopes and scopes[-1] == (top or first) and len(scopes) == 1:
                ids.setdefault(ident, []).append(name.split('[')[0])  # GHDL: "count[8:0]"
            i = j + 1
        elif tok == '$timescale':
            j = i + 1
            spec = ''
            while tokens[j] != '$end':
                spec += tokens[j]
                j += 1
            num = spec.rstrip('afmnpsu')
            scale = {'s': 10**15, 'ms': 10**12, 'us': 10**9, 'ns': 10**6, 'ps': 10**3, 'fs': 1}[spec[len(num):]]
            unit = int(num) * scale
            i = j + 1
        elif tok.startswith('$'):
            j = i + 1
            if tok not in ('$dumpvars', '$end'):
                while tokens[j] != '$end':
                    j += 1
                j += 1
            i = j
        elif tok[0] == '#':
            t = int(tok[1:]) * unit  # fs
            i += 1
        elif tok[0] in 'bBrR':
            for n in ids.get(tokens[i + 1], []):
                changes.setdefault(n, []).append((t, tok[1:].lower()))
            i += 2
        else:
            for n in ids.get(tok[1:], []):
                changes.setdefault(n, []).append((t, tok[0].lower()))
            i += 1
    edges = [t for (t, v), (_, p) in zip(changes.get('clk', [])[1:], changes.get('clk', [])) if v == '1' and p == '0']
    first_clk = changes.get('clk', [(0, '0')])[0]
    if first_clk[1] == '1':
        edges.insert(0, first_clk[0])
    return changes, sorted(set(edges))


def value(ch, t):
    """The value in force just before time t: an int, or None when unknown (x, u, z...)."""
    v = None
    for (tc, val) in ch:
        if tc >= t:
            break
        v = val
    if v is None or any(c not in '01' for c in v):
        return None
    return int(v, 2)


def main():
    if len(sys.argv) == 5 and sys.argv[1] == 'hex':
        _, _, vcd, hexf, man = sys.argv
        entry = next(e for e in json.load(open(man))['files'] if e['file'] == os.path.basename(hexf))
        fields = [(x['name'], x['width']) for x in entry['fields']]
        ch, edges = parse(vcd)
        lines = open(hexf).read().split('\n')[:-1]
        edges = edges[1:]  # the first rising edge is the reset's
        if len(edges) != len(lines):
            print(f'{vcd}: {len(edges)} cycles after reset, {hexf}: {len(lines)} vectors')
            return 1
        for n, (line, e) in enumerate(zip(lines, edges)):
            for (name, w), col in zip(fields, line.split(' ')):
                got = value(ch.get(name, []), e)
                if got != int(col, 16):
                    print(f'{vcd}: vector {n + 1}, {name}: {got} in the waveform, {int(col, 16)} in {hexf}')
                    return 1
        print(f'{vcd}: {len(lines)} vectors, {len(fields)} fields: the same as {os.path.basename(hexf)}')
        return 0
    if len(sys.argv) == 5 and sys.argv[1] == 'ghdl':
        _, _, model, ghdl, tb = sys.argv
        mch, medges = parse(model)
        gch, gedges = parse(ghdl, tb)
        names = [n for n in mch if n != 'clk']
        missing = [n for n in names if n not in gch]
        if missing:
            print(f'{ghdl}: no signal {missing[0]} in {tb} (the model names its signals after the ports)')
            return 1
        if medges != gedges:
            print(f'rising edges differ: model {len(medges)} from {medges[:3]}, GHDL {len(gedges)} from {gedges[:3]}')
            return 1
        for e in medges[1:]:
            for n in names:
                a, b = value(mch[n], e), value(gch[n], e)
                if a != b:
                    print(f'edge at {e / 1e6:g} ns, {n}: model {a}, GHDL {b}')
                    return 1
        print(f'{len(medges) - 1} cycles, {len(names)} signals: the model and GHDL agree at every rising edge')
        return 0
    if len(sys.argv) == 6 and sys.argv[1] == 'scope':
        _, _, a_vcd, a_scope, b_vcd, b_scope = sys.argv
        ach, aedges = parse(a_vcd, a_scope)
        bch, bedges = parse(b_vcd, b_scope)
        names = [n for n in bch if n not in ('clk', 'rst')]
        missing = [n for n in names if n not in ach]
        if not names or missing:
            print(f'{a_vcd}: no signal {missing[0] if missing else "at all"} in scope {a_scope}')
            return 1
        common = sorted(set(aedges[1:]) & set(bedges[1:]))
        if not common:
            print(f'{a_vcd} and {b_vcd}: no rising edge after reset in common')
            return 1
        for e in common:
            for n in names:
                x, y = value(ach[n], e), value(bch[n], e)
                if x != y:
                    print(f'edge at {e / 1e6:g} ns, {n}: {a_scope} {x}, {b_scope} {y}')
                    return 1
        print(f'{len(common)} cycles, {len(names)} signals: {a_scope} of {os.path.basename(a_vcd)} and '
              f'{b_scope} of {os.path.basename(b_vcd)} agree at every rising edge both have')
        return 0
    if len(sys.argv) == 5 and sys.argv[1] == 'bus':
        return bus(*sys.argv[2:])
    print(__doc__)
    return 2


def bus_beats(path):
    """The packets of the ray_bus scope in time order, [(to_dsp, {field: value})]: one at each
    rising edge with valid high (a packet into the sorter), and one at each rise of valid
    between edges (a packet to the DSP)."""
    ch, _ = parse(path, 'ray_bus')
    events = sorted((t, k, n, v) for n, lst in ch.items() for k, (t, v) in enumerate(lst))
    cur, beats, i = {}, [], 0
    while i < len(events):
        t = events[i][0]
        before, clk_changed = dict(cur), False
        while i < len(events) and events[i][0] == t:
            cur[events[i][2]] = events[i][3]
            clk_changed |= events[i][2] == 'clk'
            i += 1
        if before.get('clk') == '0' and cur.get('clk') == '1' and before.get('valid') == '1':
            beats.append(before)
        elif not clk_changed and before.get('valid') != '1' and cur.get('valid') == '1':
            beats.append(dict(cur))
    out = []
    for b in beats:
        if any(c not in '01' for n, v in b.items() for c in v if n not in ('clk', 'rst')):
            return None
        out.append((int(b['to_dsp'], 2), {n: int(v, 2) for n, v in b.items() if n not in ('clk', 'rst', 'valid', 'to_dsp')}))
    return out


def bus(frame, hexf, man):
    entry = next(e for e in json.load(open(man))['files'] if e['file'] == os.path.basename(hexf))
    if entry.get('offered') != entry['count']:
        print(f'{hexf}: {entry["count"]} of {entry.get("offered")} packets: give --count >= the packets')
        return 2
    names = [x['name'] for x in entry['fields']]
    writes = [dict(zip(names, (int(c, 16) for c in line.split(' ')))) for line in open(hexf).read().split('\n')[:-1]]
    beats = bus_beats(frame)
    if beats is None:
        print(f'{frame}: an unknown (x) value in a ray bus packet')
        return 1
    if not beats:
        print(f'{frame}: no packet on the ray bus')
        return 1
    qch, qedges = parse(frame, 'ray_queue')
    accepted = sum(value(qch['insert_accepted'], e) == 1 for e in qedges[1:])
    pos, others, to_dsp = 0, 0, 0
    for n, (d, f) in enumerate(beats):
        if d == 0:  # into the sorter: the write just made
            if pos >= len(writes) or writes[pos] != f:
                print(f'{frame}: bus packet {n + 1} (from the DSP) is not queue write {pos + 1} of {hexf}')
                return 1
            pos += 1
            continue
        to_dsp += 1
        skip = pos
        key = lambda w: {k: v for k, v in w.items() if k not in ('cell_tree_node', 'packet')}
        while skip < len(writes) and key(writes[skip]) != key(f):
            skip += 1
        if skip == len(writes):
            print(f'{frame}: bus packet {n + 1} (to the DSP) is no later queue write of {hexf} (from {pos + 1})')
            return 1
        others += skip - pos
        pos = skip + 1
    others += len(writes) - pos
    from_dsp = len(beats) - to_dsp
    if others != accepted - from_dsp:
        print(f'{hexf}: {others} queue writes off the bus, the sorter accepted {accepted} inserts of which '
              f'{from_dsp} came over the bus')
        return 1
    print(f'{len(beats)} ray bus packets ({to_dsp} to the DSP, {from_dsp} from it) in order among the '
          f'{len(writes)} queue writes of {os.path.basename(hexf)}; the other {others} are the sorter\'s own inserts')
    return 0


sys.exit(main())
