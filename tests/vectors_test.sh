#!/usr/bin/env bash
# The golden vectors (vectors/golden/, docs/vectors.md): regenerated with the golden set's
# own parameters and compared bit for bit (scripts/vectors_check.py names block, vector and
# field of any difference); the comparison itself is shown to catch a flipped bit and a
# changed scene CRC; the generator refuses bad options and never writes into a directory
# that holds anything but an earlier vector set. Usage: vectors_test.sh BUILD_DIR
set -u
build=${1:-build}
cube5="$PWD/$build/cube5"
golden=vectors/golden
check="python3 scripts/vectors_check.py"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/lib.sh"

# The golden set's parameters, from its manifest: the regeneration must not guess them.
args=$(python3 -c '
import json, sys
m = json.load(open(sys.argv[1]))
print("--seed %d --count %d --size %dx%d --cells %dx%dx%d" % (m["seed"], m["count"], *m["size"], *m["cells"]))
' "$golden/manifest.json") || args=""

if [ -z "$args" ]; then
    bad golden_manifest "cannot read $golden/manifest.json"
elif ! "$cube5" vectors --out "$tmp/fresh" $args >"$tmp/gen.log" 2>&1; then
    bad golden_regenerate "cube5 vectors $args failed" "$(cat "$tmp/gen.log")"
elif $check "$golden" "$tmp/fresh" >"$tmp/check.log" 2>&1; then
    ok "golden_identical ($(tail -n 1 "$tmp/check.log" | sed -E 's/^vectors_check: //; s/ identical.*//'))"
else
    bad golden_identical "the model's bits differ from $golden (a deliberate change: make golden, and say why in the commit)" \
        "$(head -n 30 "$tmp/check.log")"
fi

# caught NAME DIR PATTERN WHAT: vectors_check of DIR against the fresh set must fail, with
# PATTERN in its report.
caught() {
    if $check "$tmp/fresh" "$2" >"$tmp/$1.log" 2>&1; then
        bad "$1" "vectors_check passed $4"
    elif grep -q -- "$3" "$tmp/$1.log"; then
        ok "$1"
    else
        bad "$1" "the report does not name $4" "$(cat "$tmp/$1.log")"
    fi
}

# The check names the block, the vector index and the field of a flipped bit.
if [ -d "$tmp/fresh" ]; then
    cp -r "$tmp/fresh" "$tmp/flip"
    f="$tmp/flip/packet.directed.hex"
    # vector 3, field 4 (dir_x): flip the lowest bit of its last digit
    python3 - "$f" <<'PY'
import sys
p = sys.argv[1]; lines = open(p).read().split("\n")
cols = lines[3].split(" ")
cols[3] = cols[3][:-1] + "%x" % (int(cols[3][-1], 16) ^ 1)
lines[3] = " ".join(cols)
open(p, "w").write("\n".join(lines))
PY
    caught check_catches_bit_flip "$tmp/flip" "packet.directed.hex (block packet, directed): vector 3: dir_x expected" \
        "a flipped bit (block, vector 3, dir_x)"
    cp -r "$tmp/fresh" "$tmp/crc"
    python3 - "$tmp/crc/manifest.json" <<'PY'
import json, sys
p = sys.argv[1]; m = json.load(open(p))
m["scenes"][0]["dsp_ram"] = "crc32:00000000"
json.dump(m, open(p, "w"), indent=2)
PY
    scene0=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["scenes"][0]["scene"])' "$tmp/crc/manifest.json")
    caught check_catches_scene_crc "$tmp/crc" "scene $scene0: dsp_ram golden" "a changed DSP RAM CRC (scene, dsp_ram)"
fi

# A second run into the same directory replaces the set and gives the same bits; a
# directory holding other files is refused and left alone.
if "$cube5" vectors --out "$tmp/fresh" $args >/dev/null 2>&1 && $check "$golden" "$tmp/fresh" >/dev/null 2>&1; then
    ok rerun_replaces_set
else
    bad rerun_replaces_set "a second run into the same directory differs or failed"
fi
mkdir -p "$tmp/user" && echo keep >"$tmp/user/notes.txt"
err=$("$cube5" vectors --out "$tmp/user" --scene none 2>&1 >/dev/null)
status=$?
if [ "$status" -eq 2 ] && grep -q "refusing to write into it" <<<"$err" && [ "$(cat "$tmp/user/notes.txt")" = keep ] &&
    [ "$(ls "$tmp/user")" = notes.txt ]; then
    ok refuses_foreign_dir
else
    bad refuses_foreign_dir "exit $status" "$err" "$(ls "$tmp/user")"
fi

expect() { # expect NAME PATTERN ARGS...: exit 2 with PATTERN in the one-line error
    local name=$1 pat=$2
    shift 2
    local err status
    err=$("$cube5" vectors --out "$tmp/e" "$@" 2>&1 >/dev/null)
    status=$?
    if [ "$status" -eq 2 ] && grep -qE -- "$pat" <<<"$err" && [ "$(wc -l <<<"$err")" -eq 1 ]; then
        ok "$name"
    else
        bad "$name" "exit $status, expected 2 with /$pat/" "$err"
    fi
}
expect count_zero "--count" --count 0
expect count_text "--count" --count many
expect unknown_option "unknown option '--frobnicate'" --frobnicate 1
expect missing_value "--seed: missing value" --seed
expect unknown_scene "nosuchscene" --scene nosuchscene
expect none_and_scene "--scene none cannot be combined" --scene none --scene default
expect cells_too_many "cells" --scene default --cells 65

summary
