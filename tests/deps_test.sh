#!/usr/bin/env bash
# The set-up profiles (scripts/deps/) hold what the programs need: every shared library a
# program links, and every system header its sources include, comes from a package that its
# profile's packages bring in (apt's dependency closure), so `make demo` on a fresh machine
# installs enough for build/cube5 and the demo, and the test profile enough for the driver and
# the emulated board. Usage: deps_test.sh BUILD
set -uo pipefail
build=${1:-build}
. "$(dirname "$0")/lib.sh"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# closure PROFILE: every package the profile installs, dependencies included.
closure() {
    # shellcheck disable=SC2046
    apt-cache depends --recurse --no-recommends --no-suggests --no-conflicts --no-breaks \
        --no-replaces --no-enhances $(bash scripts/setup-deps.sh --list "$1") 2>/dev/null | sed -n 's/^\([^ <][^ ]*\)$/\1/p' |
        sed 's/:.*//' | sort -u
}
# owners PATH...: "PACKAGE PATH" for each path a package holds, in one dpkg call (each call reads
# the whole database). Every path also in its /usr-merged spelling: dpkg knows one of them.
owners() {
    local f all=()
    for f in "$@"; do all+=("$f" "${f#/usr}"); done
    dpkg -S "${all[@]}" 2>/dev/null | sed -E 's/^([^:,]+)[^ ]* (.*)$/\1 \2/'
}
# check NAME PROFILE WHAT FILE...: every FILE comes from a package of the profile's closure.
check() {
    local name=$1 profile=$2 what=$3 pkgs own missing="" path pkg
    shift 3
    [ $# -gt 0 ] || { bad "$name" "no $what found: build first"; return; }
    pkgs=$(closure "$profile")
    own=$(owners "$@")
    for path in "$@"; do
        pkg=$(awk -v p="$path" '$2 == p || "/usr" $2 == p { print $1; exit }' <<<"$own")
        if [ -z "$pkg" ]; then missing+=" $path (no package holds it)"
        elif ! grep -qx "$pkg" <<<"$pkgs"; then missing+=" $path ($pkg)"; fi
    done
    if [ -z "$missing" ]; then ok "$name"; else bad "$name" "$what not brought in by the $profile profile (scripts/deps/):$missing"; fi
}
# headers PKGCONFIG-NAMES -- DIR...: the system headers that the C and C++ sources under DIR
# include, directly or not (gcc -M over their #include <...> lines; the build's own .d
# files hold only the project's headers).
headers() {
    local cflags=() d
    while [ "$1" != -- ]; do cflags+=($(pkg-config --cflags "$1" 2>/dev/null)); shift; done
    shift
    for d in c cpp; do
        find "$@" -name "*.$d" -exec grep -h '^#include <' {} + | sort -u >"$tmp/inc.$d"
        [ -s "$tmp/inc.$d" ] || continue
        if [ $d = c ]; then gcc -std=c11 -D_DEFAULT_SOURCE "${cflags[@]}" -M -x c "$tmp/inc.$d"
        else g++ -std=c++17 "${cflags[@]}" -M -x c++ "$tmp/inc.$d"; fi
    done 2>/dev/null | tr ' \\' '\n\n' | grep '^/usr/' | sort -u | xargs -r realpath | sort -u
}

# covered NAME PROGRAM PROFILE: every library PROGRAM loads (ldd: the direct ones and
# theirs) comes from a package of the profiles' closure.
covered() {
    local name=$1 prog=$2 profile=$3 libs pkgs own missing="" path pkg
    [ -x "$prog" ] || { bad "$name" "no $prog: build first"; return; }
    pkgs=$(closure "$profile")
    libs=$(ldd "$prog" | awk '$3 ~ /^\// { print $3 }' | xargs realpath) || { bad "$name" "ldd $prog failed"; return; }
    # shellcheck disable=SC2086
    own=$(owners $libs)
    for path in $libs; do
        pkg=$(awk -v p="$path" '$2 == p || "/usr" $2 == p { print $1; exit }' <<<"$own")
        if [ -z "$pkg" ]; then missing+=" $path (no package holds it)"
        elif ! grep -qx "$pkg" <<<"$pkgs"; then missing+=" $path ($pkg)"; fi
    done
    if [ -z "$missing" ]; then ok "$name"; else bad "$name" "not brought in by the $profile profile (scripts/deps/):$missing"; fi
}

if ! command -v dpkg >/dev/null || ! command -v apt-cache >/dev/null; then
    bad deps_debian "dpkg and apt-cache are needed (the set-up is for Debian/Ubuntu)"
    summary
fi
covered demo_profile_covers_cube5 "$build/cube5" demo
covered demo_profile_covers_image_library "$build/libc5image.so" demo
covered test_profile_covers_cube5ctl "$build/cube5ctl" test
covered test_profile_covers_cube5_board "$build/cube5-board" test
# The headers the build includes (-dev packages): cube5's objects from the demo profile, the
# driver's, the emulated board's and the tests' from the test profile.
# shellcheck disable=SC2046
check demo_profile_covers_cube5_headers demo headers \
    $(headers jansson OpenImageIO ompi-c -- common cref rtl_model vectors sweep cli)
# shellcheck disable=SC2046
check test_profile_covers_driver_headers test headers \
    $(headers jansson OpenImageIO libusb-1.0 umockdev-1.0 -- host_driver board_emu tests)
# What each target asks for on a fresh tree (a copy of the tracked files, no build/): `make
# demo` runs the demo profile only, `make test` the test profile too (make -n: nothing runs).
fresh="$tmp/fresh"
mkdir -p "$fresh" && git ls-files -z | xargs -0 cp --parents -t "$fresh" 2>/dev/null
plan_demo=$(cd "$fresh" && make -n demo 2>&1)
plan_test=$(cd "$fresh" && make -n test 2>&1)
if ! grep -q "setup-deps.sh demo" <<<"$plan_demo"; then
    bad demo_installs_demo_profile_only "make -n demo runs no 'setup-deps.sh demo'" "$plan_demo"
elif grep -q "setup-deps.sh test" <<<"$plan_demo"; then
    bad demo_installs_demo_profile_only "make -n demo runs 'setup-deps.sh test'"
else
    ok demo_installs_demo_profile_only
fi
grep -q "setup-deps.sh test" <<<"$plan_test" && ok test_installs_test_profile ||
    bad test_installs_test_profile "make -n test runs no 'setup-deps.sh test'"
summary
