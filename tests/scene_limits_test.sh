#!/usr/bin/env bash
# End-to-end tests of the scene ranges and the board model's limits: the reproducers of
# tests/data/repro/ and every model limit end with exit 2 and one message naming the file,
# the key or option and the limit, quickly and without writing anything; cref renders the
# scenes the model refuses for its field widths. Usage: scene_limits_test.sh BUILD_DIR
set -u
build=${1:-build}
cube5="$PWD/$build/cube5"
repro="$PWD/tests/data/repro"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/lib.sh"

# expect NAME STATUS PATTERN -- CMD...: within 60 s, the exit status,
# PATTERN in stderr (one line, no number of 20 digits or more), nothing left in $tmp/out.
expect() {
    local name=$1 want=$2 pat=$3
    shift 4
    local err status
    rm -rf "$tmp/out" && mkdir "$tmp/out"
    err=$(timeout "${C5_TEST_LIMIT_S:-60}" "$@" 2>&1 >/dev/null)
    status=$?
    judge "$name" "$want" "$status" "$err" "$pat" || return 0
    if grep -qE '[0-9]{20}' <<<"$err"; then
        bad "$name" "a number 20 digits long or more" "$err"
    elif [ "$want" -ne 0 ] && [ -n "$(ls -A "$tmp/out")" ]; then
        bad "$name" "wrote $(ls "$tmp/out")"
    else
        ok "$name"
    fi
}

out="$tmp/out/x.exr"
expect repro_ior_1e16 2 "hang_cref_ior_1e16.json: surfaces\[0\]\.material\.ior: must be in" -- \
    "$cube5" render "$repro/hang_cref_ior_1e16.json" -o "$out"
expect repro_ior_1e300 2 "hang_cref_ior_1e300.json: surfaces\[0\]\.material\.ior: must be in .*got 1e\+300" -- \
    "$cube5" render "$repro/hang_cref_ior_1e300.json" -o "$out"
expect repro_tiny_step 2 "hang_cref_tiny_step.json: render\.step: must be in" -- \
    "$cube5" render "$repro/hang_cref_tiny_step.json" -o "$out"
expect repro_aniso_spacing 2 "hang_cref_aniso_spacing.json: grid\.spacing\[0\]: must be in" -- \
    "$cube5" render "$repro/hang_cref_aniso_spacing.json" -o "$out"
expect repro_path_up_flip 2 "partial_output_path_up_flip.json: camera_path: frame 1 of 3: up is zero" -- \
    "$cube5" render "$repro/partial_output_path_up_flip.json" -o "$tmp/out/p.png"
expect repro_path_up_flip_compare 2 "partial_output_path_up_flip.json: camera_path: frame 1 of 3" -- \
    "$cube5" compare "$repro/partial_output_path_up_flip.json"

# A path valid at 2 frames that --frames makes pass through the target: refused before
# the first frame is written.
printf '{"camera": {"eye": [2,0,0], "target": [0,0,0], "width": 4, "height": 4},
  "camera_path": {"frames": 2, "keys": [{"eye": [2,0,0], "target": [0,0,0]}, {"eye": [-2,0,0], "target": [0,0,0]}]}}' \
    >"$tmp/through.json"
expect path_ok_at_2_frames 0 "" -- "$cube5" render "$tmp/through.json"
expect path_frames_option 2 "through.json: camera_path: frame 2 of 5: the eye is on the target" -- \
    "$cube5" render "$tmp/through.json" --frames 5 -o "$tmp/out/t.png"

# Samples per ray: a step or spacing within its range, too fine for the grid's diagonal.
printf '{"volumes": [{"generator": "constant", "dims": [8,8,8]}], "transfer_function": {"opacity": [[0,0]],
  "color": [[0,1,1,1]]}, "camera": {"eye": [4,4,40], "target": [4,4,4], "up": [0,1,0], "width": 4, "height": 4},
  "render": {"step": 1e-6}}' >"$tmp/step.json"
expect samples_per_ray 2 "step.json: render\.step: a ray across the grid .* 1\.38564e\+07 samples .*at most 1048576" -- \
    "$cube5" render "$tmp/step.json" -o "$out"

# Light factors that made cref write +Inf into an EXR with exit 0.
base='"camera": {"eye": [0,0,10], "target": [0,0,0], "up": [0,1,0], "width": 4, "height": 4}'
sphere='"surfaces": [{"type": "sphere", "center": [0,0,0], "radius": 1, "material": %s}]'
printf "{$base, \"render\": {\"background\": [1e300, 0, 0]}}" >"$tmp/bg.json"
printf "{$base, \"lights\": [{\"type\": \"point\", \"position\": [0,0,5], \"intensity\": 1e300}], $sphere}" '{}' \
    >"$tmp/light.json"
printf "{$base, $sphere}" '{"ambient": 1e300}' >"$tmp/amb.json"
expect inf_background 2 "bg.json: render\.background\[0\]: must be in \[0, 1000\], got 1e\+300" -- \
    "$cube5" render "$tmp/bg.json" -o "$out"
expect inf_light 2 "light.json: lights\[0\]\.intensity: must be in \[0, 1000\]" -- "$cube5" render "$tmp/light.json" -o "$out"
expect inf_ambient 2 "amb.json: surfaces\[0\]\.material\.ambient: must be in \[0, 1000\]" -- \
    "$cube5" render "$tmp/amb.json" -o "$out"

# The board model's field-width limits: exit 2 before any volume is read or generated,
# naming the file, the key or option, the limit and the field. cref renders the same
# scenes (exit 0) where its own ranges allow.
expect model_cells 2 "built-in scene default: --cells 17x16x16: 4352 cells: .*cell id \(12 bits\) names up to 4096" -- \
    "$cube5" render default --model rtl --cells 17x16x16
expect model_cells_compare 2 "built-in scene default: --cells 17x16x16: .*12 bits" -- "$cube5" compare default --cells 17x16x16
expect model_cells_schedule 2 "built-in scene default: --cells 17x16x16: .*12 bits" -- "$cube5" schedule default --cells 17x16x16
expect model_image 2 "built-in scene default: image 600x513 .*\(9\+9 bits\) holds images up to 512x512" -- \
    "$cube5" render default --model rtl --size 600x513
n=32 surfs=""
for i in $(seq $n); do surfs="$surfs{\"type\": \"sphere\", \"center\": [$i,0,0], \"radius\": 0.5},"; done
printf "{$base, \"surfaces\": [%s]}" "${surfs%,}" >"$tmp/surf32.json"
expect model_surfaces 2 "surf32.json: surfaces: 32 of them: .*interaction field \(5 bits\) names up to 31" -- \
    "$cube5" render "$tmp/surf32.json" --model rtl
expect cref_surfaces 0 "" -- "$cube5" render "$tmp/surf32.json"
printf "{$base, \"render\": {\"max_bounces\": 16}}" >"$tmp/b16.json"
expect model_bounces 2 "b16.json: render\.max_bounces: 16: .*generation field \(4 bits\) counts up to 15" -- \
    "$cube5" render "$tmp/b16.json" --model rtl
printf "{$base, $sphere}" '{"transparency": 1, "ior": 20}' >"$tmp/ior20.json"
expect model_ior 2 "ior20.json: surfaces\[0\]\.material\.ior: 20: .*eta UQ4\.28, which holds values below 16" -- \
    "$cube5" compare "$tmp/ior20.json"
expect cref_ior 0 "" -- "$cube5" render "$tmp/ior20.json"
# The driver (cube5ctl under the emulated board) checks the same limits before it builds
# the grid, naming the file.
judge_tool=cube5ctl expect driver_ior 2 "ior20.json: surfaces\[0\]\.material\.ior: 20: .*eta UQ4\.28" -- \
    "$PWD/$build/cube5-board" run -- "$PWD/$build/cube5ctl" render "$tmp/ior20.json" -o "$tmp/out/l.png"
printf "{$base, \"volumes\": [{\"generator\": \"ramp\", \"dims\": [4,4,4]}], \"transfer_function\": {\"opacity\":
  [[0,0]], \"color\": [[0,1,1,1]], \"shading\": {\"ambient\": 16}}}" >"$tmp/amb16.json"
expect model_ambient 2 "amb16.json: transfer_function\.shading\.ambient: 16: .*UQ4\.12" -- \
    "$cube5" render "$tmp/amb16.json" --model rtl
# 1024^3 voxels in 2x2x2 cells of 512 would take minutes and gigabytes to generate: refused
# first (the 60 s limit of expect() would catch a generation).
printf '{"volumes": [{"generator": "blobs", "dims": [1024, 1024, 1024]}], "transfer_function": {"opacity":
  [[0,0]], "color": [[0,1,1,1]]}, "camera": {"eye": [512,512,3000], "target": [512,512,512], "up": [0,1,0],
  "width": 4, "height": 4}}' >"$tmp/big.json"
expect model_grid_before_generation 2 "big.json: volumes\[0\] \(dims \+ offset\): 1024 voxels along axis 0 in 2 cell\(s\): cells of 512 .*UQ8\.15" -- \
    "$cube5" render "$tmp/big.json" --model rtl --cells 2
# The same from a NRRD header's sizes, read by the precheck before the data (a sparse 1 GiB
# data file: reading it first would be refused later with the set-up's message instead).
printf 'NRRD0004\ntype: uchar\ndimension: 3\nsizes: 1024 1024 1024\nencoding: raw\ndata file: big.raw\n' >"$tmp/big.nhdr"
truncate -s 1G "$tmp/big.raw"
expect model_nrrd_grid_before_read 2 "default: volumes\[0\] \(dims \+ offset\): 1024 voxels along axis 0 in 2 cell\(s\): .*UQ8\.15" -- \
    "$cube5" render default --model rtl --cells 2 --volume "$tmp/big.nhdr"
rm -f "$tmp/big.raw"
# A step that a NRRD's own spacings set: the message names the file, not grid.spacing.
printf 'NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 4\nspacings: 1e-30 1 1\nencoding: raw\ndata file: sp.raw\n' >"$tmp/sp.nhdr"
head -c 64 /dev/zero >"$tmp/sp.raw"
expect samples_per_ray_file_spacing 2 "default: the spacing of file sp\.nhdr: a ray across the grid .* at most 1048576" -- \
    "$cube5" render default --size 8x8 --volume "$tmp/sp.nhdr" -o "$tmp/out/sp.png"
# Limits that need the built grid: %g numbers, exit 2, the file named.
printf '{"volumes": [{"generator": "ramp", "dims": [8,8,8]}], "lights": [{"type": "point", "position": [900000,0,0]}],
  "transfer_function": {"opacity": [[0,0]], "color": [[0,1,1,1]]},
  "camera": {"eye": [4,4,30], "target": [4,4,4], "up": [0,1,0], "width": 4, "height": 4}}' >"$tmp/far.json"
expect model_far_light 2 "far.json: a point light lies 900000 grid steps .*SQ13\.15" -- \
    "$cube5" render "$tmp/far.json" --model rtl
expect cref_far_light 0 "" -- "$cube5" render "$tmp/far.json"
summary
