#!/usr/bin/env python3
"""Turns spec/layouts.toml, the one source of truth for cube5's bit layouts, into a C
header (static inline pack/unpack), a VHDL package (field positions, one record type and
pack/unpack functions per layout) and the Markdown reference docs/bit-layouts.md.

Usage: gen-layouts.py SPEC.toml [--c-header OUT.h] [--markdown OUT.md] [--vhdl OUT.vhd]
       gen-layouts.py --regs REGS.toml [--c-header OUT.h] [--markdown OUT.md] [--vhdl OUT.vhd]

With --regs it reads spec/registers.toml, the board's register map (BAR0), instead, and
writes its C header, VHDL package and docs/register-map.md, checked as strictly.

With no output it only checks the spec. Every problem found is printed, one line each,
naming the layout and field, and the exit status is 1: a layout with overlapping fields,
bits beyond its width, undeclared gaps or a format that disagrees with its field's width
never reaches the C model or the docs. The schema is described at the top of the spec."""

import argparse
import os
import re
import sys

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    sys.exit("gen-layouts: needs Python 3.11 or later (tomllib)")

PROG = "gen-layouts"
ROUNDINGS = ("half-even", "half-up", "trunc", "exact")
SATURATIONS = ("saturate", "error", "none")
C_RND = {"half-even": "C5_RND_HALF_EVEN", "half-up": "C5_RND_HALF_UP", "trunc": "C5_RND_TRUNC"}
FX_MAX_WIDTH = 62  # C5_FX_MAX_WIDTH in rtl_model/proc/fixed.h
UINT_MAX_WIDTH = 32  # uint fields are uint32_t members
# Lower-case words joined by single underscores: valid in C and, upper-cased, in VHDL
# (which forbids double and trailing underscores).
NAME_RE = re.compile(r"^[a-z][a-z0-9]*(_[a-z0-9]+)*$")
RESERVED_RE = re.compile(r"^reserved[0-9]*$")
C_KEYWORDS = set(
    "auto break case char const continue default do double else enum extern float for goto "
    "if inline int long register restrict return short signed sizeof static struct switch "
    "typedef union unsigned void volatile while".split()
)
# VHDL-2008 reserved words (IEEE 1076-2008, 15.10). A field named like one of them (the
# packet's "type") cannot be a record member as is: its member gets VHDL_SUFFIX ("type_f").
VHDL_RESERVED = set(
    "abs access after alias all and architecture array assert assume assume_guarantee "
    "attribute begin block body buffer bus case component configuration constant context "
    "cover default disconnect downto else elsif end entity exit fairness file for force "
    "function generate generic group guarded if impure in inertial inout is label library "
    "linkage literal loop map mod nand new next nor not null of on open or others out "
    "package parameter port postponed procedure process property protected pure range "
    "record register reject release rem report restrict restrict_guarantee return rol ror "
    "select sequence severity shared signal sla sll sra srl strong subtype then to "
    "transport type unaffected units until use variable vmode vprop vunit wait when while "
    "with xnor xor".split()
)
VHDL_SUFFIX = "_f"
FIELD_KEYS = ("name", "lsb", "width", "format", "rounding", "saturation", "reason")
RESERVED_KEYS = ("name", "lsb", "width", "reason")
LAYOUT_KEYS = ("name", "width", "bytes_order", "doc", "field")
SIGNAL_KEYS = ("name", "format", "rounding", "saturation", "block", "reason")


class Fmt:
    """A field's format: uint, or UQi.f / SQi.f as in rtl_model/proc/fixed.h."""

    def __init__(self, text, kind, signed=False, i=0, f=0):
        self.text, self.kind, self.signed, self.i, self.f = text, kind, signed, i, f

    @property
    def fixed(self):
        return self.kind == "fixed"

    def width(self):
        return (1 if self.signed else 0) + self.i + self.f


def parse_format(text):
    if text == "uint":
        return Fmt(text, "uint")
    m = re.fullmatch(r"([US])Q([0-9]+)\.([0-9]+)", text)
    if not m:
        return None
    return Fmt(text, "fixed", m.group(1) == "S", int(m.group(2)), int(m.group(3)))


class Checker:
    """Collects every problem of the spec instead of stopping at the first."""

    def __init__(self, path):
        self.path, self.errors = path, []

    def err(self, where, msg):
        self.errors.append(f"{PROG}: {self.path}: {where}: {msg}")

    def keys(self, where, table, allowed, required):
        for k in table:
            if k not in allowed:
                self.err(where, f"unknown key '{k}' (allowed: {', '.join(allowed)})")
        ok = True
        for k in required:
            if k not in table:
                self.err(where, f"missing key '{k}'")
                ok = False
        return ok

    def string(self, where, table, key):
        v = table.get(key)
        if not isinstance(v, str) or not v.strip():
            self.err(where, f"'{key}' must be a non-empty string")
            return None
        return v

    def integer(self, where, table, key, low):
        v = table.get(key)
        if not isinstance(v, int) or isinstance(v, bool) or v < low:
            self.err(where, f"'{key}' must be an integer >= {low}, not {v!r}")
            return None
        return v

    def name(self, where, table):
        v = self.string(where, table, "name")
        if v is not None and not NAME_RE.match(v):
            self.err(where, f"name '{v}' must be lower-case words joined by single underscores")
            return None
        if v in C_KEYWORDS:
            self.err(where, f"name '{v}' is a C keyword")
            return None
        return v

    def modes(self, where, table, fmt):
        rnd = self.string(where, table, "rounding")
        if rnd is not None and rnd not in ROUNDINGS:
            self.err(where, f"rounding '{rnd}' is not one of {', '.join(ROUNDINGS)}")
        sat = self.string(where, table, "saturation")
        if sat is not None and sat not in SATURATIONS:
            self.err(where, f"saturation '{sat}' is not one of {', '.join(SATURATIONS)}")
        elif sat == "none" and fmt is not None and fmt.kind != "uint":
            self.err(where, "saturation 'none' (wraps by design) is allowed on uint fields only")
        return rnd, sat

    def fmt(self, where, table):
        text = self.string(where, table, "format")
        if text is None:
            return None
        fmt = parse_format(text)
        if fmt is None:
            self.err(where, f"format '{text}' is not uint, UQi.f or SQi.f")
        elif fmt.fixed and not 1 <= fmt.width() <= FX_MAX_WIDTH:
            self.err(where, f"format {text} is {fmt.width()} bits; fixed.h allows 1 to {FX_MAX_WIDTH}")
            return None
        return fmt


def field_head(ck, owner, table, index, raw, reserved_keys, keys, required):
    """What a layout's and a register's fields share: a table with a name, reserved or not,
    the allowed keys, lsb and width. None when raw is not a table."""
    where = f"{owner} field #{index + 1}"
    if not isinstance(raw, dict):
        ck.err(where, f"must be a table ([[{table}]])")
        return None
    name = ck.name(where, raw)
    if name is not None:
        where = f"{owner} field '{name}'"
    reserved = name is not None and RESERVED_RE.match(name) is not None
    if reserved:
        ck.keys(where, raw, reserved_keys, reserved_keys)
    else:
        ck.keys(where, raw, keys, required)
    return where, name, reserved, ck.integer(where, raw, "lsb", 0), ck.integer(where, raw, "width", 1)


def check_field(ck, lname, lwidth, index, raw):
    head = field_head(ck, f"layout '{lname}'", "layout.field", index, raw, RESERVED_KEYS, FIELD_KEYS, FIELD_KEYS)
    if head is None:
        return None
    where, name, reserved, lsb, width = head
    reason = ck.string(where, raw, "reason")
    fmt = rnd = sat = None
    if not reserved:
        fmt = ck.fmt(where, raw) if "format" in raw else None
        rnd, sat = ck.modes(where, raw, fmt)
        if fmt is not None and width is not None:
            if fmt.kind == "uint" and width > UINT_MAX_WIDTH:
                ck.err(where, f"uint fields are at most {UINT_MAX_WIDTH} bits, not {width}")
            elif fmt.fixed and fmt.width() != width:
                ck.err(where, f"format {fmt.text} is {fmt.width()} bits but the field's width is {width}")
    if lsb is not None and width is not None and lwidth is not None and lsb + width > lwidth:
        ck.err(where, f"bits {lsb + width - 1}:{lsb} reach beyond the layout's width of {lwidth} bits")
    return dict(name=name, lsb=lsb, width=width, fmt=fmt, rounding=rnd, saturation=sat,
                reason=reason, reserved=reserved)


def bit_ranges(bits):
    """Sorted bit numbers -> list of (msb, lsb) runs, highest first."""
    runs = []
    for b in sorted(bits):
        if runs and runs[-1][0] == b - 1:
            runs[-1][0] = b
        else:
            runs.append([b, b])
    return [(m, l) for m, l in reversed(runs)]


def check_coverage(ck, lname, lwidth, fields):
    """Total, overlaps and gaps, over the fields whose position is known."""
    placed = [f for f in fields if f and f["name"] and f["lsb"] is not None and f["width"] is not None]
    if len(placed) != len(fields):
        return  # already reported; positions are incomplete
    total = sum(f["width"] for f in placed)
    if total != lwidth:
        ck.err(f"layout '{lname}'", f"fields total {total} bits but the layout's width is {lwidth}")
    for i, a in enumerate(placed):
        for b in placed[i + 1:]:
            common = set(range(a["lsb"], a["lsb"] + a["width"])) & set(range(b["lsb"], b["lsb"] + b["width"]))
            for m, l in bit_ranges(common):
                ck.err(f"layout '{lname}' field '{b['name']}'",
                       f"bits {m}:{l} overlap field '{a['name']}'")
    covered = set()
    for f in placed:
        covered.update(range(f["lsb"], f["lsb"] + f["width"]))
    for m, l in bit_ranges(set(range(lwidth)) - covered):
        above = min((f for f in placed if f["lsb"] > m), key=lambda f: f["lsb"], default=None)
        below = max((f for f in placed if f["lsb"] < l), key=lambda f: f["lsb"], default=None)
        if above and below:
            near = f"between field '{above['name']}' and field '{below['name']}'"
        elif above or below:
            near = f"below field '{above['name']}'" if above else f"above field '{below['name']}'"
        else:
            near = "with no field at all"
        ck.err(f"layout '{lname}'",
               f"bits {m}:{l} ({near}) belong to no field: declare them as a reserved field")


def check_layout(ck, index, raw):
    where = f"layout #{index + 1}"
    if not isinstance(raw, dict):
        ck.err(where, "must be a table ([[layout]])")
        return None
    name = ck.name(where, raw)
    if name is not None:
        where = f"layout '{name}'"
    label = name if name is not None else f"#{index + 1}"  # for the fields' messages
    ck.keys(where, raw, LAYOUT_KEYS, LAYOUT_KEYS)
    width = ck.integer(where, raw, "width", 8)
    if width is not None and width % 8:
        ck.err(where, f"width {width} is not a whole number of bytes")
        width = None
    order = raw.get("bytes_order")
    if order != "little":
        ck.err(where, f"bytes_order must be \"little\" (byte 0 holds bits 7..0), not {order!r}")
    doc = ck.string(where, raw, "doc")
    raws = raw.get("field", [])
    if not isinstance(raws, list) or not raws:
        ck.err(where, "needs at least one [[layout.field]]")
        raws = []
    fields = [check_field(ck, label, width, i, f) for i, f in enumerate(raws)]
    if raws and all(f and f["reserved"] for f in fields):
        ck.err(where, "has only reserved fields")
    seen = set()
    for f in fields:
        if f and f["name"]:
            if f["name"] in seen:
                ck.err(f"layout '{label}' field '{f['name']}'", "duplicate field name")
            seen.add(f["name"])
    if width is not None:
        check_coverage(ck, label, width, fields)
    fields = [f for f in fields if f]
    fields.sort(key=lambda f: -(f["lsb"] or 0))
    return dict(name=name, width=width, doc=doc, fields=fields)


def check_signal(ck, index, raw):
    where = f"signal #{index + 1}"
    if not isinstance(raw, dict):
        ck.err(where, "must be a table ([[signal]])")
        return None
    name = ck.name(where, raw)
    if name is not None:
        where = f"signal '{name}'"
    ck.keys(where, raw, SIGNAL_KEYS, SIGNAL_KEYS)
    fmt = ck.fmt(where, raw) if "format" in raw else None
    if fmt is not None and not fmt.fixed:
        ck.err(where, f"format {fmt.text}: signals are UQi.f or SQi.f")
    rnd, sat = ck.modes(where, raw, fmt)
    return dict(name=name, fmt=fmt, rounding=rnd, saturation=sat,
                block=ck.string(where, raw, "block"), reason=ck.string(where, raw, "reason"))


def vhdl_member(name):
    """The field's member name in the VHDL record: the name, unless it is a reserved word."""
    return name + VHDL_SUFFIX if name in VHDL_RESERVED else name


def name_claimer(ck):
    """claim(ident, who): records who generates ident; a second owner is an error."""
    owner = {}

    def claim(ident, who):
        if ident in owner and owner[ident] != who:
            ck.err(who, f"generated name {ident} collides with {owner[ident]}")
        owner.setdefault(ident, who)

    return claim


def check_names(ck, layouts, signals):
    """Generated C and VHDL names must be unique across the whole spec (layout "a_b" with
    field "c" and layout "a" with field "b_c" would both define C5_A_B_C_LSB)."""
    claim = name_claimer(ck)

    for lay in layouts:
        up = lay["name"].upper()
        # REC, PACK, UNPACK: the VHDL record type and functions (VHDL ignores case).
        for suffix in ("WIDTH", "BYTES", "FIELDS", "RESERVED", "T", "REC", "PACK", "UNPACK"):
            claim(f"{up}_{suffix}", f"layout '{lay['name']}'")
        members = {}  # VHDL record members: unique within their layout
        for f in lay["fields"]:
            for suffix in ("LSB", "WIDTH", "FMT", "RND", "RANGE"):
                claim(f"{up}_{f['name'].upper()}_{suffix}", f"layout '{lay['name']}' field '{f['name']}'")
            if f["reserved"]:
                continue
            m = vhdl_member(f["name"])
            if m in members:
                ck.err(f"layout '{lay['name']}' field '{f['name']}'",
                       f"VHDL record member {m} collides with field '{members[m]}'")
            members.setdefault(m, f["name"])
    for s in signals:
        for suffix in ("FMT", "RND", "WIDTH", "FRAC", "SIGNED"):
            claim(f"SIG_{s['name'].upper()}_{suffix}", f"signal '{s['name']}'")


def read_spec(path, allowed):
    """The TOML document of a spec and its checker; unknown top-level keys are errors."""
    ck = Checker(path)
    try:
        with open(path, "rb") as fh:
            doc = tomllib.load(fh)
    except OSError as e:
        sys.exit(f"{PROG}: {path}: cannot read: {e.strerror}")
    except tomllib.TOMLDecodeError as e:
        sys.exit(f"{PROG}: {path}: not valid TOML: {e}")
    for k in doc:
        if k not in allowed:
            ck.err("top level", f"unknown key '{k}' (allowed: {', '.join(allowed)})")
    return ck, doc


def load(path):
    ck, doc = read_spec(path, ("decisions", "layout", "signal"))
    decisions = doc.get("decisions", [])
    if not isinstance(decisions, list) or not all(isinstance(d, str) and d.strip() for d in decisions):
        ck.err("top level", "'decisions' must be an array of non-empty strings")
        decisions = []
    raw_layouts = doc.get("layout", [])
    raw_signals = doc.get("signal", [])
    if not isinstance(raw_layouts, list) or not raw_layouts:
        ck.err("top level", "needs at least one [[layout]]")
        raw_layouts = []
    if not isinstance(raw_signals, list):
        ck.err("top level", "'signal' must be an array of tables ([[signal]])")
        raw_signals = []
    layouts = [check_layout(ck, i, r) for i, r in enumerate(raw_layouts)]
    signals = [check_signal(ck, i, r) for i, r in enumerate(raw_signals)]
    for kind, items in (("layout", layouts), ("signal", signals)):
        seen = set()
        for it in items:
            if it and it["name"]:
                if it["name"] in seen:
                    ck.err(f"{kind} '{it['name']}'", f"duplicate {kind} name")
                seen.add(it["name"])
    if not ck.errors:
        check_names(ck, layouts, signals)
    if ck.errors:
        print("\n".join(ck.errors), file=sys.stderr)
        sys.exit(1)
    return decisions, layouts, signals


# ---- shared helpers ----------------------------------------------------------------------

def msb(f):
    return f["lsb"] + f["width"] - 1


def pow2(k):
    return str(1 << k)


def real_range(fmt, width):
    """The field's values in real units, as text."""
    if fmt is None:
        return "0"
    if fmt.kind == "uint":
        return f"0 .. {(1 << width) - 1}"
    if fmt.f == 0:
        lo = f"-{pow2(fmt.i)}" if fmt.signed else "0"
        return f"{lo} .. {(1 << fmt.i) - 1}"
    lo = f"-{pow2(fmt.i)}" if fmt.signed else "0"
    return f"[{lo}, {pow2(fmt.i)} - 2^-{fmt.f}], step 2^-{fmt.f}"


def spec_label(spec_path):
    """The spec's path relative to the repository, so the output does not depend on the
    directory the generator runs from."""
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    rel = os.path.relpath(os.path.abspath(spec_path), root)
    return rel if not rel.startswith("..") else os.path.basename(spec_path)


def write(path, text):
    """Through a temporary file, so make never sees half an output."""
    d = os.path.dirname(path)
    if d:
        os.makedirs(d, exist_ok=True)
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="utf-8", newline="\n") as fh:
        fh.write(text)
    os.replace(tmp, path)


# ---- C header ----------------------------------------------------------------------------

C_PRELUDE = """\
/* Generated by scripts/gen-layouts.py from {spec}. Do not edit: change the spec; the build
 * regenerates this file. docs/bit-layouts.md explains every field.
 *
 * Per layout L: c5_L_t (one member per field: uint32_t for uint fields, int64_t raw values
 * for UQ/SQ fields, value = raw * 2^-f), C5_L_<FIELD>_LSB / _WIDTH, C5_L_<FIELD>_FMT
 * (a c5_fx_fmt) and _RND (a c5_rnd, unless the field is exact), C5_L_BYTES, and
 * c5_L_pack / c5_L_unpack / c5_L_reserved_zero. Bit i of a layout is bit i % 8 of byte
 * i / 8: byte 0 holds bits 7..0. pack asserts that every value fits its field (a value out
 * of range is a bug of its producer, which rounds and saturates as the spec says); signed
 * fields are stored as two's complement in their width, reserved bits as 0. */
#ifndef C5_LAYOUTS_H
#define C5_LAYOUTS_H

#include <assert.h>
#include <stdint.h>
#include <string.h>

#include "fixed.h"

/* ---- bit access shared by every layout ------------------------------------------------ */

/* Writes the low `width` bits of v at bits lsb .. lsb + width - 1, a byte at a time. */
static inline void c5_lay_put(uint8_t *buf, unsigned lsb, unsigned width, uint64_t v)
{{
    for (unsigned done = 0; done < width;) {{
        unsigned bit = lsb + done, off = bit % 8, n = 8 - off;
        if (n > width - done)
            n = width - done;
        uint8_t mask = (uint8_t)(((1u << n) - 1u) << off);
        buf[bit / 8] = (uint8_t)((buf[bit / 8] & ~mask) | (((v >> done) << off) & mask));
        done += n;
    }}
}}

static inline uint64_t c5_lay_get(const uint8_t *buf, unsigned lsb, unsigned width)
{{
    uint64_t v = 0;
    for (unsigned done = 0; done < width;) {{
        unsigned bit = lsb + done, off = bit % 8, n = 8 - off;
        if (n > width - done)
            n = width - done;
        v |= (uint64_t)((buf[bit / 8] >> off) & ((1u << n) - 1u)) << done;
        done += n;
    }}
    return v;
}}

/* The two's-complement value of the low `width` bits of v. */
static inline int64_t c5_lay_sext(uint64_t v, unsigned width)
{{
    uint64_t sign = (uint64_t)1 << (width - 1);
    return (int64_t)((v ^ sign) - sign);
}}

/* Whether v fits `width` bits: [0, 2^w - 1], or [-2^(w-1), 2^(w-1) - 1] when signed. */
static inline int c5_lay_fits(int64_t v, unsigned width, int is_signed)
{{
    if (is_signed)
        return v >= -((int64_t)1 << (width - 1)) && v <= ((int64_t)1 << (width - 1)) - 1;
    return v >= 0 && (uint64_t)v <= ((uint64_t)1 << width) - 1u;
}}
"""


def c_banner(title):
    """A section comment as wide as the prelude's: /* ---- title ----- */"""
    head = f"/* ---- {title} "
    return head + "-" * max(4, 92 - len(head) - 3) + " */"


def c_fmt(fmt, label):
    return f"C5_{'SQ' if fmt.signed else 'UQ'}({fmt.i}, {fmt.f}, \"{label}\")"


def word_lines(nbytes, store):
    """C lines moving the layout between its bytes and the 64-bit words w0, w1, ... of its bits
    (word k holds bits 64k..64k+63, byte i bits 8i..8i+7: little-endian), byte by byte, which
    the compiler merges into word loads and stores."""
    lines = []
    for k in range((nbytes + 7) // 8):
        n = min(8, nbytes - 8 * k)
        if store:
            lines += [f"    out[{8 * k + j}] = (uint8_t)(w{k} >> {8 * j});" for j in range(n)]
        else:
            terms = [f"(uint64_t)in[{8 * k + j}] << {8 * j}" if j else f"(uint64_t)in[{8 * k}]" for j in range(n)]
            lines.append(f"    const uint64_t w{k} = " + " | ".join(terms) + ";")
    return lines


def put_word(lsb, width, expr):
    """C lines or-ing the low `width` bits of expr into the words at bit lsb (pack and unpack
    run on every ray the board model queues: word shifts, positions fixed here)."""
    k, off = lsb // 64, lsb % 64
    mask = f" & UINT64_C({hex((1 << width) - 1)})" if width < 64 else ""
    lines = [f"    {{ uint64_t v_ = {expr}{mask};", f"      w{k} |= v_ << {off};" if off else f"      w{k} |= v_;"]
    if off + width > 64:
        lines.append(f"      w{k + 1} |= v_ >> {64 - off};")
    lines[-1] += " }"
    return lines


def get_word(lsb, width):
    """The C expression of c5_lay_get(in, lsb, width) on the words."""
    k, off = lsb // 64, lsb % 64
    body = f"w{k} >> {off}" if off else f"w{k}"
    if off + width > 64:
        body += f" | w{k + 1} << {64 - off}"
    return f"(({body}) & UINT64_C({hex((1 << width) - 1)}))" if width < 64 else f"({body})"


def c_layout(lay):
    n, up = lay["name"], lay["name"].upper()
    nbytes = lay["width"] // 8
    data = [f for f in lay["fields"] if not f["reserved"]]
    resv = [f for f in lay["fields"] if f["reserved"]]
    out = ["\n" + c_banner(f"{n}: {lay['width']} bits, {nbytes} bytes") + "\n",
           f"#define C5_{up}_WIDTH {lay['width']}",
           f"#define C5_{up}_BYTES {nbytes}", ""]
    for f in lay["fields"]:
        p = f"C5_{up}_{f['name'].upper()}"
        fmt = f["fmt"]
        out.append(f"#define {p}_LSB {f['lsb']}")
        out.append(f"#define {p}_WIDTH {f['width']}")
        if fmt is not None and fmt.fixed:
            out.append(f"#define {p}_FMT {c_fmt(fmt, n + '.' + f['name'])}")
        if f["rounding"] in C_RND:
            out.append(f"#define {p}_RND {C_RND[f['rounding']]}")
    out.append("")
    def x_list(macro, comment, with_format):
        out.append(comment)
        out.append(f"#define C5_{up}_{macro}(X) \\")
        for f in data:
            p = f"C5_{up}_{f['name'].upper()}"
            extra = f", \"{f['fmt'].text}\"" if with_format else ""
            out.append(f"    X({f['name']}, {p}_LSB, {p}_WIDTH, {1 if f['fmt'].signed else 0}{extra}) \\")
        out[-1] = out[-1][:-2]

    x_list("FIELDS", "/* X(member, lsb, width, is_signed) for every field but the reserved ones, MSB first. */", False)
    x_list("FIELDS_FORMAT", "/* The same with the field's declared format as text (\"UQ9.15\", \"uint\"). */", True)
    out.append("/* X(lsb, width) for every reserved field. */")
    if resv:
        out.append(f"#define C5_{up}_RESERVED(X) \\")
        for f in resv:
            p = f"C5_{up}_{f['name'].upper()}"
            out.append(f"    X({p}_LSB, {p}_WIDTH) \\")
        out[-1] = out[-1][:-2]
    else:
        out.append(f"#define C5_{up}_RESERVED(X)")
    out.append("")
    out.append("typedef struct {")
    for f in data:
        ctype = "int64_t" if f["fmt"].fixed else "uint32_t"
        kind = f"{f['fmt'].text} raw" if f["fmt"].fixed else "uint"
        out.append(f"    {ctype} {f['name']}; /* {kind}, bits {msb(f)}:{f['lsb']} */")
    out.append(f"}} c5_{n}_t;")
    out.append("")
    out.append(f"static inline void c5_{n}_pack(const c5_{n}_t *f, uint8_t out[C5_{up}_BYTES])")
    out.append("{")
    nwords = (nbytes + 7) // 8
    out.append("    uint64_t " + ", ".join(f"w{k} = 0" for k in range(nwords)) + "; /* reserved bits stay 0 */")
    for f in data:
        p = f"C5_{up}_{f['name'].upper()}"
        sgn = 1 if f["fmt"].signed else 0
        out.append(f"    assert(c5_lay_fits((int64_t)f->{f['name']}, {p}_WIDTH, {sgn}) && "
                   f"\"{n}.{f['name']} out of range\");")
        out.extend(put_word(f["lsb"], f["width"], f"(uint64_t)f->{f['name']}"))
    out.extend(word_lines(nbytes, True))
    out.append("}")
    out.append("")
    out.append(f"static inline void c5_{n}_unpack(const uint8_t in[C5_{up}_BYTES], c5_{n}_t *f)")
    out.append("{")
    out.extend(word_lines(nbytes, False))
    for f in data:
        p = f"C5_{up}_{f['name'].upper()}"
        get = get_word(f["lsb"], f["width"])
        if f["fmt"].signed:
            out.append(f"    f->{f['name']} = c5_lay_sext({get}, {p}_WIDTH);")
        elif f["fmt"].fixed:
            out.append(f"    f->{f['name']} = (int64_t){get};")
        else:
            out.append(f"    f->{f['name']} = (uint32_t){get};")
    out.append("}")
    out.append("")
    out.append("/* 1 if every reserved bit is 0 (a packet with a set reserved bit is corrupt). */")
    out.append(f"static inline int c5_{n}_reserved_zero(const uint8_t in[C5_{up}_BYTES])")
    out.append("{")
    if resv:
        terms = [f"c5_lay_get(in, C5_{up}_{f['name'].upper()}_LSB, C5_{up}_{f['name'].upper()}_WIDTH) == 0"
                 for f in resv]
        out.append("    return " + " &&\n           ".join(terms) + ";")
    else:
        out.append("    (void)in;")
        out.append("    return 1;")
    out.append("}")
    return "\n".join(out) + "\n"


def c_header(spec, layouts, signals):
    text = C_PRELUDE.format(spec=spec)
    for lay in layouts:
        text += c_layout(lay)
    text += "\n" + c_banner("datapath signals: declared formats (docs/bit-layouts.md, Signals)") + "\n\n"
    for s in signals:
        p = f"C5_SIG_{s['name'].upper()}"
        text += f"#define {p}_FMT {c_fmt(s['fmt'], s['name'])} /* {s['block']} */\n"
        text += (f"#define {p}_WIDTH {s['fmt'].width()}\n#define {p}_FRAC {s['fmt'].f}\n"
                 f"#define {p}_FORMAT \"{s['fmt'].text}\"\n")
        if s["rounding"] in C_RND:
            text += f"#define {p}_RND {C_RND[s['rounding']]}\n"
    text += "\n#endif\n"
    return text


# ---- VHDL package ------------------------------------------------------------------------

VHDL_PRELUDE = """\
-- Generated by scripts/gen-layouts.py from {spec}. Do not edit: change the spec; the build
-- regenerates this file. docs/bit-layouts.md explains every field.
--
-- Per layout L: L_T (the packed vector), L_WIDTH, L_<FIELD>_LSB / _WIDTH / _RANGE (a
-- subtype usable as a slice: v(L_<FIELD>_RANGE)), the record type l_rec with one
-- std_logic_vector member per field (reserved fields have none; a field named like a VHDL
-- reserved word gets the suffix {suffix}: type -> type{suffix}), and the functions
-- l_pack(rec) return L_T (reserved bits 0) and l_unpack(L_T) return l_rec. Members hold
-- the field's raw bits: signed (SQ) fields in two's complement, fixed-point fields as the
-- raw integer (value = raw * 2^-f), as in the C header. Bit i of a layout is bit i mod 8
-- of byte i / 8: byte 0 holds bits 7..0.
library ieee;
use ieee.std_logic_1164.all;

package c5_layouts_pkg is"""


def vhdl_decls(lay):
    """Constants, subtypes, the record type and the function declarations of one layout."""
    n, up = lay["name"], lay["name"].upper()
    out = ["", f"  -- {n}: {lay['width']} bits",
           f"  constant {up}_WIDTH : natural := {lay['width']};",
           f"  subtype {up}_T is std_logic_vector({lay['width'] - 1} downto 0);"]
    for f in lay["fields"]:
        p = f"{up}_{f['name'].upper()}"
        what = "reserved, zero" if f["reserved"] else f["fmt"].text
        out += [f"  -- {f['name']}: {what}",
                f"  constant {p}_LSB : natural := {f['lsb']};",
                f"  constant {p}_WIDTH : natural := {f['width']};",
                f"  subtype {p}_RANGE is natural range {msb(f)} downto {f['lsb']};"]
    out += ["", f"  -- {n} as fields, MSB first; reserved bits have no member",
            f"  type {n}_rec is record"]
    for f in lay["fields"]:
        if not f["reserved"]:
            p = f"{up}_{f['name'].upper()}"
            out.append(f"    {vhdl_member(f['name'])} : std_logic_vector({p}_WIDTH - 1 downto 0); "
                       f"-- {f['fmt'].text}, bits {msb(f)}:{f['lsb']}")
    out += ["  end record;",
            f"  function {n}_pack(r : {n}_rec) return {up}_T;",
            f"  function {n}_unpack(v : {up}_T) return {n}_rec;"]
    return out


def vhdl_bodies(lay):
    n, up = lay["name"], lay["name"].upper()
    data = [f for f in lay["fields"] if not f["reserved"]]
    out = ["", f"  function {n}_pack(r : {n}_rec) return {up}_T is",
           f"    variable v : {up}_T := (others => '0'); -- reserved bits stay 0",
           "  begin"]
    for f in data:
        out.append(f"    v({up}_{f['name'].upper()}_RANGE) := r.{vhdl_member(f['name'])};")
    out += ["    return v;", f"  end function {n}_pack;", "",
            f"  function {n}_unpack(v : {up}_T) return {n}_rec is",
            f"    variable r : {n}_rec;",
            "  begin"]
    for f in data:
        out.append(f"    r.{vhdl_member(f['name'])} := v({up}_{f['name'].upper()}_RANGE);")
    out += ["    return r;", f"  end function {n}_unpack;"]
    return out


def vhdl(spec, layouts, signals):
    out = [VHDL_PRELUDE.format(spec=spec, suffix=VHDL_SUFFIX)]
    for lay in layouts:
        out += vhdl_decls(lay)
    out += ["", "  -- datapath signals: declared formats (width includes the sign bit)"]
    for s in signals:
        p = f"SIG_{s['name'].upper()}"
        out += [f"  -- {s['name']}: {s['fmt'].text} ({s['block']})",
                f"  constant {p}_WIDTH : natural := {s['fmt'].width()};",
                f"  constant {p}_FRAC : natural := {s['fmt'].f};",
                f"  constant {p}_SIGNED : boolean := {'true' if s['fmt'].signed else 'false'};"]
    out += ["", "end package c5_layouts_pkg;", "", "package body c5_layouts_pkg is"]
    for lay in layouts:
        out += vhdl_bodies(lay)
    out += ["", "end package body c5_layouts_pkg;", ""]
    return "\n".join(out)


# ---- Markdown ----------------------------------------------------------------------------

def md_cell(text):
    return " ".join(text.split()).replace("|", "\\|")


def diagram(lay):
    """One line per 32-bit row, top row first, like the paper's figures: each segment is a
    field (or the part of it that falls in this row) with its bit range."""
    rows = []
    top = lay["width"] - 1
    for row in range((lay["width"] + 31) // 32 - 1, -1, -1):
        hi, lo = min(32 * row + 31, top), 32 * row
        segs = []
        for f in lay["fields"]:
            m, l = min(msb(f), hi), max(f["lsb"], lo)
            if m < l:
                continue
            name = f["name"]
            if (m, l) != (msb(f), f["lsb"]):
                name += f"[{m - f['lsb']}:{l - f['lsb']}]"
            segs.append(f"{name} {m}:{l}")
        rows.append(f"row {row}  {hi:>3}:{lo:<3} | " + " | ".join(segs) + " |")
    return rows


def markdown(spec, decisions, layouts, signals):
    out = ["# Bit layouts", "",
           f"Generated from `{spec}` by `scripts/gen-layouts.py`: do not edit. Change the spec and "
           "run `make docs` (the test suite fails while this file is stale). The same spec gives "
           "the C model its pack/unpack functions (`build/gen/c5_layouts.h`) and the VHDL its "
           "field positions, a record type and pack/unpack functions per layout "
           "(`build/gen/c5_layouts_pkg.vhd`, used by `fpga/`).", "",
           "Conventions: bit i of a layout is bit i % 8 of byte i / 8 (byte 0 holds bits 7..0). "
           "Formats are those of `rtl_model/proc/fixed.h`: `uint` is a plain unsigned integer, `UQi.f` "
           "is unsigned with i integer and f fraction bits (i + f bits), `SQi.f` two's complement "
           "with a sign bit not counted in i (1 + i + f bits); a fixed-point field holds the raw "
           "integer value * 2^f. Rounding is how values are rounded into the field (`exact`: the "
           "value is representable, needing rounding would be a bug). Saturation: `saturate`, the "
           "producer clamps to the range and counts the clamp; `error`, a value out of range is "
           "a bug (pack asserts); `none`, a uint counter that wraps by design. Reserved bits are "
           "written as 0.", "",
           "## Decisions against the figures", ""]
    out += [f"- {md_cell(d)}" for d in decisions]
    for lay in layouts:
        n = lay["name"]
        has_fixed = any(f["fmt"] and f["fmt"].fixed for f in lay["fields"])
        out += ["", f"## {n}: {lay['width']} bits, {lay['width'] // 8} bytes", "",
                md_cell(lay["doc"]), "",
                f"C: `c5_{n}_t`, `c5_{n}_pack()`, `c5_{n}_unpack()`, `c5_{n}_reserved_zero()`, "
                f"`C5_{n.upper()}_<FIELD>_LSB` / `_WIDTH`"
                + (" (`_FMT` and `_RND` for UQ/SQ fields)" if has_fixed else "")
                + f". VHDL: `{n}_rec`, `{n}_pack()`, `{n}_unpack()`, `{n.upper()}_T`, "
                f"`{n.upper()}_<FIELD>_LSB` / `_WIDTH` / `_RANGE`"
                + ("".join(f"; the member of field `{f['name']}` is `{vhdl_member(f['name'])}`"
                           for f in lay["fields"]
                           if not f["reserved"] and vhdl_member(f["name"]) != f["name"]))
                + ".", "",
                "```text"] + diagram(lay) + ["```", "",
                "| field | bits | width | format | range | rounding | saturation | reason |",
                "|---|---|---|---|---|---|---|---|"]
        for f in lay["fields"]:
            fmt = f["fmt"].text if f["fmt"] else "reserved"
            out.append(f"| {f['name']} | {msb(f)}:{f['lsb']} | {f['width']} | {fmt} | "
                       f"{real_range(f['fmt'], f['width'])} | {f['rounding'] or '-'} | "
                       f"{f['saturation'] or '-'} | {md_cell(f['reason'])} |")
    out += ["", "## Signals", "",
            "Declared formats of the ray processor's datapath signals (not packed anywhere). "
            "C: `C5_SIG_<NAME>_FMT`, and `_RND` unless exact.", "",
            "| signal | block | format | width | range | rounding | saturation | reason |",
            "|---|---|---|---|---|---|---|---|"]
    for s in signals:
        out.append(f"| {s['name']} | {s['block']} | {s['fmt'].text} | {s['fmt'].width()} | "
                   f"{real_range(s['fmt'], s['fmt'].width())} | {s['rounding']} | "
                   f"{s['saturation']} | {md_cell(s['reason'])} |")
    return "\n".join(out) + "\n"



# ---- the register map (--regs) ------------------------------------------------------------
# spec/registers.toml: BAR0's 32-bit registers and their fields. Checked as strictly as the
# layouts, written as a second C header, a second VHDL package and docs/register-map.md.

ACCESSES = ("ro", "rw", "w1c", "wo")
REG_BITS = 32
REG_KEYS = ("name", "offset", "doc", "field")
REG_FIELD_KEYS = ("name", "lsb", "width", "access", "reset", "doc", "format")
REG_FIELD_REQUIRED = ("name", "lsb", "width", "access", "reset", "doc")
REG_RESERVED_KEYS = ("name", "lsb", "width", "doc")


def check_reg_field(ck, rname, index, raw):
    head = field_head(ck, f"register '{rname}'", "register.field", index, raw, REG_RESERVED_KEYS, REG_FIELD_KEYS,
                      REG_FIELD_REQUIRED)
    if head is None:
        return None
    where, name, reserved, lsb, width = head
    doc = ck.string(where, raw, "doc")
    if lsb is not None and width is not None and lsb + width > REG_BITS:
        ck.err(where, f"bits {lsb + width - 1}:{lsb} reach beyond the register's {REG_BITS} bits")
    access, reset, fmt = "ro", 0, None
    if not reserved:
        access = ck.string(where, raw, "access")
        if access is not None and access not in ACCESSES:
            ck.err(where, f"access '{access}' is not one of {', '.join(ACCESSES)}")
            access = None
        reset = ck.integer(where, raw, "reset", 0)
        if reset is not None and width is not None and reset >= 1 << width:
            ck.err(where, f"reset value {reset:#x} does not fit the field's {width} bits")
            reset = None
        if reset and access == "wo":
            ck.err(where, f"reset value {reset:#x} of a write-only field (which reads 0) must be 0")
        if "format" in raw:
            fmt = ck.fmt(where, raw)
        else:
            fmt = Fmt("uint", "uint")
        if fmt is not None and width is not None and fmt.fixed and fmt.width() != width:
            ck.err(where, f"format {fmt.text} is {fmt.width()} bits but the field's width is {width}")
    return dict(name=name, lsb=lsb, width=width, access=access, reset=reset, fmt=fmt, doc=doc,
                reserved=reserved)


def check_register(ck, bar, index, raw):
    where = f"register #{index + 1}"
    if not isinstance(raw, dict):
        ck.err(where, "must be a table ([[register]])")
        return None
    name = ck.name(where, raw)
    if name is not None:
        where = f"register '{name}'"
    label = name if name is not None else f"#{index + 1}"
    ck.keys(where, raw, REG_KEYS, REG_KEYS)
    offset = ck.integer(where, raw, "offset", 0)
    if offset is not None and offset % 4:
        ck.err(where, f"offset {offset:#05x} is not 4-byte aligned")
        offset = None
    if offset is not None and bar is not None and offset + 4 > bar:
        ck.err(where, f"offset {offset:#05x} lies beyond BAR0's {bar} bytes")
        offset = None
    doc = ck.string(where, raw, "doc")
    raws = raw.get("field", [])
    if not isinstance(raws, list) or not raws:
        ck.err(where, "needs at least one [[register.field]]")
        raws = []
    fields = [check_reg_field(ck, label, i, f) for i, f in enumerate(raws)]
    if raws and all(f and f["reserved"] for f in fields):
        ck.err(where, "has only reserved fields")
    seen = set()
    for f in fields:
        if f and f["name"]:
            if f["name"] in seen:
                ck.err(f"register '{label}' field '{f['name']}'", "duplicate field name")
            seen.add(f["name"])
    # Overlaps and gaps (check_coverage speaks of layouts; its checks are the same).
    placed = [f for f in fields if f and f["name"] and f["lsb"] is not None and f["width"] is not None
              and f["lsb"] + f["width"] <= REG_BITS]
    if len(placed) == len(fields):
        for i, a in enumerate(placed):
            for b in placed[i + 1:]:
                common = set(range(a["lsb"], a["lsb"] + a["width"])) & set(range(b["lsb"], b["lsb"] + b["width"]))
                for m, l in bit_ranges(common):
                    ck.err(f"register '{label}' field '{b['name']}'", f"bits {m}:{l} overlap field '{a['name']}'")
        covered = set()
        for f in placed:
            covered.update(range(f["lsb"], f["lsb"] + f["width"]))
        for m, l in bit_ranges(set(range(REG_BITS)) - covered):
            ck.err(f"register '{label}'", f"bits {m}:{l} belong to no field: declare them as a reserved field")
    fields = [f for f in fields if f]
    fields.sort(key=lambda f: -(f["lsb"] or 0))
    return dict(name=name, offset=offset, doc=doc, fields=fields)


def reg_reset(reg):
    return sum(f["reset"] << f["lsb"] for f in reg["fields"] if not f["reserved"])


def reg_mask(f):
    return ((1 << f["width"]) - 1) << f["lsb"]


def check_reg_names(ck, regs):
    """Generated names (C5_REG_..., VHDL REG_...) must be unique across the map."""
    claim = name_claimer(ck)

    for r in regs:
        up = r["name"].upper()
        for suffix in ("OFFSET", "RESET", "FIELDS", "RESERVED_BITS", "RW_BITS", "W1C_BITS", "WO_BITS", "T"):
            claim(f"{up}_{suffix}", f"register '{r['name']}'")
        for f in r["fields"]:
            for suffix in ("LSB", "WIDTH", "MASK", "RESET", "RANGE", "GET", "SET"):
                claim(f"{up}_{f['name'].upper()}_{suffix}", f"register '{r['name']}' field '{f['name']}'")


def load_regs(path):
    ck, doc = read_spec(path, ("bar0_bytes", "decisions", "register"))
    bar = ck.integer("top level", doc, "bar0_bytes", 16)
    if bar is not None and bar & (bar - 1):
        ck.err("top level", f"bar0_bytes {bar} is not a power of two (PCI BAR sizes are)")
        bar = None
    decisions = doc.get("decisions", [])
    if not isinstance(decisions, list) or not all(isinstance(d, str) and d.strip() for d in decisions):
        ck.err("top level", "'decisions' must be an array of non-empty strings")
        decisions = []
    raws = doc.get("register", [])
    if not isinstance(raws, list) or not raws:
        ck.err("top level", "needs at least one [[register]]")
        raws = []
    regs = [check_register(ck, bar, i, r) for i, r in enumerate(raws)]
    seen, at = set(), {}
    for r in regs:
        if r and r["name"]:
            if r["name"] in seen:
                ck.err(f"register '{r['name']}'", "duplicate register name")
            seen.add(r["name"])
            if r["offset"] is not None:
                if r["offset"] in at:
                    ck.err(f"register '{r['name']}'",
                           f"offset {r['offset']:#05x} overlaps register '{at[r['offset']]}'")
                at.setdefault(r["offset"], r["name"])
    regs = [r for r in regs if r]
    if not ck.errors:
        check_reg_names(ck, regs)
    if ck.errors:
        print("\n".join(ck.errors), file=sys.stderr)
        sys.exit(1)
    regs.sort(key=lambda r: r["offset"])
    return bar, decisions, regs


def hex32(v):
    return f"0x{v:08X}"


def c_regs_header(spec, bar, regs):
    out = [f"""\
/* Generated by scripts/gen-layouts.py --regs from {spec}. Do not edit: change the spec;
 * the build regenerates this file. docs/register-map.md explains every register.
 *
 * BAR0 holds 32-bit registers. Per register R: C5_REG_R_OFFSET (bytes into BAR0),
 * C5_REG_R_RESET (the word after reset), C5_REG_R_RESERVED_BITS (bits that read 0) and
 * C5_REG_R_FIELDS(X), X(r, field, lsb, width, reset) for every non-reserved field, and
 * C5_REG_R_RW_BITS / _W1C_BITS / _WO_BITS (the bits of each write access: a register file
 * keeps rw bits, clears w1c bits written 1, and acts on wo bits without storing them). Per field F:
 * C5_REG_R_F_LSB / _WIDTH / _MASK (in place) / _RESET (the field's raw reset value), and
 * c5_reg_R_get_F(word) / c5_reg_R_set_F(word, value), which work on raw bits (a signed
 * fixed-point field's two's complement in its width). */
#ifndef C5_REGS_MAP_H
#define C5_REGS_MAP_H

#include <assert.h>
#include <stdint.h>

#define C5_REG_BAR0_BYTES {bar}
#define C5_REG_COUNT {len(regs)}

/* X(name, offset, reset word, reserved bits, fields X-macro) for every register, by offset. */
#define C5_REGS(X) \\"""]
    for r in regs:
        up = f"C5_REG_{r['name'].upper()}"
        out.append(f"    X({r['name']}, {up}_OFFSET, {up}_RESET, {up}_RESERVED_BITS, {up}_FIELDS) \\")
    out[-1] = out[-1][:-2]
    out += ["", "/* X(name, offset, reset word, rw bits, w1c bits, wo bits) for every register, by offset. */",
            "#define C5_REGS_ACCESS(X) \\"]
    for r in regs:
        up = f"C5_REG_{r['name'].upper()}"
        out.append(f"    X({r['name']}, {up}_OFFSET, {up}_RESET, {up}_RW_BITS, {up}_W1C_BITS, {up}_WO_BITS) \\")
    out[-1] = out[-1][:-2]
    for r in regs:
        n, up = r["name"], f"C5_REG_{r['name'].upper()}"
        data = [f for f in r["fields"] if not f["reserved"]]
        resv = sum(reg_mask(f) for f in r["fields"] if f["reserved"])
        out += ["", c_banner(f"{n}: offset 0x{r['offset']:03X}"), "",
                f"#define {up}_OFFSET 0x{r['offset']:03X}u",
                f"#define {up}_RESET {hex32(reg_reset(r))}u",
                f"#define {up}_RESERVED_BITS {hex32(resv)}u"]
        for acc in ("rw", "w1c", "wo"):
            bits = sum(reg_mask(f) for f in data if f["access"] == acc)
            out.append(f"#define {up}_{acc.upper()}_BITS {hex32(bits)}u")
        for f in r["fields"]:
            p = f"{up}_{f['name'].upper()}"
            what = "reserved" if f["reserved"] else f"{f['access']}, {f['fmt'].text}"
            out += [f"/* {f['name']}: {what} */",
                    f"#define {p}_LSB {f['lsb']}",
                    f"#define {p}_WIDTH {f['width']}",
                    f"#define {p}_MASK {hex32(reg_mask(f))}u"]
            if not f["reserved"]:
                out.append(f"#define {p}_RESET {f['reset']:#x}u")
        out.append(f"#define {up}_FIELDS(X) \\")
        for f in data:
            p = f"{up}_{f['name'].upper()}"
            out.append(f"    X({n}, {f['name']}, {p}_LSB, {p}_WIDTH, {p}_RESET) \\")
        out[-1] = out[-1][:-2]
        for f in data:
            p = f"{up}_{f['name'].upper()}"
            fn = f"c5_reg_{n}_{{}}_{f['name']}"
            out += ["",
                    f"static inline uint32_t {fn.format('get')}(uint32_t word)",
                    "{",
                    f"    return (word & {p}_MASK) >> {p}_LSB;",
                    "}",
                    "",
                    f"/* word with field {f['name']} replaced by value (which must fit {f['width']} bits). */",
                    f"static inline uint32_t {fn.format('set')}(uint32_t word, uint32_t value)",
                    "{",
                    f"    assert((value & ~({p}_MASK >> {p}_LSB)) == 0 && \"{n}.{f['name']} out of range\");",
                    f"    return (word & ~{p}_MASK) | ((value << {p}_LSB) & {p}_MASK);",
                    "}"]
    out += ["", "#endif", ""]
    return "\n".join(out)


def vhdl_regs(spec, bar, regs):
    out = [f"""\
-- Generated by scripts/gen-layouts.py --regs from {spec}. Do not edit: change the spec;
-- the build regenerates this file. docs/register-map.md explains every register.
--
-- Per register R: REG_R_OFFSET (bytes into BAR0) and REG_R_RESET (the 32-bit word after
-- reset). Per field F: REG_R_F_LSB / _WIDTH / _RANGE (a subtype usable as a slice:
-- word(REG_R_F_RANGE)) and REG_R_F_RESET (the field's raw bits).
library ieee;
use ieee.std_logic_1164.all;

package c5_regs_pkg is

  constant REG_BAR0_BYTES : natural := {bar};
  constant REG_WIDTH : natural := {REG_BITS};
  subtype REG_T is std_logic_vector(REG_WIDTH - 1 downto 0);"""]
    for r in regs:
        up = f"REG_{r['name'].upper()}"
        out += ["", f"  -- {r['name']}",
                f"  constant {up}_OFFSET : natural := {r['offset']};",
                f"  constant {up}_RESET : REG_T := x\"{reg_reset(r):08X}\";"]
        for f in r["fields"]:
            p = f"{up}_{f['name'].upper()}"
            what = "reserved, reads 0" if f["reserved"] else f"{f['access']}, {f['fmt'].text}"
            out += [f"  -- {f['name']}: {what}",
                    f"  constant {p}_LSB : natural := {f['lsb']};",
                    f"  constant {p}_WIDTH : natural := {f['width']};",
                    f"  subtype {p}_RANGE is natural range {msb(f)} downto {f['lsb']};"]
            if not f["reserved"]:
                bits = format(f["reset"], f"0{f['width']}b")
                out.append(f"  constant {p}_RESET : std_logic_vector({p}_WIDTH - 1 downto 0) := \"{bits}\";")
    out += ["", "end package c5_regs_pkg;", ""]
    return "\n".join(out)


def markdown_regs(spec, bar, decisions, regs):
    out = ["# Register map", "",
           f"Generated from `{spec}` by `scripts/gen-layouts.py --regs`: do not edit. Change the spec "
           "and run `make docs` (the test suite fails while this file is stale). The same spec gives "
           "the C model `build/gen/c5_regs_map.h` (offsets, field masks and reset values, get/set "
           "helpers) and the VHDL the package `c5_regs_pkg` (`build/gen/c5_regs_pkg.vhd`).", "",
           f"BAR0 is {bar} bytes (0x{bar:03X}) of 32-bit registers at 4-byte aligned offsets. Access: "
           "`ro` read-only; `rw` read/write; `w1c` reads the bit, writing 1 clears it, writing 0 "
           "leaves it; `wo` write-only, reads 0. Reset values are raw bits (a signed fixed-point "
           "field's two's complement in its width); formats are those of docs/bit-layouts.md. "
           "Reserved bits read 0 and ignore writes; software writes them as 0.", "",
           "## Decisions", ""]
    out += [f"- {md_cell(d)}" for d in decisions]
    out += ["", "## Summary", "", "| offset | register | reset | doc |", "|---|---|---|---|"]
    for r in regs:
        out.append(f"| 0x{r['offset']:03X} | [{r['name']}](#{r['name']}) | "
                   f"{hex32(reg_reset(r))} | {md_cell(r['doc'])} |")
    for r in regs:
        out += ["", f"## {r['name']}", "",
                f"Offset 0x{r['offset']:03X}, reset {hex32(reg_reset(r))}. {md_cell(r['doc'])}", "",
                "| field | bits | access | format | reset | doc |", "|---|---|---|---|---|---|"]
        for f in r["fields"]:
            bits = f"{msb(f)}:{f['lsb']}" if f["width"] > 1 else f"{f['lsb']}"
            if f["reserved"]:
                out.append(f"| {f['name']} | {bits} | - | - | 0 | {md_cell(f['doc'])} |")
            else:
                out.append(f"| {f['name']} | {bits} | {f['access']} | {f['fmt'].text} | "
                           f"{f['reset']:#x} | {md_cell(f['doc'])} |")
    return "\n".join(out) + "\n"


def main():
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__.split("\n\n")[0])
    ap.add_argument("spec", nargs="?", help="the bit layouts (spec/layouts.toml)")
    ap.add_argument("--regs", metavar="REGS.toml",
                    help="read a register map (spec/registers.toml) instead of bit layouts")
    ap.add_argument("--c-header", metavar="OUT.h")
    ap.add_argument("--markdown", metavar="OUT.md")
    ap.add_argument("--vhdl", metavar="OUT.vhd")
    args = ap.parse_args()
    if (args.spec is None) == (args.regs is None):
        ap.error("give either SPEC.toml (bit layouts) or --regs REGS.toml (register map)")
    if args.regs:
        bar, decisions, regs = load_regs(args.regs)
        spec = spec_label(args.regs)
        if args.c_header:
            write(args.c_header, c_regs_header(spec, bar, regs))
        if args.markdown:
            write(args.markdown, markdown_regs(spec, bar, decisions, regs))
        if args.vhdl:
            write(args.vhdl, vhdl_regs(spec, bar, regs))
        return
    decisions, layouts, signals = load(args.spec)
    spec = spec_label(args.spec)
    if args.c_header:
        write(args.c_header, c_header(spec, layouts, signals))
    if args.markdown:
        write(args.markdown, markdown(spec, decisions, layouts, signals))
    if args.vhdl:
        write(args.vhdl, vhdl(spec, layouts, signals))


if __name__ == "__main__":
    main()
