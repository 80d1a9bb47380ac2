#!/usr/bin/env bash
# Every option of the three tools, read from their own --help, given a value that is no value
# ("@@bad") and given no value at all: each is refused before any work with exit 2 and one
# line "TOOL: error: ..." that names the option or the value (README "Conventions"). A new
# option is covered the day it is listed in --help. Options whose value may be any name (an
# output folder, a file to create, a serial number) are given @@bad only as a missing value.
# Usage: options_test.sh BUILD
set -u
build=${1:-build}
. "$(dirname "$0")/lib.sh"
root=$PWD
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp" || exit 2
any_name=" --out --save-raw --serial "

# valued HELP: the options of a --help text that take a value ("  --opt VALUE  what it does").
valued() { sed -nE 's/^ +(-o|--[a-z0-9-]+) ([^ -][^ ]*)( |$).*/\1/p' <<<"$1" | sort -u; }

# try TOOL NAME CMD...: CMD must be refused with exit 2 in one line naming $opt or @@bad.
try() {
    local tool=$1 name=$2 err status
    shift 2
    err=$(timeout 60 "$@" 2>&1 >/dev/null)
    status=$?
    judge_tool=$tool judge "$name" 2 "$status" "$err" "(^|[ '\"])($opt|@@bad)([ :=,'\"]|$)" && ok "$name"
}

for cmd in cast compare render schedule sweep vectors; do
    pos=()
    [ "$cmd" = cast ] && pos=(phantom:shell:16)
    opts=$(valued "$("$root/$build/cube5" "$cmd" --help)")
    [ -n "$opts" ] || bad "cube5_${cmd}_options_found" "no option with a value in 'cube5 $cmd --help'"
    for opt in $opts; do
        [[ $any_name == *" $opt "* ]] ||
            try cube5 "cube5_${cmd}_${opt}_bad_value" "$root/$build/cube5" "$cmd" "${pos[@]}" "$opt" @@bad
        try cube5 "cube5_${cmd}_${opt}_no_value" "$root/$build/cube5" "$cmd" "${pos[@]}" "$opt"
    done
done

opts=$(valued "$("$root/$build/cube5ctl" --help)")
for opt in $opts; do
    for cmd in info render stats; do
        args=("$cmd")
        [ "$cmd" = render ] && args+=(default -o x.png)
        [[ $any_name == *" $opt "* ]] || try cube5ctl "cube5ctl_${cmd}_${opt}_bad_value" "$root/$build/cube5ctl" "${args[@]}" "$opt" @@bad
        try cube5ctl "cube5ctl_${cmd}_${opt}_no_value" "$root/$build/cube5ctl" "${args[@]}" "$opt"
    done
done
# render's options belong to render: info and stats refuse them, even at their defaults
for cmd in info stats; do
    for o in "--frame 0" "--size 8x8" "--cells 1" "-o x.png"; do
        opt=${o%% *}
        # shellcheck disable=SC2086 # an option and its value
        try cube5ctl "cube5ctl_${cmd}_refuses_${opt}" "$root/$build/cube5ctl" "$cmd" $o
    done
done

opts=$(valued "$("$root/$build/cube5-board" --help)")
for opt in $opts; do
    [[ $any_name == *" $opt "* ]] || try cube5-board "cube5-board_${opt}_bad_value" "$root/$build/cube5-board" run "$opt" @@bad -- true
    try cube5-board "cube5-board_${opt}_no_value" "$root/$build/cube5-board" run "$opt" -- true
done
summary
