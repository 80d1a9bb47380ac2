#!/usr/bin/env bash
# Every output option of cube5 against every kind of place, drawn at random (a fuzz-style loop
# with a fixed seed, C5_FUZZ_SEED to draw others, C5_FUZZ_RUNS how many): a new file, an
# existing file, a link to one, a dangling link, a missing folder, a folder, the command's
# input, the run's other output or a link to it. The rule (README "Conventions") predicts the
# exit status: 2 before any work for a place no file can be written, an input, or two outputs
# naming one file; 0 otherwise, with every output whole, links kept and written through. A
# refused run leaves the sandbox exactly as it was; no run leaves a temporary.
# Usage: outputs_fuzz_test.sh BUILD
set -u
build=${1:-build}
. "$(dirname "$0")/lib.sh"
root=$PWD
cube5="$root/$build/cube5"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
seed=${C5_FUZZ_SEED:-1}
runs=${C5_FUZZ_RUNS:-48}
RANDOM=$seed
echo "outputs_fuzz_test: seed $seed, $runs runs (C5_FUZZ_SEED, C5_FUZZ_RUNS)"

"$cube5" cast phantom:shell:24 --size 8 --views 1 --save-raw "$tmp/in_24x24x24_uint8.raw" >/dev/null 2>&1 ||
    { bad input_volume "cube5 cast could not save the phantom"; summary; }

# sandbox DIR: the places, each for every extension.
sandbox() {
    mkdir -p "$1"
    cp "$tmp/in_24x24x24_uint8.raw" "$1/"
    local e
    for e in png exr vcd raw; do
        printf 'old\n' >"$1/exist.$e"
        ln -s "exist.$e" "$1/lexist.$e"
        ln -s "gone.$e" "$1/dang.$e"
        mkdir "$1/adir.$e"
    done
}
# state DIR: every entry with its kind and content (links: their target), to compare.
state() { (cd "$1" && find . -printf '%p %y %l\n' | sort && find . -type f -exec md5sum {} + | sort); }

# place KIND EXT OTHER: the path for an output of extension EXT (OTHER: the run's other output).
place() {
    case $1 in
    fresh) echo "new.$2" ;;
    exist) echo "exist.$2" ;;
    lexist) echo "lexist.$2" ;;
    dang) echo "dang.$2" ;;
    nodir) echo "nodir/x.$2" ;;
    isdir) echo "adir.$2" ;;
    input) echo "in_24x24x24_uint8.raw" ;;
    same) echo "$3" ;;
    lother) echo "lother.$2" ;;
    esac
}
kinds=(fresh exist lexist dang nodir isdir input same lother)

for ((r = 0; r < runs; r++)); do
    d="$tmp/run$r"
    sandbox "$d"
    cmd=() opts=() exts=()
    case $((RANDOM % 4)) in
    0) cmd=(render default --size 8x8) opts=(-o) exts=(png) ;;
    1) cmd=(render default --model rtl --cells 2 --size 8x8) opts=(-o --vcd) exts=(png vcd) ;;
    2) cmd=(cast in_24x24x24_uint8.raw --size 8 --views 1) opts=(-o --save-raw) exts=(exr raw) ;;
    3) cmd=(render brain_mirrors --frames 2 --size 8x8) opts=(-o) exts=(png) ;;
    esac
    [ $((RANDOM % 2)) = 0 ] && exts[0]=exr && [ "${cmd[0]}" = cast ] && exts[0]=png
    args=() paths=() want=0 first="" written=()
    for i in "${!opts[@]}"; do
        k=${kinds[RANDOM % ${#kinds[@]}]}
        # "same"/"lother" need an earlier output; "input" names a file only the caster reads
        { [ "$i" = 0 ] && { [ "$k" = same ] || [ "$k" = lother ]; }; } && k=fresh
        [ "$k" = input ] && [ "${cmd[0]}" != cast ] && k=exist
        p=$(place "$k" "${exts[i]}" "$first")
        [ "$k" = lother ] && ln -s "$first" "$d/lother.${exts[i]}"
        # a sequence writes NAME_0000.png and NAME_0001.png: only a missing folder stops it
        if [ "${cmd[1]}" = brain_mirrors ]; then
            [ "$k" = nodir ] && want=2
            written+=("${p%.*}_0000.${exts[i]}" "${p%.*}_0001.${exts[i]}")
        else
            case $k in nodir | isdir | input | same | lother) want=2 ;; esac
            written+=("$p")
        fi
        [ "$i" = 0 ] && first=$p
        args+=("${opts[i]}" "$p") paths+=("$k:$p")
    done
    name="run${r}_${cmd[0]}_${cmd[1]%%_*}_$(IFS=,; echo "${paths[*]}")"
    before=$(state "$d")
    err=$(cd "$d" && "$cube5" "${cmd[@]}" "${args[@]}" 2>&1 >/dev/null)
    status=$?
    left=$(leftovers "$d")
    judge "$name" "$want" "$status" "$err" "" || continue
    if [ -n "$left" ]; then
        bad "$name" "temporaries left: $left"
        continue
    fi
    if [ "$want" != 0 ]; then
        [ "$(state "$d")" = "$before" ] && ok "$name" || bad "$name" "a refused run changed the sandbox" "$err"
        continue
    fi
    problem=""
    for p in "${written[@]}"; do
        [ -s "$d/$p" ] && ! printf 'old\n' | cmp -s - "$d/$p" || problem+=" $p not written;"
    done
    for l in lexist dang; do
        for e in png exr vcd raw; do [ -L "$d/$l.$e" ] || problem+=" $l.$e is no longer a link;"; done
    done
    cmp -s "$d/in_24x24x24_uint8.raw" "$tmp/in_24x24x24_uint8.raw" || problem+=" the input changed;"
    [ -z "$problem" ] && ok "$name" || bad "$name" "$problem (seed $seed)" "$err"
    rm -rf "$d"
done

# cube5ctl's -o follows the same rule: refused before the board is touched.
d="$tmp/ctl"
sandbox "$d"
for k in nodir isdir; do
    p=$(place "$k" png "")
    before=$(state "$d")
    err=$(cd "$d" && "$root/$build/cube5-board" run -- "$root/$build/cube5ctl" render default --size 8x8 \
        -o "$p" 2>&1 >/dev/null)
    status=$?
    judge_tool=cube5ctl judge "cube5ctl_$k" 2 "$status" "$err" "^cube5ctl: error: $p: cannot write" &&
        { [ "$(state "$d")" = "$before" ] && ok "cube5ctl_$k" || bad "cube5ctl_$k" "the sandbox changed"; }
done
summary
