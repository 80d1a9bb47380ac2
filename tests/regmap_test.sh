#!/usr/bin/env bash
# scripts/gen-layouts.py --regs: docs/register-map.md matches spec/registers.toml (regenerated
# into a temporary file), the C header stands alone, GHDL analyses the VHDL package, and
# every kind of broken register spec is refused with exit status 1 and a one-line message
# naming the register and field. Usage: regmap_test.sh
set -u
gen="$PWD/scripts/gen-layouts.py"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/lib.sh"

# ---- the real spec ----------------------------------------------------------------------

if python3 "$gen" --regs spec/registers.toml --markdown "$tmp/register-map.md" 2>"$tmp/err"; then
    if cmp -s "$tmp/register-map.md" docs/register-map.md; then
        ok regmap_docs_fresh
    else
        bad regmap_docs_fresh "docs/register-map.md is stale: run make docs" \
            "$(diff docs/register-map.md "$tmp/register-map.md" | head -n 6)"
    fi
else
    bad regmap_docs_fresh "generator failed on spec/registers.toml" "$(cat "$tmp/err")"
fi

if python3 "$gen" --regs spec/registers.toml --c-header "$tmp/gen/c5_regs_map.h" \
    --vhdl "$tmp/gen/c5_regs_pkg.vhd" 2>"$tmp/err"; then
    ok regmap_all_backends
else
    bad regmap_all_backends "$(cat "$tmp/err")"
fi
if printf '#include "c5_regs_map.h"\n' | ${CC:-cc} -std=c11 -Wall -Wextra -Werror -pedantic -fsyntax-only \
    -I"$tmp/gen" -x c - 2>"$tmp/err"; then
    ok regmap_header_self_contained
else
    bad regmap_header_self_contained "$(head -n 5 "$tmp/err")"
fi
if grep -q '^package c5_regs_pkg is$' "$tmp/gen/c5_regs_pkg.vhd" 2>/dev/null &&
   grep -q '^  constant REG_ID_OFFSET : natural := 0;$' "$tmp/gen/c5_regs_pkg.vhd" &&
   grep -q '^  constant REG_ID_RESET : REG_T := x"43554235";$' "$tmp/gen/c5_regs_pkg.vhd" &&
   grep -q '^  subtype REG_STATUS_ERROR_RANGE is natural range 7 downto 4;$' "$tmp/gen/c5_regs_pkg.vhd"; then
    ok regmap_vhdl_package
else
    bad regmap_vhdl_package "$(head -n 20 "$tmp/gen/c5_regs_pkg.vhd" 2>&1)"
fi
# GHDL is required (tests/fpga_test.sh fails without it too).
mkdir -p "$tmp/ghdl"
if ! command -v ghdl >/dev/null 2>&1; then
    bad regmap_vhdl_analyses "ghdl not found (scripts/setup-deps.sh installs it)"
elif ghdl -a --std=08 --workdir="$tmp/ghdl" "$tmp/gen/c5_regs_pkg.vhd" 2>"$tmp/err"; then
    ok regmap_vhdl_analyses
else
    bad regmap_vhdl_analyses "$(head -n 5 "$tmp/err")"
fi

# ---- broken specs -----------------------------------------------------------------------

top() { printf 'bar0_bytes = %s\n' "${1:-64}"; }
reg() { printf '[[register]]\nname = "%s"\noffset = %s\ndoc = "d"\n' "$1" "$2"; }
field() { # field NAME LSB WIDTH [ACCESS [RESET [FORMAT]]]
    printf '[[register.field]]\nname = "%s"\nlsb = %s\nwidth = %s\naccess = "%s"\nreset = %s\ndoc = "d"\n' \
        "$1" "$2" "$3" "${4:-rw}" "${5:-0}"
    [ -n "${6:-}" ] && printf 'format = "%s"\n' "$6"
    return 0
}
resv() { printf '[[register.field]]\nname = "%s"\nlsb = %s\nwidth = %s\ndoc = "d"\n' "$1" "$2" "$3"; }

# spec NAME STATUS PATTERN TOML: as in tests/layouts_test.sh: exit status, PATTERN (a fixed
# string) in stderr, only gen-layouts lines there, one line per problem, no header written
# for a refused spec, and an accepted spec's header compiles.
spec() {
    local name=$1 want=$2 pat=$3 err status
    printf '%s\n' "$4" >"$tmp/$name.toml"
    err=$(python3 "$gen" --regs "$tmp/$name.toml" --c-header "$tmp/$name.h" 2>&1 >/dev/null)
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
        -Werror -pedantic -fsyntax-only -I"$tmp" -x c - 2>&1); then
        bad "$name" "its header does not compile" "$err"
    else
        ok "$name"
    fi
}

spec regs_minimal_ok 0 "" \
    "$(top; reg a 0; field x 0 8 rw 255; resv reserved 8 24; reg b 4; field y 0 32 ro 0x12345678)"
spec regs_formats_ok 0 "" \
    "$(top; reg a 0; field v 0 29 rw 0 SQ13.15; resv reserved 29 3; reg b 8; field w 0 1 w1c; field k 1 1 wo; resv reserved0 2 30)"
spec regs_overlapping_registers 1 "register 'b': offset 0x004 overlaps register 'a'" \
    "$(top; reg a 4; field x 0 32; reg b 4; field y 0 32)"
spec regs_misaligned_offset 1 "register 'a': offset 0x006 is not 4-byte aligned" \
    "$(top; reg a 6; field x 0 32)"
spec regs_beyond_bar 1 "register 'a': offset 0x040 lies beyond BAR0's 64 bytes" \
    "$(top; reg a 64; field x 0 32)"
spec regs_bar_not_power_of_two 1 "top level: bar0_bytes 48 is not a power of two" \
    "$(top 48; reg a 0; field x 0 32)"
spec regs_field_outside 1 "register 'a' field 'x': bits 32:24 reach beyond the register's 32 bits" \
    "$(top; reg a 0; field x 24 9; resv reserved 0 24)"
spec regs_overlapping_fields 1 "register 'a' field 'y': bits 11:8 overlap field 'x'" \
    "$(top; reg a 0; field x 8 24; field y 0 12)"
spec regs_gap 1 "register 'a': bits 7:0 belong to no field" \
    "$(top; reg a 0; field x 8 24)"
spec regs_unknown_access 1 "register 'a' field 'x': access 'rc' is not one of ro, rw, w1c, wo" \
    "$(top; reg a 0; field x 0 32 rc)"
spec regs_reset_too_wide 1 "register 'a' field 'x': reset value 0x100 does not fit the field's 8 bits" \
    "$(top; reg a 0; field x 0 8 rw 256; resv reserved 8 24)"
spec regs_wo_reset 1 "register 'a' field 'x': reset value 0x1 of a write-only field (which reads 0) must be 0" \
    "$(top; reg a 0; field x 0 1 wo 1; resv reserved 1 31)"
spec regs_format_width 1 "register 'a' field 'x': format UQ1.15 is 16 bits but the field's width is 8" \
    "$(top; reg a 0; field x 0 8 rw 0 UQ1.15; resv reserved 8 24)"
spec regs_duplicate_register 1 "register 'a': duplicate register name" \
    "$(top; reg a 0; field x 0 32; reg a 4; field y 0 32)"
spec regs_duplicate_field 1 "register 'a' field 'x': duplicate field name" \
    "$(top; reg a 0; field x 0 16; field x 16 16)"
spec regs_name_collision 1 "generated name A_B_C_LSB collides" \
    "$(top; reg a_b 0; field c 0 32; reg a 4; field b_c 0 32)"
spec regs_missing_reset 1 "register 'a' field 'x': missing key 'reset'" \
    "$(top; reg a 0; printf '[[register.field]]\nname = "x"\nlsb = 0\nwidth = 32\naccess = "rw"\ndoc = "d"\n')"
spec regs_unknown_key 1 "register 'a' field 'x': unknown key 'acces'" \
    "$(top; reg a 0; field x 0 32; echo 'acces = "rw"')"
spec regs_only_reserved 1 "register 'a': has only reserved fields" \
    "$(top; reg a 0; resv reserved 0 32)"
spec regs_not_toml 1 "not valid TOML" '[[register]] name = '

summary
[ "$failed" -eq 0 ]
