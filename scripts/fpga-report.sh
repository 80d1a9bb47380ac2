#!/usr/bin/env bash
# make fpga-report: a synthesis estimate of fpga/rtl for a Lattice iCE40, written to
# docs/fpga-report.md. Every figure in the report is read from the tools' own outputs by
# this script (logs kept in BUILD/fpga/), never typed in.
#
#   1. ghdl --synth (VHDL-2008 -> Verilog) of each synthesizable top: packet,
#      ray_queue at the board's CAPACITY=256, ray_queue at the place-and-route capacities.
#   2. yosys synth_ice40: LUT4s, carries, flip-flops, block RAMs.
#   3. nextpnr-ice40 on an HX8K (ct256), --freq 100 (the paper's clock), a fixed --seed:
#      the ray queue at the largest capacity of PNR_CAPACITIES that fits, for Fmax.
#   4. yosys synth_ecp5 (Lattice ECP5, a larger family with hard multipliers and block
#      RAM) of every block in fpga/rtl and the 256-entry queue: resource counts only.
# The 256-entry sorter does not fit any iCE40 (it is synthesised, not placed); the codec
# has no registers (nothing to time). The report says so.
# Usage: fpga-report.sh [BUILD] [REPORT]  (default build/, docs/fpga-report.md)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
report=${2:-docs/fpga-report.md}
out="$build/fpga"
work="$out/work"
pkg="$build/gen/c5_layouts_pkg.vhd"

DEVICE=hx8k
PACKAGE=ct256
SEED=1
FREQ=100                 # MHz: the paper's ray processor clock
BOARD_CAPACITY=256
PNR_CAPACITIES=(32 16)   # tried largest first; the first that places is reported
RTL=(fpga/rtl/rq_pkg.vhd fpga/rtl/rq_ram.vhd fpga/rtl/rq_addr_alloc.vhd fpga/rtl/rq_stage.vhd
     fpga/rtl/ray_queue.vhd fpga/rtl/packet.vhd
     fpga/rtl/dp_pkg.vhd fpga/rtl/interp.vhd fpga/rtl/gradient.vhd fpga/rtl/classify.vhd
     fpga/rtl/composite.vhd fpga/rtl/shade.vhd fpga/rtl/traverse.vhd fpga/rtl/cell_tree.vhd)
# The datapath blocks and the Cell Tree tagging unit (tests/fpga_test.sh replays their
# golden vectors): ECP5 counts only.
DATAPATH=(interp gradient classify shade composite traverse cell_tree)
# The ECP5 device the counts are set against: the family's largest, LFE5U-85F. Its
# capacity is the data sheet's (Lattice FPGA-DS-02012, table 1.1), not a tool output.
ECP5_DEVICE=LFE5U-85F
ECP5_LUT4=83640
ECP5_EBR=208          # DP16KD, 18 Kb each
ECP5_MULT=156         # MULT18X18D

# The synthesis tools are not in `make test`'s profile (scripts/deps/): installed here when missing.
bash scripts/setup-deps.sh ghdl ghdl-mcode yosys nextpnr-ice40 fpga-icestorm
for tool in ghdl yosys nextpnr-ice40; do
    command -v "$tool" >/dev/null || { echo "fpga-report: $tool missing" >&2; exit 1; }
done
[ -f "$pkg" ] || { echo "fpga-report: $pkg missing: run make" >&2; exit 1; }
rm -rf "$out"
mkdir -p "$work"

say() { echo "fpga-report: $*" >&2; }

ghdl -a --std=08 --workdir="$work" "$pkg" "${RTL[@]}"

# synth NAME TOP [GENERIC...]: BUILD/fpga/NAME.v (ghdl), NAME.json and NAME.stat (yosys).
synth() {
    local name=$1 top=$2
    shift 2
    say "synthesising $name"
    if ! ghdl --synth --std=08 --workdir="$work" "$@" --out=verilog "$top" >"$out/$name.v" \
        2>"$out/$name.ghdl.log"; then
        cat "$out/$name.ghdl.log" >&2
        exit 1
    fi
    yosys -q -l "$out/$name.yosys.log" \
        -p "read_verilog $out/$name.v; synth_ice40 -top $top -json $out/$name.json; tee -q -o $out/$name.stat stat" \
        >/dev/null
}

# cells NAME PATTERN: the sum of the yosys cell counts whose type matches PATTERN (an ERE).
cells() {
    awk -v pat="^($2)\$" '$1 ~ pat && $2 ~ /^[0-9]+$/ { n += $2 } END { print n + 0 }' "$out/$1.stat"
}

# ecp5 NAME TOP [GENERIC...]: BUILD/fpga/NAME.ecp5.stat from yosys synth_ecp5 of the Verilog
# ghdl writes (BUILD/fpga/NAME.v, made here when the iCE40 step did not).
ecp5() {
    local name=$1 top=$2
    shift 2
    if [ ! -f "$out/$name.v" ]; then
        if ! ghdl --synth --std=08 --workdir="$work" "$@" --out=verilog "$top" >"$out/$name.v" \
            2>"$out/$name.ghdl.log"; then
            cat "$out/$name.ghdl.log" >&2
            exit 1
        fi
    fi
    say "synthesising $name for ECP5"
    yosys -q -l "$out/$name.ecp5.log" \
        -p "read_verilog $out/$name.v; synth_ecp5 -top $top; tee -q -o $out/$name.ecp5.stat stat" \
        >/dev/null
}

# pnr NAME: place and route NAME.json; 0 if it placed (timing met or not).
pnr() {
    say "placing and routing $1"
    nextpnr-ice40 --"$DEVICE" --package "$PACKAGE" --json "$out/$1.json" --freq "$FREQ" \
        --seed "$SEED" --timing-allow-fail --asc "$out/$1.asc" --log "$out/$1.pnr.log" \
        >/dev/null 2>&1
}

# The final (post-route) Fmax of the clock: the last "Max frequency for clock" line.
fmax() { grep "Max frequency for clock" "$out/$1.pnr.log" | tail -n 1 | sed -E 's/.*: ([0-9.]+) MHz.*/\1/'; }
# Utilisation "used/total" of a nextpnr resource (ICESTORM_LC, ICESTORM_RAM, SB_IO).
util() { grep -E "^Info:[[:space:]]+$2:" "$out/$1.pnr.log" | tail -n 1 | awk '{print $3 $4}'; }
# The clock's critical path as nextpnr reports it after routing: "x ns logic, y ns routing",
# and the cells it starts and ends at (the register-to-register section, not <async>).
crit() {
    awk '/Critical path report for clock/ { p = 1; next } /Critical path report/ { p = 0 }
         p && / Source / && !src { src = $NF } p && / Sink / { snk = $NF }
         p && /ns logic, .* ns routing/ { sub(/^Info: */, ""); split_ = $0 }
         END { printf "%s, from `%s` to `%s`", split_, src, snk }' "$out/$1.pnr.log"
}

synth packet packet
synth "ray_queue_$BOARD_CAPACITY" ray_queue "-gCAPACITY=$BOARD_CAPACITY"

placed="" tried=()
for cap in "${PNR_CAPACITIES[@]}"; do
    synth "ray_queue_$cap" ray_queue "-gCAPACITY=$cap"
    if pnr "ray_queue_$cap"; then
        placed=$cap
        break
    fi
    why=$(grep -m 1 -E "^ERROR" "$out/ray_queue_$cap.pnr.log" || true)
    tried+=("CAPACITY=$cap needs $(util "ray_queue_$cap" ICESTORM_LC) logic cells; nextpnr-ice40 stopped: \`${why:-no error line}\`")
done

ecp5 packet packet
ecp5 "ray_queue_$BOARD_CAPACITY" ray_queue "-gCAPACITY=$BOARD_CAPACITY"
for b in "${DATAPATH[@]}"; do
    ecp5 "$b" "$b"
done

# ---- the report -------------------------------------------------------------------------

row() { # row DESIGN CAPACITY NAME FMAX
    printf '| %s | %s | %s | %s | %s | %s | %s |\n' "$1" "$2" "$(cells "$3" SB_LUT4)" \
        "$(cells "$3" SB_CARRY)" "$(cells "$3" 'SB_DFF[A-Z]*')" "$(cells "$3" SB_RAM40_4K)" "$4"
}
per_stage() { # LUT4s and flip-flops per stage from two capacities' difference
    local a=$1 b=$2
    awk -v la="$(cells "ray_queue_$a" SB_LUT4)" -v lb="$(cells "ray_queue_$b" SB_LUT4)" \
        -v fa="$(cells "ray_queue_$a" 'SB_DFF[A-Z]*')" -v fb="$(cells "ray_queue_$b" 'SB_DFF[A-Z]*')" \
        -v ca="$(cells "ray_queue_$a" SB_CARRY)" -v cb="$(cells "ray_queue_$b" SB_CARRY)" \
        -v n=$((a - b)) 'BEGIN { printf "%.1f LUT4s, %.1f carries and %.1f flip-flops", (la - lb) / n, (ca - cb) / n, (fa - fb) / n }'
}

{
    echo "# FPGA synthesis estimate"
    echo
    echo "Generated by \`make fpga-report\` (\`scripts/fpga-report.sh\`): do not edit. Every figure below"
    echo "is read from the tools' outputs by the script; the logs are in \`$out/\`. The RTL is in"
    echo "\`fpga/rtl/\` (fpga/README.md); it is checked bit for bit against the C model's golden"
    echo "vectors by \`tests/fpga_test.sh\`."
    echo
    echo "## Tools and target"
    echo
    echo "- $(ghdl --version | sed -n 1p)"
    echo "- $(yosys -V)"
    echo "- $(nextpnr-ice40 --version 2>&1 | sed -n 1p)"
    echo "- Target: Lattice iCE40 ${DEVICE^^}, package $PACKAGE; timing constraint ${FREQ} MHz (the paper's"
    echo "  clock), placer seed $SEED."
    echo
    echo "## What was measured, and what was not"
    echo
    lcs=$(util "ray_queue_${PNR_CAPACITIES[0]}" ICESTORM_LC | cut -d/ -f2)
    luts=$(cells "ray_queue_$BOARD_CAPACITY" SB_LUT4)
    echo "- \`ray_queue\` at CAPACITY=$BOARD_CAPACITY (the board's queue): synthesised (resource counts"
    echo "  below), **not placed**: its $luts LUT4s are $(awk -v a="$luts" -v b="$lcs" 'BEGIN { printf "%.1f", a / b }') times the $lcs logic cells"
    echo "  (one LUT4 and one flip-flop each) of the ${DEVICE^^}, the largest iCE40. No Fmax is claimed"
    echo "  for it."
    if [ -n "$placed" ]; then
        echo "- \`ray_queue\` at CAPACITY=$placed, the largest of the capacities tried ($(IFS=,; echo "${PNR_CAPACITIES[*]}" | sed 's/,/, /g'))"
        echo "  that fits: placed and routed, for the Fmax of the stage logic. Every stage is the same"
        echo "  logic at any capacity, but at $BOARD_CAPACITY the \`pop\` broadcast reaches"
        echo "  $((BOARD_CAPACITY / placed)) times as many stages: this is the Fmax of the stage logic, not a"
        echo "  prediction for the $BOARD_CAPACITY-entry queue."
    else
        echo "- No capacity of ${PNR_CAPACITIES[*]} could be placed: no Fmax was measured."
    fi
    for t in ${tried[@]+"${tried[@]}"}; do
        echo "- Does not fit: $t."
    done
    echo "- \`packet\`: synthesised only. It is wiring (the generated pack/unpack), without"
    echo "  registers or logic, so there is no clock to time."
    echo "- Fmax is the register-to-register clock of the design; paths from and to the pins"
    echo "  (nextpnr's \`<async>\` domain) are not counted: in the board the queue's ports are"
    echo "  driven and read by the ray processor's registers, not by pins."
    echo
    echo "## Figures"
    echo
    echo "yosys \`synth_ice40\` cell counts (flip-flops: every \`SB_DFF*\` variant) and nextpnr's"
    echo "post-route maximum frequency."
    echo
    echo "| design | CAPACITY | SB_LUT4 | SB_CARRY | flip-flops | SB_RAM40_4K | Fmax (MHz), target ${FREQ} |"
    echo "|---|---|---|---|---|---|---|"
    row packet - packet "none (no registers)"
    row ray_queue "$BOARD_CAPACITY" "ray_queue_$BOARD_CAPACITY" "not placed (does not fit)"
    for cap in "${PNR_CAPACITIES[@]}"; do
        [ -f "$out/ray_queue_$cap.stat" ] || continue
        if [ "$cap" = "$placed" ]; then
            row ray_queue "$cap" "ray_queue_$cap" "**$(fmax "ray_queue_$cap")**"
        else
            row ray_queue "$cap" "ray_queue_$cap" "not placed (does not fit)"
        fi
    done
    echo
    if [ -n "$placed" ]; then
        echo "Place and route of CAPACITY=$placed: logic cells $(util "ray_queue_$placed" ICESTORM_LC),"
        echo "block RAMs $(util "ray_queue_$placed" ICESTORM_RAM), I/O $(util "ray_queue_$placed" SB_IO). Critical path:"
        echo "$(crit "ray_queue_$placed")."
        echo
        echo "Per stage (the difference between CAPACITY=$BOARD_CAPACITY and $placed, divided by the"
        echo "$((BOARD_CAPACITY - placed)) stages between them): $(per_stage "$BOARD_CAPACITY" "$placed")."
        echo
    fi
    echo "How yosys built the two memories (the payload RAM, CAPACITY x 32; the allocator's LIFO,"
    echo "CAPACITY x address bits), from its logs:"
    echo
    for cap in "$BOARD_CAPACITY" "${PNR_CAPACITIES[@]}"; do
        f="$out/ray_queue_$cap.yosys.log"
        [ -f "$f" ] || continue
        grep -E "^(mapping memory|using FF mapping for memory) " "$f" | sed -E \
            -e 's/^mapping memory ray_queue\.([^ ]+) via ([^ ]+)/`\1`: block RAM (`\2`)/' \
            -e 's/^using FF mapping for memory ray_queue\.([^ ]+)/`\1`: flip-flops/' \
            -e "s/^/- CAPACITY=$cap: /"
    done
    echo
    echo "## A larger family: Lattice ECP5 (yosys \`synth_ecp5\`)"
    echo
    echo "Resource counts of every block in \`fpga/rtl/\` and of the board's 256-entry queue after"
    echo "yosys's ECP5 technology mapping. ECP5 is the family the counts are given for because"
    echo "its logic cell is the same 4-input LUT as the iCE40's, so the two tables count the same"
    echo "unit, and it adds what the board's datapath needs and the iCE40 HX lacks: 18x18 hard"
    echo "multipliers and 18 Kb block RAMs. (\`synth_xilinx\` would count 6-input LUTs, not"
    echo "comparable cell for cell, for devices only the vendor's tools place.) The counts are"
    echo "set against the family's largest device, the $ECP5_DEVICE (data sheet: $ECP5_LUT4 LUT4s,"
    echo "$ECP5_EBR DP16KD block RAMs, $ECP5_MULT MULT18X18D multipliers)."
    echo
    echo "| design | LUT4 | CCU2C (2-bit carry) | flip-flops | MULT18X18D | DP16KD | distributed RAM (TRELLIS_DPR16X4) | LUT4 share of the $ECP5_DEVICE |"
    echo "|---|---|---|---|---|---|---|---|"
    for d in packet "ray_queue_$BOARD_CAPACITY" "${DATAPATH[@]}"; do
        label=$d
        [ "$d" = "ray_queue_$BOARD_CAPACITY" ] && label="ray_queue (CAPACITY=$BOARD_CAPACITY)"
        l=$(cells "$d.ecp5" LUT4)
        printf '| %s | %s | %s | %s | %s | %s | %s | %s |\n' "$label" "$l" "$(cells "$d.ecp5" CCU2C)" \
            "$(cells "$d.ecp5" 'TRELLIS_FF')" "$(cells "$d.ecp5" MULT18X18D)" "$(cells "$d.ecp5" DP16KD)" \
            "$(cells "$d.ecp5" TRELLIS_DPR16X4)" "$(awk -v a="$l" -v b="$ECP5_LUT4" 'BEGIN { printf "%.1f %%", 100 * a / b }')"
    done
    over=()
    for d in packet "ray_queue_$BOARD_CAPACITY" "${DATAPATH[@]}"; do
        if [ "$(cells "$d.ecp5" LUT4)" -gt "$ECP5_LUT4" ]; then
            if [ "$d" = "ray_queue_$BOARD_CAPACITY" ]; then over+=("ray_queue (CAPACITY=$BOARD_CAPACITY)"); else over+=("$d"); fi
        fi
    done
    if [ ${#over[@]} -gt 0 ]; then
        echo
        echo "More LUT4s than the $ECP5_DEVICE has (so not on any ECP5, before even routing):"
        echo "$(IFS=,; echo "${over[*]}" | sed 's/,/, /g')."
    fi
    echo
    echo "What these figures are:"
    echo
    echo "- Cells after \`synth_ecp5\` (generic optimisation, ABC's LUT mapping, the ECP5 cell"
    echo "  library), before packing into slices and before place and route. A CCU2C is two bits"
    echo "  of carry chain in one slice's two LUT4s, which \`LUT4\` does not count; PFUMX and"
    echo "  L6MUX21 (the slice's muxes that join LUT4s into 5- and 6-input functions) are in"
    echo "  the logs, not in the table, and cost no LUT4."
    echo "- \`interp\`, \`gradient\`, \`classify\`, \`composite\` and \`traverse\` are one pipeline"
    echo "  each at one transaction a cycle (\`fpga/rtl/dp_pkg.vhd\` states the latencies), so"
    echo "  every multiplication and division of the C model's arithmetic is its own hardware;"
    echo "  products wider than 18 bits take several MULT18X18D (and adders in LUT4s), as yosys"
    echo "  splits them. \`shade\` is a multi-cycle unit (one shared iterative normaliser, the"
    echo "  lights one after another) and \`cell_tree\` a state machine around its RAMs: their"
    echo "  counts are those of one such unit, whatever its throughput."
    echo "- \`classify\` holds its 256-entry table twice (the two neighbouring entries of a lookup"
    echo "  are read in one cycle), \`shade\` its 1,025-entry power table, \`cell_tree\` the 96 KB"
    echo "  node RAM and the 4,096-entry root table: their block RAMs (or, where yosys chose"
    echo "  so, distributed RAM or flip-flops; the logs name each memory's mapping)."
    echo
    echo "What they are not:"
    echo
    echo "- Not a fit, a utilisation or a speed: no ECP5 place and route was run (Debian"
    echo "  packages no nextpnr-ecp5), so there is no slice count after packing, no routing and"
    echo "  no Fmax; the share of the $ECP5_DEVICE is LUT4s alone. The pipelines' register"
    echo "  stages are placed for a plausible clock, not timed."
    echo "- Not the board's datapath as a whole: each block is synthesised alone, with its ports"
    echo "  as top-level pins; logic that a neighbour block would make constant or share is"
    echo "  counted in full."
    echo "- Not a minimum: the widths are the C model's exact intermediate widths (no operand"
    echo "  narrowed by range analysis), which is what makes the VHDL bit-exact."
    echo
    echo "## Commands"
    echo
    echo '```sh'
    echo "ghdl -a --std=08 --workdir=$work $pkg ${RTL[*]}"
    echo "ghdl --synth --std=08 --workdir=$work [-gCAPACITY=N] --out=verilog TOP > $out/NAME.v"
    echo "yosys -p 'read_verilog $out/NAME.v; synth_ice40 -top TOP -json $out/NAME.json; stat'"
    echo "nextpnr-ice40 --$DEVICE --package $PACKAGE --json $out/NAME.json --freq $FREQ --seed $SEED \\"
    echo "    --timing-allow-fail --asc $out/NAME.asc"
    echo "yosys -p 'read_verilog $out/NAME.v; synth_ecp5 -top TOP; stat'   # the ECP5 table"
    echo '```'
} >"$report.tmp"
mv "$report.tmp" "$report"
say "wrote $report"
