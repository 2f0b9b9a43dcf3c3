#!/usr/bin/env bash
# Benchmarks of hgcd on scene `tetra` (docs/scenes.md) and the broad phases of
# the peers found (FCL, Bullet, ODE). Called by `make bench`; runs on its own
# too. Method and fields: bench/README.md.
#
# Environment (defaults in brackets):
#   BENCH_N        object counts                  [100000 200000 500000 750000]
#   BENCH_TICKS    ticks per measurement          [9]
#   BENCH_THREADS  hgcd thread counts             [1 2]
#   BENCH_PEERS    peers to run; empty: none      [all compiled in: bench_peers --list]
#   BENCH_SEED     scene seed                     [1]
#   BENCH_MAX_TICK_SECONDS  a peer slower than this per tick stops after that tick [60]
#   BENCH_PEER_MAX_SECONDS  a peer run stops before a tick that would pass this [300]
#   BENCH_LONG_N, BENCH_LONG_TICKS  a longer hgcd run per thread count,
#                  recorded as lib "hgcd-long": its mean tick counts the
#                  renumberings of storage (every ~40 ticks at n = 750000)
#                  at their real rate, which 9 ticks do not  [the largest of
#                  BENCH_N, 100; 0 ticks: none]
#   BENCH_ENGINE   1: also the engine modes of bench_hgcd at the largest of
#                  BENCH_N, each thread count, BENCH_TICKS ticks: the caller
#                  moves and turns the bodies and hands the poses over
#                  (engine-batch: hgcd_world_set_poses, with the shared mesh
#                  and with --mesh-per-body; engine-single: hgcd_body_set_pose
#                  per body), then hgcd_world_detect; 0: none  [1]
#   BENCH_MACHINE  the machine's name in the results' path [a slug of the CPU
#                  model and the core count, e.g. xeon-2c, from /proc/cpuinfo]
#   BENCH_RESULTS  output directory               [bench/results]
#
# Builds with meson in build-bench (release, no tests), runs the measurements,
# printing one JSON line each, and then replaces
# $BENCH_RESULTS/<machine>/tetra.jsonl with them (git keeps the earlier runs;
# an interrupted run leaves the file as it was). Every line names its commit
# ("-dirty" when src/, scene/, include/ or meson.build differ from HEAD).
# Last, bench/plot.py writes the chart tetra.svg and the Markdown table
# tetra.md beside it.
set -euo pipefail
cd "$(dirname "$0")/.."

ns=${BENCH_N:-100000 200000 500000 750000}
ticks=${BENCH_TICKS:-9}
threads=${BENCH_THREADS:-1 2}
seed=${BENCH_SEED:-1}
max_tick=${BENCH_MAX_TICK_SECONDS:-60}
peer_max=${BENCH_PEER_MAX_SECONDS:-300}
results=${BENCH_RESULTS:-bench/results}

commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
if [ "$commit" != unknown ] && [ -n "$(git status --porcelain -- src scene include meson.build 2>/dev/null)" ]; then
    commit="$commit-dirty"
fi

echo "== building build-bench (release)" >&2
if [ -f build-bench/build.ninja ]; then
    meson configure build-bench -Dbuildtype=release -Dtests=false >/dev/null
else
    meson setup build-bench --buildtype=release -Dtests=false >/dev/null
fi
meson compile -C build-bench >/dev/null

bench_hgcd=build-bench/bench/bench_hgcd
bench_peers=build-bench/bench/bench_peers
if [ -n "${BENCH_PEERS+set}" ]; then peers=$BENCH_PEERS; else peers=$("$bench_peers" --list | tr '\n' ' '); fi

nproc=$(nproc 2>/dev/null || echo 1)
cpu=$(sed -n 's/^model name[[:space:]]*:[[:space:]]*//p' /proc/cpuinfo 2>/dev/null | head -n 1 | tr -d '"\\')
# The machine's slug: the CPU model without vendor, trademarks, clock and
# filler words ("Intel(R) Xeon(R) Processor" -> xeon, "AMD Ryzen 9 5950X
# 16-Core Processor" -> ryzen-9-5950x), then the core count: xeon-2c.
machine_slug() {
    local model
    model=$(printf '%s' "$cpu" | tr 'A-Z' 'a-z' | sed -e 's/([^)]*)//g' -e 's/@.*//' \
        -e 's/[0-9]*-core//g' -e 's/\b\(intel\|amd\|cpu\|processor\)\b//g' \
        -e 's/[^a-z0-9]\{1,\}/-/g' -e 's/^-//' -e 's/-$//')
    printf '%s-%sc' "${model:-$(uname -m)}" "$nproc"
}
machine=${BENCH_MACHINE:-$(machine_slug)}
case $machine in
    ''|*/*|.*) echo "run-bench.sh: BENCH_MACHINE must be a plain name, not '$machine'" >&2; exit 2 ;;
esac
mkdir -p "$results/$machine"
final="$results/$machine/tetra.jsonl"
out="$results/$machine/.tetra.jsonl.partial"
: > "$out"
echo "== $machine: $nproc cores (${cpu:-unknown cpu}); commit $commit; n = $ns; ticks = $ticks; hgcd threads = $threads; peers = ${peers:-none}" >&2
echo "== results: $final" >&2

# Runs one measurement; appends its JSON line (with machine fields added) to
# $out and prints it. A failed run is recorded as an "error" line.
run() {
    local lib=$1 n=$2 t=$3
    shift 3
    local line status=0
    line=$("$@" | tail -n 1) || status=$?
    if [ $status -ne 0 ] || [[ $line != \{*\} ]]; then
        echo "bench: $lib n=$n threads=$t failed (exit status $status)" >&2
        # (an engine mode's failure keeps its mode, so as not to stand for step mode's line)
        local mode="" arg prev=""
        for arg in "$@"; do
            [ "$prev" = --mode ] && mode=",\"mode\":\"$arg\""
            [ "$arg" = --mesh-per-body ] && mode="$mode,\"mesh_per_body\":true"
            prev=$arg
        done
        line="{\"lib\":\"$lib\",\"scene\":\"tetra\",\"n\":$n,\"seed\":$seed,\"threads\":$t,\"ticks\":0,\"commit\":\"$commit\"$mode,\"error\":\"exit status $status\"}"
    fi
    line="${line%\}},\"machine\":\"$machine\",\"nproc\":$nproc,\"cpu\":\"$cpu\",\"date\":\"$(date -u +%Y-%m-%dT%H:%M:%SZ)\"}"
    echo "$line" >> "$out"
    echo "$line"
}

start=$(date +%s)
for n in $ns; do
    for t in $threads; do
        echo "-- hgcd n=$n threads=$t" >&2
        run hgcd "$n" "$t" "$bench_hgcd" --n "$n" --seed "$seed" --threads "$t" --ticks "$ticks" \
            --commit "$commit" --check
    done
    for p in $peers; do
        echo "-- $p n=$n" >&2
        run "$p" "$n" 1 "$bench_peers" --lib "$p" --n "$n" --seed "$seed" --ticks "$ticks" \
            --commit "$commit" --max-tick-seconds "$max_tick" --max-seconds "$peer_max"
    done
done
long_n=${BENCH_LONG_N:-$(printf '%s\n' $ns | sort -n | tail -n 1)}
long_ticks=${BENCH_LONG_TICKS:-100}
if [ "$long_ticks" -gt 0 ]; then
    for t in $threads; do
        echo "-- hgcd-long n=$long_n threads=$t ticks=$long_ticks" >&2
        run hgcd-long "$long_n" "$t" "$bench_hgcd" --n "$long_n" --seed "$seed" --threads "$t" \
            --ticks "$long_ticks" --commit "$commit" --lib hgcd-long
    done
fi
engine_n=$(printf '%s\n' $ns | sort -n | tail -n 1)
if [ "${BENCH_ENGINE:-1}" != 0 ]; then
    for t in $threads; do
        for variant in "engine-batch" "engine-batch --mesh-per-body" "engine-single"; do
            echo "-- hgcd n=$engine_n threads=$t --mode $variant" >&2
            # shellcheck disable=SC2086  # $variant is the mode and its flag
            run hgcd "$engine_n" "$t" "$bench_hgcd" --n "$engine_n" --seed "$seed" --threads "$t" \
                --ticks "$ticks" --commit "$commit" --mode $variant
        done
    done
fi
echo "== measurements took $(( $(date +%s) - start )) s" >&2
mv "$out" "$final"

echo >&2
python3 bench/plot.py "$final"
