#!/usr/bin/env bash
# The parallel tests under ThreadSanitizer. Called by scripts/run-tests.sh.
#
# Why the verdict can be trusted. GCC's libgomp is not built with TSan, so
# its barriers and reductions are invisible to TSan and every parallel
# region would be reported as racing. This build uses clang with LLVM's
# OpenMP runtime (libomp, Debian libomp-dev) instead, and Archer
# (libarcher.so, shipped in libomp-dev): libomp loads it as an OMPT tool,
# and Archer tells TSan about every OpenMP synchronisation (fork/join,
# barriers, reductions, critical, locks, tasks) through TSan's annotation
# interface. TSAN_OPTIONS=ignore_noninstrumented_modules=1 makes TSan
# ignore the memory accesses inside uninstrumented libraries (libomp's own
# internals, cmocka, GMP). No suppression file is used. Before the tests,
# two canaries built the same way check the setup itself:
#   - a race-free OpenMP program (parallel for, reduction, barrier,
#     critical, per-thread vectors) must run clean, and Archer must
#     announce itself: without Archer this program is reported (that is the
#     false-report problem), so a clean run proves the synchronisation is
#     being modelled;
#   - a program with a real data race in an OpenMP loop must be reported:
#     proves TSan is active and sees races inside parallel regions.
# Only then are hgcd's tests run, and any report fails them
# (halt_on_error=1, exit code 66).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${HGCD_TSAN_BUILD:-build-tsan}
jobs=$(nproc 2>/dev/null || echo 2)

if ! command -v clang++ >/dev/null 2>&1; then
    echo "ThreadSanitizer: SKIPPED (clang++ not found; Debian: clang, libomp-dev)"
    exit 0
fi
llvm=$(clang++ -dumpversion | cut -d. -f1)
archer=/usr/lib/llvm-$llvm/lib/libarcher.so
if [ ! -f "$archer" ]; then
    echo "ThreadSanitizer: SKIPPED ($archer not found; Debian: libomp-$llvm-dev)"
    exit 0
fi
export OMP_TOOL_LIBRARIES=$archer ARCHER_OPTIONS=verbose=1 OMP_WAIT_POLICY=passive
export TSAN_OPTIONS="ignore_noninstrumented_modules=1:halt_on_error=1:exitcode=66:second_deadlock_stack=1"

# --- canaries
mkdir -p "$out/canary"
cat >"$out/canary/clean.cpp" <<'CPP'
#include <omp.h>
#include <cstdio>
#include <vector>
int main() {
    std::vector<long> v(200000);
    long sum = 0, crit = 0;
    std::vector<std::vector<int>> per(4);
    for (int it = 0; it < 3; ++it) {
#pragma omp parallel num_threads(4) reduction(+ : sum)
        {
#pragma omp for schedule(dynamic, 64)
            for (long i = 0; i < long(v.size()); ++i) v[i] += i;
#pragma omp barrier
#pragma omp for
            for (long i = 0; i < long(v.size()); ++i) sum += v[(i * 7) % v.size()];
            per[omp_get_thread_num()].push_back(it);
#pragma omp critical
            crit += 1;
        }
    }
    std::printf("%ld %ld\n", sum, crit);
    return 0;
}
CPP
cat >"$out/canary/race.cpp" <<'CPP'
#include <cstdio>
int main() {
    long s = 0;
#pragma omp parallel for num_threads(2)
    for (int i = 0; i < 100000; ++i) s += i;  // the race
    std::printf("%ld\n", s);
    return 0;
}
CPP
for c in clean race; do
    clang++ -std=c++17 -g -O1 -fsanitize=thread -fopenmp "$out/canary/$c.cpp" -o "$out/canary/$c"
done
if ! "$out/canary/clean" >"$out/canary/clean.log" 2>&1; then
    cat "$out/canary/clean.log"
    echo "ThreadSanitizer: the race-free canary was reported: OpenMP synchronisation is not modelled" >&2
    exit 1
fi
if ! grep -q "Archer detected OpenMP application with TSan" "$out/canary/clean.log"; then
    cat "$out/canary/clean.log"
    echo "ThreadSanitizer: Archer did not load" >&2
    exit 1
fi
if "$out/canary/race" >"$out/canary/race.log" 2>&1 || ! grep -q "WARNING: ThreadSanitizer: data race" "$out/canary/race.log"; then
    cat "$out/canary/race.log"
    echo "ThreadSanitizer: the racy canary was not reported" >&2
    exit 1
fi
echo "canaries: race-free OpenMP program clean with Archer, racy one reported"
export ARCHER_OPTIONS=verbose=0

# --- hgcd's tests
if [ ! -f "$out/build.ninja" ]; then
    CC=clang CXX=clang++ meson setup "$out" --buildtype=debugoptimized \
        -Db_sanitize=thread -Db_lundef=false >/dev/null
fi
tests=(api world grid threads validation bvh batch coherence incremental parallel queries margin convex)
listed=$(meson test -C "$out" --no-rebuild --list 2>/dev/null)
if grep -qx ccd <<<"$listed"; then tests+=(ccd); fi  # when libccd is found
ninja -C "$out" $(printf 'tests/test_%s ' "${tests[@]}") >/dev/null
for t in "${tests[@]}"; do  # really instrumented, hgcd included
    syms=$(nm -C "$out/tests/test_$t")
    if ! grep -q ' __tsan_func_entry$' <<<"$syms" || ! grep -qE 'hgcd::(World::detect|Grid::find_pairs)' <<<"$syms"; then
        echo "ThreadSanitizer: $out/tests/test_$t is not instrumented" >&2
        exit 1
    fi
done
# Smaller scenes (TSan is 5-15x slower); every test still runs with 2 to 8
# OpenMP threads per world, and test_threads drives 4 worlds at once.
export HGCD_TEST_TETRA_N=3000 HGCD_TEST_THREADS_N=4000 HGCD_SKIP_SLOW_TESTS=1 HGCD_TEST_BIG_MESH=100000
meson test -C "$out" --no-rebuild --print-errorlogs --num-processes "$jobs" --timeout-multiplier 4 "${tests[@]}"
echo "ThreadSanitizer: no data race reported"
