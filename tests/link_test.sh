#!/usr/bin/env bash
# The host link over real libusb against the emulated board (docs/host-protocol.md,
# board_emu/README.md): the in-process link tests ($build/tests/link-tests, run with umockdev's
# preload) and the runner cube5-board end to end with an unmodified libusb program (Python's
# ctypes on libusb-1.0). Ends with one SUMMARY line that counts both the link binary's cases
# and the checks made here.
set -uo pipefail
cd "$(dirname "$0")/.."
source tests/lib.sh
build=${1:-build}
link=$build/tests/link-tests
board=$build/cube5-board

# A short TMPDIR: umockdev's socket path must stay under 108 characters.
tmp=$(mktemp -d /tmp/c5l.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
export TMPDIR=$tmp

preload=libumockdev-preload.so.0
if [ -x "$link" ] && links_asan "$link"; then
    preload=$(gcc -print-file-name=libasan.so):$preload # ASan's runtime must come first
fi

# ---- the link binary ----------------------------------------------------------------------
if [ ! -x "$link" ]; then
    bad "link binary" "$link is missing (make $link)"
else
    out=$tmp/link.out
    LD_PRELOAD=$preload timeout 300 "$link" >"$out" 2>&1
    rc=$?
    grep -v '^SUMMARY ' "$out"
    line=$(grep '^SUMMARY ' "$out" | tail -n 1)
    if [ -z "$line" ]; then
        bad "link binary ended without a summary (status $rc: crashed or hung?)"
    else
        p=$(sed -E 's/.*passed=([0-9]+).*/\1/' <<<"$line")
        f=$(sed -E 's/.*failed=([0-9]+).*/\1/' <<<"$line")
        echo "    (link binary: passed=$p failed=$f)"
        passed=$((passed + p)) failed=$((failed + f))
    fi
fi

# ---- the runner ---------------------------------------------------------------------------
if [ ! -x "$board" ]; then
    bad "cube5-board" "$board is missing"
    summary
fi

"$board" run -- true
rc=$?
[ "$rc" -eq 0 ] && ok "cube5-board run -- true exits 0" || bad "cube5-board run -- true" "exit $rc"

"$board" run -- false
rc=$?
[ "$rc" -eq 1 ] && ok "cube5-board run -- false exits 1" || bad "cube5-board run -- false" "exit $rc"

"$board" run -- sh -c 'exit 7'
rc=$?
[ "$rc" -eq 7 ] && ok "cube5-board passes the exit status on" || bad "cube5-board exit status" "exit $rc, 7 expected"

"$board" run -- sh -c 'kill -TERM $$'
rc=$?
[ "$rc" -eq 143 ] && ok "cube5-board: a child killed by SIGTERM gives 143" || bad "cube5-board signal status" "exit $rc"

for args in "run --bogus -- true" "run --fault nope -- true" "run --fault stall:nosuchtype -- true" \
    "run --fault stall:0:0 -- true" "run --fault short:any:1:2 -- true" "run --serial" "run --serial -- true" \
    "run --fault -- true" "run" "frobnicate"; do
    # shellcheck disable=SC2086
    err=$("$board" $args 2>&1 >/dev/null)
    rc=$?
    if [ "$rc" -eq 2 ] && [ "$(wc -l <<<"$err")" = 1 ] && grep -q "^cube5-board: error: .*(see cube5-board --help)$" <<<"$err"; then
        ok "cube5-board usage error: ${args:-(nothing)}"
    else
        bad "cube5-board usage error: ${args:-(nothing)}" "exit $rc" "$err"
    fi
done
err=$("$board" 2>&1 >/dev/null)
rc=$?
[ "$rc" -eq 2 ] && grep -q "^usage: cube5-board run" <<<"$err" && ok "cube5-board alone: its usage, exit 2" ||
    bad "cube5-board alone" "exit $rc" "$err"

grep -q -- "--fault" <<<"$("$board" --help)" && ok "cube5-board --help" || bad "cube5-board --help"

# The conventions shared with cube5 (README, "Conventions"): --version from VERSION, errors
# as "TOOL: error: ...", exit 2 for bad input or usage.
version=$(cat VERSION)
for tool in "$board" "$build/cube5ctl"; do
    out=$("$tool" --version 2>&1)
    rc=$?
    [ "$rc" -eq 0 ] && [ "$out" = "$(basename "$tool") $version" ] && ok "$(basename "$tool") --version: $out" ||
        bad "$(basename "$tool") --version" "exit $rc: $out (VERSION: $version)"
done

"$board" run -- sh -c 'case "$LD_PRELOAD" in *umockdev*) [ -d "$UMOCKDEV_DIR" ];; *) false;; esac'
rc=$?
[ "$rc" -eq 0 ] && ok "the child gets the preload and UMOCKDEV_DIR" || bad "the child's environment" "exit $rc"

# (an ASan-built runner needs ASan's runtime first itself: then that is the existing entry)
first=libc.so.6
links_asan "$board" && first=$(gcc -print-file-name=libasan.so)
LD_PRELOAD=$first "$board" run -- sh -c 'case "$LD_PRELOAD" in "$0":*umockdev*) ;; *) exit 1;; esac' "$first"
rc=$?
[ "$rc" -eq 0 ] && ok "an existing LD_PRELOAD stays first" || bad "an existing LD_PRELOAD stays first" "exit $rc"

# An unmodified libusb program: finds 1209:0001, reads the serial string, claims interface 0,
# reads register 0x000 (the ID) with one bulk transfer each way. Prints what it saw and
# exits with libusb's error code of the IN transfer (as a positive number) when it fails.
cat >"$tmp/probe.py" <<'EOF'
import ctypes as C, struct, sys
u = C.CDLL("libusb-1.0.so.0")
class Desc(C.Structure):
    _fields_ = [("bLength", C.c_uint8), ("bDescriptorType", C.c_uint8), ("bcdUSB", C.c_uint16),
                ("cls", C.c_uint8), ("sub", C.c_uint8), ("proto", C.c_uint8), ("mps0", C.c_uint8),
                ("idVendor", C.c_uint16), ("idProduct", C.c_uint16), ("bcdDevice", C.c_uint16),
                ("iManufacturer", C.c_uint8), ("iProduct", C.c_uint8), ("iSerialNumber", C.c_uint8),
                ("nconf", C.c_uint8)]
u.libusb_get_device_list.argtypes = [C.c_void_p, C.POINTER(C.POINTER(C.c_void_p))]
u.libusb_get_device_descriptor.argtypes = [C.c_void_p, C.POINTER(Desc)]
u.libusb_open.argtypes = [C.c_void_p, C.POINTER(C.c_void_p)]
u.libusb_get_string_descriptor_ascii.argtypes = [C.c_void_p, C.c_uint8, C.c_char_p, C.c_int]
u.libusb_claim_interface.argtypes = [C.c_void_p, C.c_int]
u.libusb_bulk_transfer.argtypes = [C.c_void_p, C.c_ubyte, C.c_char_p, C.c_int, C.POINTER(C.c_int), C.c_uint]
u.libusb_close.argtypes = [C.c_void_p]
u.libusb_exit.argtypes = [C.c_void_p]
ctx = C.c_void_p()
assert u.libusb_init(C.byref(ctx)) == 0
lst = C.POINTER(C.c_void_p)()
n = u.libusb_get_device_list(ctx, C.byref(lst))
boards = []
for i in range(n):
    d = Desc()
    u.libusb_get_device_descriptor(lst[i], C.byref(d))
    if (d.idVendor, d.idProduct) == (0x1209, 0x0001):
        boards.append((lst[i], d))
print("boards", len(boards))
if len(boards) != 1:
    sys.exit(100)
h = C.c_void_p()
assert u.libusb_open(boards[0][0], C.byref(h)) == 0
s = C.create_string_buffer(128)
u.libusb_get_string_descriptor_ascii(h, boards[0][1].iSerialNumber, s, 128)
print("serial", s.value.decode())
assert u.libusb_claim_interface(h, 0) == 0
# reg_read, tag 5, register 0 (tlp_header, spec/layouts.toml): type, tag, status, sync 0xC5,
# length 4, addr_lo, addr_hi
pkt = struct.pack("<BBBBIII", 1, 5, 0, 0xC5, 4, 0, 0)
done = C.c_int()
r = u.libusb_bulk_transfer(h, 0x01, pkt, len(pkt), C.byref(done), 1000)
print("out", r, done.value)
buf = C.create_string_buffer(65552)
r = u.libusb_bulk_transfer(h, 0x81, buf, 65552, C.byref(done), 1000)
print("in", r, done.value)
if r == 0 and done.value == 20:
    print("id 0x%08x" % struct.unpack("<I", buf.raw[16:20])[0])
u.libusb_close(h)
u.libusb_exit(ctx)
sys.exit(-r if r < 0 else 0)
EOF

out=$(timeout 60 "$board" run --serial C5LINK-E2E -- python3 "$tmp/probe.py" 2>&1)
rc=$?
if [ "$rc" -eq 0 ] && grep -q "^boards 1$" <<<"$out" && grep -q "^serial C5LINK-E2E$" <<<"$out" &&
    grep -q "^id 0x43554235$" <<<"$out"; then
    ok "an unmodified libusb program finds the board, its serial and reads the ID"
else
    bad "libusb program under cube5-board" "exit $rc" "$out"
fi

# Faults armed by the runner reach the program: a stall is LIBUSB_ERROR_PIPE (-9), a
# disconnect LIBUSB_ERROR_NO_DEVICE (-4), silence LIBUSB_ERROR_TIMEOUT (-7).
for f in "stall:reg_completion:1 9" "disconnect:any 4" "timeout:reg_completion:1 7"; do
    set -- $f
    out=$(timeout 60 "$board" run --fault "$1" -- python3 "$tmp/probe.py" 2>&1)
    rc=$?
    [ "$rc" -eq "$2" ] && ok "cube5-board --fault $1: libusb error -$2" || bad "cube5-board --fault $1" "exit $rc, $2 expected" "$out"
done

# ---- cube5ctl under the runner -------------------------------------------------------------
# The product's own CLI, unmodified, against the emulated board: the frame equals the model's
# own render bit for bit (EXR holds the float image exactly), the fetches it served equal the
# model's, stats reads the same board afterwards, and each injected fault ends in its error.
ctl=$build/cube5ctl
cube5=$build/cube5
args=(default --size 64x48 --cells 2)
if "$board" run -- "$ctl" render "${args[@]}" -o "$tmp/via.exr" --json >"$tmp/via.json" 2>"$tmp/err" &&
   "$cube5" render "${args[@]}" --model rtl -o "$tmp/direct.exr" --json >"$tmp/direct.json" 2>>"$tmp/err"; then
    cmp -s "$tmp/via.exr" "$tmp/direct.exr" && ok "cube5ctl render through the runner = cube5 render --model rtl (EXR, bit for bit)" ||
        bad "cube5ctl render vs the model" "the EXR files differ"
    fetches=$(python3 -c 'import json,sys; v=json.load(open(sys.argv[1])); d=json.load(open(sys.argv[2]))
print(v["driver"]["fetches_served"], v["board"]["fetches"], d["frames"][0]["board"]["fetches"])' "$tmp/via.json" "$tmp/direct.json")
    read -r served reg model <<<"$fetches"
    [ "$served" = "$model" ] && [ "$reg" = "$model" ] && [ "$model" -gt 1 ] &&
        ok "cube5ctl served $served cell fetches, the board counted $reg, the model $model" ||
        bad "cell fetch counts" "served $served, board register $reg, model $model"
else
    bad "cube5ctl render through the runner" "$(cat "$tmp/err")"
fi

# A frame the scene does not have is bad input (status 2) naming --frame; nothing written.
out=$("$board" run -- "$ctl" render default --size 16x16 --frame 99999 -o "$tmp/f.png" 2>&1)
rc=$?
if [ "$rc" -eq 2 ] && grep -q "cube5ctl: error: --frame: frame 99999: the scene has frames 0..0" <<<"$out" &&
    [ ! -e "$tmp/f.png" ]; then
    ok "cube5ctl render --frame 99999: status 2 naming --frame"
else
    bad "cube5ctl render --frame 99999" "exit $rc" "$out"
fi

if "$board" run -- sh -c "\"$ctl\" render default --size 32x32 -o \"$tmp/s.png\" >/dev/null && \"$ctl\" stats --json" \
       >"$tmp/stats.json" 2>"$tmp/err" &&
   python3 -c 'import json,sys; b=json.load(open(sys.argv[1]))["board"]; sys.exit(0 if b["fetches"] == 1 and b["rays"] > 0 else 1)' \
       "$tmp/stats.json"; then
    ok "cube5ctl stats reads the last frame's counters from the same board"
else
    bad "cube5ctl stats" "$(cat "$tmp/stats.json" "$tmp/err")"
fi

# KIND:TYPE:NTH[:REPEAT] -> the start of the message (c5drv_strerror of the documented error)
while IFS='|' read -r fault want; do
    "$board" run --fault "$fault" -- "$ctl" --timeout 1500 render default --cells 2 --size 32x32 -o "$tmp/f.png" \
        >/dev/null 2>"$tmp/err"
    rc=$?
    if [ "$rc" -eq 1 ] && grep -q "^cube5ctl: error: $want" "$tmp/err"; then
        ok "cube5ctl with --fault $fault: $want"
    else
        bad "cube5ctl with --fault $fault" "exit $rc, '$want' expected: $(cat "$tmp/err")"
    fi
done <<'EOF_FAULTS'
stall:dma_read:2:9|endpoint stalled
short:dma_read:2|short transfer
timeout:interrupt:2|board did not answer in time
disconnect:dma_read:2|board disconnected
corrupt:reg_completion:5|protocol error
EOF_FAULTS
[ -f "$tmp/f.png" ] && bad "a failed frame left an image" "$tmp/f.png" || ok "no image written after a failed frame"

# Bad input is refused before any board is looked for: exit 2, one "cube5ctl: error:" line;
# an output over an input (here a NRRD header's detached data file) is never written.
ctl_input() { # NAME PATTERN -- ARGS...
    local name=$1 pat=$2
    shift 3
    "$ctl" "$@" >/dev/null 2>"$tmp/err"
    local rc=$?
    if [ "$rc" -eq 2 ] && [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -qE "^cube5ctl: error: .*$pat" "$tmp/err"; then
        ok "cube5ctl $name: exit 2, $pat"
    else
        bad "cube5ctl $name" "exit $rc: $(cat "$tmp/err")"
    fi
}
ctl_input unknown_option "unknown option" -- --bogus
ctl_input unknown_scene "neither a built-in scene" -- render nosuch -o "$tmp/x.png"
ctl_input bad_extension "unsupported image extension" -- render default -o "$tmp/x.txt"
cp tests/data/repro/overwrite_nhdr_datafile/vol.nhdr "$tmp/"
head -c 32768 /dev/zero | tr '\0' '@' >"$tmp/data.png"
printf '{"volumes": [{"file": "vol.nhdr"}], "transfer_function": {"opacity": [[0,0],[255,1]], "color": [[0,1,1,1]]},
  "camera": {"eye": [80,80,80], "target": [16,16,16], "width": 8, "height": 8}}' >"$tmp/nhdr.json"
sum=$(sha256sum <"$tmp/data.png")
ctl_input output_is_nrrd_data_file "is the data file of .*vol.nhdr .*refusing to overwrite an input" -- \
    render "$tmp/nhdr.json" -o "$tmp/data.png"
[ "$(sha256sum <"$tmp/data.png")" = "$sum" ] && ok "cube5ctl left the NRRD data file as it was" ||
    bad "cube5ctl overwrote the NRRD data file"

"$ctl" info >/dev/null 2>"$tmp/err"
rc=$?
[ "$rc" -eq 1 ] && grep -q "^cube5ctl: error: .*no board 1209:0001" "$tmp/err" && ok "cube5ctl without a board: exit 1, no board 1209:0001" ||
    bad "cube5ctl without a board" "exit $rc: $(cat "$tmp/err")"

summary
