#!/usr/bin/env bash
# `make fuzz`: builds the libFuzzer harnesses of fuzz/ with clang -fsanitize=fuzzer,address,
# undefined and runs each for FUZZ_SECONDS (docs/fuzzing.md). Usage: fuzz/run.sh BUILD_DIR
#   FUZZ_SECONDS  seconds per harness (default 60)
#   FUZZ_RUNS     instead of a time: this many executions per harness (e.g. 10000000)
#   FUZZ_ONLY     harness names to build and run (default: scene volume tlp driver)
#   FUZZ_BUILD_ONLY=1  build, do not run
# Teem's reader (air, biff, nrrd) is built here from Debian's source package with the same
# sanitizers, so that the fuzzer sees inside it; the product keeps linking Debian's libteem.
# New inputs go to BUILD/fuzz/grown/NAME; the committed seeds in fuzz/corpus/NAME are read only.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out="$build/fuzz"
names=${FUZZ_ONLY:-scene volume tlp driver}
mkdir -p "$out"

# ---- the toolchain: clang and its libFuzzer runtime (Debian's libclang-rt-14-dev) ----------
need=()
command -v clang >/dev/null || need+=(clang)
ls /usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a >/dev/null 2>&1 || need+=(libclang-rt-14-dev)
[ ${#need[@]} -eq 0 ] || bash scripts/setup-deps.sh "${need[@]}"
CC=${FUZZ_CC:-clang}

# ---- Teem's source, from Debian's source package (never committed) --------------------------
teem_src=$(ls -d "$out"/teem-src/teem-*/ 2>/dev/null | sed -n 1p || true)
if [ -z "$teem_src" ]; then
    # A private sources list: the system's apt configuration stays as it is.
    mkdir -p "$out/teem-src/lists/partial"
    cat >"$out/teem-src/sources.sources" <<'EOF'
Types: deb-src
URIs: http://deb.debian.org/debian
Suites: bookworm
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
EOF
    apt_opts=(-o "Dir::Etc::SourceList=$PWD/$out/teem-src/sources.sources" -o Dir::Etc::SourceParts=/dev/null
              -o "Dir::State::Lists=$PWD/$out/teem-src/lists")
    apt-get "${apt_opts[@]}" update
    (cd "$out/teem-src" && apt-get "${apt_opts[@]}" source --download-only teem)
    tar -C "$out/teem-src" -xf "$out"/teem-src/teem_*.orig.tar.*
    teem_src=$(ls -d "$out"/teem-src/teem-*/ | sed -n 1p)
fi

SAN="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer -g -O1"
inc="$out/teem-include"
mkdir -p "$inc/teem"
cp "$teem_src"/src/air/air.h "$teem_src"/src/biff/biff.h "$teem_src"/src/hest/hest.h "$teem_src"/src/nrrd/nrrd*.h "$inc/teem/"
cp /usr/include/teem/airExistsConf.h "$inc/teem/" 2>/dev/null ||
    printf '#ifndef airExistsConf_h\n#define airExistsConf_h\n#endif\n' >"$inc/teem/airExistsConf.h"

# Teem's reader: air, biff and nrrd (without hestNrrd.c, the command-line glue), with zlib
# as Debian builds it, without bzip2 and PNG (cube5 refuses both before Teem sees them).
# -fno-sanitize=nonnull-attribute: airArrayLenSet calls memcpy(new, NULL, 0) on every
# header (benign, docs/nrrd-teem.md); every other check stays on inside Teem.
teem_lib="$out/libteem-san.a"
if [ ! -f "$teem_lib" ]; then
    mkdir -p "$out/teem-obj"
    objs=()
    for f in "$teem_src"/src/air/*.c "$teem_src"/src/biff/*.c "$teem_src"/src/nrrd/*.c; do
        case $f in */hestNrrd.c) continue ;; esac
        o="$out/teem-obj/$(basename "$(dirname "$f")")_$(basename "${f%.c}").o"
        $CC $SAN -fsanitize=fuzzer-no-link -fno-sanitize=nonnull-attribute -w -I"$inc" -I"$teem_src/src/nrrd" -I"$teem_src/src/air" \
            -I"$teem_src/src/biff" -I"$teem_src/include" -DTEEM_ZLIB=1 -DTEEM_QNANHIBIT=1 -DTEEM_DIO=0 -c "$f" -o "$o"
        objs+=("$o")
    done
    ar rcs "$teem_lib" "${objs[@]}"
fi

# ---- the project's code and the harnesses, instrumented --------------------------------------
cflags=(-std=c11 -D_DEFAULT_SOURCE -DC5_VERSION="\"$(cat VERSION)\"" $SAN -fsanitize=fuzzer-no-link
        -Wall -Wextra -Werror -I"$inc" -Icommon -Icref -Icref/cast -Irtl_model -Irtl_model/proc -Irtl_model/dsp -Irtl_model/mem -Irtl_model/analysis -Ivectors/gen -Isweep
        -Ihost_driver -Iboard_emu -I"$build/gen" -Ifuzz)
mkdir -p "$out/obj"
lib_objs=()
for f in common/*.c cref/*.c rtl_model/*.c rtl_model/*/*.c host_driver/core.c host_driver/frame.c host_driver/hostmem.c; do
    o="$out/obj/$(echo "${f%.c}" | tr / _).o"
    if [ ! -f "$o" ] || [ "$f" -nt "$o" ] || [ -n "$(find common cref rtl_model host_driver "$build/gen" -name '*.h' -newer "$o" | sed -n 1p)" ]; then
        $CC "${cflags[@]}" -c "$f" -o "$o"
    fi
    lib_objs+=("$o")
done
# cref once more in long double (the Makefile's CREFL_SRC): cref's render.c calls it.
for f in cref/render.c cref/trace.c cref/sample.c cref/geometry.c; do
    o="$out/obj/long_$(basename "${f%.c}").o"
    [ -f "$o" ] && [ "$o" -nt "$f" ] || $CC "${cflags[@]}" -DC5_CREF_LONG -c "$f" -o "$o"
    lib_objs+=("$o")
done
# Images go through the OpenImageIO shim, a library opened on first use (common/image_load.c),
# which no harness reaches: the archive only pulls in the objects a harness needs.
rm -f "$out/libcube5-san.a"
ar rcs "$out/libcube5-san.a" "${lib_objs[@]}"
for n in $names; do
    $CC "${cflags[@]}" -fsanitize=fuzzer "fuzz/fuzz_$n.c" "$out/libcube5-san.a" "$teem_lib" \
        $(pkg-config --libs jansson) -lz -lm -lpthread -o "$out/fuzz-$n"
done
echo "fuzz: built $(for n in $names; do printf '%s ' "$out/fuzz-$n"; done)"
[ "${FUZZ_BUILD_ONLY:-0}" = 1 ] && exit 0

# ---- the runs --------------------------------------------------------------------------------
if [ -n "${FUZZ_RUNS:-}" ]; then limit=(-runs="$FUZZ_RUNS"); else limit=(-max_total_time="${FUZZ_SECONDS:-60}"); fi
status=0
for n in $names; do
    mkdir -p "$out/grown/$n"
    log="$out/fuzz-$n.log"
    echo "fuzz: $n (${limit[*]}), log $log"
    # -timeout: an input that takes over 10 s is a finding (a hang); -rss_limit_mb: so is 2 GB.
    if ! "$out/fuzz-$n" "${limit[@]}" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
        -artifact_prefix="$out/artifact-$n-" "$out/grown/$n" "fuzz/corpus/$n" >"$log" 2>&1; then
        echo "fuzz: $n FOUND something: see $log and $out/artifact-$n-*"
        status=1
    fi
    grep -E '^stat::(number_of_executed_units|average_exec_per_sec|new_units_added|peak_rss_mb)|cov: ' "$log" | tail -n 5
done
exit $status
