#!/usr/bin/env bash
# End-to-end tests of the cube5 command line: exit status and the one-line message of
# every bad input, and that outputs never overwrite inputs. Usage: cli_test.sh BUILD_DIR
set -u
build=${1:-build}
cube5="$PWD/$build/cube5"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
passed=0 failed=0

ok() { echo "ok   $1"; passed=$((passed + 1)); }
bad() { echo "FAIL $1"; shift; printf '    %s\n' "$@"; failed=$((failed + 1)); }

# expect NAME STATUS PATTERN -- CMD...: exit status, and PATTERN in stderr (one line).
expect() {
    local name=$1 want=$2 pat=$3
    shift 4
    local err status
    err=$("$@" 2>&1 >/dev/null)
    status=$?
    if [ "$status" -ne "$want" ]; then
        bad "$name" "exit $status, expected $want" "$err"
    elif [ -n "$pat" ] && ! grep -qE -- "$pat" <<<"$err"; then
        bad "$name" "stderr lacks /$pat/" "$err"
    elif [ "$want" -ne 0 ] && [ "$(wc -l <<<"$err")" -ne 1 ]; then
        bad "$name" "error is not one line" "$err"
    else
        ok "$name"
    fi
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
expect bad_size 2 "--size: expected WxH" -- "$cube5" render default --size 12
expect frames_without_path 2 "no camera_path" -- "$cube5" render default --frames 3
expect raw_ok 0 "" -- "$cube5" render "$tmp/ok.json"
expect raw_truncated 2 "short_10x10x10_uint8.raw: .*truncated" -- "$cube5" render "$tmp/short.json"
expect raw_oversized 2 "long_10x10x10_uint8.raw: .*extra bytes" -- "$cube5" render "$tmp/long.json"
expect raw_dims_mismatch 2 "vol_10x10x10_uint8.raw: .*expected 1100" -- "$cube5" render "$tmp/mismatch.json"
expect raw_unsupported_type 2 "odd_10x10x10_float32.raw: unsupported voxel type" -- "$cube5" render "$tmp/type.json"
expect raw_dims_overflow 2 "huge_4294967296x4294967296x2_uint8.raw: dims .*overflow" -- "$cube5" render "$tmp/overflow.json"
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

echo "SUMMARY passed=$passed failed=$failed"
[ "$failed" -eq 0 ]
