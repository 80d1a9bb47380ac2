#!/usr/bin/env bash
# The model inside the simulator (docs/vectors.md): GHDL runs the `_live` testbenches, which
# drive seeded random stimulus into the VHDL and check every output against the C model
# called through VHPIDIRECT (BUILD/libc5ref.so): the ray queue every cycle, the packet
# codec every field and packed word, interpolation, gradient, classification (after its
# table), compositing and the traversal step every transaction after their pipeline
# latency, the Cell Tree tagging unit every tag (to overflow) and its RAM and roots at the end,
# shading every sample under registers and a power table drawn from the seed. Each testbench must PASS on each seed (the queue filling to
# full), a seed must give the same figures twice (the stimulus comes from the seed alone),
# and with the reference told to be wrong once (C5REF_FAULT=77) each must FAIL naming the
# seed, the step, the port and both values. Usage: live_test.sh [BUILD] [SEEDS] [CYCLES]
# (defaults build/, "1 2", 1200 queue cycles; the others run 2 x CYCLES samples, steps or
# tags, 8 x CYCLES packets, CYCLES / 2 shading samples; `make regress` runs more).
set -u
cd "$(dirname "$0")/.."
build=${1:-build}
seeds=${2:-1 2}
cycles=${3:-1200}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/lib.sh"
work=$(cd "$build" && pwd)/ghdl-live

if [ ! -f "$build/libc5ref.so" ]; then
    bad libc5ref "$build/libc5ref.so missing: run make (make test builds it)"
    summary
fi
# testbench|count generic|count|step name|port the fault test breaks
live=("tb_ray_queue_live|CYCLES|$cycles|cycle|pop_key"
      "tb_packet_live|PACKETS|$((8 * cycles))|packet|pos_x"
      "tb_interp_live|SAMPLES|$((2 * cycles))|sample|value"
      "tb_gradient_live|SAMPLES|$((2 * cycles))|sample|grad\\(0\\)"
      "tb_classify_live|SAMPLES|$((2 * cycles))|sample|rgba\\(0\\)"
      "tb_composite_live|SAMPLES|$((2 * cycles))|sample|opa_out"
      "tb_traverse_live|STEPS|$((2 * cycles))|step|lifetime_out"
      "tb_cell_tree_live|TAGS|$((2 * cycles))|tag|node_out"
      "tb_shade_live|SAMPLES|$((cycles / 2))|sample|rgb\\(0\\)")
rm -rf "$work"
mkdir -p "$work"
cp "$build/libc5ref.so" "$work/" # the foreign attribute names ./libc5ref.so
src=("$build/gen/c5_layouts_pkg.vhd" fpga/rtl/rq_pkg.vhd fpga/rtl/rq_ram.vhd fpga/rtl/rq_addr_alloc.vhd
     fpga/rtl/rq_stage.vhd fpga/rtl/ray_queue.vhd fpga/rtl/packet.vhd fpga/rtl/dp_pkg.vhd
     fpga/rtl/interp.vhd fpga/rtl/gradient.vhd fpga/rtl/classify.vhd fpga/rtl/composite.vhd
     fpga/rtl/traverse.vhd fpga/rtl/cell_tree.vhd fpga/rtl/shade.vhd tb/tb_pkg.vhd tb/c5ref_pkg.vhd)
for l in "${live[@]}"; do src+=("tb/${l%%|*}.vhd"); done
if ! ghdl -a --std=08 --workdir="$work" "${src[@]}" 2>"$tmp/err"; then
    bad analyse_live "$(head -n 10 "$tmp/err")"
    summary
fi
for l in "${live[@]}"; do
    (cd "$work" && ghdl -e --std=08 "${l%%|*}") 2>>"$tmp/err" || bad "elaborate_${l%%|*}" "$(tail -n 5 "$tmp/err")"
done
# run LINE SEED OUT: the testbench of LINE on SEED, its output in OUT.
run() {
    local tb gen n
    IFS='|' read -r tb gen n _ _ <<<"$1"
    (cd "$work" && ghdl -r --std=08 "$tb" "-gSEED=$2" "-g$gen=$n") >"$3" 2>&1
}

first=${seeds%% *}
for s in $seeds; do
    for l in "${live[@]}"; do
        IFS='|' read -r tb gen n step port <<<"$l"
        if run "$l" "$s" "$tmp/a" && grep -q "PASS $tb: seed $s, $n " "$tmp/a" && ! grep -q " 0 full," "$tmp/a"; then
            ok "${tb}_seed_$s"
        else
            bad "${tb}_seed_$s" "$(grep -E 'PASS|FAIL|error' "$tmp/a" | head -n 5)" \
                "$(grep -q " 0 full," "$tmp/a" && echo "the queue never filled in $n cycles: its full and refused-insert paths went unchecked (give more cycles)")"
        fi
        [ "$s" = "$first" ] && [ "$tb" = tb_ray_queue_live ] && cp "$tmp/a" "$tmp/first"
    done
done
if run "${live[0]}" "$first" "$tmp/b" && [ "$(grep -o 'PASS.*' "$tmp/first")" = "$(grep -o 'PASS.*' "$tmp/b")" ]; then
    ok live_seed_reproduces
else
    bad live_seed_reproduces "$(grep -o 'PASS.*' "$tmp/first")" "$(grep -E 'PASS|FAIL' "$tmp/b")"
fi
# With the reference wrong at step 77 every testbench must FAIL there, naming both values.
for l in "${live[@]}"; do
    IFS='|' read -r tb gen n step port <<<"$l"
    if C5REF_FAULT=77 run "$l" "$first" "$tmp/f"; then
        bad "${tb}_fails_on_a_wrong_reference" "a wrong reference output passed"
    elif grep -qE "FAIL $tb: seed $first $step 77: $port: model -?[0-9]+, VHDL -?[0-9]+" "$tmp/f"; then
        ok "${tb}_fails_on_a_wrong_reference"
    else
        bad "${tb}_fails_on_a_wrong_reference" "$(grep -E 'PASS|FAIL|error' "$tmp/f" | head -n 5)"
    fi
done
summary
