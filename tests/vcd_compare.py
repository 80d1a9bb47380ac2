#!/usr/bin/env python3
"""Waveform checks of `cube5 vectors --vcd` (docs/vectors.md, "Waveforms").

  vcd_compare.py hex VCD HEX MANIFEST   the VCD's values at every rising clock edge after
                                        reset are the vector file's lines, field by field
  vcd_compare.py ghdl MODEL.vcd GHDL.vcd TB
                                        every signal of the model's VCD has a namesake in
                                        GHDL's VCD of testbench TB (its top scope), equal
                                        at every rising edge after reset
Values are sampled just before each rising edge of clk (1 ns before). Prints one line;
exit status 0 when the check holds, 1 on the first difference (named), 2 on bad input."""
import json, os, sys


def parse(path, top=None):
    """{name: [(time, value)]} of the signals directly in scope `top` (None: the first
    scope), and the rising edges of its clk."""
    ids, scopes, changes, t = {}, [], {}, 0
    first, unit = None, 1.0  # unit: ns per time step ($timescale)
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
            scale = {'s': 1e9, 'ms': 1e6, 'us': 1e3, 'ns': 1.0, 'ps': 1e-3, 'fs': 1e-6}[spec[len(num):]]
            unit = float(num) * scale
            i = j + 1
        elif tok.startswith('$'):
            j = i + 1
            if tok not in ('$dumpvars', '$end'):
                while tokens[j] != '$end':
                    j += 1
                j += 1
            i = j
        elif tok[0] == '#':
            t = round(int(tok[1:]) * unit)
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
                    print(f'edge at {e} ns, {n}: model {a}, GHDL {b}')
                    return 1
        print(f'{len(medges) - 1} cycles, {len(names)} signals: the model and GHDL agree at every rising edge')
        return 0
    print(__doc__)
    return 2


sys.exit(main())
