#!/usr/bin/env bash
# The model inside the simulator (docs/vectors.md): GHDL runs the `_live` testbenches, which
# drive seeded random stimulus into the VHDL and check every output against the C model
# called through VHPIDIRECT (BUILD/libc5ref.so): tb_ray_queue_live (fpga/rtl/ray_queue.vhd,
# every cycle) and tb_ray_packet_codec_live (fpga/rtl/ray_packet_codec.vhd, every field and
# the packed packet). Each seed must PASS, and the first again with the same figures (the
# stimulus comes from the seed alone); with the reference told to be wrong once
# (C5REF_FAULT) a run must FAIL naming the seed, where, the port or field and both values.
# Usage: live_test.sh [BUILD] [SEEDS] [CYCLES] (defaults build/, "1 2", 1200 queue cycles;
# the codec runs 8 packets a cycle; `make regress` runs more).
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
rm -rf "$work"
mkdir -p "$work"
cp "$build/libc5ref.so" "$work/" # the foreign attribute names ./libc5ref.so
src=("$build/gen/c5_layouts_pkg.vhd" fpga/rtl/rq_pkg.vhd fpga/rtl/rq_ram.vhd fpga/rtl/rq_addr_alloc.vhd
     fpga/rtl/rq_stage.vhd fpga/rtl/ray_queue.vhd fpga/rtl/ray_packet_codec.vhd fpga/tb/c5ref_pkg.vhd
     fpga/tb/tb_ray_queue_live.vhd fpga/tb/tb_ray_packet_codec_live.vhd)
if ! ghdl -a --std=08 --workdir="$work" "${src[@]}" 2>"$tmp/err" ||
    ! (cd "$work" && ghdl -e --std=08 tb_ray_queue_live && ghdl -e --std=08 tb_ray_packet_codec_live) 2>>"$tmp/err"; then
    bad analyse_live "$(head -n 10 "$tmp/err")"
    summary
fi
run() { (cd "$work" && ghdl -r --std=08 tb_ray_queue_live "-gSEED=$1" "-gCYCLES=$cycles") >"$2" 2>&1; }
codec() { (cd "$work" && ghdl -r --std=08 tb_ray_packet_codec_live "-gSEED=$1" "-gPACKETS=$((8 * cycles))") >"$2" 2>&1; }

# Every seed passes and fills the queue; the first seed twice, with the same figures.
first=${seeds%% *}
for s in $seeds; do
    if run "$s" "$tmp/a" && grep -q "PASS tb_ray_queue_live: seed $s, $cycles cycles" "$tmp/a" &&
        ! grep -q " 0 full," "$tmp/a"; then
        ok "ray_queue_live_seed_$s"
    else
        bad "ray_queue_live_seed_$s" "$(grep -E 'PASS|FAIL|error' "$tmp/a" | head -n 5)"
    fi
    [ "$s" = "$first" ] && cp "$tmp/a" "$tmp/first"
    if codec "$s" "$tmp/c" && grep -q "PASS tb_ray_packet_codec_live: seed $s, $((8 * cycles)) packets" "$tmp/c"; then
        ok "ray_packet_codec_live_seed_$s"
    else
        bad "ray_packet_codec_live_seed_$s" "$(grep -E 'PASS|FAIL|error' "$tmp/c" | head -n 5)"
    fi
done
if run "$first" "$tmp/b" && [ "$(grep -o 'PASS.*' "$tmp/first")" = "$(grep -o 'PASS.*' "$tmp/b")" ]; then
    ok live_seed_reproduces
else
    bad live_seed_reproduces "$(grep -o 'PASS.*' "$tmp/first")" "$(grep -E 'PASS|FAIL' "$tmp/b")"
fi
# faulty NAME N RUNNER PATTERN: with the reference wrong at step N the runner must FAIL
# and print PATTERN (an ERE).
faulty() {
    if C5REF_FAULT=$2 "$3" "$first" "$tmp/f"; then
        bad "$1" "a wrong reference output passed"
    elif grep -qE "$4" "$tmp/f"; then
        ok "$1"
    else
        bad "$1" "$(grep -E 'PASS|FAIL|error' "$tmp/f" | head -n 5)"
    fi
}
faulty live_fails_on_a_wrong_output 700 run \
    "FAIL tb_ray_queue_live: seed $first cycle 700: pop_key: model -?[0-9]+, VHDL -?[0-9]+"
faulty codec_live_fails_on_a_wrong_field 77 codec \
    "FAIL tb_ray_packet_codec_live: seed $first packet 77: pos_x: model -?[0-9]+, VHDL -?[0-9]+"
summary
