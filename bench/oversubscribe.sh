#!/usr/bin/env bash
# Does hgcd degrade gracefully when the cores are not all its own? Times a
# detect on scene `tetra` (docs/scenes.md) in bench_hgcd's engine-batch mode
# (the caller moves and turns the bodies, one hgcd_world_set_poses, one
# hgcd_world_detect per tick) with 0 and with HOGS competing CPU-bound
# processes (busy loops in sh, same priority), on 1 thread and on 2 threads:
# under hgcd's default thread policy (adaptive: fewer threads while they are
# descheduled), under the fixed policy with the OpenMP runtime's default
# waiting, and under the fixed policy with OMP_WAIT_POLICY=passive (idle
# threads sleep instead of spinning); prints a table of medians.
#
#   bash bench/oversubscribe.sh
#
# Environment (defaults in brackets):
#   BENCH_HGCD  the bench_hgcd binary [build-rel/bench/bench_hgcd, else
#               build-bench/bench/bench_hgcd: a release build]
#   N           bodies [200000]     TICKS   ticks per run [21]
#   HOGS        competing processes in the loaded rows [2]
#   REPEAT      runs of each configuration, interleaved; the table gives the
#               median of their medians [3]
#   HOG_SECONDS the hogs' time limit, should the script be killed [600]
#   PRIO        a command prefix for the benchmark and the hogs alike [none];
#               "chrt -r 1" shuts out the rest of a shared machine's load
#               (real-time round robin: the runs and the hogs then share the
#               cores among themselves, in 100 ms slices)
# The hogs are started per loaded run and killed after it (and on exit).
set -euo pipefail
cd "$(dirname "$0")/.."

bench=${BENCH_HGCD:-}
if [ -z "$bench" ]; then
    for b in build-rel/bench/bench_hgcd build-bench/bench/bench_hgcd; do
        if [ -x "$b" ]; then bench=$b; break; fi
    done
fi
if [ -z "$bench" ] || [ ! -x "$bench" ]; then
    echo "oversubscribe.sh: no bench_hgcd; build one: meson setup build-rel --buildtype=release -Dtests=false && meson compile -C build-rel bench/bench_hgcd" >&2
    exit 2
fi
n=${N:-200000}
ticks=${TICKS:-21}
hogs=${HOGS:-2}
repeat=${REPEAT:-3}
hog_seconds=${HOG_SECONDS:-600}
read -r -a prio <<<"${PRIO:-}"
commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)

hog_pids=()
stop_hogs() {
    local pid
    for pid in "${hog_pids[@]}"; do kill "$pid" 2>/dev/null || true; done
    for pid in "${hog_pids[@]}"; do wait "$pid" 2>/dev/null || true; done
    hog_pids=()
}
start_hogs() {
    local k
    for ((k = 0; k < $1; ++k)); do
        timeout "$hog_seconds" ${prio[@]+"${prio[@]}"} sh -c 'while :; do :; done' &
        hog_pids+=($!)
    done
    sleep 0.2  # let them reach the run queue
}

out=$(mktemp)
trap 'stop_hogs; rm -f "$out"' EXIT
# Configurations: "hogs threads thread-policy wait-policy"; wait policy "-"
# leaves the environment as it is.
configs=("0 1 adaptive -" "0 2 adaptive -" "0 2 fixed -" "0 2 fixed passive"
         "$hogs 1 adaptive -" "$hogs 2 adaptive -" "$hogs 2 fixed -" "$hogs 2 fixed passive")
echo "== $bench, n = $n, $ticks ticks, $repeat runs each${PRIO:+, under $PRIO}; load before: $(cut -d' ' -f1-3 /proc/loadavg)" >&2
for ((r = 1; r <= repeat; ++r)); do
    for c in "${configs[@]}"; do
        read -r h t tp policy <<<"$c"
        start_hogs "$h"
        env_args=()
        [ "$policy" != - ] && env_args=(OMP_WAIT_POLICY="$policy")
        line=$(env "${env_args[@]}" ${prio[@]+"${prio[@]}"} "$bench" --n "$n" --threads "$t" --ticks "$ticks" --mode engine-batch \
                   --thread-policy "$tp" --commit "$commit" | tail -n 1)
        stop_hogs
        echo "{\"hogs\":$h,\"policy\":\"$policy\",\"run\":$r,\"bench\":$line}" >> "$out"
        echo "-- run $r: hogs $h, threads $t, $tp, wait policy $policy" >&2
    done
done

python3 - "$out" "$hogs" "${PRIO:-}" <<'PY'
import json, statistics, sys
rows = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
groups = {}
for r in rows:
    b = r["bench"]
    groups.setdefault((r["hogs"], b["threads"], b.get("thread_policy", "fixed"), r["policy"]), []).append(b)
med = lambda bs, k: statistics.median(b[k] for b in bs)
quiet = groups.get((0, 1, "adaptive", "-"))
print("| competing processes | threads | thread policy | OMP_WAIT_POLICY | detect ms | threads used | set poses ms | "
      "worst detect ms | speed-up of detect over 1 thread | detect over the quiet 1-thread detect |")
print("|---:|---:|---|---|---:|---:|---:|---:|---:|---:|")
for (h, t, tp, p), bs in groups.items():
    one = groups.get((h, 1, "adaptive", "-"))
    ratio = f"{med(one, 'detect_ms') / med(bs, 'detect_ms'):.2f}" if one and t != 1 else "–"
    slow = f"{med(bs, 'detect_ms') / med(quiet, 'detect_ms'):.2f}" if quiet else "–"
    print(f"| {h} | {t} | {tp} | {'default' if p == '-' else p} | {med(bs, 'detect_ms'):.1f} | "
          f"{med(bs, 'threads_used_mean'):.2f} | {med(bs, 'set_poses_ms'):.1f} | "
          f"{med(bs, 'tick_max_ms'):.1f} | {ratio} | {slow} |")
b = rows[0]["bench"]
print(f"\nScene tetra, n = {b['n']}, engine-batch mode, {b['ticks']} ticks, commit {b['commit']}; medians over "
      f"{len(rows) // len(groups)} runs of each run's median (worst detect: the largest tick of the library's own timer, "
      f"median over the runs); threads used: the mean over the ticks of the threads a detect ran on; speed-up: the "
      f"1-thread detect with as many competing processes over this one"
      + (f"; every run and hog under `{sys.argv[3]}`." if sys.argv[3] else "."))
PY
