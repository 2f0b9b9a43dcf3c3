#!/usr/bin/env bash
# Every test of hgcd: the CMocka suites through meson (optimised build), the
# same suites under AddressSanitizer + UndefinedBehaviorSanitizer, the
# parallel ones under ThreadSanitizer, every test program under valgrind, a
# short fuzzing run, hgcd_mpi on 1 to 4 ranks (the meson tests mpi_np*, when
# OpenMPI is found), the plain Makefile build and install, and the Python and
# Rust bindings. Called by `make test`.
set -euo pipefail
cd "$(dirname "$0")/.."
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
jobs=$(nproc 2>/dev/null || echo 2)

# Each step's wall time is printed after it.
step_end() { [ -z "${step_name:-}" ] || printf '(%s...: %d s)\n' "${step_name:0:40}" $((SECONDS - step_start)); }
step() {
    step_end
    step_name=$1 step_start=$SECONDS
    printf '\n== %s\n' "$*"
}

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

step "the broad phase, tetrahedron-pair, convex, tree-path, thread and incremental tests again without AVX2 (AVX2 machines pick 8-box sweeps and queries, the four-body census and gather, the batched narrow kernels and the tree traversal's four-lane node tests)"
HGCD_NO_AVX2=1 build/tests/test_grid
HGCD_NO_AVX2=1 build/tests/test_convex
HGCD_NO_AVX2=1 build/tests/test_large
HGCD_NO_AVX2=1 build/tests/test_bvh
HGCD_NO_AVX2=1 build/tests/test_hint
HGCD_NO_AVX2=1 HGCD_TEST_FILTER='test_tetra*' build/tests/test_world
HGCD_NO_AVX2=1 build/tests/test_threads
HGCD_NO_AVX2=1 build/tests/test_incremental

step "the box kernels' tests again with AVX2 in place of AVX-512 (AVX-512 machines take the boxes of new orientations four at a time with it)"
HGCD_NO_AVX512=1 build/tests/test_grid
HGCD_NO_AVX512=1 build/tests/test_batch

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

step "plain Makefile build and install into a staging directory; programs built against it through pkg-config"
make -s lib scene
stage=$(mktemp -d)
make -s install DESTDIR="$stage" PREFIX=/usr >/dev/null
test -L "$stage/usr/lib/libhgcd.so.0"
# The staged hgcd.pc, its paths under the stage.
export PKG_CONFIG_PATH="$stage/usr/lib/pkgconfig" PKG_CONFIG_SYSROOT_DIR="$stage"
# A C program of the public API alone: two touching tetrahedra and a far one.
cat >"$stage/pairs.c" <<'C'
#include <hgcd/hgcd.h>
#include <stdio.h>
int main(void) {
    static const double v[] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
    static const uint32_t t[] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
    hgcd_world_desc wd = hgcd_world_desc_default();
    hgcd_world *w = NULL;
    if (hgcd_world_create(&wd, &w) != HGCD_OK) return 1;
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    md.vertices = v, md.triangles = t, md.vertex_count = 4, md.triangle_count = 4;
    hgcd_mesh mesh;
    if (hgcd_mesh_create(w, &md, &mesh) != HGCD_OK) return 1;
    static const double x[] = {0, 1.5, 10};
    for (int i = 0; i < 3; ++i) {
        hgcd_body_desc bd = hgcd_body_desc_default();
        bd.mesh = mesh, bd.position[0] = x[i];
        hgcd_body body;
        if (hgcd_body_create(w, &bd, &body) != HGCD_OK) return 1;
    }
    const hgcd_pair *pairs;
    size_t n;
    if (hgcd_world_detect(w) != HGCD_OK || hgcd_world_pairs(w, &pairs, &n) != HGCD_OK) return 1;
    printf("hgcd %s: %zu pair(s)\n", hgcd_version_string(), n);
    hgcd_world_destroy(w);
    return n == 1 ? 0 : 1;
}
C
# Shared: `pkg-config --libs` alone; the program needs libhgcd.so.0.
# shellcheck disable=SC2046
cc -std=c99 "$stage/pairs.c" -o "$stage/pairs" $(pkg-config --cflags --libs hgcd)
grep -q 'NEEDED.*libhgcd\.so\.0' <<<"$(readelf -d "$stage/pairs")"
LD_LIBRARY_PATH="$stage/usr/lib" "$stage/pairs"
# Static: the shared library taken out of the stage, `pkg-config --static`
# must bring everything libhgcd.a needs (OpenMP, C++ runtime, libccd). The
# demo links the scene support library too, staged by make install-scene
# (C++ like libhgcd, so the same list covers it).
rm "$stage"/usr/lib/libhgcd.so*
make -s install-scene DESTDIR="$stage" PREFIX=/usr >/dev/null
# shellcheck disable=SC2046
cc -std=c99 "$stage/pairs.c" -o "$stage/pairs-static" $(pkg-config --static --cflags --libs hgcd)
# shellcheck disable=SC2046
cc -std=c99 examples/demo.c -o "$stage/demo-static" -lhgcd_scene $(pkg-config --static --cflags --libs hgcd)
if grep -q 'NEEDED.*libhgcd' <<<"$(readelf -d "$stage/pairs-static")"; then
    echo "pairs-static needs a shared libhgcd" >&2
    exit 1
fi
"$stage/pairs-static"
"$stage/demo-static" --n 20000 --ticks 1 --threads 2 | tail -n 2
# hgcd_mpi, when the Makefile built it: a program of its header alone,
# linked statically against the staged libraries, on 2 ranks.
if [ -f "$stage/usr/include/hgcd/hgcd_mpi.h" ]; then
    cat >"$stage/mpi_pairs.c" <<'C'
#include <hgcd/hgcd_mpi.h>
#include <stdio.h>
int main(int argc, char **argv) {
    MPI_Init(&argc, &argv);
    int rank;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    static const double v[] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
    static const uint32_t t[] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
    hgcd_mpi_world_desc wd = hgcd_mpi_world_desc_default();
    hgcd_mpi_world *w = NULL;
    if (hgcd_mpi_world_create(MPI_COMM_WORLD, &wd, &w) != HGCD_OK) MPI_Abort(MPI_COMM_WORLD, 1);
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    md.vertices = v, md.triangles = t, md.vertex_count = 4, md.triangle_count = 4;
    uint32_t mesh;
    hgcd_mpi_body_desc b[3];
    static const double x[] = {0, 1.5, 10};
    for (int i = 0; i < 3; ++i) {
        b[i] = hgcd_mpi_body_desc_default();
        b[i].id = 100 + i, b[i].mesh = 0, b[i].position[0] = x[i];
    }
    const hgcd_mpi_pair *p;
    size_t n = 0;
    if (hgcd_mpi_mesh_register(w, &md, &mesh) != HGCD_OK || hgcd_mpi_bodies_add(w, b, rank == 0 ? 3 : 0) != HGCD_OK ||
        hgcd_mpi_detect(w) != HGCD_OK || hgcd_mpi_gather_pairs(w, 0, &p, &n) != HGCD_OK)
        MPI_Abort(MPI_COMM_WORLD, 1);
    int ok = rank != 0 || (n == 1 && p[0].a == 100 && p[0].b == 101);
    if (rank == 0) printf("hgcd_mpi: %zu pair(s) gathered\n", n);
    hgcd_mpi_world_destroy(w);
    MPI_Finalize();
    return ok ? 0 : 1;
}
C
    # shellcheck disable=SC2046
    mpicc -std=c99 "$stage/mpi_pairs.c" -o "$stage/mpi_pairs" "$stage/usr/lib/libhgcd_mpi.a" \
        $(pkg-config --static --cflags --libs hgcd)
    sh tests/run_mpi.sh 2 "$stage/mpi_pairs"
fi
unset PKG_CONFIG_PATH PKG_CONFIG_SYSROOT_DIR
rm -rf "$stage"

step "Python binding: pip install into a venv, pytest (pairs equal to a C program's, misuse, lifetime), the example"
bindings/python/test.sh

if [ -x bindings/rust/test.sh ]; then
    step "Rust bindings"
    bindings/rust/test.sh
fi

step_end
printf '\nall hgcd tests passed\n'
