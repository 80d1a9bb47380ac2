#!/usr/bin/env bash
# End-to-end tests of the cube5 command line: exit status and the one-line message of
# every bad input, and that outputs never overwrite inputs. Usage: cli_test.sh BUILD_DIR
set -u
build=${1:-build}
cube5="$PWD/$build/cube5"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/lib.sh"

# expect NAME STATUS PATTERN -- CMD...: exit status, and PATTERN in stderr (one line).
expect() {
    local name=$1 want=$2 pat=$3
    shift 4
    local err status
    err=$("$@" 2>&1 >/dev/null)
    status=$?
    judge "$name" "$want" "$status" "$err" "$pat" && ok "$name"
}

head -c 1000 /dev/zero >"$tmp/vol_10x10x10_uint8.raw"
head -c 900 /dev/zero >"$tmp/short_10x10x10_uint8.raw"
head -c 1100 /dev/zero >"$tmp/long_10x10x10_uint8.raw"
head -c 1000 /dev/zero >"$tmp/odd_10x10x10_float32.raw"
head -c 1000 /dev/zero >"$tmp/huge_4294967296x4294967296x2_uint8.raw"
scene() { # scene FILE VOLUME_JSON_FRAGMENT
    printf '{"volumes": [%s], "transfer_function": {"opacity": [[0,0],[255,1]], "color": [[0,1,1,1]]},
      "camera": {"eye": [30,30,30], "target": [5,5,5], "width": 8, "height": 8}}' "$2" >"$1"
}
scene "$tmp/ok.json" '{"file": "vol_10x10x10_uint8.raw"}'
scene "$tmp/short.json" '{"file": "short_10x10x10_uint8.raw"}'
scene "$tmp/long.json" '{"file": "long_10x10x10_uint8.raw"}'
scene "$tmp/mismatch.json" '{"file": "vol_10x10x10_uint8.raw", "dims": [10, 10, 11], "type": "uint8"}'
scene "$tmp/type.json" '{"file": "odd_10x10x10_float32.raw"}'
scene "$tmp/overflow.json" '{"file": "huge_4294967296x4294967296x2_uint8.raw"}'
scene "$tmp/missing.json" '{"file": "nowhere_2x2x2_uint8.raw"}'

expect help 0 "" -- "$cube5" help
expect render_help 0 "" -- "$cube5" render --help
expect scenes_lists_all 0 "" -- bash -c "\"$cube5\" scenes | grep -c . | grep -qx 4"
expect unknown_command 2 "unknown command" -- "$cube5" frobnicate
expect unknown_scene 2 "neither a built-in scene" -- "$cube5" render nosuch
expect unknown_option 2 "unknown option '--bogus'" -- "$cube5" render default --bogus
expect bad_threads 2 "--threads: expected an integer" -- "$cube5" render default --threads 0
expect bad_size 2 "--size: expected N or WxH" -- "$cube5" render default --size 12y
expect bad_size_zero 2 "--size: expected an integer" -- "$cube5" render default --size 0x8
# --size N is NxN in every command; the caster's views are square
for c in "render default" "compare default" "schedule default --frames 1" "sweep default --knob et=1 --out $tmp/sz"; do
    # shellcheck disable=SC2086 # a command and its words
    if "$cube5" $c --size 12 --json 2>/dev/null | python3 -c 'import json,sys; o=json.load(sys.stdin); sys.exit(0 if o.get("size", [o.get("width"), o.get("height")]) == [12, 12] else 1)'; then
        ok "size_n_is_square_${c%% *}"
    else
        bad "size_n_is_square_${c%% *}" "--size 12 did not give 12x12"
    fi
done
# every --json object lists the files written under "outputs"
for c in "render default --size 8 -o $tmp/jo.png" "compare default --size 8 --diff $tmp/jd.png" \
    "schedule default --size 8 --frames 1" "sweep default --size 8 --knob et=1 --out $tmp/jsw" \
    "cast phantom:ml:8 --views 1 --size 8 -o $tmp/jc.png"; do
    # shellcheck disable=SC2086 # a command and its words
    got=$("$cube5" $c --json 2>/dev/null | python3 -c 'import json,sys; print(" ".join(json.load(sys.stdin)["outputs"]))' 2>&1)
    want=$(grep -o "$tmp/[a-z]*\.png\|$tmp/jsw" <<<"$c")
    [ "$want" = "$tmp/jsw" ] && want="$tmp/jsw/sweep.csv $tmp/jsw/sweep.png"
    [ "$got" = "$want" ] && ok "json_outputs_${c%% *}" || bad "json_outputs_${c%% *}" "outputs '$got', expected '$want'"
done
expect cast_error_form 2 "^cube5: error: $tmp/nosuch_8x8x8_uint8.raw: " -- "$cube5" cast "$tmp/nosuch_8x8x8_uint8.raw"
expect cast_size_not_square 2 "--size: the caster's views are square" -- "$cube5" cast phantom:ml:8 --views 1 --size 8x16
expect cast_size_nxn 0 "" -- "$cube5" cast phantom:ml:8 --views 1 --size 8x8
expect frames_without_path 2 "no camera_path" -- "$cube5" render default --frames 3
expect raw_ok 0 "" -- "$cube5" render "$tmp/ok.json"
expect raw_truncated 2 "short_10x10x10_uint8.raw: .*truncated" -- "$cube5" render "$tmp/short.json"
expect raw_oversized 2 "long_10x10x10_uint8.raw: .*extra bytes" -- "$cube5" render "$tmp/long.json"
expect raw_dims_mismatch 2 "vol_10x10x10_uint8.raw: .*expected 1100" -- "$cube5" render "$tmp/mismatch.json"
expect raw_unsupported_type 2 "odd_10x10x10_float32.raw: unsupported voxel type" -- "$cube5" render "$tmp/type.json"
expect raw_dims_overflow 2 "huge_4294967296x4294967296x2_uint8.raw: dims .*overflow" -- "$cube5" render "$tmp/overflow.json"
# The memory budget (docs/out-of-core.md): a bad value is refused; a grid above it renders
# out of core with the same image, and the caster, which needs it whole, refuses it.
# a render that went out of core says so, in its summary and its JSON
if env C5_MEM_BUDGET=256K "$cube5" render default --size 8x8 | grep -q "^  memory   out of core: .*C5_MEM_BUDGET, 0.2 MiB" &&
    env C5_MEM_BUDGET=256K "$cube5" render default --size 8x8 --json |
    python3 -c 'import json,sys; g=json.load(sys.stdin)["grid"]; sys.exit(0 if g["out_of_core"] and g["mem_budget"] == 262144 else 1)' &&
    "$cube5" render default --size 8x8 --json | python3 -c 'import json,sys; sys.exit(json.load(sys.stdin)["grid"]["out_of_core"])'; then
    ok out_of_core_said
else
    bad out_of_core_said
fi
expect mem_budget_bad 2 "C5_MEM_BUDGET: expected a byte count" -- env C5_MEM_BUDGET=lots "$cube5" render "$tmp/ok.json"
expect mem_budget_zero 2 "C5_MEM_BUDGET: '0' is zero" -- env C5_MEM_BUDGET=0 "$cube5" render "$tmp/ok.json"
# cube5's cache folder (docs/out-of-core.md, "Block ranges"): bad settings refused; a volume
# file's block ranges kept where C5_CACHE_DIR, else XDG_CACHE_HOME, says, nowhere with off,
# and not for a file written just now (it could be rewritten unseen within one clock tick).
expect cache_max_bad 2 "C5_CACHE_MAX: expected a byte count" -- env C5_CACHE_MAX=lots "$cube5" render "$tmp/ok.json"
expect threads_env_bad 2 "C5_THREADS: expected a thread count 1..256, got '0'" -- env C5_THREADS=0 "$cube5" render "$tmp/ok.json"
mkdir -p "$tmp/cachehome"
cp "$tmp/ok.json" "$tmp/aged.json"
touch -d '1 hour ago' "$tmp"/vol_10x10x10_uint8.raw
rtl=(--model rtl --cells 2 --size 8x8 -o "$tmp/cached.png")
if env -u XDG_CACHE_HOME C5_CACHE_DIR="$tmp/c1" "$cube5" render "$tmp/aged.json" "${rtl[@]}" >/dev/null &&
    ls "$tmp"/c1/ranges-*.bin >/dev/null 2>&1 &&
    env -u C5_CACHE_DIR XDG_CACHE_HOME="$tmp/xdg" "$cube5" render "$tmp/aged.json" "${rtl[@]}" >/dev/null &&
    ls "$tmp"/xdg/cube5/ranges-*.bin >/dev/null 2>&1 &&
    env -u XDG_CACHE_HOME HOME="$tmp/cachehome" C5_CACHE_DIR=off "$cube5" render "$tmp/aged.json" "${rtl[@]}" >/dev/null &&
    [ ! -e "$tmp/cachehome/.cache" ]; then
    ok cache_folder_where_said
else
    bad cache_folder_where_said "expected ranges in \$C5_CACHE_DIR, then \$XDG_CACHE_HOME/cube5, none with off"
fi
touch "$tmp"/vol_10x10x10_uint8.raw
if env C5_CACHE_DIR="$tmp/c2" "$cube5" render "$tmp/aged.json" "${rtl[@]}" >/dev/null && ! ls "$tmp"/c2/*.bin >/dev/null 2>&1; then
    ok cache_not_for_a_fresh_file
else
    bad cache_not_for_a_fresh_file "a file written just now got a cache entry"
fi
expect mem_budget_cast_refused 2 "default: the grid of 96x96x96 voxels is above the memory budget .C5_MEM_BUDGET, here 262144 bytes." \
    -- env C5_MEM_BUDGET=256K "$cube5" cast default --views 1
expect mem_budget_cast_phantom_refused 2 "phantom:shell:100: 100x100x100 voxels are above the memory budget" \
    -- env C5_MEM_BUDGET=256K "$cube5" cast phantom:shell:100 --views 1
expect mem_budget_floor 2 "C5_MEM_BUDGET: '999' is below the least a grid is held in, 262144 bytes" \
    -- env C5_MEM_BUDGET=999 "$cube5" cast "$tmp/vol_10x10x10_uint8.raw" --views 1
expect mem_budget_floor_render 2 "C5_MEM_BUDGET: '1K' is below the least a grid is held in, 262144 bytes" \
    -- env C5_MEM_BUDGET=1K "$cube5" render default --size 8x8
crc() { "$@" --json | python3 -c 'import json, sys; print([f["crc32"] for f in json.load(sys.stdin)["frames"]])'; }
a=$(crc "$cube5" render default --size 24x24 --threads 2) && b=$(crc env C5_MEM_BUDGET=256K "$cube5" render default --size 24x24 --threads 2)
if [ -n "$a" ] && [ "$a" = "$b" ]; then ok "mem_budget_out_of_core_same_image"; else bad "mem_budget_out_of_core_same_image" "resident $a, out of core $b"; fi
expect raw_missing 2 "nowhere_2x2x2_uint8.raw: cannot open" -- "$cube5" render "$tmp/missing.json"
expect volume_option_bad 2 "short_10x10x10_uint8.raw: .*truncated" -- \
    "$cube5" render default --volume "$tmp/short_10x10x10_uint8.raw"
echo '{"camera": {"eye": [1,2,3], "target": [0,0,0]}, "camera": {}}' >"$tmp/dup.json"
expect scene_duplicate_key 2 "dup.json: .*duplicate" -- "$cube5" render "$tmp/dup.json"
echo '{"camera": {"eye": [1,2,NaN], "target": [0,0,0]}}' >"$tmp/nan.json"
expect scene_nan 2 "nan.json: line 1" -- "$cube5" render "$tmp/nan.json"
echo '{"camera": {"eye": [1,2,3], "target": [0,0,0], "zoom": 2}}' >"$tmp/unknown.json"
expect scene_unknown_key 2 "unknown.json: camera.zoom: unknown key" -- "$cube5" render "$tmp/unknown.json"
expect scene_missing_file 2 "absent.json: cannot" -- "$cube5" render "$tmp/absent.json"

# NRRD volumes end to end: attached gzip, detached raw, and a truncated detached file.
head -c 64 /dev/urandom >"$tmp/data.raw"
printf 'NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 4\nencoding: gzip\n\n' >"$tmp/g.nrrd"
gzip -c "$tmp/data.raw" >>"$tmp/g.nrrd"
printf 'NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 4\nencoding: raw\ndata file: data.raw\n' >"$tmp/d.nhdr"
printf 'NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 8\nencoding: raw\ndata file: data.raw\n' >"$tmp/t.nhdr"
scene "$tmp/g.json" '{"file": "g.nrrd"}'
scene "$tmp/d.json" '{"file": "d.nhdr"}'
scene "$tmp/t.json" '{"file": "t.nhdr"}'
crc() { "$cube5" render "$1" --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["frames"][0]["crc32"])'; }
expect nrrd_attached_gzip 0 "" -- "$cube5" render "$tmp/g.json"
expect nrrd_detached_raw 0 "" -- "$cube5" render "$tmp/d.json"
if [ "$(crc "$tmp/g.json")" = "$(crc "$tmp/d.json")" ] && [ "$(crc "$tmp/g.json")" != "$(crc "$tmp/ok.json")" ]; then
    ok nrrd_same_image_both_encodings
else
    bad nrrd_same_image_both_encodings "frame CRCs differ (or match an all-zero volume)"
fi
expect nrrd_truncated 2 "t.nhdr: " -- "$cube5" render "$tmp/t.json"

# Outputs: PNG and EXR by extension, nothing else; never over an input.
expect write_png 0 "" -- "$cube5" render "$tmp/ok.json" -o "$tmp/a.png"
expect write_exr 0 "" -- "$cube5" render "$tmp/ok.json" -o "$tmp/a.exr"
expect write_bad_ext 2 "unsupported image extension" -- "$cube5" render "$tmp/ok.json" -o "$tmp/a.bmpx"
cp "$tmp/ok.json" "$tmp/keep.json"
expect refuse_over_scene 2 "refusing to overwrite an input" -- "$cube5" render "$tmp/ok.json" -o "$tmp/ok.json"
if cmp -s "$tmp/ok.json" "$tmp/keep.json"; then ok scene_file_intact; else bad scene_file_intact "scene changed"; fi
cp "$tmp/vol_10x10x10_uint8.raw" "$tmp/keep.raw"
expect refuse_over_volume 2 "refusing to overwrite an input" -- \
    "$cube5" render "$tmp/ok.json" -o "$tmp/vol_10x10x10_uint8.raw"
if cmp -s "$tmp/vol_10x10x10_uint8.raw" "$tmp/keep.raw"; then ok volume_file_intact; else bad volume_file_intact "volume changed"; fi

# --json carries the documented keys; frames of a camera path get numbered files.
json=$("$cube5" render default --size 16x16 --json)
if python3 -c 'import json,sys; o=json.loads(sys.argv[1]); assert o["renderer"]=="cref"; r=o["rays"]; [r[k] for k in ("eye","shadow","reflect","refract")]; assert o["samples"]>0 and o["wall_s"]>=0' "$json"; then
    ok render_json_keys
else
    bad render_json_keys "$json"
fi
expect frames_numbered 0 "" -- "$cube5" render brain_mirrors --size 8x8 --frames 3 -o "$tmp/f.png"
if [ -f "$tmp/f_0000.png" ] && [ -f "$tmp/f_0002.png" ] && [ ! -f "$tmp/f_0003.png" ]; then ok frame_files; else bad frame_files "$(ls "$tmp")"; fi

# The board model (render --model rtl) and compare. Nothing here depends on the model's exact
# image or costs: only on the keys, their types and what any split must satisfy.
expect compare_help 0 "" -- "$cube5" compare --help
expect render_rtl 0 "" -- "$cube5" render default --size 16x16 --model rtl --cells 2 -o "$tmp/rtl.png"
json=$("$cube5" render default --size 16x16 --model rtl --cells 2x1x2 --queue-key fifo --json)
if python3 -c '
import json,sys
o=json.loads(sys.argv[1]); assert o["model"]=="rtl"; assert o["samples"]>=0
[o["rays"][k] for k in ("eye","shadow","reflect","refract")]
for f in o["frames"]:
    b=f["board"]
    for k in ("cycles","cycles_process","cycles_fetch","fetches","fetch_bytes","bus_packets","spills",
              "queue_pops","queue_max","cache_hits","cache_misses","saturations","cells"):
        assert isinstance(b[k], int) and b[k]>=0, k
    assert isinstance(b["board_s"], (int, float)) and b["fetches"]>=1
    assert set(b["stages"])=={"gradients","shadow","reflect","refract","scheduling"}
    assert all(v in (0,1) for v in b["stages"].values())
' "$json"; then
    ok render_rtl_json_keys
else
    bad render_rtl_json_keys "$json"
fi
if "$cube5" render default --size 8x8 --model rtl | grep -qE '^  stages   (eye rays only|[a-z ]+)$'; then
    ok render_rtl_stages_line
else
    bad render_rtl_stages_line "$("$cube5" render default --size 8x8 --model rtl 2>&1)"
fi
expect render_bad_model 2 "--model: expected cref or rtl" -- "$cube5" render default --model fpga
expect render_cells_needs_rtl 2 "--cells: only with --model rtl" -- "$cube5" render default --cells 2
expect render_rtl_threads_not_with_boards 2 "--threads: not with --boards" -- \
    "$cube5" render default --model rtl --boards 2 --loopback --threads 2
# The board model on 1 and 3 host threads: the same image and the same board figures (all but
# the host's: its time, the runs its helpers made and the times they were woken).
board_figures() {
    "$cube5" render brain_mirrors --model rtl --size 48x48 --cells 2 --frames 1 --threads "$1" --json |
        python3 -c 'import json, sys; o = json.load(sys.stdin); b = o["board"]; h = b.pop("host_helper_runs"); b.pop("host_helper_wakes")
print(json.dumps([o["frames"][0]["crc32"], o["samples"], o["rays"], b], sort_keys=True), h > 0)'
}
one=$(board_figures 1) three=$(board_figures 3)
if [ -n "$one" ] && [ "${one% *}" = "${three% *}" ] && [ "${one##* }" = False ] && [ "${three##* }" = True ]; then
    ok render_rtl_threads_same_frame
else
    bad render_rtl_threads_same_frame "1 thread: $one" "3 threads: $three"
fi
# The default thread count is the CPUs the process may run on: one under a one-CPU mask.
if command -v taskset >/dev/null; then
    first=$(python3 -c 'import os; print(min(os.sched_getaffinity(0)))')
    n1=$(taskset -c "$first" "$cube5" render default --size 32x32 --frames 1 --json |
        python3 -c 'import json, sys; print(json.load(sys.stdin)["threads"])')
    n1rtl=$(taskset -c "$first" "$cube5" render default --model rtl --size 32x32 --frames 1 --json |
        python3 -c 'import json, sys; print(json.load(sys.stdin)["threads"])')
    if [ "$n1" = 1 ] && [ "$n1rtl" = 1 ]; then
        ok render_default_threads_follow_affinity
    else
        bad render_default_threads_follow_affinity "cref $n1, rtl $n1rtl threads under taskset -c $first"
    fi
fi
expect render_bad_queue_key 2 "--queue-key: expected morton or fifo" -- \
    "$cube5" render default --model rtl --queue-key lifo
expect render_host_bw_needs_rtl 2 "--host-bw/--host-latency: only with --model rtl" -- \
    "$cube5" render default --host-bw 10
expect render_bad_host_bw 2 "--host-bw" -- "$cube5" render default --model rtl --host-bw 0
# The fetch stall follows the host link: no latency and a faster link stall less.
stall() { "$cube5" render brain_mirrors --size 16x16 --frames 1 --model rtl --cells 2 "$@" --json |
    python3 -c 'import json,sys; print(json.load(sys.stdin)["board"]["cycles_fetch"])'; }
s_def=$(stall); s_fast=$(stall --host-latency 0 --host-bw 800)
if [ -n "$s_def" ] && [ -n "$s_fast" ] && [ "$s_fast" -lt "$s_def" ]; then
    ok render_host_link_sets_fetch_stall
else
    bad render_host_link_sets_fetch_stall "default $s_def, fast $s_fast"
fi

json=$("$cube5" compare default --size 32x32 --cells 2 --json)
if python3 -c '
import json,sys,math
o=json.loads(sys.argv[1])
for k in ("psnr_db","rmse","max_abs_err","cref_wall_s","model_wall_s","board_s"):
    assert isinstance(o[k], (int, float)) and not isinstance(o[k], bool) and math.isfinite(o[k]), k
for k in ("board_cycles","fetches","cells"):
    assert isinstance(o[k], int), k
for k in ("psnr_ch","rmse_ch","max_abs_ch"):
    assert len(o[k])==3 and all(isinstance(v, (int, float)) for v in o[k]), k
assert 0<=o["rmse"]<=o["max_abs_err"]*(1+1e-6) and o["fetches"]>=1
assert o["cells"]==8 and o["size"]==[32,32] and o["scene"]=="default"
h=o["histogram"]; assert len(h)>=2 and all(isinstance(b["label"], str) and b["count"]>=0 for b in h)
assert sum(b["count"] for b in h)==32*32*3
' "$json"; then
    ok compare_json_keys
else
    bad compare_json_keys "$json"
fi
if "$cube5" compare default --size 16x16 --json | python3 -c 'import json,sys; json.load(sys.stdin)'; then
    ok compare_json_valid
else
    bad compare_json_valid "not valid JSON"
fi
expect compare_text 0 "" -- bash -c "\"$cube5\" compare default --size 8x8 | grep -q '^  PSNR dB'"
expect compare_diff_png 0 "" -- "$cube5" compare default --size 16x16 --cells 2 --diff "$tmp/diff.png"
if python3 -c 'import sys; d=open(sys.argv[1],"rb").read(8); sys.exit(d!=b"\x89PNG\r\n\x1a\n")' "$tmp/diff.png"; then
    ok compare_diff_is_png
else
    bad compare_diff_is_png "$(ls -l "$tmp/diff.png" 2>&1)"
fi
for v in 0 -1 2x2 999 x 2x2x2x2 ""; do
    expect "compare_bad_cells_'$v'" 2 "--cells: expected N or NxMxK" -- "$cube5" compare default --size 8x8 --cells "$v"
done
expect compare_cells_beyond_grid 2 "--cells: .*grid has only 10 voxels" -- "$cube5" compare "$tmp/ok.json" --cells 11x1x1
expect compare_cells_missing 2 "--cells: missing value" -- "$cube5" compare default --cells
expect compare_bad_frame 2 "--frame: the scene has 1 frame" -- "$cube5" compare default --frame 1
expect compare_bad_gain 2 "--gain: expected a number" -- "$cube5" compare default --gain 0
# cref in long double as the reference: the same scene, the same PSNR to 9 digits (cref's
# own rounding is ~1e-12, docs/stability.md); a bad precision is refused.
psnr_of() { python3 -c 'import json,sys; d=json.load(sys.stdin); print(d["ref_precision"], "%.9g" % d["psnr_db"])'; }
pd=$("$cube5" compare default --size 24x24 --json | psnr_of)
pl=$("$cube5" compare default --size 24x24 --ref-precision long --json | psnr_of)
if [ "${pd#double }" = "${pl#long }" ] && [ "${pd%% *}" = double ] && [ "${pl%% *}" = long ]; then
    ok compare_ref_precision_long
else
    bad compare_ref_precision_long "double: $pd, long: $pl"
fi
expect compare_bad_ref_precision 2 "--ref-precision: expected double or long, got 'quad'" -- \
    "$cube5" compare default --size 8x8 --ref-precision quad
expect compare_unknown_option 2 "unknown option '--model'" -- "$cube5" compare default --model rtl
cp "$tmp/ok.json" "$tmp/keep.json"
expect compare_refuse_diff_over_scene 2 "refusing to overwrite an input" -- \
    "$cube5" compare "$tmp/ok.json" --diff "$tmp/ok.json"
if cmp -s "$tmp/ok.json" "$tmp/keep.json"; then ok compare_scene_intact; else bad compare_scene_intact "scene changed"; fi
expect compare_diff_bad_ext 2 "unsupported image extension" -- "$cube5" compare default --diff "$tmp/d.txt"

# cube5 schedule: the JSON the issue names, the Cell Tree followed from frame 1, the
# overflow path, and refusals.
json=$("$cube5" schedule brain_mirrors --size 24x24 --cells 2 --still --frames 2 --json)
if python3 - "$json" <<'PY'
import json, sys
d = json.loads(sys.argv[1])
f0, f1 = d["frames"]
for k in ("rays", "nodes", "tree_bytes", "fetches_maxwork", "fetches_celltree", "lower_bound", "optimum"):
    assert k in f1, k
assert f1["tree_bytes"] >= 12 * f1["nodes"] > 0
assert f0["followed"] == "maxwork (first frame)" and f0["fetches_celltree"] == f0["fetches_maxwork"]
assert f1["followed"] == "celltree" and f1["sched_fallback"] == 0
assert f1["lower_bound"] <= min(f1["fetches_celltree"], f1["fetches_maxwork"])
assert f1["optimum"] is None or f1["lower_bound"] <= f1["optimum"] <= f1["fetches_celltree"]
assert f0["nodes"] == f1["nodes"]  # the same view builds the same tree
for f in (f0, f1):  # the instrument tree gives the fitting tree's sum of maxGen
    assert f["lower_bound_demand"] == f["sum_maxgen"] <= f["fetches_celltree"]
PY
then ok schedule_json; else bad schedule_json "$json"; fi
json=$("$cube5" schedule brain_mirrors --size 16x16 --cells 2 --still --tree-nodes 5 --json)
if python3 -c '
import json, sys
d = json.loads(sys.argv[1])
f0, f1 = d["frames"]
assert f0["tree_overflow"] and f0["lower_bound"] is None and f0["optimum"] is None
assert f1["followed"] == "maxwork (previous tree overflowed)"
assert f1["fetches_celltree"] == f1["fetches_maxwork"]' "$json"; then ok schedule_overflow_falls_back; else bad schedule_overflow_falls_back "$json"; fi
expect schedule_overflow_text 0 "" -- bash -c "\"$cube5\" schedule default --size 8x8 --tree-nodes 3 | grep -q 'OVERFLOWED the DSP RAM'"
json=$("$cube5" schedule brain_mirrors --size 16x16 --cells 2 --still --frames 2 --split bounded --exact-states 0 --json)
if python3 -c '
import json, sys
d = json.loads(sys.argv[1])
assert d["split_rule"] == "bounded"
f0, f1 = d["frames"]
assert f1["followed"] == "celltree" and f1["schedule_len"]["bounded"] <= f1["schedule_len"]["paper"]
p = f0["dsp_ops_schedule_parts"]
assert f0["dsp_ops_schedule"] == p["export"] + p["rule"] + p["writeback"] > 0 and f0["dsp_ops_tree"] > 0
assert f0["dsp_ops_schedule"] <= f0["dsp_budget_ops"] and f0["dsp_within_budget"]
assert abs(f0["dsp_us_at_255mips"]["schedule"] - f0["dsp_ops_schedule"] / 255.0) < 1e-3' "$json"
then ok schedule_bounded_dsp_ops; else bad schedule_bounded_dsp_ops "$json"; fi
json=$("$cube5" schedule brain_mirrors --size 16x16 --cells 3 --still --frames 2 --split window --exact-states 0 --json)
if python3 -c '
import json, sys
d = json.loads(sys.argv[1])
assert d["split_rule"] == "window"
f0, f1 = d["frames"]
assert f1["followed"] == "celltree" and 0 < f1["schedule_len"]["window"] <= f1["schedule_len"]["paper"]
for f in (f0, f1):  # the start: the shortest of the paper'"'"'s, the subtree rule'"'"'s and the
    L = f["schedule_len"]  # frame'"'"'s fetches (a schedule of its own tree)
    assert f["window_subtree"] == (L["subtree"] < L["paper"])
    assert f["window_warm"] == (f["fetches_celltree"] < min(L["paper"], L["subtree"]))
assert f0["dsp_ops_schedule"] <= f0["dsp_budget_ops"] and f0["dsp_within_budget"]' "$json"
then ok schedule_window; else bad schedule_window "$json"; fi
# The tree in the DSP's SDRAM: where it lives, its bytes, the DSP's refinement during the frame
# (the next schedule starts from it on a still camera), Max Work never beaten on a still.
json=$("$cube5" schedule brain_mirrors --size 24x24 --cells 3 --still --frames 3 --exact-states 0 --local-window 0 --tree-ram sdram --json)
if python3 -c '
import json, sys
d = json.loads(sys.argv[1])
f0, f1, f2 = d["frames"]
for f in d["frames"]:
    assert f["tree_ram"] == "sdram" and not f["tree_overflow"]
    assert f["tree_bytes"] == 16 * f["tree_slots"] + 8 * f["nodes"]
    assert 0 < f["tree_cell_nodes_max"] <= f["nodes"]
    assert f["dsp_ops_schedule"] <= f["dsp_budget_ops"]
assert f0["refined"] is None
for p, f in ((f0, f1), (f1, f2)):
    r = f["refined"]
    assert f["followed"].startswith("celltree") and f["fetches_celltree"] <= f["fetches_maxwork"]
    assert r["dsp_ops"] <= r["budget_ops"] and r["len"] <= p["schedule_len"]["window"]
    assert f["schedule_len"]["window"] <= r["len"]' "$json"
then ok schedule_tree_in_sdram; else bad schedule_tree_in_sdram "$json"; fi
if python3 -c '
import json, subprocess, sys
def ram(cells):
    out = subprocess.run([sys.argv[1], "schedule", "default", "--size", "8x8", "--cells", cells, "--frames", "1",
                          "--exact-states", "0", "--json"], capture_output=True, text=True, check=True).stdout
    return json.loads(out)["frames"][0]["tree_ram"]
assert ram("4") == "onchip" and ram("5") == "sdram"' "$cube5"
then ok schedule_tree_ram_auto; else bad schedule_tree_ram_auto "auto: on chip up to 64 cells, SDRAM beyond"; fi
expect schedule_bad_tree_ram 2 "--tree-ram: expected auto, onchip or sdram, got 'dram'" -- "$cube5" schedule default --tree-ram dram
expect schedule_bad_split 2 "--split: expected paper, lookahead, rollout, bounded, window or subtree, got 'best'" -- "$cube5" schedule default --split best
expect schedule_bad_frames 2 "--frames: expected an integer" -- "$cube5" schedule default --frames 0
expect schedule_bad_local_window 2 "--local-window: 2 is too small for a window" -- "$cube5" schedule default --local-window 2
expect schedule_local_window_range 2 "--local-window: expected an integer" -- "$cube5" schedule default --local-window 1001
expect schedule_bad_tree_nodes 2 "--tree-nodes: expected an integer" -- "$cube5" schedule default --tree-nodes 8192
expect schedule_bad_cells 2 "--cells: expected N or NxMxK" -- "$cube5" schedule default --cells 0
expect schedule_orbit_nan 2 "--orbit: expected a finite number, got 'nan'" -- "$cube5" schedule default --orbit nan
expect schedule_orbit_range 2 "--orbit: 4000 degrees a frame is outside" -- "$cube5" schedule default --orbit 4000
expect schedule_jumps_bad 2 "--jumps: expected SEED" -- "$cube5" schedule default --jumps -3
expect schedule_jumps_every 2 "--jumps: EVERY must be an integer" -- "$cube5" schedule default --jumps 1:0
expect schedule_jumps_prob 2 "--jumps: probability 2 is outside" -- "$cube5" schedule default --jumps 1:p2
expect schedule_dolly_bad 2 "--dolly: factor 0 a frame is outside" -- "$cube5" schedule default --dolly 0
expect schedule_still_and_orbit 2 "--still: a still camera cannot also move" -- "$cube5" schedule default --still --orbit 2
expect schedule_frames_negative 2 "--frames: expected an integer" -- "$cube5" schedule default --orbit 2 --frames -1
json=$("$cube5" schedule default --size 12x12 --cells 2 --orbit 30 --jumps 5:3 --exact-states 0 --json)
if python3 -c '
import json, sys
d = json.loads(sys.argv[1])
fr = d["frames"]
assert len(fr) == 8, len(fr)
assert d["motion"]["orbit_deg"] == 30 and d["motion"]["jumps_seed"] == 5 and d["motion"]["jumps_every"] == 3
assert [f["jump"] for f in fr] == [i > 0 and i % 3 == 0 for i in range(8)]' "$json"; then ok schedule_motion_json; else bad schedule_motion_json "$json"; fi
# The ledger (docs/cell-tree.md): the DSP's bank is the exact balance of the path so far,
# frame by frame, on a path that saves.
json=$("$cube5" schedule default --size 24x24 --cells 3 --orbit 2 --frames 5 --exact-states 0 --json)
if python3 -c '
import json, sys
fr = json.loads(sys.argv[1])["frames"]
for i, f in enumerate(fr):
    assert f["replay"]["bank"] == sum(g["fetches_maxwork"] - g["fetches_celltree"] for g in fr[:i + 1]), i
assert fr[-1]["replay"]["bank"] > 0' "$json"; then ok schedule_ledger_bank; else bad schedule_ledger_bank "$json"; fi
expect schedule_stale_check_bad 2 "--stale-check: expected on or off, got 'maybe'" -- "$cube5" schedule default --stale-check maybe
for chk in on off; do
    json=$("$cube5" schedule default --size 12x12 --cells 2 --orbit 30 --frames 2 --exact-states 0 --stale-check $chk --json)
    if python3 -c '
import json, sys
f = json.loads(sys.argv[1])["frames"][1]
on = sys.argv[2] == "on"
c = f["certificate"]
assert f["start_overlap"] is not None and f["start_overlap"] < 0.8
if on:  # followed under the certificate: within Max Work plus the bank and one allowance
    # the first followed frame of the path, its start queues far from those of the frame
    # before (a fast orbit): no allowance risked, no bank, so no load past the shadow
    assert c is not None and not c["identical"] and c["budget"] == 0 and c["lead_max"] <= 0
    assert c["maxwork_fetches"] == f["fetches_maxwork"]
    assert f["fetches_celltree"] <= f["fetches_maxwork"]
    assert (f["switch_reason"] is None) == (f["sched_switches"] == 0)
    assert f["switch_reason"] is None or "budget is %d" % c["budget"] in f["switch_reason"]
else:
    assert c is None and f["switched_at_load"] is None and f["switch_reason"] is None and f["sched_switches"] == 0' "$json" $chk; then ok schedule_stale_$chk; else bad schedule_stale_$chk "$json"; fi
done
expect schedule_local_walk_bad 2 "--local-walk: expected an integer in \[0, 100000\]" -- "$cube5" schedule default --local-walk -1
expect schedule_unknown_option 2 "unknown option '--model'" -- "$cube5" schedule default --model rtl

# cube5 cast (docs/caster.md): every mode and worker count writes the same bits; the JSON has
# the figures the bench reads; bad input is refused with one line.
head -c 16 /dev/zero >"$tmp/tiny_2x2x2_uint16.raw"
for m in plain ess approx approx+refine; do
    for t in 1 3; do
        "$cube5" cast phantom:shell:40 --size 48 --views 2 --mode "$m" --threads "$t" --shading on \
            -o "$tmp/cast_${m}_$t.exr" >/dev/null || bad "cast_$m_$t" "exit $?"
    done
done
for p in on off; do
    "$cube5" cast phantom:shell:40 --size 48 --views 2 --mode approx --threads 2 --shading on --producer "$p" \
        -o "$tmp/cast_producer_$p.exr" >/dev/null || bad "cast_producer_$p" "exit $?"
done
same=1
for f in "$tmp"/cast_*.exr; do cmp -s "$f" "$tmp/cast_plain_1.exr" || { same=0; echo "    differs: $f"; }; done
if [ "$same" = 1 ] && [ "$(ls "$tmp"/cast_*.exr | wc -l)" = 10 ]; then ok cast_modes_same_bits; else bad cast_modes_same_bits; fi
# --producer: on, the calling thread produces some tiles; off, the workers produce all 9 (48^2)
if python3 -c '
import json, subprocess, sys
run = lambda p: json.loads(subprocess.run([sys.argv[1], "cast", "phantom:shell:40", "--size", "48", "--views", "2",
    "--producer", p, "--queue-depth", "16", "--json"], capture_output=True, check=True).stdout)
on, off = run("on"), run("off")
assert on["producer_thread"] is True and off["producer_thread"] is False
assert all(v["tiles_self_produced"] == 9 and not v["producer_thread"] for v in off["per_view"])
assert all(v["producer_thread"] for v in on["per_view"])' "$cube5"; then ok cast_producer_flag; else bad cast_producer_flag; fi
json=$("$cube5" cast phantom:ml:32 --size 32 --views 3 --k 4 --json)
if python3 -c '
import json, sys
d = json.loads(sys.argv[1])
assert d["fps_median"] > 0 and d["ms_median"] > 0 and len(d["per_view"]) == 3
assert d["k_min"] == d["k_max"] == 4 and d["dataset"]["dims"] == [32, 32, 32]
assert all(v["samples"] > 0 for v in d["per_view"])' "$json"; then ok cast_json; else bad cast_json "$json"; fi
"$cube5" cast phantom:shell:24 --size 16 --views 1 --save-raw "$tmp/shell_24x24x24_uint8.raw" >/dev/null
a=$("$cube5" cast phantom:shell:24 --size 16 --views 2 --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["per_view"][1]["samples"])')
b=$("$cube5" cast "$tmp/shell_24x24x24_uint8.raw" --size 16 --views 2 --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["per_view"][1]["samples"])')
if [ -n "$a" ] && [ "$a" = "$b" ]; then ok cast_save_raw_round_trip; else bad cast_save_raw_round_trip "$a vs $b"; fi
expect cast_scene 0 "" -- "$cube5" cast default --size 16 --views 1
expect cast_no_input 2 "cast needs a VOLUME or SCENE" -- "$cube5" cast
expect cast_bad_mode 2 "--mode: expected plain, ess" -- "$cube5" cast phantom:ml:8 --mode fast
expect cast_bad_k 2 "--k: expected 1, 2, 4, 8 or 16" -- "$cube5" cast phantom:ml:8 --k 3
expect cast_bad_shading 2 "--shading: expected on or off" -- "$cube5" cast phantom:ml:8 --shading yes
expect cast_bad_prefetch 2 "--prefetch: expected cells, bricks, off or on" -- "$cube5" cast phantom:ml:8 --prefetch all
expect cast_bad_producer 2 "--producer: expected on, off or auto" -- "$cube5" cast phantom:ml:8 --producer 2
expect cast_nobody_produces 2 "--producer off needs --self-produce on" -- "$cube5" cast phantom:ml:8 --producer off \
    --self-produce off
expect cast_bad_phantom 2 "unknown phantom 'foot'" -- "$cube5" cast phantom:foot:8
expect cast_missing_file 2 "nothere_4x4x4_uint8.raw" -- "$cube5" cast "$tmp/nothere_4x4x4_uint8.raw"
expect cast_uint16 2 "cast takes uint8 volumes" -- "$cube5" cast "$tmp/tiny_2x2x2_uint16.raw"
expect cast_bad_tf 2 "nothere.json" -- "$cube5" cast phantom:ml:8 --tf "$tmp/nothere.json"
expect cast_bad_ext 2 "unsupported image extension" -- "$cube5" cast phantom:ml:8 -o "$tmp/x.bmp"
cp "$tmp/vol_10x10x10_uint8.raw" "$tmp/keep_10x10x10_uint8.raw"
expect cast_no_overwrite 2 "refusing to overwrite" -- "$cube5" cast "$tmp/keep_10x10x10_uint8.raw" --save-raw "$tmp/keep_10x10x10_uint8.raw"
if cmp -s "$tmp/vol_10x10x10_uint8.raw" "$tmp/keep_10x10x10_uint8.raw"; then ok cast_input_kept; else bad cast_input_kept; fi
scene "$tmp/novol.json" ''
expect cast_no_volume_scene 2 "has no volume to cast" -- "$cube5" cast "$tmp/novol.json"

# cube5 sweep (docs/sweep.md): the CSV, the PNG, the JSON, progress on stderr only, the
# refusal to overwrite, the analytic reference of a Marschner-Lobb scene, and bad input.
expect sweep_help 0 "" -- "$cube5" sweep --help
if "$cube5" sweep default --size 16 --knob step=1,2 --knob k=1,4 --out "$tmp/sw" --json --progress \
    >"$tmp/sw.json" 2>"$tmp/sw.err"; then ok sweep_runs; else bad sweep_runs "exit $?" "$(cat "$tmp/sw.err")"; fi
# header + step x {cref, model} x 2 values + k x {cast} x 2 values
if [ "$(wc -l <"$tmp/sw/sweep.csv")" = 7 ] && head -n 1 "$tmp/sw/sweep.csv" | grep -q \
    '^knob,value,default,renderer,status,psnr_db,rmse,max_abs_err,host_s,board_s,samples,'; then
    ok sweep_csv_rows
else bad sweep_csv_rows "$(cat "$tmp/sw/sweep.csv" 2>&1)"; fi
if [ "$(head -c 8 "$tmp/sw/sweep.png" 2>/dev/null | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ]; then
    ok sweep_png_is_png
else bad sweep_png_is_png "$(ls -l "$tmp/sw" 2>&1)"; fi
if python3 - "$tmp/sw.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
rows = d["rows"]
assert len(rows) == 6, len(rows)
assert [(r["knob"], r["value"], r["renderer"]) for r in rows] == [
    ("step", 1, "cref"), ("step", 1, "model"), ("step", 2, "cref"), ("step", 2, "model"),
    ("k", 1, "cast"), ("k", 4, "cast")]
assert all(r["status"] == "ok" and r["rmse"] > 0 and r["host_s"] >= 0 and r["samples"] > 0 for r in rows)
assert rows[0]["default"] and rows[1]["default"] and not rows[2]["default"]
assert all((r["board_s"] is not None) == (r["renderer"] == "model") for r in rows)
ref = d["reference"]
assert ref["field"] == "voxels" and ref["step"] == 1 / 8 and ref["et"] == 1 and ref["bounces"] == 15
assert ref["convergence"]["coarse_step"] == 1 / 4 and ref["convergence"]["diff"]["rmse"] >= 0
assert ref["cast"]["mode"] == "plain" and ref["cast"]["rows_identical_to_plain"] is True
assert d["pareto_host"] and d["pareto_board"]
assert all(rows[i]["pareto_host"] for i in d["pareto_host"])
assert all(rows[i]["renderer"] == "model" for i in d["pareto_board"])
PY
then ok sweep_json; else bad sweep_json "$(head -c 600 "$tmp/sw.json")"; fi
# 5 reference renders (cref's two, the caster's three), then the 6 rows
if grep -q '^cube5 sweep: \[1/11\] reference: cref ' "$tmp/sw.err" && grep -q '^cube5 sweep: \[6/11\] step=1 cref: ' "$tmp/sw.err" &&
    grep -q '^cube5 sweep: \[11/11\] k=4 cast' "$tmp/sw.err" && ! grep -q 'cube5 sweep: \[' "$tmp/sw.json"; then
    ok sweep_progress_on_stderr
else bad sweep_progress_on_stderr "$(cat "$tmp/sw.err")"; fi
# One rule for existing outputs (README, "Conventions"): replaced, whole, as Unix tools do.
expect sweep_replaces 0 "" -- "$cube5" sweep default --size 16 --knob et=0.9,1 --out "$tmp/sw"
if [ "$(wc -l <"$tmp/sw/sweep.csv")" = 5 ]; then ok sweep_replaced_csv; else bad sweep_replaced_csv; fi
expect sweep_force_gone 2 "--force" -- "$cube5" sweep default --size 16 --knob et=1 --out "$tmp/sw" --force
# A generated grid over the voxel limit: the scene file, the generator and the limit named.
printf '{"volumes": [{"generator": "cloud", "dims": [30000, 30000, 30000]}], "transfer_function": {"opacity": [[0,0],[255,1]], "color": [[0,1,1,1]]},
  "camera": {"eye": [1,1,1], "target": [0,0,0], "width": 8, "height": 8}}' >"$tmp/huge.json"
expect generator_over_limit 2 "huge.json: generator cloud: dims 30000x30000x30000: 27000000000000 voxels exceed the limit of [0-9]+" -- \
    "$cube5" render "$tmp/huge.json" -o "$tmp/huge.png"
expect cast_same_output 2 "--save-raw .*c.png: names the same file as -o .*c.png" -- \
    "$cube5" cast phantom:shell:20 --size 16 --views 1 -o "$tmp/c.png" --save-raw "$tmp/c.png"
expect sweep_text 0 "" -- bash -c "\"$cube5\" sweep default --size 8 --knob bounces=0,3 --out \"$tmp/sw3\" 2>/dev/null | grep -q '^  reference  cref'"
printf '{"volumes": [{"generator": "marschner_lobb", "dims": [16, 16, 16]}],
  "transfer_function": {"opacity": [[0,0],[104,0],[128,0.3],[152,0],[255,0]], "color": [[0,1,1,1]]},
  "camera": {"eye": [40,-25,30], "target": [8,8,8], "width": 12, "height": 12}}' >"$tmp/ml.json"
json=$("$cube5" sweep "$tmp/ml.json" --knob step=1,2 --knob width.rgb=12,8 --out "$tmp/swml" --json 2>/dev/null)
if python3 -c '
import json, sys
d = json.loads(sys.argv[1])
assert d["reference"]["field"] == "analytic Marschner-Lobb" and d["reference"]["cast"] is None
assert len(d["rows"]) == 6 and d["rows"][4]["renderer"] == "model" and d["rows"][4]["default"] is True and d["rows"][5]["default"] is False
assert d["rows"][0]["rmse"] < d["rows"][2]["rmse"]' "$json"; then ok sweep_marschner_lobb; else bad sweep_marschner_lobb "$json"; fi
for c in "speed=1|unknown knob 'speed'" "step=|step: no values" "step=1,,2|empty value" "et=abc|expected an opacity" \
    "et=0|expected an opacity in \(0, 1\]" "et=1.5|expected an opacity in \(0, 1\]" "bounces=16|0\.\.15" \
    "step=0|expected a step in voxels" "step=-2|expected a step in voxels" "width.pos=16|must be 1 \.\. 15" \
    "width.foo=3|unknown datapath width 'foo'" "k=3|expected 1, 2, 4, 8 or 16" "step|expected NAME=V1,V2"; do
    expect "sweep_bad_knob_'${c%%|*}'" 2 "${c#*|}" -- "$cube5" sweep default --size 8 --knob "${c%%|*}" --out "$tmp/swbad"
done
expect sweep_knob_twice 2 "--knob et: given twice" -- "$cube5" sweep default --knob et=1 --knob et=0.9 --out "$tmp/swbad"
expect sweep_knob_missing 2 "--knob: missing value" -- "$cube5" sweep default --knob
expect sweep_bad_size 2 "--size: expected" -- "$cube5" sweep default --size 0 --out "$tmp/swbad"
expect sweep_unknown_option 2 "unknown option '--bogus'" -- "$cube5" sweep default --bogus
expect sweep_k_without_volume 2 "has no volume to cast" -- "$cube5" sweep "$tmp/novol.json" --knob k=1 --out "$tmp/swbad"
if [ ! -e "$tmp/swbad" ]; then ok sweep_bad_input_writes_nothing; else bad sweep_bad_input_writes_nothing; fi
mkdir -p "$tmp/nobin"
expect sweep_without_gnuplot 1 "gnuplot with the pngcairo terminal is needed" -- \
    env PATH="$tmp/nobin" "$cube5" sweep default --size 8 --knob et=1 --out "$tmp/swnp"

# ---- Nothing the user gave is overwritten (tests/data/repro/) -------------------------------
# Every path a command writes is checked against the scene file, each volume and the data
# files a NRRD header names, before anything is written: exit 2 and the input unchanged.
at() { mkdir -p "$tmp/$1" && cd "$tmp/$1"; } # the reproducers use names relative to their folder
filler() { head -c "${2:-32768}" /dev/zero | tr '\0' '@' >"$1"; } # FILE [BYTES]
unchanged() { # NAME FILE SUM
    if [ "$(sha256sum <"$2")" = "$3" ]; then ok "$1"; else bad "$1" "$2 was overwritten"; fi
}
at of && cp "$OLDPWD/tests/data/repro/overwrite_frames/scene.json" . && filler img_0000.png
sum=$(sha256sum <img_0000.png)
expect frames_refuse_input_volume 2 "img_0000.png: is volume 0 .*refusing to overwrite an input" -- \
    "$cube5" render scene.json --size 16x16 -o img.png
unchanged frames_input_volume_kept img_0000.png "$sum"
[ ! -e img_0001.png ] && ok frames_none_written || bad frames_none_written "img_0001.png written"
expect frames_other_name_ok 0 "" -- "$cube5" render scene.json --size 8x8 -o out.png
[ -s out_0000.png ] && [ -s out_0001.png ] && ok frames_numbered_written || bad frames_numbered_written "$(ls)"
cd - >/dev/null

at od && cp "$OLDPWD/tests/data/repro/overwrite_nhdr_datafile/vol.nhdr" . && filler data.png
sum=$(sha256sum <data.png)
expect nhdr_refuse_data_file 2 "data.png: is the data file of vol.nhdr .*refusing to overwrite an input" -- \
    "$cube5" render default --size 16x16 --volume vol.nhdr -o data.png
unchanged nhdr_data_file_kept data.png "$sum"
ln data.png hard.png
expect nhdr_refuse_hard_link 2 "hard.png: is the data file of vol.nhdr" -- \
    "$cube5" render default --size 8x8 --volume vol.nhdr -o hard.png
expect compare_diff_refuse_data_file 2 "is the data file of vol.nhdr" -- \
    "$cube5" compare default --size 8x8 --volume vol.nhdr --diff data.png
expect cast_refuse_data_file 2 "is the data file of vol.nhdr" -- "$cube5" cast vol.nhdr --views 1 --size 8 -o data.png
expect cast_save_raw_refuse_data_file 2 "is the data file of vol.nhdr" -- \
    "$cube5" cast vol.nhdr --views 1 --size 8 --save-raw data.png
unchanged nhdr_data_file_kept_by_all data.png "$sum"
# "data file: LIST" and the printf-style "%d MIN MAX STEP" form: the NRRD precheck refuses
# a header with several data files before any output, and the files it names stay as they were
mkdir -p sub && filler s1.png 16384 && filler s2.png 16384 && filler sub/p001.png 16384 && filler sub/p003.png 16384
printf 'NRRD0004\ntype: uchar\ndimension: 3\nsizes: 128 128 2\nencoding: raw\ndata file: LIST\ns1.png\ns2.png\n' >list.nhdr
printf 'NRRD0004\ntype: uchar\ndimension: 3\nsizes: 128 128 2\nencoding: raw\ndata file: sub/p%%03d.png 1 3 2 2\n' >fmt.nhdr
sum=$(sha256sum <s2.png)
expect nhdr_list_refused 2 "list.nhdr: NRRD data file \"LIST\": one data file only" -- \
    "$cube5" render default --size 8x8 --volume list.nhdr -o s2.png
unchanged nhdr_list_data_file_kept s2.png "$sum"
sum=$(sha256sum <sub/p003.png)
expect nhdr_format_refused 2 "fmt.nhdr: NRRD data file .*one data file only" -- \
    "$cube5" render default --size 8x8 --volume "$tmp/od/fmt.nhdr" -o "$tmp/od/sub/p003.png"
unchanged nhdr_format_data_file_kept sub/p003.png "$sum"
cd - >/dev/null

# sweep: replaces its own files, never an input
at swin && head -c 1000 /dev/zero >sweep.csv
printf '{"volumes": [{"file": "sweep.csv", "dims": [10, 10, 10], "type": "uint8"}], "transfer_function": {"opacity": [[0,0],[255,1]], "color": [[0,1,1,1]]},
  "camera": {"eye": [30,30,30], "target": [5,5,5], "width": 8, "height": 8}}' >csvvol.json
cd - >/dev/null
expect sweep_refuse_input 2 "sweep.csv: is volume 0 .*refusing to overwrite an input" -- \
    "$cube5" sweep "$tmp/swin/csvvol.json" --knob et=1 --out "$tmp/swin"
[ "$(head -c 1000 /dev/zero | sha256sum)" = "$(sha256sum <"$tmp/swin/sweep.csv")" ] && ok sweep_input_kept ||
    bad sweep_input_kept "sweep.csv changed"
# vectors: an earlier set's files are removed before new ones are written; one that a scene
# reads is refused before the folder is touched
"$cube5" vectors --scene none --count 1 --out "$tmp/vset" >/dev/null 2>&1
first=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["files"][0]["file"])' "$tmp/vset/manifest.json")
size=$(stat -c %s "$tmp/vset/$first")
filler "$tmp/vset/$first" "$size" # the user's bytes now, not what the generator would write again
sum=$(sha256sum <"$tmp/vset/$first")
printf '{"volumes": [{"file": "%s", "dims": [%d, 1, 1], "type": "uint8"}], "transfer_function": {"opacity": [[0,0],[255,1]], "color": [[0,1,1,1]]},
  "camera": {"eye": [30,30,30], "target": [5,0,0], "width": 8, "height": 8}}' "$tmp/vset/$first" "$size" >"$tmp/vin.json"
expect vectors_refuse_folder_with_input 2 "vset: holds volume 0 .*refusing to write into a folder with an input" -- \
    "$cube5" vectors --scene "$tmp/vin.json" --count 1 --out "$tmp/vset"
[ -f "$tmp/vset/$first" ] && unchanged vectors_input_kept "$tmp/vset/$first" "$sum" || bad vectors_input_kept "removed"

# ---- -o into a missing folder: refused before the work, naming the user's path --------------
for c in "render default --size 8x8 -o $tmp/nodir/x.png" "compare default --size 8x8 --diff $tmp/nodir/d.exr" \
    "cast phantom:ml:8 --views 1 --size 8 -o $tmp/nodir/c.png"; do
    # shellcheck disable=SC2086
    expect "missing_folder_${c%% *}" 2 "$tmp/nodir/[a-z]\.(png|exr): cannot write: folder $tmp/nodir/: No such file" -- "$cube5" $c
done
if "$cube5" render default --size 8x8 -o "$tmp/nodir/x.png" 2>&1 | grep -q '\.tmp-'; then
    bad missing_folder_no_temp_name
else ok missing_folder_no_temp_name; fi

# ---- schedule: why a frame runs Max Work -----------------------------------------------------
printf '{"volumes": [{"generator": "marschner_lobb", "dims": [16, 16, 16]}], "transfer_function": {"opacity": [[0,0],[255,1]], "color": [[0,1,1,1]]},
  "camera": {"eye": [40,40,40], "target": [80,80,80], "width": 8, "height": 8}}' >"$tmp/away.json"
followed() { "$cube5" schedule "$@" --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["frames"][1]["followed"])'; }
[ "$(followed "$tmp/away.json")" = "maxwork (previous tree empty)" ] && ok schedule_previous_tree_empty ||
    bad schedule_previous_tree_empty "$(followed "$tmp/away.json")"
[ "$(followed default --size 16x16 --tree-nodes 1)" = "maxwork (previous tree overflowed)" ] &&
    ok schedule_previous_tree_overflowed || bad schedule_previous_tree_overflowed "$(followed default --size 16x16 --tree-nodes 1)"

# ---- Conventions (README): --version, help CMD, progress on stderr only ----------------------
[ "$("$cube5" --version)" = "cube5 $(cat VERSION)" ] && ok version_from_VERSION || bad version_from_VERSION "$("$cube5" --version)"
for c in render compare schedule sweep vectors cast scenes; do
    if [ "$("$cube5" help $c)" = "$("$cube5" $c --help)" ] && [ -n "$("$cube5" help $c)" ]; then ok "help_$c"; else bad "help_$c"; fi
done
# A command without options or operand: its synopsis is the name alone (the table's usage
# writer must not print an unset synopsis).
line=$("$cube5" scenes --help)
[ "$(sed -n 1p <<<"$line")" = "usage: cube5 scenes" ] && ok "help_scenes_synopsis" ||
    bad "help_scenes_synopsis" "$(sed -n 1p <<<"$line")"
expect help_unknown_command 2 "unknown command 'nosuch'" -- "$cube5" help nosuch
expect progress_not_for_scenes 2 "'--progress'" -- "$cube5" scenes --progress
# progress: one line per step with --progress (no terminal here), nothing without it, never on stdout
progress() { # NAME PATTERN -- ARGS...: stderr holds PATTERN, stdout none of it, and without --progress stderr is empty
    local name=$1 pat=$2
    shift 3
    "$cube5" "$@" --progress >"$tmp/p.out" 2>"$tmp/p.err"
    local rc=$?
    if [ "$rc" -ne 0 ] || ! grep -qE "$pat" "$tmp/p.err" || grep -q "cube5 $1: \[" "$tmp/p.out"; then
        bad "progress_$name" "exit $rc" "$(cat "$tmp/p.err")"
    elif [ -n "$("$cube5" "$@" 2>&1 >/dev/null)" ]; then
        bad "progress_$name" "stderr not empty without --progress"
    else
        ok "progress_$name"
    fi
}
progress render "^cube5 render: \[3/3\] frame 2: $tmp/pr_0002.png \([0-9.]+ s\)$" -- render brain_mirrors --size 8x8 --frames 3 -o "$tmp/pr.png"
progress render_json "^cube5 render: \[2/2\] frame 1 " -- render brain_mirrors --size 8x8 --frames 2 --json
python3 -c 'import json,sys; json.load(open(sys.argv[1]))' "$tmp/p.out" && ok progress_json_stdout_is_json || bad progress_json_stdout_is_json
progress compare "^cube5 compare: \[2/2\] rtl model: " -- compare default --size 8x8 --json
progress schedule "^cube5 schedule: \[2/2\] frame 1: " -- schedule default --size 8x8
progress vectors "^cube5 vectors: \[[0-9]+/[0-9]+\] scene default" -- vectors --scene default --size 8x8 --count 1 --out "$tmp/pv"
progress cast "^cube5 cast: \[2/2\] view 1: " -- cast phantom:ml:8 --views 2 --size 8
# on a terminal: quick runs stay quiet; with --progress each step redraws the one line
if script -qec "\"$cube5\" render default --size 8x8 >/dev/null" /dev/null | grep -q 'cube5 render: \['; then
    bad progress_tty_quiet_when_quick
else ok progress_tty_quiet_when_quick; fi
# on a terminal: a line redrawn in place once the run is past its first second; with
# --progress one line per step there too
if script -qec "\"$cube5\" render brain_mirrors --size 256x256 --frames 8 >/dev/null" /dev/null |
    grep -q $'\r\033\\[Kcube5 render: \\[[0-9]/8\\]'; then ok progress_tty_redraws; else bad progress_tty_redraws; fi
out=$(script -qec "\"$cube5\" render brain_mirrors --size 8x8 --frames 2 --progress >/dev/null" /dev/null)
if grep -q "^cube5 render: \[2/2\] frame 1" <<<"$out" && ! grep -q $'\033' <<<"$out"; then
    ok progress_flag_lines_on_a_tty
else
    bad progress_flag_lines_on_a_tty "$out"
fi
# the image library is opened on the first image: a run without one never needs it; one that
# cannot find it fails (1) naming the file and the library, and leaves nothing
expect image_lib_not_needed 0 "" -- env C5_IMAGE_LIB=/nonexistent/libc5image.so "$cube5" render default --size 8x8 --json
expect image_lib_missing 1 "nolib.png: the image library libc5image.so \(OpenImageIO\) cannot be loaded: /nonexistent/libc5image.so" -- \
    env C5_IMAGE_LIB=/nonexistent/libc5image.so "$cube5" render default --size 8x8 -o "$tmp/nolib.png"
[ -e "$tmp/nolib.png" ] && bad image_lib_missing_leaves_nothing || ok image_lib_missing_leaves_nothing
# neither a terminal nor --progress: a long run says once how to see its progress
err=$(C5_PROGRESS_HINT_S=0 "$cube5" render brain_mirrors --size 8x8 --frames 3 2>&1 >/dev/null)
[ "$(grep -c "^cube5 render: still running after 0 s (--progress prints a line per step)$" <<<"$err")" = 1 ] &&
    ok progress_hint_once || bad progress_hint_once "$err"
# the summary names the files written
"$cube5" render brain_mirrors --size 8x8 --frames 6 -o "$tmp/sn.png" | grep -q "images   6 files, $tmp/sn_0000.png ... $tmp/sn_0005.png" &&
    ok summary_names_frames || bad summary_names_frames
"$cube5" cast phantom:ml:8 --views 1 --size 8 -o "$tmp/cs.png" --save-raw "$tmp/cs.raw" | grep -q "image $tmp/cs.png" &&
    ok summary_names_cast_files || bad summary_names_cast_files

summary
[ "$failed" -eq 0 ]
