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

# The sanitizers of clang 14 and GCC 12 fail at random ("unexpected memory
# mapping") where the kernel randomises more than 28 bits of mmap addresses
# (vm.mmap_rnd_bits = 32 on some newer kernels): there, everything runs
# without address randomisation.
rnd_bits=$(cat /proc/sys/vm/mmap_rnd_bits 2>/dev/null || echo 0)
if [ -z "${HGCD_TESTS_NO_ASLR:-}" ] && [ "$rnd_bits" -gt 28 ] && setarch "$(uname -m)" -R true 2>/dev/null; then
    echo "vm.mmap_rnd_bits = $rnd_bits: running the tests without address randomisation (setarch -R)"
    HGCD_TESTS_NO_ASLR=1 exec setarch "$(uname -m)" -R bash scripts/run-tests.sh "$@"
fi

step "meson build and tests (debugoptimized)"
[ -f build/build.ninja ] || meson setup build --buildtype=debugoptimized >/dev/null
meson compile -C build >/dev/null
meson test -C build --print-errorlogs --num-processes "$jobs"

step "the library built with CXXFLAGS=-Ofast reports the same pairs; sources compiled otherwise refuse -ffast-math and -Ofast (src/common/ieee.hpp)"
bash scripts/check-ieee.sh

step "the broad phase, tetrahedron-pair and thread tests again without AVX2 (AVX2 machines pick 8-box sweeps, the four-body census and gather and the batched narrow kernels)"
HGCD_NO_AVX2=1 build/tests/test_grid
HGCD_NO_AVX2=1 HGCD_TEST_FILTER='test_tetra*' build/tests/test_world
HGCD_NO_AVX2=1 build/tests/test_threads

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

fuzz_runs=${HGCD_TEST_FUZZ_RUNS:-6000}
step "API fuzzer, ${fuzz_runs} inputs from seed 1 (libFuzzer, ASan, UBSan, GMP oracle; about a minute here; make fuzz runs it longer, at random)"
set +e
FUZZ_RUNS=$fuzz_runs bash fuzz/run.sh 300
rc=$?
set -e
if [ $rc -eq 77 ]; then
    echo "fuzzer SKIPPED: clang or its libFuzzer runtime is missing (scripts/ensure-deps.sh test installs them)"
elif [ $rc -ne 0 ]; then
    exit $rc
fi

step "plain Makefile build, install into a staging directory, link a program against it"
make -s lib scene
stage=$(mktemp -d)
make -s install DESTDIR="$stage" PREFIX=/usr >/dev/null
test -f "$stage/usr/lib/pkgconfig/hgcd.pc"
test -L "$stage/usr/lib/libhgcd.so.0"
cc -std=c99 -I"$stage/usr/include" -Iscene examples/demo.c -o "$stage/demo" build-make/libhgcd_scene.a -L"$stage/usr/lib" -lhgcd
LD_LIBRARY_PATH="$stage/usr/lib" "$stage/demo" --n 20000 --ticks 1 --threads 2 | tail -n 2
rm -rf "$stage"

if [ -x bindings/rust/test.sh ]; then
    step "Rust bindings"
    bindings/rust/test.sh
fi

printf '\nall hgcd tests passed\n'
