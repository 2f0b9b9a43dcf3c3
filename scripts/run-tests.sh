#!/usr/bin/env bash
# Every test of hgcd: the CMocka suites through meson (optimised build), the
# same suites under AddressSanitizer + UndefinedBehaviorSanitizer, the
# parallel ones under ThreadSanitizer, every test program under valgrind, a
# short fuzzing run, the plain Makefile build and install, and the Rust
# bindings. Called by `make test`.
set -euo pipefail
cd "$(dirname "$0")/.."
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
jobs=$(nproc 2>/dev/null || echo 2)

step() { printf '\n== %s\n' "$*"; }

step "meson build and tests (debugoptimized)"
[ -f build/build.ninja ] || meson setup build --buildtype=debugoptimized >/dev/null
meson compile -C build >/dev/null
meson test -C build --print-errorlogs --num-processes "$jobs"

step "every library source refuses -ffast-math and -Ofast (src/ieee.hpp)"
bash scripts/check-ieee.sh

step "the tetrahedron-pair tests again with the two-lane kernels (AVX2 machines pick four lanes)"
HGCD_NARROW_NO_AVX2=1 HGCD_TEST_FILTER='test_tetra*' build/tests/test_world
HGCD_NARROW_NO_AVX2=1 build/tests/test_threads

step "tests under AddressSanitizer + UndefinedBehaviorSanitizer"
[ -f build-asan/build.ninja ] || meson setup build-asan --buildtype=debugoptimized \
    -Db_sanitize=address,undefined -Db_lundef=false -Dcpp_args=-fno-sanitize-recover=undefined \
    -Dc_args=-fno-sanitize-recover=undefined >/dev/null
meson compile -C build-asan >/dev/null
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    HGCD_TEST_TETRA_N=5000 HGCD_SKIP_SLOW_TESTS=1 meson test -C build-asan --print-errorlogs --num-processes "$jobs" \
    --timeout-multiplier 3

step "parallel tests under ThreadSanitizer (clang, LLVM OpenMP with Archer; see scripts/test-tsan.sh)"
bash scripts/test-tsan.sh

step "tests under valgrind memcheck: leaks and memory errors (see scripts/test-valgrind.sh)"
bash scripts/test-valgrind.sh build

fuzz_seconds=${HGCD_TEST_FUZZ_SECONDS:-60}
step "API fuzzer for ${fuzz_seconds} s (libFuzzer, ASan, UBSan, GMP oracle; make fuzz runs it longer)"
set +e
bash fuzz/run.sh "$fuzz_seconds"
rc=$?
set -e
if [ $rc -eq 77 ]; then
    echo "fuzzer SKIPPED: clang or its libFuzzer runtime is missing (scripts/ensure-deps.sh test installs them)"
elif [ $rc -ne 0 ]; then
    exit $rc
fi

step "plain Makefile build, install into a staging directory, link a program against it"
make -s lib
stage=$(mktemp -d)
make -s install DESTDIR="$stage" PREFIX=/usr >/dev/null
test -f "$stage/usr/lib/pkgconfig/hgcd.pc"
test -L "$stage/usr/lib/libhgcd.so.0"
cc -std=c99 -I"$stage/usr/include" examples/demo.c -o "$stage/demo" -L"$stage/usr/lib" -lhgcd
LD_LIBRARY_PATH="$stage/usr/lib" "$stage/demo" --n 20000 --ticks 1 --threads 2 | tail -n 2
rm -rf "$stage"

if [ -x bindings/rust/test.sh ]; then
    step "Rust bindings"
    bindings/rust/test.sh
fi

printf '\nall hgcd tests passed\n'
