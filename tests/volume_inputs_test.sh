#!/usr/bin/env bash
# End-to-end: `cube5 render --volume FILE` on the reproducers of tests/data/repro/ (inputs on
# which Teem crashed, over-read, leaked, allocated 4.3 GB or read /etc/passwd as voxels, see
# docs/nrrd-teem.md), a FIFO as a detached data file, a missing file, and the spacing the
# summary names. Each must end with exit 2 and one "cube5: error: FILE: ..." line, quickly;
# under `make asan` a leak or an over-read fails the run too. Usage: volume_inputs_test.sh BUILD
set -u
build=${1:-build}
cube5="$PWD/$build/cube5"
repro="$PWD/tests/data/repro"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/lib.sh"

# refused NAME PATTERN -- ARGS...: exit 2 within 20 s, one line naming the problem.
refused() {
    local name=$1 pat=$2
    shift 3
    local err status
    err=$(cd "$tmp" && timeout 20 "$cube5" "$@" 2>&1 >/dev/null)
    status=$?
    judge "$name" 2 "$status" "$err" "$pat" && ok "$name"
}

vol() { refused "$1" "$2" -- render default --size 8x8 --volume "$repro/$1"; }
vol crash_teem_long_header_line.nrrd "crash_teem_long_header_line.nrrd: .*header line 2 is longer than 400 bytes"
vol teem_biff_stack_overflow_fuzzer.nrrd "teem_biff_stack_overflow_fuzzer.nrrd: .*header line 2"
vol teem_datafile_nul_overread.nrrd "teem_datafile_nul_overread.nrrd: .*a NUL byte in header line 6"
vol teem_text_comment_overread.nrrd "teem_text_comment_overread.nrrd: .*byte 0xca in header line 1"
vol teem_text_comment_min.nrrd "teem_text_comment_min.nrrd: .*byte 0xff in header line 1"
vol teem_empty_datafile_min.nhdr "teem_empty_datafile_min.nhdr: .*empty data file name"
vol nrrd_teem_leak_badmagic.nrrd "nrrd_teem_leak_badmagic.nrrd: .*the first line is not NRRD0001"
vol oom_nrrd_4g_u8.nrrd "oom_nrrd_4g_u8.nrrd: data is 1 bytes, expected 4294836225"
vol nrrd_reads_etc_passwd.nhdr "nrrd_reads_etc_passwd.nhdr: data file /etc/passwd: data is [0-9]+ bytes, expected 1024"
cp "$repro/crash_teem_via_scene.json" "$repro/crash_teem_long_header_line.nrrd" "$tmp/"
refused "long header line through a scene's file volume" "crash_teem_long_header_line.nrrd: .*longer than 400" \
    -- render "$tmp/crash_teem_via_scene.json" --size 8x8

# A FIFO as the detached data file: refused at once (it blocked open() forever).
mkfifo "$tmp/fifo"
printf 'NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 4\nencoding: raw\ndata file: fifo\n' >"$tmp/fifo.nhdr"
refused "detached data file is a FIFO" "fifo.nhdr: data file .*fifo: not a regular file" \
    -- render default --size 8x8 --volume "$tmp/fifo.nhdr"
printf 'NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 4\nencoding: raw\ndata file: /dev/zero\n' >"$tmp/zero.nhdr"
refused "detached data file is /dev/zero" "zero.nhdr: data file /dev/zero: not a regular file" \
    -- render default --size 8x8 --volume "$tmp/zero.nhdr"
# Trailing data after a raw NRRD's voxels: refused as a raw file's would be.
{ printf 'NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n'; printf '123456789'; } >"$tmp/long.nrrd"
refused "raw NRRD with a trailing byte" "long.nrrd: data is 9 bytes, expected 8 .*extra bytes" \
    -- render default --size 8x8 --volume "$tmp/long.nrrd"

# A missing volume is called missing (not a name without dims).
refused "--volume of a missing raw file" "/missing-c5/vol.raw: cannot open: No such file or directory" \
    -- render default --size 8x8 --volume /missing-c5/vol.raw

# The NRRD's own spacing is used and named (docs/scene-format.md, "Spacing").
{ printf 'NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 2\nspacings: 1 1 3\nencoding: raw\n\n'
  head -c 32 /dev/urandom; } >"$tmp/aniso.nrrd"
if out=$("$cube5" render default --size 8x8 --volume "$tmp/aniso.nrrd" --json 2>&1) &&
    python3 -c '
import json, sys
g = json.loads(sys.argv[1])["grid"]
sp = g["spacing"]
assert g["spacing_from"] == "file aniso.nrrd", g
assert abs(sp[2] / sp[0] - 3) < 1e-9 and sp[0] == sp[1], g' "$out"; then
    ok "a NRRD's spacings reach the grid (--json names the file)"
else
    bad "a NRRD's spacings reach the grid (--json names the file)" "$out"
fi
if out=$("$cube5" render default --size 8x8 --volume "$tmp/aniso.nrrd" 2>&1) &&
    grep -qE "^  grid .*spacing [0-9.]+ [0-9.]+ [0-9.]+ \(file aniso.nrrd, scaled to grid.size\)" <<<"$out"; then
    ok "the summary names where the spacing came from"
else
    bad "the summary names where the spacing came from" "$out"
fi
summary
