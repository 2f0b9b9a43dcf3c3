#!/usr/bin/env bash
# Builds the libFuzzer target build-fuzz/fuzz_api (see fuzz/fuzz_api.cpp):
# the library through meson with clang, AddressSanitizer, UBSan and libFuzzer
# coverage instrumentation (its source list and optional dependencies stay
# those of meson.build), then the target and the GMP oracle (tests/oracle.c)
# with clang++ directly. OpenMP is clang's: libomp (Debian libomp-dev).
# Exit status 77: clang's libFuzzer runtime is not installed (callers skip).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${HGCD_FUZZ_BUILD:-build-fuzz}

if ! command -v clang++ >/dev/null 2>&1; then
    echo "fuzz/build.sh: clang++ not found (Debian: clang)" >&2
    exit 77
fi
runtime=$(clang++ -print-file-name=libclang_rt.fuzzer-$(uname -m).a)
if [ ! -f "$runtime" ]; then
    echo "fuzz/build.sh: clang's libFuzzer runtime is missing (Debian: libclang-rt-$(clang++ -dumpversion | cut -d. -f1)-dev)" >&2
    exit 77
fi

san="-fsanitize=address,undefined -fno-sanitize-recover=undefined"
if [ ! -f "$out/build.ninja" ]; then
    CC=clang CXX=clang++ meson setup "$out" --buildtype=debugoptimized -Dtests=false \
        -Db_sanitize=address,undefined -Db_lundef=false \
        -Dcpp_args="-fsanitize=fuzzer-no-link -fno-sanitize-recover=undefined" \
        -Dc_args="-fno-sanitize-recover=undefined" >/dev/null
fi
ninja -C "$out" libhgcd.a >/dev/null

extra=()
if grep -q HGCD_HAVE_CCD "$out/compile_commands.json" 2>/dev/null; then
    read -r -a extra <<<"$(pkg-config --libs ccd 2>/dev/null || echo -lccd)"
fi
flags="-g -O1 -ffp-contract=off -fno-omit-frame-pointer $san"
clang -std=c99 $flags -fsanitize=fuzzer-no-link -c tests/oracle.c -o "$out/oracle.o"
clang -std=c99 $flags -fsanitize=fuzzer-no-link -c tests/oracle_query.c -o "$out/oracle_query.o"
clang -std=c99 $flags -fsanitize=fuzzer-no-link -c tests/oracle_distance.c -o "$out/oracle_distance.o"
clang++ -std=c++17 $flags -fsanitize=fuzzer -fopenmp -Iinclude -Itests \
    fuzz/fuzz_api.cpp "$out/oracle.o" "$out/oracle_query.o" "$out/oracle_distance.o" "$out/libhgcd.a" -lgmp -lm "${extra[@]}" -o "$out/fuzz_api"
echo "built $out/fuzz_api"
