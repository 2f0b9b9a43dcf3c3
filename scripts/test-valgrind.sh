#!/usr/bin/env bash
# Every test program under valgrind memcheck, for leaks and memory errors.
# Called by scripts/run-tests.sh with the optimised meson build (build/).
#
# memcheck runs the code 20-50x slower, so scene sizes are reduced through
# the tests' environment knobs and the oracle-heavy cases (whose cost is the
# GMP oracle, not hgcd) are left to the other runs: each program runs the
# subset listed below (cmocka name patterns, HGCD_TEST_FILTER). Any definite
# leak or memcheck error fails (--errors-for-leak-kinds=definite
# --error-exitcode=1). A canary that leaks on purpose must be caught first,
# so a clean verdict means something. OpenMP threads stay (2 per world, as
# the tests set them); OMP_NUM_THREADS=2 bounds any default.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
jobs=$(nproc 2>/dev/null || echo 2)
if ! command -v valgrind >/dev/null 2>&1; then
    echo "valgrind: SKIPPED (not installed; Debian: valgrind)"
    exit 0
fi
# nouserintercepts: keep test_oom's own operator new (valgrind would
# otherwise replace it and the allocation-failure hook with it).
vg=(valgrind -q --tool=memcheck --leak-check=full --show-leak-kinds=definite
    --errors-for-leak-kinds=definite --error-exitcode=1 --soname-synonyms=somalloc=nouserintercepts)
export OMP_NUM_THREADS=2 OMP_WAIT_POLICY=passive HGCD_SKIP_SLOW_TESTS=1 HGCD_TEST_TETRA_N=2000
export HGCD_TEST_THREADS_N=1500 HGCD_TEST_BIG_MESH=20000 HGCD_OOM_STRIDE=5
# The baseline kernels only: valgrind 3.19 cannot decode the register form of
# VEX vmovq (0F D6) that GCC emits in the AVX2 convex kernel, and stops with
# SIGILL. The AVX2 kernels are checked under ASan/UBSan and TSan instead.
export HGCD_NO_AVX2=1
logs=$build/valgrind
mkdir -p "$logs"

# The canary.
printf '#include <stdlib.h>\nint main(void) { void *volatile p = malloc(77); p = 0; return 0; }\n' >"$logs/leak.c"
cc -g -O0 "$logs/leak.c" -o "$logs/leak"
if "${vg[@]}" "$logs/leak" >"$logs/leak.log" 2>&1; then
    cat "$logs/leak.log"
    echo "valgrind: the leaking canary was not caught" >&2
    exit 1
fi

# program  filter (cmocka pattern; "*" = every test)
runs=(
    "api *"
    "limits *"
    "batch *"
    "coherence *"
    "incremental test_incremental_two_threads"
    "validation *"
    "oom *"
    "threads *"
    "grid test_touching_on_cell_faces"
    "grid test_far_coordinates"
    "world test_hand_built_pairs"
    "world test_tetra_scene"
    "world test_oversize_and_cell_limits"
    "geometry test_orient*"
    "geometry test_tt_*_*_*"
    "geometry test_scene_oracle_small"
    "bvh test_mesh_info"
    "bvh test_containment"
    "bvh test_nested_shells"
    "bvh test_exact_grid_contacts"
    "ccd test_feature_and_refusals"
    "ccd test_weak_spots"
    "ccd test_exact_contacts"
    "ccd test_penetration"
    "ccd test_mixed_fallback"
    "bvh_ray test_degenerate_first_ray"
    "convex test_hand_built"
    "convex test_kernel_decides"
    "convex test_edge_crossing"
    "margin test_scene_cases"
    "margin test_margin_refusals"
    "margin_tetra test_tetra_gaps"
)
run_one() {
    local prog=$1 filter=$2
    local exe=$build/tests/test_$prog
    if [ ! -x "$exe" ]; then
        [ "$prog" = ccd ] && { echo "  test_ccd not built (no libccd): skipped"; return 0; }
        echo "  $exe missing"
        return 1
    fi
    # A program that ignored the filter would run all its tests (slowly).
    if [ "$filter" != "*" ] && ! grep -q HGCD_TEST_FILTER tests/test_"$prog".c*; then
        echo "  tests/test_$prog: does not read HGCD_TEST_FILTER"
        return 1
    fi
    local log="$logs/${prog}_${filter//[^A-Za-z0-9_]/_}.log"
    local start=$SECONDS
    if HGCD_TEST_FILTER="$filter" "${vg[@]}" "$exe" >"$log" 2>&1; then
        echo "  test_$prog [$filter]: clean ($((SECONDS - start)) s)"
    else
        tail -n 40 "$log"
        echo "  test_$prog [$filter]: FAILED (log: $log)"
        return 1
    fi
}
export -f run_one
export build logs
for r in "${runs[@]}"; do printf '%s\0%s\0' "${r%% *}" "${r#* }"; done |
    VG="${vg[*]}" xargs -0 -n 2 -P "$jobs" bash -c 'vg=($VG); run_one "$1" "$2"' run_one
echo "valgrind: no leak, no memory error"
