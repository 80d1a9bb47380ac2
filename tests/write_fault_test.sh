#!/usr/bin/env bash
# Every output written whole or not at all (common/atomic_file.h): the faults happen. A write
# shim (tests/fault/write_fault.c, LD_PRELOAD) fails the k-th write of a tool to a file with
# ENOSPC or EIO, for k at the start, the middle and the end of each writer's output, and every
# fsync; standard output on /dev/full; where the machine lets a test mount a small tmpfs, a
# full file system as well. Each
# case checks the exit code (1), the message (the file and the system's reason) and that no
# partial and no temporary file is left. Usage: write_fault_test.sh BUILD
set -u
build=${1:-build}
. "$(dirname "$0")/lib.sh"
cube5="$build/cube5"
shim="$build/tests/libwritefault.so"
tmp=$(mktemp -d)
trap 'umount "$tmp/small" 2>/dev/null; rm -rf "$tmp"' EXIT
# An ASan build needs its runtime first among the preloaded libraries. The programs cube5
# starts (sweep's gnuplot) inherit it, and LeakSanitizer would report gnuplot's own leaks:
# leak checking is off for these runs (cube5's leaks are checked by the other suites).
pre="$shim"
if ldd "$cube5" 2>/dev/null | grep -q libasan; then
    pre="$(ldd "$cube5" | awk '/libasan/ {print $3}') $shim"
    export ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0
fi

reason() { [ "$1" = EIO ] && echo "Input/output error" || echo "No space left on device"; }


# calls CMD...: how many writes the shim counts for a clean run.
calls() { C5_FAULT_COUNT=1 LD_PRELOAD="$pre" "$@" 2>&1 >/dev/null | grep -c '^write_fault: call'; }

# fault NAME TARGET AT ERRNO CMD...: the run fails at AT (a call number, fsync, or none: no
# shim, the fault is the machine's) with ERRNO; it must exit 1 naming TARGET and the reason,
# leave no TARGET and no temporary. A TARGET ending in / is a folder of outputs: the message
# names a file in it, the files written before the fault stay (each whole).
fault() {
    local name=$1 target=$2 at=$3 eno=$4 named
    shift 4
    named=$(basename "$target")
    if [ "${target%/}" != "$target" ]; then
        target=${target%/}/.
        named=$(dirname "$target")/
    fi
    local err status
    if [ "$at" = none ]; then # a real fault (a full file system): no shim
        err=$("$@" 2>&1 >/dev/null)
    else
        err=$(C5_FAULT_AT=$at C5_FAULT_ERRNO=$eno LD_PRELOAD="$pre" "$@" 2>&1 >/dev/null)
    fi
    status=$?
    local left
    left=$(leftovers "$(dirname "$target")")
    if [ "$status" != 1 ]; then
        bad "$name" "exit $status, expected 1" "$err"
    elif ! grep -qF "$named" <<<"$err" || ! grep -qF "$(reason "$eno")" <<<"$err"; then
        bad "$name" "the message does not name $named and '$(reason "$eno")'" "$err"
    elif [ "${target%/.}" = "$target" ] && [ -e "$target" ]; then
        bad "$name" "$target was left behind"
    elif [ -n "$left" ]; then
        bad "$name" "temporaries left behind: $left"
    else
        ok "$name"
    fi
}

# sweep_k NAME TARGET CMD...: faults at the first, the middle and the last write and at fsync.
sweep_k() {
    local name=$1 target=$2
    shift 2
    local dir
    dir=$(dirname "$target")
    [ "${target%/}" != "$target" ] && dir=$(dirname "${target%/}")
    rm -rf "$dir"
    mkdir -p "$dir"
    local n
    n=$(calls "$@")
    rm -rf "$dir"
    if [ "${n:-0}" -lt 1 ]; then
        bad "${name}_counted" "the shim counted no write of $target"
        return
    fi
    local k eno=ENOSPC
    for k in $(printf '%s\n' 1 $(((n + 1) / 2)) "$n" | sort -un) fsync; do
        mkdir -p "$dir"
        fault "${name}_at_$k" "$target" "$k" "$eno" "$@"
        rm -rf "$dir"
        [ "$eno" = ENOSPC ] && eno=EIO || eno=ENOSPC
    done
}

mkdir -p "$tmp/o"
sweep_k png "$tmp/o/png/x.png" "$cube5" render default --size 32x32 -o "$tmp/o/png/x.png"
sweep_k exr "$tmp/o/exr/x.exr" "$cube5" render default --size 32x32 -o "$tmp/o/exr/x.exr"
sweep_k vcd "$tmp/o/vcd/w.vcd" "$cube5" render default --model rtl --cells 2 --size 16x16 --vcd "$tmp/o/vcd/w.vcd"
sweep_k vectors "$tmp/o/vec/v/" "$cube5" vectors --out "$tmp/o/vec/v" --scene none --count 1 --size 8x8
sweep_k sweep "$tmp/o/sw/s/" "$cube5" sweep default --knob step=2 --size 8 --out "$tmp/o/sw/s"
sweep_k raw "$tmp/o/raw/v_40x40x40_uint8.raw" "$cube5" cast phantom:shell:40 --size 16 --views 1 \
    --save-raw "$tmp/o/raw/v_40x40x40_uint8.raw"
# cube5ctl's frame, on the emulated board (the shim faults cube5ctl, not the board)
sweep_k ctl "$tmp/o/ctl/f.png" env C5_FAULT_PROG=cube5ctl "$build/cube5-board" run -- "$build/cube5ctl" \
    render default --size 32x32 -o "$tmp/o/ctl/f.png"

# A sequence that fails at frame 1 says so and leaves frame 0 whole (the bytes of a clean run).
d="$tmp/seq"
mkdir -p "$d/clean" "$d/run"
"$cube5" render brain_mirrors --size 16x16 --frames 3 -o "$d/clean/f.png" >/dev/null 2>&1
err=$(C5_FAULT_AT=2 LD_PRELOAD="$pre" "$cube5" render brain_mirrors --size 16x16 --frames 3 -o "$d/run/f.png" 2>&1 >/dev/null)
status=$?
if [ "$status" = 1 ] && grep -qF "f_0001.png" <<<"$err" && cmp -s "$d/clean/f_0000.png" "$d/run/f_0000.png" &&
    [ ! -e "$d/run/f_0001.png" ] && [ ! -e "$d/run/f_0002.png" ] && [ -z "$(leftovers "$d/run")" ]; then
    ok sequence_keeps_the_frames_before
else
    bad sequence_keeps_the_frames_before "exit $status; $(ls -a "$d/run" | tr '\n' ' ')" "$err"
fi

# A target that is a symbolic link is written through it: the link stays.
mkdir -p "$tmp/link"
"$cube5" render default --size 16x16 -o "$tmp/link/real.png" >/dev/null 2>&1
ln -s real.png "$tmp/link/l.png"
if "$cube5" render default --size 24x24 -o "$tmp/link/l.png" >/dev/null 2>&1 && [ -L "$tmp/link/l.png" ] &&
    cmp -s "$tmp/link/l.png" "$tmp/link/real.png" && [ "$(stat -c %s "$tmp/link/real.png")" -gt 0 ]; then
    ok link_written_through
else
    bad link_written_through "$(ls -la "$tmp/link")"
fi

# Standard output is an output too: a summary or a --json object that cannot be written fails
# the run (/dev/full: every write ENOSPC).
for cmd in "scenes" "render default --size 8x8 --json -o $tmp/so.png"; do
    name="stdout_full_$(cut -d' ' -f1 <<<"$cmd")"
    # shellcheck disable=SC2086 # cmd is a list of arguments
    err=$("$cube5" $cmd 2>&1 >/dev/full)
    status=$?
    if [ "$status" = 1 ] && grep -qF "standard output: cannot write: No space left on device" <<<"$err"; then
        ok "$name"
    else
        bad "$name" "exit $status" "$err"
    fi
done

# A full file system, where this machine lets a test mount one (root): the issue's cases.
mkdir -p "$tmp/small"
if mount -t tmpfs -o size=32k tmpfs "$tmp/small" 2>/dev/null; then
    dd if=/dev/zero of="$tmp/small/fill" bs=1k count=28 status=none 2>/dev/null
    fault full_png "$tmp/small/x.png" none ENOSPC "$cube5" render default --size 256x256 -o "$tmp/small/x.png"
    err=$("$cube5" render brain_mirrors --size 128x128 --frames 3 -o "$tmp/small/f.png" 2>&1 >/dev/null)
    status=$?
    left=$(find "$tmp/small" -name 'f_*' -size 0)
    if [ "$status" = 1 ] && grep -qF "No space left on device" <<<"$err" && [ -z "$left" ] &&
        [ -z "$(leftovers "$tmp/small")" ]; then
        ok full_sequence
    else
        bad full_sequence "exit $status; empty frames: $left" "$err"
    fi
    umount "$tmp/small"
else
    echo "write_fault_test: cannot mount a tmpfs here (not root?): the full file system cases use the shim only" >&2
fi
summary
