#!/usr/bin/env bash
# A tick of scene tetra from Python (bench/tick.py) against the same tick in C,
# both on one build of the library (make CXXFLAGS=-O3 into build-pybench), two
# ways, interleaved:
#  1. in one process, tick by tick: tick.py --against-c drives a second world
#     from C (bench/c_tick.c) with the same poses, alternating which goes first;
#  2. process by process: ROUNDS rounds of bench/bench_hgcd.c --mode
#     engine-batch and tick.py, the order swapped every round.
# Both use a fixed thread count (ThreadPolicy.FIXED, --thread-policy fixed).
# Prints each run's JSON line, then medians and ratios (C: set_poses + detect,
# pairs read in place; Python: set_poses + detect + pairs copied into numpy),
# and checks both gave the same pairs.
#   compare.sh [N] [THREADS] [ROUNDS] [TICKS]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../../.." && pwd)
n=${1:-200000} threads=${2:-1} rounds=${3:-7} ticks=${4:-15}
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
python=${HGCD_PYTHON:-/usr/bin/python3}
build=$repo/build-pybench
cd "$repo"
make -s BUILD="$build" CXXFLAGS=-O3 lib scene
deps=$(sed 's/\([^ ]\+\)/-l\1/g' "$build/libhgcd-static-deps.txt")
# shellcheck disable=SC2086
cc -std=c99 -O2 -Iinclude -Iscene bench/bench_hgcd.c -o "$build/bench_hgcd" \
   "$build/libhgcd_scene.a" "$build/libhgcd.a" $deps -fopenmp -lstdc++ -lm
# shellcheck disable=SC2086
cc -std=c99 -O2 -fPIC -shared -Iinclude -Iscene "$here/c_tick.c" -o "$build/c_tick.so" \
   "$build/libhgcd_scene.a" "$build/libhgcd.a" $deps -fopenmp -lstdc++ -lm -Wl,--exclude-libs,ALL
pkg=$build/python
rm -rf "$pkg" && mkdir -p "$pkg" && cp -r "$here/../hgcd" "$pkg/"
rm -f "$pkg"/hgcd/_hgcd*.so
HGCD_LIB_DIR=$build HGCD_INCLUDE_DIR=include:scene "$python" "$here/../hgcd_build.py" "$pkg/hgcd" >/dev/null

echo "-- 1. one process, alternating tick by tick ($((2 * ticks + 1)) ticks)"
PYTHONPATH=$pkg "$python" "$here/tick.py" --n "$n" --threads "$threads" --ticks $((2 * ticks + 1)) \
    --against-c "$build/c_tick.so"

echo "-- 2. separate processes, $rounds rounds of $ticks ticks"
out=$build/compare.jsonl
: >"$out"
c_run() { "$build/bench_hgcd" --n "$n" --threads "$threads" --ticks "$ticks" --mode engine-batch --thread-policy fixed | tee -a "$out"; }
py_run() { PYTHONPATH=$pkg "$python" "$here/tick.py" --n "$n" --threads "$threads" --ticks "$ticks" | tee -a "$out"; }
for r in $(seq 1 "$rounds"); do
    if [ $((r % 2)) -eq 1 ]; then c_run; py_run; else py_run; c_run; fi
done
"$python" - "$out" <<'PY'
import json, statistics, sys
runs = [json.loads(l) for l in open(sys.argv[1])]
c = [r for r in runs if r["lib"] == "hgcd"]
py = [r for r in runs if r["lib"] == "hgcd-python"]
assert len({r["pairs_fnv"] for r in runs}) == 1, "the pairs differ"
mc = statistics.median(r["wall_ms"] for r in c)
mp = statistics.median(r["wall_ms"] for r in py)
ratios = sorted(p["wall_ms"] / q["wall_ms"] for p, q in zip(py, c))
print(f"n {c[0]['n']}, threads {c[0]['threads']}, {len(c)} rounds of {c[0]['ticks']} ticks, "
      f"pairs_fnv {c[0]['pairs_fnv']} (both)")
print(f"C      wall_ms median {mc:.3f} (set_poses {statistics.median(r['set_poses_ms'] for r in c):.3f}, "
      f"detect {statistics.median(r['detect_ms'] for r in c):.3f})")
print(f"Python wall_ms median {mp:.3f} (set_poses {statistics.median(r['set_poses_ms'] for r in py):.3f}, "
      f"detect {statistics.median(r['detect_ms'] for r in py):.3f}, pairs {statistics.median(r['pairs_ms'] for r in py):.3f})")
print(f"Python / C: {mp / mc:.4f} (per-round ratios {', '.join(f'{x:.3f}' for x in ratios)})")
PY
