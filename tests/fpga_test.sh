#!/usr/bin/env bash
# The VHDL in fpga/ against the golden vectors: analyses the generated layouts package,
# fpga/rtl and tb with GHDL (VHDL-2008), then runs tb_packet on every
# vectors/golden/packet.*.hex, tb_ray_queue on every vectors/golden/ray_queue.*.hex and
# each other block's testbench (tb_interp, ..., tb_cell_tree) on its BLOCK.SOURCE.hex files
# (given the memory images BLOCK.SOURCE.IMAGE.hex it is configured with or compared
# against), and checks that the testbenches can fail (one flipped bit in a copy of a file
# must give FAIL naming the line and the column; a DUT whose out_valid never rises must give
# FAIL naming out_valid). Usage: fpga_test.sh [BUILD] (default
# build/; needs BUILD/gen/c5_layouts_pkg.vhd, which `make test` builds). C5_VECTORS=DIR reads another
# vector directory. GHDL missing is a failure, not a skip: scripts/setup-deps.sh installs it.
set -u
cd "$(dirname "$0")/.."
build=${1:-build}
vectors=${C5_VECTORS:-vectors/golden}
abs() { case $1 in /*) echo "$1" ;; *) echo "$PWD/$1" ;; esac; }
work=$(abs "$build/ghdl")
pkg="$build/gen/c5_layouts_pkg.vhd"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/lib.sh"

# Source files in dependency order: packages first, each entity before its users.
RTL=(fpga/rtl/rq_pkg.vhd fpga/rtl/rq_ram.vhd fpga/rtl/rq_addr_alloc.vhd fpga/rtl/rq_stage.vhd
     fpga/rtl/ray_queue.vhd fpga/rtl/packet.vhd
     fpga/rtl/dp_pkg.vhd fpga/rtl/interp.vhd fpga/rtl/composite.vhd
     fpga/rtl/classify.vhd fpga/rtl/gradient.vhd fpga/rtl/shade.vhd
     fpga/rtl/traverse.vhd fpga/rtl/cell_tree.vhd)
TB=(tb/tb_pkg.vhd tb/vec_io_pkg.vhd tb/tb_packet.vhd tb/tb_ray_queue.vhd
    tb/tb_interp.vhd tb/tb_composite.vhd tb/tb_classify.vhd
    tb/tb_gradient.vhd tb/tb_shade.vhd tb/tb_traverse.vhd
    tb/tb_cell_tree.vhd)
# The other blocks' testbenches, each named tb_BLOCK, replayed on BLOCK.SOURCE.hex.
DATAPATH=(interp composite classify gradient shade traverse cell_tree)

if ! command -v ghdl >/dev/null 2>&1; then
    bad ghdl_present "ghdl not found: run scripts/setup-deps.sh (installs ghdl)"
    summary
fi
if [ ! -f "$pkg" ]; then
    bad layouts_package "$pkg missing: run make (make test builds it)"
    summary
fi

# ---- analyse and elaborate --------------------------------------------------------------

rm -rf "$work"
mkdir -p "$work"
if ghdl -a --std=08 --workdir="$work" "$pkg" "${RTL[@]}" "${TB[@]}" 2>"$tmp/err"; then
    ok analyse
else
    bad analyse "$(head -n 10 "$tmp/err")"
    summary
fi
# Run from the work directory: the mcode backend elaborates in memory, the LLVM and GCC
# backends write the executable to the current directory, and -r finds it there.
for tb in tb_packet tb_ray_queue "${DATAPATH[@]/#/tb_}"; do
    if (cd "$work" && ghdl -e --std=08 "$tb") 2>"$tmp/err"; then
        ok "elaborate_$tb"
    else
        bad "elaborate_$tb" "$(head -n 10 "$tmp/err")"
    fi
done

# run TB FILE [GENERIC...]: the testbench's output in $tmp/out, its exit status returned.
run() {
    local tb=$1 file=$2
    shift 2
    (cd "$work" && ghdl -r --std=08 "$tb" "-gVECTORS=$file" "$@") >"$tmp/out" 2>&1
}

# images BLOCK FILE: the generics naming the memory images the block's testbench loads
# before replaying FILE (BLOCK.SOURCE.IMAGE.hex beside it), one a line.
images() {
    local base=${2%.hex}
    case $1 in
        classify) echo "-gTABLE=$base.tf.hex" ;;
        shade) echo "-gREGS=$base.regs.hex"; echo "-gPOW=$base.pow.hex" ;;
        cell_tree) echo "-gRAM=$base.ram_final.hex"; echo "-gROOTS=$base.roots_final.hex" ;;
    esac
}

# ---- every golden vector file -----------------------------------------------------------

# golden TB BLOCK: the testbench on every BLOCK.SOURCE.hex (memory images,
# BLOCK.SOURCE.IMAGE.hex, are the testbench's configuration, not vectors); no such file is
# a failure.
golden() {
    local tb=$1 block=$2 f name found=0 gen
    for f in "$vectors/$block".*.hex; do
        [ -e "$f" ] || continue
        case $(basename "$f" .hex) in "$block".*.*) continue ;; esac
        found=1
        name="${tb}_$(basename "$f" .hex)"
        mapfile -t gen < <(images "$block" "$(abs "$f")")
        if run "$tb" "$(abs "$f")" ${gen[@]+"${gen[@]}"} && grep -q "^PASS $tb: " "$tmp/out"; then
            ok "$name"
        else
            bad "$name" "$(grep -E '^(PASS|FAIL)|error' "$tmp/out" | head -n 12)"
        fi
    done
    [ "$found" -eq 1 ] || bad "${tb}_vectors" "no $vectors/$block.*.hex"
}
golden tb_packet packet
golden tb_ray_queue ray_queue
for b in "${DATAPATH[@]}"; do
    golden "tb_$b" "$b"
done

# ---- the testbenches can fail -----------------------------------------------------------

# flip SRC LINE COLUMN OUT: OUT is SRC with the lowest bit of column COLUMN (1-based) of
# line LINE inverted (the last hex digit mapped through 0<->1, 2<->3, ...).
flip() {
    awk -v L="$2" -v C="$3" 'NR == L {
        d = index("0123456789abcdef", substr($C, length($C), 1))
        $C = substr($C, 1, length($C) - 1) substr("1032547698badcfe", d, 1)
    } { print }' "$1" >"$4"
}

# negative NAME TB FILE PATTERN...: TB on FILE must exit non-zero, print its FAIL line and
# every PATTERN (fixed strings) in its output. A datapath TB (tb_BLOCK) is given the memory
# images of the golden file FILE was copied from ($origin).
origin=""
negative() {
    local name=$1 tb=$2 file=$3 p gen=()
    shift 3
    [ -z "$origin" ] || mapfile -t gen < <(images "${tb#tb_}" "$(abs "$origin")")
    if run "$tb" "$file" ${gen[@]+"${gen[@]}"}; then
        bad "$name" "the testbench passed a corrupted file"
        return
    fi
    if ! grep -q "^FAIL $tb: " "$tmp/out"; then
        bad "$name" "no FAIL line" "$(tail -n 5 "$tmp/out")"
        return
    fi
    for p in "$@"; do
        if ! grep -qF -- "$p" "$tmp/out"; then
            bad "$name" "output lacks: $p" "$(grep error "$tmp/out" | head -n 5)"
            return
        fi
    done
    ok "$name"
}

first() { for f in "$@"; do [ -e "$f" ] && { echo "$f"; return; }; done; }
pf=$(first "$vectors"/packet.*.hex)
qf=$(first "$vectors"/ray_queue.*.hex)
if [ -n "$pf" ]; then
    # column 9 is lifetime: pack(fields) no longer gives the packet, unpack(packet) no
    # longer gives that field
    flip "$pf" 1 9 "$tmp/packet.flipped.hex"
    negative fails_on_flipped_field tb_packet "$tmp/packet.flipped.hex" \
        "line 1: lifetime: expected" "line 1: packet (pack of the fields)" "2 errors in"
    # a column one digit short
    awk 'NR == 1 { $5 = substr($5, 2) } { print }' "$pf" >"$tmp/packet.short.hex"
    negative fails_on_malformed_line tb_packet "$tmp/packet.short.hex" \
        "line 1: dir_y: expected 4 lowercase hex digits"
fi
if [ -n "$qf" ]; then
    # the first popping cycle's pop_key (column 6) off by one bit
    line=$(awk '$5 == "1" { print NR; exit }' "$qf")
    if [ -n "$line" ]; then
        flip "$qf" "$line" 6 "$tmp/ray_queue.flipped.hex"
        negative fails_on_flipped_output tb_ray_queue "$tmp/ray_queue.flipped.hex" \
            "line $line: pop_key: expected" "1 error in"
    else
        bad fails_on_flipped_output "$qf has no cycle with pop_valid = 1"
    fi
fi
negative fails_on_missing_file tb_ray_queue "$tmp/no-such.hex" "cannot open"

# Each other block: one output bit flipped in the directed file must give one error naming
# its line and column.
# dp_negative BLOCK LINE COLUMN NAME: flip bit 0 of COLUMN (1-based) of LINE.
dp_negative() {
    local block=$1 line=$2 col=$3 cname=$4 src="$vectors/$1.directed.hex"
    if [ ! -e "$src" ]; then
        bad "fails_on_flipped_${block}" "no $src"
        return
    fi
    flip "$src" "$line" "$col" "$tmp/$block.flipped.hex"
    origin=$src
    negative "fails_on_flipped_${block}" "tb_$block" "$tmp/$block.flipped.hex" \
        "line $line: $cname: expected" "1 error in"
    origin=""
}
dp_negative interp 2 12 value
dp_negative composite 2 12 rgb_r_out
dp_negative classify 3 2 r
dp_negative gradient 2 31 grad_x
dp_negative shade 3 13 rgb_r
dp_negative traverse 2 19 leaped
dp_negative cell_tree 4 3 node_out
# the Cell Tree's final images: one bit of one slot flipped in a copy of ram_final
if [ -e "$vectors/cell_tree.directed.hex" ]; then
    flip "$vectors/cell_tree.directed.ram_final.hex" 3 1 "$tmp/ram_final.flipped.hex"
    if run tb_cell_tree "$(abs "$vectors/cell_tree.directed.hex")" "-gRAM=$tmp/ram_final.flipped.hex" \
        "-gROOTS=$(abs "$vectors/cell_tree.directed.roots_final.hex")"; then
        bad fails_on_flipped_ram_image "tb_cell_tree passed a corrupted RAM image"
    elif grep -qF "line 3: ram_final slot 2: expected" "$tmp/out" && grep -q "^FAIL tb_cell_tree: 1 error in" "$tmp/out"; then
        ok fails_on_flipped_ram_image
    else
        bad fails_on_flipped_ram_image "$(grep -E '^(PASS|FAIL)|error' "$tmp/out" | head -n 5)"
    fi
fi
# classify with another source's table: the directed vectors' colours no longer come out
if [ -e "$vectors/classify.directed.hex" ] && [ -e "$vectors/classify.default.tf.hex" ]; then
    if run tb_classify "$(abs "$vectors/classify.directed.hex")" \
        "-gTABLE=$(abs "$vectors/classify.default.tf.hex")"; then
        bad fails_on_wrong_table "tb_classify passed with another scene's table"
    elif grep -q "^FAIL tb_classify: " "$tmp/out"; then
        ok fails_on_wrong_table
    else
        bad fails_on_wrong_table "no FAIL line" "$(tail -n 5 "$tmp/out")"
    fi
fi
# a table one entry short is refused before any vector
head -n 255 "$vectors/classify.directed.tf.hex" >"$tmp/short.tf.hex"
if run tb_classify "$(abs "$vectors/classify.directed.hex")" "-gTABLE=$tmp/short.tf.hex"; then
    bad fails_on_short_table "tb_classify passed with a 255-entry table"
elif grep -q "255 entries read" "$tmp/out" && grep -q "^FAIL tb_classify: " "$tmp/out"; then
    ok fails_on_short_table
else
    bad fails_on_short_table "$(tail -n 5 "$tmp/out")"
fi

# A DUT whose out_valid never rises: the testbench's valid check (vec_io_pkg check_valid)
# must fail it on the golden interp file, naming out_valid; the flipped-file checks above
# never reach that check (their out_valid is right).
mut="$tmp/mutant"
mkdir -p "$mut"
sed "s/      out_valid <= s1_valid;/      out_valid <= '0';  -- mutant/" fpga/rtl/interp.vhd >"$mut/interp.vhd"
if ! grep -q "mutant" "$mut/interp.vhd"; then
    bad fails_on_stuck_out_valid "fpga/rtl/interp.vhd has no 'out_valid <= s1_valid;' to break"
elif ! ghdl -a --std=08 --workdir="$mut" "$pkg" fpga/rtl/dp_pkg.vhd "$mut/interp.vhd" tb/tb_pkg.vhd \
        tb/vec_io_pkg.vhd tb/tb_interp.vhd 2>"$tmp/err" || ! (cd "$mut" && ghdl -e --std=08 tb_interp) 2>>"$tmp/err"; then
    bad fails_on_stuck_out_valid "$(head -n 5 "$tmp/err")"
elif f=$(abs "$vectors/interp.directed.hex") && (cd "$mut" && ghdl -r --std=08 tb_interp "-gVECTORS=$f") >"$tmp/out" 2>&1; then
    bad fails_on_stuck_out_valid "tb_interp passed a DUT whose out_valid never rises"
elif grep -qF "line 1: out_valid: expected 1 got 0" "$tmp/out" && grep -q "^FAIL tb_interp: " "$tmp/out"; then
    ok fails_on_stuck_out_valid
else
    bad fails_on_stuck_out_valid "$(grep -E '^(PASS|FAIL)|out_valid' "$tmp/out" | head -n 5)"
fi

summary
