#!/usr/bin/env bash
# scripts/gen-layouts.py: docs/bit-layouts.md matches spec/layouts.toml (regenerated into a
# temporary file), every backend runs, and every kind of broken spec is refused with exit
# status 1 and a one-line message naming the layout and field. Usage: layouts_test.sh
set -u
gen="$PWD/scripts/gen-layouts.py"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/lib.sh"

# ---- the real spec ----------------------------------------------------------------------

if python3 "$gen" spec/layouts.toml --markdown "$tmp/bit-layouts.md" 2>"$tmp/err"; then
    if cmp -s "$tmp/bit-layouts.md" docs/bit-layouts.md; then
        ok docs_fresh
    else
        bad docs_fresh "docs/bit-layouts.md is stale: run make docs" \
            "$(diff docs/bit-layouts.md "$tmp/bit-layouts.md" | head -n 6)"
    fi
else
    bad docs_fresh "generator failed on spec/layouts.toml" "$(cat "$tmp/err")"
fi

if python3 "$gen" spec/layouts.toml --c-header "$tmp/gen/c5_layouts.h" --vhdl "$tmp/gen/pkg.vhd" 2>"$tmp/err"; then
    ok all_backends
else
    bad all_backends "$(cat "$tmp/err")"
fi
# The VHDL's shape and one field by text (fpga/ relies on these names) ...
if grep -q '^package c5_layouts_pkg is$' "$tmp/gen/pkg.vhd" 2>/dev/null &&
   grep -q '^  constant RAY_PACKET_POS_X_LSB : natural := 233;$' "$tmp/gen/pkg.vhd" &&
   grep -q '^  subtype RAY_PACKET_POS_X_RANGE is natural range 255 downto 233;$' "$tmp/gen/pkg.vhd" &&
   grep -q '^  constant RAY_PACKET_WIDTH : natural := 256;$' "$tmp/gen/pkg.vhd" &&
   grep -q '^end package c5_layouts_pkg;$' "$tmp/gen/pkg.vhd"; then
    ok vhdl_package
else
    bad vhdl_package "$(head -n 20 "$tmp/gen/pkg.vhd" 2>&1)"
fi
# ... and GHDL analyses it as VHDL-2008 (tests/fpga_test.sh fails when GHDL is missing;
# here the case is only skipped, not counted).
if command -v ghdl >/dev/null 2>&1; then
    mkdir -p "$tmp/ghdl"
    if ghdl -a --std=08 --workdir="$tmp/ghdl" "$tmp/gen/pkg.vhd" 2>"$tmp/err"; then
        ok vhdl_package_analyses
    else
        bad vhdl_package_analyses "$(head -n 5 "$tmp/err")"
    fi
else
    echo "skip vhdl_package_analyses (no ghdl)"
fi
# The header stands alone: it includes what it uses.
if printf '#include "c5_layouts.h"\n' | ${CC:-cc} -std=c11 -Wall -Wextra -Werror -pedantic -fsyntax-only \
    -Icommon -Irtl_model -Irtl_model/proc -I"$tmp/gen" -x c - 2>"$tmp/err"; then
    ok header_self_contained
else
    bad header_self_contained "$(head -n 5 "$tmp/err")"
fi

# ---- broken specs -----------------------------------------------------------------------

layout() { printf '[[layout]]\nname = "%s"\nwidth = %s\nbytes_order = "little"\ndoc = "d"\n' "$1" "$2"; }
field() { # field NAME LSB WIDTH [FORMAT [ROUNDING]]
    printf '[[layout.field]]\nname = "%s"\nlsb = %s\nwidth = %s\nformat = "%s"\nrounding = "%s"\nsaturation = "error"\nreason = "r"\n' \
        "$1" "$2" "$3" "${4:-uint}" "${5:-exact}"
}
resv() { printf '[[layout.field]]\nname = "%s"\nlsb = %s\nwidth = %s\nreason = "r"\n' "$1" "$2" "$3"; }
signal() { printf '[[signal]]\nname = "%s"\nformat = "UQ1.15"\nrounding = "trunc"\nsaturation = "saturate"\nblock = "b"\nreason = "r"\n' "$1"; }

# spec NAME STATUS PATTERN TOML: exit status, and PATTERN (a fixed string) in stderr, every
# line of which is a gen-layouts message (no Python traceback); an accepted spec's header
# must compile, a refused spec must leave no header behind.
spec() {
    local name=$1 want=$2 pat=$3 err status
    printf '%s\n' "$4" >"$tmp/$name.toml"
    err=$(python3 "$gen" "$tmp/$name.toml" --c-header "$tmp/$name.h" 2>&1 >/dev/null)
    status=$?
    if [ "$status" -ne "$want" ]; then
        bad "$name" "exit $status, expected $want" "$err"
    elif [ -n "$pat" ] && ! grep -qF -- "$pat" <<<"$err"; then
        bad "$name" "stderr lacks: $pat" "$err"
    elif [ -n "$err" ] && grep -qv '^gen-layouts: ' <<<"$err"; then
        bad "$name" "stray output" "$err"
    elif [ "$want" -ne 0 ] && [ -e "$tmp/$name.h" ]; then
        bad "$name" "a header was written for a refused spec"
    elif [ "$want" -eq 0 ] && ! err=$(printf '#include "%s.h"\n' "$name" | ${CC:-cc} -std=c11 -Wall -Wextra \
        -Werror -pedantic -fsyntax-only -Icommon -Irtl_model -Irtl_model/proc -I"$tmp" -x c - 2>&1); then
        bad "$name" "its header does not compile" "$err"
    else
        ok "$name"
    fi
}

spec spec_minimal_ok 0 "" \
    "$(layout t 16; field a 8 8; field b 0 4 SQ1.2 half-up; resv reserved 4 4; signal s)"
spec spec_numbered_reserved_ok 0 "" \
    "$(layout t 24; field a 16 8; resv reserved0 8 8; field b 4 4; resv reserved1 0 4)"
spec spec_overlap 1 "layout 't' field 'b': bits 11:8 overlap field 'a'" \
    "$(layout t 16; field a 8 8; field b 4 8; resv reserved 0 4)"
spec spec_beyond_width 1 "layout 't' field 'a': bits 16:8 reach beyond the layout's width of 16 bits" \
    "$(layout t 16; field a 8 9; field b 0 8)"
spec spec_gap 1 "layout 't': bits 8:8 (between field 'a' and field 'b') belong to no field" \
    "$(layout t 16; field a 9 7; field b 0 8)"
spec spec_gap_bottom 1 "layout 't': bits 1:0 (below field 'b') belong to no field" \
    "$(layout t 16; field a 8 8; field b 2 6)"
spec spec_total 1 "layout 't': fields total 17 bits but the layout's width is 16" \
    "$(layout t 16; field a 8 8; field b 0 9)"
spec spec_format_width 1 "layout 't' field 'a': format UQ4.8 is 12 bits but the field's width is 8" \
    "$(layout t 16; field a 8 8 UQ4.8 half-even; field b 0 8)"
spec spec_format_width_signed 1 "layout 't' field 'a': format SQ1.7 is 9 bits but the field's width is 8" \
    "$(layout t 16; field a 8 8 SQ1.7 half-even; field b 0 8)"
spec spec_duplicate_field 1 "layout 't' field 'a': duplicate field name" \
    "$(layout t 16; field a 8 8; field a 0 8)"
spec spec_duplicate_reserved 1 "layout 't' field 'reserved': duplicate field name" \
    "$(layout t 16; resv reserved 8 8; field a 4 4; resv reserved 0 4)"
spec spec_duplicate_layout 1 "layout 't': duplicate layout name" \
    "$(layout t 8; field a 0 8; layout t 8; field b 0 8)"
spec spec_duplicate_signal 1 "signal 's': duplicate signal name" \
    "$(layout t 8; field a 0 8; signal s; signal s)"
spec spec_c_name_collision 1 "generated name A_B_C_LSB collides" \
    "$(layout a_b 8; field c 0 8; layout a 8; field b_c 0 8)"
spec spec_vhdl_member_collision 1 "layout 't' field 'type_f': VHDL record member type_f collides with field 'type'" \
    "$(layout t 16; field type 8 8; field type_f 0 8)"
spec spec_vhdl_reserved_word_ok 0 "" \
    "$(layout t 16; field type 8 8; field range 0 8)"
spec spec_bad_rounding 1 "layout 't' field 'a': rounding 'nearest' is not one of" \
    "$(layout t 8; field a 0 8 uint nearest)"
spec spec_unknown_key 1 "layout 't' field 'a': unknown key 'rouding'" \
    "$(layout t 8; field a 0 8; echo 'rouding = "exact"')"
spec spec_not_whole_bytes 1 "layout 't': width 12 is not a whole number of bytes" \
    "$(layout t 12; field a 0 12)"
spec spec_not_toml 1 "not valid TOML" '[[layout]] name = '

summary
[ "$failed" -eq 0 ]
