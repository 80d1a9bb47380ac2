#!/usr/bin/env bash
# Waveforms (docs/vectors.md, "Waveforms"): `cube5 vectors --vcd` writes beside every vector
# file a VCD whose values at each rising clock edge are that file's vectors; GHDL's --vcd of
# tb_ray_queue on the same vectors agrees with the model's VCD signal by signal (same names,
# same values at every rising edge); a corrupted waveform is caught; a set written again
# without --vcd leaves no waveform behind. `cube5 render --vcd`: the frame's ray_queue scope
# is the scene's queue waveform and its ray_bus scope the packet vectors; a window; the same
# bytes twice; refusals. Usage: vcd_test.sh [BUILD] (default build/).
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
     fpga/rtl/rq_stage.vhd fpga/rtl/ray_queue.vhd tb/tb_pkg.vhd tb/vec_io_pkg.vhd tb/tb_ray_queue.vhd)
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

# `cube5 render --vcd` (docs/vectors.md, "Waveforms of a frame"): the frame's waveform
# against the vectors of the same scene, size and split. --count 1024 keeps every packet
# written to a queue and the sorter's first 4096 cycles: the whole 16x16 frame.
f="$tmp/f"
mkdir -p "$f"
render=("$cube5" render default --model rtl --size 16x16 --cells 2)
if "$cube5" vectors --out "$f/vec" --scene default --size 16x16 --cells 2 --count 1024 --vcd >"$tmp/out" 2>&1 &&
    "${render[@]}" --vcd "$f/frame.vcd" --json >"$f/frame.json" 2>"$f/frame.err"; then
    # The ray_queue scope is the scene's ray_queue waveform, cycle for cycle.
    if python3 tests/vcd_compare.py scope "$f/frame.vcd" ray_queue "$f/vec/ray_queue.default.vcd" ray_queue \
        >"$tmp/cmp" 2>&1 && grep -q "^$(($(wc -l <"$f/vec/ray_queue.default.hex"))) cycles" "$tmp/cmp" &&
        python3 - "$f/frame.json" "$(wc -l <"$f/vec/ray_queue.default.hex")" <<'PY' >>"$tmp/cmp" 2>&1
import json, sys
w = json.load(open(sys.argv[1]))['waveform']
n = int(sys.argv[2])
sys.exit(0 if (w['cycles_written'], w['cycles_frame'], w['cut'], w['from']) == (n, n, False, 0) else print(w) or 1)
PY
    then
        ok render_vcd_queue_is_the_vectors_queue
    else
        bad render_vcd_queue_is_the_vectors_queue "$(cat "$tmp/cmp")"
    fi
    # The ray_bus scope's packets among the packet vectors, and as many as the board counts.
    busn=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["board"]["bus_packets"])' "$f/frame.json")
    if python3 tests/vcd_compare.py bus "$f/frame.vcd" "$f/vec/packet.default.hex" "$f/vec/manifest.json" \
        >"$tmp/cmp" 2>&1 && grep -q "^$busn ray bus packets" "$tmp/cmp"; then
        ok render_vcd_bus_is_the_packet_vectors
    else
        bad render_vcd_bus_is_the_packet_vectors "board bus_packets $busn" "$(cat "$tmp/cmp")"
    fi
    # GHDL's tb_ray_queue on the scene's queue vectors (the whole frame) beside the frame's
    # waveform: the side by side of docs/vectors.md.
    if (cd "$work" && ghdl -r --std=08 tb_ray_queue "-gVECTORS=$f/vec/ray_queue.default.hex" \
        "--vcd=$f/ghdl.vcd") >"$tmp/out" 2>&1 &&
        python3 tests/vcd_compare.py ghdl "$f/frame.vcd" "$f/ghdl.vcd" tb_ray_queue >"$tmp/cmp" 2>&1; then
        ok render_vcd_queue_and_ghdl_waves_agree
    else
        bad render_vcd_queue_and_ghdl_waves_agree "$(tail -n 3 "$tmp/out")" "$(cat "$tmp/cmp")"
    fi
    # Both checks fail on a waveform changed in one value: the count one higher in cycle 20,
    # one bit of the 30th bus packet flipped.
    python3 - "$f/frame.vcd" "$f/bad_q.vcd" "$f/bad_b.vcd" <<'PY'
import sys
text = open(sys.argv[1]).read().split('\n')
def ident(scope, name):
    cur = None
    for l in text:
        w = l.split()
        if l.startswith('$scope'):
            cur = w[2]
        if l.startswith('$var') and cur == scope and w[4] == name:
            return w[3]
def corrupt(out, scope, name, nth, t_min):
    i, seen, t, res = ident(scope, name), 0, 0, []
    for l in text:
        if l.startswith('#'):
            t = int(l[1:])
        w = l.split()
        if len(w) == 2 and w[1] == i and t >= t_min and seen >= 0:
            seen += 1
            if seen == nth:
                l, seen = 'b' + bin(int(w[0][1:], 2) ^ 1)[2:] + ' ' + i, -1
        res.append(l)
    open(out, 'w').write('\n'.join(res))
corrupt(sys.argv[2], 'ray_queue', 'count', 1, 200 * 10**6)
corrupt(sys.argv[3], 'ray_bus', 'pos_x', 30, 0)
PY
    if python3 tests/vcd_compare.py scope "$f/bad_q.vcd" ray_queue "$f/vec/ray_queue.default.vcd" ray_queue \
        >"$tmp/cmp" 2>&1; then
        bad render_vcd_queue_check_can_fail "a corrupted count passed"
    elif grep -q ", count: ray_queue" "$tmp/cmp"; then
        ok render_vcd_queue_check_can_fail
    else
        bad render_vcd_queue_check_can_fail "$(cat "$tmp/cmp")"
    fi
    if python3 tests/vcd_compare.py bus "$f/bad_b.vcd" "$f/vec/packet.default.hex" "$f/vec/manifest.json" \
        >"$tmp/cmp" 2>&1; then
        bad render_vcd_bus_check_can_fail "a corrupted packet passed"
    elif grep -q "bus packet" "$tmp/cmp"; then
        ok render_vcd_bus_check_can_fail
    else
        bad render_vcd_bus_check_can_fail "$(cat "$tmp/cmp")"
    fi
    # A window: --vcd-from C --vcd-cycles N holds cycles C..C+N-1 at the times of the whole
    # frame's, says so in its header, and the cut is said on stderr.
    if "${render[@]}" --vcd "$f/win.vcd" --vcd-from 100 --vcd-cycles 200 >/dev/null 2>"$f/win.err" &&
        python3 tests/vcd_compare.py scope "$f/win.vcd" ray_queue "$f/frame.vcd" ray_queue >"$tmp/cmp" 2>&1 &&
        grep -q "^200 cycles" "$tmp/cmp" && grep -q '^\$comment .*cycles 100 to 299 of the frame' "$f/win.vcd" &&
        grep -q "cycles 100 to 299 of the frame's [0-9]* (cut: --vcd-cycles)" "$f/win.err"; then
        ok render_vcd_window
    else
        bad render_vcd_window "$(cat "$tmp/cmp")" "$(cat "$f/win.err")" "$(grep -m1 '^\$comment' "$f/win.vcd")"
    fi
    # The same bytes on every run (a frame with taps runs on the calling thread alone),
    # and no date in the file.
    if "${render[@]}" --threads 3 --vcd "$f/again.vcd" >/dev/null 2>&1 && cmp -s "$f/frame.vcd" "$f/again.vcd" &&
        ! grep -q '\$date' "$f/frame.vcd"; then
        ok render_vcd_same_bytes
    else
        bad render_vcd_same_bytes "$(cmp "$f/frame.vcd" "$f/again.vcd" 2>&1)"
    fi
else
    bad render_vcd "$(cat "$tmp/out")" "$(cat "$f/frame.err" 2>/dev/null)"
fi
# Refusals: one line, exit 2, nothing written over.
refuse() { # refuse NAME PATTERN -- CMD...
    local name=$1 pat=$2 err status
    shift 3
    err=$("$@" 2>&1 >/dev/null)
    status=$?
    judge "$name" 2 "$status" "$err" "$pat" && ok "$name"
}
# An existing waveform is replaced, whole, as -o replaces an image (README, "Conventions");
# -o and --vcd naming one file (through a link too) are refused before the frame is rendered.
echo keep >"$f/taken.vcd"
if "${render[@]}" --vcd "$f/taken.vcd" >/dev/null 2>&1 && head -c 9 "$f/taken.vcd" | grep -q '^\$version'; then
    ok render_vcd_replaces_existing
else
    bad render_vcd_replaces_existing "$(head -c 40 "$f/taken.vcd")"
fi
ln -sf same.png "$f/alias.png"
refuse render_vcd_same_file_as_image "--vcd .*alias.png: names the same file as -o .*same.png" -- "${render[@]}" \
    -o "$f/same.png" --vcd "$f/alias.png"
[ -e "$f/same.png" ] && bad render_vcd_same_file_nothing_written "$f/same.png was written"
refuse render_vcd_cycles_zero "--vcd-cycles: expected an integer in \[1, " -- "${render[@]}" --vcd "$f/n.vcd" --vcd-cycles 0
refuse render_vcd_cycles_word "--vcd-cycles: expected an integer" -- "${render[@]}" --vcd "$f/n.vcd" --vcd-cycles many
refuse render_vcd_from_negative "--vcd-from: expected an integer in \[0, " -- "${render[@]}" --vcd "$f/n.vcd" --vcd-from -1
refuse render_vcd_window_alone "--vcd-cycles/--vcd-from: only with --vcd FILE" -- "${render[@]}" --vcd-cycles 5
refuse render_vcd_cref "--vcd: only with --model rtl" -- "$cube5" render default --size 16x16 --vcd "$f/n.vcd"
refuse render_vcd_frames "--vcd: the waveform is of one frame" -- "$cube5" render brain_mirrors --model rtl --size 8x8 \
    --frames 2 --vcd "$f/n.vcd"
refuse render_vcd_missing_value "--vcd: missing value" -- "${render[@]}" --vcd
[ ! -e "$f/n.vcd" ] || bad render_vcd_refusals_write_nothing "$f/n.vcd was written"

# Written again without --vcd: the earlier set's waveforms are removed with it.
if "$cube5" vectors --out "$v" --scene none --count 16 >"$tmp/out" 2>&1 && ! ls "$v"/*.vcd >/dev/null 2>&1 &&
    ! grep -q '"waveform"' "$v/manifest.json"; then
    ok rewrite_without_vcd_removes_waveforms
else
    bad rewrite_without_vcd_removes_waveforms "$(ls "$v" | grep vcd | head -n 3)" "$(cat "$tmp/out")"
fi
summary
