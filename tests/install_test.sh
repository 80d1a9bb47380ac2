#!/usr/bin/env bash
# `make install` into a temporary DESTDIR, then a program outside the tree built with nothing
# but `pkg-config --cflags --libs c5drv` against the staged copy: it identifies the emulated
# board (the installed cube5-board) and renders a frame whose pixels equal the model's; the
# same with the static library; every installed header compiles on its own (C and C++);
# `make uninstall` leaves nothing behind. Usage: install_test.sh BUILD
set -u
cd "$(dirname "$0")/.."
. tests/lib.sh
build=${1:-build}
src=$PWD
version=$(cat VERSION)
major=${version%%.*}
prefix=/opt/c5test # not a system folder: pkg-config would drop its -L and -I

tmp=$(mktemp -d /tmp/c5i.XXXXXX) # short: umockdev's socket path must stay under 108 characters
trap 'rm -rf "$tmp"' EXIT
stage=$tmp/stage
root=$stage$prefix
export TMPDIR=$tmp

if ! make -s --no-print-directory -C "$src" install BUILD="$build" DESTDIR="$stage" PREFIX="$prefix" >"$tmp/make.log" 2>&1; then
    bad "make install" "$(tail -n 20 "$tmp/make.log")"
    summary
fi
ok "make install DESTDIR=... PREFIX=$prefix"

missing=""
for f in bin/cube5 bin/cube5ctl bin/cube5-board lib/cube5/libc5image.so "lib/libc5drv.so.$version" "lib/libc5drv.so.$major" lib/libc5drv.so \
    lib/libc5drv.a include/cube5/c5drv.h include/cube5/c5_regs_map.h lib/pkgconfig/c5drv.pc \
    share/man/man1/cube5.1 share/man/man1/cube5ctl.1 share/man/man1/cube5-board.1; do
    [ -e "$root/$f" ] || missing+=" $f"
done
[ -z "$missing" ] && ok "installed: the three programs, the image library, libc5drv (.so, .a), headers, c5drv.pc, man pages" ||
    bad "installed files missing" "$missing"
# the installed cube5 finds its image library in ../lib/cube5 (the build tree is not looked at)
if (cd "$tmp" && "$root/bin/cube5" render default --size 8x8 -o "$tmp/installed.png" >/dev/null 2>&1) &&
    [ -s "$tmp/installed.png" ]; then
    ok "the installed cube5 writes an image through $prefix/lib/cube5/libc5image.so"
else
    bad "the installed cube5 writing an image" "$(cd "$tmp" && "$root/bin/cube5" render default --size 8x8 -o "$tmp/installed.png" 2>&1)"
fi
[ "$(readlink "$root/lib/libc5drv.so")" = "libc5drv.so.$major" ] &&
    [ "$(readlink "$root/lib/libc5drv.so.$major")" = "libc5drv.so.$version" ] &&
    ok "libc5drv.so -> libc5drv.so.$major -> libc5drv.so.$version" || bad "libc5drv symlinks" "$(ls -l "$root/lib")"

dyn=$(readelf -d "$root/lib/libc5drv.so.$version" 2>&1)
grep -q "Library soname: \[libc5drv.so.$major\]" <<<"$dyn" && ok "SONAME libc5drv.so.$major (VERSION $version)" ||
    bad "SONAME" "$dyn"
exported=$(nm -D --defined-only "$root/lib/libc5drv.so.$version" | awk '$2 != "A" {print $3}')
others=$(grep -v '^c5drv_' <<<"$exported")
[ -n "$exported" ] && [ -z "$others" ] && ok "libc5drv.so exports only c5drv_* ($(wc -l <<<"$exported") symbols)" ||
    bad "libc5drv.so exports more than c5drv_*" "$others"
globals=$(nm --defined-only "$root/lib/libc5drv.a" | awk '$2 ~ /^[A-TV-Z]$/ && $3 !~ /^c5drv_/ {print $3}')
[ -z "$globals" ] && ok "libc5drv.a keeps only c5drv_* global" || bad "libc5drv.a global symbols" "$globals"

export PKG_CONFIG_PATH=$root/lib/pkgconfig PKG_CONFIG_SYSROOT_DIR=$stage
pcv=$(pkg-config --modversion c5drv 2>&1)
[ "$pcv" = "$version" ] && ok "pkg-config c5drv: version $pcv" || bad "pkg-config --modversion c5drv" "$pcv"
cflags=$(pkg-config --cflags c5drv) libs=$(pkg-config --libs c5drv)
slibs=$(pkg-config --static --libs c5drv)

# An ASan build's libraries need its runtime: loaded first at run time, linked into a static
# program (tests/link_test.sh does the same).
preload="" san=""
if links_asan "$root/bin/cube5-board"; then
    preload=$(gcc -print-file-name=libasan.so)
    san="-fsanitize=address,undefined"
fi

for h in "$root"/include/cube5/*.h; do
    name=$(basename "$h")
    if err=$(cd "$tmp" && printf '#include <%s>\n' "$name" |
        cc -std=c11 -Wall -Wextra -Werror -pedantic $cflags -fsyntax-only -x c - 2>&1) &&
        err=$(cd "$tmp" && printf '#include <%s>\nint main() { return 0; }\n' "$name" |
            c++ -Wall -Wextra -Werror $cflags -fsyntax-only -x c++ - 2>&1); then
        ok "installed header $name compiles on its own (C11 -pedantic, C++)"
    else
        bad "installed header $name alone" "$err"
    fi
done

# The program: identify the board, read its ID register, render a scene at 16x16 on it and
# write the frame's floats to a file.
cat >"$tmp/probe.c" <<'EOF'
#include <c5_regs_map.h>
#include <c5drv.h>
#include <stdio.h>
#include <stdlib.h>

static int fail(c5drv *d, const char *what, int rc)
{
    fprintf(stderr, "%s: %s: %s\n", what, c5drv_strerror(rc), d ? c5drv_message(d) : "");
    c5drv_close(d);
    return 1;
}

int main(int argc, char **argv)
{
    c5drv *d = NULL;
    char msg[256];
    int rc = c5drv_open_usb(C5DRV_USB_VID, C5DRV_USB_PID, NULL, &d, msg, sizeof msg);
    if (rc) {
        fprintf(stderr, "open: %s: %s\n", c5drv_strerror(rc), msg);
        return 1;
    }
    c5drv_info info;
    uint32_t id = 0;
    if ((rc = c5drv_identify(d, &info)) || (rc = c5drv_reg_read(d, C5_REG_ID_OFFSET, &id)))
        return fail(d, "identify", rc);
    printf("id 0x%08x reg 0x%08x spec 0x%08x version %u.%u serial %s\n", (unsigned)info.id, (unsigned)id,
           (unsigned)C5_REG_ID_RESET, info.major, info.minor, info.serial);
    if (argc == 3) {
        FILE *f = fopen(argv[1], "rb");
        static char json[1 << 16];
        size_t n = f ? fread(json, 1, sizeof json - 1, f) : 0;
        if (f)
            fclose(f);
        json[n] = '\0';
        c5drv_image img = {0};
        c5drv_counters c;
        if ((rc = c5drv_load_scene(d, json, NULL, argv[1], NULL, 16, 16)) || (rc = c5drv_start_frame(d, 0)) ||
            (rc = c5drv_wait_frame(d, 60000)) || (rc = c5drv_read_frame(d, &img)) ||
            (rc = c5drv_read_counters(d, &c)))
            return fail(d, "render", rc);
        FILE *out = fopen(argv[2], "wb");
        size_t count = (size_t)img.w * (size_t)img.h * 3;
        int bad = !out || fwrite(img.rgb, sizeof *img.rgb, count, out) != count;
        if (out)
            bad |= fclose(out) != 0;
        printf("frame %dx%d fetches %u\n", img.w, img.h, (unsigned)c.fetches);
        c5drv_image_free(&img);
        if (bad)
            return fail(d, "writing the frame", C5DRV_OK);
    }
    c5drv_close(d);
    return 0;
}
EOF

# What the model renders: the CRC-32 of the float pixels (cube5 render --json "crc32").
want=$(cd "$tmp" && "$root/bin/cube5" render "$src/scenes/default.json" --model rtl --size 16x16 --json |
    python3 -c 'import json,sys; print(json.load(sys.stdin)["frames"][0]["crc32"])')
crc() { python3 -c 'import sys,zlib; print("%08x" % zlib.crc32(open(sys.argv[1],"rb").read()))' "$1"; }

# probe KIND LINK-FLAGS...: builds the program in $tmp and runs it under the installed runner.
probe() {
    local kind=$1
    shift
    local exe=$tmp/probe-$kind out err
    if ! err=$(cd "$tmp" && cc -std=c11 -Wall -Wextra -Werror probe.c "$@" -o "$exe" 2>&1); then
        bad "$kind: building a program with pkg-config c5drv" "$err"
        return
    fi
    ok "$kind: a program outside the tree builds with: cc probe.c $*"
    local needed
    needed=$(readelf -d "$exe" | grep -c "Shared library: \[libc5drv.so.$major\]")
    if [ "$kind" = shared ]; then
        [ "$needed" -eq 1 ] && ok "shared: the program needs libc5drv.so.$major" || bad "shared: NEEDED" "$(readelf -d "$exe")"
    else
        [ "$needed" -eq 0 ] && ok "static: the program needs no libc5drv.so" || bad "static: links libc5drv.so"
    fi
    out=$(cd "$tmp" && LD_PRELOAD=$preload LD_LIBRARY_PATH=$root/lib timeout 120 "$root/bin/cube5-board" run \
        --serial C5INSTALL -- "$exe" "$src/scenes/default.json" "$tmp/frame-$kind.f32" 2>&1)
    local rc=$? reset
    reset=$(sed -n 's/^id .* spec \(0x[0-9a-f]*\) .*/\1/p' <<<"$out")
    if [ "$rc" -eq 0 ] && [ -n "$reset" ] && grep -q "^id $reset reg $reset spec $reset version 1\.[0-9]* serial C5INSTALL$" <<<"$out"; then
        ok "$kind: the program identifies the emulated board (id $reset, serial C5INSTALL)"
    else
        bad "$kind: identifying the emulated board" "exit $rc" "$out"
    fi
    local got
    got=$([ -s "$tmp/frame-$kind.f32" ] && crc "$tmp/frame-$kind.f32")
    [ -n "$want" ] && [ "$got" = "$want" ] && ok "$kind: its 16x16 frame of default is the model's (crc32 $got)" ||
        bad "$kind: the frame through the installed library" "crc32 $got, the model's $want" "$out"
}
# shellcheck disable=SC2086
probe shared $cflags $libs
# libc5drv.a itself, the rest shared: libusb-1.0.pc's private -ludev is for a static libusb
# and needs libudev-dev, which a shared libusb does not.
slibs=${slibs/-lc5drv/-l:libc5drv.a}
[ -e "$(cc -print-file-name=libudev.so)" ] || slibs=${slibs//-ludev/}
for l in -lusb-1.0 -ljansson -lteem -lz -lm; do
    grep -qw -- "$l" <<<"$slibs" || bad "pkg-config --static --libs c5drv lacks $l" "$slibs"
done
# shellcheck disable=SC2086
probe static $cflags $slibs $san

# Installed for real (no DESTDIR) into a prefix outside the loader's folders: a program built
# with nothing but pkg-config's flags finds libc5drv at run time (the rpath c5drv.pc gives),
# with no LD_LIBRARY_PATH.
real=$tmp/real
if make -s --no-print-directory -C "$src" install BUILD="$build" PREFIX="$real" >"$tmp/make.log" 2>&1; then
    rlibs=$(PKG_CONFIG_PATH=$real/lib/pkgconfig PKG_CONFIG_SYSROOT_DIR= pkg-config --libs c5drv)
    rcflags=$(PKG_CONFIG_PATH=$real/lib/pkgconfig PKG_CONFIG_SYSROOT_DIR= pkg-config --cflags c5drv)
    # shellcheck disable=SC2086
    if err=$(cd "$tmp" && cc -std=c11 probe.c $rcflags $rlibs -o "$tmp/probe-real" 2>&1); then
        out=$(cd "$tmp" && env -u LD_LIBRARY_PATH LD_PRELOAD=$preload "$real/bin/cube5-board" run -- "$tmp/probe-real" 2>&1)
        rc=$?
        [ "$rc" -eq 0 ] && grep -q "^id " <<<"$out" &&
            ok "installed in $real: a program built with pkg-config's flags ($rlibs) runs without LD_LIBRARY_PATH" ||
            bad "a program against $real" "exit $rc; libs: $rlibs" "$out"
    else
        bad "building against $real" "$err"
    fi
else
    bad "make install PREFIX=$real" "$(tail -n 20 "$tmp/make.log")"
fi

# Uninstalling leaves no file and no link (the folders PREFIX had before may stay).
if make -s --no-print-directory -C "$src" uninstall BUILD="$build" DESTDIR="$stage" PREFIX="$prefix" >"$tmp/make.log" 2>&1; then
    left=$(find "$stage" ! -type d)
    [ -z "$left" ] && ok "make uninstall removes every installed file" || bad "make uninstall left files" "$left"
else
    bad "make uninstall" "$(tail -n 20 "$tmp/make.log")"
fi
summary
