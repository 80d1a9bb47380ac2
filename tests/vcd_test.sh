#!/usr/bin/env bash
# Waveforms (docs/vectors.md, "Waveforms"): `cube5 vectors --vcd` writes beside every vector
# file a VCD whose values at each rising clock edge are that file's vectors; GHDL's --vcd of
# tb_ray_queue on the same vectors agrees with the model's VCD signal by signal (same names,
# same values at every rising edge); a corrupted waveform is caught; a set written again
# without --vcd leaves no waveform behind. Usage: vcd_test.sh [BUILD] (default build/).
set -u
cd "$(dirname "$0")/.."
build=${1:-build}
cube5="$build/cube5"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/lib.sh"
v="$tmp/v"

if ! "$cube5" vectors --out "$v" --scene default --count 16 --vcd >"$tmp/out" 2>&1; then
    bad vectors_vcd "$(cat "$tmp/out")"
    summary
fi
# Every vector file: its waveform is listed in the manifest and equals it.
n=0
while IFS='|' read -r hex wave; do
    n=$((n + 1))
    if [ -z "$wave" ]; then
        bad "waveform_$hex" "no waveform in manifest.json"
    elif python3 tests/vcd_compare.py hex "$v/$wave" "$v/$hex" "$v/manifest.json" >"$tmp/cmp" 2>&1; then
        ok "waveform_${hex%.hex}"
    else
        bad "waveform_${hex%.hex}" "$(cat "$tmp/cmp")"
    fi
done < <(python3 -c '
import json, sys
for e in json.load(open(sys.argv[1]))["files"]:
    if e["kind"] == "vectors":
        print(e["file"] + "|" + e.get("waveform", ""))' "$v/manifest.json")
[ "$n" -gt 10 ] || bad waveform_files "only $n vector files in the set"

# The model's waveform of the ray queue beside GHDL's of its testbench on the same vectors.
work=$(cd "$build" && pwd)/ghdl-vcd
rm -rf "$work"
mkdir -p "$work"
# The queue's sources in dependency order (tests/fpga_test.sh analyses every block).
src=("$build/gen/c5_layouts_pkg.vhd" fpga/rtl/rq_pkg.vhd fpga/rtl/rq_ram.vhd fpga/rtl/rq_addr_alloc.vhd
     fpga/rtl/rq_stage.vhd fpga/rtl/ray_queue.vhd fpga/tb/tb_pkg.vhd fpga/tb/vec_io_pkg.vhd fpga/tb/tb_ray_queue.vhd)
if ghdl -a --std=08 --workdir="$work" "${src[@]}" 2>"$tmp/err" &&
    (cd "$work" && ghdl -e --std=08 tb_ray_queue && ghdl -r --std=08 tb_ray_queue \
        "-gVECTORS=$v/ray_queue.directed.hex" "--vcd=$tmp/ghdl.vcd") >"$tmp/out" 2>>"$tmp/err"; then
    if python3 tests/vcd_compare.py ghdl "$v/ray_queue.directed.vcd" "$tmp/ghdl.vcd" tb_ray_queue >"$tmp/cmp"; then
        ok ray_queue_model_and_ghdl_waves_agree
    else
        bad ray_queue_model_and_ghdl_waves_agree "$(cat "$tmp/cmp")"
    fi
    # The comparison can fail: the model's count one higher from the 20th cycle on.
    python3 - "$v/ray_queue.directed.vcd" "$tmp/bad.vcd" <<'PY'
import sys
lines = open(sys.argv[1]).read().split('\n')
ident = next(l.split()[3] for l in lines if l.startswith('$var') and l.split()[4] == 'count')
t, out, done = 0, [], False
for l in lines:
    if l.startswith('#'):
        t = int(l[1:])
    if not done and t >= 200 and l.startswith('b') and l.split()[1] == ident:
        l = 'b' + bin(int(l.split()[0][1:], 2) + 1)[2:] + ' ' + ident
        done = True
    out.append(l)
open(sys.argv[2], 'w').write('\n'.join(out))
PY
    if python3 tests/vcd_compare.py ghdl "$tmp/bad.vcd" "$tmp/ghdl.vcd" tb_ray_queue >"$tmp/cmp"; then
        bad waves_differ_on_a_corrupted_value "the comparison passed a corrupted waveform"
    elif grep -q ", count: model" "$tmp/cmp"; then
        ok waves_differ_on_a_corrupted_value
    else
        bad waves_differ_on_a_corrupted_value "$(cat "$tmp/cmp")"
    fi
else
    bad ray_queue_ghdl_vcd "$(head -n 10 "$tmp/err")" "$(tail -n 3 "$tmp/out")"
fi

# Written again without --vcd: the earlier set's waveforms are removed with it.
if "$cube5" vectors --out "$v" --scene none --count 16 >"$tmp/out" 2>&1 && ! ls "$v"/*.vcd >/dev/null 2>&1 &&
    ! grep -q '"waveform"' "$v/manifest.json"; then
    ok rewrite_without_vcd_removes_waveforms
else
    bad rewrite_without_vcd_removes_waveforms "$(ls "$v" | grep vcd | head -n 3)" "$(cat "$tmp/out")"
fi
summary
